#include "diagnose_model.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "minimize.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/interpolate.h"

namespace wearscar::fusion::internal {
namespace {

double QAt(const Data& d, const Sample& s, double shift) {
  if (shift == 0) return s.q;
  // Linear interpolation of the measured Q at t + shift (uniform sampling).
  const double pos = static_cast<double>(s.index) + shift / d.dt;
  const double last = static_cast<double>(d.record->size() - 1);
  return support::InterpolateAtIndex(d.record->tangential_n,
                                     std::clamp(pos, 0.0, last));
}

}  // namespace

// Residual Q_measured - Q_model of one sample.
double Residual(const Data& d,
                const Sample& s,
                double mu,
                const std::vector<const Effect*>& effects,
                const std::vector<const double*>& params) {
  EffectContext c;
  c.x_mm = s.x;
  c.s = s.s;
  c.speed_mm_s = s.speed;
  c.depth_mm = s.depth;
  c.softness = s.softness;
  c.to_end_mm = s.to_end;
  c.q_slope = s.q_slope;
  c.q_measured_n = s.q;
  c.time_s = s.t;
  c.p_n = s.p;
  c.k = s.k;
  for (size_t e = 0; e < effects.size(); ++e) effects[e]->Apply(params[e], &c);
  const double mu_eff = mu * c.mu_factor;
  const double denom = 1.0 - s.s * mu_eff * c.k;
  const double model =
      denom > 0
          ? WearScarTangentialForce(c.p_n, c.k, mu_eff, s.s) + s.s * c.extra_n
          : d.options->undefined_model_residual_n;
  return QAt(d, s, c.time_shift_s) - model;
}

namespace {

// Eq. 6 for one cycle under a model with mu given.
double CycleJ(const Data& d, const DiagCycle& c, double mu, const Model& m) {
  std::vector<const double*> p;
  for (const auto& v : m.params) p.push_back(v.data());
  double f2 = 0, r2 = 0;
  for (const Sample& s : c.samples) {
    const double r = Residual(d, s, mu, m.effects, p);
    (s.s > 0 ? f2 : r2) += r * r;
  }
  return std::sqrt(f2) / c.norm_forward + std::sqrt(r2) / c.norm_reverse;
}

}  // namespace

// mu of one cycle with the effects held fixed.
double FitCycleMu(const Data& d,
                  const DiagCycle& c,
                  const Model& m,
                  double* j) {
  const FitMuOptions& f = d.options->mu_fit;
  const ScalarMinimum best =
      MinimizeOnInterval([&](double mu) { return CycleJ(d, c, mu, m); },
                         f.mu_min,
                         f.mu_max,
                         f.grid_points,
                         f.tolerance,
                         f.max_iterations);
  *j = best.value;
  return best.x;
}

namespace {

// Ceres residuals of one cycle, normalised so that their squared sum is
// J_forward^2 + J_reverse^2.
struct CycleCost {
  CycleCost(const Data* d,
            const DiagCycle* c,
            std::vector<const Effect*> effects)
      : d_(d), c_(c), effects_(std::move(effects)) {}
  bool operator()(double const* const* params, double* residuals) const {
    std::vector<const double*> p(params + 1, params + 1 + effects_.size());
    for (size_t i = 0; i < c_->samples.size(); ++i) {
      const Sample& s = c_->samples[i];
      residuals[i] = Residual(*d_, s, params[0][0], effects_, p) /
                     (s.s > 0 ? c_->norm_forward : c_->norm_reverse);
    }
    return true;
  }
  const Data* d_;
  const DiagCycle* c_;
  std::vector<const Effect*> effects_;
};

}  // namespace

// Fits the effect parameters (shared) and one mu per cycle on `train`.
// Returns the per-cycle mu, updates m.params.
std::vector<double> FitModel(const Data& d,
                             const std::vector<int>& train,
                             Model* m) {
  std::vector<double> mu(train.size(), 0.1);
  if (m->effects.empty()) {
    for (size_t i = 0; i < train.size(); ++i) {
      double j;
      mu[i] = FitCycleMu(d, d.cycles[train[i]], *m, &j);
    }
    return mu;
  }
  // Start mu from the plain fit of each cycle.
  Model plain;
  for (size_t i = 0; i < train.size(); ++i) {
    double j;
    mu[i] = FitCycleMu(d, d.cycles[train[i]], plain, &j);
  }
  ceres::Problem problem;
  for (size_t i = 0; i < train.size(); ++i) {
    const DiagCycle& c = d.cycles[train[i]];
    auto* cost =
        new ceres::DynamicNumericDiffCostFunction<CycleCost, ceres::CENTRAL>(
            new CycleCost(&d, &c, m->effects));
    cost->AddParameterBlock(1);
    std::vector<double*> blocks = {&mu[i]};
    for (auto& p : m->params) {
      cost->AddParameterBlock(static_cast<int>(p.size()));
      blocks.push_back(p.data());
    }
    cost->SetNumResiduals(static_cast<int>(c.samples.size()));
    problem.AddResidualBlock(cost, nullptr, blocks);
    problem.SetParameterLowerBound(&mu[i], 0, d.options->mu_fit.mu_min);
    problem.SetParameterUpperBound(&mu[i], 0, d.options->mu_fit.mu_max);
  }
  for (size_t e = 0; e < m->effects.size(); ++e) {
    const auto lo = m->effects[e]->Lower(), hi = m->effects[e]->Upper();
    for (size_t k = 0; k < lo.size(); ++k) {
      problem.SetParameterLowerBound(
          m->params[e].data(), static_cast<int>(k), lo[k]);
      problem.SetParameterUpperBound(
          m->params[e].data(), static_cast<int>(k), hi[k]);
    }
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(
          so.sparse_linear_algebra_library_type)) {
    so.linear_solver_type = ceres::DENSE_SCHUR;
  }
  so.max_num_iterations = d.options->solver_iterations;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  ++d.solves;
  if (summary.termination_type != ceres::CONVERGENCE) ++d.not_converged;
  return mu;
}

// Held-out J per diagnosis cycle (block cross-validation over whole cycles).
std::vector<double> HeldOut(const Data& d,
                            const Model& m,
                            int folds,
                            std::vector<std::vector<double>>* fold_params) {
  const int n = static_cast<int>(d.cycles.size());
  std::vector<double> j(n, 0.0);
  if (fold_params) fold_params->clear();
  for (int f = 0; f < folds; ++f) {
    const int lo = f * n / folds, hi = (f + 1) * n / folds;
    std::vector<int> train;
    for (int i = 0; i < n; ++i) {
      if (i < lo || i >= hi) train.push_back(i);
    }
    Model fm = m;
    FitModel(d, train, &fm);
    for (int i = lo; i < hi; ++i) FitCycleMu(d, d.cycles[i], fm, &j[i]);
    if (fold_params) {
      std::vector<double> flat;
      for (const auto& p : fm.params)
        flat.insert(flat.end(), p.begin(), p.end());
      fold_params->push_back(flat);
    }
  }
  return j;
}

// Per-cycle BIC of a model fitted on all diagnosis cycles: each cycle counts
// as one observation (samples within a cycle are strongly correlated).
double CycleBic(const Data& d, const Model& m, int parameters) {
  std::vector<int> all(d.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  double sum = 0;
  for (size_t i = 0; i < d.cycles.size(); ++i) {
    double j;
    FitCycleMu(d, d.cycles[i], m, &j);
    sum += j * j;
  }
  const double n = static_cast<double>(d.cycles.size());
  return n * std::log(sum / n) + parameters * std::log(n);
}

int ParameterCount(const Model& m) {
  int p = 0;
  for (const auto& v : m.params) p += static_cast<int>(v.size());
  return p;
}

double Mean(const std::vector<double>& v) {
  return v.empty() ? 0.0
                   : std::accumulate(v.begin(), v.end(), 0.0) /
                         static_cast<double>(v.size());
}

namespace {

// The residuals' sums a map is made of: per direction along x, per
// direction from the last reversal, per block of cycles, and near the
// stroke's ends.
struct MapSums {
  MapSums(int nb, int nr, int nk)
      : sa(Eigen::MatrixXd::Zero(2, nb)),
        ss(sa),
        cnt(sa),
        ra(Eigen::MatrixXd::Zero(2, nr)),
        rc(ra),
        ka(Eigen::VectorXd::Zero(nk)),
        kc(ka) {}
  Eigen::MatrixXd sa, ss, cnt, ra, rc;
  Eigen::VectorXd ka, kc;
  double all = 0, end_sum = 0, rest_sum = 0, start_sum = 0;
  long all_n = 0, end_n = 0, rest_n = 0, start_n = 0;
};

void AddSample(const Sample& s,
               double r,
               int block,
               double x_lo,
               double x_hi,
               MapSums* m) {
  const int nb = static_cast<int>(m->sa.cols()),
            nr = static_cast<int>(m->ra.cols());
  const double stroke = x_hi - x_lo;
  const int row = s.s > 0 ? 0 : 1;
  const int b =
      std::clamp(static_cast<int>((s.x - x_lo) / stroke * nb), 0, nb - 1);
  m->sa(row, b) += std::abs(r);
  m->ss(row, b) += r;
  m->cnt(row, b) += 1;
  const double from_rev = stroke - s.to_end;
  const int rb =
      std::clamp(static_cast<int>(from_rev / stroke * nr), 0, nr - 1);
  m->ra(row, rb) += std::abs(r);
  m->rc(row, rb) += 1;
  m->ka[block] += std::abs(r);
  m->kc[block] += 1;
  m->all += std::abs(r);
  ++m->all_n;
  if (s.to_end < 0.1 * stroke) {
    m->end_sum += std::abs(r);
    ++m->end_n;
  } else if (from_rev < 0.1 * stroke) {
    m->start_sum += std::abs(r);
    ++m->start_n;
  } else {
    m->rest_sum += std::abs(r);
    ++m->rest_n;
  }
}

// The map in words.
std::string Where(const ResidualMap& map, const MapSums& m) {
  Eigen::Index row, col;
  map.mean_abs_n.maxCoeff(&row, &col);
  std::vector<double> bins(map.mean_abs_n.data(),
                           map.mean_abs_n.data() + map.mean_abs_n.size());
  std::nth_element(bins.begin(), bins.begin() + bins.size() / 2, bins.end());
  const double median = std::max(bins[bins.size() / 2], 1e-12);
  const double fwd = (m.ss.row(0).sum()) / std::max(1.0, m.cnt.row(0).sum());
  const double rev = (m.ss.row(1).sum()) / std::max(1.0, m.cnt.row(1).sum());
  const double rest = m.rest_n > 0 ? m.rest_sum / m.rest_n : 0.0;
  return fmt::format(
      "mean |r| {:.3f} N; largest at x = {:.2f} mm moving {} ({:.1f}x the "
      "median bin); "
      "approaching the stroke end {:.2f} N, just after a reversal {:.2f} N, "
      "elsewhere {:.2f} N; "
      "mean r forward {:+.3f} N, reverse {:+.3f} N; first cycles {:.3f} N, "
      "last {:.3f} N",
      map.mean_abs_n_all,
      map.x_mm[col],
      row == 0 ? "forward" : "in reverse",
      map.mean_abs_n(row, col) / median,
      m.end_n ? m.end_sum / m.end_n : 0.0,
      m.start_n ? m.start_sum / m.start_n : 0.0,
      rest,
      fwd,
      rev,
      map.block_mean_abs_n[0],
      map.block_mean_abs_n[map.block_mean_abs_n.size() - 1]);
}

}  // namespace

ResidualMap Map(const Data& d,
                const Model& m,
                const DiagnoseOptions& o,
                double x_lo,
                double x_hi) {
  ResidualMap map;
  const int nb = o.position_bins, nr = o.reversal_bins, nk = o.cycle_blocks;
  map.x_mm = Eigen::VectorXd::LinSpaced(
      nb, x_lo + 0.5 * (x_hi - x_lo) / nb, x_hi - 0.5 * (x_hi - x_lo) / nb);
  const double stroke = x_hi - x_lo;
  map.from_reversal_mm = Eigen::VectorXd::LinSpaced(
      nr, 0.5 * stroke / nr, stroke - 0.5 * stroke / nr);
  MapSums sums(nb, nr, nk);
  std::vector<const double*> p;
  for (const auto& v : m.params) p.push_back(v.data());
  for (size_t ci = 0; ci < d.cycles.size(); ++ci) {
    const DiagCycle& c = d.cycles[ci];
    double j;
    const double mu = FitCycleMu(d, c, m, &j);
    const int block = static_cast<int>(ci * nk / d.cycles.size());
    for (const Sample& s : c.samples)
      AddSample(s, Residual(d, s, mu, m.effects, p), block, x_lo, x_hi, &sums);
  }
  map.mean_abs_n = sums.sa.cwiseQuotient(sums.cnt.cwiseMax(1.0));
  map.mean_n = sums.ss.cwiseQuotient(sums.cnt.cwiseMax(1.0));
  map.reversal_mean_abs_n = sums.ra.cwiseQuotient(sums.rc.cwiseMax(1.0));
  map.block_mean_abs_n = sums.ka.cwiseQuotient(sums.kc.cwiseMax(1.0));
  for (int k = 0; k < nk; ++k) {
    map.block_first_cycle.push_back(d.cycles[k * d.cycles.size() / nk].cycle);
  }
  map.mean_abs_n_all = sums.all_n > 0 ? sums.all / sums.all_n : 0.0;
  map.where = Where(map, sums);
  return map;
}

// Per-direction binned average of a channel over the diagnosis cycles.
Eigen::MatrixXd BinProfile(const force::ForceRecord& r,
                           const force::CycleSet& cycles,
                           const std::vector<int>& use,
                           const Eigen::VectorXd& channel,
                           double x0,
                           double step,
                           Eigen::Index bins) {
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(2, bins), cnt = sum;
  for (int c : use) {
    for (const force::HalfCycle* h :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      const int row = h->direction > 0 ? 0 : 1;
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        if (!std::isfinite(r.x_mm[i]) || !std::isfinite(channel[i])) continue;
        const Eigen::Index b =
            static_cast<Eigen::Index>(std::floor((r.x_mm[i] - x0) / step));
        if (b < 0 || b >= bins) continue;
        sum(row, b) += channel[i];
        cnt(row, b) += 1;
      }
    }
  }
  Eigen::MatrixXd out(2, bins);
  for (int row = 0; row < 2; ++row) {
    for (Eigen::Index b = 0; b < bins; ++b) {
      out(row, b) = cnt(row, b) > 0 ? sum(row, b) / cnt(row, b) : std::nan("");
    }
  }
  return out;
}

}  // namespace wearscar::fusion::internal
