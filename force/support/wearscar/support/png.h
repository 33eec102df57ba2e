#pragma once

// PNG bytes in memory by libpng (OpenCV's imgcodecs would pull in a
// hundred libraries, GDAL among them, for this one call). Private to
// wearscar's libraries (header-only, never installed); whoever includes it
// links libpng.

#include <png.h>

#include <csetjmp>
#include <string>
#include <utility>

namespace wearscar::support {

struct PngOptions {
  // zlib's level, 0-9, and libpng's row filters (PNG_FILTER_*). libpng's
  // own choice (6, every filter tried on every row) takes 8-10x the time
  // of 1 without filters, for images of flat colour runs at most a fifth
  // smaller, sometimes larger.
  int compression_level = 6;
  int filters = PNG_ALL_FILTERS;
};

namespace internal {

struct PngSink {
  std::string bytes, error;
};

inline void PngWrite(png_structp png, png_bytep data, png_size_t size) {
  static_cast<PngSink*>(png_get_io_ptr(png))
      ->bytes.append(reinterpret_cast<const char*>(data), size);
}

inline void PngFlush(png_structp) {}

[[noreturn]] inline void PngError(png_structp png, png_const_charp message) {
  static_cast<PngSink*>(png_get_error_ptr(png))->error = message;
  png_longjmp(png, 1);
}

inline void PngWarning(png_structp, png_const_charp) {}

// Only plain locals between setjmp and the jump back.
inline bool WritePng(PngSink* sink,
                     int width,
                     int height,
                     int channels,
                     bool bgr,
                     const unsigned char* pixels,
                     long row_stride,
                     const PngOptions& options) {
  png_structp png = png_create_write_struct(
      PNG_LIBPNG_VER_STRING, sink, PngError, PngWarning);
  if (png == nullptr) {
    sink->error = "libpng could not start";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, PngWrite, PngFlush);
  png_set_IHDR(png,
               info,
               static_cast<png_uint_32>(width),
               static_cast<png_uint_32>(height),
               8,
               channels == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, options.compression_level);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, options.filters);
  if (bgr) png_set_bgr(png);
  png_write_info(png, info);
  for (int r = 0; r < height; ++r) {
    png_write_row(png, const_cast<png_bytep>(pixels + r * row_stride));
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace internal

// Encodes `height` rows of `width` pixels of 8-bit RGB, BGR (`bgr`) or
// RGBA (`channels` 4), each row `row_stride` bytes from the last, the
// first row the image's top. Returns the PNG, or an empty string with
// libpng's reason in `why`.
inline std::string EncodePng(int width,
                             int height,
                             int channels,
                             bool bgr,
                             const void* pixels,
                             long row_stride,
                             const PngOptions& options,
                             std::string* why) {
  internal::PngSink sink;
  if (!internal::WritePng(&sink,
                          width,
                          height,
                          channels,
                          bgr,
                          static_cast<const unsigned char*>(pixels),
                          row_stride,
                          options)) {
    if (why != nullptr) *why = sink.error;
    return {};
  }
  return std::move(sink.bytes);
}

}  // namespace wearscar::support
