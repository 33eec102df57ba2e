// Digital Surf .sur (Mountains; written by many profilometers and
// microscopes). Layout (not in FORMATS.md) after Gwyddion's surffile.c,
// SurfaceTopography's SUR.py and surfalize's sur.py: a 512-byte
// little-endian header, a comment and a private zone, then int16 or int32
// points, x fastest; "DSCOMPRESSED" files hold the points as zlib streams
// behind a small directory.
#include <fmt/format.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "byte_reader.h"
#include "inflate.h"
#include "wearscar/scan/formats.h"

namespace wearscar::scan {
namespace {

using internal::ByteReader;

constexpr std::uint64_t kHeaderSize = 512;
constexpr std::uint64_t kByteOrder = 12;      // int16: 0 = PC, 257 = Mac
constexpr std::uint64_t kObjects = 14;        // uint16
constexpr std::uint64_t kType = 18;           // int16: 2 = surface
constexpr std::uint64_t kOperator = 50;       // char[30]
constexpr std::uint64_t kNonMeasured = 86;    // int16: 1 = zmin - 2 marks them
constexpr std::uint64_t kBits = 98;           // int16: 16 or 32
constexpr std::uint64_t kZMin = 100;          // int32
constexpr std::uint64_t kColumns = 108;       // int32
constexpr std::uint64_t kRows = 112;          // int32
constexpr std::uint64_t kPoints = 116;        // int32
constexpr std::uint64_t kSpacing = 120;       // float x, y, z
constexpr std::uint64_t kSpacingUnits = 180;  // char[16] x, y, z
constexpr std::uint64_t kInversion = 290;     // int16
constexpr std::uint64_t kDate = 306;  // int16 s, min, h, day, month, year
constexpr std::uint64_t kCompressedSize = 324;  // uint32
constexpr std::uint64_t kCommentSize = 334;     // uint16 comment, private
constexpr std::uint64_t kZOffset = 474;         // float
constexpr std::uint64_t kMaxStreams = 1024;

// Millimetres per unit of a spacing unit ("nm", "um", "µm" in Latin-1 or
// UTF-8, "mm", "m"), or 0 when unknown.
double MmPerUnit(const std::string& unit) {
  if (unit == "m") return 1e3;
  if (unit == "mm") return 1.0;
  if (unit == "um" || unit == "\xb5m" || unit == "\xc2\xb5m") return 1e-3;
  if (unit == "nm") return 1e-6;
  if (unit == "pm") return 1e-9;
  if (unit == "A" || unit == "\xc5") return 1e-7;
  return 0.0;
}

// The points of a "DSCOMPRESSED" file: a uint32 count of streams, each
// stream's raw and zipped length, then the zlib streams, whose raw lengths
// must add up to the map's `expected` bytes before anything is inflated.
std::string InflatePoints(const ByteReader& in,
                          std::uint64_t at,
                          std::uint64_t expected,
                          const ReadScanOptions& options) {
  const auto streams = in.At<std::uint32_t>(at, "the stream count");
  if (streams == 0 || streams > kMaxStreams) {
    throw ScanError(
        fmt::format("{}: byte {}: {} compressed streams; expected "
                    "1 to {}",
                    in.name(),
                    at,
                    streams,
                    kMaxStreams));
  }
  in.Need(at + 4, 8 * std::uint64_t{streams}, "the stream directory");
  // Every stated length is checked (present in the file, within the
  // decompression limits) before anything is allocated or inflated.
  internal::InflateBudget budget(options);
  std::uint64_t raw_total = 0;
  std::uint64_t offset = at + 4 + 8 * std::uint64_t{streams};
  for (std::uint32_t i = 0; i < streams; ++i) {
    const std::uint64_t raw = in.At<std::uint32_t>(at + 4 + 8 * i, "raw");
    const std::uint64_t zipped = in.At<std::uint32_t>(at + 8 + 8 * i, "zip");
    in.Need(offset, zipped, "a compressed stream");
    budget.Check(zipped,
                 raw,
                 expected,
                 fmt::format("{}: byte {}: stream {}", in.name(), offset, i));
    budget.Spend(raw);
    raw_total += raw;
    offset += zipped;
  }
  if (raw_total != expected) {
    throw ScanError(fmt::format(
        "{}: byte {}: the streams hold {} bytes; the header's map needs {}",
        in.name(),
        at + 4,
        raw_total,
        expected));
  }
  std::string out(expected, '\0');
  std::uint64_t written = 0;
  offset = at + 4 + 8 * std::uint64_t{streams};
  for (std::uint32_t i = 0; i < streams; ++i) {
    const std::uint64_t raw = in.At<std::uint32_t>(at + 4 + 8 * i, "raw");
    const std::uint64_t zipped = in.At<std::uint32_t>(at + 8 + 8 * i, "zip");
    const std::string where =
        fmt::format("{}: byte {}: stream {}", in.name(), offset, i);
    uLongf got = static_cast<uLongf>(raw);
    const int rc = uncompress(reinterpret_cast<Bytef*>(out.data() + written),
                              &got,
                              reinterpret_cast<const Bytef*>(in.Data(offset)),
                              static_cast<uLong>(zipped));
    if (rc != Z_OK || got != raw) {
      throw ScanError(fmt::format("{}: inflates to {} bytes ({}); expected {}",
                                  where,
                                  rc == Z_OK ? got : 0,
                                  rc == Z_BUF_ERROR
                                      ? "more than stated, or cut short"
                                  : rc == Z_DATA_ERROR ? "not a zlib stream"
                                                       : "zlib error",
                                  raw));
    }
    written += raw;
    offset += zipped;
  }
  return out;
}

void CheckObject(const ByteReader& in, std::int64_t type, std::int64_t rows) {
  const std::string name = in.name();
  const auto order = in.At<std::int16_t>(kByteOrder, "byte order");
  if (order != 0) {
    throw ScanError(
        fmt::format("{}: byte {}: byte order {} (Macintosh); expected 0 (PC)",
                    name,
                    kByteOrder,
                    order));
  }
  // 2 surface, 11 intensity surface, 16 RGB intensity surface (the surface
  // comes first); Gwyddion writes its exports as 1, a "profile" of rows.
  if (!(type == 2 || type == 11 || type == 16 || (type == 1 && rows > 1))) {
    throw ScanError(fmt::format(
        "{}: byte {}: object type {}{}; expected a surface (2, 11 or 16)",
        name,
        kType,
        type,
        type == 1 ? " (a profile)" : ""));
  }
}

// What the header says of the points.
struct Header {
  bool compressed = false;
  std::int64_t cols = 0, rows = 0;
  int bits = 0;
  double mm_per[3] = {0, 0, 0};  // x, y, z spacing units
  double spacing[3] = {0, 0, 0};
  std::uint64_t data = 0;  // first byte after the comment and private zone
};

Header ReadHeader(const ByteReader& in) {
  const std::string& name = in.name();
  in.Need(0, kHeaderSize, "the 512-byte header");
  Header h;
  const std::string magic = in.Text(0, 12, "magic");
  h.compressed = magic == "DSCOMPRESSED";
  if (!h.compressed && magic != "DIGITAL SURF") {
    throw ScanError(fmt::format(
        "{}: byte 0: found '{}'; expected 'DIGITAL SURF' or 'DSCOMPRESSED'",
        name,
        internal::Printable(magic)));
  }
  h.cols = in.At<std::int32_t>(kColumns, "points per line");
  h.rows = in.At<std::int32_t>(kRows, "lines");
  CheckObject(in, in.At<std::int16_t>(kType, "object type"), h.rows);
  internal::CheckMapSize(in, kColumns, h.cols, h.rows);
  const std::int64_t points = in.At<std::int32_t>(kPoints, "point count");
  if (points != h.cols * h.rows) {
    throw ScanError(
        fmt::format("{}: byte {}: {} points in a map of {} x {}; expected {}",
                    name,
                    kPoints,
                    points,
                    h.cols,
                    h.rows,
                    h.cols * h.rows));
  }
  h.bits = in.At<std::int16_t>(kBits, "bits per point");
  if (h.bits != 16 && h.bits != 32) {
    throw ScanError(
        fmt::format("{}: byte {}: {} bits per point; expected 16 or 32",
                    name,
                    kBits,
                    h.bits));
  }
  for (int a = 0; a < 3; ++a) {
    const std::string unit =
        in.Text(kSpacingUnits + 16 * a, 16, "spacing unit");
    h.spacing[a] = in.At<float>(kSpacing + 4 * a, "spacing");
    h.mm_per[a] = MmPerUnit(unit);
    if (h.mm_per[a] == 0 || !std::isfinite(h.spacing[a]) ||
        (a < 2 && !(h.spacing[a] > 0))) {
      throw ScanError(fmt::format(
          "{}: byte {}: {} spacing {} '{}'; expected a positive number in m, "
          "mm, um or nm",
          name,
          kSpacing + 4 * a,
          "xyz"[a],
          h.spacing[a],
          internal::Printable(unit)));
    }
  }
  h.data = kHeaderSize + in.At<std::uint16_t>(kCommentSize, "comment size") +
           in.At<std::uint16_t>(kCommentSize + 2, "private size");
  return h;
}

// The points in mm, NaN where the file marks them as not measured, with
// the file's inversion applied.
HeightMap::Heights Heights(const ByteReader& in,
                           const Header& h,
                           const ReadScanOptions& options) {
  const std::uint64_t n = static_cast<std::uint64_t>(h.cols * h.rows);
  const std::uint64_t expected = n * static_cast<std::uint64_t>(h.bits / 8);
  std::string inflated;
  const char* p = nullptr;
  if (h.compressed) {
    const auto stated = in.At<std::uint32_t>(kCompressedSize, "data size");
    in.Need(h.data, stated, "the compressed points");
    inflated = InflatePoints(in, h.data, expected, options);
    p = inflated.data();
  } else {
    in.Need(h.data, expected, "the points");
    p = in.Data(h.data);
  }
  const bool marked = in.At<std::int16_t>(kNonMeasured, "non-measured") == 1;
  const std::int64_t invalid =
      std::int64_t{in.At<std::int32_t>(kZMin, "zmin")} - 2;
  const double z_mm = h.spacing[2] * h.mm_per[2];
  const double z0_mm = in.At<float>(kZOffset, "z offset") * h.mm_per[2];
  HeightMap::Heights z(h.rows, h.cols);
  for (std::uint64_t i = 0; i < n; ++i) {
    std::int64_t raw;
    if (h.bits == 16) {
      std::int16_t s;
      std::memcpy(&s, p + 2 * i, 2);
      raw = s;
    } else {
      std::int32_t s;
      std::memcpy(&s, p + 4 * i, 4);
      raw = s;
    }
    z.data()[i] =
        marked && raw == invalid
            ? std::numeric_limits<float>::quiet_NaN()
            : static_cast<float>(z_mm * static_cast<double>(raw) + z0_mm);
  }
  // Inversion: 1 z, 2 z and rows, 3 z and columns (as Gwyddion applies it).
  const auto inversion = in.At<std::int16_t>(kInversion, "inversion");
  if (inversion >= 1 && inversion <= 3) z = -z;
  if (inversion == 2) z = z.colwise().reverse().eval();
  if (inversion == 3) z = z.rowwise().reverse().eval();
  return z;
}

HeightMapMetadata Metadata(const ByteReader& in) {
  HeightMapMetadata m;
  m.format = "sur";
  const std::string who = in.Text(kOperator, 30, "instrument name");
  m.instrument = "Digital Surf" + (who.empty() ? "" : " (" + who + ")");
  std::int16_t d[6];
  for (int k = 0; k < 6; ++k) d[k] = in.At<std::int16_t>(kDate + 2 * k, "date");
  if (d[5] > 0 && d[4] >= 1 && d[4] <= 12 && d[3] >= 1 && d[3] <= 31) {
    m.date = fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02}",
                         d[5],
                         d[4],
                         d[3],
                         d[2],
                         d[1],
                         d[0]);
  }
  const auto objects = in.At<std::uint16_t>(kObjects, "object count");
  if (objects > 1) {
    m.warnings.push_back(fmt::format(
        "the file holds {} objects; the first, a surface, was read", objects));
  }
  return m;
}

HeightMap ParseSur(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options) {
  const ByteReader in(bytes, name);
  const Header h = ReadHeader(in);
  HeightMap map;
  map.height_mm = Heights(in, h, options);
  SyncValidity(&map);
  map.dx_mm = h.spacing[0] * h.mm_per[0];
  map.dy_mm = h.spacing[1] * h.mm_per[1];
  map.metadata = Metadata(in);
  return map;
}

}  // namespace

namespace internal {
ScanFormat DigitalSurfFormat() {
  return {"sur",
          "Digital Surf .sur",
          "Digital Surf Mountains, and the profilometers and microscopes that "
          "export to it",
          {".sur"},
          {"DIGITAL SURF", "DSCOMPRESSED"},
          [](std::string_view head, std::string_view) {
            return head.rfind("DIGITAL SURF", 0) == 0 ||
                           head.rfind("DSCOMPRESSED", 0) == 0
                       ? kDetectMagic
                       : 0;
          },
          &ParseSur};
}
}  // namespace internal

}  // namespace wearscar::scan
