#pragma once
// Whether the scan is this test's track and this specimen's: the home of
// the rules that doubt a scan (the track's length against the stroke, the
// track's centre against where the stroke ran, the waviness against
// P/S's), decided once on the comparison. The scan identity's analysis
// unit (fusion/units) runs it before the verdict, which reads its result
// (MismatchReport::Identity); the assumptions and result.json say it from
// there.

#include <string>
#include <vector>

#include "wearscar/scan/track.h"

namespace wearscar::fusion {

struct MismatchReport;
struct VerdictOptions;

struct ScanIdentity {
  // A scan compared with P/S or a depth channel's profile (not with the
  // friction's, integrated from the friction, whose errors are not a
  // sensor's noise): nothing below holds otherwise.
  bool judged = false;
  // The waviness lines up a period away as well (rings of one width), at
  // least VerdictOptions::min_waviness_twin.
  bool lines_up_twice = false;
  // The premise of the waviness's test, held: the waviness stands above
  // its noise and lines up at one place only or the track's place against
  // the stroke is known (which tells a twin lined up elsewhere).
  bool checkable = false;
  // The findings, each with its words ("" none): the track's length unlike
  // the stroke's (another test's), the track's centre away from where the
  // stroke ran, the waviness below this specimen's (another specimen's).
  bool another_test = false, moved = false, foreign = false;
  std::string length_text, centre_text, waviness_text;

  bool Doubted() const { return another_test || moved || foreign; }
  // The verdict's reasons, in order (length, centre, waviness).
  std::vector<std::string> Reasons() const;
  // The doubt said while the force side alone passes, "" where no
  // finding: another test's track first, then another specimen's.
  std::string Doubt() const;
};

ScanIdentity JudgeScanIdentity(const MismatchReport& r,
                               const VerdictOptions& o);

// The track's length is what this test's stroke wears: at least the
// stroke, at most the stroke and the track's width beside it, within
// VerdictOptions::track_length_tolerance of the stroke and two pixels.
bool TrackLengthFitsStroke(double length_mm,
                           double width_mm,
                           double stroke_mm,
                           double pixel_mm,
                           const VerdictOptions& o);

// A track found with low confidence for its elongation alone (deep above
// the roughness) whose length this test's stroke wears: a short stroke's
// track, only its width longer than the stroke, not texture. Its outline
// still does not place it (scan::Track::PlaceKnown).
bool ShortStrokesTrack(const scan::Track& t,
                       double stroke_mm,
                       double pixel_mm,
                       const scan::TrackOptions& track,
                       const VerdictOptions& o);

}  // namespace wearscar::fusion
