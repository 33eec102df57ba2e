// Sensofar .plu (SensoSCAN / SensoMAP, confocal and interferometric
// topographies). Layout (not in FORMATS.md) after Gwyddion's sensofar.c and
// SurfaceTopography's PLU.py: a 500-byte little-endian header, then per
// layer its size and float32 heights in micrometres, x fastest.
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "byte_reader.h"
#include "wearscar/scan/formats.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr std::uint64_t kDate = 0;                    // char[128]
constexpr std::uint64_t kCalibration = 388;           // yres, xres, ...
constexpr std::uint64_t kPitchX = kCalibration + 16;  // float, um
constexpr std::uint64_t kPitchY = kCalibration + 20;
constexpr std::uint64_t kType = 428;        // uint32: 3 = topography
constexpr std::uint64_t kLayers = 489;      // uint8: number of layers
constexpr std::uint64_t kFirstLayer = 500;  // uint32 rows, uint32 cols
constexpr std::uint32_t kTopography = 3;
constexpr float kUndefined = 1000001.0f;

const char* MeasurementName(std::uint32_t type) {
  switch (type) {
    case 0:
      return "an image";
    case 1:
      return "a profile";
    case 2:
      return "a set of profiles";
    case 4:
      return "coordinates";
    case 5:
      return "a thickness";
    default:
      return "an unknown kind";
  }
}

HeightMap ParsePlu(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions&) {
  ByteReader in(bytes, name);
  in.Need(0, kFirstLayer + 8, "the 508-byte PLU header");
  const auto type = in.At<std::uint32_t>(kType, "measurement type");
  if (type != kTopography) {
    throw ScanError(fmt::format(
        "{}: byte {}: measurement type {} ({}); expected 3, a topography",
        name,
        kType,
        type,
        MeasurementName(type)));
  }
  if (in.At<std::uint8_t>(kLayers, "layer count") == 0) {
    throw ScanError(fmt::format(
        "{}: byte {}: the file holds no layer; expected at least one",
        name,
        kLayers));
  }
  const double dx_um = in.At<float>(kPitchX, "x pitch");
  const double dy_um = in.At<float>(kPitchY, "y pitch");
  if (!(dx_um > 0 && dy_um > 0 && std::isfinite(dx_um) &&
        std::isfinite(dy_um))) {
    throw ScanError(
        fmt::format("{}: byte {}: pitch {} x {} um; expected positive values",
                    name,
                    kPitchX,
                    dx_um,
                    dy_um));
  }
  const std::int64_t rows = in.At<std::uint32_t>(kFirstLayer, "rows");
  const std::int64_t cols = in.At<std::uint32_t>(kFirstLayer + 4, "columns");
  internal::CheckMapSize(in, kFirstLayer, cols, rows);
  const std::uint64_t data = kFirstLayer + 8;
  in.Need(data, static_cast<std::uint64_t>(cols * rows) * 4, "the heights");

  HeightMap map;
  map.Resize(rows, cols);
  const char* p = in.Data(data);
  for (std::int64_t i = 0; i < rows * cols; ++i) {
    float v;
    std::memcpy(&v, p + 4 * i, 4);
    map.height_mm.data()[i] = (v == kUndefined || !std::isfinite(v))
                                  ? std::numeric_limits<float>::quiet_NaN()
                                  : static_cast<float>(1e-3 * v);
  }
  SyncValidity(&map);
  map.dx_mm = 1e-3 * dx_um;
  map.dy_mm = 1e-3 * dy_um;
  map.metadata.format = "plu";
  map.metadata.instrument = "Sensofar";
  map.metadata.date = in.Text(kDate, 128, "date");
  return map;
}

}  // namespace

namespace internal {
ScanFormat SensofarPluFormat() {
  return {"plu",
          "Sensofar .plu",
          "Sensofar PLu neox, S neox (confocal, interferometry)",
          {".plu", ".apx"},
          {},
          [](std::string_view, std::string_view ext) {
            return ext == ".plu" || ext == ".apx" ? kDetectExtension : 0;
          },
          &ParsePlu};
}
}  // namespace internal

}  // namespace wearscar::scan
