// Zygo MetroPro .dat (NewView, GPI and other MetroPro interferometers).
// Layout (not in FORMATS.md) after Gwyddion's metropro.c and
// SurfaceTopography's MetroPro.py: a big-endian header of header_size bytes
// (834 or 4096), the intensity block of ac_n_bytes, then the connected phase as
// int32, x fastest; heights in metres are phase * intf_scale_factor *
// obliquity_factor * wavelength / (4096, 32768 or 131072 by phase_res).
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>

#include "byte_reader.h"
#include "wearscar/scan/formats.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr std::uint64_t kHeaderSize = 6;       // uint32
constexpr std::uint64_t kIntensityBytes = 60;  // uint32 ac_n_bytes
constexpr std::uint64_t kPhaseWidth = 68;      // uint16 cn_org_width, height
constexpr std::uint64_t kPhaseBytes = 72;      // uint32 cn_n_bytes
constexpr std::uint64_t kTimeStamp = 76;       // int32, Unix seconds
constexpr std::uint64_t kScaleFactor = 164;    // float intf_scale_factor
constexpr std::uint64_t kWavelength = 168;     // float, m
constexpr std::uint64_t kObliquity = 176;      // float
constexpr std::uint64_t kLateralRes = 184;     // float, m per pixel
constexpr std::uint64_t kPhaseRes = 218;       // int16: 0, 1, 2
constexpr std::uint64_t kSign = 232;           // int16
constexpr std::uint64_t kObjective = 246;      // char[12]
constexpr std::uint64_t kMinHeaderSize = 834;
constexpr std::int32_t kInvalidPhase = 2147483640;

const std::string kMagics[] = {std::string("\x88\x1b\x03\x6f", 4),
                               std::string("\x88\x1b\x03\x70", 4),
                               std::string("\x88\x1b\x03\x71", 4)};

bool HasMagic(std::string_view head) {
  for (const std::string& m : kMagics) {
    if (head.substr(0, 4) == m) return true;
  }
  return false;
}

// Metres per stored phase unit: scale factor x obliquity x wavelength over
// the phase resolution's steps, negated when the file says so.
double HeightStepM(const ByteReader& in) {
  const auto phase_res = in.AtBigEndian<std::int16_t>(kPhaseRes, "phase_res");
  if (phase_res < 0 || phase_res > 2) {
    throw ScanError(fmt::format("{}: byte {}: phase_res {}; expected 0, 1 or 2",
                                in.name(),
                                kPhaseRes,
                                phase_res));
  }
  const double steps[] = {4096.0, 32768.0, 131072.0};
  const double scale_m =
      double{in.AtBigEndian<float>(kScaleFactor, "intf_scale_factor")} *
      in.AtBigEndian<float>(kObliquity, "obliquity_factor") *
      in.AtBigEndian<float>(kWavelength, "wavelength") / steps[phase_res] *
      (in.AtBigEndian<std::int16_t>(kSign, "sign") ? -1.0 : 1.0);
  if (!(std::isfinite(scale_m) && scale_m != 0)) {
    throw ScanError(fmt::format(
        "{}: byte {}: a height step of {} m from the scale factor, "
        "obliquity and wavelength; expected a finite, non-zero step",
        in.name(),
        kScaleFactor,
        scale_m));
  }
  return scale_m;
}

// The acquisition time (Unix seconds in the header) as UTC, or "".
std::string Date(const ByteReader& in) {
  const std::time_t t = in.AtBigEndian<std::int32_t>(kTimeStamp, "time");
  std::tm tm{};
  if (t <= 0 || gmtime_r(&t, &tm) == nullptr) return {};
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return date;
}

// Where the phase data are and how many: the header's sizes, checked.
struct PhaseBlock {
  std::uint64_t offset = 0, bytes = 0;
  std::int64_t cols = 0, rows = 0;
};

PhaseBlock CheckPhaseBlock(const ByteReader& in) {
  const std::string& name = in.name();
  const std::uint64_t header =
      in.AtBigEndian<std::uint32_t>(kHeaderSize, "size");
  const std::uint64_t intensity =
      in.AtBigEndian<std::uint32_t>(kIntensityBytes, "intensity size");
  PhaseBlock b;
  b.cols = in.AtBigEndian<std::uint16_t>(kPhaseWidth, "width");
  b.rows = in.AtBigEndian<std::uint16_t>(kPhaseWidth + 2, "height");
  b.bytes = in.AtBigEndian<std::uint32_t>(kPhaseBytes, "size");
  if (header < kMinHeaderSize) {
    throw ScanError(
        fmt::format("{}: byte {}: header of {} bytes; expected 834 or more",
                    name,
                    kHeaderSize,
                    header));
  }
  if (b.cols == 0 || b.rows == 0 || b.bytes == 0) {
    throw ScanError(fmt::format(
        "{}: byte {}: the phase block is {} x {} ({} bytes): the file holds "
        "no height data",
        name,
        kPhaseWidth,
        b.cols,
        b.rows,
        b.bytes));
  }
  internal::CheckMapSize(in, kPhaseWidth, b.cols, b.rows);
  if (b.bytes != static_cast<std::uint64_t>(b.cols * b.rows) * 4) {
    throw ScanError(fmt::format(
        "{}: byte {}: a phase block of {} bytes for {} x {} points; expected "
        "{}",
        name,
        kPhaseBytes,
        b.bytes,
        b.cols,
        b.rows,
        b.cols * b.rows * 4));
  }
  b.offset = header + intensity;
  in.Need(b.offset, b.bytes, "the phase data");
  return b;
}

HeightMap ParseMetroPro(const std::string& bytes,
                        const std::string& name,
                        const ReadScanOptions&) {
  ByteReader in(bytes, name);
  in.Need(0, kMinHeaderSize, "the 834-byte header");
  if (!HasMagic(bytes)) {
    throw ScanError(
        fmt::format("{}: byte 0: found '{}'; expected the MetroPro magic "
                    "'\\x88\\x1b\\x03\\x6f' to '\\x71'",
                    name,
                    internal::Printable(bytes.substr(0, 4))));
  }
  const PhaseBlock block = CheckPhaseBlock(in);
  const double scale_m = HeightStepM(in);
  const double pixel_m = in.AtBigEndian<float>(kLateralRes, "lateral_res");
  if (!(pixel_m > 0 && std::isfinite(pixel_m))) {
    throw ScanError(fmt::format(
        "{}: byte {}: lateral resolution {} m per pixel; expected a positive "
        "value (the file is not calibrated laterally)",
        name,
        kLateralRes,
        pixel_m));
  }
  HeightMap map;
  map.Resize(block.rows, block.cols);
  const char* p = in.Data(block.offset);
  for (std::int64_t i = 0; i < block.rows * block.cols; ++i) {
    unsigned char b[4];
    std::memcpy(b, p + 4 * i, 4);
    const std::int32_t v = static_cast<std::int32_t>(
        (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) |
        (std::uint32_t{b[2]} << 8) | std::uint32_t{b[3]});
    map.height_mm.data()[i] = v >= kInvalidPhase
                                  ? std::numeric_limits<float>::quiet_NaN()
                                  : static_cast<float>(1e3 * scale_m * v);
  }
  SyncValidity(&map);
  map.dx_mm = map.dy_mm = 1e3 * pixel_m;
  map.metadata.format = "metropro";
  const std::string objective = in.Text(kObjective, 12, "objective");
  map.metadata.instrument =
      "Zygo MetroPro" + (objective.empty() ? "" : " (" + objective + ")");
  map.metadata.date = Date(in);
  return map;
}

}  // namespace

namespace internal {
ScanFormat ZygoMetroProFormat() {
  return {"metropro",
          "Zygo MetroPro .dat",
          "Zygo NewView, GPI and other MetroPro interferometers",
          {".dat"},
          {kMagics[0], kMagics[1], kMagics[2]},
          [](std::string_view head, std::string_view) {
            return HasMagic(head) ? kDetectMagic : 0;
          },
          &ParseMetroPro};
}
}  // namespace internal

}  // namespace wearscar::scan
