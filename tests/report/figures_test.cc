// wearscar::report's image figures: in SVG gnuplot draws a 2 x 2 stand-in
// and wearscar paints the grid into its place. Judged against gnuplot's own
// rendering of the same grid from the same script.
#include "wearscar/report/figures.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/simulated.h"
#include "report_helpers.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/report/html_report.h"
#include "wearscar/report/specimen_folder.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;
using test_support::Slurp;

struct Bitmap {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  int At(int row, int col, int channel) const {
    return rgba[(static_cast<size_t>(row) * width + col) * 4 + channel];
  }
};

std::string FromBase64(const std::string& text) {
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned value = 0;
  int bits = 0;
  for (char c : text) {
    const size_t v = kAlphabet.find(c);
    if (v == std::string::npos) continue;  // '=' padding
    value = (value << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((value >> bits) & 255);
    }
  }
  return out;
}

// Every bitmap embedded in an SVG, decoded to RGBA, and the <image>
// elements' placement (their attributes before the data). std::regex
// recurses per character: no use on 80 KB of base64.
void Images(const std::string& svg,
            std::vector<Bitmap>* bitmaps,
            std::vector<std::string>* places) {
  static const std::string kData = "data:image/png;base64,";
  for (size_t at = svg.find("<image "); at != std::string::npos;
       at = svg.find("<image ", at + 1)) {
    const size_t data = svg.find(kData, at);
    ASSERT_NE(data, std::string::npos);
    const size_t end = svg.find_first_of("'\"", data);
    ASSERT_NE(end, std::string::npos);
    places->push_back(svg.substr(at, svg.find(" xlink:href", at) - at));
    const std::string png =
        FromBase64(svg.substr(data + kData.size(), end - data - kData.size()));
    png_image img;
    std::memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_memory(&img, png.data(), png.size()))
        << img.message;
    img.format = PNG_FORMAT_RGBA;
    Bitmap b;
    b.width = static_cast<int>(img.width);
    b.height = static_cast<int>(img.height);
    b.rgba.resize(PNG_IMAGE_SIZE(img));
    ASSERT_TRUE(png_image_finish_read(&img, nullptr, b.rgba.data(), 0, nullptr))
        << img.message;
    bitmaps->push_back(std::move(b));
  }
}

// A levelled map of 300 x 200 pixels, 10 um pitch: a groove along x with
// a tilt, and a block of unmeasured pixels near the origin (bottom left
// of the figure).
fusion::MapAnalysis GroovedMap() {
  fusion::MapAnalysis a;
  scan::HeightMap& m = a.levelled;
  m.Resize(200, 300);
  m.dx_mm = m.dy_mm = 0.01;
  m.metadata.source = "figures_test";
  for (int r = 0; r < 200; ++r) {
    for (int c = 0; c < 300; ++c) {
      const double y = r * 0.01, x = c * 0.01;
      const bool hole = r >= 10 && r < 30 && c >= 20 && c < 60;
      m.height_mm(r, c) =
          hole ? NAN
               : static_cast<float>(
                     -0.02 * std::exp(-std::pow((y - 1.0) / 0.3, 2)) +
                     0.004 * x + 0.001 * std::sin(7 * x));
      m.valid(r, c) = hole ? 0 : 1;
    }
  }
  return a;
}

TEST(ImageFigures, TheSvgHoldsThePixelsGnuplotDrawsFromTheGrid) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("raster");
  const fusion::MapAnalysis map = GroovedMap();
  const FigureSet set = DrawMapFigure(dir.string(), "grooved", map);
  ASSERT_TRUE(set.missing.empty()) << set.message;
  std::vector<Bitmap> ours;
  std::vector<std::string> our_places;
  Images(Slurp(dir / "scan_map.svg"), &ours, &our_places);
  ASSERT_EQ(ours.size(), 1u);

  // The script draws a stand-in and names the clause drawing the grid
  // itself; that clause, run in the same script, is gnuplot's own figure.
  std::string script = Slurp(dir / kFigureData / "figures.gp");
  std::smatch own;
  ASSERT_TRUE(std::regex_search(
      script, own, std::regex("gnuplot draws it with: plot ([^\n]*)")));
  EXPECT_NE(own[1].str().find("scan_map.f32' binary array=(300,200)"),
            std::string::npos);
  const std::regex stand_in("'figure-data/stand_in\\.f32'[^\n]*?with image");
  ASSERT_TRUE(std::regex_search(script, stand_in));
  script = std::regex_replace(script, stand_in, own[1].str());
  script = std::regex_replace(
      script, std::regex("scan_map\\.svg\\.part"), "reference.svg");
  // The colour range is the grid's, in um.
  float lo = INFINITY, hi = -INFINITY;
  for (int r = 0; r < 200; ++r) {
    for (int c = 0; c < 300; ++c) {
      const float v = 1e3f * map.levelled.height_mm(r, c);
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  std::smatch range;
  ASSERT_TRUE(std::regex_search(
      script, range, std::regex("set cbrange \\[([^:]*):([^\\]]*)\\]")));
  EXPECT_DOUBLE_EQ(std::stod(range[1]), static_cast<double>(lo));
  EXPECT_DOUBLE_EQ(std::stod(range[2]), static_cast<double>(hi));
  std::ofstream(dir / kFigureData / "reference.gp") << script;
  ASSERT_TRUE(RunGnuplotScript(dir.string(), "reference.gp"));
  std::vector<Bitmap> theirs;
  std::vector<std::string> their_places;
  Images(Slurp(dir / "reference.svg"), &theirs, &their_places);
  ASSERT_EQ(theirs.size(), 1u);

  // Placed where gnuplot places the grid, pixel for pixel its colours.
  EXPECT_EQ(our_places[0], their_places[0]);
  const Bitmap &a = ours[0], &b = theirs[0];
  ASSERT_EQ(a.width, 300);
  ASSERT_EQ(a.height, 200);
  ASSERT_EQ(b.width, a.width);
  ASSERT_EQ(b.height, a.height);
  int worst = 0, transparent = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) {
    worst = std::max(worst, std::abs(a.rgba[i] - b.rgba[i]));
  }
  for (int r = 0; r < a.height; ++r) {
    for (int c = 0; c < a.width; ++c) transparent += a.At(r, c, 3) == 0;
  }
  EXPECT_LE(worst, 1);
  // The unmeasured block: transparent, at the bottom left (the map's first
  // rows are the figure's lowest).
  EXPECT_EQ(transparent, 20 * 40);
  EXPECT_EQ(a.At(199 - 15, 30, 3), 0);
  EXPECT_EQ(a.At(15, 30, 3), 255);
  // The groove (y = 1 mm, row 100) is the deepest: the palette's first
  // colour, dark violet #2c0e5a, within rounding.
  EXPECT_NEAR(a.At(199 - 100, 0, 0), 0x2c, 12);
  EXPECT_NEAR(a.At(199 - 100, 0, 2), 0x5a, 12);
}

TEST(ImageFigures, AFlatGridIsLeftToGnuplot) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("flat-raster");
  fusion::MapAnalysis map = GroovedMap();
  map.levelled.height_mm.setZero();
  map.levelled.valid.setOnes();
  const FigureSet set = DrawMapFigure(dir.string(), "flat", map);
  ASSERT_TRUE(set.missing.empty()) << set.message;
  const std::string script = Slurp(dir / kFigureData / "figures.gp");
  EXPECT_EQ(script.find("stand_in"), std::string::npos);
  EXPECT_NE(script.find("plot 'figure-data/scan_map.f32' binary"),
            std::string::npos);
  std::vector<Bitmap> images;
  std::vector<std::string> places;
  Images(Slurp(dir / "scan_map.svg"), &images, &places);
  ASSERT_EQ(images.size(), 1u);
  EXPECT_EQ(images[0].width, 300);
}

// The figures of a simulated test (60 cycles with its scan).
struct DrawnTest {
  fs::path dir;
  FigureSet set;
  fusion::TestProducts products;
};

DrawnTest DrawSimulatedTest(const std::string& what) {
  samples::SimulationOptions o = samples::PaperCase("S-RT-R");
  o.cycles = 60;
  const sim::SimulatedTest t = sim::Simulate(o);
  const fusion::FuseOptions options;
  const fusion::TestResult r = fusion::AnalyzeTest(t.record, t.scan, options);
  DrawnTest d{test_support::FreshFolder(what), {}, {}};
  d.products = WriteTestResults(d.dir.string(), "S-RT-R", t.record, r, options);
  d.set = DrawTestFigures(d.dir.string(), "S-RT-R", r, options, d.products);
  return d;
}

// A figure's data file: per block, the table and columns its comment
// names and the rows after its header.
struct Block {
  std::string table;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> SplitAt(const std::string& s, char c) {
  std::vector<std::string> parts(1);
  for (char ch : s) {
    if (ch == c) {
      parts.emplace_back();
    } else {
      parts.back() += ch;
    }
  }
  return parts;
}

std::vector<Block> Blocks(const std::string& text) {
  std::vector<Block> blocks;
  std::istringstream in(text);
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.rfind("# ", 0) == 0) {
      const size_t colon = line.find(": ");
      Block b;
      b.table = line.substr(2, colon - 2);
      std::string names = line.substr(colon + 2);
      names = names.substr(0, names.find(" where"));
      b.columns = SplitAt(names, ',');
      blocks.push_back(b);
      header = true;
    } else if (header) {
      EXPECT_EQ(SplitAt(line, ','), blocks.back().columns);
      header = false;
    } else if (!line.empty()) {
      blocks.back().rows.push_back(SplitAt(line, ','));
    }
  }
  return blocks;
}

// Every figure names the columns it plots; each block of its data holds
// those columns of a table the test's products hold, with the table's
// values (as %.8g), or of a table of the figure's own (the track's
// outline, the minima of J).
TEST(FigureData, EachFigurePlotsNamedColumnsOfTheTestsTables) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const DrawnTest d = DrawSimulatedTest("figure-data");
  ASSERT_TRUE(d.set.missing.empty()) << d.set.message;
  EXPECT_EQ(d.set.shown.size(), 15u);
  int checked = 0;
  for (const auto& e : fs::directory_iterator(d.dir / kFigureData)) {
    if (e.path().extension() != ".csv") continue;
    for (const Block& b : Blocks(Slurp(e.path()))) {
      SCOPED_TRACE(e.path().filename().string() + " " + b.table);
      const fusion::Table* t = d.products.Find(b.table);
      if (t == nullptr) {
        EXPECT_TRUE(b.table == "track_outline" || b.table == "minima");
        continue;
      }
      const std::vector<std::string>& known = fusion::TableColumns(b.table);
      for (const std::string& c : b.columns)
        EXPECT_NE(std::find(known.begin(), known.end(), c), known.end()) << c;
      // The first row of the block is a row of the table.
      if (b.rows.empty() || b.table == "loops.csv") continue;
      const int x = t->ColumnIndex(b.columns[0]),
                y = t->ColumnIndex(b.columns[1]);
      const auto& row0 = t->rows[0];
      EXPECT_EQ(b.rows[0][0], fmt::format("{:.8g}", row0[x]));
      if (std::isfinite(row0[y])) {
        EXPECT_EQ(b.rows[0][1], fmt::format("{:.8g}", row0[y]));
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 25);
}

// Lines of the detail cycle are broken where the sliding direction
// changes: in Fig. 12's data the forward samples end in a blank line and
// the reverse samples follow (no line joins them across the reversal).
TEST(FigureData, TheDetailCyclesLinesBreakAtTheReversal) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const DrawnTest d = DrawSimulatedTest("breaks");
  const std::string data =
      Slurp(d.dir / kFigureData / "fig12_reconstruction.csv");
  const std::string first = data.substr(0, data.find("\n\n\n"));
  // One break inside the first block: forward, then reverse.
  size_t breaks = 0;
  for (size_t at = first.find("\n\n"); at != std::string::npos;
       at = first.find("\n\n", at + 2))
    ++breaks;
  EXPECT_EQ(breaks, 1u);
  const fusion::Table* detail = d.products.Find("detail.csv");
  ASSERT_NE(detail, nullptr);
  const int dir = detail->ColumnIndex("direction");
  size_t forward = 0;
  for (const auto& row : detail->rows) forward += row[dir] > 0;
  // Comment, header and the forward rows before the break.
  const std::string head = first.substr(0, first.find("\n\n"));
  EXPECT_EQ(static_cast<size_t>(std::count(head.begin(), head.end(), '\n')),
            forward + 1);
}

}  // namespace
}  // namespace wearscar::report

namespace wearscar::report {
namespace {

std::vector<SpecimenSeries> Batch(int n) {
  std::vector<SpecimenSeries> specimens;
  for (int i = 0; i < n; ++i) {
    SpecimenSeries s;
    s.name = fmt::format("oak_{:02d}", i + 1);
    s.cycles =
        fusion::Table({"cycle", "mu_hat_force", "J_force", "mu_energy_g"});
    for (int c = 1; c <= 40; ++c)
      s.cycles.rows.push_back({double(c), 0.1 + 0.005 * i, 0.2, 0.11});
    s.wear_rate = NAN;
    specimens.push_back(std::move(s));
  }
  return specimens;
}

// Twelve specimens are not twelve similar colours in one key: each gets a
// panel of its own, drawn over the others in grey, four tics a side; six
// keep one panel with a key.
TEST(AuditFigures, ManySpecimensAreSmallMultiples) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("small-multiples");
  const FigureSet set = DrawAuditFigures(dir.string(), Batch(12));
  ASSERT_TRUE(set.missing.empty()) << set.message;
  std::ifstream in(dir / "figure-data" / "figures.gp");
  const std::string gp((std::istreambuf_iterator<char>(in)),
                       std::istreambuf_iterator<char>());
  const size_t at = gp.find("# audit_fig13_mu_hat");
  ASSERT_NE(at, std::string::npos) << gp.substr(0, 400);
  const std::string fig = gp.substr(at, gp.find("unset multiplot", at) - at);
  EXPECT_NE(fig.find("set multiplot layout 3,4 title"), std::string::npos);
  EXPECT_NE(fig.find("each specimen over the others in grey"),
            std::string::npos);
  int titles = 0;
  for (size_t t = fig.find("set title 'oak_"); t != std::string::npos;
       t = fig.find("set title 'oak_", t + 1))
    ++titles;
  EXPECT_EQ(titles, 12);
  EXPECT_NE(fig.find("lc rgb '#c8c8c8'"), std::string::npos);
  EXPECT_NE(fig.find("set xtics 10\n"), std::string::npos);  // 40 cycles
  const fs::path few = test_support::FreshFolder("one-key");
  ASSERT_TRUE(DrawAuditFigures(few.string(), Batch(6)).missing.empty());
  std::ifstream in6(few / "figure-data" / "figures.gp");
  const std::string gp6((std::istreambuf_iterator<char>(in6)),
                        std::istreambuf_iterator<char>());
  EXPECT_EQ(gp6.find("set multiplot layout"), std::string::npos);
}

// Five specimens whose points nearly coincide: their names beside the
// wear figure's points are placed apart (no two at one offset), where one
// offset stacked them into one unreadable blot.
TEST(AuditFigures, NamesBesideNearbyPointsDoNotOverlap) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("labels");
  std::vector<SpecimenSeries> batch = Batch(5);
  for (int i = 0; i < 5; ++i) {
    batch[i].mu_hat.mean = batch[i].mu_hat.low = batch[i].mu_hat.high =
        0.12 + 0.0001 * i;
    batch[i].wear_rate = 0.1 + 0.0001 * i;
  }
  batch.push_back(batch[0]);  // and one far from them
  batch.back().name = "far";
  batch.back().mu_hat.mean = batch.back().mu_hat.low =
      batch.back().mu_hat.high = 0.2;
  batch.back().wear_rate = 0.3;
  ASSERT_TRUE(DrawAuditFigures(dir.string(), batch).missing.empty());
  std::ifstream in(dir / "figure-data" / "figures.gp");
  const std::string gp((std::istreambuf_iterator<char>(in)),
                       std::istreambuf_iterator<char>());
  std::set<std::string> offsets;
  int labels = 0;
  for (size_t at = gp.find("set label "); at != std::string::npos;
       at = gp.find("set label ", at + 1)) {
    const size_t o = gp.find(" offset ", at);
    offsets.insert(gp.substr(o, gp.find(" font", o) - o));
    ++labels;
  }
  EXPECT_EQ(labels, 6);
  EXPECT_GE(offsets.size(), 5u);  // the five close ones each apart
}

// A batch beyond 30 specimens is one panel of its median per cycle and
// the band of its middle 80%: the figure's size no longer grows with the
// batch's square, and no name is written on an axis or beside a point.
TEST(AuditFigures, ALargeBatchIsItsMedianAndBand) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("band");
  std::vector<SpecimenSeries> batch = Batch(101);
  for (int i = 0; i < 101; ++i) batch[i].wear_rate = 0.1 + 0.001 * i;
  const FigureSet set = DrawAuditFigures(dir.string(), batch);
  ASSERT_TRUE(set.missing.empty()) << set.message;
  std::ifstream in(dir / "figure-data" / "figures.gp");
  const std::string gp((std::istreambuf_iterator<char>(in)),
                       std::istreambuf_iterator<char>());
  EXPECT_EQ(gp.find("set multiplot layout"), std::string::npos);
  EXPECT_NE(gp.find("the batch's 101 specimens per cycle"), std::string::npos);
  EXPECT_EQ(gp.find("'oak_"), std::string::npos);  // no names drawn
  // The percentiles of mu-hat at cycle 1: specimens i give 0.1 + 0.005 i,
  // so the 10th, 50th and 90th are those of i = 10, 50 and 90.
  std::ifstream data(dir / "figure-data" / "audit_fig13_mu_hat.csv");
  std::string line, first;
  while (std::getline(data, line))
    if (!line.empty() && line[0] != '#' && first.empty() &&
        std::isdigit(static_cast<unsigned char>(line[0])))
      first = line;
  double cycle = 0, p10 = 0, p90 = 0;
  ASSERT_EQ(std::sscanf(first.c_str(), "%lf,%lf,%lf", &cycle, &p10, &p90), 3)
      << first;
  EXPECT_EQ(cycle, 1);
  EXPECT_NEAR(p10, 0.15, 1e-9);
  EXPECT_NEAR(p90, 0.55, 1e-9);
  EXPECT_LT(fs::file_size(dir / "audit_fig13_mu_hat.svg"), 100000u);
}

// Fig. 16 of a batch too large to name draws each specimen's interval and
// mean as strokes, a few paths in all: a marker per specimen made 4,000
// SVG elements at 1,000 specimens, which held the report's index in a
// browser for most of a second. The strokes are the intervals' own ends.
TEST(AuditFigures, ALargeBatchsDifferencesAreStrokesNotMarkers) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path dir = test_support::FreshFolder("difference-strokes");
  std::vector<SpecimenSeries> batch = Batch(300);
  for (int i = 0; i < 300; ++i) {
    batch[i].diff_mean.mean = 0.001 * i;
    batch[i].diff_mean.low = 0.001 * i - 0.002;
    batch[i].diff_mean.high = 0.001 * i + 0.003;
    batch[i].diff_energy.mean = -0.001 * i;
    batch[i].diff_energy.low = -0.001 * i - 0.001;
    batch[i].diff_energy.high = -0.001 * i + 0.001;
  }
  ASSERT_TRUE(DrawAuditFigures(dir.string(), batch).missing.empty());
  std::ifstream in(dir / "audit_fig16_differences.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
  int markers = 0, paths = 0;
  for (size_t at = svg.find("<use"); at != std::string::npos;
       at = svg.find("<use", at + 1))
    ++markers;
  for (size_t at = svg.find("<path"); at != std::string::npos;
       at = svg.find("<path", at + 1))
    ++paths;
  EXPECT_LT(markers, 20) << "a marker per specimen";
  EXPECT_LT(paths, 100);
  EXPECT_LT(svg.size(), 150000u);
  // Specimen 7's strokes: its interval from 0.005 up 0.005, its mean 0.007
  // from x = 6.6 across 0.8; the energy's interval from -0.008 up 0.002.
  std::ifstream data(dir / "figure-data" / "audit_fig16_differences.csv");
  const std::vector<std::array<double, 4>> want = {
      {7, 0.005, 0, 0.005}, {6.6, 0.007, 0.8, 0}, {7, -0.008, 0, 0.002}};
  std::vector<bool> found(want.size(), false);
  std::string line;
  while (std::getline(data, line)) {
    std::array<double, 4> v{};
    if (std::sscanf(
            line.c_str(), "%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3]) != 4)
      continue;
    for (size_t k = 0; k < want.size(); ++k) {
      bool same = true;
      for (int c = 0; c < 4; ++c) same &= std::abs(v[c] - want[k][c]) < 1e-9;
      found[k] = found[k] || same;
    }
  }
  for (size_t k = 0; k < want.size(); ++k) EXPECT_TRUE(found[k]) << k;
}

}  // namespace
}  // namespace wearscar::report
