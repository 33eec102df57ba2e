#include "wearscar/fusion/lugre.h"

#include <gtest/gtest.h>

#include <cmath>

#include "wearscar/force/cycles.h"

namespace wearscar::fusion {
namespace {

// A record whose Q is exactly LuGre with known parameters on the paper's
// drive (1 Hz, +-2.85 mm, 2 kHz).
force::ForceRecord LugreRecord(const LugreParameters& p, double periods) {
  const double rate = 2000;
  const Eigen::Index n = static_cast<Eigen::Index>(periods * rate);
  force::ForceRecord r;
  r.time_s = Eigen::VectorXd::LinSpaced(n, 0, (n - 1) / rate);
  r.x_mm = (2 * M_PI * r.time_s.array()).sin().matrix() * 2.85;
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index a = std::max<Eigen::Index>(0, i - 2),
                       b = std::min(n - 1, i + 2);
    v[i] = (r.x_mm[b] - r.x_mm[a]) / (r.time_s[b] - r.time_s[a]);
  }
  r.tangential_n = SimulateLugre(p, r.time_s, v);
  r.normal_n = Eigen::VectorXd::Constant(n, 30.0);
  return r;
}

TEST(Lugre, ExactBristleUpdateIsStableWhereEulerIsNot) {
  // sigma0 = 1e4 N/mm at 2 kHz: a h = sigma0 |v| h / s >> 2 at speed.
  LugreParameters p{1e4, 0.0, 0.0, 5.0, 4.0, 6.0};
  const force::ForceRecord r = LugreRecord(p, 2.0);
  EXPECT_LT(r.tangential_n.cwiseAbs().maxCoeff(), 6.0 + 1e-9);
  // Explicit Euler on the same data diverges or oscillates beyond F_s.
  double z = 0, worst = 0;
  for (Eigen::Index i = 1; i < r.size(); ++i) {
    const double h = 1.0 / 2000, vel = (r.x_mm[i] - r.x_mm[i - 1]) / h;
    const double s = 4.0 + 2.0 * std::exp(-std::pow(vel / 5.0, 2));
    z += h * (vel - 1e4 * std::abs(vel) * z / s);
    worst = std::max(worst, std::abs(1e4 * z));
  }
  EXPECT_GT(worst, 6.0 * 10);
}

// LuGre fitted on cycle 2 of a record made with `truth` (F_c, F_s given).
LugreFit FitKnown(const LugreParameters& truth, force::CycleSet* cycles) {
  const force::ForceRecord r = LugreRecord(truth, 4.5);
  *cycles = force::SegmentCycles(r.x_mm);
  force::FindGrossSlip(r, cycles);
  LugreOptions o;
  o.coulomb_n = truth.coulomb_n;
  o.static_n = truth.static_n;
  return FitLugre(r, *cycles, 2, o);
}

TEST(Lugre, RecoversKnownParametersIncludingNegativeSigma2) {
  const LugreParameters truth{120.0, 0.05, -0.01, 6.0, 4.0, 6.5};
  force::CycleSet cycles;
  const LugreFit fit = FitKnown(truth, &cycles);
  EXPECT_NEAR(fit.parameters.sigma0_n_per_mm, 120.0, 6.0) << fit.BriefReport();
  EXPECT_NEAR(fit.parameters.sigma1_n_s_per_mm, 0.05, 0.01)
      << fit.BriefReport();
  EXPECT_NEAR(fit.parameters.sigma2_n_s_per_mm, -0.01, 0.001)
      << fit.BriefReport();
  EXPECT_NEAR(fit.parameters.stribeck_speed_mm_s, 6.0, 0.3)
      << fit.BriefReport();
  EXPECT_LT(fit.cost, 1e-3);
  EXPECT_EQ(fit.samples,
            cycles.cycles[2].reverse.end - cycles.cycles[2].forward.begin);
  // The negative viscous damping fits, and is said to be unphysical.
  EXPECT_FALSE(fit.physically_plausible);
  EXPECT_EQ(fit.message,
            "fitted (physically implausible: sigma2 < 0: a negative damping "
            "fits the loop's shape but is no material's; LuGre is a "
            "comparison and does not change mu-hat)");
}

TEST(Lugre, PositiveDampingsAreReportedAsConverged) {
  force::CycleSet cycles;
  const LugreFit fit = FitKnown({120.0, 0.05, 0.01, 6.0, 4.0, 6.5}, &cycles);
  EXPECT_NEAR(fit.parameters.sigma2_n_s_per_mm, 0.01, 0.001)
      << fit.BriefReport();
  EXPECT_TRUE(fit.physically_plausible);
  EXPECT_EQ(fit.message, "converged");
}

TEST(Lugre, BadOptionsAndCycleAreErrors) {
  const force::ForceRecord r = LugreRecord({100, 0, 0, 5, 4, 6}, 3.5);
  force::CycleSet cycles = force::SegmentCycles(r.x_mm);
  EXPECT_THROW(FitLugre(r, cycles, 7), FusionError);
  LugreOptions o;
  o.coulomb_n = 5;
  o.static_n = 4;
  EXPECT_THROW(FitLugre(r, cycles, 0, o), FusionError);
}

}  // namespace
}  // namespace wearscar::fusion
