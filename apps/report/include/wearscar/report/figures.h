#pragma once

#include <string>
#include <vector>

#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"

namespace wearscar::report {

// The figures of one test (the paper's Figs. 5-8, 10-15, 17), drawn by
// gnuplot from the CSV files WriteTestResults wrote into `dir`, as PNG and
// SVG. Writes the scan map data first when the result has a scan.
struct FigureSet {
  std::vector<std::string> png;  // in display order
  std::vector<std::string> titles;
  std::string message;  // empty when everything was drawn
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

FigureSet DrawTestFigures(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& result,
                          const fusion::FuseOptions& options);

// The levelled map of `wearscar scan` with axes in mm, a colour bar in um,
// a scale bar and the track when one was found (scan_map.png and .svg).
FigureSet DrawMapFigure(const std::string& dir,
                        const std::string& name,
                        const fusion::MapAnalysis& map);

// Figures across specimens (Figs. 13-16 for a batch) into `dir`.
struct SpecimenSeries {
  std::string name;
  std::string dir;  // holding cycles.csv
  // Over the compared cycles, with their 95% intervals: mu-hat minus the
  // mean and the energy COF (Fig. 16), and mu-hat (k from P).
  fusion::Statistic diff_mean, diff_energy, mu_hat;
  double wear_rate = 0;  // mm^3/(N m); NaN without a scan
};
FigureSet DrawAuditFigures(const std::string& dir,
                           const std::vector<SpecimenSeries>& specimens);

}  // namespace wearscar::report
