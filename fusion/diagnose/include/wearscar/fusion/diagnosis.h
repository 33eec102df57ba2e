#pragma once
// What a diagnosis is asked (DiagnoseOptions) and what it holds (the
// residual maps, the candidates tried, the effects named), with the rule
// that picks a step's candidate: what the diagnosis's own files, the
// products and the report read, apart from the functions that make a
// diagnosis (diagnose.h).

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "wearscar/force/periodic.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/premise.h"

namespace wearscar::fusion {

struct DiagnoseOptions {
  int running_in_cycles = 50;  // diagnosis cycles come after these
  int max_cycles = 40;         // spread evenly over the rest
  int decimation = 4;          // every n-th gross-slip sample
  int folds = 5;               // block cross-validation over whole cycles
  // A candidate is named when all three agree: the held-out J drops by this
  // fraction, it drops on this fraction of the held-out cycles, and the
  // per-cycle BIC falls by more than bic_margin.
  double min_relative_gain = 0.10;
  double min_improved_fraction = 0.75;
  double bic_margin = 6.0;
  // A candidate with fewer parameters that achieves this share of the best
  // candidate's held-out improvement is kept instead (parsimony).
  double parsimony = 0.9;
  // A second or later effect must also lower the held-out J by this share
  // of min_relative_gain of the initial J (not only of the current one).
  double later_share = 0.25;
  int max_effects = 4;
  // The residual's signature decides: when one direction parity dominates
  // the residual (its rms this many times the other's), a candidate that
  // removes less of that parity than of the other is a look-alike; it is
  // not named unless its held-out gain is signature_margin times that of
  // the best candidate that matches.
  double signature_dominance = 2.0;
  double signature_margin = 2.0;
  // Look for periodic lines the drive does not make (mains pick-up, a
  // resonance) and try notching the strongest as "periodic interference".
  bool periodic_lines = true;
  // "None of these": the residual left repeats above its noise by this
  // z-score (ResidualMap::repeatable_z) and no candidate was accepted. The
  // 22 clean simulated tests (the 11 cases at noise 1 and 2, 200 cycles)
  // reach up to 19: the wear-scar model's own small misfit repeats too.
  double unexplained_z = 25.0;
  // ... and is at least this share of the measured Q's rms: the model's
  // own misfit seen above a depth channel's small noise (a clean
  // dead-weight test: 0.012 N, 0.21% of Q, z 80) is no effect worth a
  // word; adhesion at the dwells (dwell_adhesion 0.6) leaves 0.81%.
  double unexplained_share = 0.004;
  // With the scan's slope (a rig whose P carries no profile): the depth
  // scale fitted to the diagnosed cycles, k = k_scan / (1 + g), is doubted
  // in words beyond this |g| (a track deepening by a third over the last
  // cycles is no wear a test shows; 0.033 on the simulator's S-RT-R).
  double scan_scale_warning = 0.3;
  // Per-cycle binned P and Q for the base slope: bins of this width, or of
  // the largest x step between samples when that is wider (low rates).
  double profile_step_mm = 0.01;
  double profile_span_mm = 0.3;    // cubic Savitzky-Golay span on the bins
  bool average_directions = true;  // one slope from both directions' P
  // Cycles averaged for the base slope (with the ensemble estimate): more
  // than the fit's, because a noisy slope fitted against Q shrinks (an
  // apparent elastic compliance) and the diagnosis compares such shrinkage.
  // At 21, P's noise through the slope was the held-out J's floor at twice
  // the paper's noise (a viscous film: 13-33% lower); 81 blurs a growing
  // track into a shape (friction along the track named for the film).
  int slope_cycles = 41;
  int position_bins = 40;
  int reversal_bins = 20;
  int cycle_blocks = 8;
  std::vector<std::string> candidates;  // names; empty = the whole library
  // Keys of effects the test's own evidence rules out (DiagnoseTest: of
  // the elastic compliance and the spring's stiffness, one formula, the
  // one the track's history does not support), and why, in words.
  std::vector<std::string> ruled_out;
  std::string ruled_out_why;
  // Friction along the track: knots over the stroke, and the weights of
  // its roughness penalty the held-out cycles choose from.
  int along_track_knots = 24;
  std::vector<double> shape_penalties = {0.001, 0.01, 0.1};
  // Once that smooth shape is named, a finer one that keeps edges is tried
  // in its place: a band's sharp boundary, which the smooth shape rounds
  // off over a knot spacing (and a lag of the Q channel then mimics). This
  // many knots (0: none), half of them gathered where the smooth shape
  // changes fastest, their total variation weighted by one of these; kept
  // when its held-out J is lower.
  int edge_knots = 64;
  std::vector<double> edge_penalties = {1e-3};
  // mu of one cycle under a model: grid, then Brent, over [mu_min, mu_max]
  // (finer than the per-cycle fit's: the diagnosis compares small gains).
  FitMuOptions mu_fit{0.0, 1.0, 41, 1e-6, 60};
  int solver_iterations = 50;  // Ceres, joint fit of effects and mu
  // Residual where the model is undefined (1 - s mu k <= 0), in N.
  double undefined_model_residual_n = 1e6;
  int min_samples_per_cycle = 11;  // cycles with fewer are left out
  int slope_polynomial_order = 3;  // Savitzky-Golay order of the base slope
  bool IsValid(std::string* why) const;
};

// Where the residual r = Q_measured - Q_model sits (rows: forward, reverse).
struct ResidualMap {
  Eigen::VectorXd x_mm;        // bin centres along the stroke
  Eigen::MatrixXd mean_abs_n;  // 2 x bins
  Eigen::MatrixXd mean_n;      // 2 x bins, signed
  Eigen::VectorXd
      from_reversal_mm;  // bin centres of the distance from the last reversal
  Eigen::MatrixXd reversal_mean_abs_n;  // 2 x bins
  std::vector<int> block_first_cycle;
  Eigen::VectorXd block_mean_abs_n;
  double mean_abs_n_all = 0.0;
  // The cycle-mean signed residual split by the direction of sliding at
  // the same x: odd = (forward - reverse) / 2 (friction along the track is
  // odd: it opposes the motion both ways), even = (forward + reverse) / 2
  // (a scale of k adds the same sign both ways; Effect::DirectionParity);
  // NaN where a direction has no samples. Their rms over the bins, N.
  Eigen::VectorXd odd_n, even_n;
  double odd_rms_n = 0.0, even_rms_n = 0.0;
  // How far the cycle-mean map stands above its own noise: the bins'
  // chi-square against their standard errors over cycles, as a z-score
  // (0 for pure noise), and the repeatable part's rms (N).
  double repeatable_z = 0.0, repeatable_rms_n = 0.0;
  std::string where;  // the same in words
};

// Friction along the track as the diagnosis recovered it (when named):
// mu_eff / mu - 1 at the knots, and how it follows the groove's depth and
// the depth's short-wave texture (below 1 mm), so that one sees whether
// friction follows wear, the wood's bands, or neither.
struct AlongTrackFrictionShape {
  Eigen::VectorXd x_mm, a;
  // The groove's depth along the same range (scan, else the force side),
  // for the figure beside a(x).
  Eigen::VectorXd depth_x_mm, depth_mm;
  double penalty = 0;                // the roughness weight chosen
  double correlation_depth = NAN;    // Pearson r with the groove's depth
  double correlation_texture = NAN;  // with the depth's short-wave part
  // The friction map's steady pattern in its bins (forward, reverse; NaN
  // where empty), relative to the steady cycles' mean mu-hat: what was
  // measured along the track, beside a(x); and Pearson r of a(x), averaged
  // over each bin, with the two directions' mean.
  Eigen::VectorXd map_x_mm, map_forward, map_reverse;
  double correlation_map = NAN;
  bool empty() const { return a.size() == 0; }
};

struct CandidateResult {
  std::string effect;
  std::vector<std::string> parameter_names;
  std::vector<double> parameters;     // fitted on all diagnosis cycles
  std::vector<double> uncertainties;  // jackknife over the folds
  double heldout_before = 0.0;        // mean held-out J per cycle
  double heldout_after = 0.0;
  double relative_gain = 0.0;
  double improved_fraction = 0.0;
  double delta_bic = 0.0;
  bool plausible = true;  // the fitted sign is the effect's physics
  // What the channels show against the fit (Effect::Contradiction), in
  // words; empty when nothing does.
  std::string contradicted;
  // Its premises as checked (Effect::CheckPremises): a failed one keeps it
  // from being named.
  std::vector<Premise> premises;
  bool accepted = false;
  // What it removes of the residual's cycle-mean map along the stroke, by
  // direction parity (ResidualMap: rms before less rms after, N), and
  // whether that is the parity dominating the residual (false: a
  // look-alike; DiagnoseOptions::signature_dominance).
  double odd_removed_n = 0.0, even_removed_n = 0.0;
  bool matches_signature = true;
};

// The residual's cycle-mean map split by the direction of sliding (its
// odd and even parts' rms, N; ResidualMap).
struct ResidualParity {
  double odd_rms_n = 0.0, even_rms_n = 0.0;
};

// The selection rule of one step. Of the candidates `tried`, sorted by
// held-out J, the one the step keeps (its index) and why, when not the
// best (words in *note); `before` is the held-out J before the step,
// `residual` the residual's parts before it. Of candidates that explain
// nearly as much (o.parsimony of the best one's held-out improvement), the
// one with the fewest parameters: in a sine drive the speed is a function
// of x, and a free shape along the track can mimic a speed dependence.
// Then the residual's signature (sets each one's matches_signature): a
// look-alike gives way to the best accepted candidate that removes the
// dominating parity, unless its held-out gain is o.signature_margin times
// that one's; with none, it is marked not accepted.
size_t PickCandidate(std::vector<CandidateResult>* tried,
                     double before,
                     const ResidualParity& residual,
                     const DiagnoseOptions& o,
                     std::string* note);

struct DiagnosisStep {
  CandidateResult chosen;              // the candidate the step kept
  std::vector<CandidateResult> tried;  // every candidate, the kept first
  std::string note;  // why a candidate other than the best was kept
};

struct Diagnosis {
  std::vector<int> cycles;   // the diagnosis cycles
  std::string slope_source;  // where k came from, in words
  std::vector<DiagnosisStep>
      steps;  // the last one is the rejection that stopped it
  std::vector<std::string> named;  // accepted effects, in order
  // Final model: named effects with their parameters.
  std::vector<CandidateResult> model;
  double heldout_initial = 0.0, heldout_final = 0.0;
  ResidualMap before, after;
  AlongTrackFrictionShape along_track;  // when friction along it is named
  // Periodic lines found in Q and P, and the one notched out when
  // "periodic interference" was named (0 otherwise).
  std::vector<force::PeriodicLine> lines;
  double notched_hz = 0.0;
  // The residual after the named effects still repeats from cycle to cycle
  // above its noise (ResidualMap::repeatable_z), and nothing in the
  // library explains it: "none of these".
  bool unexplained = false;
  std::string message = "not run";
  // Joint fits (Ceres) run over the folds and candidates, and those that
  // ended without converging (iteration limit, failure): a diagnosis
  // resting on them says so.
  int solves = 0, solves_not_converged = 0;
  std::string BriefReport() const;
};

}  // namespace wearscar::fusion
