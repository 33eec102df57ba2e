#pragma once

#include <string>

#include "wearscar/scan/height_map.h"
#include "wearscar/scan/track.h"

namespace wearscar::scan {

struct PreviewOptions {
  int max_width_px = 1600;  // larger maps are scaled down (area averaging)
  // Height colour scale between these percentiles of the valid heights.
  double low_percentile = 0.01, high_percentile = 0.99;
  bool IsValid(std::string* why) const;
};

// A PNG preview of a levelled map: heights in colour (viridis; invalid
// pixels grey), the detected track's outline (length x width, white), its
// centreline (red) and centre (cross). Returns the PNG bytes.
// A Track of zero length (none was found) draws the map alone.
std::string EncodeTrackPreviewPng(const HeightMap& levelled,
                                  const Track& track,
                                  const PreviewOptions& options = {});

// Same, written to `path` (temporary name, then rename).
void WriteTrackPreviewPng(const HeightMap& levelled,
                          const Track& track,
                          const std::string& path,
                          const PreviewOptions& options = {});

}  // namespace wearscar::scan
