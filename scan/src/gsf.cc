#include "wearscar/scan/gsf.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include "byte_reader.h"
#include "file_io.h"
#include "wearscar/scan/formats.h"
#include "wearscar/support/text.h"

namespace wearscar::scan {
namespace {

constexpr char kMagic[] = "Gwyddion Simple Field 1.0";

// Metres per unit of an SI length unit as Gwyddion writes them.
std::optional<double> UnitToMm(const std::string& unit) {
  if (unit.empty() || unit == "m") return 1e3;
  if (unit == "mm") return 1.0;
  if (unit == "um" || unit == "\xC2\xB5m" || unit == "\xCE\xBCm") return 1e-3;
  if (unit == "nm") return 1e-6;
  return std::nullopt;
}

std::string Trim(std::string_view s) { return std::string(support::Trim(s)); }

}  // namespace

namespace {

// The "Name = value" lines between the magic line and the NUL padding,
// with the line each came from (for messages).
struct GsfHeader {
  std::string name;
  size_t nul = 0;  // first NUL byte: the header ends there
  std::map<std::string, std::string> fields;
  std::map<std::string, size_t> field_line;

  long long Int(const char* key) {
    auto it = fields.find(key);
    if (it == fields.end()) {
      throw ScanError(fmt::format(
          "{}: header has no {}; expected '{} = <pixels>'", name, key, key));
    }
    long long v = 0;
    auto r = std::from_chars(
        it->second.data(), it->second.data() + it->second.size(), v);
    if (r.ec != std::errc() || r.ptr != it->second.data() + it->second.size() ||
        v <= 0 || v > kMaxPixels) {
      throw ScanError(fmt::format(
          "{}: header line {}: {} = '{}'; expected a positive pixel count up "
          "to {}",
          name,
          field_line[key],
          key,
          internal::Printable(it->second),
          kMaxPixels));
    }
    return v;
  }
  double Real(const char* key, double fallback) {
    auto it = fields.find(key);
    if (it == fields.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0' || !(v > 0) ||
        !std::isfinite(v)) {
      throw ScanError(
          fmt::format("{}: header line {}: {} = '{}'; expected a positive "
                      "length",
                      name,
                      field_line[key],
                      key,
                      internal::Printable(it->second)));
    }
    return v;
  }
};

GsfHeader ReadGsfHeader(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, sizeof(kMagic) - 1, kMagic) != 0) {
    throw ScanError(
        fmt::format("{}: byte 0: found '{}', expected the GSF magic '{}'",
                    name,
                    internal::Printable(bytes, 25),
                    kMagic));
  }
  const size_t nul = bytes.find('\0');
  if (nul == std::string::npos) {
    throw ScanError(
        fmt::format("{}: no NUL byte ends the GSF header; expected 1-4 NUL "
                    "bytes then float32 data",
                    name));
  }
  GsfHeader h;
  h.name = name;
  h.nul = nul;
  std::map<std::string, std::string>& fields = h.fields;
  std::map<std::string, size_t>& field_line = h.field_line;
  size_t pos = bytes.find('\n');
  size_t line_no = 1;
  while (pos != std::string::npos && pos < nul) {
    const size_t end = std::min(bytes.find('\n', pos + 1), nul);
    const std::string line = Trim(bytes.substr(pos + 1, end - pos - 1));
    ++line_no;
    pos = end == nul ? std::string::npos : end;
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) {
      throw ScanError(
          fmt::format("{}: header line {}: found '{}', expected 'Name = value'",
                      name,
                      line_no,
                      internal::Printable(line, 60)));
    }
    fields[Trim(line.substr(0, eq))] = Trim(line.substr(eq + 1));
    field_line[Trim(line.substr(0, eq))] = line_no;
  }
  return h;
}

}  // namespace

HeightMap ParseGsf(const std::string& bytes, const std::string& name) {
  GsfHeader h = ReadGsfHeader(bytes, name);
  std::map<std::string, std::string>& fields = h.fields;
  const size_t nul = h.nul;
  const long long xres = h.Int("XRes"), yres = h.Int("YRes");
  if (xres * yres > kMaxPixels) {
    throw ScanError(fmt::format("{}: XRes x YRes = {} x {} exceeds {} pixels",
                                name,
                                xres,
                                yres,
                                kMaxPixels));
  }
  const auto xy_unit =
      UnitToMm(fields.count("XYUnits") ? fields["XYUnits"] : "m");
  const auto z_unit = UnitToMm(fields.count("ZUnits") ? fields["ZUnits"] : "m");
  if (!xy_unit || !z_unit) {
    throw ScanError(
        fmt::format("{}: XYUnits '{}' / ZUnits '{}'; expected m, mm, um or nm",
                    name,
                    fields["XYUnits"],
                    fields["ZUnits"]));
  }
  const double xreal = h.Real("XReal", 1.0), yreal = h.Real("YReal", 1.0);
  // Data start: the header plus NUL padding is a multiple of 4.
  const size_t data = (nul / 4 + 1) * 4;
  const size_t row_bytes = static_cast<size_t>(xres) * 4;
  size_t need = static_cast<size_t>(yres) * row_bytes;
  const size_t present = bytes.size() > data ? bytes.size() - data : 0;
  // A file cut short (an interrupted copy) keeps its whole rows when at
  // least half are there, with a warning giving the count.
  const long long rows_present = static_cast<long long>(present / row_bytes);
  std::string cut;
  if (present < need) {
    if (rows_present < 2 || 2 * rows_present < yres) {
      throw ScanError(
          fmt::format("{}: byte {}: data truncated: {} bytes present, expected "
                      "{} for {} x {} float32",
                      name,
                      data,
                      present,
                      need,
                      xres,
                      yres));
    }
    cut = fmt::format(
        "the file is cut short: {} of the {} rows declared (YRes) are whole "
        "and were read; was the copy interrupted?",
        rows_present,
        yres);
  }
  const long long rows = cut.empty() ? yres : rows_present;
  need = static_cast<size_t>(rows) * row_bytes;
  HeightMap map;
  map.Resize(rows, xres);
  if (!cut.empty()) map.metadata.warnings.push_back(cut);
  const float scale = static_cast<float>(*z_unit);
  std::memcpy(map.height_mm.data(), bytes.data() + data, need);
  map.height_mm *= scale;
  map.dx_mm = xreal * *xy_unit / static_cast<double>(xres);
  map.dy_mm = yreal * *xy_unit / static_cast<double>(yres);
  if (cut.empty() && bytes.size() > data + need) {
    map.metadata.warnings.push_back(
        fmt::format("{} trailing bytes after the data ignored",
                    bytes.size() - data - need));
  }
  SyncValidity(&map);
  map.metadata.source = name;
  map.metadata.format = "gsf";
  if (fields.count("Title")) map.metadata.channel = fields["Title"];
  return map;
}

HeightMap ReadGsf(const std::string& path) {
  return ParseGsf(internal::ReadFileBytes(path), path);
}

void WriteGsf(const HeightMap& map, const std::string& path) {
  std::string out = fmt::format(
      "{}\nXRes = {}\nYRes = {}\nXReal = {:.9g}\nYReal = {:.9g}\nXYUnits = "
      "m\nZUnits = m\n"
      "Title = {}\n",
      kMagic,
      map.cols(),
      map.rows(),
      map.dx_mm * map.cols() * 1e-3,
      map.dy_mm * map.rows() * 1e-3,
      map.metadata.channel);
  out.append(4 - out.size() % 4, '\0');
  const size_t start = out.size();
  out.resize(start + static_cast<size_t>(map.height_mm.size()) * 4);
  HeightMap::Heights metres = map.height_mm * 1e-3f;
  for (Eigen::Index i = 0; i < metres.size(); ++i) {
    if (!map.valid.data()[i]) metres.data()[i] = std::nanf("");
  }
  std::memcpy(out.data() + start,
              metres.data(),
              static_cast<size_t>(metres.size()) * 4);
  internal::WriteFileAtomically(path, out);
}

namespace internal {
ScanFormat GsfFormat() {
  return {"gsf",
          "Gwyddion Simple Field .gsf",
          "Gwyddion and anything that exports to it",
          {".gsf"},
          {"Gwyddion Simple Field"},
          [](std::string_view head, std::string_view) {
            return head.rfind("Gwyddion Simple Field", 0) == 0 ? kDetectMagic
                                                               : 0;
          },
          [](const std::string& bytes,
             const std::string& name,
             const ReadScanOptions&) { return ParseGsf(bytes, name); }};
}
}  // namespace internal

}  // namespace wearscar::scan
