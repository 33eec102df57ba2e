// ASCII matrices as labs export them: Gwyddion's ASCII export, headers
// stating a pixel size and a height conversion factor, plain grids, stylus
// profiles (refused by name), cut and malformed rows. The texts are
// written here in the layouts those programs write.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../common/compress.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/gsf.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::scan {
namespace {

std::string MessageOf(const std::string& text, const ReadScanOptions& o = {}) {
  try {
    ParseAsciiMatrix(text, "m.txt", o);
  } catch (const ScanError& e) {
    return e.what();
  }
  return "";
}

// Gwyddion's export: '#' header with the sizes in um (UTF-8 micro sign),
// the height unit alone, tab-separated values in m with three-digit
// exponents (as Windows' C library prints them).
const char kGwyddion[] =
    "# Channel: Height\n"
    "# Width: 40.00 \xc2\xb5m\n"
    "# Height: 30.00 \xc2\xb5m\n"
    "# Value units: m\n"
    "1.000000e-006\t2.000000e-006\t3.000000e-006\t4.000000e-006\n"
    "5.000000e-006\t6.000000e-006\t7.000000e-006\t8.000000e-006\n"
    "9.000000e-006\t1.000000e-005\t1.100000e-005\t1.200000e-005\n";

TEST(AsciiMatrix, GwyddionExportReadsItsSizeAndUnits) {
  const HeightMap h = ParseAsciiMatrix(kGwyddion, "g.txt", {});
  ASSERT_EQ(h.rows(), 3);
  ASSERT_EQ(h.cols(), 4);
  EXPECT_NEAR(h.dx_mm, 0.040 / 4, 1e-12);
  EXPECT_NEAR(h.dy_mm, 0.030 / 3, 1e-12);
  EXPECT_NEAR(h.height_mm(2, 3), 0.012, 1e-9);  // 1.2e-5 m
  EXPECT_EQ(h.metadata.channel, "Height");
  EXPECT_EQ(h.metadata.format, "ascii-headed");
  EXPECT_TRUE(h.metadata.warnings.empty());
}

// Its "# Height:" line is a size, not a Keyence VR CSV's Height block.
TEST(AsciiMatrix, GwyddionExportIsNotTakenForAKeyenceCsv) {
  EXPECT_EQ(DetectScanFormat(kGwyddion, "g.csv").name, "ascii");
  EXPECT_EQ(
      DetectScanFormat("XY Calibration,1.5,um\nHeight\n1,2\n", "k.csv").name,
      "keyence_csv");
}

// A header in the style of SPIP and similar exports: pixel counts, a pixel
// size in m and a conversion of the stored integers to m.
TEST(AsciiMatrix, PixelSizeAndHeightConversionFactor) {
  const std::string text =
      "x-pixels = 4\ny-pixels = 3\npixel size=3.69862e-007 m\n"
      "height conversion factor (-> m)=1e-009\n"
      "10 20 30 40\n50 60 70 80\n90 100 110 120\n";
  const HeightMap h = ParseAsciiMatrix(text, "s.txt", {});
  EXPECT_NEAR(h.dx_mm, 3.69862e-4, 1e-12);
  EXPECT_NEAR(h.dy_mm, 3.69862e-4, 1e-12);
  EXPECT_NEAR(h.height_mm(2, 3), 120e-6, 1e-10);  // 120 nm
  EXPECT_TRUE(h.metadata.warnings.empty());
  // Counts that match neither way round are refused.
  EXPECT_NE(
      MessageOf("w = 5\nh = 3\npixel size = 1 um\n" +
                text.substr(text.find("10 ")))
          .find("the header states 5 x 3 pixels; found 3 rows of 4 values"),
      std::string::npos);
}

// A Wyko/Vision ASCII export: the size as two words of one line, then
// the pixel, the data unit and the height conversion factor.
TEST(AsciiMatrix, VisionExportWithTheSizeOnOneLine) {
  const std::string text =
      "h=3 w=4\npixel size=3.69862e-007 m\ndata unit=rad\n"
      "height conversion factor (-> m)=6.30079e-008\n"
      "10 20 30 40\n50 60 70 80\n90 100 110 120\n";
  const HeightMap h = ParseAsciiMatrix(text, "vision.txt", {});
  EXPECT_EQ(h.rows(), 3);
  EXPECT_EQ(h.cols(), 4);
  EXPECT_NEAR(h.dx_mm, 3.69862e-4, 1e-12);
  EXPECT_NEAR(h.height_mm(2, 3), 120 * 6.30079e-8 * 1e3, 1e-9);  // float
  // Stated the other way round from the data: refused, naming both.
  EXPECT_NE(
      MessageOf("h=5 w=4\npixel size=1 um\n" + text.substr(text.find("10 ")))
          .find("the header states 4 x 5 pixels; found 3 rows of 4 "
                "values"),
      std::string::npos);
}

TEST(AsciiMatrix, AStylusProfileIsRefusedAsALineProfile) {
  // A Dektak CSV: parameters, results, then lateral position and height.
  const std::string dektak =
      "Scan Parameters\nScan Type,Standard Scan\nLength,1500.0 um\n\n"
      "Scan Data\nLateral um,Raw Micrometer,\n0.0,-0.00933,,\n0.2,-0.00760,,\n"
      "0.3,-0.00644,,\n0.5,-0.00498,,\n";
  const std::string m = MessageOf(dektak);
  EXPECT_NE(m.find("4 rows of 2 numbers: a line profile"), std::string::npos)
      << m;
  EXPECT_NE(MessageOf("1 2 3 4 5 6\n").find("a line profile"),
            std::string::npos);
}

TEST(AsciiMatrix, PlainGridNeedsThePitchAndSaysWhatItAssumed) {
  const std::string grid = "1 2 3\n4 nan 6\n7 8 9\n";
  EXPECT_NE(MessageOf(grid).find("give it with --ascii-pitch"),
            std::string::npos);
  ReadScanOptions o;
  o.ascii_pitch_mm = 0.005;
  const HeightMap mm = ParseAsciiMatrix(grid, "m.txt", o);
  EXPECT_NEAR(mm.height_mm(2, 2), 9.0, 1e-6);
  ASSERT_EQ(mm.metadata.warnings.size(), 1u);
  EXPECT_NE(mm.metadata.warnings[0].find("no unit: taken as mm"),
            std::string::npos);
  o.ascii_z_unit = "um";
  const HeightMap um = ParseAsciiMatrix(grid, "m.txt", o);
  EXPECT_NEAR(um.height_mm(2, 2), 9e-3, 1e-9);
  EXPECT_FALSE(um.valid(1, 1));
  EXPECT_TRUE(um.metadata.warnings.empty());
  // The option against a stated size: the option's, said.
  o.ascii_pitch_mm = 0.02;
  const HeightMap g = ParseAsciiMatrix(kGwyddion, "g.txt", o);
  EXPECT_NEAR(g.dx_mm, 0.02, 1e-12);
  ASSERT_EQ(g.metadata.warnings.size(), 1u);
  EXPECT_NE(g.metadata.warnings[0].find("states a pixel of 10 um"),
            std::string::npos)
      << g.metadata.warnings[0];
}

TEST(AsciiMatrix, ACutLastRowIsDroppedWithAWarning) {
  std::string text = kGwyddion;
  text += "1.3e-005\t1.4e-005\n";
  const HeightMap h = ParseAsciiMatrix(text, "g.txt", {});
  EXPECT_EQ(h.rows(), 3);
  EXPECT_NEAR(h.dy_mm, 0.030 / 4, 1e-12);  // the size covers the cut row
  ASSERT_EQ(h.metadata.warnings.size(), 1u);
  EXPECT_NE(h.metadata.warnings[0].find("line 8) is cut, 2 of 4 values"),
            std::string::npos)
      << h.metadata.warnings[0];
  // Short inside the data: an error, not a cut.
  EXPECT_NE(MessageOf("1 2 3\n4 5\n7 8 9\n10 11 12\n")
                .find("line 2: 2 values; expected 3"),
            std::string::npos);
}

TEST(AsciiMatrix, NumbersWithTextAfterThemAreRefused) {
  EXPECT_NE(MessageOf("1 2 3\n4 5 6mm\n7 8 9\n",
                      [] {
                        ReadScanOptions o;
                        o.ascii_pitch_mm = 0.01;
                        return o;
                      }())
                .find("line 2, value 3: found '6mm', expected a number"),
            std::string::npos);
  EXPECT_NE(MessageOf("# Width: ten um\n1 2 3\n4 5 6\n7 8 9\n")
                .find("line 1: found '# Width: ten um'; expected a number"),
            std::string::npos);
  EXPECT_NE(MessageOf("1 2 3\n4 5 6\nEnd of data\n7 8 9\n")
                .find("line 3: found 'End of data' amid the heights"),
            std::string::npos);
}

// A map compressed whole (gzip, zstd) reads as the file it expands to, its
// format told from the expanded bytes and the name under the suffix.
TEST(CompressedScan, ReadsAsTheFileItExpandsTo) {
  const std::string dir = ::testing::TempDir();
  const std::string gz = dir + "/g.txt.gz";
  std::ofstream(gz, std::ios::binary) << packing::Gzip(kGwyddion);
  ReadScanOptions o;
  o.min_pitch_mm = 1e-4;
  o.warn_field_mm = 0;
  const HeightMap a = ReadScan(gz, o);
  EXPECT_EQ(a.metadata.format, "ascii-headed");
  EXPECT_NEAR(a.height_mm(2, 3), 0.012, 1e-9);
  HeightMap m;
  m.Resize(6, 8);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 8; ++c) m.height_mm(r, c) = 0.001f * (r + c);
  m.valid.setConstant(1);
  m.dx_mm = m.dy_mm = 0.0074;
  WriteGsf(m, dir + "/m.gsf");
  std::ifstream in(dir + "/m.gsf", std::ios::binary);
  const std::string gsf((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
  std::ofstream(dir + "/m.gsf.zst", std::ios::binary) << packing::Zstd(gsf);
  const HeightMap b = ReadScan(dir + "/m.gsf.zst", o);
  EXPECT_EQ(b.metadata.format, "gsf");
  EXPECT_TRUE(b.height_mm.isApprox(m.height_mm, 1e-6f));
  EXPECT_EQ(ScanFormatOf(dir + "/m.gsf.zst", kDetectExtension)->name, "gsf");
  // Cut short: refused with the reason.
  std::ofstream(gz, std::ios::binary) << packing::Gzip(kGwyddion).substr(0, 40);
  try {
    ReadScan(gz, o);
    ADD_FAILURE() << "a cut gzip file was read";
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find("g.txt.gz (gzip-compressed): the "
                                         "gzip data end after 40 bytes, cut "
                                         "short"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace wearscar::scan
