// Every cycle's mu-hat of a test, and the split of each J into what this
// test's noise explains and what repeats at the same x (FitFriction).

#include <cmath>
#include <future>
#include <optional>
#include <utility>
#include <vector>

#include "fit_mu_internal.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion {

using internal::KNoiseBiasPerVariance;
using internal::Resolved;

void ApplyRepeatSplit(const std::array<RepeatSplit, 2>& split,
                      const std::array<double, 2>& q_total,
                      MuFit* f) {
  double floor = 0, excess = 0;
  for (int d = 0; d < 2; ++d) {
    const double qq = q_total[d];
    f->misfit_sq[d] = qq > 0 ? split[d].total / qq : std::nan("");
    f->repeat_sq[d] = qq > 0 ? split[d].repeat / qq : std::nan("");
    floor += std::sqrt(std::max(0.0, f->misfit_sq[d] - f->repeat_sq[d]));
    excess += std::sqrt(std::max(0.0, f->repeat_sq[d]));
  }
  f->cost_floor = floor;
  f->cost_excess = excess;
}

namespace {

// Each converged fit's J split (ApplyRepeatSplit).
void SplitCosts(const std::vector<std::array<RepeatSplit, 2>>& split,
                const std::vector<std::array<double, 2>>& q_total,
                std::vector<MuFit>* fits) {
  for (size_t c = 0; c < fits->size(); ++c) {
    if ((*fits)[c].converged)
      ApplyRepeatSplit(split[c], q_total[c], &(*fits)[c]);
  }
}

// Each converged fit's repeating misfit that changes sign with the motion
// (MuFit::repeat_odd_sq): the direction split's (SplitRepeatable's
// `parity`) two directions over 4.
void SplitParity(const std::vector<std::array<RepeatSplit, 2>>& parity,
                 const std::vector<std::array<double, 2>>& q_total,
                 std::vector<MuFit>* fits) {
  for (size_t c = 0; c < fits->size(); ++c) {
    MuFit& f = (*fits)[c];
    const double qq = q_total[c][0] + q_total[c][1];
    if (!f.converged || !(qq > 0)) continue;
    const double odd = (parity[c][0].repeat + parity[c][1].repeat) / 4;
    f.repeat_odd_sq = 2 * odd / qq;
  }
}

// The rms of k's repeatable part and of its noise over all cycles.
void SplitSlopeNoise(const std::vector<std::array<RepeatSplit, 2>>& split_k,
                     FrictionFits* out) {
  double total = 0, repeat = 0;
  long samples = 0;
  for (const auto& cycle : split_k) {
    for (const RepeatSplit& r : cycle) {
      if (!std::isfinite(r.repeat)) continue;
      total += r.total;
      repeat += r.repeat;
      samples += r.samples;
    }
  }
  if (samples > 0) {
    out->k_signal_rms = std::sqrt(std::max(0.0, repeat) / samples);
    out->k_noise_rms = std::sqrt(std::max(0.0, total - repeat) / samples);
  }
}

// Each converged cycle's mu-hat less its second-order bias from the k noise
// the split estimated.
void RemoveKNoiseBias(const std::vector<double>& bias_per_variance,
                      FrictionFits* out) {
  const double variance = out->k_ensemble_noise_rms * out->k_ensemble_noise_rms;
  double sum = 0;
  int n = 0;
  for (size_t c = 0; c < out->cycles.size(); ++c) {
    MuFit& f = out->cycles[c];
    if (!f.converged) continue;
    const double correction = -variance * bias_per_variance[c];
    f.mu_hat += correction;
    sum += correction;
    ++n;
  }
  out->k_noise_correction = n > 0 ? sum / n : 0.0;
}

// Fits every cycle and keeps what the noise split needs: the misfit
// Qm - Qw and k binned along x per cycle (sums of squares per cycle and
// direction beside). Each cycle writes only its own places (its fit, its
// sums, its cycle's bins), so that two threads may fit halves.
struct CycleFitter {
  CycleFitter(const force::ForceRecord& r,
              const force::CycleSet& c,
              const FrictionFitOptions& o,
              const PlateProfile* scan,
              const std::vector<double>* scale,
              bool bin_slope,
              FrictionFits* fits)
      : record(r),
        cycles(c),
        options(o),
        resolved(Resolved(o, SamplingRateOf(r))),
        scan_slope(scan),
        slope_scale(scale),
        n(static_cast<int>(c.cycles.size())),
        grid(PlateGrid::Covering(r, c, o.repeatability.bin_mm)),
        misfit(grid, 0, o.split_noise ? n - 1 : -1, /*with_x=*/false),
        // (k's bins serve the force side's noise split alone: an empty
        // range for the scan's k, which AddRange then skips.)
        slope(grid,
              0,
              bin_slope && o.split_noise ? n - 1 : -1,
              /*with_x=*/false),
        misfit_total(n),
        q_total(n),
        k_total(n),
        bias_per_variance(n, 0.0),
        out(fits) {
    out->cycles.resize(static_cast<std::size_t>(n));
    if (o.keep_samples) out->samples.resize(static_cast<std::size_t>(n));
  }

  // The cycles [first, last) with `slopes` (the force side's ensemble,
  // slid along them) or, null, the scan's.
  void Fit(int first, int last, const ForceSlopes* slopes) {
    Eigen::VectorXd residual;
    for (int c = first; c < last; ++c) {
      if (!options.fit_cycle.empty() &&
          (c >= static_cast<int>(options.fit_cycle.size()) ||
           !options.fit_cycle[static_cast<std::size_t>(c)]))
        continue;
      CycleSamples s = slopes ? slopes->Gather(c)
                              : GatherCycle(record,
                                            cycles.cycles[c],
                                            SlopeSource::kScan,
                                            resolved,
                                            scan_slope);
      if (!slopes && slope_scale != nullptr) {
        s.forward.k *= (*slope_scale)[c];
        s.reverse.k *= (*slope_scale)[c];
      }
      MuFit fit = FitMu(s, options.fit);
      if (fit.converged)
        bias_per_variance[c] = KNoiseBiasPerVariance(s, fit.mu_hat);
      if (options.split_noise) {
        int d = 0;
        for (const SlipSamples* h : {&s.forward, &s.reverse})
          AddDirection(c, d++, *h, fit, &residual);
      }
      out->cycles[static_cast<std::size_t>(c)] = std::move(fit);
      if (options.keep_samples)
        out->samples[static_cast<std::size_t>(c)] = std::move(s);
    }
  }

  // One direction's misfit and k, binned in one pass each (AddRange skips
  // what is not finite), and their sums of squares.
  void AddDirection(int c,
                    int d,
                    const SlipSamples& h,
                    const MuFit& fit,
                    Eigen::VectorXd* residual) {
    double rr = 0, qq = 0, kk = 0;
    const Eigen::Index m = h.q_n.size();
    residual->resize(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      const double r =
          fit.converged
              ? h.q_n[i] - WearScarTangentialForce(
                               h.p_n[i], h.k[i], fit.mu_hat, h.direction)
              : std::nan("");
      (*residual)[i] = r;
      if (std::isfinite(r)) rr += r * r;
      qq += h.q_n[i] * h.q_n[i];
      kk += h.k[i] * h.k[i];
    }
    misfit.AddRange(c, h.direction, h.x_mm.data(), residual->data(), 0, m);
    slope.AddRange(c, h.direction, h.x_mm.data(), h.k.data(), 0, m);
    misfit_total[c][d] = rr;
    q_total[c][d] = qq;
    k_total[c][d] = kk;
  }

  const force::ForceRecord& record;
  const force::CycleSet& cycles;
  const FrictionFitOptions& options;
  const FrictionFitOptions resolved;
  const PlateProfile* scan_slope;
  const std::vector<double>* slope_scale;
  const int n;
  const PlateGrid grid;
  CycleBins misfit, slope;
  std::vector<std::array<double, 2>> misfit_total, q_total, k_total;
  std::vector<double> bias_per_variance;
  FrictionFits* out;
};

// The cycles fitted: with `two`, the second half of the cycles on a thread
// of its own (the force side's with its own ensemble, its first window
// summed afresh: the same sums to the bit as slid, float sums of a few
// cycles being exact in double), so the fits are the same with and
// without.
void FitCycles(const force::ForceRecord& record,
               const force::CycleSet& cycles,
               const FrictionFitOptions& options,
               const ForceSlopes* force_slopes,
               bool two,
               CycleFitter* fitter) {
  const int n = static_cast<int>(cycles.cycles.size());
  if (!two) {
    fitter->Fit(0, n, force_slopes);
    return;
  }
  const int half = n / 2;
  std::future<void> done = std::async(std::launch::async, [&] {
    std::optional<ForceSlopes> second;
    if (force_slopes) second.emplace(record, cycles, options);
    fitter->Fit(half, n, second ? &*second : nullptr);
  });
  fitter->Fit(0, half, force_slopes);
  done.get();
}

// The split: other cycles at the same x whose k shares no P sample with
// this cycle's form the template. Each fit's J split into out's fits;
// returns k's split (the force side's), made beside the misfit's with
// `two`.
std::vector<std::array<RepeatSplit, 2>> SplitNoise(
    const CycleFitter& fitter,
    const FrictionFitOptions& options,
    int shared,
    bool force_side,
    bool two,
    FrictionFits* out) {
  std::vector<std::array<RepeatSplit, 2>> split_k;
  if (!options.split_noise) return split_k;
  std::future<void> k_split;
  if (force_side) {
    k_split = std::async(two ? std::launch::async : std::launch::deferred, [&] {
      split_k = SplitRepeatable(
          fitter.slope, fitter.k_total, shared, options.repeatability, two);
    });
  }
  std::vector<std::array<RepeatSplit, 2>> parity;
  const std::vector<std::array<RepeatSplit, 2>> same =
      SplitRepeatable(fitter.misfit,
                      fitter.misfit_total,
                      shared,
                      options.repeatability,
                      two,
                      &parity);
  SplitCosts(same, fitter.q_total, &out->cycles);
  SplitParity(parity, fitter.q_total, &out->cycles);
  if (k_split.valid()) k_split.get();
  return split_k;
}

// The first and last cycles fitted (a live window's new ones), where the
// k noise is probed.
std::pair<int, int> FittedSpan(const std::vector<char>& fit, int n) {
  int lo = 0, hi = n - 1;
  if (!fit.empty()) {
    while (lo < hi && (lo >= static_cast<int>(fit.size()) || !fit[lo])) ++lo;
    while (hi > lo && (hi >= static_cast<int>(fit.size()) || !fit[hi])) --hi;
  }
  return {lo, hi};
}

}  // namespace

FrictionFits FitFriction(const force::ForceRecord& record,
                         const force::CycleSet& cycles,
                         SlopeSource source,
                         const FrictionFitOptions& options,
                         const PlateProfile* scan_slope,
                         const std::vector<double>* slope_scale) {
  WEARSCAR_CHECK(record.IsConsistent(),
                 "FitFriction needs channels of one length");
  WEARSCAR_CHECK(
      slope_scale == nullptr || slope_scale->size() == cycles.cycles.size(),
      "FitFriction needs one slope scale per cycle");
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("friction fit options: " + why);
  if (source == SlopeSource::kScan && scan_slope == nullptr) {
    throw FusionError(
        "slope from the scan requested but no scan slope profile given");
  }
  const int n = static_cast<int>(cycles.cycles.size());
  FrictionFits out;
  std::optional<ForceSlopes> force_slopes;
  int shared = 1;
  if (source == SlopeSource::kForce) {
    force_slopes.emplace(record, cycles, options);
    out.slope = force_slopes->Describe();
    shared = force_slopes->SharedCycles();
    out.correlated_cycles = shared;
  } else {
    out.slope = "k = dh/dx of the scan's centreline in plate coordinates";
    out.correlated_cycles = std::max(1, n);
  }
  CycleFitter fitter(record,
                     cycles,
                     options,
                     scan_slope,
                     slope_scale,
                     /*bin_slope=*/source == SlopeSource::kForce,
                     &out);
  const bool two = options.threads > 1 && n / 2 >= 2 * shared;
  FitCycles(record,
            cycles,
            options,
            force_slopes ? &*force_slopes : nullptr,
            two,
            &fitter);
  const std::vector<std::array<RepeatSplit, 2>> split_k =
      SplitNoise(fitter, options, shared, force_slopes.has_value(), two, &out);
  if (source == SlopeSource::kForce) {
    if (options.split_noise) SplitSlopeNoise(split_k, &out);
    const auto [lo, hi] = FittedSpan(options.fit_cycle, n);
    out.k_ensemble_noise_rms =
        std::sqrt(std::isnan(options.k_noise_variance)
                      ? force_slopes->EnsembleNoiseVariance(lo, hi)
                      : options.k_noise_variance);
    if (options.correct_k_noise_bias &&
        std::isfinite(out.k_ensemble_noise_rms)) {
      RemoveKNoiseBias(fitter.bias_per_variance, &out);
    }
  }
  return out;
}

std::vector<MuFit> FitFrictionPerCycle(const force::ForceRecord& record,
                                       const force::CycleSet& cycles,
                                       SlopeSource source,
                                       const FrictionFitOptions& options,
                                       const PlateProfile* scan_slope,
                                       const std::vector<double>* slope_scale) {
  return FitFriction(record, cycles, source, options, scan_slope, slope_scale)
      .cycles;
}

}  // namespace wearscar::fusion
