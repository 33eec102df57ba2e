#pragma once

#include <optional>
#include <string>
#include <vector>

#include "wearscar/scan/height_map.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// A height map analysed alone (wearscar scan): levelled, spikes removed,
// the track found (or why not), its centreline and cross-sections.
struct MapAnalysisOptions {
  scan::LevelOptions level;
  scan::SpikeOptions spikes;
  scan::TrackOptions track;
  scan::ProfileOptions profile;
  // Cross-sections at these positions along the track from its centre;
  // empty = at -1/4, 0 and +1/4 of its length.
  std::vector<double> sections_mm;
  double section_half_width_mm = 1.5;

  bool IsValid(std::string* why) const;
};

struct MapAnalysis {
  scan::HeightMap levelled;
  scan::LevelSummary level;
  int spikes_removed = 0;
  std::optional<scan::Track> track;  // absent: no_track says why
  std::string no_track;
  scan::WearProfile centreline;
  std::vector<scan::WearProfile> sections;  // at sections_mm
  std::vector<double> sections_mm;
};

// Throws ScanError for invalid options; a map without a track is analysed
// as far as it goes (no_track set).
MapAnalysis AnalyzeMap(scan::HeightMap map, const MapAnalysisOptions& options);

}  // namespace wearscar::fusion
