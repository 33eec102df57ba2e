// A short stroke's track (scan_identity.h, ShortStrokesTrack): only its
// width longer than the stroke, it is less than three times as long as
// wide and the scan's reader finds it with low confidence ("it may be
// texture"). Where its length is what the stroke wears and it stands deep
// above the roughness, it is taken as the wear track and said so among the
// assumptions, not warned of; any other low-confidence track still is.

#include <gtest/gtest.h>

#include <string>

#include "common/histories.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/scan_identity.h"
#include "wearscar/fusion/verdict_options.h"

namespace wearscar::fusion {
namespace {

scan::Track ShortTrack() {
  scan::Track t;
  t.low_confidence = true;
  t.elongation = 2.6;
  t.length_mm = 4.6;
  t.width_mm = 1.9;
  t.depth_to_roughness = 40;
  return t;
}

TEST(ShortStroke, ALengthTheStrokeWearsAndADepthAboveTheRoughness) {
  const scan::TrackOptions track;
  const VerdictOptions o;
  const double stroke = 3.0, pixel = 0.0074;
  EXPECT_TRUE(ShortStrokesTrack(ShortTrack(), stroke, pixel, track, o));
  scan::Track t = ShortTrack();
  t.length_mm = 6.0;  // longer than the stroke and the track's width
  EXPECT_FALSE(ShortStrokesTrack(t, stroke, pixel, track, o));
  t = ShortTrack();
  t.length_mm = 2.5;  // shorter than the stroke
  EXPECT_FALSE(ShortStrokesTrack(t, stroke, pixel, track, o));
  t = ShortTrack();
  t.depth_to_roughness = 2.0;  // barely deeper than the roughness
  EXPECT_FALSE(ShortStrokesTrack(t, stroke, pixel, track, o));
  t = ShortTrack();
  t.reaches_edge = true;  // its length the field's
  EXPECT_FALSE(ShortStrokesTrack(t, stroke, pixel, track, o));
  t = ShortTrack();
  t.low_confidence = false;  // nothing to answer
  EXPECT_FALSE(ShortStrokesTrack(t, stroke, pixel, track, o));
}

bool Says(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& l : lines)
    if (l.find(what) != std::string::npos) return true;
  return false;
}

// The project's simulator on a 3 mm stroke, both woods: the track 2.5-2.9
// times as long as wide, found with low confidence, taken as the wear
// track; the same track given with a 5.7 mm stroke's record is warned of.
TEST(ShortStroke, ATrackTheStrokeExplainsIsAssumedNotWarnedOf) {
  for (const char* name : {"S-RT-R", "B-RT-R"}) {
    samples::SimulationOptions o = samples::PaperCase(name, false);
    o.cycles = 60;
    o.amplitude_mm = 1.5;
    const sim::SimulatedTest t = sim::Simulate(o);
    const TestResult r = AnalyzeTest(t.record, t.scan, sim::WithoutLugre());
    ASSERT_TRUE(r.scan.has_value()) << name;
    EXPECT_TRUE(r.scan->track.low_confidence) << name;
    EXPECT_TRUE(r.verdict.explained) << name;
    EXPECT_FALSE(Says(r.warnings, "it may be texture")) << name;
    EXPECT_TRUE(Says(r.assumptions,
                     "the scan's track is taken as the wear track although "
                     "it is only"))
        << name;
    EXPECT_TRUE(Says(r.assumptions, "the stroke of 3.00 mm")) << name;

    const sim::SimulatedTest longer = sim::HistoryCase(name, 1.0, 0, 60);
    const TestResult l =
        AnalyzeTest(longer.record, t.scan, sim::WithoutLugre());
    EXPECT_TRUE(Says(l.warnings, "it may be texture")) << name;
    EXPECT_FALSE(Says(l.assumptions, "taken as the wear track")) << name;
  }
}

}  // namespace
}  // namespace wearscar::fusion
