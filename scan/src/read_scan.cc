#include "wearscar/scan/read_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "file_io.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::scan {

bool ReadScanOptions::IsValid(std::string* why) const {
  if (measurement_index < 0) {
    if (why) *why = "measurement_index must be >= 0";
    return false;
  }
  if (ascii_pitch_mm < 0) {
    if (why) *why = "ascii_pitch_mm must be >= 0";
    return false;
  }
  if (!(min_pitch_mm > 0 && max_pitch_mm >= min_pitch_mm &&
        max_pixel_aspect >= 1 && warn_field_mm >= 0)) {
    if (why) *why = "pixel limits out of range";
    return false;
  }
  if (max_member_bytes == 0 || max_total_bytes == 0 ||
      !(max_expansion_ratio >= 1)) {
    if (why) *why = "decompression limits must be positive (ratio >= 1)";
    return false;
  }
  return true;
}

namespace {

HeightMap ParseByContent(const std::string& bytes,
                         const std::string& path,
                         const ReadScanOptions& options);

}  // namespace

void AllowLargeMaps(ReadScanOptions* o) {
  o->max_member_bytes = std::uint64_t{8} << 30;
  o->max_total_bytes = std::uint64_t{16} << 30;
  o->max_expansion_ratio = 1e12;
}

void CheckPixels(HeightMap* map, const ReadScanOptions& o) {
  const std::string& file = map->metadata.source;
  const double dx = map->dx_mm, dy = map->dy_mm;
  if (!(dx >= o.min_pitch_mm && dx <= o.max_pitch_mm && dy >= o.min_pitch_mm &&
        dy <= o.max_pitch_mm)) {
    throw ScanError(fmt::format(
        "{}: a pixel of {:.4g} x {:.4g} mm; expected {:.4g} to {:.4g} mm "
        "(check the file's pixel size or length unit)",
        file,
        dx,
        dy,
        o.min_pitch_mm,
        o.max_pitch_mm));
  }
  const double aspect = std::max(dx, dy) / std::min(dx, dy);
  if (aspect > o.max_pixel_aspect) {
    throw ScanError(fmt::format(
        "{}: pixels of {:.4g} x {:.4g} mm, {:.4g} times longer one way than "
        "the other; expected at most {} (unequal pitches this strong are "
        "usually a wrong size in the header; allow them explicitly if real)",
        file,
        dx,
        dy,
        aspect,
        o.max_pixel_aspect));
  }
  const double width = std::max(map->cols() * dx, map->rows() * dy);
  if (width < o.warn_field_mm) {
    map->metadata.warnings.push_back(fmt::format(
        "the map is {:.3g} mm wide ({} x {} pixels of {:.4g} um): smaller than "
        "a reciprocating stroke; check the pixel size",
        width,
        map->cols(),
        map->rows(),
        1e3 * dx));
  }
}

HeightMap ReadScan(const std::string& path, const ReadScanOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw ScanError(fmt::format("{}: {}", path, why));
  const std::string bytes = internal::ReadFileBytes(path);
  HeightMap map = ParseByContent(bytes, path, options);
  if (map.metadata.source.empty()) map.metadata.source = path;
  CheckPixels(&map, options);
  return map;
}

namespace {

HeightMap ParseByContent(const std::string& bytes,
                         const std::string& path,
                         const ReadScanOptions& options) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  auto starts = [&](const char* magic) { return bytes.rfind(magic, 0) == 0; };
  if (starts("KPK0") || starts("KPK1")) {
    if (ext == ".zag") return ParseZag(bytes, path, options);
    return ParseZon(bytes, path, options);
  }
  if (starts("VK4_") || starts("VK3_")) return ParseVk4(bytes, path);
  if (starts("VK6") || starts("VK7")) return ParseVk67(bytes, path, options);
  if (starts("Gwyddion Simple Field")) return ParseGsf(bytes, path);
  if (starts("PK\x03\x04")) return ParseX3p(bytes, path, options);
  // Extensions of binary formats whose magic did not match: say so.
  for (const char* e :
       {".zon", ".zag", ".vk4", ".vk6", ".vk7", ".x3p", ".gsf"}) {
    if (ext == e) {
      throw ScanError(fmt::format(
          "{}: byte 0: found {}, which is not the magic of a {} file",
          path,
          fmt::format("{:?}", bytes.substr(0, 4)).substr(0, 20),
          ext));
    }
  }
  // Text: the Keyence CSV export names its Height block; anything else is an
  // ASCII matrix.
  const std::string head = bytes.substr(0, 1 << 16);
  if (head.find("Height") != std::string::npos ||
      head.find("XY Calibration") != std::string::npos ||
      head.find("\x8d\x82\x82\xb3") != std::string::npos) {
    return ParseKeyenceCsv(bytes, path);
  }
  return ParseAsciiMatrix(bytes, path, options);
}

}  // namespace

}  // namespace wearscar::scan
