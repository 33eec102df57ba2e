#pragma once

// PNG bytes in memory by libpng (OpenCV's imgcodecs would pull in a
// hundred libraries, GDAL among them, for this one call).

#include <string>

namespace wearscar::support {

struct PngOptions {
  // zlib's level, 0-9.
  int compression_level = 6;
  // libpng's choice of row filter, tried on every row; false: no filter
  // (much faster for images of flat colour runs, about as small).
  bool filter_rows = true;
};

// Encodes `height` rows of `width` pixels of 8-bit RGB, BGR (`bgr`) or
// RGBA (`channels` 4), each row `row_stride` bytes from the last, the
// first row the image's top. Returns the PNG, or an empty string with
// libpng's reason in `why`.
std::string EncodePng(int width,
                      int height,
                      int channels,
                      bool bgr,
                      const void* pixels,
                      long row_stride,
                      const PngOptions& options,
                      std::string* why);

}  // namespace wearscar::support
