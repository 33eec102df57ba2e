// Alicona InfiniteFocus .al3d. Layout (not in FORMATS.md) after Gwyddion's
// alicona.c and SurfaceTopography's AL3D.py: a 17-byte magic, then tags of
// 52 bytes (key[20], value[30], CR LF) starting with Version and TagCount,
// then at DepthImageOffset float32 heights in metres, rows padded to 8
// bytes.
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "byte_reader.h"
#include "wearscar/scan/formats.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr char kMagic[] = "AliconaImaging\0\r\n";
constexpr std::uint64_t kMagicSize = sizeof(kMagic) - 1;  // 17
constexpr std::uint64_t kTagSize = 52;
constexpr std::uint64_t kMaxTags = 4096;

struct Tag {
  std::string value;
  std::uint64_t offset = 0;
};

std::map<std::string, Tag> ReadTags(const ByteReader& in) {
  std::map<std::string, Tag> tags;
  auto read_tag = [&](std::uint64_t at) {
    in.Need(at, kTagSize, "a 52-byte tag");
    if (std::memcmp(in.Data(at + 50), "\r\n", 2) != 0) {
      throw ScanError(fmt::format(
          "{}: byte {}: a tag ends in '{}'; expected CR LF",
          in.name(),
          at + 50,
          internal::Printable(std::string_view(in.Data(at + 50), 2))));
    }
    const std::string key = in.Text(at, 20, "tag key");
    tags[key] = {in.Text(at + 20, 30, "tag value"), at + 20};
    return key;
  };
  if (read_tag(kMagicSize) != "Version" ||
      read_tag(kMagicSize + kTagSize) != "TagCount") {
    throw ScanError(
        fmt::format("{}: byte {}: the first tags are not Version and TagCount",
                    in.name(),
                    kMagicSize));
  }
  const Tag& count = tags["TagCount"];
  std::uint64_t n = 0;
  const auto r = std::from_chars(
      count.value.data(), count.value.data() + count.value.size(), n);
  if (r.ec != std::errc() || r.ptr != count.value.data() + count.value.size() ||
      n > kMaxTags) {
    throw ScanError(fmt::format(
        "{}: byte {}: TagCount '{}'; expected a whole number up to {}",
        in.name(),
        count.offset,
        internal::Printable(count.value),
        kMaxTags));
  }
  in.Need(kMagicSize + 2 * kTagSize, n * kTagSize, "the tags TagCount names");
  for (std::uint64_t i = 0; i < n; ++i) {
    read_tag(kMagicSize + (2 + i) * kTagSize);
  }
  return tags;
}

double Number(const ByteReader& in,
              const std::map<std::string, Tag>& tags,
              const std::string& key) {
  const auto it = tags.find(key);
  if (it == tags.end()) {
    throw ScanError(
        fmt::format("{}: byte {}: no tag {}; expected one in the header",
                    in.name(),
                    kMagicSize,
                    key));
  }
  const std::string& v = it->second.value;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size()) {
    throw ScanError(
        fmt::format("{}: byte {}: tag {} is '{}'; expected a number",
                    in.name(),
                    it->second.offset,
                    key,
                    internal::Printable(v)));
  }
  return x;
}

HeightMap ParseAl3d(const std::string& bytes,
                    const std::string& name,
                    const ReadScanOptions&) {
  ByteReader in(bytes, name);
  in.Need(0, kMagicSize, "the magic");
  if (std::memcmp(in.Data(0), kMagic, kMagicSize) != 0) {
    throw ScanError(
        fmt::format("{}: byte 0: found '{}'; expected 'AliconaImaging'",
                    name,
                    internal::Printable(bytes.substr(0, kMagicSize))));
  }
  const std::map<std::string, Tag> tags = ReadTags(in);
  const double cols_d = Number(in, tags, "Cols");
  const double rows_d = Number(in, tags, "Rows");
  const std::int64_t cols = cols_d >= 0 && cols_d <= kMaxPixels
                                ? static_cast<std::int64_t>(cols_d)
                                : -1;
  const std::int64_t rows = rows_d >= 0 && rows_d <= kMaxPixels
                                ? static_cast<std::int64_t>(rows_d)
                                : -1;
  internal::CheckMapSize(in, tags.at("Cols").offset, cols, rows);
  const double dx_m = Number(in, tags, "PixelSizeXMeter");
  const double dy_m = Number(in, tags, "PixelSizeYMeter");
  if (!(dx_m > 0 && dy_m > 0 && std::isfinite(dx_m) && std::isfinite(dy_m))) {
    throw ScanError(
        fmt::format("{}: byte {}: pixel {} x {} m; expected positive values",
                    name,
                    tags.at("PixelSizeXMeter").offset,
                    dx_m,
                    dy_m));
  }
  const double offset_d = Number(in, tags, "DepthImageOffset");
  if (!(offset_d > 0 && offset_d < static_cast<double>(bytes.size()))) {
    throw ScanError(fmt::format(
        "{}: byte {}: DepthImageOffset {}; expected a position inside the "
        "{}-byte file (0 means the file holds no depth image)",
        name,
        tags.at("DepthImageOffset").offset,
        offset_d,
        bytes.size()));
  }
  const auto offset = static_cast<std::uint64_t>(offset_d);
  const double invalid = tags.count("InvalidPixelValue")
                             ? Number(in, tags, "InvalidPixelValue")
                             : std::numeric_limits<double>::quiet_NaN();
  // Rows are padded to a multiple of 8 bytes.
  const std::uint64_t stride =
      (static_cast<std::uint64_t>(cols) * 4 + 7) / 8 * 8;
  in.Need(offset,
          stride * static_cast<std::uint64_t>(rows - 1) +
              static_cast<std::uint64_t>(cols) * 4,
          "the depth image");

  HeightMap map;
  map.Resize(rows, cols);
  const double tolerance = 1.5e-7 * std::abs(invalid);
  for (std::int64_t r = 0; r < rows; ++r) {
    const char* p = in.Data(offset + static_cast<std::uint64_t>(r) * stride);
    for (std::int64_t c = 0; c < cols; ++c) {
      float v;
      std::memcpy(&v, p + 4 * c, 4);
      const bool bad =
          !std::isfinite(v) ||
          (std::isfinite(invalid) && std::abs(v - invalid) <= tolerance);
      map.height_mm(r, c) = bad ? std::numeric_limits<float>::quiet_NaN()
                                : static_cast<float>(1e3 * v);
    }
  }
  SyncValidity(&map);
  map.dx_mm = 1e3 * dx_m;
  map.dy_mm = 1e3 * dy_m;
  map.metadata.format = "al3d";
  map.metadata.instrument = "Alicona Imaging";
  const auto app = tags.find("CreatingApplication");
  if (app != tags.end() && !app->second.value.empty()) {
    map.metadata.instrument += " (" + app->second.value + ")";
  }
  return map;
}

}  // namespace

namespace internal {
ScanFormat AliconaAl3dFormat() {
  return {"al3d",
          "Alicona .al3d",
          "Alicona InfiniteFocus, Bruker Alicona (focus variation)",
          {".al3d"},
          {std::string(kMagic, kMagicSize)},
          [](std::string_view head, std::string_view) {
            return head.substr(0, kMagicSize) ==
                           std::string_view(kMagic, kMagicSize)
                       ? kDetectMagic
                       : 0;
          },
          &ParseAl3d};
}
}  // namespace internal

}  // namespace wearscar::scan
