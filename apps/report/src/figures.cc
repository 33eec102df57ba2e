#include "wearscar/report/figures.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <numeric>
#include <string_view>

#include "wearscar/fusion/products.h"
#include "wearscar/report/html_report.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/support/check.h"
#include "wearscar/support/png.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;

// An image plot of a float32 grid in figure-data. In a PNG figure gnuplot
// draws the grid (`plot`). In an SVG figure it draws a 2 x 2 stand-in of
// the same extent and colour range (`stand_in`) and this program then puts
// the grid, painted in the palette gnuplot would have used, in place of the
// stand-in's embedded bitmap (`png`): gnuplot spent 20-35 ms of CPU on
// each 7 k-50 k pixel image, most of the test's figure time, where the
// painting and its PNG take 1-2 ms. The same pixels, to one level of 255
// (tests/report/figures_test.cc).
struct Raster {
  std::string plot, stand_in, png;
};

// A figure: its file stem, title and gnuplot body (after terminal/output),
// where RasterMarker(i) stands for the plot clause of rasters[i].
struct Figure {
  std::string stem, title, body;
  // gnuplot's time for it in SVG, ms (DrawingMs): balances the two
  // scripts.
  int weight = 5;
  std::vector<Raster> rasters = {};
};

// Where a figure's body has a raster's plot clause: ASCII record
// separators, which no gnuplot command holds.
std::string RasterMarker(size_t i) { return fmt::format("\x1e{}\x1e", i); }

// A colour scale: gnuplot's `set palette defined` with evenly spaced
// stops, 0xRRGGBB each.
using Palette = std::vector<unsigned>;

// The scan map's heights: violet, blue, teal, green, yellow, white.
const Palette& HeightPalette() {
  static const Palette p{
      0x2c0e5a, 0x3b5ba5, 0x2fa39a, 0xa6d96a, 0xfee08b, 0xf9f9f9};
  return p;
}

// Values over cycles and x (the friction map, the track's history): the
// same without the white.
const Palette& GridPalette() {
  static const Palette p{0x2c0e5a, 0x3b5ba5, 0x2fa39a, 0xa6d96a, 0xfee08b};
  return p;
}

std::string PaletteCommand(const Palette& p) {
  std::string s = "set palette defined (";
  for (size_t i = 0; i < p.size(); ++i)
    s += fmt::format("{}{} '#{:06x}'", i ? ", " : "", i, p[i]);
  return s + ")\n";
}

// The colour gnuplot gives `gray` (0 to 1) on `p`: linear in RGB between
// the two stops about it, each channel rounded to 1/255.
void PaletteColour(const Palette& p, double gray, unsigned char* rgb) {
  const size_t n = p.size() - 1;
  const size_t k =
      std::min(static_cast<size_t>(std::clamp(gray, 0.0, 1.0) * n), n - 1);
  const double from = static_cast<double>(k) / n,
               to = static_cast<double>(k + 1) / n;
  const double f = (gray - from) / (to - from);
  for (int j = 0; j < 3; ++j) {
    const int shift = 16 - 8 * j;
    const double a = ((p[k] >> shift) & 255) / 255.0,
                 b = ((p[k + 1] >> shift) & 255) / 255.0;
    rgb[j] = static_cast<unsigned char>(255 * (a + f * (b - a)) + 0.5);
  }
}

// The grid `values` (width x height, row by row from y0 upwards, NaN for
// no value) as float32 <file> in figure-data, its pixels dx x dy centred
// from (x0, y0): returns gnuplot's commands drawing it in `palette` over
// its range of values, and adds its raster to `fig`. A grid without two
// distinct values is left to gnuplot's own scaling.
std::string ImagePlot(const std::string& dir,
                      const std::string& file,
                      int width,
                      int height,
                      double dx,
                      double dy,
                      double x0,
                      double y0,
                      const std::vector<float>& values,
                      const Palette& palette,
                      Figure* fig) {
  WEARSCAR_CHECK(values.size() == static_cast<size_t>(width) * height,
                 "an image plot has width x height values");
  WriteTextAtomically(FigureDataPath(dir, file),
                      std::string(reinterpret_cast<const char*>(values.data()),
                                  values.size() * sizeof(float)));
  const std::string plot = fmt::format(
      "'{}/{}' binary array=({},{}) dx={} dy={} origin=({},{}) "
      "format='%float32' with image",
      kFigureData,
      file,
      width,
      height,
      dx,
      dy,
      x0,
      y0);
  double lo = INFINITY, hi = -INFINITY;
  for (float v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min<double>(lo, v);
    hi = std::max<double>(hi, v);
  }
  if (!(hi > lo)) return "plot " + plot;
  // Rows of RGBA from the top (the grid's last row); transparent where the
  // grid has no value, as gnuplot leaves it.
  std::vector<unsigned char> rgba(values.size() * 4, 0);
  for (int r = 0; r < height; ++r) {
    const float* row =
        values.data() + static_cast<size_t>(height - 1 - r) * width;
    unsigned char* out = rgba.data() + static_cast<size_t>(r) * width * 4;
    for (int c = 0; c < width; ++c, out += 4) {
      if (!std::isfinite(row[c])) continue;
      PaletteColour(palette, (row[c] - lo) / (hi - lo), out);
      out[3] = 255;
    }
  }
  std::string why;
  // zlib's fastest level, no row filters: a tenth of libpng's default
  // time, about as large as gnuplot's own PNG.
  std::string png = support::EncodePng(width,
                                       height,
                                       4,
                                       /*bgr=*/false,
                                       rgba.data(),
                                       4L * width,
                                       {1, /*filter_rows=*/false},
                                       &why);
  if (png.empty()) return "plot " + plot;  // gnuplot draws it then
  // Two pixels each way over the grid's extent (Draw writes the file).
  const double sx = 0.5 * width * dx, sy = 0.5 * height * dy;
  const std::string stand_in = fmt::format(
      "'{}/stand_in.f32' binary array=(2,2) dx={} dy={} origin=({},{}) "
      "format='%float32' with image",
      kFigureData,
      sx,
      sy,
      x0 - 0.5 * dx + 0.5 * sx,
      y0 - 0.5 * dy + 0.5 * sy);
  fig->rasters.push_back({plot, stand_in, std::move(png)});
  return fmt::format("set cbrange [{}:{}]\nplot {}",
                     lo,
                     hi,
                     RasterMarker(fig->rasters.size() - 1));
}

// A figure's body for `term`: each raster's clause in place of its marker;
// in SVG the stand-ins, with the clause that draws the grid itself in a
// comment (for whoever runs the script on its own).
std::string BodyFor(const Figure& f, const std::string& term) {
  std::string body = f.body, note;
  for (size_t i = 0; i < f.rasters.size(); ++i) {
    const std::string marker = RasterMarker(i);
    const size_t at = body.find(marker);
    WEARSCAR_CHECK(at != std::string::npos, "a raster's marker is in its body");
    const bool svg = term == "svg";
    body.replace(
        at, marker.size(), svg ? f.rasters[i].stand_in : f.rasters[i].plot);
    if (svg) {
      note += fmt::format(
          "# wearscar puts image {} into the SVG over its 2 x 2 stand-in; "
          "gnuplot draws it with: plot {}\n",
          i + 1,
          f.rasters[i].plot);
    }
  }
  return note + body;
}

// Puts the rasters' PNGs, in order, in place of the bitmaps gnuplot
// embedded in the SVG at `path` for their stand-ins. False (the file
// left as it is) when the SVG does not hold one bitmap per raster.
bool PaintRasters(const std::string& path, const std::vector<Raster>& rasters) {
  if (rasters.empty()) return true;
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) return false;
  const std::string svg((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
  static constexpr std::string_view kData = "data:image/png;base64,";
  std::string out;
  size_t from = 0, k = 0;
  for (size_t at = svg.find(kData); at != std::string::npos;
       at = svg.find(kData, from)) {
    const size_t payload = at + kData.size();
    const size_t end = svg.find_first_of("'\"", payload);
    if (k == rasters.size() || end == std::string::npos) return false;
    out.append(svg, from, payload - from);
    out += Base64(rasters[k++].png);
    from = end;
  }
  if (k != rasters.size()) return false;
  out.append(svg, from, std::string::npos);
  WriteTextAtomically(path, out);
  return true;
}

std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

// gnuplot splits and converts every field of a data file's rows, the
// columns a plot does not use too: about 50 ns a field, so a clause over
// cycles.csv (30 columns, 600 rows) costs about 1 ms, and reading the
// result tables was about 30 of the 58 ms of CPU gnuplot spent on a
// test's 14 SVG figures. Each figure's clauses over a result table read a
// copy in figure-data holding only the columns the figure uses
// (<figure>.<table>), with the header, rows and blank lines as they are
// (`skip`, `every` and `index` select the same rows) and the columns of
// `using` renumbered. The script keeps each plot command as written over
// the tables in a comment above it. The figures are the same to the byte
// (tests/report/figures_test.cc).
class SlimTables {
 public:
  explicit SlimTables(std::string dir) : dir_(std::move(dir)) {}

  // `body` with its plot commands over the tables in `dir` reading their
  // copies for the figure `stem`; a clause this cannot follow (no `using`,
  // a column named by a variable, a quoted field in the table) keeps the
  // table it names.
  std::string Rewrite(const std::string& stem, const std::string& body);

 private:
  // A result table split into fields once; nullptr when it is not one
  // this can copy (absent, a quote in it, a path leaving `dir`).
  struct Table {
    std::vector<std::vector<std::string_view>> rows;  // blank line: none
    std::string text;
  };
  const Table* Read(const std::string& file);

  std::string dir_;
  std::map<std::string, std::unique_ptr<Table>> tables_;
  // The copies written: their names in figure-data and the tables they
  // copy (two tables whose names differ only by '/' and '_' are never
  // given one copy).
  std::map<std::string, std::string> written_;
};

// The name in figure-data of a figure's copy of a table: <figure>.<table>,
// a table in a sub-folder with '_' for '/'.
std::string CopyName(const std::string& figure, const std::string& table) {
  std::string name = figure + "." + table;
  std::replace(name.begin(), name.end(), '/', '_');
  return name;
}

// Splits `s` at `separator` outside quotes (gnuplot's '...' and "...")
// and parentheses.
std::vector<std::string> SplitOutside(const std::string& s, char separator) {
  std::vector<std::string> parts(1);
  int depth = 0;
  char quote = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote != 0) {
      if (c == '\\' && quote == '"' && i + 1 < s.size()) {
        parts.back() += c;
        parts.back() += s[++i];
        continue;
      }
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '(') {
      ++depth;
    } else if (c == ')') {
      --depth;
    } else if (c == separator && depth == 0) {
      parts.emplace_back();
      continue;
    }
    parts.back() += c;
  }
  return parts;
}

// The data file a clause names first ('...', with '' inside for a quote),
// and where its text after the name starts; false when the clause does
// not start with a quoted name.
bool ClauseFile(const std::string& clause, std::string* file, size_t* rest) {
  size_t i = clause.find_first_not_of(' ');
  if (i == std::string::npos || clause[i] != '\'') return false;
  file->clear();
  for (++i; i < clause.size(); ++i) {
    if (clause[i] != '\'') {
      *file += clause[i];
    } else if (i + 1 < clause.size() && clause[i + 1] == '\'') {
      *file += '\'';
      ++i;
    } else {
      *rest = i + 1;
      return true;
    }
  }
  return false;
}

// Where a clause's `using` specification is: [*begin, *end) (it ends at
// a blank outside parentheses and quotes); false without one.
bool UsingSpec(const std::string& clause,
               size_t from,
               size_t* begin,
               size_t* end) {
  char quote = 0;
  for (size_t i = from; i < clause.size(); ++i) {
    const char c = clause[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '\'' || c == '"') {
      quote = c;
      continue;
    }
    if (clause.compare(i, 7, " using ") != 0) continue;
    size_t j = i + 7;
    while (j < clause.size() && clause[j] == ' ') ++j;
    *begin = j;
    int depth = 0;
    for (; j < clause.size(); ++j) {
      if (clause[j] == '(') ++depth;
      if (clause[j] == ')') --depth;
      if (clause[j] == ' ' && depth == 0) break;
    }
    *end = j;
    return *end > *begin;
  }
  return false;
}

// The columns a `using` specification reads: a part that is a number, $N,
// and column(N) and its kin (N >= 1: 0 and below are gnuplot's
// pseudo-columns, the same in any file). With `map`, the specification
// with each such N replaced by map(N). False when it reads a column this
// cannot see ($ or column( not followed by a number).
template <typename Map>
bool SpecColumns(const std::string& spec,
                 std::vector<int>* columns,
                 const Map& map,
                 std::string* rewritten) {
  static const char* const kByColumn[] = {"$",
                                          "column(",
                                          "stringcolumn(",
                                          "strcol(",
                                          "valid(",
                                          "xtic(",
                                          "xticlabels(",
                                          "ytic(",
                                          "yticlabels(",
                                          "x2tic(",
                                          "y2tic(",
                                          "ztic(",
                                          "cbtic("};
  const auto digits = [](const std::string& s, size_t at) {
    size_t e = at;
    while (e < s.size() && std::isdigit(static_cast<unsigned char>(s[e]))) ++e;
    return e;
  };
  if (rewritten) rewritten->clear();
  const std::vector<std::string> parts = SplitOutside(spec, ':');
  for (size_t p = 0; p < parts.size(); ++p) {
    const std::string& part = parts[p];
    std::string out;
    if (!part.empty() && digits(part, 0) == part.size()) {
      const int n = std::stoi(part);
      if (n >= 1) columns->push_back(n);
      out = n >= 1 ? std::to_string(map(n)) : part;
    } else {
      for (size_t i = 0; i < part.size();) {
        const char* found = nullptr;
        for (const char* name : kByColumn) {
          const size_t len = std::strlen(name);
          // A function's name starts a word (not the end of another's).
          const bool starts =
              i == 0 ||
              !(std::isalnum(static_cast<unsigned char>(part[i - 1])) ||
                part[i - 1] == '_');
          if (part.compare(i, len, name) == 0 && (name[0] == '$' || starts)) {
            found = name;
            break;
          }
        }
        if (found == nullptr) {
          out += part[i++];
          continue;
        }
        const size_t at = i + std::strlen(found), e = digits(part, at);
        // $name, column(expression): not a column this can follow.
        if (e == at ||
            (found[0] != '$' && (e == part.size() || part[e] != ')')))
          return false;
        const int n = std::stoi(part.substr(at, e - at));
        if (n >= 1) columns->push_back(n);
        out += part.substr(i, at - i) +
               (n >= 1 ? std::to_string(map(n)) : part.substr(at, e - at));
        i = e;
      }
    }
    if (rewritten) *rewritten += (p > 0 ? ":" : "") + out;
  }
  return true;
}

const SlimTables::Table* SlimTables::Read(const std::string& file) {
  auto it = tables_.find(file);
  if (it != tables_.end()) return it->second.get();
  std::unique_ptr<Table>& t = tables_[file];
  const fs::path path(file);
  // The tables in the folder; not figure-data's own files.
  const bool inside = path.is_relative() && path.extension() == ".csv" &&
                      *path.begin() != kFigureData &&
                      std::none_of(path.begin(),
                                   path.end(),
                                   [](const fs::path& p) { return p == ".."; });
  if (!inside) return nullptr;
  std::ifstream in(fs::path(dir_) / path, std::ios::binary);
  if (!in) return nullptr;
  auto table = std::make_unique<Table>();
  table->text.assign(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
  if (table->text.find('"') != std::string::npos) return nullptr;
  std::string_view text = table->text;
  while (!text.empty()) {
    const size_t eol = std::min(text.find('\n'), text.size());
    std::string_view line = text.substr(0, eol);
    text.remove_prefix(std::min(eol + 1, text.size()));
    std::vector<std::string_view>& row = table->rows.emplace_back();
    if (line.empty()) continue;
    for (;;) {
      const size_t comma = line.find(',');
      row.push_back(line.substr(0, comma));
      if (comma == std::string_view::npos) break;
      line.remove_prefix(comma + 1);
    }
  }
  t = std::move(table);
  return t.get();
}

std::string SlimTables::Rewrite(const std::string& stem,
                                const std::string& body) {
  // The body's lines; the plot commands' clauses.
  std::vector<std::string> lines;
  for (size_t at = 0; at <= body.size();) {
    const size_t eol = std::min(body.find('\n', at), body.size());
    lines.push_back(body.substr(at, eol - at));
    at = eol + 1;
  }
  struct Clause {
    std::string file, text;
  };
  std::map<size_t, std::vector<Clause>> plots;  // by line
  // Per table: the columns the figure reads, or not copied (false).
  std::map<std::string, std::pair<bool, std::vector<int>>> used;
  const auto identity = [](int n) { return n; };
  for (size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].rfind("plot ", 0) != 0) continue;
    std::vector<Clause>& clauses = plots[l];
    std::string previous;
    for (std::string& text : SplitOutside(lines[l].substr(5), ',')) {
      Clause c{"", std::move(text)};
      size_t rest = 0;
      if (ClauseFile(c.text, &c.file, &rest)) {
        if (c.file.empty()) c.file = previous;
        previous = c.file;
        if (Read(c.file) != nullptr) {
          auto& [ok, columns] =
              used.try_emplace(c.file, true, std::vector<int>()).first->second;
          size_t b = 0, e = 0;
          ok =
              ok && UsingSpec(c.text, rest, &b, &e) &&
              SpecColumns(c.text.substr(b, e - b), &columns, identity, nullptr);
        }
      } else {
        c.file.clear();
      }
      clauses.push_back(std::move(c));
    }
  }
  // The copies: the columns in the table's order.
  std::map<std::string, std::vector<int>> renumber;  // old -> new, by table
  for (auto& [file, entry] : used) {
    auto& [ok, columns] = entry;
    if (!ok || columns.empty()) continue;
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const Table& t = *Read(file);
    std::string copy;
    copy.reserve(t.text.size() / 4);
    bool fits = true;
    for (const auto& row : t.rows) {
      if (!row.empty()) {
        if (static_cast<int>(row.size()) < columns.back()) fits = false;
        if (!fits) break;
        size_t length = 0;
        for (size_t k = 0; k < columns.size(); ++k) {
          if (k > 0) copy += ',';
          const std::string_view v = row[columns[k] - 1];
          copy.append(v.data(), v.size());
          length += v.size();
        }
        // One empty field would read as a blank line (a new block).
        if (length == 0 && columns.size() == 1) fits = false;
      }
      copy += '\n';
    }
    const std::string name = CopyName(stem, file);
    const auto [at, added] = written_.try_emplace(name, file);
    if (!fits || at->second != file) continue;
    if (added) WriteTextAtomically(FigureDataPath(dir_, name), copy);
    std::vector<int>& to = renumber[file];
    to.assign(columns.back() + 1, 0);
    for (size_t k = 0; k < columns.size(); ++k)
      to[columns[k]] = static_cast<int>(k + 1);
  }
  if (renumber.empty()) return body;
  std::string out;
  for (size_t l = 0; l < lines.size(); ++l) {
    if (l > 0) out += '\n';
    auto p = plots.find(l);
    bool changed = false;
    std::string plot = "plot ";
    if (p != plots.end()) {
      for (size_t k = 0; k < p->second.size(); ++k) {
        Clause& c = p->second[k];
        auto r = renumber.find(c.file);
        std::string text = c.text;
        if (!c.file.empty() && r != renumber.end()) {
          std::string given;
          size_t rest = 0, b = 0, e = 0;
          ClauseFile(text, &given, &rest);
          UsingSpec(text, rest, &b, &e);
          std::vector<int> columns;
          std::string spec;
          const std::vector<int>& to = r->second;
          SpecColumns(
              text.substr(b, e - b),
              &columns,
              [&](int n) { return to[n]; },
              &spec);
          text.replace(b, e - b, spec);
          if (!given.empty()) {
            const size_t q = text.find('\'');
            text.replace(
                q,
                rest - q,
                Quote(std::string(kFigureData) + "/" + CopyName(stem, c.file)));
          }
          changed = true;
        }
        plot += (k > 0 ? "," : "") + text;
      }
    }
    if (changed) {
      out += "# over the result tables: " + lines[l] + "\n" + plot;
    } else {
      out += lines[l];
    }
  }
  return out;
}

// gnuplot with one script, in `dir`, output to `log`, without a shell (a
// folder name with quotes or spaces is only ever a path). Returns the pid,
// or -1 with errno.
pid_t SpawnGnuplot(const std::string& dir,
                   const std::string& script,
                   const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  posix_spawn_file_actions_addopen(
      &actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(
      &actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::string program = "gnuplot", arg = script;
  char* argv[] = {program.data(), arg.data(), nullptr};
  pid_t pid = -1;
  const int error =
      posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    errno = error;
    return -1;
  }
  return pid;
}

// gnuplot on <dir>/figure-data/<script>, in `dir` (the figures' data
// files are named relative to it), its output in <script stem>.log beside
// the script. Returns the pid, or -1.
pid_t StartGnuplot(const std::string& dir, const std::string& script) {
  const std::string abs = fs::absolute(dir).string();
  const std::string stem = fs::path(script).stem().string();
  return SpawnGnuplot(abs,
                      std::string(kFigureData) + "/" + script,
                      FigureDataPath(abs, stem + ".log"));
}

bool WaitGnuplot(pid_t pid) {
  int status = 0;
  return pid >= 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) &&
         WEXITSTATUS(status) == 0;
}

// A figure file is drawn when it exists, is not empty and starts as its
// format does.
bool LooksDrawn(const std::string& path, const char* term) {
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, sizeof(head));
  if (in.gcount() < 4) return false;
  if (std::string(term) == "png") return std::memcmp(head, "\x89PNG", 4) == 0;
  return std::memcmp(head, "<?xm", 4) == 0 || std::memcmp(head, "<svg", 4) == 0;
}

// The formats asked for, PNG first (what a report shows when both are
// drawn).
std::vector<const char*> Terms(const FigureFormats& formats) {
  std::vector<const char*> terms;
  if (formats.png) terms.push_back("png");
  if (formats.svg) terms.push_back("svg");
  return terms;
}

// Runs gnuplot on the figures in each format asked for: with PNG on two
// scripts side by side (two processes, the figures split by weight), so
// that both cores are busy (0.67x the wall time of one on the full-size
// test); in SVG alone one gnuplot draws them all as fast as two (0.123
// against 0.124 s) for half the CPU, the second's start costing what the
// split saves. Each figure is drawn under a temporary name and renamed into
// place only when it is there, not empty and of its format: a killed or failed
// gnuplot leaves no half figure. What was asked for and not drawn is in
// the set's `missing`, with a message.
FigureSet Draw(const std::string& dir,
               const std::vector<Figure>& figures,
               const FigureFormats& formats,
               int processes = 2,
               GnuplotSession* session = nullptr) {
  const std::vector<const char*> terms = Terms(formats);
  const size_t scripts =
      std::min<size_t>(session != nullptr || !formats.png
                           ? 1
                           : static_cast<size_t>(std::clamp(processes, 1, 2)),
                       figures.size());
  // Heaviest first, each to the script with the least weight so far.
  std::vector<size_t> order(figures.size());
  std::iota(order.begin(), order.end(), size_t{0});
  // In PNG gnuplot draws each image itself, 15-35 ms.
  const auto weight = [&](const Figure& f) {
    return f.weight +
           (formats.png ? 25 * static_cast<int>(f.rasters.size()) : 0);
  };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return weight(figures[a]) > weight(figures[b]);
  });
  std::vector<std::vector<size_t>> parts(scripts);
  std::vector<int> load(scripts, 0);
  for (size_t i : order) {
    const size_t k = static_cast<size_t>(
        std::min_element(load.begin(), load.end()) - load.begin());
    parts[k].push_back(i);
    load[k] += weight(figures[i]);
  }
  const std::string preamble =
      "set datafile separator ','\nset datafile missing ''\nset grid\nset "
      "key outside right top\nset style data lines\n";
  const bool stand_ins =
      formats.svg && std::any_of(figures.begin(), figures.end(), [](auto& f) {
        return !f.rasters.empty();
      });
  if (stand_ins) {
    WriteTextAtomically(FigureDataPath(dir, "stand_in.f32"),
                        std::string(4 * sizeof(float), '\0'));
  }
  SlimTables slim(dir);
  std::vector<pid_t> pids;
  bool session_failed = false;
  for (size_t k = 0; k < scripts; ++k) {
    std::string script = preamble;
    for (size_t i : parts[k]) {
      const Figure& f = figures[i];
      for (const char* term : terms) {
        script += std::string(term) == "png"
                      ? "set terminal pngcairo size 960,560 noenhanced font "
                        "'DejaVu Sans,10'\n"
                      : "set terminal svg size 960,560 noenhanced font "
                        "'DejaVu Sans,10' background 'white'\n";
        script += fmt::format("set output {}\nset title {} noenhanced\n",
                              Quote(f.stem + "." + term + ".part"),
                              Quote(f.title));
        script += slim.Rewrite(f.stem, BodyFor(f, term)) +
                  "\nunset output\nreset session\n" + preamble;
      }
    }
    const std::string name = fmt::format("figures_{}.gp", k + 1);
    WriteTextAtomically(FigureDataPath(dir, name), script);
    if (session != nullptr) {
      session_failed |= !session->Run(dir, name);
    } else {
      pids.push_back(StartGnuplot(dir, name));
    }
  }
  bool failed = session_failed;
  for (pid_t pid : pids) failed |= !WaitGnuplot(pid);
  FigureSet set;
  for (const Figure& f : figures) {
    std::string shown;
    for (const char* term : terms) {
      const std::string final_path =
          (fs::path(dir) / (f.stem + "." + term)).string();
      const std::string part = final_path + ".part";
      if (LooksDrawn(part, term) &&
          (std::string(term) != "svg" || PaintRasters(part, f.rasters)) &&
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
  if (set.missing.empty()) return set;
  set.message = fmt::format(
      "{} of the {} figures asked for were not drawn ({}{}){}",
      set.missing.size(),
      terms.size() * figures.size(),
      set.missing[0],
      set.missing.size() > 1 ? ", ..." : "",
      failed
          ? fmt::format("; gnuplot failed: see {}/figures_*.log", kFigureData)
          : "");
  return set;
}

// A scale bar's length: 1, 2 or 5 x 10^n mm, at most a fifth of `width`.
double ScaleBarMm(double width_mm) {
  const double target = width_mm / 5;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= target) return m * decade;
  }
  return decade;
}

// The track's axis (index 0) and its two edges (index 1) for gnuplot.
void WriteTrackOutline(const std::string& dir, const scan::Track& t) {
  const double th = t.angle_deg * M_PI / 180, ax = std::cos(th),
               ay = std::sin(th);
  const double half = 0.5 * t.length_mm;
  std::string track = "x_mm,y_mm\n";
  track += fmt::format("{},{}\n{},{}\n\n\n",
                       t.centre_x_mm - half * ax,
                       t.centre_y_mm - half * ay,
                       t.centre_x_mm + half * ax,
                       t.centre_y_mm + half * ay);
  for (double side : {-1.0, 1.0}) {
    const double ox = -ay * side * (0.5 * t.width_mm),
                 oy = ax * side * (0.5 * t.width_mm);
    track += fmt::format("{},{}\n{},{}\n\n",
                         t.centre_x_mm - half * ax + ox,
                         t.centre_y_mm - half * ay + oy,
                         t.centre_x_mm + half * ax + ox,
                         t.centre_y_mm + half * ay + oy);
  }
  WriteTextAtomically(FigureDataPath(dir, "track_outline.csv"), track);
}

// The levelled map downsampled to at most 320 columns as float32 for
// gnuplot's binary array reader (NaN = not measured), with the track's
// axis and edges when there is one, axes in mm, a colour bar in um and a
// scale bar.
void WriteScanMap(const std::string& dir,
                  const scan::HeightMap& m,
                  const scan::Track* t,
                  Figure* fig) {
  const int f = std::max<int>(1, static_cast<int>(std::ceil(m.cols() / 320.0)));
  const int w = static_cast<int>(m.cols() / f),
            h = static_cast<int>(m.rows() / f);
  std::vector<float> values(static_cast<size_t>(w) * h);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      double sum = 0;
      int n = 0;
      for (int dr = 0; dr < f; ++dr) {
        for (int dc = 0; dc < f; ++dc) {
          if (m.valid(r * f + dr, c * f + dc)) {
            sum += m.height_mm(r * f + dr, c * f + dc);
            ++n;
          }
        }
      }
      values[static_cast<size_t>(r) * w + c] =
          n > 0 ? static_cast<float>(1e3 * sum / n) : NAN;  // um
    }
  }
  const double dx = f * m.dx_mm, dy = f * m.dy_mm;
  const double bar = ScaleBarMm(w * dx), x0 = 0.05 * w * dx, y0 = 0.06 * h * dy;
  // The axes span the map (gnuplot's autoscale would round them out to
  // tic marks, and differently for the SVG's stand-in, see Raster).
  fig->body = fmt::format(
      "set size ratio -1\nset xlabel 'x (mm)'\nset ylabel 'y (mm)'\nset "
      "cblabel 'height (um)'\n{0}set key bottom right inside opaque\n"
      "set xrange [{8}:{9}]\nset yrange [{10}:{11}]\n"
      "set arrow 1 from first {1}, first {2} to first {3}, first {2} nohead "
      "lw 4 lc rgb 'black' front\n"
      "set label 1 '{4:g} mm' at first {5}, first {6} center front\n"
      "{7} notitle",
      PaletteCommand(HeightPalette()),
      x0,
      y0,
      x0 + bar,
      bar,
      x0 + bar / 2,
      y0 + 0.05 * h * dy,
      ImagePlot(dir,
                "scan_map.f32",
                w,
                h,
                dx,
                dy,
                0,
                0,
                values,
                HeightPalette(),
                fig),
      -0.5 * dx,
      (w - 0.5) * dx,
      -0.5 * dy,
      (h - 0.5) * dy);
  if (!t) return;
  WriteTrackOutline(dir, *t);
  fig->body += fmt::format(
      ", '{0}/track_outline.csv' skip 1 index 0 using 1:2 with lines lw 2 "
      "lc rgb 'red' title 'track axis (centreline)', '' skip 1 index 1 using "
      "1:2 with lines lw 1 dt 2 lc rgb 'black' title 'track width'",
      kFigureData);
}

}  // namespace

std::string SlimPlotTables(const std::string& dir,
                           const std::string& figure,
                           const std::string& body) {
  return SlimTables(dir).Rewrite(figure, body);
}

std::string FigureDataPath(const std::string& dir, const std::string& file) {
  const fs::path sub = fs::path(dir) / kFigureData;
  EnsureDirectory(sub.string());
  return (sub / file).string();
}

bool FigureFormats::Parse(const std::string& text, FigureFormats* formats) {
  FigureFormats f{false, false};
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string word = text.substr(start, comma - start);
    if (word == "svg") {
      f.svg = true;
    } else if (word == "png") {
      f.png = true;
    } else {
      return false;
    }
    start = comma + 1;
  }
  *formats = f;
  return true;
}

std::string FigureFormats::Text() const {
  return svg && png ? "svg,png" : png ? "png" : svg ? "svg" : "";
}

bool FigureFormats::IsValid(std::string* why) const {
  if (svg || png) return true;
  if (why) *why = "figures need a format: svg, png or both";
  return false;
}

bool RunGnuplotScript(const std::string& dir, const std::string& script) {
  return WaitGnuplot(StartGnuplot(dir, script));
}

GnuplotSession::~GnuplotSession() { Stop(); }

bool GnuplotSession::Start() {
  // Its input a socket (a write to a gnuplot that ended fails instead of
  // raising SIGPIPE), its output and errors one pipe; the ends kept here
  // close on exec, so that no other program started meanwhile holds them.
  int in[2], out[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, in) != 0) return false;
  if (pipe2(out, O_CLOEXEC) != 0) {
    close(in[0]);
    close(in[1]);
    return false;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[1], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDERR_FILENO);
  std::string program = "gnuplot";
  char* argv[] = {program.data(), nullptr};
  pid_t pid = -1;
  const int error =
      posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  close(in[1]);
  close(out[1]);
  if (error != 0) {
    close(in[0]);
    close(out[0]);
    return false;
  }
  pid_ = pid;
  input_ = in[0];
  output_ = fdopen(out[0], "r");
  if (output_ == nullptr) {
    close(out[0]);
    Stop();
    return false;
  }
  return true;
}

void GnuplotSession::Stop() {
  if (input_ >= 0) close(input_);  // gnuplot ends at the end of its input
  if (output_ != nullptr) std::fclose(output_);
  if (pid_ >= 0) {
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  input_ = -1;
  output_ = nullptr;
  pid_ = -1;
}

bool GnuplotSession::Run(const std::string& dir, const std::string& script) {
  const std::string abs = fs::absolute(dir).string();
  // A folder name with a line break cannot be a gnuplot command's string.
  if (abs.find_first_of("\r\n") != std::string::npos)
    return RunGnuplotScript(dir, script);
  if (pid_ < 0 && !Start()) return false;
  // After the script, a line on gnuplot's error output (`set print` with
  // no file, whatever the script set) that says it is done and whether it
  // failed (GPVAL_ERRNO; gnuplot reading its input goes on after an error).
  const std::string marker = fmt::format("wearscar-done-{}", ++serial_);
  const std::string commands = fmt::format(
      "cd {}\nload {}\nset print\nprint sprintf('{} %d', "
      "GPVAL_ERRNO)\nreset errors\n",
      Quote(abs),
      Quote(std::string(kFigureData) + "/" + script),
      marker);
  for (size_t sent = 0; sent < commands.size();) {
    const ssize_t n = send(
        input_, commands.data() + sent, commands.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) {
      Stop();
      return false;
    }
    sent += static_cast<size_t>(n);
  }
  std::string log;
  bool done = false, ok = false;
  char* line = nullptr;
  size_t capacity = 0;
  ssize_t length;
  while ((length = getline(&line, &capacity, output_)) > 0) {
    const std::string_view text(line, static_cast<size_t>(length));
    if (text.substr(0, marker.size() + 1) == marker + " ") {
      done = true;
      ok = text.substr(marker.size() + 1, 2) == "0\n";
      break;
    }
    log.append(text);
  }
  std::free(line);
  const std::string stem = fs::path(script).stem().string();
  WriteTextAtomically(FigureDataPath(abs, stem + ".log"), log);
  if (!done) Stop();  // gnuplot ended: a new one for the next script
  return done && ok;
}

namespace {

// gnuplot on the PATH, where posix_spawnp looks for it (a shell running
// `gnuplot --version` took 40 ms, a fifth of the figures' time).
bool GnuplotOnPath() {
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/bin:/bin";
  for (size_t start = 0; start <= path.size();) {
    const size_t colon = std::min(path.find(':', start), path.size());
    const std::string dir = path.substr(start, colon - start);
    if (::access(((dir.empty() ? "." : dir) + "/gnuplot").c_str(), X_OK) == 0)
      return true;
    start = colon + 1;
  }
  return false;
}

}  // namespace

bool PlotterAvailable(std::string* why) {
  static const bool found = GnuplotOnPath();
  if (!found && why) {
    *why =
        "gnuplot was not found: figures are skipped, the numeric outputs are "
        "complete "
        "(install the Debian package gnuplot-nox)";
  }
  return found;
}

namespace {

// One plot clause per exported cycle over its rows of loops.csv (rows are
// grouped by cycle): selecting rows by range is twice as fast in gnuplot as
// testing the cycle column on every row.
std::string LoopsPlot(const std::string& dir) {
  std::string plot;
  std::ifstream in(fs::path(dir) / "loops.csv");
  std::string line;
  std::getline(in, line);
  std::string last;
  long row = 0, first = 0;
  auto clause = [&](long end) {
    if (last.empty()) return;
    plot += fmt::format(
        "{}'loops.csv' skip 1 every ::{}::{} using 3:4 "
        "title 'cycle {}'",
        plot.empty() ? "plot " : ", ",
        first,
        end,
        last);
  };
  while (std::getline(in, line)) {
    const std::string c = line.substr(0, line.find(','));
    if (c != last) {
      clause(row - 1);
      last = c;
      first = row;
    }
    ++row;
  }
  clause(row - 1);
  return plot;
}

// The column of cycles.csv a figure plots (a name that is not a column is
// a bug of this program).
int Col(const char* name) {
  const int c = fusion::CycleColumn(name);
  WEARSCAR_CHECK(c > 0, "a figure plots a column of cycles.csv");
  return c;
}

// The running-in cycles shaded and labelled on a plot over cycles
// (Figs. 5, 6, 13-15); nothing when there is none.
std::string RunningInMark(const fusion::TestResult& r) {
  const int n = r.force.running_in.cycles;
  if (n <= 0) return "";
  return fmt::format(
      "set object 1 rect from first 0.5, graph 0 to first {0}.5, graph 1 "
      "behind fc rgb '#e6e6e6' fs solid 1.0 noborder\n"
      "set label 1 'running-in ({0} cycles)' at first 1, graph 0.96 front\n",
      n);
}

// Figs. 5-7: loops and envelopes.
void AddForceFigures(const std::string& dir,
                     const std::string& name,
                     const fusion::TestResult& r,
                     std::vector<Figure>* figs) {
  const std::string mark = RunningInMark(r);
  const std::string loops_plot = LoopsPlot(dir);
  figs->push_back({"fig07_loops",
                   name + ": hysteresis loops (Fig. 7)",
                   "set xlabel 'x (mm)'\nset ylabel 'Q (N)'\n" + loops_plot});
  // Figs. 5 and 6: the envelope (max and min per cycle) of Q and of P.
  for (const char force : {'Q', 'P'}) {
    figs->push_back(
        {force == 'Q' ? "fig05_q_envelope" : "fig06_p_envelope",
         name + fmt::format(
                    ": envelope of {} (Fig. {})", force, force == 'Q' ? 5 : 6),
         mark + fmt::format("set xlabel 'cycle'\nset ylabel '{0} (N)'\nplot "
                            "'cycles.csv' skip 1 using 1:{1} title '{0} max', "
                            "'' skip 1 using 1:{2} title '{0} min'",
                            force,
                            Col(force == 'Q' ? "Q_max_N" : "P_max_N"),
                            Col(force == 'Q' ? "Q_min_N" : "P_min_N"))});
  }
}

// Figs. 8a-d: the scan map with the track, the aligned profiles.
void AddScanFigures(const std::string& dir,
                    const std::string& name,
                    const fusion::TestResult& r,
                    std::vector<Figure>* figs) {
  if (r.scan) {
    Figure map{"fig08ab_scan_map",
               name + ": levelled scan, detected track (Fig. 8a-b)",
               ""};
    WriteScanMap(dir, r.scan->levelled, &r.scan->track, &map);
    figs->push_back(map);
    figs->push_back(
        {"fig08cd_profiles",
         name +
             ": spring displacement P/S and aligned scan profile (Fig. 8c-d)",
         fmt::format("set xlabel 'x (mm)'\nset ylabel 'height (mm)'\nplot "
                     "'profiles.csv' skip 1 "
                     "using 1:($2-{0}) title 'P/S forward - {0:.4f} mm', '' "
                     "skip 1 using 1:($3-{0}) title 'P/S reverse - {0:.4f} "
                     "mm', '' skip 1 using 1:($5*{1}) lw 2 title 'scan "
                     "centreline x {1:.2f}'",
                     r.scan->alignment.offset_mm,
                     r.scan->alignment.scale)});
  }
}

// The minimum of J(mu) of each slope on Fig. 11: mu-hat and its J.
std::string CostMinima(const fusion::TestResult& r) {
  std::string plot;
  auto point = [&](const fusion::MuFit& f, const char* slope, int pt) {
    if (!f.converged) return;
    plot += fmt::format(
        ", '+' using ({0}):({1}) every ::0::0 with points pt {2} ps 1.6 lc "
        "rgb 'black' title 'minimum, k from {3}: mu-hat {0:.4f}, J {1:.4f}'",
        f.mu_hat,
        f.cost,
        pt,
        slope);
  };
  const int dc = r.detail_cycle;
  if (dc >= 0 && dc < static_cast<int>(r.force.fit_force.size()))
    point(r.force.fit_force[dc], "P", 7);
  if (r.scan && dc >= 0 && dc < static_cast<int>(r.scan->fit_scan.size()))
    point(r.scan->fit_scan[dc], "scan", 5);
  return plot;
}

// Figs. 10-12 and 17 on the detail cycle.
void AddDetailFigures(const std::string& name,
                      const fusion::TestResult& r,
                      std::vector<Figure>* figs) {
  figs->push_back(
      {"fig10_slope",
       name + fmt::format(": slope k of the sliding path, cycle {} (Fig. 10)",
                          r.detail_cycle + 1),
       "set xlabel 'x (mm)'\nset ylabel 'k'\nplot 'detail.csv' skip 1 using "
       "3:6 title "
       "'k from P' lc rgb '#888888', '' skip 1 using 3:7 lw 2 title 'k from "
       "scan'"});
  figs->push_back(
      {"fig11_cost",
       name + fmt::format(": J(mu), cycle {} (Fig. 11)", r.detail_cycle + 1),
       "set xlabel 'mu'\nset ylabel 'J'\nset logscale y\nplot 'cost_curve.csv' "
       "skip 1 "
       "using 1:2 title 'k from P', '' skip 1 using 1:3 title 'k from scan'" +
           CostMinima(r)});
  figs->push_back(
      {"fig12_reconstruction",
       name + fmt::format(": measured and reconstructed Q, cycle {} (Fig. 12)",
                          r.detail_cycle + 1),
       "set xlabel 'x (mm)'\nset ylabel 'Q (N)'\nplot 'detail.csv' skip 1 "
       "using 3:8 "
       "lc rgb '#1f77b4' title 'wear-scar, k from P', '' skip 1 using 3:9 lw 2 "
       "lc rgb "
       "'#ff7f0e' title 'wear-scar, k from scan', '' skip 1 using 3:4 with "
       "points pt 7 "
       "ps 0.25 lc rgb 'black' title 'measured'"});
  if (r.lugre) {
    figs->push_back(
        {"fig17_lugre",
         name + fmt::format(": LuGre and wear-scar, cycle {} (Fig. 17)",
                            r.detail_cycle + 1),
         "set xlabel 'x (mm)'\nset ylabel 'Q (N)'\nplot 'lugre.csv' skip 1 "
         "using 2:3 "
         "lc rgb 'black' title 'measured', '' skip 1 using 2:4 dt 2 lw 2 title "
         "'LuGre', '' skip 1 using 2:5 dt 4 lw 2 title 'wear-scar'"});
  }
}

// One direction of a (cycle, direction, bin) table as float32 rows of
// bins, one row per cycle, for gnuplot's binary array reader (NaN = empty
// bin); returns the commands drawing it as an image (ImagePlot), bins
// centred on x and cycles from 1. An image is one bitmap: drawing ten
// thousand boxes instead took gnuplot about half a second per figure and
// format.
template <typename Value>
std::string WriteCycleGrid(const std::string& dir,
                           const std::string& file,
                           const std::vector<double>& x_mm,
                           int cycles,
                           Value value,
                           Figure* fig) {
  const size_t bins = x_mm.size();
  std::vector<float> values(bins * static_cast<size_t>(cycles));
  for (int c = 0; c < cycles; ++c) {
    for (size_t b = 0; b < bins; ++b)
      values[static_cast<size_t>(c) * bins + b] =
          static_cast<float>(value(c, b));
  }
  return ImagePlot(dir,
                   file,
                   static_cast<int>(bins),
                   cycles,
                   x_mm[1] - x_mm[0],
                   1,
                   x_mm[0],
                   1,
                   values,
                   GridPalette(),
                   fig);
}

// The friction map: mu along the stroke (x) and over the cycles, raw
// (s Q / P) above corrected for the slope of the sliding path, forward
// sliding; below them the track's height along the same x (the spring's
// P/S, and the aligned scan when there is one).
void AddFrictionMapFigure(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& r,
                          std::vector<Figure>* figs) {
  const auto& m = r.friction_map;
  if (m.x_mm.size() < 2 || m.cycles < 1) return;
  const auto forward = [&m](const std::vector<double>& mu) {
    return [&m, &mu](int c, size_t b) { return mu[m.Index(c, 0, b)]; };
  };
  const double half = 0.5 * (m.x_mm[1] - m.x_mm[0]);
  Figure fig{"fig_friction_map",
             name + ": friction map mu(x, cycle), raw and corrected",
             ""};
  const std::string raw = WriteCycleGrid(
      dir, "friction_map_raw.f32", m.x_mm, m.cycles, forward(m.mu_raw), &fig);
  const std::string corrected = WriteCycleGrid(dir,
                                               "friction_map_corrected.f32",
                                               m.x_mm,
                                               m.cycles,
                                               forward(m.mu_corrected),
                                               &fig);
  fig.body = fmt::format(
      "set multiplot layout {0},1 title 'spatial variation of mu after "
      "running-in: corrected {1:.4f} (noise floor {2:.4f}), raw {3:.4f}'\n"
      "unset key\nset ylabel 'cycle'\nset cblabel 'mu'\n{9}"
      "set xrange [{4}:{5}]\nset yrange [0.5:{6}]\n"
      "set lmargin 10\nset rmargin 16\n"
      "set title 'raw: s Q / P (forward)'\n{7}\n"
      "set title 'corrected for the slope: s (Q - P k) / (P + k Q) "
      "(forward)'\n{8}\nset autoscale y\n",
      r.scan ? 3 : 2,
      m.spatial_sd_corrected,
      m.spatial_sd_noise,
      m.spatial_sd_raw,
      m.x_mm.front() - half,
      m.x_mm.back() + half,
      m.cycles + 0.5,
      raw,
      corrected,
      PaletteCommand(GridPalette()));
  if (r.scan) {
    fig.body +=
        "set title 'the track along x'\nset key inside top right\nset xlabel "
        "'x (mm)'\nset "
        "ylabel 'height (mm)'\nplot 'profiles.csv' skip 1 using 1:(-$4) with "
        "lines title '-P/S (mean of both directions)', '' skip 1 using 1:(-$6) "
        "with lines lw 2 title 'scan (aligned, scaled)'\n";
  }
  fig.body += "unset multiplot";
  figs->push_back(std::move(fig));
}

// The track's history from the spring: h(x, cycle) = P/S about its mean
// (forward sliding) above, its waviness per cycle below.
void AddTrackHistoryFigure(const std::string& dir,
                           const std::string& name,
                           const fusion::TestResult& r,
                           std::vector<Figure>* figs) {
  const auto& h = r.track_history;
  if (h.x_mm.size() < 2 || h.cycles < 2) return;
  const double half = 0.5 * (h.x_mm[1] - h.x_mm[0]);
  Figure fig{"fig_track_history",
             name + ": the track's history from the spring, h(x, cycle) = P/S",
             ""};
  const std::string grid = WriteCycleGrid(
      dir,
      "track_history.f32",
      h.x_mm,
      h.cycles,
      [&h](int c, size_t b) { return h.height_mm[h.Index(c, 0, b)]; },
      &fig);
  fig.body = fmt::format(
      "set multiplot layout 2,1 title 'waviness {0:.4f} mm in cycle 1, "
      "{1:.4f} mm at the end; steady from cycle {2}'\nset lmargin 10\n"
      "set rmargin 16\n{8}set xlabel 'x (mm)'\nset ylabel 'cycle'\nset "
      "cblabel 'h (mm)'\nunset key\nset title 'h(x, cycle): P/S about its "
      "mean, forward sliding'\nset xrange [{5}:{6}]\nset yrange "
      "[0.5:{7}]\n{3}\nset autoscale\nset xlabel 'cycle'\nset ylabel "
      "'waviness (mm)'\nunset colorbox\nset title 'waviness: the sd of "
      "h along the stroke'\n"
      "plot 'cycles.csv' skip 1 using 1:{4} with lines lw 2 notitle\n"
      "unset multiplot",
      h.waviness_sd_mm.front(),
      h.final_waviness_sd_mm,
      h.steady_cycle + 1,
      grid,
      Col("waviness_sd_mm"),
      h.x_mm.front() - half,
      h.x_mm.back() + half,
      h.cycles + 0.5,
      PaletteCommand(GridPalette()));
  figs->push_back(std::move(fig));
}

// Figs. 13-15 per cycle.
void AddCycleFigures(const std::string& name,
                     const fusion::TestResult& r,
                     const fusion::FuseOptions& opt,
                     std::vector<Figure>* figs) {
  const std::string mark = RunningInMark(r);
  figs->push_back(
      {"fig13_mu_hat",
       name + ": mu-hat per cycle (Fig. 13)",
       mark + fmt::format(
                  "set xlabel 'cycle'\nset ylabel 'mu'\nset style fill "
                  "transparent solid 0.25 noborder\nplot 'cycles.csv' skip 1 "
                  "using 1:{3}:{4} with filledcurves lc rgb '#1f77b4' title "
                  "'95% interval, k from P', '' skip 1 using 1:{5}:{6} with "
                  "filledcurves lc rgb '#ff7f0e' title '95% interval, k from "
                  "scan', '' skip 1 using 1:{0} with points pt 7 ps 0.6 lc rgb "
                  "'#1f77b4' "
                  "title 'mu-hat, k from P', '' skip 1 using 1:{1} with points "
                  "pt 7 ps "
                  "0.6 lc rgb '#ff7f0e' title 'mu-hat, k from scan', '' skip "
                  "1 using 1:{2} with lines lc rgb '#2ca02c' title 'mean "
                  "method'",
                  Col("mu_hat_force"),
                  Col("mu_hat_scan"),
                  Col("mu_mean"),
                  Col("mu_hat_force_low"),
                  Col("mu_hat_force_high"),
                  Col("mu_hat_scan_low"),
                  Col("mu_hat_scan_high"))});
  // J as the paper defines it beside the part this test's noise explains
  // (its floor): the verdict judges what stands above the floor.
  const bool paper =
      opt.verdict.cost_criterion == fusion::CostCriterion::kPaperJ;
  figs->push_back(
      {"fig14_cost",
       name + ": J per cycle and its noise floor (Fig. 14)",
       mark +
           fmt::format(
               "set xlabel 'cycle'\nset ylabel 'J'\nset yrange [0:*]\nplot "
               "'cycles.csv' skip 1 using 1:{} lc rgb '#1f77b4' title 'J, k "
               "from "
               "P', '' skip 1 using 1:{} with lines lw 2 lc rgb 'black' dt 2 "
               "title 'its noise floor', '' skip 1 using 1:{} lc rgb '#ff7f0e' "
               "title 'J, k from scan', '' skip 1 using 1:{} with lines lw 2 "
               "lc "
               "rgb '#d62728' dt 3 title 'its noise floor'{}",
               Col("J_force"),
               Col("J_force_floor"),
               Col("J_scan"),
               Col("J_scan_floor"),
               paper ? fmt::format(", {} dt 3 lc rgb 'red' title 'threshold "
                                   "(paper)'",
                                   opt.verdict.max_cost)
                     : std::string())});
  figs->push_back(
      {"fig15_energy_cof",
       name + ": energy-based COF (Fig. 15)",
       mark + fmt::format("set xlabel 'cycle'\nset ylabel 'mu'\nplot "
                          "'cycles.csv' skip 1 using 1:{} title 'E_d / (4 "
                          "P delta_g)', '' skip 1 using 1:{} title 'E_d / "
                          "(4 P delta_max)'",
                          Col("mu_energy_g"),
                          Col("mu_energy_max"))});
}

}  // namespace

namespace {

// gnuplot's time for each figure of a test in SVG, ms (the least of five
// runs on the full-size test, beside a start of 31 ms; an image is drawn
// as a stand-in, see Raster).
int DrawingMs(const std::string& stem) {
  static const std::map<std::string, int> kMs{{"fig05_q_envelope", 5},
                                              {"fig06_p_envelope", 3},
                                              {"fig07_loops", 10},
                                              {"fig08ab_scan_map", 2},
                                              {"fig08cd_profiles", 11},
                                              {"fig10_slope", 5},
                                              {"fig11_cost", 4},
                                              {"fig12_reconstruction", 7},
                                              {"fig13_mu_hat", 9},
                                              {"fig14_cost", 6},
                                              {"fig15_energy_cof", 3},
                                              {"fig17_lugre", 8},
                                              {"fig_friction_map", 8},
                                              {"fig_track_history", 4}};
  const auto it = kMs.find(stem);
  return it == kMs.end() ? 5 : it->second;
}

std::vector<Figure> TestFigures(const std::string& dir,
                                const std::string& name,
                                const fusion::TestResult& r,
                                const fusion::FuseOptions& opt) {
  std::vector<Figure> figs;
  AddForceFigures(dir, name, r, &figs);
  AddScanFigures(dir, name, r, &figs);
  AddDetailFigures(name, r, &figs);
  AddCycleFigures(name, r, opt, &figs);
  AddFrictionMapFigure(dir, name, r, &figs);
  AddTrackHistoryFigure(dir, name, r, &figs);
  for (Figure& f : figs) f.weight = DrawingMs(f.stem);
  return figs;
}

}  // namespace

FigureSet DrawTestFigures(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& r,
                          const fusion::FuseOptions& opt,
                          const FigureFormats& formats,
                          int processes) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  return Draw(dir, TestFigures(dir, name, r, opt), formats, processes);
}

FigureSet DrawTestFigures(GnuplotSession* session,
                          const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& r,
                          const fusion::FuseOptions& opt,
                          const FigureFormats& formats) {
  WEARSCAR_CHECK(session != nullptr, "DrawTestFigures needs a session");
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  return Draw(dir, TestFigures(dir, name, r, opt), formats, 1, session);
}

namespace {

// A statistic's 95% interval, the mean itself where none was estimated.
double Low(const fusion::Statistic& s) {
  return std::isfinite(s.low) ? s.low : s.mean;
}
double High(const fusion::Statistic& s) {
  return std::isfinite(s.high) ? s.high : s.mean;
}

// The batch: each specimen's specific wear rate against its mu-hat (with
// its 95% interval), labelled (wear_and_mu.csv).
void AddWearFigure(const std::string& dir,
                   const std::vector<SpecimenSeries>& specimens,
                   std::vector<Figure>* figs) {
  std::string data =
      "specimen,mu_hat,mu_hat_sd,wear_rate_mm3_per_N_m,mu_hat_low,"
      "mu_hat_high\n";
  int points = 0;
  for (const SpecimenSeries& s : specimens) {
    if (!std::isfinite(s.wear_rate) || !std::isfinite(s.mu_hat.mean)) continue;
    data += fmt::format("{},{},{},{},{},{}\n",
                        s.name,
                        s.mu_hat.mean,
                        s.mu_hat.sd,
                        s.wear_rate,
                        Low(s.mu_hat),
                        High(s.mu_hat));
    ++points;
  }
  if (points == 0) return;
  WriteTextAtomically((fs::path(dir) / "wear_and_mu.csv").string(), data);
  figs->push_back(
      {"audit_wear_vs_mu",
       "specific wear rate against mu-hat, all specimens",
       "set xlabel 'mu-hat (k from P)'\nset ylabel 'specific wear rate "
       "(mm^3/(N m))'\nunset key\nplot 'wear_and_mu.csv' skip 1 using "
       "2:4:5:6 with xerrorbars pt 7 lc rgb '#1f77b4', '' skip 1 using 2:4:1 "
       "with labels offset 1,0.6 left font ',8'"});
}

}  // namespace

FigureSet DrawMapFigure(const std::string& dir,
                        const std::string& name,
                        const fusion::MapAnalysis& map,
                        const FigureFormats& formats) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  std::vector<Figure> figs(1);
  figs[0] = {"scan_map",
             name + (map.track ? ": levelled map and the worn track"
                               : ": levelled map (no track found)"),
             ""};
  WriteScanMap(dir, map.levelled, map.track ? &*map.track : nullptr, &figs[0]);
  return Draw(dir, figs, formats);
}

FigureSet DrawAuditFigures(const std::string& dir,
                           const std::vector<SpecimenSeries>& specimens,
                           const FigureFormats& formats) {
  std::string why;
  if (!PlotterAvailable(&why)) return FigureSet{{}, {}, {}, why, {}};
  std::vector<Figure> figs;
  auto across = [&](const char* stem,
                    const char* title,
                    int column,
                    const char* ylabel) {
    // Beyond 20 specimens the key's font shrinks and it wraps into
    // columns, so that it stays beside the plot.
    std::string body = fmt::format(
        "set xlabel 'cycle'\nset ylabel '{}'\n{}plot ",
        ylabel,
        specimens.size() > 20 ? "set key font ',7' maxrows 40\n" : "");
    for (size_t i = 0; i < specimens.size(); ++i) {
      const std::string rel =
          fs::relative(fs::path(specimens[i].dir) / "cycles.csv", dir).string();
      // Eight colours, then the next dash pattern: 40 specimens stay
      // apart (the key wraps in columns).
      body +=
          fmt::format("{}{} skip 1 using 1:{} lc {} dt {} title {} noenhanced",
                      i ? ", " : "",
                      Quote(rel),
                      column,
                      i % 8 + 1,
                      (i / 8) % 5 + 1,
                      Quote(specimens[i].name));
    }
    figs.push_back({stem, title, body});
  };
  if (specimens.empty()) return {};
  across("audit_fig13_mu_hat",
         "mu-hat per cycle, all specimens (Fig. 13)",
         Col("mu_hat_force"),
         "mu-hat");
  across("audit_fig14_cost",
         "J per cycle, all specimens (Fig. 14)",
         Col("J_force"),
         "J");
  across("audit_fig15_energy",
         "energy-based COF, all specimens (Fig. 15)",
         Col("mu_energy_g"),
         "mu_Ed");
  // Fig. 16: the mean per-cycle differences with their 95% intervals.
  std::string data =
      "index,name,dm,dm_sd,de,de_sd,dm_low,dm_high,de_low,de_high\n";
  for (size_t i = 0; i < specimens.size(); ++i) {
    const auto& s = specimens[i];
    data += fmt::format("{},{},{},{},{},{},{},{},{},{}\n",
                        i,
                        s.name,
                        s.diff_mean.mean,
                        s.diff_mean.sd,
                        s.diff_energy.mean,
                        s.diff_energy.sd,
                        Low(s.diff_mean),
                        High(s.diff_mean),
                        Low(s.diff_energy),
                        High(s.diff_energy));
  }
  WriteTextAtomically((fs::path(dir) / "method_differences.csv").string(),
                      data);
  figs.push_back(
      {"audit_fig16_differences",
       "mu-hat minus mean and energy COF, means over the cycles with their "
       "95% intervals (Fig. 16)",
       "set ylabel 'difference'\nset xtics rotate by -45 noenhanced\nset "
       "xrange [-0.5:*]\nset offsets 0,0.5,0,0\nplot "
       "'method_differences.csv' skip 1 using ($1-0.1):3:7:8:xtic(2) with "
       "yerrorbars pt 7 title 'mu-hat - mu mean', '' skip 1 using "
       "($1+0.1):5:9:10 with yerrorbars pt 5 title 'mu-hat - mu energy', 0 "
       "lc rgb 'black' notitle"});
  AddWearFigure(dir, specimens, &figs);
  return Draw(dir, figs, formats);
}

}  // namespace wearscar::report
