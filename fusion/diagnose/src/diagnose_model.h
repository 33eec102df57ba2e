#pragma once
// The diagnosis's model: the wear-scar law with effects from the library,
// one mu per cycle and the effects' parameters shared, fitted by Ceres,
// judged on cycles it was not fitted on (held-out J), and the residual's
// map along the stroke.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/diagnosis.h"
#include "wearscar/fusion/effects.h"

namespace wearscar::fusion::internal {

struct Sample {
  Eigen::Index index;  // into the record
  int s;
  double x, t, speed, p, q, k, q_slope, depth, to_end;
  double u;  // x along the stroke, 0 to 1
};

struct DiagCycle {
  int cycle;
  std::vector<Sample> samples;
  double norm_forward = 1, norm_reverse = 1;  // ||Q_m|| per direction
};

// The data every fit reads, plus the record for time-shifted Q.
struct Data {
  const force::ForceRecord* record;
  std::vector<DiagCycle> cycles;
  double dt = 0;
  double x_lo = 0, x_hi = 0;  // the stroke the residual maps bin
  const DiagnoseOptions* options = nullptr;
  DirectEvidence evidence;
  // Ceres solves and those that did not converge (fits run one at a time).
  mutable int solves = 0, not_converged = 0;
};

// The active model: effects and a parameter vector per effect.
struct Model {
  std::vector<const Effect*> effects;
  std::vector<std::vector<double>> params;
  // Per effect: the weight of its penalty residuals (per fitted cycle),
  // and for a penalised shape its effective degrees of freedom in the last
  // fit (what the information criterion counts).
  std::vector<double> penalty;
  std::vector<double> dof;
};

// What a residual was made of: the context after the effects, mu_eff and
// the model's derivative in it (for analytic derivatives in shapes).
struct ResidualTerms {
  EffectContext context;
  double mu_eff = 0, d_model_d_mu_eff = 0;
};

// Residual Q_measured - Q_model of one sample (its terms in *terms).
double Residual(const Data& d,
                const Sample& s,
                double mu,
                const std::vector<const Effect*>& effects,
                const std::vector<const double*>& params,
                ResidualTerms* terms = nullptr);

// mu of one cycle with the effects held fixed; its J in *j.
double FitCycleMu(const Data& d, const DiagCycle& c, const Model& m, double* j);

// Fits the effect parameters (shared) and one mu per cycle on `train`.
// Returns the per-cycle mu, updates m.params.
std::vector<double> FitModel(const Data& d,
                             const std::vector<int>& train,
                             Model* m);

// Held-out J per diagnosis cycle (block cross-validation over whole
// cycles); each fold's parameters in *fold_params when given.
std::vector<double> HeldOut(const Data& d,
                            const Model& m,
                            int folds,
                            std::vector<std::vector<double>>* fold_params);

// Per-cycle BIC of a model fitted on all diagnosis cycles.
double CycleBic(const Data& d, const Model& m, double parameters);
// The parameters the information criterion counts: a penalised shape's
// effective degrees of freedom, every other parameter as one.
double ParameterCount(const Model& m);
double Mean(const std::vector<double>& v);

// The residual along the stroke per direction, by distance from the last
// reversal and by block of cycles, and in words.
ResidualMap Map(const Data& d,
                const Model& m,
                const DiagnoseOptions& o,
                double x_lo,
                double x_hi);

// The cycle-mean residual along the stroke (options' position_bins) under
// `m` with each cycle's mu given, split by the direction of sliding at the
// same x (ResidualMap's odd_rms_n and even_rms_n).
struct ParitySplit {
  double odd_rms_n = 0, even_rms_n = 0;
};
ParitySplit SplitByParity(const Data& d,
                          const Model& m,
                          const std::vector<double>& mu);

// Per-direction binned average of a channel over the diagnosis cycles
// (each half's whole stroke, stick included).
Eigen::MatrixXd BinProfile(const force::ForceRecord& r,
                           const force::CycleSet& cycles,
                           const std::vector<int>& use,
                           const Eigen::VectorXd& channel,
                           double x0,
                           double step,
                           Eigen::Index bins);

}  // namespace wearscar::fusion::internal
