#pragma once

#include <string>
#include <vector>

#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"

namespace wearscar::report {

// The files each figure is drawn as. SVG (vector: any browser, office
// suite or journal takes it) is the default: gnuplot draws it in a quarter
// of the time of its PNG.
struct FigureFormats {
  bool svg = true;
  bool png = false;

  // From "svg", "png" or both joined by a comma.
  static bool Parse(const std::string& text, FigureFormats* formats);
  // "svg", "png" or "svg,png".
  std::string Text() const;
  // At least one format.
  bool IsValid(std::string* why) const;
};

// Figures drawn by gnuplot into a folder.
struct FigureSet {
  // One file per figure drawn, in display order: its PNG when PNG was
  // drawn, else its SVG (what a report shows).
  std::vector<std::string> shown;
  std::vector<std::string> titles;
  std::vector<std::string> files;  // every file drawn, in every format
  std::string message;             // empty when everything was drawn
  // Figures asked for and not drawn (or drawn empty): file names.
  std::vector<std::string> missing;
};

// What the figures are drawn from besides the result tables (gnuplot
// scripts and their logs, the downsampled map, the track outline) goes
// into this sub-folder of the output folder.
inline constexpr const char* kFigureData = "figure-data";

// <dir>/figure-data/<file>, creating the sub-folder.
std::string FigureDataPath(const std::string& dir, const std::string& file);

// Runs gnuplot on the script <dir>/figure-data/<script> in `dir` and waits;
// its output goes to figure-data/<stem>.log. False when it failed.
bool RunGnuplotScript(const std::string& dir, const std::string& script);

// True when gnuplot runs; `why` says what is missing otherwise.
bool PlotterAvailable(std::string* why);

// The figures of one test (the paper's Figs. 5-8, 10-15, 17, the friction
// map and the track's history), drawn by gnuplot from the test's tables in
// `products` (MakeTestProducts) into `dir`; each figure's columns go to
// figure-data/<figure>.csv, the script to figure-data/figures.gp. Images
// are painted by this program into the SVG (gnuplot draws them in PNG).
FigureSet DrawTestFigures(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& result,
                          const fusion::FuseOptions& options,
                          const fusion::TestProducts& products,
                          const FigureFormats& formats = {});

// The levelled map of `wearscar scan` with axes in mm, a colour bar in um,
// a scale bar and the track when one was found (scan_map.svg / .png).
FigureSet DrawMapFigure(const std::string& dir,
                        const std::string& name,
                        const fusion::MapAnalysis& map,
                        const FigureFormats& formats = {});

// Figures across specimens (Figs. 13-16 for a batch) into `dir`.
struct SpecimenSeries {
  std::string name;
  // Its cycles.csv (at least cycle, mu_hat_force, J_force, mu_energy_g).
  fusion::Table cycles;
  // Over the compared cycles, with their 95% intervals: mu-hat minus the
  // mean and the energy COF (Fig. 16), and mu-hat (k from P).
  fusion::Statistic diff_mean, diff_energy, mu_hat;
  double wear_rate = 0;  // mm^3/(N m); NaN without a scan
};
FigureSet DrawAuditFigures(const std::string& dir,
                           const std::vector<SpecimenSeries>& specimens,
                           const FigureFormats& formats = {});

}  // namespace wearscar::report
