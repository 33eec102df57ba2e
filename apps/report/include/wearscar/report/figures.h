#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"

namespace wearscar::report {

// The files each figure is drawn as. SVG (vector: any browser, office
// suite or journal takes it) is the default: gnuplot draws it in a quarter
// of the time of its PNG, three quarters of which go into the PNG's zlib
// compression and filters (measured, README "Speed").
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

// A figure's gnuplot body with each plot command over the CSV tables in
// `dir` reading copies in figure-data (<figure>.<table>) that hold only
// the columns the figure uses, the rows as they are: gnuplot converts
// every field of every row it reads, so this spares it most of them. Each
// rewritten command stays above its copy's as a comment ("# over the
// result tables: plot ..."); a clause it cannot follow (no `using`, a
// column given by an expression) keeps its table. What the figures of
// this module do with every body they draw.
std::string SlimPlotTables(const std::string& dir,
                           const std::string& figure,
                           const std::string& body);

// Runs gnuplot on the script <dir>/figure-data/<script> in `dir` and waits;
// its output goes to figure-data/<stem>.log. False when it failed.
bool RunGnuplotScript(const std::string& dir, const std::string& script);

// One gnuplot kept running for one script after another (an audit's
// worker draws specimen after specimen with it): each script then costs no
// gnuplot start (about 35 ms of CPU and 900 page faults; 82 shared
// libraries). One per thread; the destructor ends gnuplot and waits.
class GnuplotSession {
 public:
  GnuplotSession() = default;
  ~GnuplotSession();
  GnuplotSession(const GnuplotSession&) = delete;
  GnuplotSession& operator=(const GnuplotSession&) = delete;

  // As RunGnuplotScript: the script <dir>/figure-data/<script> with `dir`
  // as the working folder, its messages in figure-data/<stem>.log. False
  // when the script had an error or gnuplot ended (started again on the
  // next call).
  bool Run(const std::string& dir, const std::string& script);

 private:
  bool Start();
  void Stop();
  int pid_ = -1;
  int input_ = -1;               // gnuplot's standard input
  std::FILE* output_ = nullptr;  // its standard output and error
  long serial_ = 0;
};

// True when gnuplot runs; `why` says what is missing otherwise.
bool PlotterAvailable(std::string* why);

// The figures of one test (the paper's Figs. 5-8, 10-15, 17, the friction
// map and the track's history), drawn by gnuplot from the CSV files
// WriteTestResults wrote into `dir`. Writes the scan map data first when
// the result has a scan. With PNG, `processes` gnuplots share the figures
// side by side: 2 keep both cores of a single test busy; 1 where the
// caller's workers already do (SVG alone is drawn by one gnuplot, as fast
// as by two). Images are painted by this program into the SVG (gnuplot
// draws them in PNG). Workers drawing test after test (an audit) use the
// overload below with a GnuplotSession each, sparing a gnuplot start per
// test.
FigureSet DrawTestFigures(const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& result,
                          const fusion::FuseOptions& options,
                          const FigureFormats& formats = {},
                          int processes = 2);
// The same figures drawn by one script in `session`.
FigureSet DrawTestFigures(GnuplotSession* session,
                          const std::string& dir,
                          const std::string& name,
                          const fusion::TestResult& result,
                          const fusion::FuseOptions& options,
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
  std::string dir;  // holding cycles.csv
  // Over the compared cycles, with their 95% intervals: mu-hat minus the
  // mean and the energy COF (Fig. 16), and mu-hat (k from P).
  fusion::Statistic diff_mean, diff_energy, mu_hat;
  double wear_rate = 0;  // mm^3/(N m); NaN without a scan
};
FigureSet DrawAuditFigures(const std::string& dir,
                           const std::vector<SpecimenSeries>& specimens,
                           const FigureFormats& formats = {});

}  // namespace wearscar::report
