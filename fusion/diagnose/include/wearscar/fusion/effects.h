#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "wearscar/fusion/premise.h"

namespace wearscar::fusion {

// What a candidate effect sees of one gross-slip sample, and what it may
// change before the wear-scar law Q = P (k + s mu_eff) / (1 - s mu_eff k) +
// extra is applied. Effects only touch the fields their formula names.
struct EffectContext {
  // Inputs (read only for effects).
  double x_mm = 0;        // plate position
  int s = 1;              // direction of motion
  double speed_mm_s = 0;  // |dx/dt|
  double depth_mm = 0;    // groove depth at x (scan, or force side)
  // x along the diagnosis's stroke: 0 at its lowest x, 1 at its highest.
  double stroke_fraction = 0;
  double to_end_mm = 0;     // distance to the stroke end ahead
  double q_slope = 0;       // (1/S) dQ/dx of the measured Q (crosstalk)
  double q_measured_n = 0;  // measured Q at this sample
  double time_s = 0;
  // Effects may modify these.
  double p_n = 0;           // normal force used by the law
  double k = 0;             // slope of the sliding path used by the law
  double mu_factor = 1;     // mu_eff = mu * mu_factor
  double extra_n = 0;       // added to Q in the direction of motion's sign
  double time_shift_s = 0;  // compare with the measured Q at time + shift
};

// How an effect's contribution to Q at one x differs between the two
// directions of sliding: odd (the same size, opposite sign: it opposes
// the motion both ways, as friction along the track does), even (the same
// sign both ways: a scale of the track's slope), or mixed (a lag of Q,
// whose slope part is odd and friction part even). The
// residual's split (ResidualMap::odd_rms_n, even_rms_n) shows which the
// missing effect is.
enum class Parity { kOdd, kEven, kMixed };
const char* ParityName(Parity p);  // "odd", "even", "mixed"

// What the channels show of an effect directly, apart from the joint fit
// of Q (NaN where not measured): the crosstalk of Q into P as P's own
// difference between the directions at the same x against Q's (a spring
// presses the same both ways at the same height, so only crosstalk makes
// P follow the direction of sliding), with its standard error; measured
// only where k comes from P (a servo holding the load would hold the
// measured P).
// And the delay of Q's turn at the reversals behind x's (ReversalDelay):
// in the stick that follows a reversal Q follows x through the contact's
// tangential stiffness, so a lag of the Q channel shows there as Q
// following x of that much earlier, while friction varying along the
// track changes nothing there.
struct DirectEvidence {
  double crosstalk_from_p = std::nan("");
  double crosstalk_from_p_se = std::nan("");
  double q_delay_s = std::nan("");
  double q_delay_se_s = std::nan("");
  int reversals = 0;  // the turns q_delay_s is the median of
};

// A named physical term with parameters. Adding an effect to wearscar is
// one new subclass registered in EffectLibrary(); nothing else changes.
class Effect {
 public:
  virtual ~Effect() = default;
  virtual std::string Name() const = 0;  // in words, for reports
  // One word: the effect's name in options, in the simulator's switch
  // (wearscar simulate --effect KEY=strength) and in diagnosis.json.
  virtual std::string Key() const = 0;
  virtual std::string Formula() const = 0;
  virtual std::vector<std::string> ParameterNames() const = 0;  // with units
  virtual std::vector<double> Initial() const = 0;
  virtual std::vector<double> Lower() const = 0;
  virtual std::vector<double> Upper() const = 0;
  // Modifies the context for parameters p (length ParameterNames().size()).
  virtual void Apply(const double* p, EffectContext* c) const = 0;
  // Whether the effect only scales the slope of the sliding path, k ->
  // (1 + g) k (an elastic part in phase with the track): with a slope that
  // is one fixed profile (the scan's), it is that profile's depth scale.
  virtual bool ScalesTheSlope() const { return false; }
  virtual Parity DirectionParity() const { return Parity::kMixed; }
  // The parameter reported as the effect's strength.
  virtual int StrengthIndex() const { return 0; }
  // Whether fitted parameters are the effect's physics (a resistance that
  // resists): an implausible fit is not named. The fit itself is left
  // unbounded there (a bound at zero slows it several times).
  virtual bool Plausible(const double* /*p*/) const { return true; }
  // Words when what the channels show directly contradicts the fitted
  // parameters (empty when nothing does): such a fit is a look-alike of
  // what Q's misfit holds, and is not named.
  virtual std::string Contradiction(const double* /*p*/,
                                    const DirectEvidence& /*e*/) const {
    return {};
  }
  // The premises its naming rests on beyond the held-out gain, in words:
  // that the fitted parameters are its physics (checked by Plausible), and
  // what the channels must show of it directly (checked by Contradiction
  // where DirectlyMeasured); nullptr where it has none of that kind.
  virtual const char* PhysicsPremise() const { return nullptr; }
  virtual const char* DirectPremise() const { return nullptr; }
  // Whether the channels measured what DirectPremise names, and what.
  virtual bool DirectlyMeasured(const DirectEvidence& /*e*/) const {
    return false;
  }
  virtual std::string DirectEvidenceText(const DirectEvidence& /*e*/) const {
    return {};
  }
  // Those premises, each checked on the fitted parameters p and the direct
  // evidence (a direct one not measured is "not checked"). A candidate
  // with a failed premise is not named; diagnosis.json lists them.
  std::vector<Premise> CheckPremises(const double* p,
                                     const DirectEvidence& e) const;
  // Effects with many parameters (a shape) are held smooth by penalty
  // residuals added to the fit with a weight the diagnosis chooses by the
  // held-out cycles; `weight` multiplies the roughness terms.
  virtual int PenaltyCount() const { return 0; }
  // For an effect that only multiplies mu_factor by m(p, x): fills grad
  // with dm/dp_j / m (ParameterNames().size() values) and returns true, so
  // that the fit differentiates a many-parameter shape analytically.
  // A shape's knots as fractions of the sliding range (0 to 1); empty for
  // an effect that is no shape.
  virtual std::vector<double> Knots() const { return {}; }
  virtual bool MuFactorGradient(const double* /*p*/,
                                const EffectContext& /*c*/,
                                double* /*grad*/) const {
    return false;
  }
  virtual void Penalty(const double* /*p*/,
                       double /*weight*/,
                       double* /*residuals*/) const {}
};

// The library, in a fixed order: ploughing, velocity dependence (Stribeck),
// viscous term, direction asymmetry, channel time lag, crosstalk of Q into
// P, end-of-stroke hook, elastic compliance of the track, the spring's
// stiffness, friction varying
// along the track (with DiagnoseOptions' knots: see AlongTrackFriction).
const std::vector<std::unique_ptr<Effect>>& EffectLibrary();

// Friction along the track without an assumed shape: mu_eff = mu (1 +
// a(x)), a(x) linear between `knots` equally spaced values over the stroke,
// the same in both directions; its mean is held at 0 (the cycle's mu
// carries the level) and its second differences are the penalty, or with
// `edges` its first differences' absolute values (total variation: a band's
// sharp edge is kept where the smooth shape rounds it off).
std::unique_ptr<Effect> AlongTrackFriction(int knots, bool edges = false);
// The same through knots at the given fractions of the sliding range
// (increasing, from 0 to 1): denser where the friction changes fastest.
std::unique_ptr<Effect> AlongTrackFrictionAt(std::vector<double> knots,
                                             bool edges);

// Finds an effect by its name or its key; nullptr when unknown.
const Effect* FindEffect(const std::string& name);

}  // namespace wearscar::fusion
