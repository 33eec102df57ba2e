#pragma once
// The path of a sphere that rides a worn track: its lowest point as it
// rests on the scanned surface, at each position along the track's axis.
// The sphere does not follow the centreline: along the track its centre
// follows the surface dilated by the sphere (the ball envelope of ISO
// 16610-41's morphological filters), which bridges the valleys that curve
// tighter than 1/R, so where the waviness curves at nearly 1/R the two
// differ; across the track its contact patch spans the groove it carved
// and averages the roughness it presses on. This is the path whose slope
// tilts the contact.

#include <string>

#include "wearscar/scan/height_map.h"
#include "wearscar/scan/track.h"

namespace wearscar::scan {

struct SpherePathOptions {
  double radius_mm = 3.25;  // the sphere's (the paper's); 0: no sphere
  double step_mm = 0.01;    // along the axis, and the surface's grid
  double extend_mm = 0.0;   // beyond the track's ends
  // The surface searched around each position: the track's half width (the
  // sphere's contact in its own groove), at least this.
  double min_reach_mm = 0.2;
  bool IsValid(std::string* why) const;
};

// Requires levelled.IsConsistent(). Heights as the centreline's (the
// sphere's lowest point), NaN where the surface under the sphere's centre,
// or over two thirds of its reach along the track, was not measured. Throws
// ScanError for invalid options or a track too long for the grid.
WearProfile SpherePath(const HeightMap& levelled,
                       const Track& track,
                       const SpherePathOptions& options = {});

}  // namespace wearscar::scan
