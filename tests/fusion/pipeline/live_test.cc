#include "wearscar/fusion/live.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/simulated.h"
#include "wearscar/fusion/analysis.h"

namespace wearscar::fusion {
namespace {

samples::SimulationOptions RunningOptions(const std::string& name,
                                          int cycles,
                                          double rate) {
  samples::SimulationOptions o = samples::PaperCase(name);
  o.cycles = cycles;
  o.sampling_rate_hz = rate;
  o.scan_cols = 32;
  o.scan_rows = 24;
  o.scan_pitch_mm = 0.25;
  return o;
}

sim::SimulatedTest RunningTest(const std::string& name,
                               int cycles,
                               double rate) {
  return sim::Simulate(RunningOptions(name, cycles, rate));
}

force::ForceRecord Rows(const force::ForceRecord& r,
                        Eigen::Index from,
                        Eigen::Index n) {
  force::ForceRecord s;
  s.time_s = r.time_s.segment(from, n);
  s.x_mm = r.x_mm.segment(from, n);
  s.tangential_n = r.tangential_n.segment(from, n);
  s.normal_n = r.normal_n.segment(from, n);
  if (r.has_depth()) s.depth_mm = r.depth_mm.segment(from, n);
  s.metadata = r.metadata;
  return s;
}

struct Followed {
  std::vector<LiveCycle> cycles;
  std::vector<LiveEvent> events;
  Eigen::Index most_samples_held = 0;
};

// The record handed over in pieces of `piece` samples, as a follower
// would.
Followed Follow(const force::ForceRecord& r,
                Eigen::Index piece,
                LiveOptions live = {},
                const FuseOptions& fuse = {}) {
  LiveAnalysis a(fuse, live);
  Followed f;
  for (Eigen::Index at = 0; at < r.size(); at += piece) {
    const Eigen::Index n = std::min(piece, r.size() - at);
    for (const LiveCycle& c : a.Add(Rows(r, at, n))) f.cycles.push_back(c);
    for (const LiveEvent& e : a.TakeEvents()) f.events.push_back(e);
    f.most_samples_held = std::max(f.most_samples_held, a.samples_held());
  }
  return f;
}

const LiveEvent* Find(const std::vector<LiveEvent>& events,
                      const std::string& kind) {
  for (const LiveEvent& e : events)
    if (e.kind == kind) return &e;
  return nullptr;
}

TEST(LiveAnalysis, EachCycleOnceWithTheWholeTestsNumbers) {
  const sim::SimulatedTest t = RunningTest("B-RT-R", 80, 1000);
  const ForceFitted whole = AnalyzeForce(t.record, FuseOptions{}.analysis);
  const std::vector<force::CycleCof> cof =
      force::ComputeClassicCof(t.record, whole.cycles);
  const Followed f = Follow(t.record, 357);
  // Every complete cycle, numbered as the whole test numbers them; the last
  // one completes only with the samples after it.
  ASSERT_EQ(f.cycles.size(), whole.cycles.cycles.size());
  for (size_t c = 0; c < f.cycles.size(); ++c) {
    ASSERT_EQ(f.cycles[c].cycle, static_cast<int>(c) + 1);
    const auto& cycle = whole.cycles.cycles[c];
    EXPECT_NEAR(
        f.cycles[c].end_time_s, t.record.time_s[cycle.reverse.end - 1], 1e-9);
    // The classic COFs need no other cycle: the same numbers.
    EXPECT_NEAR(f.cycles[c].mu_mean, cof[c].mu_mean, 1e-12);
  }
  // mu-hat with k from P over the cycles before (not the centred ensemble
  // of the whole test): the mean after running-in within 0.001 of the whole
  // test's, and the per-cycle values within their own scatter.
  double sum = 0, diff2 = 0;
  int n = 0;
  for (size_t c = whole.running_in.cycles; c < f.cycles.size(); ++c) {
    sum += f.cycles[c].mu_hat;
    const double d = f.cycles[c].mu_hat - whole.fits.cycles[c].mu_hat;
    diff2 += d * d;
    ++n;
  }
  EXPECT_NEAR(sum / n, whole.fits.mu_hat.mean, 0.001);
  EXPECT_LT(std::sqrt(diff2 / n), 3 * whole.fits.mu_hat.sd + 1e-4);
  // J's split from the cycles' own template (the misfits of earlier cycles
  // as reported, the ensemble's width and more before), once there is one:
  // the same share of J in its noise floor as the whole test's (J itself
  // is larger live: k from the cycle and the 5 before it, not 11 around).
  const int sep = FrictionFitOptions{}.ensemble.cycles;
  double live_floor = 0, live_j = 0, whole_floor = 0, whole_j = 0;
  for (size_t c = 0; c < f.cycles.size(); ++c) {
    const LiveCycle& l = f.cycles[c];
    if (static_cast<int>(c) < sep) {
      EXPECT_TRUE(std::isnan(l.cost_floor)) << "cycle " << c + 1;
    }
    if (static_cast<int>(c) < std::max<int>(sep + 2, whole.running_in.cycles))
      continue;
    ASSERT_TRUE(std::isfinite(l.cost_floor)) << "cycle " << c + 1;
    live_floor += l.cost_floor;
    live_j += l.cost;
    whole_floor += whole.fits.cycles[c].cost_floor;
    whole_j += whole.fits.cycles[c].cost;
  }
  EXPECT_NEAR(live_floor / live_j, whole_floor / whole_j, 0.05);
  // The samples held stay within the window, however long the test.
  EXPECT_LT(f.most_samples_held, (LiveOptions{}.window_cycles + 3) * 1000);
}

// The loop shown is the latest cycle's, also when a look completes several
// (the page draws the newest loop, not the first of a look's).
TEST(LiveAnalysis, TheLoopShownIsTheLatestReportedCycles) {
  const sim::SimulatedTest t = RunningTest("B-RT-R", 30, 1000);
  LiveAnalysis a(FuseOptions{});
  int looks_with_several = 0;
  for (Eigen::Index at = 0; at < t.record.size(); at += 4000) {
    const Eigen::Index n = std::min<Eigen::Index>(4000, t.record.size() - at);
    const std::vector<LiveCycle> got = a.Add(Rows(t.record, at, n));
    if (got.empty()) continue;
    looks_with_several += got.size() > 1;
    ASSERT_TRUE(std::isfinite(got.back().mu_hat));
    EXPECT_EQ(a.loop().cycle, got.back().cycle);
    ASSERT_FALSE(a.loop().x_mm.empty());
    // Its samples end where the cycle's reverse half ends: near the stroke's
    // start, x falling.
    EXPECT_EQ(a.loop().direction.back(), -1);
  }
  EXPECT_GT(looks_with_several, 3);
}

// The first cycles are reported by the look whose rows complete the second
// (the first analysis needs two): looks of 1.95 s of a 2 kHz test, as a
// watch at 20x real time takes them, left them a look longer.
TEST(LiveAnalysis, TheFirstCyclesAreReportedByTheLookThatCompletesThem) {
  const sim::SimulatedTest t = RunningTest("B-RT-R", 12, 2000);
  const force::CycleSet whole = force::SegmentCycles(t.record.x_mm);
  // A cycle completes once x is back from its end's minimum by the
  // hysteresis: by half a stroke, a quarter cycle after its end.
  const force::Cycle& second = whole.cycles.at(1);
  const Eigen::Index complete =
      second.reverse.end + (second.reverse.end - second.forward.begin) / 4;
  LiveAnalysis a{FuseOptions{}};
  const Eigen::Index piece = 3900;
  int reported = 0;
  for (Eigen::Index at = 0; at < t.record.size() && reported == 0;
       at += piece) {
    const Eigen::Index n = std::min(piece, t.record.size() - at);
    reported += static_cast<int>(a.Add(Rows(t.record, at, n)).size());
    if (at + n >= complete) {
      EXPECT_GE(reported, 2) << "rows up to " << at + n << ", the second cycle "
                             << "complete by " << complete;
      break;
    }
  }
}

TEST(LiveAnalysis, RunningInThenSteadyThenAVerdict) {
  const sim::SimulatedTest t = RunningTest("B-RT-R", 200, 1000);
  const Followed f = Follow(t.record, 500);
  const LiveEvent* r = Find(f.events, "running-in");
  const LiveEvent* s = Find(f.events, "steady");
  const LiveEvent* v = Find(f.events, "verdict");
  ASSERT_NE(r, nullptr);
  ASSERT_NE(s, nullptr);
  ASSERT_NE(v, nullptr);
  EXPECT_GE(s->cycle, 60);  // two steady windows
  EXPECT_NE(s->message.find("could stop"), std::string::npos);
  EXPECT_NE(v->message.find("explained by wear-scar"), std::string::npos);
  EXPECT_TRUE(s->good);  // good news, shown green
  EXPECT_TRUE(v->good);
}

TEST(LiveAnalysis, AnElasticPartTurnsTheVerdict) {
  const sim::SimulatedTest t = RunningTest("S-RL-R", 120, 1000);
  const Followed f = Follow(t.record, 500);
  const LiveEvent* v = Find(f.events, "verdict");
  ASSERT_NE(v, nullptr);
  EXPECT_NE(v->message.find("not explained"), std::string::npos) << v->message;
  EXPECT_FALSE(v->good);  // a warning
}

TEST(LiveAnalysis, ATrackDeeperThanTheLimitRaisesAnAlert) {
  const sim::SimulatedTest t = RunningTest("S-RL-R", 60, 1000);
  const Followed all = Follow(t.record, 500);
  ASSERT_GT(all.cycles.size(), 50u);
  // A limit the track passes half-way through.
  const double limit = 0.5 * (all.cycles[5].depth_mm + all.cycles[50].depth_mm);
  size_t first = 0;
  while (first < all.cycles.size() && !(all.cycles[first].depth_mm > limit))
    ++first;
  ASSERT_GT(first, 5u);
  ASSERT_LT(first, 50u);
  LiveOptions o;
  o.max_depth_mm = limit;
  const Followed f = Follow(t.record, 500, o);
  const LiveEvent* d = Find(f.events, "depth");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->cycle, static_cast<int>(first) + 1);
  EXPECT_NE(d->message.find(fmt::format("beyond the limit {:.4f} mm", limit)),
            std::string::npos)
      << d->message;
}

// A mains pick-up (0.03 N at 50 Hz, locked to the 1 Hz drive): found as
// soon as the window holds three cycles, said once, and removed from Q and
// P before the cycles after it are fitted, as fuse removes it: their
// mu-hat is the clean test's and no verdict says "not explained"; kept
// (--notch none), it is said as carried and the verdicts fail.
TEST(LiveAnalysis, APickUpIsFoundEarlyAndRemovedFromTheLiveFits) {
  samples::SimulationOptions o = RunningOptions("B-RT-R", 70, 2000);
  const Followed clean = Follow(sim::Simulate(o).record, 900);
  EXPECT_EQ(Find(clean.events, "periodic"), nullptr)
      << Find(clean.events, "periodic")->message;
  o.effects.pickup_n = 0.03;
  const force::ForceRecord hum = sim::Simulate(o).record;
  const Followed f = Follow(hum, 900);
  const LiveEvent* p = Find(f.events, "periodic");
  ASSERT_NE(p, nullptr);
  EXPECT_LE(p->cycle, 3);
  EXPECT_NE(p->message.find("removed from Q and P before the cycles from"),
            std::string::npos)
      << p->message;
  const size_t hz = p->message.find(" Hz");
  ASSERT_NE(hz, std::string::npos) << p->message;
  const size_t at = p->message.rfind(' ', hz - 1) + 1;
  EXPECT_NEAR(std::stod(p->message.substr(at, hz - at)), 50.0, 0.02)
      << p->message;
  FuseOptions keep;
  keep.notch_found_lines = false;
  const Followed k = Follow(hum, 900, {}, keep);
  ASSERT_NE(Find(k.events, "periodic"), nullptr);
  EXPECT_NE(Find(k.events, "periodic")->message.find("the live fits carry"),
            std::string::npos);
  ASSERT_EQ(f.cycles.size(), clean.cycles.size());
  ASSERT_EQ(k.cycles.size(), clean.cycles.size());
  double removed = 0, kept = 0;
  for (size_t c = p->cycle + 1; c < clean.cycles.size(); ++c) {
    removed = std::max(removed,
                       std::abs(f.cycles[c].mu_hat - clean.cycles[c].mu_hat));
    kept =
        std::max(kept, std::abs(k.cycles[c].mu_hat - clean.cycles[c].mu_hat));
  }
  // (The first cycles carry it into the ensemble's k and the noise
  // split's template of the cycles after them.)
  EXPECT_LT(removed, 0.5 * kept);
  auto failed = [](const Followed& run) {
    int n = 0;
    for (const LiveEvent& e : run.events) {
      n += e.kind == "verdict" &&
           e.message.find("not explained") != std::string::npos;
    }
    return n;
  };
  EXPECT_EQ(failed(f), 0);
  EXPECT_GT(failed(k), 0);
}

// A dead weight (P constant): k from P is noise. With a depth channel the
// watch takes k from it as fuse decides (said before the cycles of the
// first verdict are fitted) and finds the test explained, mu-hat near the
// truth; without one it says the verdict cannot be judged, never "not
// explained" (k from P misses the track's tilt: J 0.5 against a floor of
// 0.3).
TEST(LiveAnalysis, ADeadWeightTakesTheDepthOrSaysTheVerdictCannotBeJudged) {
  for (const bool depth : {true, false}) {
    SCOPED_TRACE(depth ? "a depth channel" : "no depth channel");
    samples::SimulationOptions o = RunningOptions("B-RT-R", 90, 1000);
    o.rig = samples::Rig::kDeadWeight;
    o.depth_channel = depth;
    const sim::SimulatedTest t = sim::Simulate(o);
    ASSERT_EQ(t.record.has_depth(), depth);
    const Followed f = Follow(t.record, 500);
    const LiveEvent* profile = Find(f.events, "profile");
    bool not_judged = false;
    for (const LiveEvent& e : f.events) {
      if (e.kind != "verdict") continue;
      EXPECT_EQ(e.message.find("not explained"), std::string::npos)
          << e.message;
      not_judged |= e.message.find("not judged") != std::string::npos;
    }
    if (!depth) {
      EXPECT_EQ(profile, nullptr);
      EXPECT_TRUE(not_judged);
      continue;
    }
    ASSERT_NE(profile, nullptr);
    EXPECT_LE(profile->cycle, 20);
    EXPECT_NE(profile->message.find("k from the depth channel"),
              std::string::npos)
        << profile->message;
    double live = 0, truth = 0;
    int n = 0;
    for (const LiveCycle& c : f.cycles) {
      if (c.cycle <= 30 || !std::isfinite(c.mu_hat)) continue;
      live += c.mu_hat;
      truth += t.truth.mu_per_cycle[c.cycle - 1];
      ++n;
    }
    ASSERT_GT(n, 40);
    fmt::print("dead weight, depth channel: live mu-hat {:.4f}, truth {:.4f}\n",
               live / n,
               truth / n);
    EXPECT_NEAR(live / n, truth / n, 0.003);
  }
}

}  // namespace
}  // namespace wearscar::fusion
