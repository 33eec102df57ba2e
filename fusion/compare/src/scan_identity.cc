// The rules that doubt a scan (scan_identity.h), decided once.
#include "wearscar/fusion/scan_identity.h"

#include <fmt/format.h>

#include <cmath>

#include "wearscar/fusion/mismatch.h"
#include "wearscar/fusion/verdict_options.h"

namespace wearscar::fusion {
namespace {

// The waviness lines up elsewhere too (VerdictOptions::min_waviness_twin).
bool LinesUpTwice(const MismatchReport& r, const VerdictOptions& o) {
  return r.waviness_runner_up >= o.min_waviness_twin;
}

// Checkable where the waviness stands above its noise and either lines up
// at one place only or the track's place against the stroke is known.
bool Checkable(const MismatchReport& r, const VerdictOptions& o) {
  return r.has_scan && r.identity_judged &&
         r.waviness_to_noise >= o.min_waviness_to_noise &&
         std::isfinite(r.waviness_correlation) &&
         (!LinesUpTwice(r, o) || std::isfinite(r.centre_offset_mm));
}

bool Foreign(const MismatchReport& r, const VerdictOptions& o) {
  return Checkable(r, o) && r.waviness_correlation < o.min_waviness_correlation;
}

bool TrackLengthDiffers(const MismatchReport& r, const VerdictOptions& o) {
  return r.has_scan && r.track_length_mm > 0 && r.stroke_mm > 0 &&
         r.track_width_mm >= 0 &&
         !TrackLengthFitsStroke(r.track_length_mm,
                                r.track_width_mm,
                                r.stroke_mm,
                                r.scan_pixel_mm,
                                o);
}

bool TrackCentreMoved(const MismatchReport& r, const VerdictOptions& o) {
  // As the waviness, judged against P/S or a depth channel's profile (the
  // friction's, integrated, aligns less surely).
  if (!(r.has_scan && r.identity_judged && std::isfinite(r.centre_offset_mm) &&
        r.track_width_mm > 0))
    return false;
  const double w = r.track_width_mm, outline = r.centre_offset_mm,
               walls = r.ends_offset_mm;
  if (std::abs(outline) > o.max_centre_offset * w) return true;
  return std::isfinite(walls) && outline * walls > 0 &&
         std::abs(outline) > o.max_centre_offset_agreed * w &&
         std::abs(walls) > o.max_centre_offset_agreed * w;
}

// The waviness of another specimen's track.
std::string ForeignWaviness(const MismatchReport& r, const VerdictOptions& o) {
  return fmt::format(
      "the scan's waviness (its rings and texture, the groove's shape "
      "removed) correlates with P/S's at r = {:.2f} (corrected for noise; "
      "limit {:.2f}: this specimen's own scan leaves only what the model "
      "misses of the sphere's path), although the whole profiles correlate "
      "at r = {:.2f} (the groove's shape, common to every track of a case)",
      r.waviness_correlation,
      o.min_waviness_correlation,
      r.correlation);
}

std::string TrackLengthText(const MismatchReport& r, const VerdictOptions& o) {
  return fmt::format(
      "its worn track is {:.2f} mm long, while this test's stroke of {:.2f} "
      "mm wears one of {:.2f}-{:.2f} mm (the stroke and up to the track's "
      "width beyond it; tolerance {:g}% of the stroke): another test's "
      "track, or a wrong pixel size or x unit",
      r.track_length_mm,
      r.stroke_mm,
      r.stroke_mm,
      r.stroke_mm + r.track_width_mm,
      100 * o.track_length_tolerance);
}

std::string CentreText(const MismatchReport& r, const VerdictOptions& o) {
  if (std::abs(r.centre_offset_mm) <= o.max_centre_offset * r.track_width_mm)
    return fmt::format(
        "it matches P/S only with its track {:.2f} mm (its outline's "
        "centre) and {:.2f} mm (the sphere's reversals on its end walls) "
        "from where the stroke ran (limit {:g} of the track's width, {:.2f} "
        "mm, where the two agree): its waviness (r = {:.2f}) lines up "
        "elsewhere",
        r.centre_offset_mm,
        r.ends_offset_mm,
        o.max_centre_offset_agreed,
        o.max_centre_offset_agreed * r.track_width_mm,
        r.waviness_correlation);
  return fmt::format(
      "it matches P/S only with its track's centre {:.2f} mm from the "
      "stroke's (limit {:g} of the track's width, {:.2f} mm): its waviness "
      "(r = {:.2f}) lines up elsewhere than where the stroke ran",
      r.centre_offset_mm,
      o.max_centre_offset,
      o.max_centre_offset * r.track_width_mm,
      r.waviness_correlation);
}

}  // namespace

const ScanIdentity& MismatchReport::Identity() const {
  static const ScanIdentity kNone{};
  return scan_identity ? *scan_identity : kNone;
}

std::vector<std::string> ScanIdentity::Reasons() const {
  std::vector<std::string> out;
  if (another_test)
    out.push_back("the scan may be another test's: " + length_text);
  if (moved)
    out.push_back("the scan may be another specimen's: " + centre_text);
  if (foreign) out.push_back(waviness_text);
  return out;
}

std::string ScanIdentity::Doubt() const {
  if (another_test)
    return "the scan may belong to another test: " + length_text +
           "; the verdict is judged on the force side (check that the scan "
           "is this test's)";
  if (moved || foreign)
    return "the scan may belong to another specimen: " +
           (moved ? centre_text : waviness_text) +
           "; the verdict is judged on the force side (check that the scan "
           "is this specimen's)";
  return "";
}

bool TrackLengthFitsStroke(double length_mm,
                           double width_mm,
                           double stroke_mm,
                           double pixel_mm,
                           const VerdictOptions& o) {
  const double slack = o.track_length_tolerance * stroke_mm + 2 * pixel_mm;
  return length_mm >= stroke_mm - slack &&
         length_mm <= stroke_mm + width_mm + slack;
}

bool ShortStrokesTrack(const scan::Track& t,
                       double stroke_mm,
                       double pixel_mm,
                       const scan::TrackOptions& track,
                       const VerdictOptions& o) {
  return t.low_confidence && !t.manual && !t.reaches_edge &&
         t.depth_to_roughness >= track.confident_depth_to_roughness &&
         stroke_mm > 0 && t.width_mm > 0 &&
         TrackLengthFitsStroke(t.length_mm, t.width_mm, stroke_mm, pixel_mm, o);
}

ScanIdentity JudgeScanIdentity(const MismatchReport& r,
                               const VerdictOptions& o) {
  ScanIdentity id;
  if (!r.has_scan) return id;
  id.judged = r.identity_judged;
  id.lines_up_twice = LinesUpTwice(r, o);
  id.checkable = Checkable(r, o);
  id.another_test = TrackLengthDiffers(r, o);
  id.moved = TrackCentreMoved(r, o);
  id.foreign = Foreign(r, o);
  if (id.another_test) id.length_text = TrackLengthText(r, o);
  if (id.moved) id.centre_text = CentreText(r, o);
  if (id.foreign) id.waviness_text = ForeignWaviness(r, o);
  return id;
}

}  // namespace wearscar::fusion
