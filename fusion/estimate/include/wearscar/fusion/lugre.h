#pragma once

#include <Eigen/Core>
#include <string>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/error.h"

namespace wearscar::fusion {

// LuGre friction (paper Eqs. 8-10):
//   F = sigma0 z + sigma1 dz/dt + sigma2 v
//   dz/dt = v - sigma0 |v| z / s(v)
//   s(v) = F_c + (F_s - F_c) exp(-(v / v_s)^2)
struct LugreParameters {
  double sigma0_n_per_mm = 0.0;    // bristle stiffness
  double sigma1_n_s_per_mm = 0.0;  // bristle damping
  double sigma2_n_s_per_mm =
      0.0;  // viscous term (negative = velocity weakening)
  double stribeck_speed_mm_s = 0.0;
  double coulomb_n = 0.0;  // F_c, given
  double static_n = 0.0;   // F_s, given
};

// Simulates F over a sampled trajectory. The bristle state uses the exact
// solution of its linear ODE for the velocity held constant over a sample:
//   z(t + h) = z_ss + (z(t) - z_ss) exp(-a h),  a = sigma0 |v| / s(v),
// stable at any step (explicit Euler is not at 2 kHz with stiff contacts).
Eigen::VectorXd SimulateLugre(
    const LugreParameters& p,
    const Eigen::Ref<const Eigen::VectorXd>& time_s,
    const Eigen::Ref<const Eigen::VectorXd>& velocity_mm_s,
    double z0_mm = 0.0);

struct LugreOptions {
  // F_c and F_s; 0 = estimated from the cycle (median |Q| over the central
  // half of gross slip; 99th percentile of |Q|).
  double coulomb_n = 0.0;
  double static_n = 0.0;
  int max_iterations = 200;
  // Where Ceres starts: a bristle stiffness of the order of the stick slope,
  // little damping, no viscous term, v_s 5 mm/s (F_c and F_s are ignored).
  LugreParameters initial{150.0, 1e-3, 0.0, 5.0};
  bool IsValid(std::string* why) const;
};

struct LugreFit {
  LugreParameters parameters;
  double cost = 0.0;  // paper Eq. 11: |Q_m - Q_LuGre| / |Q_m| over the cycle
  int samples = 0;
  int iterations = 0;
  bool converged = false;
  // Both dampings >= 0; a converged fit with a negative one says
  // "fitted (physically implausible: sigma1 < 0)" in its message.
  bool physically_plausible = true;
  std::string message = "not run";
  Eigen::VectorXd time_s, x_mm, q_measured_n,
      q_lugre_n;  // the fitted cycle (Fig. 17)
  std::string BriefReport() const;
};

// Fits sigma0, sigma1, sigma2 and v_s (Ceres, Levenberg-Marquardt with
// sigma0, v_s > 0) on one cycle; the cycle before warms the bristle state.
LugreFit FitLugre(const force::ForceRecord& record,
                  const force::CycleSet& cycles,
                  int cycle,
                  const LugreOptions& options = {});

}  // namespace wearscar::fusion
