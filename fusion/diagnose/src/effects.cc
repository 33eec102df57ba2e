#include "wearscar/fusion/effects.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion {
namespace {

// Ploughing: the sphere pushes material ahead of it; the resistance grows
// with the groove depth:  extra = s c_p depth(x).
class Ploughing : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kOdd; }
  std::string Name() const override { return "ploughing"; }
  std::string Key() const override { return "ploughing"; }
  std::string Formula() const override { return "Q += s c_p depth(x)"; }
  std::vector<std::string> ParameterNames() const override {
    return {"c_p_N_per_mm"};
  }
  std::vector<double> Initial() const override { return {1.0}; }
  std::vector<double> Lower() const override { return {-100.0}; }
  // A resistance: material pushed ahead never pulls the sphere on.
  bool Plausible(const double* p) const override { return p[0] >= 0; }
  const char* PhysicsPremise() const override {
    return "material pushed ahead resists the sliding (c_p >= 0)";
  }
  std::vector<double> Upper() const override { return {100.0}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->extra_n += p[0] * c->depth_mm;
  }
};

// Velocity dependence, Stribeck type: friction rises at low speed,
//   mu_eff = mu (1 + a exp(-(v / v_s)^2)).
class Stribeck : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kOdd; }
  std::string Name() const override { return "velocity dependence (Stribeck)"; }
  std::string Key() const override { return "stribeck"; }
  std::string Formula() const override {
    return "mu_eff = mu (1 + a exp(-(v/v_s)^2))";
  }
  std::vector<std::string> ParameterNames() const override {
    return {"a", "v_s_mm_per_s"};
  }
  std::vector<double> Initial() const override { return {0.1, 3.0}; }
  std::vector<double> Lower() const override { return {-0.9, 0.05}; }
  std::vector<double> Upper() const override { return {5.0, 30.0}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->mu_factor *= StribeckFactor(c->speed_mm_s, p[0], p[1]);
  }
};

// Viscous resistance proportional to the sliding speed: extra = s c_v |v|.
class Viscous : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kOdd; }
  std::string Name() const override { return "viscous term"; }
  std::string Key() const override { return "viscous"; }
  std::string Formula() const override { return "Q += s c_v |v|"; }
  std::vector<std::string> ParameterNames() const override {
    return {"c_v_N_s_per_mm"};
  }
  std::vector<double> Initial() const override { return {0.01}; }
  std::vector<double> Lower() const override { return {-1.0}; }
  // A film sheared resists (c_v >= 0): a negative one would be friction
  // falling with speed, which is the Stribeck candidate's to claim.
  bool Plausible(const double* p) const override { return p[0] >= 0; }
  const char* PhysicsPremise() const override {
    return "a sheared film resists the sliding (c_v >= 0)";
  }
  std::vector<double> Upper() const override { return {1.0}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->extra_n += p[0] * c->speed_mm_s;
  }
};

// Direction asymmetry: mu_forward = mu (1 + a), mu_reverse = mu (1 - a).
// mu (1 + s a) adds a mu P through the wear-scar law's denominator
// 1 - s mu k: mixed (measured odd on the simulator's ratchet law).
class Asymmetry : public Effect {
 public:
  std::string Name() const override { return "direction asymmetry"; }
  std::string Key() const override { return "asymmetry"; }
  std::string Formula() const override { return "mu_eff = mu (1 + s a)"; }
  std::vector<std::string> ParameterNames() const override { return {"a"}; }
  std::vector<double> Initial() const override { return {0.01}; }
  std::vector<double> Lower() const override { return {-0.9}; }
  std::vector<double> Upper() const override { return {0.9}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->mu_factor *= 1.0 + c->s * p[0];
  }
};

// Time lag of the Q channel: the measured Q at t is the force at t - tau,
// so the model at t is compared with the measurement at t + tau.
// Its residual -tau d/dt[P (k + s mu)] has an even part, mu P' |v|, and
// an odd one, (P k)' |v|, which dominates on a wavy track: mixed.
class TimeLag : public Effect {
 public:
  std::string Name() const override { return "time lag of the Q channel"; }
  std::string Key() const override { return "q_lag"; }
  std::string Formula() const override { return "Q_measured(t) = Q(t - tau)"; }
  std::vector<std::string> ParameterNames() const override { return {"tau_s"}; }
  std::vector<double> Initial() const override { return {0.0005}; }
  std::vector<double> Lower() const override { return {-0.02}; }
  std::vector<double> Upper() const override { return {0.02}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->time_shift_s += p[0];
  }
  // Q must turn late at the reversals by the lag: a fit whose tau the
  // turns show less than half of (by three standard errors) took another
  // effect's misfit (sharp friction bands shift the loops as a lag does,
  // but not the turns).
  const char* DirectPremise() const override {
    return "Q turns late at the reversals by at least half the fitted lag "
           "(friction varying along the track shifts the loops, not the "
           "turns)";
  }
  bool DirectlyMeasured(const DirectEvidence& e) const override {
    return std::isfinite(e.q_delay_s) && std::isfinite(e.q_delay_se_s);
  }
  std::string DirectEvidenceText(const DirectEvidence& e) const override {
    return fmt::format(
        "Q turns at the reversals {:.2f} +- {:.2f} ms behind x (the median "
        "over {} turns)",
        1e3 * e.q_delay_s,
        1e3 * e.q_delay_se_s,
        e.reversals);
  }
  std::string Contradiction(const double* p,
                            const DirectEvidence& e) const override {
    const double tau = p[0], seen = e.q_delay_s, se = e.q_delay_se_s;
    if (!std::isfinite(seen) || !std::isfinite(se) || tau == 0) return {};
    const double towards = tau > 0 ? seen + 3 * se : -(seen - 3 * se);
    if (towards >= 0.5 * std::abs(tau)) return {};
    return fmt::format(
        "Q turns at the reversals {:.2f} +- {:.2f} ms behind x (the median "
        "over {} turns), not the {:.2f} ms fitted",
        1e3 * seen,
        1e3 * se,
        e.reversals,
        1e3 * tau);
  }
};

// Crosstalk of Q into the P channel: P_measured = P + c Q, which also
// corrupts the slope: k = (1/S) dP/dx - c (1/S) dQ/dx.
class Crosstalk : public Effect {
 public:
  std::string Name() const override { return "crosstalk of Q into P"; }
  std::string Key() const override { return "crosstalk"; }
  std::string Formula() const override {
    return "P = P_measured - c Q_measured, k = k_measured - c (1/S) dQ/dx";
  }
  std::vector<std::string> ParameterNames() const override { return {"c"}; }
  std::vector<double> Initial() const override { return {0.005}; }
  std::vector<double> Lower() const override { return {-0.5}; }
  std::vector<double> Upper() const override { return {0.5}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->p_n -= p[0] * c->q_measured_n;
    c->k -= p[0] * c->q_slope;
  }
  // P itself must follow the direction of sliding by c times Q's change:
  // a fit whose c the P channel shows less than half of (by three
  // standard errors) took another effect's misfit.
  const char* DirectPremise() const override {
    return "P itself follows the direction of sliding by at least half the "
           "fitted share of Q's change (a spring presses alike both ways)";
  }
  bool DirectlyMeasured(const DirectEvidence& e) const override {
    return std::isfinite(e.crosstalk_from_p) &&
           std::isfinite(e.crosstalk_from_p_se);
  }
  std::string DirectEvidenceText(const DirectEvidence& e) const override {
    return fmt::format(
        "P follows the direction of sliding by c = {:.2g} +- {:.2g} of Q's "
        "change",
        e.crosstalk_from_p,
        e.crosstalk_from_p_se);
  }
  std::string Contradiction(const double* p,
                            const DirectEvidence& e) const override {
    const double c = p[0], seen = e.crosstalk_from_p;
    const double se = e.crosstalk_from_p_se;
    if (!std::isfinite(seen) || !std::isfinite(se) || c == 0) return {};
    const double towards_c = c > 0 ? seen + 3 * se : -(seen - 3 * se);
    if (towards_c >= 0.5 * std::abs(c)) return {};
    return fmt::format(
        "P itself follows the direction of sliding by c = {:.2g} +- {:.2g} "
        "of Q's change, not the {:.2g} fitted",
        seen,
        se,
        c);
  }
};

// End-of-stroke hook: extra resistance approaching the end of the stroke,
//   extra = s H exp(-(distance to the end ahead) / lambda).
class Hook : public Effect {
 public:
  std::string Name() const override { return "end-of-stroke hook"; }
  std::string Key() const override { return "hook"; }
  std::string Formula() const override {
    return "Q += s H exp(-d_end / lambda)";
  }
  std::vector<std::string> ParameterNames() const override {
    return {"H_N", "lambda_mm"};
  }
  std::vector<double> Initial() const override { return {0.2, 0.3}; }
  std::vector<double> Lower() const override { return {-20.0, 0.02}; }
  // A resistance (H >= 0): a negative hook would be a pull towards the
  // stroke's end, no pile-up's, and with a speed dependence it mimics a
  // peak after the reversal (adhesion grown at the dwell).
  bool Plausible(const double* p) const override { return p[0] >= 0; }
  const char* PhysicsPremise() const override {
    return "material piled up at the stroke's end resists the sliding "
           "(H >= 0)";
  }
  std::vector<double> Upper() const override { return {20.0, 3.0}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->extra_n += p[0] * std::exp(-c->to_end_mm / p[1]);
  }
};

// Elastic compliance of the track: the spring follows the worn geometry
// plus an elastic part in phase with it, f = (1 + beta) f_geometric, so the
// contact tilts by k = k_measured / (1 + beta).
class ElasticCompliance : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kEven; }
  std::string Name() const override {
    return "elastic compliance of the track";
  }
  std::string Key() const override { return "elastic"; }
  bool ScalesTheSlope() const override { return true; }
  std::string Formula() const override { return "k = k_measured / (1 + beta)"; }
  std::vector<std::string> ParameterNames() const override { return {"beta"}; }
  std::vector<double> Initial() const override { return {0.1}; }
  std::vector<double> Lower() const override { return {-0.5}; }
  std::vector<double> Upper() const override { return {20.0}; }
  void Apply(const double* p, EffectContext* c) const override {
    c->k /= 1.0 + p[0];
  }
};

// The loading spring's stiffness other than the one k was divided by: P/S
// is the worn geometry times S_rig / S_used, so the contact tilts by
// k = k_measured / ratio. The same formula as the elastic compliance; the
// two are told apart by the track's history (SpringCheck: an elastic part
// is there from the first cycle, a wrong stiffness scales a track that
// grew from nothing), and the diagnosis tries the one it supports.
class SpringStiffness : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kEven; }
  std::string Name() const override { return "spring stiffness"; }
  std::string Key() const override { return "spring"; }
  bool ScalesTheSlope() const override { return true; }
  std::string Formula() const override {
    return "k = k_measured / ratio, ratio = S_rig / S_used";
  }
  std::vector<std::string> ParameterNames() const override { return {"ratio"}; }
  std::vector<double> Initial() const override { return {1.1}; }
  std::vector<double> Lower() const override { return {0.05}; }
  std::vector<double> Upper() const override { return {20.0}; }
  void Apply(const double* p, EffectContext* c) const override { c->k /= p[0]; }
};

// Friction that varies along the track in any smooth pattern (the wood's
// hardness bands, a trend, a soft spot): mu_eff = mu (1 + a(x)), a(x)
// linear between equally spaced knots over the stroke.
class AlongTrack : public Effect {
 public:
  Parity DirectionParity() const override { return Parity::kOdd; }
  AlongTrack(std::vector<double> u, bool edges)
      : u_(std::move(u)), knots_(static_cast<int>(u_.size())), edges_(edges) {}
  std::string Name() const override {
    return "friction varying along the track";
  }
  std::string Key() const override { return "mu_along_track"; }
  std::string Formula() const override {
    return fmt::format(
        "mu_eff = mu (1 + a(x)), a(x) through {} knots, mean 0, {}",
        knots_,
        edges_ ? "edges kept (total variation)" : "smooth");
  }
  std::vector<std::string> ParameterNames() const override {
    std::vector<std::string> names;
    for (int i = 0; i < knots_; ++i) names.push_back(fmt::format("a_{}", i));
    return names;
  }
  std::vector<double> Initial() const override {
    return std::vector<double>(knots_, 0.0);
  }
  std::vector<double> Lower() const override {
    return std::vector<double>(knots_, -0.5);
  }
  std::vector<double> Upper() const override {
    return std::vector<double>(knots_, 0.5);
  }
  void Apply(const double* p, EffectContext* c) const override {
    int i;
    double w;
    Locate(*c, &i, &w);
    c->mu_factor *= 1.0 + (1 - w) * p[i] + w * p[i + 1];
  }
  std::vector<double> Knots() const override { return u_; }
  bool MuFactorGradient(const double* p,
                        const EffectContext& c,
                        double* grad) const override {
    int i;
    double w;
    Locate(c, &i, &w);
    const double m = 1.0 + (1 - w) * p[i] + w * p[i + 1];
    std::fill(grad, grad + knots_, 0.0);
    grad[i] = (1 - w) / m;
    grad[i + 1] = w / m;
    return true;
  }
  // The knots' mean (held at 0: the level is each cycle's mu) and their
  // roughness: the second differences' squares, or (edges kept) the first
  // differences' absolute values, the total variation, which costs a step
  // no more than a ramp of the same height. Its residual is
  // sign(d) sqrt(sqrt(d^2 + eps^2) - eps): squared, |d| beyond eps and
  // d^2 / (2 eps) within it, smooth for the solver.
  int PenaltyCount() const override { return knots_ - 1; }
  void Penalty(const double* p, double weight, double* r) const override {
    double mean = 0;
    for (int i = 0; i < knots_; ++i) mean += p[i] / knots_;
    r[0] = kMeanWeight * mean;
    const double w = std::sqrt(weight);
    for (int i = 1; i + 1 < knots_; ++i) {
      if (!edges_) {
        r[i] = w * (p[i - 1] - 2 * p[i] + p[i + 1]);
        continue;
      }
      const double d = p[i + 1] - p[i];
      r[i] =
          w *
          std::copysign(
              std::sqrt(std::sqrt(d * d + kEdgeEps * kEdgeEps) - kEdgeEps), d);
    }
  }

 private:
  // The knot interval of x and the weight of its upper knot.
  void Locate(const EffectContext& c, int* i, double* w) const {
    const double u = std::clamp(c.stroke_fraction, 0.0, 1.0);
    const auto above = std::upper_bound(u_.begin(), u_.end(), u);
    *i = std::clamp(static_cast<int>(above - u_.begin()) - 1, 0, knots_ - 2);
    *w = std::clamp((u - u_[*i]) / (u_[*i + 1] - u_[*i]), 0.0, 1.0);
  }
  static constexpr double kMeanWeight = 10.0;
  static constexpr double kEdgeEps = 1e-3;  // of a, below any band's step
  std::vector<double> u_;  // the knots' fractions of the sliding range
  int knots_;
  bool edges_;
};

}  // namespace

const char* ParityName(Parity p) {
  return p == Parity::kOdd ? "odd" : p == Parity::kEven ? "even" : "mixed";
}

const std::vector<std::unique_ptr<Effect>>& EffectLibrary() {
  static const std::vector<std::unique_ptr<Effect>> library = [] {
    std::vector<std::unique_ptr<Effect>> v;
    v.push_back(std::make_unique<Ploughing>());
    v.push_back(std::make_unique<Stribeck>());
    v.push_back(std::make_unique<Viscous>());
    v.push_back(std::make_unique<Asymmetry>());
    v.push_back(std::make_unique<TimeLag>());
    v.push_back(std::make_unique<Crosstalk>());
    v.push_back(std::make_unique<Hook>());
    v.push_back(std::make_unique<ElasticCompliance>());
    v.push_back(std::make_unique<SpringStiffness>());
    v.push_back(AlongTrackFriction(12));
    return v;
  }();
  return library;
}

std::unique_ptr<Effect> AlongTrackFriction(int knots, bool edges) {
  const int n = std::max(3, knots);
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i) u[i] = static_cast<double>(i) / (n - 1);
  return std::make_unique<AlongTrack>(std::move(u), edges);
}

std::unique_ptr<Effect> AlongTrackFrictionAt(std::vector<double> knots,
                                             bool edges) {
  if (knots.size() < 3 || knots.front() != 0.0 || knots.back() != 1.0 ||
      !std::is_sorted(knots.begin(), knots.end()) ||
      std::adjacent_find(knots.begin(), knots.end()) != knots.end()) {
    throw FusionError(
        "a shape's knots must increase strictly from 0 to 1, at least 3");
  }
  return std::make_unique<AlongTrack>(std::move(knots), edges);
}

std::vector<Premise> Effect::CheckPremises(const double* p,
                                           const DirectEvidence& e) const {
  using State = Premise::State;
  std::vector<Premise> premises;
  if (const char* physics = PhysicsPremise()) {
    const bool held = Plausible(p);
    premises.push_back(
        {Name(),
         physics,
         held ? State::kHeld : State::kFailed,
         fmt::format("fitted {} = {:.3g}", ParameterNames()[0], p[0]),
         held ? "" : "not named: the fit took another effect's misfit"});
  }
  if (const char* direct = DirectPremise()) {
    if (!DirectlyMeasured(e)) {
      premises.push_back({Name(),
                          direct,
                          State::kNotChecked,
                          "not measured by the channels",
                          "named on the held-out gain alone"});
    } else {
      const std::string against = Contradiction(p, e);
      premises.push_back({Name(),
                          direct,
                          against.empty() ? State::kHeld : State::kFailed,
                          against.empty() ? DirectEvidenceText(e) : against,
                          against.empty()
                              ? ""
                              : "not named: a look-alike of what Q's "
                                "misfit holds"});
    }
  }
  return premises;
}

const Effect* FindEffect(const std::string& name) {
  for (const auto& e : EffectLibrary()) {
    if (e->Name() == name || e->Key() == name) return e.get();
  }
  return nullptr;
}

}  // namespace wearscar::fusion
