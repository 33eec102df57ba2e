// The figures across the specimens of a batch: Figs. 13-15 over the
// cycles, Fig. 16's method differences and the specific wear rate against
// mu-hat.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>

#include "draw.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/output_folder.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;
using internal::FigureSpec;
using internal::Series;

// A statistic's 95% interval, the mean itself where none was estimated.
double Low(const fusion::Statistic& s) {
  return std::isfinite(s.low) ? s.low : s.mean;
}
double High(const fusion::Statistic& s) {
  return std::isfinite(s.high) ? s.high : s.mean;
}

// The specimens' cycles in one table, `specimen` their index.
fusion::Table CyclesBySpecimen(const std::vector<SpecimenSeries>& specimens) {
  fusion::Table t(
      {"specimen", "cycle", "mu_hat_force", "J_force", "mu_energy_g"});
  for (size_t i = 0; i < specimens.size(); ++i) {
    const fusion::Table& c = specimens[i].cycles;
    const int cycle = c.ColumnIndex("cycle"),
              mu = c.ColumnIndex("mu_hat_force"), j = c.ColumnIndex("J_force"),
              e = c.ColumnIndex("mu_energy_g");
    if (cycle < 0 || mu < 0 || j < 0 || e < 0) continue;
    for (const auto& row : c.rows) {
      t.rows.push_back(
          {static_cast<double>(i), row[cycle], row[mu], row[j], row[e]});
    }
  }
  return t;
}

// 1, 2 or 5 times a power of ten, at least `rough`.
double NiceStep(double rough) {
  if (!(rough > 0) || !std::isfinite(rough)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(rough)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * p >= rough) return m * p;
  }
  return 10 * p;
}

// Beyond this many specimens a batch figure is small multiples: a panel
// per specimen, drawn over the others in grey (no key of a dozen similar
// colours); beyond kMostPanels, one panel of the batch's median per cycle
// and the band of its middle 80% (a panel per specimen, each drawing them
// all, grows as the square of the batch), the specimens' names left to
// the tables and their pages.
constexpr std::size_t kMostInOneKey = 6;
constexpr std::size_t kMostPanels = 30;

// The batch's 10th, 50th and 90th percentiles per cycle of each column
// of Figs. 13-15 over the specimens that have the cycle.
fusion::Table CyclePercentiles(const std::vector<SpecimenSeries>& specimens) {
  const char* const columns[] = {"mu_hat_force", "J_force", "mu_energy_g"};
  std::vector<std::string> names = {"cycle", "specimens"};
  for (const char* c : columns)
    for (const char* p : {"_p10", "_p50", "_p90"})
      names.push_back(std::string(c) + p);
  fusion::Table t(names);
  std::map<double, std::array<std::vector<double>, 3>> by_cycle;
  for (const SpecimenSeries& sp : specimens) {
    const int cycle = sp.cycles.ColumnIndex("cycle");
    if (cycle < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int y = sp.cycles.ColumnIndex(columns[k]);
      if (y < 0) continue;
      for (const auto& row : sp.cycles.rows)
        if (std::isfinite(row[y])) by_cycle[row[cycle]][k].push_back(row[y]);
    }
  }
  const auto quantile = [](std::vector<double> v, double q) {
    if (v.empty()) return static_cast<double>(NAN);
    const auto at = static_cast<std::ptrdiff_t>(
        std::lround(q * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + at, v.end());
    return v[static_cast<std::size_t>(at)];
  };
  for (const auto& [cycle, values] : by_cycle) {
    std::vector<double> row = {cycle, static_cast<double>(values[0].size())};
    for (const auto& v : values)
      for (double q : {0.1, 0.5, 0.9}) row.push_back(quantile(v, q));
    t.rows.push_back(std::move(row));
  }
  return t;
}

FigureSpec Band(const char* stem,
                const char* title,
                const char* column,
                const char* ylabel,
                std::size_t specimens) {
  const std::string c = column;
  Series band("cycles_percentiles",
              "cycle",
              c + "_p10",
              "the middle 80% of the specimens",
              {c + "_p90"});
  band.style = "filledcurves lc rgb '#c6dbef'";
  Series median("cycles_percentiles", "cycle", c + "_p50", "their median");
  median.style = "lines lw 2.5 lc rgb '#1f77b4'";
  return {stem,
          fmt::format("{}: the batch's {} specimens per cycle (each on its "
                      "page)",
                      title,
                      specimens),
          {{"", "cycle", ylabel, "", {}, "", {band, median}}}};
}

FigureSpec SmallMultiples(const char* stem,
                          const char* title,
                          const char* column,
                          const char* ylabel,
                          const std::vector<SpecimenSeries>& specimens) {
  FigureSpec f{stem,
               fmt::format("{}: each specimen over the others in grey", title),
               {}};
  const std::size_t n = specimens.size();
  f.columns = n <= 9 ? 3 : n <= 16 ? 4 : 5;
  const std::size_t rows = (n + f.columns - 1) / f.columns;
  // About four tics a side: small panels, 14 px text.
  double last_cycle = 1, lo = INFINITY, hi = -INFINITY;
  for (const SpecimenSeries& sp : specimens) {
    const int c = sp.cycles.ColumnIndex("cycle"),
              y = sp.cycles.ColumnIndex(column);
    if (c < 0 || y < 0) continue;
    for (const auto& row : sp.cycles.rows) {
      last_cycle = std::max(last_cycle, row[c]);
      if (std::isfinite(row[y]))
        lo = std::min(lo, row[y]), hi = std::max(hi, row[y]);
    }
  }
  const std::string tics = fmt::format(
      "set xtics {:g}\n{}",
      NiceStep(last_cycle / 4),
      hi > lo ? fmt::format("set ytics {:g}\n", NiceStep((hi - lo) / 3)) : "");
  for (std::size_t i = 0; i < n; ++i) {
    const bool left = i % f.columns == 0, bottom = i / f.columns == rows - 1;
    internal::Panel p{specimens[i].name,
                      bottom ? "cycle" : "",
                      left ? ylabel : "",
                      "set title font ',14'\nset tics font ',14'\n"
                      "set xlabel font ',14'\nset ylabel font ',14'\n"
                      "unset key\n" +
                          tics + (bottom ? "" : "unset xlabel\n") +
                          (left ? "" : "unset ylabel\n"),
                      {},
                      "",
                      {}};
    Series others("cycles_by_specimen", "cycle", column, "");
    others.break_at = "specimen";
    others.style = "lines lw 1 lc rgb '#c8c8c8'";
    Series self("cycles_by_specimen", "cycle", column, "");
    self.select = "specimen";
    self.select_value = static_cast<double>(i);
    self.style = fmt::format("lines lw 2.5 lc {}", i % 8 + 1);
    p.series = {others, self};
    f.panels.push_back(std::move(p));
  }
  return f;
}

// One of Figs. 13-15 over every specimen: a line each in its own colour
// and one key; small multiples beyond kMostInOneKey specimens.
FigureSpec Across(const char* stem,
                  const char* title,
                  const char* column,
                  const char* ylabel,
                  const std::vector<SpecimenSeries>& specimens) {
  if (specimens.size() > kMostPanels)
    return Band(stem, title, column, ylabel, specimens.size());
  if (specimens.size() > kMostInOneKey)
    return SmallMultiples(stem, title, column, ylabel, specimens);
  FigureSpec f{stem, title, {{"", "cycle", ylabel, "", {}, "", {}}}};
  for (size_t i = 0; i < specimens.size(); ++i) {
    Series s("cycles_by_specimen", "cycle", column, specimens[i].name);
    s.select = "specimen";
    s.select_value = static_cast<double>(i);
    s.style =
        fmt::format("lines lw 1.5 lc {} dt {}", i % 8 + 1, (i / 8) % 5 + 1);
    f.panels[0].series.push_back(s);
  }
  return f;
}

// method_differences.csv (Fig. 16) and wear_and_mu.csv, written into the
// batch's folder; `index` numbers the specimens for the x axis.
fusion::Table MethodDifferences(const std::vector<SpecimenSeries>& specimens) {
  fusion::Table t({"index",
                   "mu_hat_minus_mu_mean",
                   "mu_hat_minus_mu_mean_sd",
                   "mu_hat_minus_mu_energy",
                   "mu_hat_minus_mu_energy_sd",
                   "mu_hat_minus_mu_mean_low",
                   "mu_hat_minus_mu_mean_high",
                   "mu_hat_minus_mu_energy_low",
                   "mu_hat_minus_mu_energy_high"});
  for (size_t i = 0; i < specimens.size(); ++i) {
    const auto& s = specimens[i];
    t.rows.push_back({static_cast<double>(i),
                      s.diff_mean.mean,
                      s.diff_mean.sd,
                      s.diff_energy.mean,
                      s.diff_energy.sd,
                      Low(s.diff_mean),
                      High(s.diff_mean),
                      Low(s.diff_energy),
                      High(s.diff_energy)});
  }
  return t;
}

fusion::Table WearAndMu(const std::vector<SpecimenSeries>& specimens) {
  fusion::Table t({"index",
                   "mu_hat",
                   "mu_hat_sd",
                   "wear_rate_mm3_per_N_m",
                   "mu_hat_low",
                   "mu_hat_high"});
  for (size_t i = 0; i < specimens.size(); ++i) {
    const auto& s = specimens[i];
    if (!std::isfinite(s.wear_rate) || !std::isfinite(s.mu_hat.mean)) continue;
    t.rows.push_back({static_cast<double>(i),
                      s.mu_hat.mean,
                      s.mu_hat.sd,
                      s.wear_rate,
                      Low(s.mu_hat),
                      High(s.mu_hat)});
  }
  return t;
}

// The specimens' names on the x axis (Fig. 16), and beside their points
// (the wear figure).
std::string NameTics(const std::vector<SpecimenSeries>& specimens) {
  std::string tics = "set xtics rotate by -45 (";
  for (size_t i = 0; i < specimens.size(); ++i)
    tics += fmt::format(
        "{}{} {}", i ? ", " : "", internal::Quote(specimens[i].name), i);
  return tics + ")\n";
}

// Each point's name beside it, placed where it overlaps no name placed
// before: to the right or left of the point, above or below, tried in turn
// (a name's box estimated from a 14 px character on the 1200 x 600 figure
// in units of the data's span), the first free place taken, else the
// first.
std::string PointLabels(const std::vector<SpecimenSeries>& specimens,
                        const fusion::Table& wear) {
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const auto& row : wear.rows) {
    x_lo = std::min(x_lo, row[1]), x_hi = std::max(x_hi, row[1]);
    y_lo = std::min(y_lo, row[3]), y_hi = std::max(y_hi, row[3]);
  }
  const double x_span = x_hi > x_lo ? 1.2 * (x_hi - x_lo) : 1,
               y_span = y_hi > y_lo ? 1.2 * (y_hi - y_lo) : 1;
  const double char_w = 0.0085, char_h = 0.04;  // of the plot's width, height
  struct Box {
    double x0, x1, y0, y1;
  };
  std::vector<Box> placed;
  struct Place {
    double dx, dy;
    bool left;
  };
  constexpr Place kPlaces[] = {{1, 0.6, true},
                               {1, -1.0, true},
                               {-1, 0.6, false},
                               {-1, -1.0, false},
                               {1, 1.8, true},
                               {1, -2.2, true},
                               {-1, 1.8, false},
                               {-1, -2.2, false}};
  std::string labels;
  for (const auto& row : wear.rows) {
    const std::string& name = specimens[static_cast<size_t>(row[0])].name;
    const double px = (row[1] - x_lo) / x_span, py = (row[3] - y_lo) / y_span;
    const double width = char_w * static_cast<double>(name.size());
    const auto box = [&](const Place& p) {
      const double at = px + p.dx * char_w;
      const double y = py + p.dy * char_h;
      return p.left ? Box{at, at + width, y - char_h / 2, y + char_h / 2}
                    : Box{at - width, at, y - char_h / 2, y + char_h / 2};
    };
    const auto free = [&](const Box& b) {
      return std::none_of(placed.begin(), placed.end(), [&](const Box& o) {
        return b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1;
      });
    };
    const Place* chosen = &kPlaces[0];
    for (const Place& p : kPlaces) {
      if (free(box(p))) {
        chosen = &p;
        break;
      }
    }
    placed.push_back(box(*chosen));
    labels += fmt::format(
        "set label {} {} at first {}, first {} offset {:g},{:g} {} font "
        "',14'\n",
        static_cast<int>(row[0]) + 1,
        internal::Quote(name),
        row[1],
        row[3],
        chosen->dx,
        chosen->dy,
        chosen->left ? "left" : "right");
  }
  return labels;
}

// A table's CSV with the specimens' names in place of its first column
// (their index).
std::string WithNames(const fusion::Table& t,
                      const std::vector<SpecimenSeries>& specimens) {
  const std::string csv = t.ToCsv();
  std::string out = "specimen";
  size_t row = 0, at = 0;
  for (size_t eol; (eol = csv.find('\n', at)) != std::string::npos;
       at = eol + 1) {
    if (row > 0) out += specimens[static_cast<size_t>(t.rows[row - 1][0])].name;
    const size_t comma = csv.find(',', at);
    out.append(csv, comma, eol + 1 - comma);
    ++row;
  }
  return out;
}

// Fig. 16's marks for a batch too large to name: each specimen's interval
// a vertical stroke from its low end, its mean a short horizontal one
// (gnuplot's vectors: a few paths for the whole batch, where a point marker
// each made an SVG of thousands of elements that held a browser's page
// for most of a second at 1,000 specimens).
fusion::Table DifferenceMarks(const fusion::Table& differences) {
  fusion::Table t({"index",
                   "left",
                   "zero",
                   "width",
                   "mean_low",
                   "mean_span",
                   "mean",
                   "energy_low",
                   "energy_span",
                   "energy"});
  const auto at = [&](const std::vector<double>& row, const char* column) {
    return row[static_cast<size_t>(differences.ColumnIndex(column))];
  };
  for (const auto& r : differences.rows) {
    const double lm = at(r, "mu_hat_minus_mu_mean_low");
    const double le = at(r, "mu_hat_minus_mu_energy_low");
    t.rows.push_back({r[0],
                      r[0] - 0.4,
                      0,
                      0.8,
                      lm,
                      at(r, "mu_hat_minus_mu_mean_high") - lm,
                      at(r, "mu_hat_minus_mu_mean"),
                      le,
                      at(r, "mu_hat_minus_mu_energy_high") - le,
                      at(r, "mu_hat_minus_mu_energy")});
  }
  return t;
}

// Fig. 16's series: named, a marker and error bar per specimen; else the
// marks above (the same intervals and means, in the same colours).
std::vector<Series> DifferenceSeries(bool named) {
  if (named) {
    Series dm("method_differences.csv",
              "index",
              "mu_hat_minus_mu_mean",
              "mu-hat - mu mean",
              {"mu_hat_minus_mu_mean_low", "mu_hat_minus_mu_mean_high"});
    dm.style = "yerrorbars pt 7 lc 1";
    Series de("method_differences.csv",
              "index",
              "mu_hat_minus_mu_energy",
              "mu-hat - mu energy",
              {"mu_hat_minus_mu_energy_low", "mu_hat_minus_mu_energy_high"});
    de.style = "yerrorbars pt 5 lc 2";
    return {dm, de};
  }
  std::vector<Series> marks;
  const char* kWhich[][3] = {{"mean", "mu-hat - mu mean", "1"},
                             {"energy", "mu-hat - mu energy", "2"}};
  for (const auto& w : kWhich) {
    const std::string name = w[0];
    Series interval("difference_marks",
                    "index",
                    name + "_low",
                    "",
                    {"zero", name + "_span"});
    interval.style = std::string("vectors nohead lc ") + w[2];
    Series mean("difference_marks", "left", name, w[1], {"width", "zero"});
    mean.style = std::string("vectors nohead lw 2 lc ") + w[2];
    marks.push_back(interval);
    marks.push_back(mean);
  }
  return marks;
}

// Fig. 16: each specimen's mu-hat minus the classic COFs, named on the
// axis while the names can be read.
FigureSpec DifferencesFigure(const std::vector<SpecimenSeries>& specimens,
                             bool named) {
  Series zero;
  zero.function = "0";
  zero.style = "lines lc rgb 'black'";
  std::vector<Series> series = DifferenceSeries(named);
  series.push_back(zero);
  return {"audit_fig16_differences",
          "mu-hat minus mean and energy COF, means over the cycles with their "
          "95% intervals (Fig. 16)",
          {{"",
            "specimen",
            "difference (-)",
            (named ? NameTics(specimens)
                   : "set xlabel 'specimen (its index in "
                     "method_differences.csv)'\n") +
                "set xrange [-0.5:*]\nset offsets 0,0.5,0,0\n",
            {},
            "",
            series}}};
}

}  // namespace

FigureSet DrawAuditFigures(const std::string& dir,
                           const std::vector<SpecimenSeries>& specimens,
                           const FigureFormats& formats) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  if (specimens.empty()) return {};
  const fusion::Table cycles = CyclesBySpecimen(specimens);
  const fusion::Table percentiles = CyclePercentiles(specimens);
  // Names on the axis and beside the points while they can be read.
  const bool named = specimens.size() <= kMostPanels;
  const fusion::Table differences = MethodDifferences(specimens);
  const fusion::Table marks = DifferenceMarks(differences);
  const fusion::Table wear = WearAndMu(specimens);
  WriteTextAtomically((fs::path(dir) / "method_differences.csv").string(),
                      WithNames(differences, specimens));
  std::vector<FigureSpec> figs = {
      Across("audit_fig13_mu_hat",
             "mu-hat per cycle, all specimens (Fig. 13)",
             "mu_hat_force",
             "mu-hat (-)",
             specimens),
      Across("audit_fig14_cost",
             "J per cycle, all specimens (Fig. 14)",
             "J_force",
             "J (-)",
             specimens),
      Across("audit_fig15_energy",
             "energy-based COF, all specimens (Fig. 15)",
             "mu_energy_g",
             "mu_Ed (-)",
             specimens)};
  figs.push_back(DifferencesFigure(specimens, named));
  if (!wear.rows.empty()) {
    WriteTextAtomically((fs::path(dir) / "wear_and_mu.csv").string(),
                        WithNames(wear, specimens));
    Series w("wear_and_mu.csv",
             "mu_hat",
             "wear_rate_mm3_per_N_m",
             "",
             {"mu_hat_low", "mu_hat_high"});
    w.style = "xerrorbars pt 7 lc rgb '#1f77b4'";
    figs.push_back(
        {"audit_wear_vs_mu",
         "specific wear rate against mu-hat, all specimens",
         {{"",
           "mu-hat, k from P (-)",
           "specific wear rate (mm^3/(N m))",
           "unset key\n" + (named ? PointLabels(specimens, wear) : ""),
           {},
           "",
           {w}}}});
  }
  const internal::TableSet tables = {{"cycles_by_specimen", &cycles},
                                     {"cycles_percentiles", &percentiles},
                                     {"method_differences.csv", &differences},
                                     {"difference_marks", &marks},
                                     {"wear_and_mu.csv", &wear}};
  return internal::Draw(dir, figs, tables, formats);
}

}  // namespace wearscar::report
