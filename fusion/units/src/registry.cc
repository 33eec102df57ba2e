// The registry of analysis units: one line per unit, in the order they
// run within a stage and write their products (unit.h).

#include <fmt/format.h>

#include <cmath>

#include "units.h"

namespace wearscar::fusion {

const std::vector<const AnalysisUnit*>& AnalysisUnits() {
  static const std::vector<const AnalysisUnit*> kUnits = {
      &internal::ClassicCofsAnalysis(),
      &internal::SpringFitAnalysis(),
      &internal::DepthFitAnalysis(),
      &internal::ScanFitAnalysis(),
      &internal::PeriodicLinesAnalysis(),
      &internal::SlidingAnalysis(),
      &internal::LugreAnalysis(),
      &internal::FrictionMapAnalysis(),
      &internal::TrackHistoryAnalysis(),
      &internal::ScanIdentityAnalysis(),
      &internal::SpringCheckAnalysis(),
      &internal::ScreenAnalysis(),
      &internal::ScanShapeAnalysis(),
      &internal::WearAnalysis(),
      &internal::DetailCycleAnalysis(),
  };
  return kUnits;
}

nlohmann::json StatisticJson(const Statistic& s) {
  nlohmann::json j = {{"mean", s.mean}, {"sd", s.sd}, {"count", s.count}};
  if (std::isfinite(s.low)) {
    j["interval95"] = {s.low, s.high};
    j["effective_cycles"] = s.effective_count;
  }
  return j;
}

std::string GridRanges(const std::vector<double>& x_mm, int cycles) {
  const double half = 0.5 * (x_mm[1] - x_mm[0]);
  return fmt::format("set xrange [{}:{}]\nset yrange [0.5:{}]\n",
                     x_mm.front() - half,
                     x_mm.back() + half,
                     cycles + 0.5);
}

}  // namespace wearscar::fusion
