// When the scanned track's shape appeared in the record, cycle by cycle
// (scan_shape_history.h): an analysis unit that reads the scan side, the
// profile's decision, the verdict and the track's history from the spring.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "units.h"
#include "wearscar/fusion/align.h"
#include "wearscar/fusion/scan_shape_history.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion::internal {
namespace {

// The premises, checked on the result: which failed first ("" none).
// P/S carries the track's height (the profile is the spring's); the scan
// is this test's; its profile follows P/S over the compared cycles.
std::vector<Premise> Checked(const TestResult& r) {
  std::vector<Premise> p(3);
  p[0] = {
      "scan shape history",
      "P/S follows the track's height (the loading spring's profile)",
      r.profile.FromSpring() ? Premise::State::kHeld : Premise::State::kFailed,
      "the force side's profile is " + r.profile.ProfileName(),
      "not computed: the record's P does not carry the track"};
  p[1] = {"scan shape history",
          "the scan is this test's track",
          r.scan && r.verdict.scan_doubt.empty() ? Premise::State::kHeld
                                                 : Premise::State::kFailed,
          r.scan ? (r.verdict.scan_doubt.empty() ? "its identity is not doubted"
                                                 : r.verdict.scan_doubt)
                 : "no scan was used",
          "not computed: give this test's scan"};
  const double c = r.mismatch.correlation_noise_corrected;
  const double least = r.options.verdict.min_correlation;
  p[2] = {
      "scan shape history",
      "the scan's profile follows P/S over the compared cycles",
      r.scan && c >= least ? Premise::State::kHeld : Premise::State::kFailed,
      fmt::format("r = {:.3f} (noise-corrected; at least {:.2f})", c, least),
      "not computed: the profiles do not match, so the share of the "
      "scan's shape in a cycle says nothing"};
  return p;
}

class ScanShapeUnit : public TypedUnit<ScanShapeHistory> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "scan_shape_history",
        "per cycle, how much of the aligned scan's profile P/S holds: when "
        "the scanned track's shape appeared (from nothing, or there from "
        "the first recorded cycle)",
        {"track_history",
         "the scan",
         "the decision",
         "the verdict (the scan's identity)"},
        {{"scan_shape_history.csv",
          {"cycle", "scan_shape_factor", "scan_shape_r"},
          "per cycle, the factor of the aligned scan's profile in P/S and "
          "their correlation along x"}}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kJudged;
  }
  ScanShapeHistory Run(const UnitInput& in) const override;
  // The track's history said where the result is read: there from the
  // first recorded cycle (at least half of the scanned shape from cycle 1
  // on) or grown during the record.
  void Say(const ScanShapeHistory& h, TestResult* r) const override {
    if (!h.abstained.empty() || !std::isfinite(h.first_factor)) return;
    if (h.half_cycle == 0) {
      r->assumptions.push_back(fmt::format(
          "the worn track was there from the first recorded cycle (a "
          "pre-worn or resumed specimen, or a later block of a long test): "
          "the first {} cycles' P/S hold {:.2f} of the scanned shape",
          h.first_cycles,
          h.first_factor));
    } else {
      r->assumptions.push_back(fmt::format(
          "the worn track grew during the record: the first {} cycles' P/S "
          "hold {:.2f} of the scanned shape{}",
          h.first_cycles,
          h.first_factor,
          h.half_cycle > 0
              ? fmt::format(", half of it from cycle {} on", h.half_cycle + 1)
              : std::string()));
    }
  }
  // The first cycles pooled: the track history's pool, fewer where the
  // record is shorter.
  std::vector<UnitChoice> Choices(const ScanShapeHistory& h,
                                  const TestResult& r) const override {
    if (!h.abstained.empty()) return {};
    const int given = r.options.track_history.pool_cycles;
    return {{"first_cycles",
             given,
             h.first_cycles,
             h.first_cycles < given
                 ? fmt::format("the record has {} cycles", h.first_cycles)
                 : ""}};
  }
  std::vector<Premise> Premises(const ScanShapeHistory& h,
                                const TestResult&) const override {
    return h.premises;
  }
  nlohmann::json Json(const ScanShapeHistory& h,
                      const TestResult&) const override {
    if (!h.abstained.empty()) return {{"abstained", h.abstained}};
    return {{"first_cycles", h.first_cycles},
            {"first_cycles_factor", h.first_factor},
            {"compared_cycles_factor", h.compared_factor},
            {"half_from_cycle",
             h.half_cycle >= 0 ? nlohmann::json(h.half_cycle + 1)
                               : nlohmann::json()}};
  }
  std::vector<UnitTable> Tables(const ScanShapeHistory& h,
                                const force::ForceRecord&,
                                const TestResult&) const override {
    if (h.factor.empty()) return {};
    Table t(Spec().tables[0].columns);
    for (size_t c = 0; c < h.factor.size(); ++c)
      t.rows.push_back(
          {static_cast<double>(c + 1), h.factor[c], h.correlation[c]});
    return MovedList(UnitTable{"scan_shape_history.csv", std::move(t)});
  }
  std::vector<UnitFigure> Figures(const ScanShapeHistory& h,
                                  const std::string& name,
                                  const TestResult&) const override {
    if (h.factor.empty()) return {};
    UnitSeries factor{"scan_shape_history.csv",
                      "cycle",
                      "scan_shape_factor",
                      "factor of the scan's profile in P/S"};
    UnitSeries r{"scan_shape_history.csv",
                 "cycle",
                 "scan_shape_r",
                 "correlation along x",
                 UnitSeries::Role::kScan};
    return {{"fig_scan_shape_history",
             fmt::format("{}: the scanned track's shape in each cycle's P/S "
                         "(first {} cycles {:.2f}, compared cycles {:.2f})",
                         name,
                         h.first_cycles,
                         h.first_factor,
                         h.compared_factor),
             {{"",
               "cycle",
               "factor, r (-)",
               "set key inside bottom right\n",
               std::nullopt,
               "",
               {factor, r}}}}};
  }
};

// The factor and correlation of `s` (about its mean) in `h` along x,
// over the bins where both are finite.
std::pair<double, double> FactorAndCorrelation(const std::vector<double>& h,
                                               const std::vector<double>& s) {
  double mh = 0, ms = 0;
  int n = 0;
  for (size_t b = 0; b < h.size(); ++b) {
    if (std::isfinite(h[b]) && std::isfinite(s[b])) mh += h[b], ms += s[b], ++n;
  }
  if (n < 3) return {NAN, NAN};
  mh /= n, ms /= n;
  double hs = 0, ss = 0, hh = 0;
  for (size_t b = 0; b < h.size(); ++b) {
    if (!std::isfinite(h[b]) || !std::isfinite(s[b])) continue;
    hs += (h[b] - mh) * (s[b] - ms);
    ss += (s[b] - ms) * (s[b] - ms);
    hh += (h[b] - mh) * (h[b] - mh);
  }
  if (!(ss > 0) || !(hh > 0)) return {NAN, NAN};
  return {hs / ss, hs / std::sqrt(ss * hh)};
}

double MeanOver(const std::vector<double>& v, int first, int last) {
  double sum = 0;
  int n = 0;
  for (int c = std::max(first, 0); c <= last && c < static_cast<int>(v.size());
       ++c) {
    if (std::isfinite(v[c])) sum += v[c], ++n;
  }
  return n > 0 ? sum / n : NAN;
}

ScanShapeHistory ScanShapeUnit::Run(const UnitInput& in) const {
  const TestResult& r = *in.judged;
  ScanShapeHistory out;
  out.premises = Checked(r);
  for (const Premise& p : out.premises) {
    if (p.Failed()) {
      out.abstained =
          fmt::format("{} ({}): {}", p.statement, p.evidence, p.otherwise);
      return out;
    }
  }
  const TrackHistory& th = r.units.Get<TrackHistory>();
  const ScanAnalysis& scan = *r.scan;
  const Eigen::Map<const Eigen::VectorXd> x(
      th.x_mm.data(), static_cast<Eigen::Index>(th.x_mm.size()));
  const Eigen::VectorXd s_raw =
      ScanHeightAtPlate(scan.profile, scan.alignment, x);
  // The scan as P/S sees it over the compared cycles.
  std::vector<double> s(th.x_mm.size());
  for (size_t b = 0; b < s.size(); ++b)
    s[b] = scan.alignment.scale * s_raw[static_cast<Eigen::Index>(b)];
  std::vector<double> h(th.x_mm.size());
  for (int c = 0; c < th.cycles; ++c) {
    // Both directions' mean (either where one is empty).
    for (size_t b = 0; b < h.size(); ++b) {
      const double f = th.height_mm[th.Index(c, 0, b)],
                   v = th.height_mm[th.Index(c, 1, b)];
      h[b] = std::isfinite(f) && std::isfinite(v) ? 0.5 * (f + v)
             : std::isfinite(f)                   ? f
                                                  : v;
    }
    const auto [factor, correlation] = FactorAndCorrelation(h, s);
    out.factor.push_back(factor);
    out.correlation.push_back(correlation);
  }
  // The first cycles: one pool of the track history's waviness.
  out.first_cycles = std::min(th.cycles, in.options.track_history.pool_cycles);
  out.first_factor = MeanOver(out.factor, 0, out.first_cycles - 1);
  out.compared_factor = MeanOver(out.factor, r.window.first, r.window.last);
  for (int c = th.cycles - 1; c >= 0 && out.factor[c] >= 0.5; --c)
    out.half_cycle = c;
  return out;
}

}  // namespace

const AnalysisUnit& ScanShapeAnalysis() {
  static const ScanShapeUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
