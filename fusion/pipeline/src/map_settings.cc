// The settings of a scan analysed alone (`wearscar scan`, Python's
// analyze_scan): reading the file, levelling, spikes, the centreline and
// cross-sections, the track.

#include <fmt/format.h>

#include "scan_settings.h"
#include "wearscar/fusion/settings.h"

namespace wearscar::fusion {
namespace {

using internal::ScanFileSettings;
using internal::TrackSettings;
using support::IntegerSetting;
using support::NumberSetting;

using M = MapSettings;

// The map alone: levelling, spikes, centreline and cross-sections.
std::vector<support::Setting<M>> MapAnalysisSettings() {
  const char* g = "Scan";
  auto a = [](M& m) -> MapAnalysisOptions& { return m.analysis; };
  return {
      IntegerSetting<M>(
          "level-order",
          g,
          "Reference surface order (1-3)",
          1,
          3,
          [a](M& m) -> int& { return a(m).level.polynomial_order; }),
      NumberSetting<M>(
          "ransac-threshold",
          g,
          "RANSAC inlier band, mm",
          1e-9,
          10,
          [a](M& m) -> double& { return a(m).level.ransac_threshold_mm; }),
      NumberSetting<M>(
          "spike-threshold",
          g,
          "Spike height, mm",
          1e-9,
          100,
          [a](M& m) -> double& { return a(m).spikes.threshold_mm; }),
      NumberSetting<M>(
          "band",
          g,
          "Centreline band width, mm",
          0,
          100,
          [a](M& m) -> double& { return a(m).profile.band_width_mm; }),
      NumberSetting<M>("step",
                       g,
                       "Centreline step, mm (0 = the pitch)",
                       0,
                       100,
                       [a](M& m) -> double& { return a(m).profile.step_mm; }),
      {"sections",
       g,
       "Cross-sections at these positions along the track from its centre, "
       "mm (comma-separated; default -1/4, 0, +1/4 of its length)",
       "NUMBERS",
       ~0u,
       [](M* m, const std::string& text) {
         size_t start = 0;
         while (start <= text.size()) {
           const size_t comma = std::min(text.find(',', start), text.size());
           m->analysis.sections_mm.push_back(support::ParseNumber(
               text.substr(start, comma - start), -1e4, 1e4));
           start = comma + 1;
         }
       },
       [](const M&) { return std::string(); },
       true},
      NumberSetting<M>(
          "section-half-width",
          g,
          "Cross-section half width, mm",
          1e-6,
          1e3,
          [a](M& m) -> double& { return a(m).section_half_width_mm; }),
  };
}

}  // namespace

const std::vector<support::Setting<MapSettings>>& MapSettingList() {
  static const std::vector<support::Setting<M>> list = [] {
    std::vector<support::Setting<M>> all = ScanFileSettings<M>(
        [](M& m) -> scan::ReadScanOptions& { return m.read_scan; });
    for (auto& s : MapAnalysisSettings()) all.push_back(std::move(s));
    for (auto& s : TrackSettings<M>(
             [](M& m) -> scan::TrackOptions& { return m.analysis.track; }))
      all.push_back(std::move(s));
    return all;
  }();
  return list;
}

MapSettings MakeMapSettings(
    const std::vector<std::pair<std::string, std::string>>& given) {
  MapSettings m;
  support::ApplySettings(MapSettingList(), given, &m);
  std::string why;
  if (!m.analysis.IsValid(&why) || !m.read_scan.IsValid(&why))
    throw support::SettingFailed("", why);
  return m;
}

}  // namespace wearscar::fusion
