#include "diagnose_model.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/interpolate.h"
#include "wearscar/support/minimize.h"

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
                const std::vector<const double*>& params,
                ResidualTerms* terms) {
  EffectContext c;
  c.x_mm = s.x;
  c.s = s.s;
  c.speed_mm_s = s.speed;
  c.depth_mm = s.depth;
  c.stroke_fraction = s.u;
  c.to_end_mm = s.to_end;
  c.q_slope = s.q_slope;
  c.q_measured_n = s.q;
  c.time_s = s.t;
  c.p_n = s.p;
  c.k = s.k;
  for (size_t e = 0; e < effects.size(); ++e) effects[e]->Apply(params[e], &c);
  const double mu_eff = mu * c.mu_factor;
  const double denom = 1.0 - s.s * mu_eff * c.k;
  if (terms) {
    terms->context = c;
    terms->mu_eff = mu_eff;
    // dQ/dmu_eff of the wear-scar law: P s (1 + k^2) / (1 - s mu_eff k)^2.
    terms->d_model_d_mu_eff =
        denom > 0 ? c.p_n * s.s * (1 + c.k * c.k) / (denom * denom) : 0.0;
  }
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
  const support::ScalarMinimum best = support::MinimizeOnInterval(
      [&](double mu) { return CycleJ(d, c, mu, m); },
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
// J_forward^2 + J_reverse^2. The derivatives in mu and in a shape's
// parameters are analytic (a shape's many parameters each touch a few
// samples; numeric differences would evaluate the cycle twice per
// parameter), central differences for the others as Ceres takes them.
//
// The rows R with R'R = gram: gram = P' L D L' P (LDLT with pivoting), so
// R = D^(1/2) L' P, D at least 0 (a gram); Eigen applies P to the right
// as its transpose.
Eigen::MatrixXd RootOfGram(const Eigen::MatrixXd& gram) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(gram);
  const Eigen::VectorXd root = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd lt = ldlt.matrixU();
  return (root.asDiagonal() * lt) * ldlt.transpositionsP().transpose();
}

// The compressed rows [R_J R_r] as Ceres' residuals (R_r, the last column)
// and each block's Jacobian (its columns from `offsets`).
void WriteCompressed(const Eigen::MatrixXd& rows,
                     const std::vector<int>& offsets,
                     const std::vector<int>& sizes,
                     double* residuals,
                     double** jacobians) {
  const Eigen::Index m = rows.rows(), last = rows.cols() - 1;
  for (Eigen::Index k = 0; k < m; ++k) residuals[k] = rows(k, last);
  for (size_t b = 0; b < sizes.size(); ++b) {
    if (jacobians[b] == nullptr) continue;
    for (Eigen::Index k = 0; k < m; ++k)
      for (int j = 0; j < sizes[b]; ++j)
        jacobians[b][k * sizes[b] + j] = rows(k, offsets[b] + j);
  }
}

// A cycle of many samples is handed to Ceres compressed: for the residuals
// r and their Jacobian J (n samples, P parameters), the P + 1 rows of R
// with R'R = [J r]'[J r]. They give the solver the same cost r'r, gradient
// J'r and Gauss-Newton matrix J'J as the n rows, so the same steps, while
// its elimination of each cycle's mu costs (P + 1) P^2 instead of n P^2
// (a shape's knots touch two samples' rows each, which the gram below
// skips: Ceres would take them as dense). Without the Jacobian the first
// residual is |r| and the others 0.
class CycleCost : public ceres::CostFunction {
 public:
  CycleCost(const Data* d,
            const DiagCycle* c,
            std::vector<const Effect*> effects,
            std::vector<bool> analytic)
      : d_(d),
        c_(c),
        effects_(std::move(effects)),
        analytic_(std::move(analytic)) {
    mutable_parameter_block_sizes()->push_back(1);
    for (const Effect* e : effects_) {
      mutable_parameter_block_sizes()->push_back(
          static_cast<int>(e->ParameterNames().size()));
    }
    for (size_t b = 0; b < parameter_block_sizes().size(); ++b) {
      const int size = parameter_block_sizes()[b];
      offsets_.push_back(columns_);
      numeric_offsets_.push_back(IsAnalytic(b) ? -1 : numeric_columns_);
      columns_ += size;
      if (!IsAnalytic(b)) numeric_columns_ += size;
    }
    const int n = static_cast<int>(c->samples.size());
    compressed_ = n > 2 * (columns_ + 1);
    set_num_residuals(compressed_ ? columns_ + 1 : n);
  }

  bool Evaluate(double const* const* params,
                double* residuals,
                double** jacobians) const override {
    const size_t n = c_->samples.size();
    std::vector<double> r(n);
    std::vector<ResidualTerms> terms(jacobians ? n : 0);
    Residuals(params, r.data(), jacobians ? terms.data() : nullptr);
    if (!jacobians) {
      if (!compressed_) {
        std::copy(r.begin(), r.end(), residuals);
        return true;
      }
      std::fill(residuals, residuals + columns_ + 1, 0.0);
      residuals[0] =
          Eigen::Map<const Eigen::VectorXd>(r.data(), r.size()).norm();
      return true;
    }
    const Eigen::MatrixXd numeric = NumericColumns(params);
    if (!compressed_) {
      std::copy(r.begin(), r.end(), residuals);
      WriteRows(params, terms, numeric, jacobians);
      return true;
    }
    Compress(params, terms, numeric, r, residuals, jacobians);
    return true;
  }

 private:
  static constexpr double kRelativeStep = 1e-6;  // Ceres' default
  double Norm(const Sample& s) const {
    return s.s > 0 ? c_->norm_forward : c_->norm_reverse;
  }
  // mu's block is analytic (dQ/dmu = dQ/dmu_eff times mu_factor); so is a
  // shape's.
  bool IsAnalytic(size_t b) const { return b == 0 || analytic_[b - 1]; }
  void Residuals(double const* const* params,
                 double* out,
                 ResidualTerms* terms) const {
    const std::vector<const double*> p(params + 1,
                                       params + 1 + effects_.size());
    for (size_t i = 0; i < c_->samples.size(); ++i) {
      const Sample& s = c_->samples[i];
      out[i] =
          Residual(
              *d_, s, params[0][0], effects_, p, terms ? &terms[i] : nullptr) /
          Norm(s);
    }
  }
  // The columns of J taken by central differences: the blocks' but the
  // analytic ones', in their order.
  Eigen::MatrixXd NumericColumns(double const* const* params) const {
    const size_t n = c_->samples.size();
    const std::vector<int>& sizes = parameter_block_sizes();
    Eigen::MatrixXd jac(n, numeric_columns_);
    std::vector<double> plus(n), minus(n);
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (IsAnalytic(b)) continue;
      std::vector<double> x(params[b], params[b] + sizes[b]);
      std::vector<const double*> moved(params, params + sizes.size());
      moved[b] = x.data();
      for (int j = 0; j < sizes[b]; ++j) {
        const double x0 = x[j];
        const double h = kRelativeStep * (x0 != 0 ? std::abs(x0) : 1.0);
        x[j] = x0 + h;
        Residuals(moved.data(), plus.data(), nullptr);
        x[j] = x0 - h;
        Residuals(moved.data(), minus.data(), nullptr);
        x[j] = x0;
        for (size_t i = 0; i < n; ++i)
          jac(i, numeric_offsets_[b] + j) = (plus[i] - minus[i]) / (2 * h);
      }
    }
    return jac;
  }
  // An analytic block's derivatives at sample i into grad: its entries
  // are those of mu_factor's gradient (d ln mu_factor) times this, mu's
  // the factor itself.
  double AnalyticScale(size_t b, size_t i, const ResidualTerms& t) const {
    const double d_mu_eff = -t.d_model_d_mu_eff / Norm(c_->samples[i]);
    return b == 0 ? d_mu_eff * t.context.mu_factor : d_mu_eff * t.mu_eff;
  }
  void AnalyticRow(double const* const* params,
                   size_t b,
                   size_t i,
                   const ResidualTerms& t,
                   double* grad) const {
    const double scale = AnalyticScale(b, i, t);
    if (b == 0) {
      grad[0] = scale;
      return;
    }
    effects_[b - 1]->MuFactorGradient(params[b], t.context, grad);
    for (int j = 0; j < parameter_block_sizes()[b]; ++j) grad[j] *= scale;
  }
  void WriteRows(double const* const* params,
                 const std::vector<ResidualTerms>& terms,
                 const Eigen::MatrixXd& numeric,
                 double** jacobians) const {
    const std::vector<int>& sizes = parameter_block_sizes();
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      const int size = sizes[b];
      for (size_t i = 0; i < terms.size(); ++i) {
        double* row = jacobians[b] + i * size;
        if (IsAnalytic(b)) {
          AnalyticRow(params, b, i, terms[i], row);
        } else {
          for (int j = 0; j < size; ++j)
            row[j] = numeric(i, numeric_offsets_[b] + j);
        }
      }
    }
  }
  void Compress(double const* const* params,
                const std::vector<ResidualTerms>& terms,
                const Eigen::MatrixXd& numeric,
                const std::vector<double>& r,
                double* residuals,
                double** jacobians) const {
    const int m = columns_ + 1;
    const std::vector<int>& sizes = parameter_block_sizes();
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(m, m);
    std::vector<int> col;
    std::vector<double> value, grad;
    for (size_t i = 0; i < terms.size(); ++i) {
      col.clear();
      value.clear();
      for (size_t b = 0; b < sizes.size(); ++b) {
        if (!IsAnalytic(b)) {
          for (int j = 0; j < sizes[b]; ++j) {
            col.push_back(offsets_[b] + j);
            value.push_back(numeric(i, numeric_offsets_[b] + j));
          }
          continue;
        }
        grad.resize(sizes[b]);
        if (b == 0) {
          grad[0] = 1.0;
        } else {
          effects_[b - 1]->MuFactorGradient(
              params[b], terms[i].context, grad.data());
        }
        const double scale = AnalyticScale(b, i, terms[i]);
        for (int j = 0; j < sizes[b]; ++j) {
          if (grad[j] == 0) continue;
          col.push_back(offsets_[b] + j);
          value.push_back(scale * grad[j]);
        }
      }
      col.push_back(columns_);
      value.push_back(r[i]);
      for (size_t a = 0; a < col.size(); ++a)
        for (size_t c = 0; c < col.size(); ++c)
          gram(col[a], col[c]) += value[a] * value[c];
    }
    WriteCompressed(RootOfGram(gram), offsets_, sizes, residuals, jacobians);
  }
  const Data* d_;
  const DiagCycle* c_;
  std::vector<const Effect*> effects_;
  std::vector<bool> analytic_;
  // Each block's first column in J and in the numeric columns (-1: none).
  std::vector<int> offsets_, numeric_offsets_;
  int columns_ = 0, numeric_columns_ = 0;
  bool compressed_ = false;
};

// Whether an effect differentiates itself (a shape on mu_factor).
bool HasAnalyticGradient(const Effect* e) {
  const std::vector<double> p = e->Initial();
  std::vector<double> grad(p.size());
  return e->MuFactorGradient(p.data(), EffectContext{}, grad.data());
}

// An effect's penalty residuals (a shape's mean and roughness).
struct PenaltyCost {
  bool operator()(double const* const* params, double* residuals) const {
    effect->Penalty(params[0], weight, residuals);
    return true;
  }
  const Effect* effect;
  double weight;
};

// A penalised shape's effective degrees of freedom at the solution,
// tr((Jd'Jd + Jp'Jp)^-1 Jd'Jd) with Jd the data's and Jp the penalty's
// Jacobian in the shape's parameters (the cycles' mu held).
double EffectiveDof(ceres::Problem* problem,
                    const std::vector<ceres::ResidualBlockId>& data,
                    ceres::ResidualBlockId penalty,
                    std::vector<double>* shape) {
  auto gram = [&](const std::vector<ceres::ResidualBlockId>& blocks) {
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = {shape->data()};
    eo.residual_blocks = blocks;
    ceres::CRSMatrix j;
    problem->Evaluate(eo, nullptr, nullptr, nullptr, &j);
    const Eigen::Index n = static_cast<Eigen::Index>(shape->size());
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
    for (int r = 0; r < j.num_rows; ++r) {
      Eigen::VectorXd row = Eigen::VectorXd::Zero(n);
      for (int k = j.rows[r]; k < j.rows[r + 1]; ++k)
        row[j.cols[k]] = j.values[k];
      g += row * row.transpose();
    }
    return g;
  };
  const Eigen::MatrixXd hd = gram(data), hp = gram({penalty});
  return (hd + hp).ldlt().solve(hd).trace();
}

// The penalties that hold shapes smooth (their weight per fitted cycle,
// `cycles` of them) and the effects' bounds; the penalties' blocks.
std::vector<ceres::ResidualBlockId> AddPenaltiesAndBounds(
    Model* model, double cycles, ceres::Problem* problem) {
  Model& m = *model;
  std::vector<ceres::ResidualBlockId> blocks;
  for (size_t e = 0; e < m.effects.size(); ++e) {
    const Effect* effect = m.effects[e];
    if (effect->PenaltyCount() == 0) continue;
    const double weight = (e < m.penalty.size() ? m.penalty[e] : 0.0) * cycles;
    auto* cost =
        new ceres::DynamicNumericDiffCostFunction<PenaltyCost, ceres::CENTRAL>(
            new PenaltyCost{effect, weight});
    cost->AddParameterBlock(static_cast<int>(m.params[e].size()));
    cost->SetNumResiduals(effect->PenaltyCount());
    blocks.push_back(
        problem->AddResidualBlock(cost, nullptr, m.params[e].data()));
  }
  for (size_t e = 0; e < m.effects.size(); ++e) {
    const auto lo = m.effects[e]->Lower(), hi = m.effects[e]->Upper();
    double* params = m.params[e].data();
    for (size_t k = 0; k < lo.size(); ++k) {
      problem->SetParameterLowerBound(params, static_cast<int>(k), lo[k]);
      problem->SetParameterUpperBound(params, static_cast<int>(k), hi[k]);
    }
  }
  return blocks;
}

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
  std::vector<ceres::ResidualBlockId> data_blocks;
  std::vector<bool> analytic;
  for (const Effect* e : m->effects) analytic.push_back(HasAnalyticGradient(e));
  for (size_t i = 0; i < train.size(); ++i) {
    const DiagCycle& c = d.cycles[train[i]];
    std::vector<double*> blocks = {&mu[i]};
    for (auto& p : m->params) blocks.push_back(p.data());
    auto* cost = new CycleCost(&d, &c, m->effects, analytic);
    data_blocks.push_back(problem.AddResidualBlock(cost, nullptr, blocks));
    problem.SetParameterLowerBound(&mu[i], 0, d.options->mu_fit.mu_min);
    problem.SetParameterUpperBound(&mu[i], 0, d.options->mu_fit.mu_max);
  }
  const std::vector<ceres::ResidualBlockId> penalty_blocks =
      AddPenaltiesAndBounds(m, static_cast<double>(train.size()), &problem);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(
          so.sparse_linear_algebra_library_type)) {
    so.linear_solver_type = ceres::DENSE_SCHUR;
  }
  so.max_num_iterations = d.options->solver_iterations;
  // With bounds Ceres tries each step in a projected line search first. A
  // cubic interpolation asks the Jacobian at every trial, so at every
  // step; a quadratic one the cost alone, and gives the same step
  // whenever the whole step is taken.
  so.line_search_interpolation_type = ceres::QUADRATIC;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  ++d.solves;
  if (summary.termination_type != ceres::CONVERGENCE) ++d.not_converged;
  m->dof.assign(m->effects.size(), 0.0);
  size_t penalised = 0;
  for (size_t e = 0; e < m->effects.size(); ++e) {
    if (m->effects[e]->PenaltyCount() == 0) continue;
    m->dof[e] = EffectiveDof(
        &problem, data_blocks, penalty_blocks[penalised++], &m->params[e]);
  }
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
double CycleBic(const Data& d, const Model& m, double parameters) {
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

double ParameterCount(const Model& m) {
  double p = 0;
  for (size_t e = 0; e < m.params.size(); ++e) {
    p += e < m.dof.size() && m.dof[e] > 0
             ? m.dof[e]
             : static_cast<double>(m.params[e].size());
  }
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

// How far the residual repeats: the maps of the two halves of the
// diagnosis cycles, m1 and m2 per bin, agree in what repeats and differ in
// noise. The halves do not share the cycles their slopes were averaged
// over, so the slope's noise (common to neighbouring cycles) does not pass
// for a repeatable residual. Repeatable power: mean(m1 m2); its noise:
// mean((m1 - m2)^2) / 4 per bin of the mean map.
void Repeatability(const Eigen::MatrixXd& half1,
                   const Eigen::MatrixXd& half2,
                   ResidualMap* map) {
  double common = 0, diff = 0;
  int bins = 0;
  for (Eigen::Index i = 0; i < half1.size(); ++i) {
    const double a = half1.data()[i], b = half2.data()[i];
    if (!std::isfinite(a) || !std::isfinite(b)) continue;
    common += a * b;
    diff += 0.25 * (a - b) * (a - b);
    ++bins;
  }
  if (bins == 0 || !(diff > 0)) return;
  common /= bins;
  diff /= bins;
  // A pure-noise map: mean(m1 m2) = 0 with sd 2 diff / sqrt(bins).
  map->repeatable_z = common / (2 * diff / std::sqrt(bins));
  map->repeatable_rms_n = std::sqrt(std::max(0.0, common));
}

// The signed map's direction-odd and direction-even parts.
void OddEven(ResidualMap* map) {
  const Eigen::Index nb = map->mean_n.cols();
  map->odd_n.resize(nb);
  map->even_n.resize(nb);
  double odd2 = 0, even2 = 0;
  int n = 0;
  for (Eigen::Index b = 0; b < nb; ++b) {
    const double f = map->mean_n(0, b), r = map->mean_n(1, b);
    const bool both = map->mean_abs_n(0, b) > 0 && map->mean_abs_n(1, b) > 0;
    map->odd_n[b] = both ? 0.5 * (f - r) : std::nan("");
    map->even_n[b] = both ? 0.5 * (f + r) : std::nan("");
    if (!both) continue;
    odd2 += map->odd_n[b] * map->odd_n[b];
    even2 += map->even_n[b] * map->even_n[b];
    ++n;
  }
  map->odd_rms_n = n > 0 ? std::sqrt(odd2 / n) : 0.0;
  map->even_rms_n = n > 0 ? std::sqrt(even2 / n) : 0.0;
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
  // Per bin and half of the cycles: the sum of the cycles' mean residuals
  // and the count of cycles.
  Eigen::MatrixXd half_sum[2] = {Eigen::MatrixXd::Zero(2, nb),
                                 Eigen::MatrixXd::Zero(2, nb)};
  Eigen::MatrixXd half_n[2] = {half_sum[0], half_sum[0]};
  for (size_t ci = 0; ci < d.cycles.size(); ++ci) {
    const DiagCycle& c = d.cycles[ci];
    double j;
    const double mu = FitCycleMu(d, c, m, &j);
    const int block = static_cast<int>(ci * nk / d.cycles.size());
    MapSums one(nb, 2, 1);
    for (const Sample& s : c.samples) {
      const double r = Residual(d, s, mu, m.effects, p);
      AddSample(s, r, block, x_lo, x_hi, &sums);
      AddSample(s, r, 0, x_lo, x_hi, &one);
    }
    const int h = 2 * ci < d.cycles.size() ? 0 : 1;
    for (int row = 0; row < 2; ++row) {
      for (int b = 0; b < nb; ++b) {
        if (one.cnt(row, b) == 0) continue;
        half_sum[h](row, b) += one.ss(row, b) / one.cnt(row, b);
        half_n[h](row, b) += 1;
      }
    }
  }
  const auto mean_of = [](const Eigen::MatrixXd& sum,
                          const Eigen::MatrixXd& n) {
    Eigen::MatrixXd mean = sum.cwiseQuotient(n);
    for (Eigen::Index i = 0; i < mean.size(); ++i) {
      if (n.data()[i] == 0) mean.data()[i] = std::nan("");
    }
    return mean;
  };
  Repeatability(
      mean_of(half_sum[0], half_n[0]), mean_of(half_sum[1], half_n[1]), &map);
  map.mean_abs_n = sums.sa.cwiseQuotient(sums.cnt.cwiseMax(1.0));
  map.mean_n = sums.ss.cwiseQuotient(sums.cnt.cwiseMax(1.0));
  map.reversal_mean_abs_n = sums.ra.cwiseQuotient(sums.rc.cwiseMax(1.0));
  map.block_mean_abs_n = sums.ka.cwiseQuotient(sums.kc.cwiseMax(1.0));
  for (int k = 0; k < nk; ++k) {
    map.block_first_cycle.push_back(d.cycles[k * d.cycles.size() / nk].cycle);
  }
  map.mean_abs_n_all = sums.all_n > 0 ? sums.all / sums.all_n : 0.0;
  OddEven(&map);
  map.where = Where(map, sums);
  return map;
}

ParitySplit SplitByParity(const Data& d,
                          const Model& m,
                          const std::vector<double>& mu) {
  const int nb = d.options->position_bins;
  MapSums sums(nb, 1, 1);
  std::vector<const double*> p;
  for (const auto& v : m.params) p.push_back(v.data());
  for (size_t ci = 0; ci < d.cycles.size(); ++ci) {
    for (const Sample& s : d.cycles[ci].samples) {
      AddSample(
          s, Residual(d, s, mu[ci], m.effects, p), 0, d.x_lo, d.x_hi, &sums);
    }
  }
  ResidualMap map;
  map.mean_n = sums.ss.cwiseQuotient(sums.cnt.cwiseMax(1.0));
  map.mean_abs_n = sums.cnt;  // only whether a bin has samples
  OddEven(&map);
  return {map.odd_rms_n, map.even_rms_n};
}

// Per-direction binned average of a channel over the diagnosis cycles,
// over each half's whole stroke: P (and a depth channel) follows the track
// in stick as in gross slip, and where the slip starts late (a steep wall
// near a stroke end holds Q's climb back) the slope would otherwise be
// missing, or extrapolated from half a window, over that part of the track.
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
      for (Eigen::Index i = h->begin; i < h->end; ++i) {
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
