#include "images.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string_view>

#include "wearscar/report/figures.h"
#include "wearscar/report/html_report.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/support/check.h"
#include "wearscar/support/png.h"

namespace wearscar::report::internal {
namespace {

// The colour gnuplot gives `gray` (0 to 1) on `p`: linear in RGB between
// the two stops about it, each channel rounded to 1/255.
void PaletteColour(const Palette& p, double gray, unsigned char* rgb) {
  const size_t n = p.size() - 1;
  const size_t k =
      std::min(static_cast<size_t>(std::clamp(gray, 0.0, 1.0) * n), n - 1);
  const double from = static_cast<double>(k) / n,
               to = static_cast<double>(k + 1) / n;
  const double f = (gray - from) / (to - from);
  for (int j = 0; j < 3; ++j) {
    const int shift = 16 - 8 * j;
    const double a = ((p[k] >> shift) & 255) / 255.0,
                 b = ((p[k + 1] >> shift) & 255) / 255.0;
    rgb[j] = static_cast<unsigned char>(std::lround(255 * (a + f * (b - a))));
  }
}

// The grid in RGBA rows from the top (the grid's last row); transparent
// where it has no value, as gnuplot leaves it.
std::string PaintPng(const Image& image, double lo, double hi) {
  const int width = image.width, height = image.height;
  std::vector<unsigned char> rgba(image.values.size() * 4, 0);
  for (int r = 0; r < height; ++r) {
    const float* row =
        image.values.data() + static_cast<size_t>(height - 1 - r) * width;
    unsigned char* out = rgba.data() + static_cast<size_t>(r) * width * 4;
    for (int c = 0; c < width; ++c, out += 4) {
      if (!std::isfinite(row[c])) continue;
      PaletteColour(*image.palette, (row[c] - lo) / (hi - lo), out);
      out[3] = 255;
    }
  }
  std::string why;
  // zlib's fastest level, no row filters: a tenth of libpng's default
  // time, about as large as gnuplot's own PNG.
  return support::EncodePng(width,
                            height,
                            4,
                            /*bgr=*/false,
                            rgba.data(),
                            4L * width,
                            {1, /*filter_rows=*/false},
                            &why);
}

}  // namespace

const Palette& HeightPalette() {
  static const Palette p{
      0x2c0e5a, 0x3b5ba5, 0x2fa39a, 0xa6d96a, 0xfee08b, 0xf9f9f9};
  return p;
}

const Palette& GridPalette() {
  static const Palette p{0x2c0e5a, 0x3b5ba5, 0x2fa39a, 0xa6d96a, 0xfee08b};
  return p;
}

std::string PaletteCommand(const Palette& p) {
  std::string s = "set palette defined (";
  for (size_t i = 0; i < p.size(); ++i)
    s += fmt::format("{}{} '#{:06x}'", i ? ", " : "", i, p[i]);
  return s + ")\n";
}

Raster MakeRaster(const std::string& dir, const Image& image) {
  WEARSCAR_CHECK(
      image.values.size() == static_cast<size_t>(image.width) * image.height,
      "an image has width x height values");
  WEARSCAR_CHECK(image.palette != nullptr, "an image has a palette");
  WriteTextAtomically(
      FigureDataPath(dir, image.file),
      std::string(reinterpret_cast<const char*>(image.values.data()),
                  image.values.size() * sizeof(float)));
  Raster r;
  r.plot = fmt::format(
      "'{}/{}' binary array=({},{}) dx={} dy={} origin=({},{}) "
      "format='%float32' with image",
      kFigureData,
      image.file,
      image.width,
      image.height,
      image.dx,
      image.dy,
      image.x0,
      image.y0);
  r.lo = INFINITY;
  r.hi = -INFINITY;
  for (float v : image.values) {
    if (!std::isfinite(v)) continue;
    r.lo = std::min<double>(r.lo, v);
    r.hi = std::max<double>(r.hi, v);
  }
  if (!(r.hi > r.lo)) return r;
  r.png = PaintPng(image, r.lo, r.hi);
  if (r.png.empty()) return r;  // gnuplot draws it then
  // Two pixels each way over the grid's extent.
  WriteTextAtomically(FigureDataPath(dir, "stand_in.f32"),
                      std::string(4 * sizeof(float), '\0'));
  const double sx = 0.5 * image.width * image.dx,
               sy = 0.5 * image.height * image.dy;
  r.stand_in = fmt::format(
      "'{}/stand_in.f32' binary array=(2,2) dx={} dy={} origin=({},{}) "
      "format='%float32' with image",
      kFigureData,
      sx,
      sy,
      image.x0 - 0.5 * image.dx + 0.5 * sx,
      image.y0 - 0.5 * image.dy + 0.5 * sy);
  return r;
}

bool PaintRasters(const std::string& path,
                  const std::vector<std::string>& pngs) {
  if (pngs.empty()) return true;
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) return false;
  const std::string svg((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
  static constexpr std::string_view kData = "data:image/png;base64,";
  std::string out;
  size_t from = 0, k = 0;
  for (size_t at = svg.find(kData); at != std::string::npos;
       at = svg.find(kData, from)) {
    const size_t payload = at + kData.size();
    const size_t end = svg.find_first_of("'\"", payload);
    if (k == pngs.size() || end == std::string::npos) return false;
    out.append(svg, from, payload - from);
    out += Base64(pngs[k++]);
    from = end;
  }
  if (k != pngs.size()) return false;
  out.append(svg, from, std::string::npos);
  WriteTextAtomically(path, out);
  return true;
}

double ScaleBarMm(double width_mm) {
  const double target = width_mm / 5;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= target) return m * decade;
  }
  return decade;
}

}  // namespace wearscar::report::internal
