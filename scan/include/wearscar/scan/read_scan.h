#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan {

struct ReadScanOptions {
  // .zag: which measurement (0-based; ListZagMeasurements names them).
  int measurement_index = 0;
  // ASCII matrix: pixel pitch (mm) and the unit of the heights.
  // ASCII matrices whose header does not say (0, "": not given; a
  // matrix's heights without a unit are then taken as mm, with a warning).
  double ascii_pitch_mm = 0.0;
  std::string ascii_z_unit;
  // Decompression limits (archive members, zstd frames), checked before
  // inflating where the container states the size and while inflating
  // where it does not: a member expands to at most max_member_bytes; beyond
  // free_expansion_bytes, to at most max_expansion_ratio times its
  // compressed size; the members of one file to at most max_total_bytes
  // together. A 8192 x 8192 map of float64 is 512 MiB.
  std::uint64_t max_member_bytes = std::uint64_t{1} << 30;
  std::uint64_t max_total_bytes = std::uint64_t{3} << 29;  // 1.5 GiB
  std::uint64_t free_expansion_bytes = std::uint64_t{64} << 20;
  double max_expansion_ratio = 100.0;
  // Pixels: refused outside [min, max] mm or when one side is more than
  // max_pixel_aspect times the other (a wrong size in a header); a map
  // narrower than warn_field_mm is read with a warning.
  double min_pitch_mm = 1e-6;
  double max_pitch_mm = 100.0;
  double max_pixel_aspect = 20.0;
  double warn_field_mm = 0.5;

  bool IsValid(std::string* why) const;
};

// Reads any supported height map, chosen by magic bytes (then extension):
// Keyence .zon / .zag (KPK0, KPK1), .vk4 / .vk6 / .vk7, Keyence VR CSV,
// ISO 5436-2 .x3p, Gwyddion .gsf, ASCII matrix. Throws ScanError.
HeightMap ReadScan(const std::string& path,
                   const ReadScanOptions& options = {});

// The opt-in for truly large maps: a member up to 8 GiB, a file 16 GiB,
// any expansion ratio.
void AllowLargeMaps(ReadScanOptions* options);

// The checks ReadScan applies to every map it returns (pixel size, aspect,
// field of view); throws ScanError, or adds a warning.
void CheckPixels(HeightMap* map, const ReadScanOptions& options);

// The individual readers, over bytes in memory; `name` appears in errors.
HeightMap ParseX3p(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options = {});
HeightMap ParseVk4(const std::string& bytes, const std::string& name);
HeightMap ParseVk67(const std::string& bytes,
                    const std::string& name,
                    const ReadScanOptions& options = {});
HeightMap ParseZon(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options = {});
HeightMap ParseZag(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options = {});
std::vector<std::string> ListZagMeasurements(const std::string& bytes,
                                             const std::string& name);
HeightMap ParseKeyenceCsv(const std::string& bytes, const std::string& name);
HeightMap ParseAsciiMatrix(const std::string& bytes,
                           const std::string& name,
                           const ReadScanOptions& options);

}  // namespace wearscar::scan
