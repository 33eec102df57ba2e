// Bruker/Veeco Vision .opd (Wyko NT, ContourGT white-light interferometers).
// Layout (not in FORMATS.md) after Gwyddion's opdfile.c and SurfaceTopography's
// OPD.py: two bytes, a directory of 24-byte entries (name[16], int16 type,
// int32 length, uint16 attributes) whose first entry is the directory
// itself; the blocks follow in directory order. Heights are in wavelengths
// (times Wavelength / Mult nm), stored column by column.
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "byte_reader.h"
#include "wearscar/scan/formats.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr std::uint64_t kDirectory = 2;
constexpr std::uint64_t kEntrySize = 24;
constexpr std::int16_t kArray = 3;

struct Block {
  std::int16_t type = 0;
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
};

std::map<std::string, Block> ReadDirectory(const ByteReader& in) {
  in.Need(kDirectory, kEntrySize, "the directory entry");
  if (in.Text(kDirectory, 16, "directory name") != "Directory") {
    throw ScanError(fmt::format(
        "{}: byte 2: found '{}'; expected the block 'Directory'",
        in.name(),
        internal::Printable(std::string_view(in.Data(kDirectory), 16))));
  }
  const auto length = in.At<std::int32_t>(kDirectory + 18, "directory length");
  if (length < static_cast<std::int32_t>(kEntrySize) || length % kEntrySize) {
    throw ScanError(fmt::format(
        "{}: byte {}: directory of {} bytes; expected a positive multiple "
        "of 24",
        in.name(),
        kDirectory + 18,
        length));
  }
  const std::uint64_t entries = static_cast<std::uint64_t>(length) / kEntrySize;
  in.Need(kDirectory, entries * kEntrySize, "the directory");
  std::map<std::string, Block> blocks;
  std::uint64_t offset = kDirectory + entries * kEntrySize;
  for (std::uint64_t i = 1; i < entries; ++i) {
    const std::uint64_t at = kDirectory + i * kEntrySize;
    const auto size = in.At<std::int32_t>(at + 18, "block length");
    if (size <= 0) continue;
    const std::string name = in.Text(at, 16, "block name");
    if (!name.empty() && !blocks.count(name)) {
      blocks[name] = {in.At<std::int16_t>(at + 16, "block type"),
                      offset,
                      static_cast<std::uint64_t>(size)};
    }
    offset += static_cast<std::uint64_t>(size);
  }
  return blocks;
}

// The block named `key` read as a number of its own type, or `fallback`.
double Scalar(const ByteReader& in,
              const std::map<std::string, Block>& blocks,
              const std::string& key,
              double fallback) {
  const auto it = blocks.find(key);
  if (it == blocks.end()) return fallback;
  const Block& b = it->second;
  switch (b.type) {
    case 6:
      return in.At<std::int16_t>(b.offset, key.c_str());
    case 7:
      return in.At<float>(b.offset, key.c_str());
    case 8:
      return in.At<double>(b.offset, key.c_str());
    case 12:
      return in.At<std::int32_t>(b.offset, key.c_str());
    default:
      throw ScanError(fmt::format(
          "{}: byte {}: block {} has type {}; expected a number (6, 7, 8 "
          "or 12)",
          in.name(),
          b.offset,
          key,
          b.type));
  }
}

// The array holding the heights: the one PrimaryData2D names (a string
// after a 0x12 0x01 prefix and its length), else the first of the usual
// names.
const Block* HeightBlock(const ByteReader& in,
                         const std::map<std::string, Block>& blocks) {
  const auto primary = blocks.find("PrimaryData2D");
  if (primary != blocks.end() && primary->second.length >= 3) {
    const Block& p = primary->second;
    const auto len = in.At<std::uint8_t>(p.offset + 2, "PrimaryData2D");
    if (in.At<std::uint8_t>(p.offset, "PrimaryData2D") == 0x12 &&
        3u + len <= p.length) {
      const auto it = blocks.find(in.Text(p.offset + 3, len, "PrimaryData2D"));
      if (it != blocks.end() && it->second.type == kArray) return &it->second;
    }
  }
  for (const char* key : {"RAW_DATA", "RAW DATA", "OPD", "Raw"}) {
    const auto it = blocks.find(key);
    if (it != blocks.end() && it->second.type == kArray) return &it->second;
  }
  return nullptr;
}

// The height array's size and element width, checked against its block.
struct OpdArray {
  std::int64_t nx = 0, ny = 0;
  int element_size = 0;
};

OpdArray CheckArray(const ByteReader& in,
                    const Block& data,
                    const std::string& name) {
  OpdArray a;
  a.nx = in.At<std::uint16_t>(data.offset, "array width");
  a.ny = in.At<std::uint16_t>(data.offset + 2, "array height");
  a.element_size = in.At<std::uint16_t>(data.offset + 4, "element size");
  internal::CheckMapSize(in, data.offset, a.nx, a.ny);
  if (a.element_size != 1 && a.element_size != 2 && a.element_size != 4) {
    throw ScanError(
        fmt::format("{}: byte {}: elements of {} bytes; expected 1, 2 or 4",
                    name,
                    data.offset + 4,
                    a.element_size));
  }
  const std::uint64_t n = static_cast<std::uint64_t>(a.nx * a.ny);
  if (6 + n * a.element_size != data.length) {
    throw ScanError(fmt::format(
        "{}: byte {}: an array of {} x {} x {} bytes in a block of {} "
        "bytes; expected 6 more than the array",
        name,
        data.offset,
        a.nx,
        a.ny,
        a.element_size,
        data.length));
  }
  in.Need(data.offset + 6, n * a.element_size, "the height array");
  return a;
}

// The heights' scale (mm per stored unit) and the pixel size.
struct OpdScale {
  double height_mm = 0, dx_mm = 0, dy_mm = 0;
};

OpdScale ReadScale(const ByteReader& in,
                   const std::map<std::string, Block>& blocks,
                   const std::string& name) {
  const double wavelength_nm = Scalar(in, blocks, "Wavelength", 0.0);
  const double mult = Scalar(in, blocks, "Mult", 1.0);
  const double aspect = Scalar(in, blocks, "Aspect", 1.0);
  const double pixel_mm = Scalar(in, blocks, "Pixel_size", 0.0);
  if (!(wavelength_nm > 0 && mult > 0 && aspect > 0 && pixel_mm > 0 &&
        std::isfinite(wavelength_nm * aspect * pixel_mm))) {
    throw ScanError(
        fmt::format("{}: Wavelength {:.6g} nm, Mult {:.6g}, Aspect {:.6g}, "
                    "Pixel_size {:.6g} mm; expected positive values in the "
                    "blocks of those names",
                    name,
                    wavelength_nm,
                    mult,
                    aspect,
                    pixel_mm));
  }
  return {1e-6 * wavelength_nm / mult, pixel_mm, pixel_mm * aspect};
}

// Column by column (x slow); the first stored row is the bottom of the
// image as the instrument shows it. Invalid values are NaN.
void FillHeights(const char* p,
                 const OpdArray& a,
                 double scale_mm,
                 HeightMap* map) {
  for (std::int64_t x = 0; x < a.nx; ++x) {
    for (std::int64_t y = 0; y < a.ny; ++y) {
      const std::int64_t i = x * a.ny + y;
      double v = std::numeric_limits<double>::quiet_NaN();
      if (a.element_size == 1) {
        v = static_cast<unsigned char>(p[i]);
      } else if (a.element_size == 2) {
        std::int16_t s;
        std::memcpy(&s, p + 2 * i, 2);
        if (s < 32766) v = s;
      } else {
        float f;
        std::memcpy(&f, p + 4 * i, 4);
        if (std::isfinite(f) && f < 1e38f) v = f;
      }
      map->height_mm(a.ny - 1 - y, x) = static_cast<float>(scale_mm * v);
    }
  }
}

HeightMap ParseOpd(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions&) {
  ByteReader in(bytes, name);
  const std::map<std::string, Block> blocks = ReadDirectory(in);
  const Block* data = HeightBlock(in, blocks);
  if (data == nullptr) {
    throw ScanError(fmt::format(
        "{}: byte 2: the directory names no height array (RAW_DATA, OPD or "
        "Raw); expected one",
        name));
  }
  const OpdArray array = CheckArray(in, *data, name);
  const OpdScale scale = ReadScale(in, blocks, name);
  HeightMap map;
  map.Resize(array.ny, array.nx);
  FillHeights(in.Data(data->offset + 6), array, scale.height_mm, &map);
  SyncValidity(&map);
  map.dx_mm = scale.dx_mm;
  map.dy_mm = scale.dy_mm;
  map.metadata.format = "opd";
  map.metadata.instrument = "Bruker/Veeco Vision (Wyko)";
  auto text = [&](const char* key) {
    const auto it = blocks.find(key);
    return it != blocks.end() && it->second.type == 5
               ? in.Text(it->second.offset, it->second.length, key)
               : std::string();
  };
  map.metadata.date = text("Date");
  const std::string time = text("Time");
  if (!time.empty())
    map.metadata.date += (map.metadata.date.empty() ? "" : " ") + time;
  return map;
}

}  // namespace

namespace internal {
ScanFormat WykoOpdFormat() {
  return {"opd",
          "Bruker/Veeco Vision .opd",
          "Bruker/Veeco Wyko NT, ContourGT (white-light interferometry)",
          {".opd"},
          {std::string("\x01\x00Directory", 11)},
          [](std::string_view head, std::string_view) {
            return head.size() >= 11 && head.substr(2, 9) == "Directory"
                       ? kDetectMagic
                       : 0;
          },
          &ParseOpd};
}
}  // namespace internal

}  // namespace wearscar::scan
