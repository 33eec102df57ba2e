// The readers of Sensofar, Alicona, Bruker/Veeco, Digital Surf and Zygo
// maps, read from the real files in ../shared/data/other to the reference
// values of shared/data/README.md (SurfaceTopography's reader tests), and
// the registry that chooses among all the formats.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "common/paths.h"
#include "file_helpers.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::scan {
namespace {

const std::string kOther = std::string(WEARSCAR_SHARED_DATA) + "/other/";

#define REQUIRE_OTHER_FILES()                                                \
  if (!std::filesystem::exists(kOther)) {                                    \
    GTEST_SKIP() << "../shared/data/other is absent: real instrument files " \
                    "not available";                                         \
  }

using test_files::Slurp;
using test_files::Spit;

// Root mean square of the valid heights about their mean, in mm (two
// passes: the mean may be far larger than the spread).
double Rms(const HeightMap& m) {
  double sum = 0;
  long n = 0;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    if (m.valid.data()[i]) sum += m.height_mm.data()[i], ++n;
  }
  const double mean = sum / n;
  double sum2 = 0;
  for (Eigen::Index i = 0; i < m.height_mm.size(); ++i) {
    const double d = m.height_mm.data()[i] - mean;
    if (m.valid.data()[i]) sum2 += d * d;
  }
  return std::sqrt(sum2 / n);
}

// ---------------------------------------------------------------- real files

TEST(RealFiles, SensofarPluToReferenceValues) {
  REQUIRE_OTHER_FILES();
  const HeightMap m = ReadScan(kOther + "plu-1.plu");
  EXPECT_EQ(m.metadata.format, "plu");
  ASSERT_EQ(m.cols(), 768);
  ASSERT_EQ(m.rows(), 576);
  // 1274.880066 x 956.160049 um.
  EXPECT_NEAR(m.cols() * m.dx_mm, 1.274880066, 1e-8);
  EXPECT_NEAR(m.rows() * m.dy_mm, 0.956160049, 1e-8);
  EXPECT_NEAR(Rms(m), 2.834391e-3, 2e-9);  // 2.834391 um
  EXPECT_EQ(m.ValidCount(), 768 * 576);
  EXPECT_EQ(m.metadata.instrument, "Sensofar");
  EXPECT_EQ(m.metadata.date, "Fri Mar 10 16:35:59 2023");
}

TEST(RealFiles, AliconaAl3dToReferenceValues) {
  REQUIRE_OTHER_FILES();
  const HeightMap m = ReadScan(kOther + "al3d-1.al3d");
  EXPECT_EQ(m.metadata.format, "al3d");
  ASSERT_EQ(m.cols(), 200);
  ASSERT_EQ(m.rows(), 296);
  EXPECT_NEAR(m.cols() * m.dx_mm, 8.76054e-05 * 1e3, 1e-10);
  EXPECT_NEAR(m.rows() * m.dy_mm, 1.29655992e-04 * 1e3, 1e-10);
  // Heights are stored as float32 in mm: agreement to 3 parts in 10^6.
  EXPECT_NEAR(Rms(m), 7.688266102603082e-06 * 1e3, 2e-8);
  EXPECT_EQ(m.metadata.instrument.rfind("Alicona Imaging", 0), 0u)
      << m.metadata.instrument;
}

TEST(RealFiles, BrukerOpdToReferenceValues) {
  REQUIRE_OTHER_FILES();
  const std::string path = kOther + "opd-1.opd";
  const HeightMap m = ReadScan(path);
  EXPECT_EQ(m.metadata.format, "opd");
  ASSERT_EQ(m.cols(), 640);
  ASSERT_EQ(m.rows(), 480);
  // 0.125909140 x 0.094431855 (mm: Pixel_size is in mm).
  EXPECT_NEAR(m.cols() * m.dx_mm, 0.125909140, 1e-8);
  EXPECT_NEAR(m.rows() * m.dy_mm, 0.094431855, 1e-8);
  // Height scale factor 0.0005772949829101563 (mm per stored unit): the
  // first stored value (column 0, bottom row) times it.
  const std::string bytes = Slurp(path);
  // The array follows a 1000-entry directory (2 + 24000 bytes) and the 18
  // bytes of the blocks listed before it; 6 bytes give its size.
  float first;
  std::memcpy(&first, bytes.data() + 2 + 1000 * 24 + 18 + 6, 4);
  EXPECT_NEAR(m.height_mm(479, 0),
              first * 0.0005772949829101563,
              1e-6 * std::abs(first * 0.0005772949829101563));
  EXPECT_EQ(m.rows() * m.cols() - m.ValidCount(), 116);  // stored >= 1e38
  EXPECT_EQ(m.metadata.date, "7/7/2015 16:19:48");
  EXPECT_NE(m.metadata.instrument.find("Wyko"), std::string::npos);
}

TEST(RealFiles, DigitalSurfSurToReferenceValues) {
  REQUIRE_OTHER_FILES();
  const HeightMap m = ReadScan(kOther + "sur-3.sur");
  EXPECT_EQ(m.metadata.format, "sur");
  ASSERT_EQ(m.cols(), 512);
  ASSERT_EQ(m.rows(), 512);
  EXPECT_NEAR(m.cols() * m.dx_mm, 0.151319552 * 1e3, 1e-5);
  EXPECT_NEAR(m.rows() * m.dy_mm, 0.151319552 * 1e3, 1e-5);
  // The file marks non-measured points (zmin - 2); the reference reader
  // does not, and counts them as heights of -2 nm (before the file's z
  // offset, which it does not apply). Put them back to compare with its
  // rms, 0.0019200491394179297 m.
  EXPECT_EQ(m.ValidCount(), 29135);
  float z0_m;
  std::memcpy(&z0_m, Slurp(kOther + "sur-3.sur").data() + 474, 4);
  HeightMap all = m;
  all.height_mm =
      m.valid.select(m.height_mm, static_cast<float>(-2e-6 + 1e3 * z0_m));
  all.valid.setOnes();
  EXPECT_NEAR(Rms(all), 0.0019200491394179297 * 1e3, 2e-6);
  EXPECT_EQ(m.metadata.date, "2023-06-22 10:08:53");
}

TEST(RealFiles, ZygoMetroProToReferenceValues) {
  REQUIRE_OTHER_FILES();
  const HeightMap m = ReadScan(kOther + "metropro-1.dat");
  EXPECT_EQ(m.metadata.format, "metropro");
  ASSERT_EQ(m.cols(), 640);
  ASSERT_EQ(m.rows(), 480);
  EXPECT_NEAR(m.cols() * m.dx_mm, 7.028812979115173e-04 * 1e3, 1e-9);
  EXPECT_NEAR(m.rows() * m.dy_mm, 5.27160973433638e-04 * 1e3, 1e-9);
  EXPECT_NEAR(Rms(m), 7.528822204734589e-08 * 1e3, 1e-11);
  EXPECT_EQ(m.metadata.instrument.rfind("Zygo", 0), 0u);
}

// The compressed variant of .sur holds the same points as zlib streams:
// made here from the real file, it must read to the same map.
TEST(RealFiles, DigitalSurfCompressedReadsLikeThePlainFile) {
  REQUIRE_OTHER_FILES();
  const std::string plain = Slurp(kOther + "sur-3.sur");
  const std::string points = plain.substr(512);
  // Two streams, to exercise the directory.
  std::string block;
  auto u32 = [](std::uint32_t v) {
    return std::string(reinterpret_cast<char*>(&v), 4);
  };
  const std::size_t half = points.size() / 2;
  std::string zipped[2];
  for (int i = 0; i < 2; ++i) {
    const std::string part =
        points.substr(i * half, i ? std::string::npos : half);
    uLongf len = compressBound(part.size());
    zipped[i].resize(len);
    ASSERT_EQ(compress(reinterpret_cast<Bytef*>(zipped[i].data()),
                       &len,
                       reinterpret_cast<const Bytef*>(part.data()),
                       part.size()),
              Z_OK);
    zipped[i].resize(len);
  }
  block = u32(2) + u32(half) + u32(zipped[0].size()) +
          u32(points.size() - half) + u32(zipped[1].size()) + zipped[0] +
          zipped[1];
  std::string header = plain.substr(0, 512);
  header.replace(0, 12, "DSCOMPRESSED");
  const std::uint32_t size = block.size();
  std::memcpy(header.data() + 324, &size, 4);
  const std::string path = ::testing::TempDir() + "/compressed.sur";
  Spit(path, header + block);
  const HeightMap a = ReadScan(kOther + "sur-3.sur");
  const HeightMap b = ReadScan(path);
  ASSERT_EQ(b.rows(), a.rows());
  ASSERT_EQ(b.cols(), a.cols());
  EXPECT_TRUE((a.valid == b.valid).all());
  EXPECT_TRUE(
      (a.valid.cast<bool>() == false || a.height_mm == b.height_mm).all());
  EXPECT_LT(header.size() + block.size(), plain.size() / 5);
}

// Every real file cut short, or with a header byte changed, ends in a
// ScanError naming the file (never a crash, a hang or a huge allocation).
TEST(RealFiles, CutOrCorruptedFilesAreRefusedWithTheirName) {
  REQUIRE_OTHER_FILES();
  std::mt19937 rng(7);
  for (const char* file : {"plu-1.plu",
                           "al3d-1.al3d",
                           "opd-1.opd",
                           "sur-3.sur",
                           "metropro-1.dat"}) {
    const std::string bytes = Slurp(kOther + file);
    const std::string path = ::testing::TempDir() + "/cut_" + file;
    // Cut inside the heights (later blocks, images and textures, may go).
    for (double f : {0.0, 0.001, 0.01, 0.1, 0.25}) {
      Spit(path, bytes.substr(0, static_cast<std::size_t>(f * bytes.size())));
      try {
        ReadScan(path);
        ADD_FAILURE() << file << " cut to " << f << " was read";
      } catch (const ScanError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos)
            << e.what();
      }
    }
    for (int trial = 0; trial < 200; ++trial) {
      std::string bad = bytes;
      const std::size_t at = rng() % std::min<std::size_t>(1024, bad.size());
      bad[at] = static_cast<char>(rng());
      Spit(path, bad);
      try {
        ReadScan(path);  // a changed byte may still be a valid map
      } catch (const ScanError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos)
            << e.what();
      }
    }
  }
}

// ------------------------------------------------------------------ registry

TEST(ScanRegistry, NamesAreUniqueAndEveryFormatDetectsAndParses) {
  std::set<std::string> names;
  for (const ScanFormat& f : ScanFormats()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_NE(f.detect, nullptr) << f.name;
    EXPECT_NE(f.parse, nullptr) << f.name;
    EXPECT_FALSE(f.extensions.empty()) << f.name;
    EXPECT_EQ(FindScanFormat(f.name), &f);
    for (const std::string& e : f.extensions) {
      EXPECT_NE(ScanExtensionList().find(e.substr(1)), std::string::npos) << e;
    }
  }
  for (const char* n : {"zon",
                        "zag",
                        "vk4",
                        "vk67",
                        "x3p",
                        "gsf",
                        "plu",
                        "al3d",
                        "opd",
                        "sur",
                        "metropro",
                        "keyence_csv",
                        "ascii"}) {
    EXPECT_NE(FindScanFormat(n), nullptr) << n;
  }
  EXPECT_EQ(FindScanFormat("bmp"), nullptr);
}

TEST(ScanRegistry, ContentDecidesOverTheName) {
  REQUIRE_OTHER_FILES();
  // A real map renamed: found by its magic.
  for (const auto& [file, format] :
       std::vector<std::pair<std::string, std::string>>{
           {"sur-3.sur", "sur"},
           {"metropro-1.dat", "metropro"},
           {"opd-1.opd", "opd"},
           {"al3d-1.al3d", "al3d"}}) {
    const std::string bytes = Slurp(kOther + file);
    EXPECT_EQ(DetectScanFormat(bytes, "renamed.bin").name, format) << file;
    const std::string path =
        ::testing::TempDir() + "/renamed_" + format + ".bin";
    Spit(path, bytes);
    ASSERT_NE(BinaryScanFormatOf(path), nullptr) << file;
    EXPECT_EQ(BinaryScanFormatOf(path)->name, format);
    EXPECT_EQ(ReadScan(path).metadata.format, format);
  }
  // .plu has no magic: its extension decides.
  EXPECT_EQ(DetectScanFormat(Slurp(kOther + "plu-1.plu"), "x.PLU").name, "plu");
}

TEST(ScanRegistry, DatIsZygoByMagicElseTextElseRefused) {
  // A text .dat (a force export or an ASCII matrix) is not a MetroPro map.
  EXPECT_EQ(DetectScanFormat("1 2 3\n4 5 6\n", "map.dat").name, "ascii");
  const std::string force_dat = ::testing::TempDir() + "/force.dat";
  Spit(force_dat, "time_s,x_mm,Q_N,P_N\n0,0,1,30\n");
  EXPECT_EQ(BinaryScanFormatOf(force_dat), nullptr);
  // Binary without the magic: refused, naming what was expected.
  try {
    DetectScanFormat(std::string("\x01\x02\x00\x04rest", 8), "map.dat");
    ADD_FAILURE() << "binary .dat without the magic was accepted";
  } catch (const ScanError& e) {
    EXPECT_NE(std::string(e.what()).find("not the magic of a .dat file (Zygo"),
              std::string::npos)
        << e.what();
  }
  // A binary format's extension without its magic: refused even as text.
  EXPECT_THROW(DetectScanFormat("1 2 3\n", "map.sur"), ScanError);
}

}  // namespace
}  // namespace wearscar::scan
