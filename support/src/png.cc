#include "wearscar/support/png.h"

#include <png.h>

#include <csetjmp>
#include <utility>

namespace wearscar::support {
namespace {

struct PngSink {
  std::string bytes, error;
};

void PngWrite(png_structp png, png_bytep data, png_size_t size) {
  static_cast<PngSink*>(png_get_io_ptr(png))
      ->bytes.append(reinterpret_cast<const char*>(data), size);
}

void PngFlush(png_structp) {}

[[noreturn]] void PngError(png_structp png, png_const_charp message) {
  static_cast<PngSink*>(png_get_error_ptr(png))->error = message;
  png_longjmp(png, 1);
}

void PngWarning(png_structp, png_const_charp) {}

// Only plain locals between setjmp and the jump back.
bool WritePng(PngSink* sink,
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
  png_set_filter(png,
                 PNG_FILTER_TYPE_BASE,
                 options.filter_rows ? PNG_ALL_FILTERS : PNG_FILTER_NONE);
  if (bgr) png_set_bgr(png);
  png_write_info(png, info);
  for (int r = 0; r < height; ++r) {
    png_write_row(png, const_cast<png_bytep>(pixels + r * row_stride));
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::string EncodePng(int width,
                      int height,
                      int channels,
                      bool bgr,
                      const void* pixels,
                      long row_stride,
                      const PngOptions& options,
                      std::string* why) {
  PngSink sink;
  if (!WritePng(&sink,
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
