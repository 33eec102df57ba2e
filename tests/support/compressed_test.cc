#include "wearscar/support/compressed.h"

#include <gtest/gtest.h>

#include <string>

#include "../common/compress.h"

namespace wearscar::support {
namespace {

std::string Text(std::size_t lines) {
  std::string t = "Time [s],Position [mm],Fx [N],Fz [N]\n";
  for (std::size_t i = 0; i < lines; ++i)
    t += std::to_string(i * 0.002) + ",1.25,-3.5," + std::to_string(i % 97) +
         "\n";
  return t;
}

TEST(Compressed, TellsGzipAndZstdByTheirFirstBytes) {
  const std::string t = Text(10);
  EXPECT_EQ(CompressionOf(packing::Gzip(t)), Compression::kGzip);
  EXPECT_EQ(CompressionOf(packing::Zstd(t)), Compression::kZstd);
  EXPECT_EQ(CompressionOf(t), Compression::kNone);
  EXPECT_EQ(CompressionOf("\x1f"), Compression::kNone);
  EXPECT_STREQ(CompressionName(Compression::kZstd), "zstd");
}

TEST(Compressed, NamesWithoutTheirSuffix) {
  EXPECT_EQ(WithoutCompressionSuffix("lab/oak_01.csv.gz"), "lab/oak_01.csv");
  EXPECT_EQ(WithoutCompressionSuffix("a.TXT.ZST"), "a.TXT");
  EXPECT_EQ(WithoutCompressionSuffix("a.zstd"), "a");
  EXPECT_EQ(WithoutCompressionSuffix("a.csv"), "a.csv");
  EXPECT_EQ(WithoutCompressionSuffix(".gz"), ".gz");
}

TEST(Compressed, ExpandsToTheSameBytes) {
  const std::string t = Text(200000);  // several MiB: more than one step
  for (const std::string& packed : {packing::Gzip(t), packing::Zstd(t)}) {
    std::string out, why;
    ASSERT_TRUE(Decompress(
        packed, CompressionOf(packed), 1ull << 30, false, &out, &why))
        << why;
    EXPECT_EQ(out, t);
  }
  // Two gzip members one after the other, as `cat a.gz b.gz` makes.
  const std::string two = packing::Gzip("abc\n") + packing::Gzip("def\n");
  std::string out, why;
  ASSERT_TRUE(Decompress(two, Compression::kGzip, 1 << 20, false, &out, &why));
  EXPECT_EQ(out, "abc\ndef\n");
}

TEST(Compressed, CutCorruptOrTooLargeIsRefusedWithTheReason) {
  const std::string t = Text(20000);
  for (const std::string& packed : {packing::Gzip(t), packing::Zstd(t)}) {
    const Compression c = CompressionOf(packed);
    std::string out, why;
    EXPECT_FALSE(Decompress(
        packed.substr(0, packed.size() / 2), c, 1ull << 30, false, &out, &why));
    EXPECT_NE(why.find("cut short"), std::string::npos) << why;
    std::string bad = packed;
    for (std::size_t i = 20; i < 60; ++i) bad[i] = static_cast<char>(~bad[i]);
    EXPECT_FALSE(Decompress(bad, c, 1ull << 30, false, &out, &why));
    EXPECT_NE(why.find("corrupt"), std::string::npos) << why;
    // Beyond the bound: refused, or its head when a head is asked for.
    EXPECT_FALSE(Decompress(packed, c, 1 << 16, false, &out, &why));
    EXPECT_NE(why.find("expands to more than"), std::string::npos) << why;
    ASSERT_TRUE(Decompress(packed, c, 1 << 16, true, &out, &why)) << why;
    EXPECT_EQ(out, t.substr(0, 1 << 16));
  }
}

}  // namespace
}  // namespace wearscar::support
