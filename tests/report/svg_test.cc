// Every figure of a full-size test and of an audit, read as the SVG files
// a reader opens: no text under 14 px, a unit on every axis, and no line
// that runs across a reversal of the stroke (from the end of one stroke
// into the next) or along x and back.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <pugixml.hpp>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "common/simulated.h"
#include "report_helpers.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/report/audit.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/specimen_folder.h"
#include "wearscar/scan/gsf.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;
using test_support::FreshFolder;
using test_support::Slurp;

// The font size in px an element is drawn with: its own or its nearest
// ancestor's font-size attribute or style; 0 when none says.
double FontSize(pugi::xml_node n) {
  static const std::regex in_style(R"(font-size:\s*([0-9.]+))");
  for (; n; n = n.parent()) {
    if (const pugi::xml_attribute a = n.attribute("font-size"))
      return std::atof(a.value());
    std::cmatch m;
    const char* style = n.attribute("style").value();
    if (std::regex_search(style, m, in_style)) return std::stod(m[1]);
  }
  return 0;
}

struct SvgFacts {
  int texts = 0;
  double smallest_font = INFINITY;
  std::set<std::string> strings;       // every text's content
  std::vector<std::string> reversing;  // open lines that turn back in x
  int lines = 0;                       // open lines checked
};

// An open line's points turn back in x: after moving more than 3 px one
// way, x retreats more than 3 px from its furthest point (noise in a
// stroke's x is well under a pixel at 1200 px).
bool TurnsBack(const std::vector<double>& x) {
  constexpr double kPx = 3;
  int heading = 0;
  double extreme = x.front();
  for (double v : x) {
    if (heading == 0) {
      if (std::abs(v - extreme) > kPx) heading = v > extreme ? 1 : -1;
      if (heading != 0) extreme = v;
      continue;
    }
    if ((v - extreme) * heading > 0) extreme = v;
    if ((extreme - v) * heading > kPx) return true;
  }
  return false;
}

SvgFacts ReadSvg(const fs::path& path) {
  SvgFacts f;
  pugi::xml_document doc;
  const pugi::xml_parse_result ok = doc.load_file(path.c_str());
  EXPECT_TRUE(ok) << path << ": " << ok.description();
  for (const pugi::xpath_node& t : doc.select_nodes("//text")) {
    ++f.texts;
    f.smallest_font = std::min(f.smallest_font, FontSize(t.node()));
    f.strings.insert(t.node().child_value());
  }
  static const std::regex point(R"((-?[0-9.]+),(-?[0-9.]+))");
  for (const pugi::xpath_node& p : doc.select_nodes("//path")) {
    const std::string d = p.node().attribute("d").value();
    const std::string fill = p.node().attribute("fill").value();
    // Frames, keys' boxes and filled bands are closed shapes, not lines.
    if (d.find('Z') != std::string::npos || (!fill.empty() && fill != "none"))
      continue;
    // Each "M" starts a line of its own.
    size_t at = d.find('M');
    while (at != std::string::npos) {
      const size_t next = d.find('M', at + 1);
      const std::string sub = d.substr(at, next - at);
      std::vector<double> x;
      for (std::sregex_iterator i(sub.begin(), sub.end(), point), end; i != end;
           ++i)
        x.push_back(std::stod((*i)[1]));
      if (x.size() >= 3) {
        ++f.lines;
        if (TurnsBack(x))
          f.reversing.push_back(path.filename().string() + ": " +
                                sub.substr(0, 80));
      }
      at = next;
    }
  }
  return f;
}

// The axis labels a figure script sets ("set xlabel 'x (mm)'"), and the
// panels ("plot ...") drawn without an x or y label. Small multiples (a
// grid of more than one column) share their axes' labels along the grid's
// left column and bottom row; their panels are counted apart.
struct ScriptLabels {
  std::vector<std::string> labels;
  int panels = 0, unlabelled = 0, grid_panels = 0;
};

ScriptLabels ReadLabels(const fs::path& gp) {
  ScriptLabels s;
  static const std::regex label(R"(^set ([xyc]b?)label '(.*)'$)");
  static const std::regex grid(R"(^set multiplot layout \d+,(\d+).*)");
  std::ifstream in(gp);
  bool x = false, y = false, in_grid = false;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, label)) {
      s.labels.push_back(m[2]);
      if (m[1] == "x") x = true;
      if (m[1] == "y") y = true;
    } else if (std::regex_match(line, m, grid)) {
      in_grid = std::stoi(m[1]) > 1;
    } else if (line.rfind("unset multiplot", 0) == 0) {
      in_grid = false;
    } else if (line.rfind("plot ", 0) == 0) {
      ++s.panels;
      if (in_grid) {
        ++s.grid_panels;
      } else if (!x || !y) {
        ++s.unlabelled;
      }
    } else if (line.rfind("reset session", 0) == 0) {
      x = y = false;
    } else if (line.rfind("unset xlabel", 0) == 0) {
      x = false;
    } else if (line.rfind("unset ylabel", 0) == 0) {
      y = false;
    }
  }
  return s;
}

// A unit in parentheses ends the label ("Q (N)", "mu (-)", "wear rate
// (mm^3/(N m))"); a count of cycles and a list of specimens have none.
bool HasUnit(const std::string& label) {
  static const std::regex unit(R"(.*\(.+\)\s*$)");
  return label == "cycle" || label == "specimen" ||
         std::regex_match(label, unit);
}

void CheckFolder(const fs::path& dir, int expected_figures) {
  int figures = 0, lines = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".svg") continue;
    ++figures;
    SCOPED_TRACE(e.path().string());
    const SvgFacts f = ReadSvg(e.path());
    EXPECT_GT(f.texts, 5);
    lines += f.lines;
    EXPECT_GE(f.smallest_font, 14);
    EXPECT_TRUE(f.reversing.empty())
        << f.reversing.size() << " lines turn back, the first "
        << f.reversing.front();
  }
  EXPECT_EQ(figures, expected_figures) << dir;
  EXPECT_GE(lines, 2 * figures) << dir;
  // The scripts the figures were drawn with: every panel labelled on both
  // axes, every label with its unit and drawn in the figures.
  std::set<std::string> drawn;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".svg") {
      const SvgFacts f = ReadSvg(e.path());
      drawn.insert(f.strings.begin(), f.strings.end());
    }
  int scripts = 0;
  for (const auto& e : fs::directory_iterator(dir / "figure-data")) {
    if (e.path().extension() != ".gp") continue;
    ++scripts;
    const ScriptLabels s = ReadLabels(e.path());
    EXPECT_GT(s.panels, 0) << e.path();
    EXPECT_EQ(s.unlabelled, 0) << e.path();
    for (const std::string& l : s.labels) {
      EXPECT_TRUE(HasUnit(l)) << e.path() << ": '" << l << "'";
      EXPECT_TRUE(drawn.count(l)) << e.path() << ": '" << l << "' not drawn";
    }
  }
  EXPECT_GE(scripts, 1) << dir;
}

// The paper's B-RT-R at full size (600 cycles at 2 kHz, a 1024 x 768
// scan): its 15 figures (the last the scan's shape per cycle, a unit's).
TEST(SvgFigures, AFullSizeTestsFiguresAreReadable) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  ASSERT_EQ(o.cycles, 600);
  const sim::SimulatedTest t = sim::Simulate(o);
  const fusion::FuseOptions options;
  const fusion::TestResult r = fusion::AnalyzeTest(t.record, t.scan, options);
  const fs::path dir = FreshFolder("svg-full-size");
  const fusion::TestProducts products =
      WriteTestResults(dir.string(), "B-RT-R", t.record, r, options);
  const FigureSet set =
      DrawTestFigures(dir.string(), "B-RT-R", r, options, products);
  ASSERT_TRUE(set.missing.empty()) << set.message;
  CheckFolder(dir, 15);
  EXPECT_TRUE(fs::exists(dir / "fig_scan_shape_history.svg"));
  fs::remove_all(dir);
}

// An audit of seven specimens (more than one key holds: small multiples),
// one of them flagged: each specimen's figures and the batch's; and the
// flagged one's diagnosis figure.
TEST(SvgFigures, AnAuditsFiguresAreReadable) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path in = FreshFolder("svg-audit-in");
  const std::vector<std::string> cases = {
      "B-RT-R", "B-RT-T", "B-RL-R", "S-RT-R", "S-RL-R", "S-TL-L", "B-TL-T"};
  for (const std::string& c : cases) {
    samples::SimulationOptions o = samples::PaperCase(c);
    o.cycles = 60;
    o.scan_cols = 384;
    o.scan_rows = 288;
    o.scan_pitch_mm = 0.0198;
    const sim::SimulatedTest t = sim::Simulate(o);
    force::WriteForceCsv(t.record, (in / (c + ".force.csv")).string());
    scan::WriteGsf(t.scan, (in / (c + ".scan.gsf")).string());
  }
  const fs::path out = FreshFolder("svg-audit-out");
  AuditOptions options;
  const AuditResult r = Audit(fusion::FindSpecimens(in.string(), options.batch),
                              out.string(),
                              "seven specimens",
                              options);
  ASSERT_EQ(r.failed, 0);
  ASSERT_GE(r.flagged, 1);  // S-RL-R, with its elastic part
  CheckFolder(out, 5);
  // The flagged specimen diagnosed as `audit --diagnose` does, its figure
  // beside the others.
  const std::string flagged = (in / "S-RL-R.force.csv").string();
  const force::ForceRecord record = force::ReadForceFile(flagged);
  const fusion::TestResult result = fusion::AnalyzeTest(
      record, scan::ReadScan((in / "S-RL-R.scan.gsf").string()), options.fuse);
  const fusion::Diagnosis d =
      fusion::DiagnoseTest(record, result, options.fuse);
  const FigureSet shown =
      WriteDiagnosis((out / "S-RL-R").string(), "S-RL-R", d, true);
  ASSERT_EQ(shown.shown.size(), 2u);  // nothing along the track named
  EXPECT_EQ(fs::path(shown.shown[1]).stem(), "diagnosis_direction_split");
  EXPECT_EQ(shown.titles[1],
            "S-RL-R: diagnosis, the residual split by direction");
  for (const std::string& c : cases) {
    SCOPED_TRACE(c);
    // The diagnosis adds its residual map and its direction split.
    CheckFolder(out / c, c == "S-RL-R" ? 17 : 15);
  }
  fs::remove_all(in);
  fs::remove_all(out);
}

}  // namespace
}  // namespace wearscar::report
