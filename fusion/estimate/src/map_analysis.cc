#include "wearscar/fusion/map_analysis.h"

namespace wearscar::fusion {

bool MapAnalysisOptions::IsValid(std::string* why) const {
  if (!level.IsValid(why) || !track.IsValid(why) || !profile.IsValid(why))
    return false;
  if (!(section_half_width_mm > 0)) {
    if (why) *why = "section_half_width_mm must be > 0";
    return false;
  }
  return true;
}

MapAnalysis AnalyzeMap(scan::HeightMap map, const MapAnalysisOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw scan::ScanError("scan analysis options: " + why);
  MapAnalysis a;
  a.level = scan::LevelHeightMap(&map, o.level);
  a.spikes_removed = scan::RemoveSpikes(&map, o.spikes);
  try {
    a.track = scan::FindTrack(map, o.track);
  } catch (const scan::NoTrackError& e) {
    a.no_track = e.what();
  }
  if (a.track) {
    a.centreline = scan::ExtractCentreline(map, *a.track, o.profile);
    a.sections_mm = o.sections_mm;
    if (a.sections_mm.empty()) {
      const double l = a.track->length_mm;
      a.sections_mm = {-0.25 * l, 0.0, 0.25 * l};
    }
    for (double s : a.sections_mm) {
      a.sections.push_back(
          scan::ExtractCrossSection(map, *a.track, s, o.section_half_width_mm));
    }
  }
  a.levelled = std::move(map);
  return a;
}

}  // namespace wearscar::fusion
