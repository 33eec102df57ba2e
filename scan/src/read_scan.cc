#include "wearscar/scan/read_scan.h"

#include <fmt/format.h>

#include <algorithm>

#include "file_io.h"
#include "inflate.h"
#include "wearscar/scan/formats.h"
#include "wearscar/support/compressed.h"

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

void AllowLargeMaps(ReadScanOptions* o) {
  o->max_member_bytes = std::uint64_t{8} << 30;
  o->max_total_bytes = std::uint64_t{16} << 30;
  o->max_expansion_ratio = 1e12;
}

void CheckPixels(HeightMap* map, const ReadScanOptions& o) {
  const std::string& file = map->metadata.source;
  if (map->rows() < 2 || map->cols() < 2) {
    throw ScanError(fmt::format(
        "{}: a 1-D profile ({} x {} points); expected a height map of the "
        "worn track (an area scan: the track's centreline and its width are "
        "found in it)",
        file,
        map->cols(),
        map->rows()));
  }
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
  std::string bytes = internal::ReadFileBytes(path);
  const support::Compression packed = support::CompressionOf(bytes);
  if (packed != support::Compression::kNone) {
    // A text map (or any other) gzip- or zstd-compressed as a whole.
    // Within the limits of a compressed member (ReadScanOptions).
    const double by_ratio =
        options.max_expansion_ratio * static_cast<double>(bytes.size());
    const auto bound = static_cast<std::uint64_t>(std::min(
        static_cast<double>(options.max_member_bytes),
        std::max(static_cast<double>(options.free_expansion_bytes), by_ratio)));
    const std::string where = fmt::format(
        "{} ({}-compressed)", path, support::CompressionName(packed));
    std::string expanded, what;
    if (!support::Decompress(bytes, packed, bound, false, &expanded, &what)) {
      if (expanded.size() >= bound) {
        internal::InflateBudget(options).Check(
            bytes.size(), bound + 1, options.max_member_bytes, where);
      }
      throw ScanError(fmt::format("{}: {}", where, what));
    }
    bytes = std::move(expanded);
  }
  HeightMap map = DetectScanFormat(bytes, path).parse(bytes, path, options);
  if (map.metadata.source.empty()) map.metadata.source = path;
  CheckPixels(&map, options);
  return map;
}

}  // namespace wearscar::scan
