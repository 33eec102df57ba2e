#include "wearscar/scan/gsf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace wearscar::scan {
namespace {

HeightMap Ramp(int rows, int cols) {
  HeightMap m;
  m.height_mm.resize(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m.height_mm(r, c) = 0.001f * r - 0.002f * c;
  }
  m.height_mm(1, 2) = NAN;
  m.dx_mm = 0.0074;
  m.dy_mm = 0.0074;
  SyncValidity(&m);
  return m;
}

TEST(Gsf, WriteThenReadKeepsHeightsPitchAndInvalidPixels) {
  const HeightMap a = Ramp(5, 7);
  const std::string path = ::testing::TempDir() + "/ramp.gsf";
  WriteGsf(a, path);
  const HeightMap b = ReadGsf(path);
  ASSERT_EQ(b.rows(), 5);
  ASSERT_EQ(b.cols(), 7);
  EXPECT_NEAR(b.dx_mm, 0.0074, 1e-12);
  EXPECT_EQ(b.ValidCount(), 34);
  EXPECT_FALSE(b.valid(1, 2));
  EXPECT_TRUE(std::isnan(b.height_mm(1, 2)));
  EXPECT_NEAR(b.height_mm(4, 6), 0.004 - 0.012, 1e-7);
}

std::string Header(const std::string& fields) {
  std::string h = "Gwyddion Simple Field 1.0\n" + fields;
  h.append(4 - h.size() % 4, '\0');
  return h;
}

TEST(Gsf, BadInputsNameTheProblem) {
  auto expect = [](const std::string& bytes, const std::string& what) {
    try {
      ParseGsf(bytes, "x.gsf");
      FAIL() << "expected ScanError: " << what;
    } catch (const ScanError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos)
          << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("x.gsf: ", 0), 0u) << e.what();
    }
  };
  expect("Not a GSF at all", "expected the GSF magic");
  expect(Header("XRes = 2\n"), "header has no YRes");
  expect(Header("XRes = 2\nYRes = 2\n") + std::string(12, '\0'),
         "data truncated: 12 bytes present, expected 16");
  expect(Header("XRes = 100000\nYRes = 100000\n"), "exceeds 268435456 pixels");
  expect(Header("XRes = -3\nYRes = 2\n"), "expected a positive pixel count");
  expect(
      Header("XRes = 1\nYRes = 1\nXYUnits = furlong\n") + std::string(4, '\0'),
      "expected m, mm, um or nm");
  expect("Gwyddion Simple Field 1.0\nXRes = 1\n", "no NUL byte");
  // A number with text after it is not taken for its leading digits.
  expect(Header("XRes = 8abc\nYRes = 2\n") + std::string(64, '\0'),
         "XRes = '8abc'; expected a positive pixel count");
  expect(Header("XRes = 2\nYRes = 2\nXReal = 0.01 m\n") + std::string(16, '\0'),
         "XReal = '0.01 m'; expected a positive length");
}

// A file cut short keeps its whole rows, with the count, when at least
// half of them are there; with fewer it is refused.
TEST(Gsf, ACutFileKeepsItsWholeRowsAndSaysHowMany) {
  const HeightMap a = Ramp(10, 7);
  const std::string path = ::testing::TempDir() + "/cut.gsf";
  WriteGsf(a, path);
  std::ifstream in(path, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)),
                          std::istreambuf_iterator<char>());
  // Six whole rows and half of the seventh.
  const std::size_t data = whole.size() - 10 * 7 * 4;
  const HeightMap b = ParseGsf(whole.substr(0, data + 6 * 28 + 14), "cut.gsf");
  ASSERT_EQ(b.rows(), 6);
  EXPECT_NEAR(b.dy_mm, a.dy_mm, 1e-12);
  EXPECT_NEAR(b.height_mm(5, 6), a.height_mm(5, 6), 1e-9);
  ASSERT_EQ(b.metadata.warnings.size(), 1u);
  EXPECT_NE(b.metadata.warnings[0].find("6 of the 10 rows declared"),
            std::string::npos)
      << b.metadata.warnings[0];
  EXPECT_THROW(ParseGsf(whole.substr(0, data + 4 * 28), "cut.gsf"), ScanError);
}

}  // namespace
}  // namespace wearscar::scan
