// The figures of one test (the paper's Figs. 5-8, 10-15, 17, the friction
// map and the track's history) and of a map alone, as rows of figure
// specs over the test's tables (fusion::TestTableSchemas).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "draw.h"
#include "images.h"
#include "wearscar/fusion/unit.h"
#include "wearscar/report/figures.h"

namespace wearscar::report {
namespace {

using internal::FigureSpec;
using internal::Image;
using internal::kClassicColour;
using internal::kForceColour;
using internal::kLimitColour;
using internal::kMeasuredColour;
using internal::kScanColour;
using internal::Panel;
using internal::Series;
using internal::TableSet;

// The force side's slope as the figures name it: "k from P" (P/S) or
// "k from the depth" (the depth channel).
std::string ForceSideK(const fusion::TestResult& r) {
  return r.profile.SlopeName();
}

// The force side's profile in a key: "P/S" (the spring), "depth" (the
// depth channel) or "friction profile" (a dead weight's friction).
std::string ForceSideProfile(const fusion::TestResult& r) {
  return r.profile.ShortProfileName();
}

Series Line(const char* table,
            const char* x,
            const char* y,
            std::string title,
            const char* colour,
            double width = 1.5,
            int dash = 1) {
  Series s(table, x, y, std::move(title));
  s.style = fmt::format("lines lw {} dt {} lc rgb '{}'", width, dash, colour);
  return s;
}

Series Dots(const char* table,
            const char* x,
            const char* y,
            std::string title,
            const char* colour,
            double size = 0.6,
            int type = 7) {
  Series s(table, x, y, std::move(title));
  s.style = fmt::format("points pt {} ps {} lc rgb '{}'", type, size, colour);
  return s;
}

// A band between two columns (a 95% interval).
Series Band(const char* table,
            const char* x,
            const char* low,
            const char* high,
            std::string title,
            const char* colour) {
  Series s(table, x, low, std::move(title), {high});
  s.style = fmt::format(
      "filledcurves lc rgb '{}' fs transparent solid 0.25 "
      "noborder",
      colour);
  return s;
}

// The running-in cycles shaded and labelled on a plot over cycles;
// nothing when there is none.
std::string RunningInMark(const fusion::TestResult& r) {
  const int n = r.force.running_in.cycles;
  if (n <= 0) return "";
  return fmt::format(
      "set object 1 rect from first 0.5, graph 0 to first {0}.5, graph 1 "
      "behind fc rgb '#e6e6e6' fs solid 1.0 noborder\n"
      "set label 1 'running-in ({0} cycles)' at first 1, graph 0.96 front\n",
      n);
}

// A figure of one panel.
FigureSpec Plot(std::string stem,
                std::string title,
                std::string xlabel,
                std::string ylabel,
                std::string setup,
                std::vector<Series> series) {
  return {std::move(stem),
          std::move(title),
          {{"",
            std::move(xlabel),
            std::move(ylabel),
            std::move(setup),
            {},
            "",
            std::move(series)}}};
}

// A column of cycles.csv over the cycles, as a line or as points.
Series OverCycles(const char* column,
                  std::string title,
                  const char* colour,
                  double width = 1.5,
                  int dash = 1) {
  return Line(
      "cycles.csv", "cycle", column, std::move(title), colour, width, dash);
}
Series DotsOverCycles(const char* column,
                      std::string title,
                      const char* colour) {
  return Dots("cycles.csv", "cycle", column, std::move(title), colour);
}

// Fig. 7: the loops of the cycles loops.csv holds.
FigureSpec LoopFigure(const std::string& name, const fusion::Table& loops) {
  FigureSpec f = Plot("fig07_loops",
                      name + ": hysteresis loops (Fig. 7)",
                      "x (mm)",
                      "Q (N)",
                      "",
                      {});
  std::set<double> cycles;
  for (const auto& row : loops.rows) cycles.insert(row[0]);
  for (double c : cycles) {
    Series s("loops.csv", "x_mm", "Q_N", fmt::format("cycle {:g}", c));
    s.select = "cycle";
    s.select_value = c;
    s.style = "lines lw 1.5";
    f.panels[0].series.push_back(s);
  }
  return f;
}

// Figs. 5-6 and 13-15 over the cycles, the running-in shaded.
std::vector<FigureSpec> CycleFigures(const std::string& name,
                                     const fusion::TestResult& r,
                                     const fusion::FuseOptions& o) {
  const std::string mark = RunningInMark(r);
  const std::string kp = ForceSideK(r);
  std::vector<FigureSpec> f = {
      Plot("fig05_q_envelope",
           name + ": envelope of Q (Fig. 5)",
           "cycle",
           "Q (N)",
           mark,
           {OverCycles("Q_max_N", "Q max", kForceColour),
            OverCycles("Q_min_N", "Q min", kScanColour)}),
      Plot("fig06_p_envelope",
           name + ": envelope of P (Fig. 6)",
           "cycle",
           "P (N)",
           mark,
           {OverCycles("P_max_N", "P max", kForceColour),
            OverCycles("P_min_N", "P min", kScanColour)}),
      Plot("fig13_mu_hat",
           name + ": mu-hat per cycle (Fig. 13)",
           "cycle",
           "mu (-)",
           mark,
           {Band("cycles.csv",
                 "cycle",
                 "mu_hat_force_low",
                 "mu_hat_force_high",
                 "95% interval, " + kp,
                 kForceColour),
            Band("cycles.csv",
                 "cycle",
                 "mu_hat_scan_low",
                 "mu_hat_scan_high",
                 "95% interval, k from scan",
                 kScanColour),
            DotsOverCycles("mu_hat_force", "mu-hat, " + kp, kForceColour),
            DotsOverCycles("mu_hat_scan", "mu-hat, k from scan", kScanColour),
            OverCycles("mu_mean", "mean method", kClassicColour)}),
      Plot("fig14_cost",
           name + ": J per cycle and its noise floor (Fig. 14)",
           "cycle",
           "J (-)",
           mark + "set yrange [0:*]\n",
           {DotsOverCycles("J_force", "J, " + kp, kForceColour),
            OverCycles(
                "J_force_floor", "its noise floor", kMeasuredColour, 2, 2),
            DotsOverCycles("J_scan", "J, k from scan", kScanColour),
            OverCycles("J_scan_floor", "its noise floor", kLimitColour, 2, 3)}),
      Plot(
          "fig15_energy_cof",
          name + ": energy-based COF (Fig. 15)",
          "cycle",
          "mu (-)",
          mark,
          {OverCycles("mu_energy_g", "E_d / (4 P delta_g)", kClassicColour),
           OverCycles("mu_energy_max", "E_d / (4 P delta_max)", kForceColour)}),
  };
  if (o.verdict.cost_criterion == fusion::CostCriterion::kPaperJ) {
    Series threshold;
    threshold.function = fmt::format("{}", o.verdict.max_cost);
    threshold.title = "threshold (paper)";
    threshold.style = fmt::format("lines dt 3 lw 2 lc rgb '{}'", kLimitColour);
    f[3].panels[0].series.push_back(threshold);
  }
  return f;
}

// A column of detail.csv along x, the line broken where the sliding
// direction changes.
Series AlongDetail(const char* column,
                   std::string title,
                   const char* colour,
                   double width = 1.5) {
  Series s =
      Line("detail.csv", "x_mm", column, std::move(title), colour, width);
  s.break_at = "direction";
  return s;
}

// Fig. 11's minima of J(mu): mu-hat and its J with each slope (the rows
// of `minima`: slope 0 from P, 1 from the scan).
void AddCostMinima(const fusion::TestResult& r,
                   fusion::Table* minima,
                   FigureSpec* fig11) {
  auto point =
      [&](const fusion::MuFit& fit, double slope, const char* what, int type) {
        if (!fit.converged) return;
        minima->rows.push_back({slope, fit.mu_hat, fit.cost});
        Series s =
            Dots("minima",
                 "mu",
                 "J",
                 fmt::format("minimum, k from {}: mu-hat {:.4f}, J {:.4f}",
                             what,
                             fit.mu_hat,
                             fit.cost),
                 kMeasuredColour,
                 1.6,
                 type);
        s.select = "slope";
        s.select_value = slope;
        fig11->panels[0].series.push_back(s);
      };
  const int dc = r.detail_cycle;
  if (dc >= 0 && dc < static_cast<int>(r.ForceFits().cycles.size()))
    point(r.ForceFits().cycles[dc], 0, "P", 7);
  const std::vector<fusion::MuFit>& scan_fits = r.ScanSlopeFits().cycles;
  if (r.scan && dc >= 0 && dc < static_cast<int>(scan_fits.size()))
    point(scan_fits[dc], 1, "scan", 5);
}

// Figs. 10-12 and 17 on the detail cycle.
std::vector<FigureSpec> DetailFigures(const std::string& name,
                                      const fusion::TestResult& r,
                                      fusion::Table* minima) {
  const std::string cycle = ", cycle " + std::to_string(r.detail_cycle + 1);
  const std::string kp = ForceSideK(r);
  std::vector<FigureSpec> f = {
      Plot("fig10_slope",
           name + ": slope k of the sliding path" + cycle + " (Fig. 10)",
           "x (mm)",
           "k (-)",
           "",
           {AlongDetail("k_force", kp, kForceColour, 1),
            AlongDetail("k_scan", "k from scan", kScanColour, 2.5)}),
      Plot(
          "fig11_cost",
          name + ": J(mu)" + cycle + " (Fig. 11)",
          "mu (-)",
          "J (-)",
          "set logscale y\n",
          {Line("cost_curve.csv", "mu", "J_force", kp, kForceColour),
           Line("cost_curve.csv", "mu", "J_scan", "k from scan", kScanColour)}),
      Plot(
          "fig12_reconstruction",
          name + ": measured and reconstructed Q" + cycle + " (Fig. 12)",
          "x (mm)",
          "Q (N)",
          "",
          {AlongDetail("Q_model_force_N", "wear-scar, " + kp, kForceColour),
           AlongDetail(
               "Q_model_scan_N", "wear-scar, k from scan", kScanColour, 2.5),
           Dots(
               "detail.csv", "x_mm", "Q_N", "measured", kMeasuredColour, 0.3)}),
  };
  AddCostMinima(r, minima, &f[1]);
  return f;
}

// The levelled map downsampled to at most 320 columns, in um.
Image MapImage(const scan::HeightMap& m) {
  const int f = std::max<int>(1, static_cast<int>(std::ceil(m.cols() / 320.0)));
  Image im;
  im.file = "scan_map.f32";
  im.width = static_cast<int>(m.cols() / f);
  im.height = static_cast<int>(m.rows() / f);
  im.dx = f * m.dx_mm;
  im.dy = f * m.dy_mm;
  im.palette = &internal::HeightPalette();
  im.values.resize(static_cast<size_t>(im.width) * im.height);
  for (int r = 0; r < im.height; ++r) {
    for (int c = 0; c < im.width; ++c) {
      double sum = 0;
      int n = 0;
      for (int dr = 0; dr < f; ++dr) {
        for (int dc = 0; dc < f; ++dc) {
          if (!m.valid(r * f + dr, c * f + dc)) continue;
          sum += m.height_mm(r * f + dr, c * f + dc);
          ++n;
        }
      }
      im.values[static_cast<size_t>(r) * im.width + c] =
          n > 0 ? static_cast<float>(1e3 * sum / n) : NAN;
    }
  }
  return im;
}

// The track's axis (line 0) and its two edges (lines 1, 2).
fusion::Table TrackOutline(const scan::Track& t) {
  const double th = t.angle_deg * M_PI / 180, ax = std::cos(th),
               ay = std::sin(th), half = 0.5 * t.length_mm;
  fusion::Table o({"line", "x_mm", "y_mm"});
  for (int line = 0; line < 3; ++line) {
    const double side = line == 0 ? 0 : line == 1 ? -1 : 1;
    const double ox = -ay * side * 0.5 * t.width_mm,
                 oy = ax * side * 0.5 * t.width_mm;
    o.rows.push_back({static_cast<double>(line),
                      t.centre_x_mm - half * ax + ox,
                      t.centre_y_mm - half * ay + oy});
    o.rows.push_back({static_cast<double>(line),
                      t.centre_x_mm + half * ax + ox,
                      t.centre_y_mm + half * ay + oy});
  }
  return o;
}

// The scan map with axes in mm spanning the map, a colour bar in um, a
// scale bar and, with a track, its axis and edges.
Panel MapPanel(const scan::HeightMap& m, const scan::Track* t) {
  Panel p{"", "x (mm)", "y (mm)", "", MapImage(m), "height (um)", {}};
  const Image& im = *p.image;
  const double w = im.width * im.dx, h = im.height * im.dy;
  const double bar = internal::ScaleBarMm(w), x0 = 0.05 * w, y0 = 0.06 * h;
  p.setup = fmt::format(
      "set size ratio -1\nset key bottom right inside opaque\n"
      "set xrange [{6}:{7}]\nset yrange [{8}:{9}]\n"
      "set arrow 1 from first {0}, first {1} to first {2}, first {1} nohead "
      "lw 4 lc rgb 'black' front\n"
      "set label 1 '{3:g} mm' at first {4}, first {5} center front\n",
      x0,
      y0,
      x0 + bar,
      bar,
      x0 + bar / 2,
      y0 + 0.05 * h,
      -0.5 * im.dx,
      w - 0.5 * im.dx,
      -0.5 * im.dy,
      h - 0.5 * im.dy);
  if (t == nullptr) return p;
  for (int line = 0; line < 3; ++line) {
    Series s("track_outline",
             "x_mm",
             "y_mm",
             line == 0   ? "track axis (centreline)"
             : line == 1 ? "track width"
                         : "");
    s.select = "line";
    s.select_value = line;
    s.style = line == 0 ? "lines lw 3 lc rgb 'red'"
                        : "lines lw 1.5 dt 2 lc rgb 'black'";
    p.series.push_back(s);
  }
  return p;
}

// One direction of a (cycle, direction, bin) grid as an image: bins
// centred on x, cycles from 1, forward sliding.
template <typename Value>
Image CycleGrid(const char* file,
                const std::vector<double>& x_mm,
                int cycles,
                Value value) {
  Image im;
  im.file = file;
  im.width = static_cast<int>(x_mm.size());
  im.height = cycles;
  im.dx = x_mm[1] - x_mm[0];
  im.dy = 1;
  im.x0 = x_mm[0];
  im.y0 = 1;
  im.palette = &internal::GridPalette();
  im.values.resize(x_mm.size() * static_cast<size_t>(cycles));
  for (int c = 0; c < cycles; ++c) {
    for (size_t b = 0; b < x_mm.size(); ++b)
      im.values[static_cast<size_t>(c) * x_mm.size() + b] =
          static_cast<float>(value(c, b));
  }
  return im;
}

// A unit's figure (fusion::UnitFigure) as the report draws it.
const char* Colour(fusion::UnitSeries::Role role) {
  using Role = fusion::UnitSeries::Role;
  switch (role) {
    case Role::kScan:
      return kScanColour;
    case Role::kMeasured:
      return kMeasuredColour;
    case Role::kClassic:
      return kClassicColour;
    case Role::kLimit:
      return kLimitColour;
    case Role::kForce:
      break;
  }
  return kForceColour;
}

FigureSpec FromUnit(const fusion::UnitFigure& u) {
  FigureSpec f{u.stem, u.title, {}};
  for (const fusion::UnitPanel& p : u.panels) {
    Panel panel{p.title, p.xlabel, p.ylabel, p.setup, {}, p.cblabel, {}};
    if (p.grid && p.grid->x_mm.size() >= 2) {
      const fusion::UnitGrid& g = *p.grid;
      const size_t bins = g.x_mm.size();
      panel.image = CycleGrid(
          g.file.c_str(), g.x_mm, g.rows, [&g, bins](int c, size_t b) {
            return g.values[static_cast<size_t>(c) * bins + b];
          });
    }
    for (const fusion::UnitSeries& s : p.series) {
      Series line = s.style == "points" ? Dots(s.table.c_str(),
                                               s.x.c_str(),
                                               s.y.c_str(),
                                               s.title,
                                               Colour(s.role))
                                        : Line(s.table.c_str(),
                                               s.x.c_str(),
                                               s.y.c_str(),
                                               s.title,
                                               Colour(s.role),
                                               s.width,
                                               s.dash);
      line.y_scale = s.y_scale;
      line.select = s.select;
      line.select_value = s.select_value;
      panel.series.push_back(std::move(line));
    }
    f.panels.push_back(std::move(panel));
  }
  return f;
}

}  // namespace

FigureSet DrawTestFigures(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& r,
                          const fusion::FuseOptions& options,
                          const fusion::TestProducts& products,
                          const FigureFormats& formats) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  TableSet tables;
  for (const auto& [file, table] : products.tables) tables[file] = &table;
  static const fusion::Table kNoLoops;
  const fusion::Table* loops = products.Find("loops.csv");
  std::vector<FigureSpec> figs = CycleFigures(name, r, options);
  figs.insert(figs.begin(), LoopFigure(name, loops ? *loops : kNoLoops));
  fusion::Table minima({"slope", "mu", "J"});
  fusion::Table outline;
  if (r.scan) {
    outline = TrackOutline(r.scan->track);
    tables["track_outline"] = &outline;
    FigureSpec map{"fig08ab_scan_map",
                   name + ": levelled scan, detected track (Fig. 8a-b)",
                   {MapPanel(r.scan->Levelled(), &r.scan->track)}};
    Series fwd = Line("profiles.csv",
                      "x_mm",
                      "f_forward_mm",
                      fmt::format("{} forward - {:.4f} mm",
                                  ForceSideProfile(r),
                                  r.scan->alignment.offset_mm),
                      kForceColour);
    Series rev = Line("profiles.csv",
                      "x_mm",
                      "f_reverse_mm",
                      fmt::format("{} reverse - {:.4f} mm",
                                  ForceSideProfile(r),
                                  r.scan->alignment.offset_mm),
                      kForceColour,
                      1.5,
                      2);
    fwd.y_offset = rev.y_offset = -r.scan->alignment.offset_mm;
    Series h =
        Line("profiles.csv",
             "x_mm",
             "h_scan_mm",
             fmt::format("scan centreline x {:.2f}", r.scan->alignment.scale),
             kScanColour,
             2.5);
    h.y_scale = r.scan->alignment.scale;
    figs.push_back(map);
    figs.push_back(
        {"fig08cd_profiles",
         fmt::format("{}: {} and the aligned scan profile (Fig. 8c-d)",
                     name,
                     r.profile.FromDepth() || r.profile.FromFriction()
                         ? r.profile.ProfileName()
                         : "the spring displacement P/S"),
         {{"", "x (mm)", "height (mm)", "", {}, "", {fwd, rev, h}}}});
  }
  if (!r.scan && r.unused_map) {
    figs.push_back({"fig08ab_scan_map",
                    name + ": levelled scan, no track found (not used)",
                    {MapPanel(*r.unused_map, nullptr)}});
  }
  for (FigureSpec& f : DetailFigures(name, r, &minima))
    figs.push_back(std::move(f));
  tables["minima"] = &minima;
  // The analysis units' figures, in the registry's order.
  for (const auto& [unit, result] : fusion::UnitsThatRan(r)) {
    for (const fusion::UnitFigure& f : unit->FiguresErased(result, name, r))
      figs.push_back(FromUnit(f));
  }
  return internal::Draw(dir, figs, tables, formats);
}

FigureSet DrawMapFigure(const std::string& dir,
                        const std::string& name,
                        const fusion::MapAnalysis& map,
                        const FigureFormats& formats) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  TableSet tables;
  fusion::Table outline;
  if (map.track) {
    outline = TrackOutline(*map.track);
    tables["track_outline"] = &outline;
  }
  const std::vector<FigureSpec> figs = {
      {"scan_map",
       name + (map.track ? ": levelled map and the worn track"
                         : ": levelled map (no track found)"),
       {MapPanel(map.levelled, map.track ? &*map.track : nullptr)}}};
  return internal::Draw(dir, figs, tables, formats);
}

}  // namespace wearscar::report
