// The force side's and the scan's mu-hat, J and profiles side by side.

#include "wearscar/fusion/compare_slopes.h"

#include <cmath>
#include <future>
#include <utility>
#include <vector>

namespace wearscar::fusion {
namespace {

// (k_force - k_scan)^2 at each gross-slip sample of cycles [from, to)
// where the scan has a slope, in order, each handed to `add`; the force
// side's slopes those of the compared cycles [first, last].
template <typename Add>
void KDifferences(const force::ForceRecord& record,
                  const ForceAnalysis& force,
                  const PlateProfile& scan_slope,
                  const FrictionFitOptions& friction,
                  std::pair<int, int> compared,
                  int from,
                  int to,
                  Add add) {
  const ForceSlopes force_slopes(
      record, force.cycles, friction, compared.first, compared.second);
  for (int c = from; c < to; ++c) {
    const CycleSamples kf = force_slopes.Gather(c);
    for (const SlipSamples* s : {&kf.forward, &kf.reverse}) {
      for (Eigen::Index i = 0; i < s->k.size(); ++i) {
        const double ks = scan_slope.At(s->x_mm[i]);
        if (!std::isfinite(ks)) continue;
        add((s->k[i] - ks) * (s->k[i] - ks));
      }
    }
  }
}

// Per-cycle values over [first, last] in the summaries the report uses.
class CycleRange {
 public:
  CycleRange(int first, int last) : first_(first), last_(last) {}

  template <typename F>
  std::vector<double> Values(F value) const {
    std::vector<double> v;
    for (int c = first_; c <= last_; ++c) v.push_back(value(c));
    return v;
  }
  template <typename F>
  Statistic Stat(F value) const {
    return Summarise(Values(value), 0);
  }
  // The classic COFs: judged by their own scatter (SummariseSeries).
  template <typename F>
  Statistic Series(F value) const {
    const std::vector<double> v = Values(value);
    return SummariseSeries(v, 0, static_cast<int>(v.size()) - 1);
  }
  // mu-hat and what is computed from it carry the fits' standard errors,
  // correlated over the cycles that share a slope.
  template <typename F>
  Statistic WithErrors(const std::vector<MuFit>& fits,
                       int correlated,
                       F value) const {
    std::vector<double> v, se;
    for (int c = first_; c <= last_; ++c) {
      const bool ok = fits[c].converged;
      v.push_back(ok ? value(c) : std::nan(""));
      se.push_back(ok ? fits[c].standard_error : std::nan(""));
    }
    return SummariseWithErrors(
        v, se, 0, static_cast<int>(v.size()) - 1, correlated);
  }
  // mu-hat minus mu_energy with the slope the verdict judges.
  Interval MethodDifference(const std::vector<MuFit>& fits,
                            const std::vector<force::CycleCof>& cof) const {
    std::vector<double> d(fits.size(), std::nan(""));
    for (int c = first_; c <= last_ && c < static_cast<int>(fits.size()); ++c) {
      if (fits[c].converged) d[c] = fits[c].mu_hat - cof[c].mu_energy_g;
    }
    return MeanInterval(d, first_, last_);
  }
  int Count() const { return last_ - first_ + 1; }

 private:
  int first_, last_;
};

void CompareForceSide(const SlopeFits& fits,
                      const std::vector<force::CycleCof>& cof,
                      const CycleRange& range,
                      MismatchReport* r) {
  const auto& ff = fits.cycles;
  const int shared = fits.correlated_cycles;
  r->mu_force =
      range.WithErrors(ff, shared, [&](int c) { return ff[c].mu_hat; });
  r->cost_force = range.Stat(
      [&](int c) { return ff[c].converged ? ff[c].cost : std::nan(""); });
  // The classic COFs' own noise is small against mu-hat's (they average
  // Q/P over whole half cycles): the differences carry mu-hat's errors.
  r->mu_force_minus_mean = range.WithErrors(
      ff, shared, [&](int c) { return ff[c].mu_hat - cof[c].mu_mean; });
  r->mu_force_minus_energy = range.WithErrors(
      ff, shared, [&](int c) { return ff[c].mu_hat - cof[c].mu_energy_g; });
  r->split_force = SplitCost(ff, r->first_cycle, r->last_cycle);
  r->method_difference = range.MethodDifference(ff, cof);
}

// The stroke's centre in the scan against the sphere's reversals there
// (MismatchReport::ends_offset_mm).
void EndsOffset(const ForceAnalysis& force,
                const ScanAnalysis& scan,
                MismatchReport* r) {
  const scan::TrackEnds& e = scan.ends;
  const double stroke = force.cycles.x_max_mm - force.cycles.x_min_mm;
  r->walls = e.low.Found() + e.high.Found();
  double centre = NAN;
  if (r->walls == 2) {
    centre = 0.5 * (e.low.position_mm + e.high.position_mm);
    r->ends_stroke_mm = e.high.position_mm - e.low.position_mm;
  } else if (e.low.Found()) {
    centre = e.low.position_mm + 0.5 * stroke;
  } else if (e.high.Found()) {
    centre = e.high.position_mm - 0.5 * stroke;
  }
  r->ends_offset_mm =
      scan.alignment.ScanFromPlate(
          0.5 * (force.cycles.x_min_mm + force.cycles.x_max_mm)) -
      centre;
}

void CompareScanSide(const ForceAnalysis& force,
                     const std::vector<force::CycleCof>& cof,
                     const ScanAnalysis& scan,
                     const std::vector<MuFit>& fs,
                     const CycleRange& range,
                     MismatchReport* r) {
  r->has_scan = true;
  r->correlation = scan.alignment.correlation;
  r->correlation_noise_corrected = scan.alignment.correlation_noise_corrected;
  r->waviness_correlation = scan.alignment.waviness_correlation;
  r->waviness_to_noise = scan.alignment.waviness_to_noise;
  r->waviness_runner_up = scan.alignment.waviness_runner_up;
  r->waviness_runner_up_shift_mm = scan.alignment.waviness_runner_up_shift_mm;
  r->amplitude_ratio = scan.alignment.amplitude_ratio;
  const scan::Track& t = scan.track;
  if (t.PlaceKnown()) {
    r->track_length_mm = t.length_mm;
    r->track_width_mm = t.width_mm;
    const double flip = scan.alignment.flipped ? -1.0 : 1.0;
    r->centre_offset_mm =
        scan.alignment.shift_mm +
        flip * 0.5 * (force.cycles.x_min_mm + force.cycles.x_max_mm);
  }
  EndsOffset(force, scan, r);
  r->scan_pixel_mm = std::max(scan.Levelled().dx_mm, scan.Levelled().dy_mm);
  r->stroke_mm = force.cycles.stroke_mm;
  r->amplitude_ratio_low = scan.alignment.amplitude_ratio_low;
  r->amplitude_ratio_high = scan.alignment.amplitude_ratio_high;
  r->split_scan = SplitCost(fs, r->first_cycle, r->last_cycle);
  if (r->cost_force.count == 0)
    r->method_difference = range.MethodDifference(fs, cof);
  // One scan slope for every cycle: its errors are common to all.
  r->mu_scan =
      range.WithErrors(fs, range.Count(), [&](int c) { return fs[c].mu_hat; });
  r->cost_scan = range.Stat(
      [&](int c) { return fs[c].converged ? fs[c].cost : std::nan(""); });
  r->mu_force_minus_scan = r->mu_force.mean - r->mu_scan.mean;
}

}  // namespace

// With `parallel` the second half of the cycles on a thread of its own
// (its own ensemble, as the fit's), its terms added after the first half's
// in the order one thread adds them.
double KRmsDifference(const force::ForceRecord& record,
                      const ForceAnalysis& force,
                      const PlateProfile& scan_slope,
                      const FrictionFitOptions& friction,
                      int first,
                      int last,
                      bool parallel) {
  const int half =
      parallel && last - first >= 8 ? (first + last + 1) / 2 : last + 1;
  std::vector<double> second;
  std::future<void> beside;
  if (half <= last) {
    beside = std::async(std::launch::async, [&] {
      KDifferences(record,
                   force,
                   scan_slope,
                   friction,
                   {first, last},
                   half,
                   last + 1,
                   [&](double d) { second.push_back(d); });
    });
  }
  double sum2 = 0;
  long n = 0;
  KDifferences(record,
               force,
               scan_slope,
               friction,
               {first, last},
               first,
               half,
               [&](double d) { sum2 += d, ++n; });
  if (beside.valid()) beside.get();
  for (const double d : second) sum2 += d, ++n;
  return n > 0 ? std::sqrt(sum2 / n) : std::nan("");
}

MismatchReport CompareSlopes(const force::ForceRecord& record,
                             const ForceAnalysis& force,
                             const SlopeFits& fits,
                             const ClassicCofs& classic,
                             const ScanAnalysis* scan,
                             const ScanFits& scan_fits,
                             const ProfileDecision& profile,
                             int first,
                             int last,
                             const FuseOptions& options,
                             std::optional<double> k_rms_difference) {
  MismatchReport r;
  r.first_cycle = first;
  r.last_cycle = last;
  r.force_slope_name = profile.ChannelName();
  r.force_profile_name = profile.ProfileName();
  r.force_slope_judged = profile.ForceSlopeJudged();
  const CycleRange range(first, last);
  const std::vector<force::CycleCof>& cof = classic.cycles;
  r.mu_mean = range.Series([&](int c) { return cof[c].mu_mean; });
  r.mu_energy = range.Series([&](int c) { return cof[c].mu_energy_g; });
  // Without a profile in P (a dead weight) its fits are not used.
  if (profile.ForceSlopeJudged()) {
    CompareForceSide(fits, cof, range, &r);
  } else {
    r.method_difference = range.MethodDifference({}, cof);
  }
  if (scan == nullptr) return r;
  CompareScanSide(force, cof, *scan, scan_fits.cycles, range, &r);
  r.identity_judged = !profile.FromFriction();
  if (!profile.ForceSlopeJudged()) {
    r.k_rms_difference = std::nan("");
  } else if (k_rms_difference) {
    r.k_rms_difference = *k_rms_difference;
  } else {
    r.k_rms_difference = KRmsDifference(record,
                                        force,
                                        scan->slope,
                                        options.analysis.friction,
                                        first,
                                        last,
                                        options.parallel);
  }
  return r;
}

}  // namespace wearscar::fusion
