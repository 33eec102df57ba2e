#include "wearscar/fusion/fit_mu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "minimize.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// |Qm - Qw| / |Qm| over one direction.
double DirectionCost(const SlipSamples& s, double mu) {
  // Vectorised form of |Qm - P (k + s mu) / (1 - s mu k)| / |Qm|.
  const double sm = s.direction * mu;
  const auto k = s.k.array();
  const auto denom = 1.0 - sm * k;
  if (s.k.size() == 0 || (denom <= 0.0).any()) return kInf;
  const double num =
      (s.q_n.array() - s.p_n.array() * (k + sm) / denom).square().sum();
  const double den = s.q_n.squaredNorm();
  return den > 0 ? std::sqrt(num / den) : kInf;
}

void AppendSlip(const force::ForceRecord& r,
                const force::HalfCycle& half,
                SlopeSource source,
                const FrictionFitOptions& o,
                const SlopeProfile* scan_slope,
                SlipSamples* out) {
  out->direction = half.direction;
  const Eigen::Index b = half.slip_begin, e = half.slip_end;
  Eigen::VectorXd k;
  if (source == SlopeSource::kForce) {
    k = force::SlopeFromNormalForce(r.x_mm, r.normal_n, b, e, o.slope);
  } else {
    k.resize(e - b);
    for (Eigen::Index i = b; i < e; ++i) k[i - b] = scan_slope->At(r.x_mm[i]);
  }
  // Keep the samples where everything is finite.
  Eigen::Index n = 0;
  out->q_n.resize(e - b);
  out->p_n.resize(e - b);
  out->k.resize(e - b);
  out->x_mm.resize(e - b);
  for (Eigen::Index i = b; i < e; ++i) {
    const double q = r.tangential_n[i], p = r.normal_n[i], kk = k[i - b];
    if (!std::isfinite(q) || !std::isfinite(p) || !std::isfinite(kk)) continue;
    out->q_n[n] = q;
    out->p_n[n] = p;
    out->k[n] = kk;
    out->x_mm[n] = r.x_mm[i];
    ++n;
  }
  out->q_n.conservativeResize(n);
  out->p_n.conservativeResize(n);
  out->k.conservativeResize(n);
  out->x_mm.conservativeResize(n);
}

}  // namespace

double WearScarCost(const CycleSamples& samples, double mu) {
  return DirectionCost(samples.forward, mu) +
         DirectionCost(samples.reverse, mu);
}

bool FitMuOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(mu_min >= 0 && mu_max > mu_min))
    return fail("need 0 <= mu_min < mu_max");
  if (grid_points < 3) return fail("grid_points must be >= 3");
  if (!(tolerance > 0)) return fail("tolerance must be > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  return true;
}

bool FrictionFitOptions::IsValid(std::string* why) const {
  return slope.IsValid(why) && fit.IsValid(why);
}

std::string MuFit::BriefReport() const {
  return fmt::format("mu-hat {:.4f}, J {:.4f}, {} samples, {} iterations, {}{}",
                     mu_hat,
                     cost,
                     samples,
                     iterations,
                     message,
                     at_bound ? " (at a bound)" : "");
}

MuFit FitMu(const CycleSamples& samples, const FitMuOptions& o) {
  MuFit fit;
  std::string why;
  if (!o.IsValid(&why)) {
    fit.message = "invalid options: " + why;
    return fit;
  }
  fit.samples =
      static_cast<int>(samples.forward.q_n.size() + samples.reverse.q_n.size());
  if (samples.forward.q_n.size() < 3 || samples.reverse.q_n.size() < 3) {
    fit.message = "too few gross-slip samples";
    return fit;
  }
  const internal::ScalarMinimum m = internal::MinimizeOnInterval(
      [&](double mu) { return WearScarCost(samples, mu); },
      o.mu_min,
      o.mu_max,
      o.grid_points,
      o.tolerance,
      o.max_iterations);
  if (!m.found) {
    fit.message = "J is infinite on the whole interval (|mu k| >= 1)";
    return fit;
  }
  const double x = m.x, fx = m.value;
  const int iter = m.iterations;
  fit.converged = m.converged;
  fit.mu_hat = x;
  fit.cost = fx;
  fit.iterations = iter;
  fit.at_bound =
      (x - o.mu_min) < 10 * o.tolerance || (o.mu_max - x) < 10 * o.tolerance;
  fit.message = fit.converged ? "converged" : "iteration limit reached";
  return fit;
}

Eigen::VectorXd CostCurve(const CycleSamples& samples,
                          const Eigen::VectorXd& mu_grid) {
  Eigen::VectorXd j(mu_grid.size());
  for (Eigen::Index i = 0; i < mu_grid.size(); ++i)
    j[i] = WearScarCost(samples, mu_grid[i]);
  return j;
}

double SlopeProfile::At(double x) const {
  const Eigen::Index n = x_mm.size();
  if (n < 2 || !(x >= x_mm[0] && x <= x_mm[n - 1])) return std::nan("");
  const double* begin = x_mm.data();
  const double* it = std::upper_bound(begin, begin + n, x);
  Eigen::Index i = std::clamp<Eigen::Index>((it - begin) - 1, 0, n - 2);
  const double t = (x - x_mm[i]) / (x_mm[i + 1] - x_mm[i]);
  return (1 - t) * k[i] + t * k[i + 1];
}

CycleSamples GatherCycle(const force::ForceRecord& record,
                         const force::Cycle& cycle,
                         SlopeSource source,
                         const FrictionFitOptions& options,
                         const SlopeProfile* scan_slope) {
  if (source == SlopeSource::kScan && scan_slope == nullptr) {
    throw FusionError(
        "slope from the scan requested but no scan slope profile given");
  }
  CycleSamples s;
  AppendSlip(record, cycle.forward, source, options, scan_slope, &s.forward);
  AppendSlip(record, cycle.reverse, source, options, scan_slope, &s.reverse);
  return s;
}

std::vector<MuFit> FitFrictionPerCycle(const force::ForceRecord& record,
                                       const force::CycleSet& cycles,
                                       SlopeSource source,
                                       const FrictionFitOptions& options,
                                       const SlopeProfile* scan_slope) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("friction fit options: " + why);
  std::vector<MuFit> fits;
  fits.reserve(cycles.cycles.size());
  for (const force::Cycle& c : cycles.cycles) {
    fits.push_back(FitMu(GatherCycle(record, c, source, options, scan_slope),
                         options.fit));
  }
  return fits;
}

}  // namespace wearscar::fusion
