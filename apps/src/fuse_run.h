#pragma once
// `wearscar fuse` as a function: `wearscar watch` ends with it, so that a
// test followed live ends with the products fuse gives of the finished
// file.

#include <string>
#include <vector>

#include "setting_flags.h"
#include "wearscar/fusion/products.h"
#include "wearscar/report/figures.h"

namespace wearscar::app {

struct FuseArgs {
  std::string force_file;
  std::string scan_file;
  std::string out;
  std::string name;
  fusion::ProductOptions write;
  int detail_cycle = 0;    // from 1; 0 = the last
  std::vector<int> loops;  // from 1
  bool no_figures = false;
  report::FigureFormats figure_formats;
  GivenSettings given;  // the settings as written
};

// Analyses and writes as `wearscar fuse` does (prints its summary; sets
// the exit status when figures are missing).
void RunFuse(FuseArgs a);

}  // namespace wearscar::app
