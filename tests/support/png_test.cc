#include "wearscar/support/png.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <vector>

namespace wearscar::support {
namespace {

// Decodes a PNG to 8-bit RGBA rows with libpng's simplified API.
std::vector<unsigned char> DecodeRgba(const std::string& bytes,
                                      int* width,
                                      int* height) {
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()))
    return {};
  image.format = PNG_FORMAT_RGBA;
  std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr))
    return {};
  *width = static_cast<int>(image.width);
  *height = static_cast<int>(image.height);
  return pixels;
}

TEST(EncodePng, RgbaRoundTripsWithAndWithoutRowFilters) {
  const int w = 5, h = 3;
  std::vector<unsigned char> rgba(4 * w * h);
  for (size_t i = 0; i < rgba.size(); ++i)
    rgba[i] = static_cast<unsigned char>(i * 7);
  for (bool filter : {true, false}) {
    std::string why;
    const std::string png =
        EncodePng(w, h, 4, false, rgba.data(), 4L * w, {1, filter}, &why);
    ASSERT_FALSE(png.empty()) << why;
    EXPECT_EQ(png.substr(1, 3), "PNG");
    int dw = 0, dh = 0;
    EXPECT_EQ(DecodeRgba(png, &dw, &dh), rgba);
    EXPECT_EQ(dw, w);
    EXPECT_EQ(dh, h);
  }
}

// BGR rows with padding (an OpenCV image's step): the blue byte first in
// memory becomes the PNG's third channel, the padding is not read.
TEST(EncodePng, BgrRowsWithAStrideBecomeRgb) {
  const int w = 2, h = 2;
  const long stride = 8;  // 6 bytes of pixels, 2 of padding
  const unsigned char bgr[16] = {
      10, 20, 30, 40, 50, 60, 99, 99, 70, 80, 90, 1, 2, 3, 99, 99};
  std::string why;
  const std::string png = EncodePng(w, h, 3, true, bgr, stride, {}, &why);
  ASSERT_FALSE(png.empty()) << why;
  int dw = 0, dh = 0;
  const std::vector<unsigned char> rgba = DecodeRgba(png, &dw, &dh);
  const std::vector<unsigned char> expected = {
      30, 20, 10, 255, 60, 50, 40, 255, 90, 80, 70, 255, 3, 2, 1, 255};
  EXPECT_EQ(rgba, expected);
}

// libpng's refusal comes back as its reason, not a crash or a longjmp
// through the caller.
TEST(EncodePng, AnImpossibleImageGivesLibpngsReason) {
  const unsigned char pixel[4] = {0, 0, 0, 0};
  std::string why;
  EXPECT_TRUE(EncodePng(0, 1, 4, false, pixel, 4, {}, &why).empty());
  EXPECT_NE(why.find("IHDR"), std::string::npos) << why;
}

}  // namespace
}  // namespace wearscar::support
