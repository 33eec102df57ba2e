// ASCII matrices: a grid of heights, one row per line, with or without a
// header saying its size and units (Gwyddion's ASCII export, SPIP and
// other instruments' "pixel size = ..." headers). A two-column or two-row
// file is a line profile (a stylus trace), not a map, and is refused as
// such.
#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "byte_reader.h"
#include "text_cells.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/read_scan.h"
#include "wearscar/support/text.h"

namespace wearscar::scan {
namespace {

using internal::Lines;
using internal::Number;
using internal::Trim;
using internal::UnitToMm;

constexpr std::string_view kSeparators = " \t,;";

// What a header states; a length with its unit as written ("" when none).
struct Length {
  double value = NAN;
  std::string unit;
};
struct MatrixHeader {
  Length width, height, pixel;  // sizes and pixel size
  std::string x_unit, z_unit;   // lateral and height units stated alone
  double z_factor = NAN;        // heights times this, in z_factor_unit
  std::string z_factor_unit, channel;
  long rows = -1, cols = -1;        // stated pixel counts
  std::vector<std::string> stated;  // "Width: 10 µm", for messages
};

// "10.00 µm" -> {10, "µm"}; nullopt when no number leads.
std::optional<Length> ReadLength(std::string_view value) {
  value = Trim(value);
  std::size_t end = 0;
  while (end < value.size() && value[end] != ' ' && value[end] != '\t') ++end;
  const auto v = Number(value.substr(0, end), '.');
  if (!v) return std::nullopt;
  return Length{*v, std::string(Trim(value.substr(end)))};
}

std::optional<long> ReadCount(std::string_view value) {
  const auto v = Number(Trim(value), '.');
  if (!v || !(*v >= 1) || *v > (1 << 20) || std::floor(*v) != *v)
    return std::nullopt;
  return static_cast<long>(*v);
}

// A line of several "key=value" words ("h=650 w=650", a Wyko/Vision ASCII
// export's first line), split into them; the line itself otherwise.
std::vector<std::string_view> KeyValueWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
    std::size_t end = pos;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
    const std::string_view word = line.substr(pos, end - pos);
    if (!word.empty()) {
      const auto eq = word.find('=');
      if (eq == 0 || eq == std::string_view::npos ||
          word.find_first_of(":=", eq + 1) != std::string_view::npos)
        return {line};
      words.push_back(word);
    }
    pos = end;
  }
  return words.size() > 1 ? words : std::vector<std::string_view>{line};
}

// One header line ("# Width: 10.00 µm", "pixel size=3.7e-007 m", "h=650
// w=650"); keys it does not know are kept for nothing. Returns false for a
// known key whose value is not what it should be (the line is then
// refused).
bool ReadHeaderLine(std::string_view line, MatrixHeader* h) {
  while (!line.empty() &&
         (line.front() == '#' || line.front() == ' ' || line.front() == '\t'))
    line.remove_prefix(1);
  const std::vector<std::string_view> words = KeyValueWords(line);
  if (words.size() > 1) {
    bool ok = true;
    for (std::string_view w : words) ok = ReadHeaderLine(w, h) && ok;
    return ok;
  }
  const std::size_t at = line.find_first_of(":=");
  if (at == std::string_view::npos) return true;
  const std::string key = support::Lower(Trim(line.substr(0, at)));
  const std::string_view value = line.substr(at + 1);
  const auto length = [&](Length* into) {
    const auto l = ReadLength(value);
    if (l) *into = *l;
    return l.has_value();
  };
  const auto count = [&](long* into) {
    const auto n = ReadCount(value);
    if (n) *into = *n;
    return n.has_value();
  };
  bool ok = true, known = true;
  if (key == "width" || key == "x-length" || key == "breite") {
    ok = length(&h->width);
  } else if (key == "height" || key == "y-length" || key == "h\xc3\xb6he") {
    ok = length(&h->height);
  } else if (key == "pixel size") {
    ok = length(&h->pixel);
  } else if (key == "w" || key == "x-pixels" || key == "xres") {
    ok = count(&h->cols);
  } else if (key == "h" || key == "y-pixels" || key == "yres") {
    ok = count(&h->rows);
  } else if (key == "x-unit" || key == "xy-unit" || key == "lateral unit") {
    h->x_unit = std::string(Trim(value));
  } else if (key == "value units" || key == "z-unit" || key == "zunit" ||
             key == "height unit") {
    h->z_unit = std::string(Trim(value));
  } else if (key.rfind("height conversion factor", 0) == 0) {
    // "height conversion factor (-> m)=1e-009": heights times it, in m.
    const std::size_t arrow = key.find("->");
    const std::size_t close = key.find(')', arrow);
    if (arrow != std::string::npos && close != std::string::npos)
      h->z_factor_unit =
          std::string(Trim(key.substr(arrow + 2, close - arrow - 2)));
    const auto v = Number(Trim(value), '.');
    ok = v.has_value() && *v != 0 && std::isfinite(*v);
    if (ok) h->z_factor = *v;
  } else if (key == "channel" || key == "kanal") {
    h->channel = std::string(Trim(value));
  } else {
    known = false;
  }
  if (known) h->stated.push_back(std::string(Trim(line)));
  return ok;
}

// A row of numbers; nullopt when its first token is not one (a header
// line). A later token that is not a number is an error naming it.
std::optional<long> ReadRow(std::string_view line,
                            double scale,
                            std::vector<float>* values,
                            std::string* bad_token) {
  long count = 0;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && kSeparators.find(line[pos]) != kSeparators.npos)
      ++pos;
    if (pos >= line.size()) break;
    std::size_t end = pos;
    while (end < line.size() && kSeparators.find(line[end]) == kSeparators.npos)
      ++end;
    const std::string_view tok = line.substr(pos, end - pos);
    const auto v = Number(tok, '.');
    if (!v) {
      if (count == 0) return std::nullopt;
      *bad_token = std::string(tok);
      return -(count + 1);
    }
    values->push_back(static_cast<float>(*v * scale));
    ++count;
    pos = end;
  }
  return count;
}

struct Grid {
  std::vector<float> values;  // as written
  long rows = 0, cols = -1;
  std::string cut;  // a warning: the last row was cut and dropped
  // The rows the export wrote, the cut one included (its size covers them).
  long WrittenRows() const { return rows + (cut.empty() ? 0 : 1); }
};

bool OnlyBlankAfter(const std::vector<std::string_view>& lines, std::size_t i) {
  for (std::size_t j = i + 1; j < lines.size(); ++j) {
    if (!Trim(lines[j]).empty()) return false;
  }
  return true;
}

Grid ReadGrid(const std::vector<std::string_view>& lines,
              const std::string& name,
              MatrixHeader* header) {
  Grid g;
  const auto header_line = [&](std::string_view line, std::size_t i) {
    if (!ReadHeaderLine(line, header)) {
      throw ScanError(fmt::format(
          "{}: line {}: found '{}'; expected a number after the key",
          name,
          i + 1,
          internal::Printable(line, 60)));
    }
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = Trim(lines[i]);
    if (line.empty()) continue;
    if (line.front() == '#') {
      header_line(line, i);
      continue;
    }
    std::string bad;
    const std::optional<long> count = ReadRow(line, 1.0, &g.values, &bad);
    if (!count) {
      if (g.rows > 0) {
        throw ScanError(fmt::format(
            "{}: line {}: found '{}' amid the heights; expected a row of "
            "numbers",
            name,
            i + 1,
            internal::Printable(line, 40)));
      }
      header_line(line, i);
      continue;
    }
    if (*count < 0) {
      throw ScanError(
          fmt::format("{}: line {}, value {}: found '{}', expected a number",
                      name,
                      i + 1,
                      -*count,
                      internal::Printable(bad, 30)));
    }
    if (g.cols < 0) g.cols = *count;
    if (*count < g.cols && g.rows >= 2 && OnlyBlankAfter(lines, i)) {
      // The last row cut short (an interrupted export): dropped.
      g.values.resize(g.values.size() - static_cast<std::size_t>(*count));
      g.cut = fmt::format(
          "the last row (line {}) is cut, {} of {} values, and was dropped: "
          "was the export interrupted?",
          i + 1,
          *count,
          g.cols);
      break;
    }
    if (*count != g.cols) {
      throw ScanError(
          fmt::format("{}: line {}: {} values; expected {} like the first row",
                      name,
                      i + 1,
                      *count,
                      g.cols));
    }
    ++g.rows;
    if (static_cast<std::int64_t>(g.cols) * g.rows > kMaxPixels) {
      throw ScanError(fmt::format("{}: more than {} pixels", name, kMaxPixels));
    }
  }
  if (g.rows == 0 || g.cols <= 0)
    throw ScanError(fmt::format("{}: no rows of numbers found", name));
  return g;
}

// mm per unit of a stated length: its own unit, else the lateral unit,
// else the height unit (Gwyddion states one unit for all).
std::optional<double> LateralMm(const Length& l, const MatrixHeader& h) {
  for (const std::string* u : {&l.unit, &h.x_unit, &h.z_unit}) {
    if (!u->empty()) return UnitToMm(*u);
  }
  return std::nullopt;
}

// The pixel size the header states (mm), or nullopt; throws when it states
// a size in a unit it does not say.
std::optional<double> StatedPitch(const MatrixHeader& h,
                                  const Grid& g,
                                  const std::string& name) {
  const auto mm = [&](const Length& l) {
    const auto f = LateralMm(l, h);
    if (!f) {
      throw ScanError(fmt::format(
          "{}: the header states a size of {} '{}' but no length unit it "
          "knows; expected m, mm, um or nm (or give --ascii-pitch)",
          name,
          l.value,
          l.unit));
    }
    return l.value * *f;
  };
  if (std::isfinite(h.pixel.value)) return mm(h.pixel);
  if (std::isfinite(h.width.value)) return mm(h.width) / g.cols;
  if (std::isfinite(h.height.value)) return mm(h.height) / g.WrittenRows();
  return std::nullopt;
}

// Heights in mm per value as written, and whether the file said so.
std::pair<double, bool> HeightScale(const MatrixHeader& h,
                                    const ReadScanOptions& options,
                                    const std::string& name) {
  double factor = 1.0;
  std::string unit = h.z_unit;
  if (std::isfinite(h.z_factor)) {
    factor = h.z_factor;
    if (!h.z_factor_unit.empty()) unit = h.z_factor_unit;
  }
  const bool stated = !unit.empty();
  if (!stated)
    unit = options.ascii_z_unit.empty() ? "mm" : options.ascii_z_unit;
  const auto to_mm = UnitToMm(unit);
  if (!to_mm) {
    throw ScanError(fmt::format(
        "{}: height unit '{}'; expected mm, um, nm or m", name, unit));
  }
  return {factor * *to_mm, stated || !options.ascii_z_unit.empty()};
}

}  // namespace

HeightMap ParseAsciiMatrix(const std::string& bytes,
                           const std::string& name,
                           const ReadScanOptions& options) {
  MatrixHeader header;
  Grid g = ReadGrid(Lines(bytes), name, &header);
  if (g.cols <= 2 || g.rows <= 2) {
    throw ScanError(fmt::format(
        "{}: {} rows of {} numbers: a line profile (a stylus trace or one "
        "line of a scan), not a height map; expected an area scan of the "
        "worn track (its centreline and width are found in it)",
        name,
        g.rows,
        g.cols));
  }
  // Stated pixel counts: rows and columns, or the other way round.
  if (header.rows > 0 || header.cols > 0) {
    const long rows = g.WrittenRows();
    const long r = header.rows > 0 ? header.rows : rows;
    const long c = header.cols > 0 ? header.cols : g.cols;
    if (!((r == rows && c == g.cols) || (r == g.cols && c == rows))) {
      throw ScanError(fmt::format(
          "{}: the header states {} x {} pixels; found {} rows of {} values",
          name,
          c,
          r,
          rows,
          g.cols));
    }
  }
  HeightMap map;
  if (!g.cut.empty()) map.metadata.warnings.push_back(g.cut);
  const std::optional<double> stated = StatedPitch(header, g, name);
  double pitch = stated.value_or(options.ascii_pitch_mm);
  if (options.ascii_pitch_mm > 0 && stated &&
      std::abs(options.ascii_pitch_mm - *stated) > 0.01 * *stated) {
    pitch = options.ascii_pitch_mm;
    map.metadata.warnings.push_back(fmt::format(
        "the header states a pixel of {:.4g} um, --ascii-pitch {:.4g} um: "
        "the option's was used",
        1e3 * *stated,
        1e3 * pitch));
  }
  if (!(pitch > 0)) {
    throw ScanError(fmt::format(
        "{}: an ASCII matrix whose header states no pixel size (no 'Width', "
        "'pixel size' or 'x-length'); give it with --ascii-pitch (mm)",
        name));
  }
  if (std::isfinite(header.width.value) && std::isfinite(header.height.value) &&
      !std::isfinite(header.pixel.value)) {
    // Gwyddion's Width and Height: pixels may be unequal.
    map.dx_mm = pitch;
    map.dy_mm = header.height.value * LateralMm(header.height, header).value() /
                g.WrittenRows();
  } else {
    map.dx_mm = map.dy_mm = pitch;
  }
  const auto [scale, unit_known] = HeightScale(header, options, name);
  if (!unit_known) {
    map.metadata.warnings.push_back(
        "the heights state no unit: taken as mm (give --ascii-unit)");
  }
  for (float& v : g.values) v = static_cast<float>(v * scale);
  map.height_mm =
      Eigen::Map<HeightMap::Heights>(g.values.data(), g.rows, g.cols);
  SyncValidity(&map);
  map.metadata.source = name;
  map.metadata.format = header.stated.empty() ? "ascii" : "ascii-headed";
  if (!header.channel.empty()) map.metadata.channel = header.channel;
  return map;
}

namespace internal {
ScanFormat AsciiMatrixFormat() {
  return {"ascii",
          "ASCII matrix",
          "any instrument (a grid of numbers; Gwyddion's ASCII export and "
          "headers stating the pixel size read, else --ascii-pitch)",
          {".txt", ".csv", ".asc", ".dat"},
          {},
          [](std::string_view, std::string_view) { return kDetectFallback; },
          &ParseAsciiMatrix};
}
}  // namespace internal

}  // namespace wearscar::scan
