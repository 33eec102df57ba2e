// Keyence readers: VK-X (.vk4, .vk6, .vk7) and VR (.zon, .zag). Layouts in
// FORMATS.md (after Gwyddion keyence.c, SurfaceTopography ZON.py / VK.py).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <pugixml.hpp>

#include "byte_reader.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/read_scan.h"
#include "zip_archive.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr char kZonHeights[] = "4cdb0c75-5706-48cc-a9a1-adf395d609ae";
constexpr char kZonMask[] = "9e7ca6dd-0e6a-4d7b-8986-f0a7b773c916";
constexpr char kZonCalibration[] = "686613b8-27b5-4a29-8ffc-438c2780873e";
constexpr char kZonDevice[] = "cbc1d39b-215f-4d56-a20e-cf8e5f570755";
constexpr char kZonScan[] = "1d35862b-3b48-4df2-9235-833ef590b043";
// A ZAG's measurements are the members */<kZagPayload>; its inventory
// member (f1724dc6-686c-4502-9227-2a594bc8ed33) is not needed to find them.
constexpr char kZagPayload[] = "84b648d7-e44f-4909-ac11-0476720a67ff";

// VK4 offset table entries (absolute offsets; 0 = absent).
enum Vk4Entry { kMeasurementConditions = 0, kHeight0 = 6 };

}  // namespace

// Offsets within the VK4 measurement-conditions block.
constexpr std::uint64_t kConditionsXPitch = 168;
constexpr std::uint64_t kConditionsYPitch = 172;
constexpr std::uint64_t kConditionsZStep = 176;

namespace {

// The VK4 height image's header: size and bit depth, checked against its
// byte size.
struct Vk4Image {
  std::uint32_t width = 0, height = 0, bits = 0;
  std::uint64_t bytes = 0;
};

Vk4Image CheckVk4Image(const ByteReader& in,
                       std::uint64_t at,
                       const std::string& name) {
  Vk4Image im;
  im.width = in.At<std::uint32_t>(at, "height image width");
  im.height = in.At<std::uint32_t>(at + 4, "height image height");
  im.bits = in.At<std::uint32_t>(at + 8, "bit depth");
  const auto size = in.At<std::uint32_t>(at + 16, "byte size");
  if (im.width == 0 || im.height == 0 ||
      static_cast<std::int64_t>(im.width) * im.height > kMaxPixels) {
    throw ScanError(fmt::format(
        "{}: byte {}: height image {} x {}; expected 1 to {} pixels",
        name,
        at,
        im.width,
        im.height,
        kMaxPixels));
  }
  if (im.bits != 8 && im.bits != 16 && im.bits != 32) {
    throw ScanError(
        fmt::format("{}: byte {}: bit depth {}; expected 8, 16 or 32",
                    name,
                    at + 8,
                    im.bits));
  }
  im.bytes = std::uint64_t{im.width} * im.height * (im.bits / 8);
  if (size != im.bytes) {
    throw ScanError(fmt::format(
        "{}: byte {}: byte size {} disagrees with {} x {} x {} bits = {}",
        name,
        at + 16,
        size,
        im.width,
        im.height,
        im.bits,
        im.bytes));
  }
  return im;
}

// Pitches and z step in picometres within the conditions block.
std::array<double, 3> Vk4Calibration(const ByteReader& in,
                                     std::uint64_t conditions,
                                     const std::string& name) {
  const double x_pm = in.At<std::uint32_t>(conditions + kConditionsXPitch,
                                           "x length per pixel");
  const double y_pm = in.At<std::uint32_t>(conditions + kConditionsYPitch,
                                           "y length per pixel");
  const double z_pm =
      in.At<std::uint32_t>(conditions + kConditionsZStep, "z length per digit");
  if (!(x_pm > 0) || !(y_pm > 0) || !(z_pm > 0)) {
    throw ScanError(fmt::format(
        "{}: byte {}: calibration x {} pm, y {} pm, z {} pm per digit; "
        "expected positive values",
        name,
        conditions + kConditionsXPitch,
        x_pm,
        y_pm,
        z_pm));
  }
  return {x_pm, y_pm, z_pm};
}

}  // namespace

HeightMap ParseVk4(const std::string& bytes, const std::string& name) {
  ByteReader in(bytes, name);
  in.Need(0, 12 + 18 * 4, "the VK4 header and offset table");
  const std::string magic = bytes.substr(0, 4);
  if (magic != "VK4_" && magic != "VK3_") {
    throw ScanError(fmt::format(
        "{}: byte 0: found magic '{}', expected 'VK4_'", name, magic));
  }
  // Offsets are uint32 in the file; every sum below is 64-bit (a block near
  // 4 GiB must not wrap to a small offset).
  const std::uint64_t conditions =
      in.At<std::uint32_t>(12 + 4 * kMeasurementConditions, "offset table");
  const std::uint64_t height =
      in.At<std::uint32_t>(12 + 4 * kHeight0, "offset table");
  if (conditions == 0 || height == 0) {
    throw ScanError(
        fmt::format("{}: byte 12: the offset table has no {} block",
                    name,
                    conditions == 0 ? "measurement-conditions" : "height"));
  }
  const auto [x_pm, y_pm, z_pm] = Vk4Calibration(in, conditions, name);
  const Vk4Image im = CheckVk4Image(in, height, name);
  constexpr std::uint64_t kImageHeader = 796;
  in.Need(height + kImageHeader, im.bytes, "the height pixels");
  HeightMap map;
  map.Resize(im.height, im.width);
  const char* p = in.Data(height + kImageHeader);
  const double to_mm = z_pm * 1e-9;
  for (std::uint64_t i = 0; i < std::uint64_t{im.width} * im.height; ++i) {
    std::uint32_t raw = 0;
    std::memcpy(&raw, p + i * (im.bits / 8), im.bits / 8);
    map.height_mm.data()[i] = static_cast<float>(raw * to_mm);
  }
  map.dx_mm = x_pm * 1e-9;
  map.dy_mm = y_pm * 1e-9;
  SyncValidity(&map);
  map.metadata.source = name;
  map.metadata.format = "vk4";
  map.metadata.instrument = "Keyence VK-X";
  return map;
}

HeightMap ParseVk67(const std::string& bytes,
                    const std::string& name,
                    const ReadScanOptions& options) {
  ByteReader in(bytes, name);
  in.Need(0, 7, "the VK6/VK7 header");
  const std::string magic = bytes.substr(0, 3);
  if (magic != "VK6" && magic != "VK7") {
    throw ScanError(fmt::format(
        "{}: byte 0: found magic '{}', expected 'VK6' or 'VK7'", name, magic));
  }
  const auto bmp = in.At<std::uint32_t>(3, "BMP size");
  const std::uint64_t zip_at = 7 + std::uint64_t{bmp};
  in.Need(zip_at, 4, "the ZIP archive after the thumbnail");
  internal::ZipArchive zip(bytes.substr(zip_at),
                           fmt::format("{} (ZIP at byte {})", name, zip_at),
                           options);
  if (!zip.Has("Vk4File")) {
    throw ScanError(
        fmt::format("{}: the archive has no member 'Vk4File'", name));
  }
  HeightMap map = ParseVk4(zip.Read("Vk4File"), name + ":Vk4File");
  map.metadata.source = name;
  map.metadata.format = magic == "VK6" ? "vk6" : "vk7";
  return map;
}

namespace {

constexpr std::uint64_t kNoCap = std::numeric_limits<std::uint64_t>::max();
constexpr std::uint64_t kXmlCap = std::uint64_t{16} << 20;

// A member of a ZON archive; KPK1 members are zstd frames.
std::string ReadZonMember(const internal::ZipArchive& zip,
                          const std::string& member,
                          bool zstd,
                          std::uint64_t cap = kNoCap) {
  std::string raw = zip.Read(member, cap);
  if (!zstd) return raw;
  return internal::ZstdDecompress(
      raw,
      &zip.budget(),
      cap,
      fmt::format("{}: member '{}' (zstd)", zip.name(), member));
}

struct GridHeader {
  std::int32_t width, height, element, stride;
};

GridHeader ReadGridHeader(const std::string& data,
                          const std::string& where,
                          int element_size) {
  ByteReader in(data, where);
  GridHeader g{in.At<std::int32_t>(0, "width"),
               in.At<std::int32_t>(4, "height"),
               in.At<std::int32_t>(8, "element size"),
               in.At<std::int32_t>(12, "bytes per row")};
  if (g.width <= 0 || g.height <= 0 ||
      static_cast<std::int64_t>(g.width) * g.height > kMaxPixels) {
    throw ScanError(fmt::format("{}: byte 0: {} x {} pixels; expected 1 to {}",
                                where,
                                g.width,
                                g.height,
                                kMaxPixels));
  }
  if (g.element != element_size || g.stride < g.width * element_size) {
    throw ScanError(fmt::format(
        "{}: byte 8: element size {} and row stride {}; expected {} and "
        "at least {}",
        where,
        g.element,
        g.stride,
        element_size,
        g.width * element_size));
  }
  in.Need(16,
          static_cast<std::uint64_t>(g.stride) * (g.height - 1) +
              static_cast<std::uint64_t>(g.width) * element_size,
          "the pixel rows");
  return g;
}

double XmlNumber(const pugi::xml_document& doc, const char* path) {
  const pugi::xpath_node n = doc.select_node(path);
  if (!n) return std::nan("");
  return std::strtod(n.node().child_value(), nullptr);
}

// The calibration member's pixel size and height unit, in metres.
std::pair<double, double> ZonCalibration(const internal::ZipArchive& zip,
                                         bool zstd,
                                         const std::string& name,
                                         const std::string& prefix) {
  const std::string member = prefix + kZonCalibration;
  if (!zip.Has(member)) {
    throw ScanError(
        fmt::format("{}: member '{}' (calibration XML) is missing; the pixel "
                    "size and height scale cannot be known",
                    name,
                    member));
  }
  pugi::xml_document calib;
  const std::string xml = ReadZonMember(zip, member, zstd, kXmlCap);
  if (!calib.load_buffer(xml.data(), xml.size()))
    throw ScanError(fmt::format("{}: member '{}' is not XML", name, member));
  const double m_per_px = XmlNumber(calib, "//XYCalibration/MeterPerPixel");
  const double m_per_unit = XmlNumber(calib, "//ZCalibration/MeterPerUnit");
  if (!(m_per_px > 0) || !(m_per_unit > 0)) {
    throw ScanError(
        fmt::format("{}: member '{}': XYCalibration/MeterPerPixel = {} and "
                    "ZCalibration/MeterPerUnit = {}; expected positive numbers",
                    name,
                    member,
                    m_per_px,
                    m_per_unit));
  }
  return {m_per_px, m_per_unit};
}

// The mask member's invalid pixels (bits 0-1 set) as NaN; a warning when
// the archive has none.
void ApplyZonMask(const internal::ZipArchive& zip,
                  bool zstd,
                  const std::string& name,
                  const std::string& prefix,
                  const GridHeader& g,
                  HeightMap* map) {
  const std::string member = prefix + kZonMask;
  if (!zip.Has(member)) {
    map->metadata.warnings.push_back(
        "no validity mask member; every pixel taken as valid");
    return;
  }
  const std::string mask = ReadZonMember(zip, member, zstd);
  const GridHeader mg =
      ReadGridHeader(mask, fmt::format("{}: member '{}'", name, member), 1);
  if (mg.width != g.width || mg.height != g.height) {
    throw ScanError(fmt::format("{}: mask is {} x {} but heights are {} x {}",
                                name,
                                mg.width,
                                mg.height,
                                g.width,
                                g.height));
  }
  for (int r = 0; r < g.height; ++r) {
    const char* row =
        mask.data() + 16 + static_cast<std::uint64_t>(r) * mg.stride;
    for (int c = 0; c < g.width; ++c) {
      if (static_cast<unsigned char>(row[c]) & 0x03) map->height_mm(r, c) = NAN;
    }
  }
}

HeightMap ZonFromArchive(const internal::ZipArchive& zip,
                         bool zstd,
                         const std::string& name,
                         const std::string& prefix) {
  const std::string heights_member = prefix + kZonHeights;
  if (!zip.Has(heights_member)) {
    throw ScanError(fmt::format(
        "{}: member '{}' (heights) is missing", name, heights_member));
  }
  const auto [m_per_px, m_per_unit] = ZonCalibration(zip, zstd, name, prefix);
  const std::string data = ReadZonMember(zip, heights_member, zstd);
  const GridHeader g = ReadGridHeader(
      data, fmt::format("{}: member '{}'", name, heights_member), 4);
  HeightMap map;
  map.Resize(g.height, g.width);
  const float scale = static_cast<float>(m_per_unit * 1e3);
  for (int r = 0; r < g.height; ++r) {
    const char* row =
        data.data() + 16 + static_cast<std::uint64_t>(r) * g.stride;
    for (int c = 0; c < g.width; ++c) {
      std::int32_t v;
      std::memcpy(&v, row + 4 * c, 4);
      map.height_mm(r, c) = static_cast<float>(v) * scale;
    }
  }
  ApplyZonMask(zip, zstd, name, prefix, g, &map);
  map.dx_mm = map.dy_mm = m_per_px * 1e3;
  SyncValidity(&map);
  map.metadata.source = name;
  auto text_of = [&](const char* member, const char* path) -> std::string {
    if (!zip.Has(prefix + member)) return "";
    pugi::xml_document d;
    const std::string x = ReadZonMember(zip, prefix + member, zstd, kXmlCap);
    if (!d.load_buffer(x.data(), x.size())) return "";
    const pugi::xpath_node n = d.select_node(path);
    return n ? n.node().child_value() : "";
  };
  map.metadata.instrument = text_of(kZonDevice, "//DeviceModelName");
  map.metadata.date = text_of(kZonScan, "//ScanDateTime");
  return map;
}

// KPK0/KPK1 wrapper: magic, BMP size, BMP, (a few bytes,) then the ZIP.
constexpr std::uint64_t kKpkBmpSizeOffset = 4;
constexpr std::uint64_t kKpkBmpOffset = 8;
constexpr std::uint64_t kKpkMaxGap = 4096;
std::string ZipOfKpk(const std::string& bytes,
                     const std::string& name,
                     bool* zstd) {
  ByteReader in(bytes, name);
  in.Need(0, 8, "the KPK header");
  const std::string magic = bytes.substr(0, 4);
  if (magic != "KPK0" && magic != "KPK1") {
    throw ScanError(
        fmt::format("{}: byte 0: found magic '{}', expected 'KPK0' or 'KPK1'",
                    name,
                    magic));
  }
  *zstd = magic == "KPK1";
  const auto bmp = in.At<std::uint32_t>(kKpkBmpSizeOffset, "BMP size");
  const std::uint64_t after_bmp = kKpkBmpOffset + std::uint64_t{bmp};
  in.Need(after_bmp, 4, "the ZIP archive after the thumbnail");
  // Real files put a few bytes between the BMP and the ZIP (a VR-6100 file:
  // two uint32, 4 and 2): the ZIP starts at the first local-file header
  // after the BMP, within a short distance of it.
  static const std::string kLocalHeader("PK\x03\x04", 4);
  const std::size_t zip_at = bytes.find(kLocalHeader, after_bmp);
  if (zip_at == std::string::npos || zip_at - after_bmp > kKpkMaxGap) {
    throw ScanError(fmt::format(
        "{}: byte {}: no ZIP local-file header (PK\\3\\4) within {} bytes "
        "after the {}-byte thumbnail; expected the ZIP container",
        name,
        after_bmp,
        kKpkMaxGap,
        bmp));
  }
  return bytes.substr(zip_at);
}

}  // namespace

HeightMap ParseZon(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options) {
  bool zstd = false;
  internal::ZipArchive zip(ZipOfKpk(bytes, name, &zstd), name, options);
  HeightMap map = ZonFromArchive(zip, zstd, name, "");
  map.metadata.format = zstd ? "zon (KPK1)" : "zon (KPK0)";
  return map;
}

std::vector<std::string> ListZagMeasurements(const std::string& bytes,
                                             const std::string& name) {
  bool zstd = false;
  const ReadScanOptions defaults;  // only names are read
  internal::ZipArchive zip(ZipOfKpk(bytes, name, &zstd), name, defaults);
  std::vector<std::string> items;
  const std::string suffix = std::string("/") + kZagPayload;
  for (const std::string& m : zip.Members()) {
    if (m.size() > suffix.size() &&
        m.compare(m.size() - suffix.size(), suffix.size(), suffix) == 0) {
      items.push_back(m.substr(0, m.size() - suffix.size()));
    }
  }
  std::sort(items.begin(), items.end());
  return items;
}

HeightMap ParseZag(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options) {
  const std::vector<std::string> items = ListZagMeasurements(bytes, name);
  if (items.empty()) {
    throw ScanError(fmt::format(
        "{}: no measurement payload '*/{}' in the archive", name, kZagPayload));
  }
  if (options.measurement_index < 0 ||
      options.measurement_index >= static_cast<int>(items.size())) {
    throw ScanError(
        fmt::format("{}: measurement {} requested; the file holds {} (0-{})",
                    name,
                    options.measurement_index,
                    items.size(),
                    items.size() - 1));
  }
  bool zstd = false;
  internal::ZipArchive zip(ZipOfKpk(bytes, name, &zstd), name, options);
  const std::string member =
      items[options.measurement_index] + "/" + kZagPayload;
  std::string payload = zip.Read(member);
  const std::string item_name =
      fmt::format("{}:{}", name, items[options.measurement_index]);
  HeightMap map = ParseZon(payload, item_name, options);
  map.metadata.format = "zag";
  return map;
}

namespace internal {
namespace {
bool IsKpk(std::string_view head) {
  return head.rfind("KPK0", 0) == 0 || head.rfind("KPK1", 0) == 0;
}
}  // namespace

ScanFormat KeyenceZagFormat() {
  return {"zag",
          "Keyence VR .zag",
          "Keyence VR-3000/5000/6000 (several measurements)",
          {".zag"},
          {"KPK0", "KPK1"},
          [](std::string_view head, std::string_view ext) {
            return IsKpk(head) && ext == ".zag" ? kDetectMagic + 1 : 0;
          },
          &ParseZag};
}

ScanFormat KeyenceZonFormat() {
  return {"zon",
          "Keyence VR .zon",
          "Keyence VR-3000/5000/6000",
          {".zon"},
          {"KPK0", "KPK1"},
          [](std::string_view head, std::string_view) {
            return IsKpk(head) ? kDetectMagic : 0;
          },
          &ParseZon};
}

ScanFormat KeyenceVk4Format() {
  return {"vk4",
          "Keyence VK-X .vk4",
          "Keyence VK-X100/200/1000 laser confocal",
          {".vk4"},
          {"VK4_", "VK3_"},
          [](std::string_view head, std::string_view) {
            return head.rfind("VK4_", 0) == 0 || head.rfind("VK3_", 0) == 0
                       ? kDetectMagic
                       : 0;
          },
          [](const std::string& bytes,
             const std::string& name,
             const ReadScanOptions&) { return ParseVk4(bytes, name); }};
}

ScanFormat KeyenceVk67Format() {
  return {"vk67",
          "Keyence VK-X .vk6/.vk7",
          "Keyence VK-X3000, VK-X1000 (newer software)",
          {".vk6", ".vk7"},
          {"VK6", "VK7"},
          [](std::string_view head, std::string_view) {
            return head.rfind("VK6", 0) == 0 || head.rfind("VK7", 0) == 0
                       ? kDetectMagic
                       : 0;
          },
          &ParseVk67};
}
}  // namespace internal

}  // namespace wearscar::scan
