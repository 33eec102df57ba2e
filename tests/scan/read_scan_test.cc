#include "wearscar/scan/read_scan.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zip.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/paths.h"
#include "file_helpers.h"

namespace wearscar::scan {
namespace {

const std::string kShared = WEARSCAR_SHARED_DATA;

#define REQUIRE_SHARED_DATA()                                               \
  if (!std::filesystem::exists(kShared)) {                                  \
    GTEST_SKIP()                                                            \
        << "../shared/data is absent: real instrument files not available"; \
  }

using test_files::Slurp;
using test_files::Spit;

// ---------------------------------------------------------------- real files

TEST(RealFiles, KeyenceVk6ToReferenceValues) {
  REQUIRE_SHARED_DATA();
  const HeightMap m =
      ReadScan(kShared + "/keyence/60um_50E_30-50shots_depthpro.vk6");
  ASSERT_EQ(m.cols(), 1024);
  ASSERT_EQ(m.rows(), 768);
  EXPECT_NEAR(m.dx_mm, 271217e-9, 1e-12);
  EXPECT_NEAR(m.dy_mm, 271217e-9, 1e-12);
  EXPECT_EQ(m.metadata.format, "vk6");
  // Heights in um at (row, col).
  EXPECT_NEAR(m.height_mm(0, 0) * 1e3, 11.479, 5e-4);
  EXPECT_NEAR(m.height_mm(0, 1023) * 1e3, 14.566, 5e-4);
  EXPECT_NEAR(m.height_mm(767, 0) * 1e3, 16.164, 5e-4);
  EXPECT_NEAR(m.height_mm.maxCoeff() * 1e3, 19.315, 5e-4);
  EXPECT_EQ(m.height_mm(202, 540), 0.0f);
  EXPECT_EQ((m.height_mm == 0.0f).count(), 1);
  double sum = 0, sum2 = 0;
  long n = 0;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    const double v = m.height_mm.data()[i] * 1e3;
    if (v == 0) continue;
    sum += v;
    sum2 += v * v;
    ++n;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 14.906, 5e-4);
  EXPECT_NEAR(std::sqrt(sum2 / n - mean * mean), 2.907, 5e-4);
}

TEST(RealFiles, KeyenceVr6100ZonToReferenceValues) {
  // A real KPK1 file: 8 bytes between the BMP and the ZIP, ZIP64, zstd
  // members without a stated size (shared/data/README.md).
  REQUIRE_SHARED_DATA();
  const HeightMap m = ReadScan(kShared + "/keyence/vr6100_test_1.zon");
  ASSERT_EQ(m.cols(), 1024);
  ASSERT_EQ(m.rows(), 769);
  EXPECT_NEAR(m.dx_mm, 2.36311288524538e-05 * 1e3, 1e-12);
  EXPECT_NEAR(m.dy_mm, m.dx_mm, 1e-15);
  EXPECT_EQ(m.metadata.format, "zon (KPK1)");
  EXPECT_EQ(m.metadata.instrument, "VR-6100");
  EXPECT_NE(m.metadata.date.find("12/18/2025 12:47:39"), std::string::npos)
      << m.metadata.date;
  // Raw 29620 x 1e-8 m = 296.20 um at (0, 0).
  EXPECT_NEAR(m.height_mm(0, 0) * 1e3, 296.20, 5e-3);
  EXPECT_EQ(m.valid.size() - m.valid.count(), 2048);
  double lo = 1e9, hi = -1e9, sum = 0;
  long n = 0;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    if (!m.valid.data()[i]) continue;
    const double v = m.height_mm.data()[i] * 1e3;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    sum += v;
    ++n;
  }
  EXPECT_NEAR(lo, -2429.4, 0.05);
  EXPECT_NEAR(hi, 1926.2, 0.05);
  EXPECT_NEAR(sum / n, 529.96, 0.005);
}

TEST(RealFiles, Vk4InsideVk6ReadsAlone) {
  REQUIRE_SHARED_DATA();
  // The VK6 wrapper holds a complete VK4: reading it through the VK4 reader
  // must give the same map.
  const std::string bytes =
      Slurp(kShared + "/keyence/60um_50E_30-50shots_depthpro.vk6");
  std::uint32_t bmp;
  std::memcpy(&bmp, bytes.data() + 3, 4);
  const std::string zip_bytes = bytes.substr(7 + bmp);
  zip_error_t err;
  zip_source_t* src =
      zip_source_buffer_create(zip_bytes.data(), zip_bytes.size(), 0, &err);
  zip_t* z = zip_open_from_source(src, ZIP_RDONLY, &err);
  ASSERT_NE(z, nullptr);
  zip_stat_t st;
  zip_stat(z, "Vk4File", 0, &st);
  std::string vk4(st.size, '\0');
  zip_file_t* f = zip_fopen(z, "Vk4File", 0);
  zip_fread(f, vk4.data(), vk4.size());
  zip_fclose(f);
  zip_discard(z);
  const std::string path = ::testing::TempDir() + "/inner.vk4";
  Spit(path, vk4);
  const HeightMap m = ReadScan(path);
  EXPECT_EQ(m.metadata.format, "vk4");
  EXPECT_NEAR(m.height_mm(0, 1023) * 1e3, 14.566, 5e-4);
}

TEST(RealFiles, X3pInlineDataListWithEmptyDatum) {
  REQUIRE_SHARED_DATA();
  const HeightMap m = ReadScan(kShared + "/x3p/ISO5436-sample1.x3p");
  ASSERT_EQ(m.rows(), 4);
  ASSERT_EQ(m.cols(), 4);
  EXPECT_NEAR(m.dx_mm, 16.016, 1e-9);  // 0.016016 m
  EXPECT_EQ(m.ValidCount(), 15);
  EXPECT_FALSE(m.valid(1, 3));
  EXPECT_NEAR(m.height_mm(0, 0), 486.219120804151, 1e-3);  // 0.4862 m in mm
}

TEST(RealFiles, X3pBinaryFloat64WithValidMask) {
  REQUIRE_SHARED_DATA();
  const HeightMap m = ReadScan(kShared + "/x3p/ISO5436-sample1_bin.x3p");
  EXPECT_EQ(m.ValidCount(), 15);
  float lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    if (!m.valid.data()[i]) continue;
    lo = std::min(lo, m.height_mm.data()[i]);
    hi = std::max(hi, m.height_mm.data()[i]);
  }
  EXPECT_NEAR(lo / 1e3, -0.80837, 1e-5);
  EXPECT_NEAR(hi / 1e3, 1.04760, 1e-5);
}

TEST(RealFiles, X3pInt16WithIncrementAndOffset) {
  REQUIRE_SHARED_DATA();
  const HeightMap m = ReadScan(kShared + "/x3p/ISO5436-sample4_bin.x3p");
  EXPECT_EQ(m.ValidCount(), 15);
  float lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    if (!m.valid.data()[i]) continue;
    lo = std::min(lo, m.height_mm.data()[i]);
    hi = std::max(hi, m.height_mm.data()[i]);
  }
  // height = raw * 0.001 - 0.5 m; raw -308 .. 1548.
  EXPECT_NEAR(lo, (-308 * 0.001 - 0.5) * 1e3, 1e-3);
  EXPECT_NEAR(hi, (1548 * 0.001 - 0.5) * 1e3, 1e-3);
}

TEST(RealFiles, X3pNestedInAFolder) {
  REQUIRE_SHARED_DATA();
  const HeightMap m = ReadScan(kShared + "/x3p/csafe-logo.x3p");
  EXPECT_EQ(m.cols(), 741);
  EXPECT_EQ(m.rows(), 419);
  EXPECT_NEAR(m.dx_mm, 6.45e-4, 1e-12);
  EXPECT_EQ(m.ValidCount(), 741 * 419);
  EXPECT_NEAR(m.height_mm.minCoeff(), 2.078e-4, 1e-7);
  EXPECT_NEAR(m.height_mm.maxCoeff(), 8.275e-4, 1e-7);
}

// ------------------------------------------------ ZON / ZAG built to layout

std::string Zip(const std::map<std::string, std::string>& members) {
  const std::string path = ::testing::TempDir() + "/build.zip";
  std::filesystem::remove(path);
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  std::vector<std::string> keep;
  keep.reserve(members.size());
  for (const auto& [name, data] : members) {
    keep.push_back(data);
    zip_source_t* s =
        zip_source_buffer(z, keep.back().data(), keep.back().size(), 0);
    zip_file_add(z, name.c_str(), s, ZIP_FL_OVERWRITE);
  }
  zip_close(z);
  return Slurp(path);
}

std::string Grid(
    int w, int h, int element, int stride, const std::vector<std::int32_t>& v) {
  std::string out(16 + static_cast<size_t>(stride) * h, '\0');
  const std::int32_t head[4] = {w, h, element, stride};
  std::memcpy(out.data(), head, 16);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::int32_t x = v[r * w + c];
      std::memcpy(out.data() + 16 + r * stride + c * element, &x, element);
    }
  }
  return out;
}

const char kHeights[] = "4cdb0c75-5706-48cc-a9a1-adf395d609ae";
const char kMask[] = "9e7ca6dd-0e6a-4d7b-8986-f0a7b773c916";
const char kCalib[] = "686613b8-27b5-4a29-8ffc-438c2780873e";
const char kDevice[] = "cbc1d39b-215f-4d56-a20e-cf8e5f570755";

std::string Zstd(const std::string& s) {
  std::string out(ZSTD_compressBound(s.size()), '\0');
  out.resize(ZSTD_compress(out.data(), out.size(), s.data(), s.size(), 3));
  return out;
}

// A 3 x 2 ZON: rows padded to 16 bytes, heights raw * 1e-8 m, pixel
// 7.413 um, mask marking (1, 0) not measured and (0, 2) excluded.
std::string Zon(bool kpk1, bool with_calibration = true) {
  std::map<std::string, std::string> m;
  m[kHeights] = Grid(3, 2, 4, 16, {100, 200, 300, -400, 500, 600});
  m[kMask] = Grid(3, 2, 1, 4, {0, 0x10, 0x02, 0x01, 0, 0x04});
  if (with_calibration) {
    m[kCalib] =
        "<Calibration><XYCalibration><MeterPerPixel>7.413e-6</MeterPerPixel></"
        "XYCalibration>"
        "<ZCalibration><MeterPerUnit>1e-8</MeterPerUnit></ZCalibration></"
        "Calibration>";
  }
  m[kDevice] = "<Device><DeviceModelName>VR-6200</DeviceModelName></Device>";
  if (kpk1) {
    for (auto& [k, v] : m) v = Zstd(v);
  }
  const std::string bmp = "BM-thumbnail-bytes";
  std::string out = kpk1 ? "KPK1" : "KPK0";
  const std::uint32_t size = static_cast<std::uint32_t>(bmp.size());
  out.append(reinterpret_cast<const char*>(&size), 4);
  return out + bmp + Zip(m);
}

void ExpectZonValues(const HeightMap& h) {
  ASSERT_EQ(h.cols(), 3);
  ASSERT_EQ(h.rows(), 2);
  EXPECT_NEAR(h.dx_mm, 7.413e-3, 1e-12);
  EXPECT_NEAR(
      h.height_mm(0, 1), 200 * 1e-8 * 1e3, 1e-9);  // quality bit only: valid
  EXPECT_NEAR(h.height_mm(1, 1), 500 * 1e-5, 1e-9);
  EXPECT_FALSE(h.valid(1, 0));
  EXPECT_FALSE(h.valid(0, 2));
  EXPECT_TRUE(h.valid(1, 2));
  EXPECT_EQ(h.ValidCount(), 4);
  EXPECT_EQ(h.metadata.instrument, "VR-6200");
}

TEST(Zon, Kpk0WithPaddedRowsMaskAndCalibration) {
  const std::string path =
      ::testing::TempDir() + "/kpk0-" + std::to_string(getpid()) + ".zon";
  Spit(path, Zon(false));
  const HeightMap h = ReadScan(path);
  ExpectZonValues(h);
  EXPECT_EQ(h.metadata.format, "zon (KPK0)");
}

TEST(Zon, Kpk1ZstdMembers) {
  const std::string path =
      ::testing::TempDir() + "/kpk1-" + std::to_string(getpid()) + ".zon";
  Spit(path, Zon(true));
  ExpectZonValues(ReadScan(path));
}

TEST(Zag, ListsMeasurementsAndPicksOneByIndex) {
  std::map<std::string, std::string> m;
  m["f1724dc6-686c-4502-9227-2a594bc8ed33"] = "<Inventory/>";
  m["item0/data/84b648d7-e44f-4909-ac11-0476720a67ff"] = Zon(false);
  m["item1/data/84b648d7-e44f-4909-ac11-0476720a67ff"] = Zon(true);
  std::string bytes = "KPK0";
  const std::uint32_t zero = 0;
  bytes.append(reinterpret_cast<const char*>(&zero), 4);
  bytes += Zip(m);
  EXPECT_EQ(ListZagMeasurements(bytes, "x.zag"),
            (std::vector<std::string>{"item0/data", "item1/data"}));
  ReadScanOptions o;
  o.measurement_index = 1;
  ExpectZonValues(ParseZag(bytes, "x.zag", o));
  o.measurement_index = 2;
  EXPECT_THROW(ParseZag(bytes, "x.zag", o), ScanError);
}

// ------------------------------------------------------------ text formats

TEST(KeyenceCsv, EnglishHeaderQuotedCellsEmptyInvalidUmUnit) {
  const std::string text =
      "\"Measurement\",\"VR-6200\"\nHorizontal,3\nVertical,2\nXY "
      "Calibration,7.413,um\n"
      "Unit,um\nHeight\n1.5,\"2.5\",\n,4,5\n\n";
  const HeightMap h = ParseKeyenceCsv(text, "k.csv");
  ASSERT_EQ(h.cols(), 3);
  ASSERT_EQ(h.rows(), 2);
  EXPECT_NEAR(h.dx_mm, 7.413e-3, 1e-12);
  EXPECT_NEAR(h.height_mm(0, 1), 2.5e-3, 1e-9);
  EXPECT_FALSE(h.valid(0, 2));
  EXPECT_FALSE(h.valid(1, 0));
  EXPECT_EQ(h.ValidCount(), 4);
}

// A VR CSV cut short: the rows present are read with a warning giving the
// count when they are at least half the map; fewer are refused.
TEST(KeyenceCsv, ACutFileKeepsItsRowsAndSaysHowMany) {
  std::string text =
      "Horizontal,3\nVertical,4\nXY Calibration,7.413,um\nUnit,um\n"
      "Height\n1,2,3\n4,5,6\n7,8,9\n";
  const HeightMap h = ParseKeyenceCsv(text, "cut.csv");
  EXPECT_EQ(h.rows(), 3);
  ASSERT_FALSE(h.metadata.warnings.empty());  // (and the tiny field)
  EXPECT_EQ(h.metadata.warnings[0],
            "the map has 3 of the 4 rows its header declares (Vertical): the "
            "file is cut; the 3 rows present are read");
  text.replace(text.find("Vertical,4"), 10, "Vertical,8");
  try {
    ParseKeyenceCsv(text, "short.csv");
    FAIL() << "3 of 8 rows read";
  } catch (const ScanError& e) {
    EXPECT_EQ(std::string(e.what()),
              "short.csv: 3 height rows after line 5; expected 8 (Vertical)");
  }
  // Cut short with the missing rows written as empty cells: said too.
  const HeightMap empty_tail = ParseKeyenceCsv(
      "Horizontal,3\nVertical,4\nXY Calibration,7.413,um\nUnit,um\n"
      "Height\n1,2,3\n4,5,6\n,,\n,,\n",
      "empty.csv");
  EXPECT_EQ(empty_tail.rows(), 4);
  EXPECT_EQ(empty_tail.ValidCount(), 6);
  ASSERT_FALSE(empty_tail.metadata.warnings.empty());
  EXPECT_EQ(empty_tail.metadata.warnings[0],
            "the last 2 of the 4 rows have no measured point (empty cells): "
            "the export may be cut short; read as not measured");
}

TEST(KeyenceCsv, ShiftJisKeysSemicolonsDecimalComma) {
  // Keys in Japanese (Shift-JIS): the pitch row is found by its um unit and
  // the size by the data block under the Shift-JIS 'Height' (高さ) row.
  const std::string text =
      "\x90\x85\x95\xbd;3\n\x90\x82\x92\xbc;"
      "2\nXY\x83\x4c\x83\x83\x83\x8a\x83\x75;18,53;"
      "\x83\xca"
      "m\n\x8d\x82\x82\xb3\n0,1;0,2;0,3\n0,4;;0,6\n";
  const HeightMap h = ParseKeyenceCsv(text, "jp.csv");
  ASSERT_EQ(h.cols(), 3);
  EXPECT_NEAR(h.dx_mm, 18.53e-3, 1e-12);
  EXPECT_NEAR(h.height_mm(1, 2), 0.6, 1e-7);
  EXPECT_FALSE(h.valid(1, 1));
}

TEST(AsciiMatrix, NeedsPitchAndReadsUnits) {
  const std::string text = "# exported\n1 2 3\n4 nan 6\n7 8 9\n";
  EXPECT_THROW(ParseAsciiMatrix(text, "m.txt", {}), ScanError);
  ReadScanOptions o;
  o.ascii_pitch_mm = 0.005;
  o.ascii_z_unit = "um";
  const HeightMap h = ParseAsciiMatrix(text, "m.txt", o);
  EXPECT_EQ(h.rows(), 3);
  EXPECT_NEAR(h.height_mm(1, 2), 6e-3, 1e-9);
  EXPECT_FALSE(h.valid(1, 1));
}

// --------------------------------------------------- malformed binary input

struct Bad {
  std::string label;
  std::string bytes;
  std::string ext;
  std::string message;
};

std::string Vk4Header(std::uint32_t w,
                      std::uint32_t h,
                      std::uint32_t bits,
                      std::uint32_t size,
                      size_t pixel_bytes) {
  std::string b(12 + 72, '\0');
  std::memcpy(b.data(), "VK4_", 4);
  const std::uint32_t cond = static_cast<std::uint32_t>(b.size());
  std::memcpy(b.data() + 12, &cond, 4);
  std::string c(200, '\0');
  const std::uint32_t pm[3] = {7413000, 7413000, 100};
  std::memcpy(c.data() + 168, pm, 12);
  b += c;
  const std::uint32_t height = static_cast<std::uint32_t>(b.size());
  std::memcpy(b.data() + 12 + 6 * 4, &height, 4);
  std::string img(796, '\0');
  const std::uint32_t hdr[5] = {w, h, bits, 0, size};
  std::memcpy(img.data(), hdr, 20);
  return b + img + std::string(pixel_bytes, '\x01');
}

class ScanBadInput : public ::testing::TestWithParam<Bad> {};

TEST_P(ScanBadInput, ClearErrorNamingFileAndPlace) {
  const Bad& c = GetParam();
  const std::string path = ::testing::TempDir() + "/bad_" + c.label + c.ext;
  Spit(path, c.bytes);
  try {
    ReadScan(path);
    FAIL() << "expected ScanError";
  } catch (const ScanError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(c.message), std::string::npos) << m;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Classes,
    ScanBadInput,
    ::testing::Values(
        Bad{"vk4_wrong_magic",
            "VK9_" + std::string(100, '\0'),
            ".vk4",
            "not the magic of a .vk4"},
        Bad{"vk4_truncated",
            Vk4Header(4, 4, 32, 64, 10),
            ".vk4",
            "truncated: the height pixels"},
        Bad{"vk4_size_mismatch",
            Vk4Header(4, 4, 32, 60, 64),
            ".vk4",
            "byte size 60 disagrees with 4 x 4 x 32 bits = 64"},
        Bad{"vk4_absurd",
            Vk4Header(100000, 100000, 32, 0, 0),
            ".vk4",
            "height image 100000 x 100000; expected 1 to 268435456 pixels"},
        Bad{"vk4_bits", Vk4Header(2, 2, 12, 6, 6), ".vk4", "bit depth 12"},
        Bad{"vk6_short", "VK6\x05", ".vk6", "truncated"},
        Bad{"zon_no_calibration",
            Zon(false, false),
            ".zon",
            "(calibration XML) is missing"},
        Bad{"zon_not_zip",
            std::string("KPK0\0\0\0\0garbage", 15),
            ".zon",
            "byte 8: no ZIP local-file header"},
        Bad{"x3p_not_zip",
            "PK\x03\x04garbage",
            ".x3p",
            "not a readable ZIP archive"},
        Bad{"csv_ragged",
            "XY Calibration,7,um\nHeight\n1,2,3\n4,5\n",
            ".csv",
            "line 4: 2 values; expected 3"},
        Bad{"csv_no_pitch",
            "Horizontal,2\nHeight\n1,2\n",
            ".csv",
            "no 'XY Calibration' row"}),
    [](const ::testing::TestParamInfo<Bad>& param_info) {
      return param_info.param.label;
    });

TEST(ScanBadInput, ZipMemberOverTheLimitIsRefused) {
  ReadScanOptions o;
  o.max_member_bytes = 20;  // the heights member is 48 bytes
  try {
    ParseZon(Zon(false), "big.zon", o);
    FAIL();
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find("the limit is 20 bytes"),
              std::string::npos)
        << e.what();
  }
  try {
    ParseZon(Zon(true), "big1.zon", o);
    FAIL();
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find("limit"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("big1.zon: member"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace wearscar::scan

namespace wearscar::scan {
namespace {

// A Keyence VR CSV header as the instrument writes it (quoted cells, a Z
// calibration row in um after the XY one, a magnification) over nx x 2
// heights.
std::string VrCsv(const std::string& header_rows, int nx) {
  std::string s = "\"Measurement\",\"sample 1\"\n" + header_rows +
                  "\"Horizontal\",\"" + std::to_string(nx) +
                  "\"\n\"Vertical\",\"2\"\n\"Magnification\",\"12\",\"x\"\n"
                  "\"Height\"\n";
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < nx; ++c)
      s += (c ? "," : "") + std::to_string(0.001 * c);
    s += "\n";
  }
  return s;
}

TEST(KeyenceCsv, OnlyTheXyCalibrationRowIsThePixel) {
  // Before: any calibration row in um was taken, the Z one last, and every
  // length came out 74x too small.
  const HeightMap m =
      ParseKeyenceCsv(VrCsv("\"XY Calibration\",\"7.413\",\"um\"\n\"Z "
                            "Calibration\",\"0.1\",\"um\"\n",
                            1024),
                      "vr.csv");
  EXPECT_NEAR(m.dx_mm, 0.007413, 1e-12);
  EXPECT_TRUE(m.metadata.warnings.empty());
  // The same rows the other way round.
  const HeightMap r =
      ParseKeyenceCsv(VrCsv("\"Z Calibration\",\"0.1\",\"um\"\n\"XY "
                            "Calibration\",\"7.413\",\"um\"\n",
                            1024),
                      "vr.csv");
  EXPECT_NEAR(r.dx_mm, 0.007413, 1e-12);
}

TEST(KeyenceCsv, AnImplausibleFieldOfViewIsRefusedOrWarnedOf) {
  // No XY row: a Z calibration is never the pixel.
  try {
    ParseKeyenceCsv(VrCsv("\"Z Calibration\",\"0.1\",\"um\"\n", 1024), "z.csv");
    FAIL();
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find("z.csv: no 'XY Calibration' row"),
              std::string::npos)
        << e.what();
  }
  // 0.005 um on 1024 pixels: 5 um wide, refused with the line.
  try {
    ParseKeyenceCsv(VrCsv("\"XY Calibration\",\"0.005\",\"um\"\n", 1024),
                    "tiny.csv");
    FAIL();
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "tiny.csv: line 2: a pixel of 0.005 um makes the 1024 x 2 "
                  "map 0.00512 mm wide"),
              std::string::npos)
        << e.what();
  }
  // 0.1 um: 0.1 mm wide, read with a warning.
  const HeightMap w = ParseKeyenceCsv(
      VrCsv("\"XY Calibration\",\"0.1\",\"um\"\n", 1024), "small.csv");
  ASSERT_EQ(w.metadata.warnings.size(), 1u);
  EXPECT_NE(w.metadata.warnings[0].find("a Keyence VR sees 1 to 100 mm"),
            std::string::npos);
}

// A 1-D profile (one line of heights, a profilometer's line scan) is
// refused by name: the track's centreline and width need an area scan.
TEST(ReadScan, AOneDimensionalProfileIsRefusedByName) {
  const std::string path = ::testing::TempDir() + "/profile-line.txt";
  std::string line;
  for (int i = 0; i < 400; ++i) line += (i ? " " : "") + std::to_string(i % 7);
  std::ofstream(path) << line << "\n";
  ReadScanOptions o;
  o.ascii_pitch_mm = 0.005;
  try {
    ReadScan(path, o);
    FAIL() << "a profile was read as a map";
  } catch (const ScanError& e) {
    EXPECT_EQ(std::string(e.what()),
              path +
                  ": 1 rows of 400 numbers: a line profile (a stylus trace "
                  "or one line of a scan), not a height map; expected an "
                  "area scan of the worn track (its centreline and width are "
                  "found in it)");
  }
}

}  // namespace
}  // namespace wearscar::scan
