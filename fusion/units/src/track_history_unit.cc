// The track's history from the spring as an analysis unit
// (track_history.h): P/S per cycle and direction about its mean, its
// waviness per cycle. The pipeline's core reads it before the units are
// collected (the profile's decision, the scan's slope history, the spring
// check: UnitRunner::Await).

#include <fmt/format.h>

#include <cmath>

#include "units.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion::internal {
namespace {

class TrackHistoryUnit : public TypedUnit<TrackHistory> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "track_history",
        "the track's shape under load per cycle from the spring alone, P/S "
        "about its mean, its waviness per cycle and its growth",
        {"the record", "the cycles", "the spring (as given)"},
        {{"track_history.csv",
          {"cycle", "direction", "x_mm", "h_mm"},
          "the track's height from the spring, P/S about its mean, per "
          "cycle"}},
        {{"cycles.csv", "slip_fallback", {"waviness_sd_mm"}}}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCycles;
  }
  bool WorthAThread() const override { return true; }
  TrackHistory Run(const UnitInput& in) const override {
    return ComputeTrackHistory(
        in.record,
        in.force.cycles,
        in.options.analysis.friction.slope.spring_n_per_mm,
        in.options.track_history);
  }
  // Its waviness from the first cycle to the end.
  nlohmann::json Json(const TrackHistory& h,
                      const TestResult& r) const override {
    nlohmann::json j = {
        {"bin_mm", r.options.track_history.bin_mm},
        {"steady_from_cycle", h.cycles > 0 ? h.steady_cycle + 1 : 0},
        {"final_waviness_sd_mm", h.final_waviness_sd_mm},
        {"growth_per_cycle_mm", h.growth_per_cycle_mm},
        {"first_waviness_sd_mm",
         h.waviness_sd_mm.empty() ? std::nan("") : h.waviness_sd_mm.front()}};
    // The final state against the scan: the alignment's amplitude ratio
    // (P/S over the compared cycles against the scanned profile).
    if (r.scan)
      j["final_vs_scan_amplitude_ratio"] = r.scan->alignment.amplitude_ratio;
    return j;
  }
  std::vector<UnitTable> Tables(const TrackHistory& h,
                                const force::ForceRecord&,
                                const TestResult&) const override {
    Table t(Spec().tables[0].columns);
    for (int c = 0; c < h.cycles; ++c) {
      for (int d = 0; d < 2; ++d) {
        for (size_t b = 0; b < h.x_mm.size(); ++b) {
          const double v = h.height_mm[h.Index(c, d, b)];
          if (std::isfinite(v))
            t.rows.push_back({static_cast<double>(c + 1),
                              d == 0 ? 1.0 : -1.0,
                              h.x_mm[b],
                              v});
        }
      }
    }
    return MovedList(UnitTable{"track_history.csv", std::move(t)});
  }
  // Its waviness per cycle beside the cycle's mu-hat.
  std::vector<std::vector<double>> Columns(const TrackHistory& h,
                                           const UnitColumns&,
                                           const TestResult& r) const override {
    std::vector<std::vector<double>> rows;
    for (size_t c = 0; c < r.force.cycles.cycles.size(); ++c)
      rows.push_back(
          {c < h.waviness_sd_mm.size() ? h.waviness_sd_mm[c] : std::nan("")});
    return rows;
  }
  std::vector<UnitFigure> Figures(const TrackHistory& h,
                                  const std::string& name,
                                  const TestResult& r) const override;
};

// h(x, cycle) = P/S about its mean (forward sliding) above, its waviness
// per cycle below. Drawn from P/S: on a rig whose P does not follow the
// track (a dead weight: the depth channel or the friction used) it would
// show noise, and is not drawn.
std::vector<UnitFigure> TrackHistoryUnit::Figures(const TrackHistory& h,
                                                  const std::string& name,
                                                  const TestResult& r) const {
  if (h.x_mm.size() < 2 || h.cycles < 2 || !r.profile.FromSpring()) return {};
  UnitGrid grid{"track_history.f32", h.x_mm, h.cycles, {}};
  for (int c = 0; c < h.cycles; ++c) {
    for (size_t b = 0; b < h.x_mm.size(); ++b)
      grid.values.push_back(static_cast<float>(h.height_mm[h.Index(c, 0, b)]));
  }
  return {{"fig_track_history",
           fmt::format("{}: the track's history from the spring, h = P/S; "
                       "waviness {:.4f} mm in cycle 1, {:.4f} mm at the end, "
                       "steady from cycle {}",
                       name,
                       h.waviness_sd_mm.front(),
                       h.final_waviness_sd_mm,
                       h.steady_cycle + 1),
           {{"h(x, cycle): P/S about its mean, forward sliding",
             "x (mm)",
             "cycle",
             GridRanges(h.x_mm, h.cycles) + "unset key\n",
             std::move(grid),
             "h (mm)",
             {}},
            {"waviness: the sd of h along the stroke",
             "cycle",
             "waviness (mm)",
             // From 0: a waviness that barely changes was autoscaled to a
             // span below the labels' digits, which then repeated.
             "set autoscale\nset yrange [0:*]\nunset colorbox\nunset key\n",
             std::nullopt,
             "",
             {UnitSeries("cycles.csv",
                         "cycle",
                         "waviness_sd_mm",
                         "",
                         UnitSeries::Role::kForce,
                         2)}}}}};
}

}  // namespace

const AnalysisUnit& TrackHistoryAnalysis() {
  static const TrackHistoryUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
