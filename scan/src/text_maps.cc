// The Keyence VR CSV export of a height map.
#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

#include "byte_reader.h"
#include "file_io.h"
#include "text_cells.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/gsf.h"
#include "wearscar/scan/read_scan.h"
#include "wearscar/support/text.h"

namespace wearscar::scan {
namespace {

using internal::IsMicrometre;
using internal::Lines;
using internal::Number;
using internal::SplitCells;
using internal::Trim;
using internal::UnitToMm;
using support::Lower;

// Fields of view, mm: refused outside the first pair, warned of outside
// what a Keyence VR measures.
constexpr double kMinField = 0.01, kMaxField = 1000.0;
constexpr double kMaxSide = 1 << 16;  // pixels
constexpr double kVrMinField = 1.0, kVrMaxField = 100.0;

}  // namespace

namespace {

// What the rows before the Height block say.
struct VrHeader {
  char delim = ',', decimal = '.';
  long nx = -1, ny = -1;  // Horizontal, Vertical (-1 = not stated)
  double pitch_mm = std::nan("");
  size_t pitch_key_row = 0, fallback_pitch_row = 0;  // 1-based lines
  double z_to_mm = 1.0;  // heights in mm unless a unit row says otherwise
  size_t height_row = 0;
};

// Delimiter: ';' when the header rows use it (decimal-comma locales).
void ChooseDelimiter(const std::vector<std::string_view>& lines, VrHeader* h) {
  int semis = 0, commas = 0;
  for (size_t i = 0; i < std::min<size_t>(lines.size(), 30); ++i) {
    semis +=
        static_cast<int>(std::count(lines[i].begin(), lines[i].end(), ';'));
    commas +=
        static_cast<int>(std::count(lines[i].begin(), lines[i].end(), ','));
  }
  h->delim = semis > 0 && semis * 2 >= commas ? ';' : ',';
  h->decimal = h->delim == ';' ? ',' : '.';
}

VrHeader ReadVrHeader(const std::vector<std::string_view>& lines,
                      const std::string& name) {
  VrHeader h;
  ChooseDelimiter(lines, &h);
  const char delim = h.delim, decimal = h.decimal;
  long& nx = h.nx;
  long& ny = h.ny;
  double& pitch_mm = h.pitch_mm;
  size_t& pitch_key_row = h.pitch_key_row;
  size_t& fallback_pitch_row = h.fallback_pitch_row;
  double& z_to_mm = h.z_to_mm;
  size_t height_row = lines.size();
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto cells = SplitCells(lines[i], delim);
    if (cells.empty()) continue;
    const std::string key = Lower(cells[0]);
    if (key == "height" || key == "\x8d\x82\x82\xb3" /* Shift-JIS 高さ */ ||
        key == "\xe9\xab\x98\xe3\x81\x95" /* UTF-8 高さ */) {
      height_row = i;
      break;
    }
    if (cells.size() < 2) continue;
    const auto value = Number(cells[1], decimal);
    // Keys in English; in Japanese (Shift-JIS or UTF-8) the pitch row is
    // recognised by its micrometre unit, the sizes by the data block.
    if ((key == "horizontal" || key == "vertical") && value) {
      // A size before any cast: whole, positive, at most kMaxSide.
      if (!(*value >= 1 && *value <= kMaxSide) ||
          *value != std::floor(*value)) {
        throw ScanError(fmt::format(
            "{}: line {}: {} = {}; expected a whole number of pixels from 1 "
            "to {}",
            name,
            i + 1,
            std::string(cells[0]),
            internal::Printable(cells[1], 30),
            kMaxSide));
      }
      (key == "horizontal" ? nx : ny) = static_cast<long>(*value);
    }
    const bool unit_says_um =
        (cells.size() >= 3 && IsMicrometre(cells[2])) || IsMicrometre(cells[1]);
    // The pixel size: the key "XY Calibration" whole (other calibration rows,
    // a Z calibration in um per digit, are not the pixel); without an
    // English key (Japanese headers), a row in um whose key names XY.
    if (value && key == "xy calibration") {
      pitch_mm = *value * 1e-3;  // um per pixel
      pitch_key_row = i + 1;
    } else if (value && unit_says_um && pitch_key_row == 0 &&
               key.find("xy") != std::string::npos &&
               key.find('z') == std::string::npos && std::isnan(pitch_mm)) {
      pitch_mm = *value * 1e-3;
      fallback_pitch_row = i + 1;
    }
    if ((key == "unit" || key == "z unit" || key == "height unit") &&
        UnitToMm(cells[1])) {
      z_to_mm = *UnitToMm(cells[1]);
    }
  }
  h.height_row = height_row;
  if (height_row == lines.size()) {
    throw ScanError(fmt::format(
        "{}: no row starting with 'Height'; expected the Keyence VR CSV "
        "height export",
        name));
  }
  if (!(pitch_mm > 0)) {
    throw ScanError(fmt::format(
        "{}: no 'XY Calibration' row (um per pixel) before line {}; the "
        "pixel size cannot be known",
        name,
        height_row + 1));
  }
  return h;
}

// The data block: rows after the Height row, up to trailing empty rows;
// every row nx values (the first row decides when Horizontal is absent).
std::vector<std::vector<float>> ReadVrRows(
    const std::vector<std::string_view>& lines,
    const std::string& name,
    VrHeader* h) {
  const char delim = h->delim, decimal = h->decimal;
  const double z_to_mm = h->z_to_mm;
  long& nx = h->nx;
  const long ny = h->ny;
  const size_t height_row = h->height_row;
  std::vector<std::vector<float>> rows;
  size_t first = height_row + 1;
  // The Height row may carry the first data row after the key.
  for (size_t i = first; i < lines.size(); ++i) {
    if (Trim(lines[i]).empty()) continue;
    const auto cells = SplitCells(lines[i], delim);
    std::vector<float> row;
    row.reserve(cells.size());
    size_t c0 = 0;
    size_t end = cells.size();
    while (end > 0 && cells[end - 1].empty() &&
           (nx < 0 || static_cast<long>(end) > nx))
      --end;
    for (size_t c = c0; c < end; ++c) {
      if (cells[c].empty()) {
        row.push_back(NAN);
        continue;
      }
      const auto v = Number(cells[c], decimal);
      if (!v) {
        throw ScanError(
            fmt::format("{}: line {}, column {}: found '{}', expected a height",
                        name,
                        i + 1,
                        c + 1,
                        internal::Printable(cells[c], 30)));
      }
      row.push_back(static_cast<float>(*v * z_to_mm));
    }
    if (nx < 0) nx = static_cast<long>(row.size());
    if (static_cast<long>(row.size()) != nx) {
      throw ScanError(
          fmt::format("{}: line {}: {} values; expected {} (Horizontal)",
                      name,
                      i + 1,
                      row.size(),
                      nx));
    }
    rows.push_back(std::move(row));
    if (ny > 0 && static_cast<long>(rows.size()) > ny) {
      throw ScanError(fmt::format(
          "{}: line {}: more than {} rows (Vertical)", name, i + 1, ny));
    }
  }
  return rows;
}

// Rows at the end with no measured point: an export cut short that wrote
// the rest as empty cells (or a scan that ends off the specimen), said.
void SayAnEmptyTail(const std::vector<std::vector<float>>& rows,
                    long ny,
                    HeightMap* map) {
  long empty_tail = 0;
  while (empty_tail < ny && std::all_of(rows[ny - 1 - empty_tail].begin(),
                                        rows[ny - 1 - empty_tail].end(),
                                        [](float v) { return std::isnan(v); }))
    ++empty_tail;
  if (empty_tail > 0 && empty_tail < ny) {
    map->metadata.warnings.push_back(fmt::format(
        "the last {} of the {} rows have no measured point (empty cells): "
        "the export may be cut short; read as not measured",
        empty_tail,
        ny));
  }
}

}  // namespace

HeightMap ParseKeyenceCsv(const std::string& bytes, const std::string& name) {
  std::string_view text(bytes);
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.remove_prefix(3);
  const std::vector<std::string_view> lines = Lines(text);
  VrHeader h = ReadVrHeader(lines, name);
  const std::vector<std::vector<float>> rows = ReadVrRows(lines, name, &h);
  const long nx = h.nx;
  long ny = h.ny;
  const size_t height_row = h.height_row;
  const double pitch_mm = h.pitch_mm;
  const size_t pitch_key_row = h.pitch_key_row,
               fallback_pitch_row = h.fallback_pitch_row;
  if (ny < 0) ny = static_cast<long>(rows.size());
  // A file cut short (an interrupted export or copy) keeps the rows it has
  // when they are at least half the map, with a warning; fewer is refused.
  std::string cut;
  const long found = static_cast<long>(rows.size());
  if (found < ny && 2 * found >= ny && found >= 2) {
    cut = fmt::format(
        "the map has {} of the {} rows its header declares (Vertical): the "
        "file is cut; the {} rows present are read",
        found,
        ny,
        found);
    ny = found;
  }
  if (found != ny || ny == 0 || nx <= 0) {
    throw ScanError(
        fmt::format("{}: {} height rows after line {}; expected {} (Vertical)",
                    name,
                    rows.size(),
                    height_row + 1,
                    ny));
  }
  // The field of view the pixel implies: a Keyence VR sees 1 to 100 mm; a
  // wrong calibration row scales every length and slope.
  const size_t pitch_row = pitch_key_row ? pitch_key_row : fallback_pitch_row;
  const double field_mm = std::max(nx, ny) * pitch_mm;
  if (!(field_mm >= kMinField && field_mm <= kMaxField)) {
    throw ScanError(fmt::format(
        "{}: line {}: a pixel of {:.4g} um makes the {} x {} map {:.4g} mm "
        "wide; expected a field of view of {} to {} mm (is line {} the XY "
        "calibration in um per pixel?)",
        name,
        pitch_row,
        pitch_mm * 1e3,
        nx,
        ny,
        field_mm,
        kMinField,
        kMaxField,
        pitch_row));
  }
  HeightMap map;
  if (!cut.empty()) map.metadata.warnings.push_back(cut);
  SayAnEmptyTail(rows, ny, &map);
  if (field_mm < kVrMinField || field_mm > kVrMaxField) {
    map.metadata.warnings.push_back(fmt::format(
        "line {}: a pixel of {:.4g} um makes the map {:.4g} mm wide; a "
        "Keyence VR sees {} to {} mm: check the XY calibration",
        pitch_row,
        pitch_mm * 1e3,
        field_mm,
        kVrMinField,
        kVrMaxField));
  }
  map.Resize(ny, nx);
  for (long r = 0; r < ny; ++r) {
    for (long c = 0; c < nx; ++c) map.height_mm(r, c) = rows[r][c];
  }
  map.dx_mm = map.dy_mm = pitch_mm;
  SyncValidity(&map);
  map.metadata.source = name;
  map.metadata.format = "keyence-csv";
  map.metadata.instrument = "Keyence VR";
  return map;
}

void WriteKeyenceCsv(const HeightMap& map, const std::string& path) {
  if (!(map.dx_mm > 0) || std::abs(map.dx_mm - map.dy_mm) > 1e-9 * map.dx_mm) {
    throw ScanError(fmt::format(
        "{}: the Keyence CSV holds one XY calibration; found pixels of {} x "
        "{} mm",
        path,
        map.dx_mm,
        map.dy_mm));
  }
  std::string out = fmt::format(
      "\"Measurement\",\"{}\"\nSource,\"{}\"\nHorizontal,{}\nVertical,{}\n"
      "XY Calibration,{:.6f},um\nUnit,mm\nHeight\n",
      map.metadata.instrument.empty() ? "height map" : map.metadata.instrument,
      map.metadata.source,
      map.cols(),
      map.rows(),
      map.dx_mm * 1e3);
  out.reserve(out.size() + static_cast<size_t>(map.height_mm.size()) * 11);
  for (Eigen::Index r = 0; r < map.rows(); ++r) {
    for (Eigen::Index c = 0; c < map.cols(); ++c) {
      if (c > 0) out.push_back(',');
      if (map.valid(r, c))
        fmt::format_to(std::back_inserter(out), "{:.7f}", map.height_mm(r, c));
    }
    out.push_back('\n');
  }
  internal::WriteFileAtomically(path, out);
}

namespace {
// A row whose first cell is "Height" or "XY Calibration" (or Shift-JIS
// "Height"), outside '#' comments: a Gwyddion header's "# Height: 10 um"
// is an ASCII matrix's size, not this export.
bool LooksLikeVrCsv(std::string_view head) {
  if (head.find("\x8d\x82\x82\xb3") != std::string_view::npos) return true;
  for (const std::string_view line : Lines(head)) {
    const std::string_view t = Trim(line);
    if (t.empty() || t.front() == '#') continue;
    const std::string key =
        Lower(Trim(line.substr(0, line.find_first_of(",;\t"))));
    if (key == "height" || key == "xy calibration" ||
        key == "\xe9\xab\x98\xe3\x81\x95")
      return true;
  }
  return false;
}
}  // namespace

namespace internal {
ScanFormat KeyenceCsvFormat() {
  return {"keyence_csv",
          "Keyence VR CSV export",
          "Keyence VR series (CSV export of the height block)",
          {".csv"},
          {},
          [](std::string_view head, std::string_view) {
            return LooksLikeVrCsv(head) ? kDetectText : 0;
          },
          [](const std::string& bytes,
             const std::string& name,
             const ReadScanOptions&) { return ParseKeyenceCsv(bytes, name); }};
}

}  // namespace internal

}  // namespace wearscar::scan
