#include "draw.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "wearscar/report/output_folder.h"
#include "wearscar/support/check.h"

namespace wearscar::report::internal {

// A canvas 1200 wide with text of 16 px (tick labels, legends and titles
// alike), readable at the figure's native size; 720 high, or 330 a row
// for three or more rows of panels.
std::string Terminal(const std::string& term, int rows) {
  const int height = std::max(720, 330 * rows);
  return term == "svg" ? fmt::format(
                             "set terminal svg size 1200,{} noenhanced font "
                             "'DejaVu Sans,16' background 'white'\n",
                             height)
                       : fmt::format(
                             "set terminal pngcairo size 1200,{} noenhanced "
                             "font 'DejaVu Sans,16'\n",
                             height);
}

namespace {

namespace fs = std::filesystem;

constexpr const char* kPreamble =
    "set datafile separator ','\nset datafile missing ''\nset grid\nset key "
    "below\nset style data lines\n";

std::string Cell(double v) {
  return std::isfinite(v) ? fmt::format("{:.8g}", v) : std::string();
}

// The rows at which a line's x has turned back (the end of a stroke, in a
// loop Q(x)): a turn is x retreating from its running extreme by more
// than a hundredth of the span, so that encoder noise breaks nothing, and
// the line breaks right after the extreme.
std::vector<bool> StrokeStarts(const std::vector<double>& x) {
  std::vector<bool> starts(x.size(), false);
  double lo = INFINITY, hi = -INFINITY;
  for (double v : x) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!(hi > lo)) return starts;
  const double tolerance = 1e-2 * (hi - lo);
  int heading = 0;
  size_t extreme = x.size();
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) continue;
    if (extreme == x.size()) {
      extreme = i;
      continue;
    }
    const double step = x[i] - x[extreme];
    if (heading == 0) {  // not yet moving
      if (std::abs(step) > tolerance) {
        heading = step > 0 ? 1 : -1;
        extreme = i;
      }
      continue;
    }
    if (step * heading >= 0) {
      extreme = i;
    } else if (-step * heading > tolerance) {
      if (extreme + 1 < x.size()) starts[extreme + 1] = true;
      heading = -heading;
      extreme = i;
    }
  }
  return starts;
}

// One series' block of the figure's data file: a comment naming its
// source, the columns' names, the rows.
std::string Block(const Series& s, const fusion::Table& t) {
  std::vector<std::string> names = {s.x, s.y};
  names.insert(names.end(), s.more.begin(), s.more.end());
  std::vector<int> at;
  for (const std::string& n : names) {
    at.push_back(t.ColumnIndex(n));
    WEARSCAR_CHECK(at.back() >= 0, "a figure plots a column of its table");
  }
  const int select = s.select.empty() ? -1 : t.ColumnIndex(s.select);
  const int brk = s.break_at.empty() ? -1 : t.ColumnIndex(s.break_at);
  WEARSCAR_CHECK(s.select.empty() || select >= 0,
                 "a figure selects by a column");
  WEARSCAR_CHECK(s.break_at.empty() || brk >= 0, "a figure breaks at a column");
  std::string out = fmt::format(
      "# {}: {}{}\n",
      s.table,
      fmt::join(names, ","),
      select >= 0 ? fmt::format(" where {} = {}", s.select, s.select_value)
                  : "");
  out += fmt::format("{}\n", fmt::join(names, ","));
  std::vector<const std::vector<double>*> rows;
  std::vector<double> x;
  for (const auto& row : t.rows) {
    if (select >= 0 && row[select] != s.select_value) continue;
    rows.push_back(&row);
    x.push_back(row[at[0]]);
  }
  // A line breaks where x turns back, too: no line joins two strokes.
  const bool lines = s.style.rfind("lines", 0) == 0;
  const std::vector<bool> turn =
      lines ? StrokeStarts(x) : std::vector<bool>(x.size(), false);
  double previous = NAN;
  bool first = true;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& row = *rows[i];
    if (brk >= 0 && !first && row[brk] != previous) {
      out += '\n';
    } else if (turn[i]) {
      out += '\n';
    }
    if (brk >= 0) previous = row[brk];
    first = false;
    for (size_t k = 0; k < at.size(); ++k) {
      if (k > 0) out += ',';
      out += Cell(row[at[k]]);
    }
    out += '\n';
  }
  return out;
}

// The plot clause of a series whose block is `index` of `data`. The block
// holds the series' columns in the order Block writes them (x, y, more),
// named in its header row, which gnuplot skips: the clause refers to them
// by number, since a column named in `using` is looked up through
// gnuplot's expression evaluator on every row (docs/performance.md).
std::string Clause(const Series& s, const std::string& data, int index) {
  const std::string title =
      s.title.empty() ? "notitle" : "title " + Quote(s.title);
  if (!s.function.empty())
    return fmt::format("{} with {} {}", s.function, s.style, title);
  std::string y = "2";
  if (s.y_scale != 1 || s.y_offset != 0) {
    y = fmt::format("($2*{}+{})", s.y_scale, s.y_offset);
  }
  std::string using_ = "1:" + y;
  for (size_t k = 0; k < s.more.size(); ++k)
    using_ += fmt::format(":{}", k + 3);
  return fmt::format("{} index {} using {} with {} {}",
                     Quote(data),
                     index,
                     using_,
                     s.style,
                     title);
}

// A figure's data file and its panels' commands for `term`; the rasters
// it paints in SVG are added to `pngs`.
struct FigureScript {
  std::string data;                             // figure-data/<stem>.csv
  std::vector<std::vector<std::string>> plots;  // per panel: clauses
  std::vector<std::string> svg_plots;           // per panel: with stand-ins
  std::vector<std::string> pngs;
  std::vector<std::string> image_setup;  // per panel
  std::vector<std::string> svg_notes;    // per panel: comment lines
};

FigureScript Prepare(const std::string& dir,
                     const FigureSpec& f,
                     const TableSet& tables) {
  FigureScript out;
  const std::string data_name =
      std::string(kFigureData) + "/" + f.stem + ".csv";
  int index = 0;
  for (const Panel& p : f.panels) {
    std::vector<std::string> clauses, svg_clauses;
    std::string setup, note;
    if (p.image) {
      const Raster r = MakeRaster(dir, *p.image);
      setup += PaletteCommand(*p.image->palette);
      clauses.push_back(r.plot + " notitle");
      if (!r.png.empty()) {
        setup += fmt::format("set cbrange [{}:{}]\n", r.lo, r.hi);
        svg_clauses.push_back(r.stand_in + " notitle");
        note =
            "# wearscar paints the image over this 2 x 2 stand-in; "
            "gnuplot draws it with: plot " +
            r.plot + "\n";
        out.pngs.push_back(r.png);
      } else {
        svg_clauses.push_back(r.plot + " notitle");
      }
    }
    for (const Series& s : p.series) {
      std::string clause;
      if (s.function.empty()) {
        const auto t = tables.find(s.table);
        WEARSCAR_CHECK(t != tables.end() && t->second != nullptr,
                       "a figure's table is given to Draw");
        if (index > 0) out.data += "\n\n";
        out.data += Block(s, *t->second);
        clause = Clause(s, data_name, index++);
      } else {
        clause = Clause(s, data_name, 0);
      }
      clauses.push_back(clause);
      svg_clauses.push_back(clause);
    }
    out.plots.push_back(clauses);
    out.svg_plots.push_back(
        fmt::format("{}", fmt::join(svg_clauses, ", \\\n  ")));
    out.image_setup.push_back(setup);
    out.svg_notes.push_back(note);
  }
  return out;
}

std::string PanelCommands(const Panel& p,
                          const std::string& image_setup,
                          const std::string& note,
                          const std::string& plot) {
  std::string s;
  if (!p.title.empty()) s += "set title " + Quote(p.title) + "\n";
  if (!p.xlabel.empty()) s += "set xlabel " + Quote(p.xlabel) + "\n";
  if (!p.ylabel.empty()) s += "set ylabel " + Quote(p.ylabel) + "\n";
  if (!p.cblabel.empty()) s += "set cblabel " + Quote(p.cblabel) + "\n";
  s += image_setup + p.setup;
  if (!s.empty() && s.back() != '\n') s += '\n';
  return s + note + "plot " + plot + "\n";
}

// The commands drawing figure `f` into <stem>.<term>.part.
std::string FigureCommands(const FigureSpec& f,
                           const FigureScript& prepared,
                           const std::string& term) {
  const bool svg = term == "svg";
  const int columns = std::max(1, f.columns);
  const int rows = (static_cast<int>(f.panels.size()) + columns - 1) / columns;
  std::string s = fmt::format("# {}: {}\n{}set output {}\n",
                              f.stem,
                              f.title,
                              Terminal(term, rows),
                              Quote(f.stem + "." + term + ".part"));
  const bool multi = f.panels.size() > 1;
  if (multi) {
    s += fmt::format(
        "set multiplot layout {},{} title {}\n", rows, columns, Quote(f.title));
  } else {
    s += "set title " + Quote(f.title) + "\n";
  }
  for (size_t k = 0; k < f.panels.size(); ++k) {
    const std::string plot =
        svg ? prepared.svg_plots[k]
            : fmt::format("{}", fmt::join(prepared.plots[k], ", \\\n  "));
    s += PanelCommands(f.panels[k],
                       prepared.image_setup[k],
                       svg ? prepared.svg_notes[k] : "",
                       plot);
  }
  if (multi) s += "unset multiplot\n";
  return s + "unset output\nreset session\n" + kPreamble;
}

// gnuplot on figure-data/<script> in `dir` (the figures' data files are
// named relative to it), its output in <script stem>.log beside the
// script, without a shell. Returns the pid, or -1.
pid_t StartGnuplot(const std::string& dir, const std::string& script) {
  const std::string abs = fs::absolute(dir).string();
  const std::string log =
      FigureDataPath(abs, fs::path(script).stem().string() + ".log");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, abs.c_str());
  posix_spawn_file_actions_addopen(
      &actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(
      &actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::string program = "gnuplot",
              arg = std::string(kFigureData) + "/" + script;
  char* argv[] = {program.data(), arg.data(), nullptr};
  pid_t pid = -1;
  const int error =
      posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

// A figure file is drawn when it exists, is not empty and starts as its
// format does.
bool LooksDrawn(const std::string& path, const std::string& term) {
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, sizeof(head));
  if (in.gcount() < 4) return false;
  if (term == "png") return std::memcmp(head, "\x89PNG", 4) == 0;
  return std::memcmp(head, "<?xm", 4) == 0 || std::memcmp(head, "<svg", 4) == 0;
}

// Renames the drawn figures into place; what is missing is in the set.
FigureSet Collect(const std::string& dir,
                  const std::vector<FigureSpec>& figures,
                  const std::vector<FigureScript>& prepared,
                  const std::vector<std::string>& terms) {
  FigureSet set;
  for (size_t i = 0; i < figures.size(); ++i) {
    const FigureSpec& f = figures[i];
    std::string shown;
    for (const std::string& term : terms) {
      const std::string final_path =
          (fs::path(dir) / (f.stem + "." + term)).string();
      const std::string part = final_path + ".part";
      if (LooksDrawn(part, term) &&
          (term != "svg" || PaintRasters(part, prepared[i].pngs)) &&
          std::rename(part.c_str(), final_path.c_str()) == 0) {
        set.files.push_back(final_path);
        if (shown.empty()) shown = final_path;
        continue;
      }
      std::remove(part.c_str());
      set.missing.push_back(f.stem + "." + term);
    }
    if (!shown.empty()) {
      set.shown.push_back(shown);
      set.titles.push_back(f.title);
    }
  }
  return set;
}

}  // namespace

std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

bool RunGnuplot(const std::string& dir, const std::string& script) {
  const pid_t pid = StartGnuplot(dir, script);
  int status = 0;
  return pid >= 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) &&
         WEXITSTATUS(status) == 0;
}

FigureSet Draw(const std::string& dir,
               const std::vector<FigureSpec>& figures,
               const TableSet& tables,
               const FigureFormats& formats) {
  // PNG first: what a report shows when both are drawn.
  std::vector<std::string> terms;
  if (formats.png) terms.emplace_back("png");
  if (formats.svg) terms.emplace_back("svg");
  std::vector<FigureScript> prepared;
  std::string script = kPreamble;
  for (const FigureSpec& f : figures) {
    prepared.push_back(Prepare(dir, f, tables));
    if (!prepared.back().data.empty()) {
      WriteTextAtomically(FigureDataPath(dir, f.stem + ".csv"),
                          prepared.back().data);
    }
    for (const std::string& term : terms)
      script += FigureCommands(f, prepared.back(), term);
  }
  WriteTextAtomically(FigureDataPath(dir, "figures.gp"), script);
  const bool ran = RunGnuplot(dir, "figures.gp");
  FigureSet set = Collect(dir, figures, prepared, terms);
  if (set.missing.empty()) return set;
  set.message = fmt::format(
      "{} of the {} figures asked for were not drawn ({}{}){}",
      set.missing.size(),
      terms.size() * figures.size(),
      set.missing[0],
      set.missing.size() > 1 ? ", ..." : "",
      ran ? ""
          : fmt::format("; gnuplot failed: see {}/figures.log", kFigureData));
  return set;
}

}  // namespace wearscar::report::internal
