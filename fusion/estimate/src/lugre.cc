#include "wearscar/fusion/lugre.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/fusion/error.h"
#include "wearscar/support/robust_stats.h"

namespace wearscar::fusion {
namespace {

// One step of the bristle state and the friction force at its end.
template <typename T>
T LugreStep(const T* p, double fc, double fs, double v, double h, T* z) {
  using std::abs;
  using std::exp;
  const T& sigma0 = p[0];
  const T& sigma1 = p[1];
  const T& sigma2 = p[2];
  const T& vs = p[3];
  const T r = v / vs;
  const T s = fc + (fs - fc) * exp(-r * r);
  const T a = sigma0 * std::abs(v) / s;
  if (std::abs(v) > 0) {
    const T z_ss = v / a;
    *z = z_ss + (*z - z_ss) * exp(-a * h);
  }
  const T zdot = v - a * *z;
  return sigma0 * *z + sigma1 * zdot + sigma2 * v;
}

// Residuals Q_m - Q_LuGre over a cycle, the bristle state carried through
// a warm-up stretch first:
//   r_i = Q_m,i - (sigma0 z_i + sigma1 dz_i/dt + sigma2 v_i).
struct LugreCost {
  LugreCost(const std::vector<double>* dt,
            const std::vector<double>* v,
            const std::vector<double>* q,
            size_t warmup,
            double fc,
            double fs)
      : dt_(dt), v_(v), q_(q), warmup_(warmup), fc_(fc), fs_(fs) {}

  template <typename T>
  bool operator()(T const* const* params, T* residuals) const {
    const T* p = params[0];
    T z = T(0.0);
    for (size_t i = 0; i < v_->size(); ++i) {
      const T f = LugreStep(p, fc_, fs_, (*v_)[i], (*dt_)[i], &z);
      if (i >= warmup_) residuals[i - warmup_] = (*q_)[i] - f;
    }
    return true;
  }

  static ceres::CostFunction* Create(const std::vector<double>* dt,
                                     const std::vector<double>* v,
                                     const std::vector<double>* q,
                                     size_t warmup,
                                     double fc,
                                     double fs) {
    auto* cost = new ceres::DynamicAutoDiffCostFunction<LugreCost, 8>(
        new LugreCost(dt, v, q, warmup, fc, fs));
    cost->AddParameterBlock(4);
    cost->SetNumResiduals(static_cast<int>(v->size() - warmup));
    return cost;
  }

  const std::vector<double>* dt_;
  const std::vector<double>* v_;
  const std::vector<double>* q_;
  size_t warmup_;
  double fc_, fs_;
};

using support::Percentile;

}  // namespace

bool LugreOptions::IsValid(std::string* why) const {
  if (coulomb_n < 0 || static_n < 0 || (static_n > 0 && coulomb_n > static_n)) {
    if (why) *why = "need 0 <= F_c <= F_s (0 = estimate)";
    return false;
  }
  if (max_iterations < 1) {
    if (why) *why = "max_iterations must be >= 1";
    return false;
  }
  if (!(initial.sigma0_n_per_mm > 0 && initial.stribeck_speed_mm_s > 0 &&
        std::isfinite(initial.sigma1_n_s_per_mm) &&
        std::isfinite(initial.sigma2_n_s_per_mm))) {
    if (why) *why = "the initial sigma0 and v_s must be > 0, all finite";
    return false;
  }
  return true;
}

std::string LugreFit::BriefReport() const {
  const auto& p = parameters;
  return fmt::format(
      "sigma0 {:.4g} N/mm, sigma1 {:.3g} Ns/mm, sigma2 {:.3g} Ns/mm ({}), v_s "
      "{:.3g} mm/s; "
      "F_c {:.3g} N, F_s {:.3g} N; J {:.4f}; {}",
      p.sigma0_n_per_mm,
      p.sigma1_n_s_per_mm,
      p.sigma2_n_s_per_mm,
      p.sigma2_n_s_per_mm < 0 ? "negative damping" : "positive",
      p.stribeck_speed_mm_s,
      p.coulomb_n,
      p.static_n,
      cost,
      message);
}

Eigen::VectorXd SimulateLugre(const LugreParameters& p,
                              const Eigen::Ref<const Eigen::VectorXd>& time_s,
                              const Eigen::Ref<const Eigen::VectorXd>& v,
                              double z0_mm) {
  const double params[4] = {p.sigma0_n_per_mm,
                            p.sigma1_n_s_per_mm,
                            p.sigma2_n_s_per_mm,
                            p.stribeck_speed_mm_s};
  Eigen::VectorXd f(v.size());
  double z = z0_mm;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double h = i > 0 ? time_s[i] - time_s[i - 1]
                           : (v.size() > 1 ? time_s[1] - time_s[0] : 0);
    f[i] = LugreStep(params, p.coulomb_n, p.static_n, v[i], h, &z);
  }
  return f;
}

namespace {

// F_c and F_s where not given (0): the median |Q| of the central half of
// each gross slip, and the 99th percentile of |Q| over the cycle (at least
// F_c).
void CoulombAndStatic(const force::ForceRecord& r,
                      const force::Cycle& c,
                      double* fc,
                      double* fs) {
  if (*fc != 0 && *fs != 0) return;
  std::vector<double> central, all;
  for (const force::HalfCycle* h : {&c.forward, &c.reverse}) {
    const Eigen::Index n = h->slip_end - h->slip_begin;
    for (Eigen::Index i = h->slip_begin + n / 4; i < h->slip_end - n / 4; ++i)
      central.push_back(std::abs(r.tangential_n[i]));
    for (Eigen::Index i = h->begin; i < h->end; ++i)
      all.push_back(std::abs(r.tangential_n[i]));
  }
  if (*fc == 0) *fc = Percentile(central, 0.5);
  if (*fs == 0) *fs = std::max(*fc, Percentile(all, 0.99));
}

// The samples the fit runs over: time steps, velocities and Q from the
// warm-up half cycle before the cycle to its end; `warmup` of them before
// the cycle.
struct LugreSamples {
  std::vector<double> dt, v, q;
  size_t warmup = 0;
  Eigen::Index begin = 0;  // the cycle's first sample in the record
};

LugreSamples GatherLugre(const force::ForceRecord& r,
                         const force::CycleSet& cycles,
                         int cycle) {
  LugreSamples s;
  const force::Cycle& c = cycles.cycles[cycle];
  s.begin = c.forward.begin;
  // Warm up the bristle over the previous half cycle (or what exists).
  const Eigen::Index warm_begin = cycle > 0
                                      ? cycles.cycles[cycle - 1].reverse.begin
                                      : std::max<Eigen::Index>(1, s.begin);
  for (Eigen::Index i = std::max<Eigen::Index>(1, warm_begin);
       i < c.reverse.end;
       ++i) {
    const double h = r.time_s[i] - r.time_s[i - 1];
    const Eigen::Index a = std::max<Eigen::Index>(0, i - 2),
                       b = std::min(r.size() - 1, i + 2);
    // Velocity over a 5-sample centred difference (LVDT noise).
    const double vel = (r.x_mm[b] - r.x_mm[a]) / (r.time_s[b] - r.time_s[a]);
    s.dt.push_back(h);
    s.v.push_back(std::isfinite(vel) ? vel : 0.0);
    s.q.push_back(std::isfinite(r.tangential_n[i]) ? r.tangential_n[i] : 0.0);
  }
  s.warmup =
      static_cast<size_t>(s.begin - std::max<Eigen::Index>(1, warm_begin));
  return s;
}

// How the fit ended: converged, or fitted with a negative damping (it fits
// the loop but no bristle dissipates energy that way: reported as fitted,
// not as a physical model), or the solver's message.
void JudgeFit(const ceres::Solver::Summary& summary,
              const double* params,
              LugreFit* fit) {
  fit->iterations = static_cast<int>(summary.iterations.size());
  fit->converged = summary.termination_type == ceres::CONVERGENCE;
  std::string implausible;
  if (params[1] < 0) implausible = "sigma1 < 0";
  if (params[2] < 0)
    implausible +=
        (implausible.empty() ? "" : ", ") + std::string("sigma2 < 0");
  fit->physically_plausible = implausible.empty();
  fit->message = summary.termination_type != ceres::CONVERGENCE
                     ? summary.message
                 : implausible.empty()
                     ? "converged"
                     : "fitted (physically implausible: " + implausible +
                           ": a negative damping fits the loop's shape but "
                           "is no material's; LuGre is a comparison and "
                           "does not change mu-hat)";
}

// The fitted model along the cycle and its cost (paper Eq. 11).
void TraceCycle(const force::ForceRecord& r,
                const LugreSamples& s,
                const double* params,
                double fc,
                double fs,
                LugreFit* fit) {
  const size_t n = s.v.size() - s.warmup;
  fit->samples = static_cast<int>(n);
  fit->time_s.resize(n);
  fit->x_mm.resize(n);
  fit->q_measured_n.resize(n);
  fit->q_lugre_n.resize(n);
  double z = 0, num = 0, den = 0;
  for (size_t i = 0; i < s.v.size(); ++i) {
    const double f = LugreStep(params, fc, fs, s.v[i], s.dt[i], &z);
    if (i < s.warmup) continue;
    const size_t k = i - s.warmup;
    const Eigen::Index src = s.begin + static_cast<Eigen::Index>(k);
    fit->time_s[k] = r.time_s[src];
    fit->x_mm[k] = r.x_mm[src];
    fit->q_measured_n[k] = s.q[i];
    fit->q_lugre_n[k] = f;
    num += (s.q[i] - f) * (s.q[i] - f);
    den += s.q[i] * s.q[i];
  }
  fit->cost = den > 0 ? std::sqrt(num / den) : std::nan("");
}

}  // namespace

LugreFit FitLugre(const force::ForceRecord& r,
                  const force::CycleSet& cycles,
                  int cycle,
                  const LugreOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("LuGre options: " + why);
  if (cycle < 0 || cycle >= static_cast<int>(cycles.cycles.size())) {
    throw FusionError(fmt::format("LuGre: cycle {} is not among the {} cycles",
                                  cycle,
                                  cycles.cycles.size()));
  }
  const LugreSamples s = GatherLugre(r, cycles, cycle);
  double fc = options.coulomb_n, fs = options.static_n;
  CoulombAndStatic(r, cycles.cycles[cycle], &fc, &fs);
  const LugreParameters& p0 = options.initial;
  double params[4] = {p0.sigma0_n_per_mm,
                      p0.sigma1_n_s_per_mm,
                      p0.sigma2_n_s_per_mm,
                      p0.stribeck_speed_mm_s};
  ceres::Problem problem;
  problem.AddResidualBlock(
      LugreCost::Create(&s.dt, &s.v, &s.q, s.warmup, fc, fs), nullptr, params);
  problem.SetParameterLowerBound(params, 0, 1e-3);
  problem.SetParameterLowerBound(params, 3, 1e-3);
  ceres::Solver::Options so;
  so.max_num_iterations = options.max_iterations;
  so.linear_solver_type = ceres::DENSE_QR;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  LugreFit fit;
  fit.parameters = {params[0], params[1], params[2], params[3], fc, fs};
  JudgeFit(summary, params, &fit);
  TraceCycle(r, s, params, fc, fs, &fit);
  return fit;
}

}  // namespace wearscar::fusion
