#pragma once
// Grids drawn as images (a scan map, a friction map over the cycles). In a
// PNG figure gnuplot draws the grid itself; in an SVG figure it draws a
// 2 x 2 stand-in of the same extent and colour range and wearscar paints
// the grid, in the palette gnuplot would have used, into the stand-in's
// place (gnuplot spends far longer drawing the grid than this painting
// takes). The same pixels to one level of 255 (tests/report/figures_test.cc).

#include <string>
#include <vector>

namespace wearscar::report::internal {

// A colour scale: gnuplot's `set palette defined` with evenly spaced
// stops, 0xRRGGBB each.
using Palette = std::vector<unsigned>;

// The scan map's heights: violet, blue, teal, green, yellow, white.
const Palette& HeightPalette();
// Values over cycles and x (the friction map, the track's history): the
// same without the white.
const Palette& GridPalette();
std::string PaletteCommand(const Palette& p);

// A grid of values: width x height, row by row from y0 upwards, NaN for
// no value, its pixels dx x dy centred from (x0, y0).
struct Image {
  std::string file;  // its float32 file in figure-data
  int width = 0, height = 0;
  double dx = 1, dy = 1, x0 = 0, y0 = 0;
  std::vector<float> values;
  const Palette* palette = nullptr;
};

// How a figure draws an image: gnuplot's own clause, the stand-in's (with
// its colour range) and the painted PNG; a grid without two distinct
// values has no stand-in (gnuplot draws it in every format).
struct Raster {
  std::string plot, stand_in, png;
  double lo = 0, hi = 0;
};

// Writes the image's float32 file and its stand-in's into figure-data and
// paints its PNG.
Raster MakeRaster(const std::string& dir, const Image& image);

// Puts `pngs`, in order, in place of the bitmaps gnuplot embedded in the
// SVG at `path` for the stand-ins. False (the file left as it is) when the
// SVG does not hold one bitmap per PNG.
bool PaintRasters(const std::string& path,
                  const std::vector<std::string>& pngs);

// A scale bar's length: 1, 2 or 5 x 10^n mm, at most a fifth of `width`.
double ScaleBarMm(double width_mm);

}  // namespace wearscar::report::internal
