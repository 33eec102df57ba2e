#include "wearscar/fusion/diagnose.h"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "diagnose_model.h"
#include "minimize.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/interpolate.h"

namespace wearscar::fusion {

using internal::BinProfile;
using internal::CycleBic;
using internal::Data;
using internal::DiagCycle;
using internal::FitModel;
using internal::HeldOut;
using internal::Map;
using internal::Mean;
using internal::Model;
using internal::ParameterCount;
using internal::Sample;

bool DiagnoseOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (max_cycles < 2 * folds || folds < 2)
    return fail("need folds >= 2 and max_cycles >= 2 folds");
  if (decimation < 1) return fail("decimation must be >= 1");
  if (!(min_relative_gain > 0 && min_relative_gain < 1))
    return fail("min_relative_gain in (0,1)");
  if (!(min_improved_fraction > 0 && min_improved_fraction <= 1)) {
    return fail("min_improved_fraction in (0, 1]");
  }
  if (position_bins < 2 || reversal_bins < 2 || cycle_blocks < 1)
    return fail("bins must be >= 2");
  if (slope_cycles < 1 || slope_cycles > 10001)
    return fail("slope_cycles must be in [1, 10001]");
  if (!(profile_step_mm > 0) || !(profile_span_mm > 0)) {
    return fail("profile_step_mm and profile_span_mm must be > 0");
  }
  for (const auto& c : candidates) {
    if (FindEffect(c) == nullptr) return fail("unknown candidate effect");
  }
  std::string inner;
  if (!mu_fit.IsValid(&inner)) return fail(("mu_fit: " + inner).c_str());
  if (solver_iterations < 1) return fail("solver_iterations must be >= 1");
  if (!(undefined_model_residual_n > 0))
    return fail("undefined_model_residual_n must be > 0");
  if (min_samples_per_cycle < 2)
    return fail("min_samples_per_cycle must be >= 2");
  if (slope_polynomial_order < 1 || slope_polynomial_order > 5)
    return fail("slope_polynomial_order must be 1 to 5");
  return true;
}

std::string Diagnosis::BriefReport() const {
  std::string s = message;
  if (solves > 0) {
    s += fmt::format(
        "; {} joint fits, {} not converged", solves, solves_not_converged);
  }
  return s;
}

namespace {

// Up to max_cycles cycles spread evenly over those after running-in.
std::vector<int> ChooseCycles(int n, int first, int max_cycles) {
  const int available = n - first;
  const int m = std::min(max_cycles, available);
  std::vector<int> chosen;
  for (int i = 0; i < m; ++i) {
    chosen.push_back(first +
                     static_cast<int>(static_cast<long>(i) * (available - 1) /
                                      std::max(1, m - 1)));
  }
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

// Bins along x over the chosen cycles: the option's width, or the largest
// x step between samples (so that every bin holds samples at low sampling
// rates).
struct ProfileGrid {
  double x_lo = INFINITY, x_hi = -INFINITY, bin = 0;
  Eigen::Index bins = 0;
  Eigen::VectorXd centres;
};

ProfileGrid MakeProfileGrid(const force::ForceRecord& record,
                            const force::CycleSet& cycles,
                            const std::vector<int>& chosen,
                            double profile_step_mm) {
  ProfileGrid g;
  double max_step = 0;
  for (int c : chosen) {
    for (Eigen::Index i = cycles.cycles[c].forward.begin;
         i < cycles.cycles[c].reverse.end;
         ++i) {
      if (!std::isfinite(record.x_mm[i])) continue;
      g.x_lo = std::min(g.x_lo, record.x_mm[i]);
      g.x_hi = std::max(g.x_hi, record.x_mm[i]);
      if (i == cycles.cycles[c].forward.begin) continue;
      const double dx = std::abs(record.x_mm[i] - record.x_mm[i - 1]);
      if (std::isfinite(dx)) max_step = std::max(max_step, dx);
    }
  }
  g.bin = std::max(profile_step_mm, 1.05 * max_step);
  g.bins = static_cast<Eigen::Index>(std::ceil((g.x_hi - g.x_lo) / g.bin)) + 1;
  g.centres = Eigen::VectorXd::LinSpaced(
      g.bins, g.x_lo + 0.5 * g.bin, g.x_lo + (g.bins - 0.5) * g.bin);
  return g;
}

// Base slope of one cycle: its own P (and Q, for crosstalk) binned along x
// per direction over the cycle and its neighbours (the ensemble of
// FrictionFitOptions: the track changes slowly, and at the paper's noise
// one cycle's slope is noisy enough that shrinking it, an apparent elastic
// compliance, would lower the cost on clean data), smoothed by a cubic
// Savitzky-Golay filter and differentiated once: k = (1/S) dP/dx and
// (1/S) dQ/dx. Binning and smoothing keep the noise of a sample-wise
// derivative out of the comparison (no effect can win by shrinking noisy
// slopes), while each cycle keeps its own track.
class CycleSlopes {
 public:
  CycleSlopes(const force::ForceRecord& record,
              const force::CycleSet& cycles,
              const ProfileGrid& grid,
              const FrictionFitOptions& friction,
              const DiagnoseOptions& o)
      : record_(record), cycles_(cycles), grid_(grid), o_(o) {
    sg_ = friction.slope;
    sg_.method = force::DerivativeMethod::kSavitzkyGolay;
    sg_.window = std::max(
        7,
        2 * static_cast<int>(std::round(0.5 * o.profile_span_mm / grid.bin)) +
            1);
    sg_.polynomial_order = o.slope_polynomial_order;
    sg_.min_span_mm = 0;
    spring_ = friction.slope.spring_n_per_mm;
    half_ = friction.k_estimate == KEstimate::kEnsemble
                ? std::max(friction.ensemble.cycles, o.slope_cycles) / 2
                : 0;
  }

  void operator()(int c, PlateProfile kp[2], PlateProfile kq[2]) const {
    const int n = static_cast<int>(cycles_.cycles.size());
    std::vector<int> window;
    for (int j = std::max(0, c - half_); j <= std::min(n - 1, c + half_); ++j)
      window.push_back(j);
    const Eigen::MatrixXd pc = Bin(window, record_.normal_n);
    const Eigen::MatrixXd qc = Bin(window, record_.tangential_n);
    Eigen::VectorXd kpd[2], kqd[2];
    for (int row = 0; row < 2; ++row) {
      const Eigen::VectorXd pr = pc.row(row).transpose(),
                            qr = qc.row(row).transpose();
      kpd[row] =
          force::DerivativeAlongX(grid_.centres, pr, 0, grid_.bins, sg_) /
          spring_;
      kqd[row] =
          force::DerivativeAlongX(grid_.centres, qr, 0, grid_.bins, sg_) /
          spring_;
    }
    // Both directions slide over the same geometry: their mean slope halves
    // the noise variance. Crosstalk then enters through the mean of the two
    // Q slopes (P_dir = P + c Q_dir).
    const Eigen::VectorXd kp_mean = 0.5 * (kpd[0] + kpd[1]);
    const Eigen::VectorXd kq_mean = 0.5 * (kqd[0] + kqd[1]);
    for (int row = 0; row < 2; ++row) {
      kp[row] = {grid_.centres, o_.average_directions ? kp_mean : kpd[row]};
      kq[row] = {grid_.centres, o_.average_directions ? kq_mean : kqd[row]};
    }
  }

  Eigen::MatrixXd Bin(const std::vector<int>& which,
                      const Eigen::VectorXd& channel) const {
    return BinProfile(
        record_, cycles_, which, channel, grid_.x_lo, grid_.bin, grid_.bins);
  }
  double spring() const { return spring_; }

 private:
  const force::ForceRecord& record_;
  const force::CycleSet& cycles_;
  const ProfileGrid& grid_;
  const DiagnoseOptions& o_;
  force::SlopeOptions sg_;
  double spring_ = 0;
  int half_ = 0;
};

// Depth without a scan: the force side's mean profile below its highest
// point (the constant part is absorbed by mu).
PlateProfile ForceSideDepth(const Eigen::MatrixXd& p_prof,
                            const ProfileGrid& grid,
                            double spring) {
  Eigen::VectorXd f(grid.bins);
  double top = -INFINITY;
  for (Eigen::Index b = 0; b < grid.bins; ++b) {
    const double a = p_prof(0, b), c = p_prof(1, b);
    f[b] = std::isfinite(a) && std::isfinite(c) ? 0.5 * (a + c) / spring
           : std::isfinite(a)                   ? a / spring
                                                : c / spring;
    if (std::isfinite(f[b])) top = std::max(top, f[b]);
  }
  return {grid.centres, (top - f.array()).matrix()};
}

// A profile's shape over [lo, hi] normalised to mean 0 and sd 1 (zero
// where it does not vary).
PlateProfile Normalised(const PlateProfile& p, double lo, double hi) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < p.k.size(); ++i) {
    if (p.x_mm[i] < lo || p.x_mm[i] > hi || !std::isfinite(p.k[i])) continue;
    sum += p.k[i];
    sum2 += p.k[i] * p.k[i];
    ++n;
  }
  PlateProfile out = p;
  const double mean = n > 0 ? sum / n : 0;
  const double sd =
      n > 1 ? std::sqrt(std::max(0.0, sum2 / n - mean * mean)) : 0;
  out.k = sd > 0 ? Eigen::VectorXd((p.k.array() - mean) / sd)
                 : Eigen::VectorXd::Zero(p.k.size());
  return out;
}

// The gross-slip samples of cycle c (every o.decimation-th) with their
// slopes, depth, speed and distance to the stroke end.
DiagCycle GatherCycle(const force::ForceRecord& record,
                      const force::Cycle& cy,
                      int c,
                      const CycleSlopes& slopes,
                      const PlateProfile& depth,
                      const PlateProfile& softness,
                      int decimation) {
  double cmin = INFINITY, cmax = -INFINITY;
  for (Eigen::Index i = cy.forward.begin; i < cy.reverse.end; ++i) {
    if (!std::isfinite(record.x_mm[i])) continue;
    cmin = std::min(cmin, record.x_mm[i]);
    cmax = std::max(cmax, record.x_mm[i]);
  }
  DiagCycle dc;
  dc.cycle = c;
  PlateProfile kp[2], kq[2];
  slopes(c, kp, kq);
  double f2 = 0, r2 = 0;
  for (const force::HalfCycle* h : {&cy.forward, &cy.reverse}) {
    const int row = h->direction > 0 ? 0 : 1;
    for (Eigen::Index i = h->slip_begin; i < h->slip_end; i += decimation) {
      const Eigen::Index a = std::max<Eigen::Index>(0, i - 2),
                         b = std::min(record.size() - 1, i + 2);
      Sample s;
      s.index = i;
      s.s = h->direction;
      s.x = record.x_mm[i];
      s.t = record.time_s[i];
      s.speed = std::abs((record.x_mm[b] - record.x_mm[a]) /
                         (record.time_s[b] - record.time_s[a]));
      s.p = record.normal_n[i];
      s.q = record.tangential_n[i];
      s.k = kp[row].At(s.x);
      s.q_slope = kq[row].At(s.x);
      s.depth = depth.At(s.x);
      s.softness = softness.At(s.x);
      s.to_end = h->direction > 0 ? cmax - s.x : s.x - cmin;
      if (!std::isfinite(s.x) || !std::isfinite(s.p) || !std::isfinite(s.q) ||
          !std::isfinite(s.k) || !std::isfinite(s.q_slope) ||
          !std::isfinite(s.depth) || !std::isfinite(s.softness) ||
          !std::isfinite(s.speed)) {
        continue;
      }
      (h->direction > 0 ? f2 : r2) += s.q * s.q;
      dc.samples.push_back(s);
    }
  }
  dc.norm_forward = std::sqrt(std::max(f2, 1e-12));
  dc.norm_reverse = std::sqrt(std::max(r2, 1e-12));
  return dc;
}

// One candidate added to `model`: held-out cost over the folds, parameters
// on all cycles with their jackknife spread over the folds, the change of
// the information criterion, and whether it passes the acceptance rules.
CandidateResult TryEffect(const Data& data,
                          const Model& model,
                          const std::vector<double>& base,
                          double base_bic,
                          const Effect* e,
                          const DiagnoseOptions& o,
                          Model* trial,
                          std::vector<double>* heldout) {
  *trial = model;
  trial->effects.push_back(e);
  trial->params.push_back(e->Initial());
  std::vector<std::vector<double>> fold_params;
  *heldout = HeldOut(data, *trial, o.folds, &fold_params);
  const std::vector<double>& h = *heldout;
  CandidateResult r;
  r.effect = e->Name();
  r.parameter_names = e->ParameterNames();
  r.heldout_before = Mean(base);
  r.heldout_after = Mean(h);
  r.relative_gain = (r.heldout_before - r.heldout_after) / r.heldout_before;
  int better = 0;
  for (size_t i = 0; i < h.size(); ++i) better += h[i] < base[i];
  r.improved_fraction =
      static_cast<double>(better) / static_cast<double>(h.size());
  std::vector<int> all(data.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  FitModel(data, all, trial);
  r.parameters = trial->params.back();
  const size_t offset =
      static_cast<size_t>(ParameterCount(*trial)) - r.parameters.size();
  r.uncertainties.assign(r.parameters.size(), 0.0);
  const double k = static_cast<double>(fold_params.size());
  for (size_t q = 0; q < r.parameters.size(); ++q) {
    double mean = 0;
    for (const auto& fp : fold_params) mean += fp[offset + q] / k;
    double var = 0;
    for (const auto& fp : fold_params)
      var += (fp[offset + q] - mean) * (fp[offset + q] - mean);
    r.uncertainties[q] = std::sqrt((k - 1) / k * var);
  }
  r.delta_bic = CycleBic(data, *trial, ParameterCount(*trial)) - base_bic;
  r.accepted = r.relative_gain >= o.min_relative_gain &&
               r.improved_fraction >= o.min_improved_fraction &&
               r.delta_bic < -o.bic_margin;
  return r;
}

// Greedy forward selection: each round tries every candidate not yet in
// the model and keeps the best if it passes; stops at the first round whose
// best fails, or at max_effects.
void SelectEffects(const Data& data,
                   const std::vector<const Effect*>& pool,
                   const DiagnoseOptions& o,
                   Diagnosis* out,
                   Model* model,
                   std::vector<double>* base) {
  double base_bic = CycleBic(data, *model, 0);
  while (static_cast<int>(model->effects.size()) < o.max_effects) {
    DiagnosisStep step;
    Model best_model;
    std::vector<double> best_heldout;
    for (const Effect* e : pool) {
      if (std::find(model->effects.begin(), model->effects.end(), e) !=
          model->effects.end())
        continue;
      Model trial;
      std::vector<double> h;
      const CandidateResult r =
          TryEffect(data, *model, *base, base_bic, e, o, &trial, &h);
      if (step.tried.empty() ||
          r.heldout_after < step.tried.front().heldout_after) {
        step.tried.insert(step.tried.begin(), r);
        best_model = trial;
        best_heldout = h;
      } else {
        step.tried.push_back(r);
      }
    }
    if (step.tried.empty()) break;
    std::sort(step.tried.begin() + 1,
              step.tried.end(),
              [](const auto& a, const auto& b) {
                return a.heldout_after < b.heldout_after;
              });
    step.chosen = step.tried.front();
    out->steps.push_back(step);
    if (!step.chosen.accepted) break;
    *model = best_model;
    *base = best_heldout;
    base_bic += step.chosen.delta_bic;
    out->named.push_back(step.chosen.effect);
    out->model.push_back(step.chosen);
  }
}

std::vector<const Effect*> CandidatePool(const DiagnoseOptions& o) {
  std::vector<const Effect*> pool;
  for (const auto& e : EffectLibrary()) {
    if (o.candidates.empty() ||
        std::find(o.candidates.begin(), o.candidates.end(), e->Name()) !=
            o.candidates.end()) {
      pool.push_back(e.get());
    }
  }
  return pool;
}

}  // namespace

Diagnosis Diagnose(const force::ForceRecord& record,
                   const force::CycleSet& cycles,
                   const FrictionFitOptions& friction,
                   const PlateProfile* depth,
                   const DiagnoseOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw FusionError("diagnose options: " + why);
  Diagnosis out;
  const int n = static_cast<int>(cycles.cycles.size());
  const int first = std::min(o.running_in_cycles, n / 2);
  if (n - first < 2 * o.folds) {
    throw FusionError(
        fmt::format("diagnosis needs at least {} cycles after running-in; the "
                    "record has {} of {}",
                    2 * o.folds,
                    n - first,
                    n));
  }
  out.cycles = ChooseCycles(n, first, o.max_cycles);
  const ProfileGrid grid =
      MakeProfileGrid(record, cycles, out.cycles, o.profile_step_mm);
  const CycleSlopes slopes(record, cycles, grid, friction, o);
  PlateProfile force_depth;
  if (depth == nullptr) {
    force_depth = ForceSideDepth(
        slopes.Bin(out.cycles, record.normal_n), grid, slopes.spring());
    depth = &force_depth;
  }
  Data data;
  data.record = &record;
  data.options = &o;
  data.dt = record.size() > 1
                ? (record.time_s[record.size() - 1] - record.time_s[0]) /
                      (record.size() - 1)
                : 1e-3;
  const PlateProfile softness = Normalised(*depth, grid.x_lo, grid.x_hi);
  for (int c : out.cycles) {
    DiagCycle dc = GatherCycle(
        record, cycles.cycles[c], c, slopes, *depth, softness, o.decimation);
    if (static_cast<int>(dc.samples.size()) >= o.min_samples_per_cycle)
      data.cycles.push_back(std::move(dc));
  }
  if (static_cast<int>(data.cycles.size()) < 2 * o.folds) {
    throw FusionError("too few usable cycles for the diagnosis");
  }
  Model model;
  std::vector<double> base = HeldOut(data, model, o.folds, nullptr);
  out.heldout_initial = Mean(base);
  out.before = Map(data, model, o, grid.x_lo, grid.x_hi);
  SelectEffects(data, CandidatePool(o), o, &out, &model, &base);
  // Report the final parameters of every named effect from the last fit.
  for (size_t e = 0; e < out.model.size(); ++e)
    out.model[e].parameters = model.params[e];
  out.heldout_final = Mean(base);
  out.after = Map(data, model, o, grid.x_lo, grid.x_hi);
  out.solves = data.solves;
  out.solves_not_converged = data.not_converged;
  out.message =
      out.named.empty()
          ? fmt::format(
                "no effect named: the wear-scar model leaves nothing a "
                "candidate explains (held-out J {:.4f})",
                out.heldout_initial)
          : fmt::format("named {}; held-out J {:.4f} -> {:.4f} ({:.0f}% lower)",
                        fmt::join(out.named, ", "),
                        out.heldout_initial,
                        out.heldout_final,
                        100 * (1 - out.heldout_final / out.heldout_initial));
  return out;
}

Diagnosis DiagnoseTest(const force::ForceRecord& record,
                       const TestResult& r,
                       const FuseOptions& fuse,
                       const DiagnoseOptions& options) {
  PlateProfile depth;
  if (r.scan) {
    const auto& fp = r.scan->force_profile;
    depth.x_mm = fp.x_mm;
    depth.k = -ScanHeightAtPlate(r.scan->profile, r.scan->alignment, fp.x_mm);
  }
  return Diagnose(record,
                  r.force.cycles,
                  fuse.analysis.friction,
                  r.scan ? &depth : nullptr,
                  options);
}

}  // namespace wearscar::fusion
