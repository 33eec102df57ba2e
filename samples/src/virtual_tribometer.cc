#include "wearscar/samples/virtual_tribometer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "record_from.h"
#include "riding_path.h"
#include "simulator_tools.h"
#include "wearscar/samples/effect_laws.h"
#include "wearscar/support/interpolate.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/robust_stats.h"

namespace wearscar::samples {
namespace {

using internal::BlurInPlace;
using internal::GaussianSmooth;
using internal::Grid;
using internal::Rng;
using internal::Texture;
using support::kPi;

double Quantise(double v, double resolution) {
  return resolution > 0 ? std::round(v / resolution) * resolution : v;
}

// Drive position and velocity at time t.
void DriveAt(const SimulationOptions& o, double t, double* x, double* v) {
  const double w = 2 * kPi * o.frequency_hz;
  if (o.drive == Drive::kSine) {
    *x = o.amplitude_mm * std::sin(w * t);
    *v = o.amplitude_mm * w * std::cos(w * t);
    return;
  }
  // Triangle with the same extremes and period, starting at 0 going up.
  double p = std::fmod(t * o.frequency_hz + 0.25, 1.0);  // 0 at x = -A
  const double speed = 4 * o.amplitude_mm * o.frequency_hz;
  if (p < 0.5) {
    *x = -o.amplitude_mm + speed * p / o.frequency_hz;
    *v = speed;
  } else {
    *x = o.amplitude_mm - speed * (p - 0.5) / o.frequency_hz;
    *v = -speed;
  }
}

}  // namespace

bool SimulationOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(amplitude_mm > 0)) return fail("amplitude_mm must be > 0");
  if (!(frequency_hz > 0)) return fail("frequency_hz must be > 0");
  if (!(sampling_rate_hz >= 20 * frequency_hz)) {
    return fail("sampling_rate_hz must be at least 20 x frequency_hz");
  }
  if (cycles < 2 || cycles > 100000)
    return fail("cycles must be in [2, 100000]");
  if (record_from_cycle < 0 || record_from_cycle > 100000)
    return fail("record_from_cycle must be in [0, 100000]");
  if (static_cast<double>(cycles + 1) * sampling_rate_hz / frequency_hz > 2e8) {
    return fail("more than 2e8 samples requested");
  }
  if (!(spring_n_per_mm > 0)) return fail("spring_n_per_mm must be > 0");
  if (!(contact_stiffness_n_per_mm > 0))
    return fail("contact_stiffness_n_per_mm must be > 0");
  if (!(ring_period_mm > 0)) return fail("ring_period_mm must be > 0");
  if (!(ring_width_cv >= 0 && ring_width_cv <= 0.5))
    return fail("ring_width_cv must be 0 to 0.5");
  if (!(latewood_fraction > 0 && latewood_fraction < 1)) {
    return fail("latewood_fraction must be in (0, 1)");
  }
  if (!(hardness_contrast >= 1)) return fail("hardness_contrast must be >= 1");
  if (!(final_depth_mm >= 0 && final_depth_mm < sphere_radius_mm)) {
    return fail("final_depth_mm must be in [0, sphere radius)");
  }
  if (!(mu_initial >= 0 && mu_steady >= 0)) return fail("mu must be >= 0");
  if (scan_cols < 16 || scan_rows < 16 ||
      static_cast<double>(scan_cols) * scan_rows > 1 << 26) {
    return fail("scan size must be between 16 x 16 and 2^26 pixels");
  }
  if (!(scan_pitch_mm > 0)) return fail("scan_pitch_mm must be > 0");
  if (!(roughness_mm >= 0 && roughness_length_mm >= 0 &&
        fibre_amplitude_mm >= 0 && fibre_width_mm > 0 && rim_fraction >= 0 &&
        rim_width_mm > 0 && scan_invalid_fraction >= 0 &&
        scan_invalid_fraction < 0.5 && scan_invalid_cluster_mm >= 0)) {
    return fail("scan texture, rim and invalid-pixel settings out of range");
  }
  if (effects.stribeck_rise != 0 && !(effects.stribeck_speed_mm_s > 0)) {
    return fail("stribeck_speed_mm_s must be > 0");
  }
  if (effects.hook_n != 0 && !(effects.hook_length_mm > 0)) {
    return fail("hook_length_mm must be > 0");
  }
  if (effects.q_lag_s < 0) return fail("q_lag_s must be >= 0");
  if (!(effects.ringing_hz >= 0 && effects.ringing_hz <= 1e5 &&
        effects.ringing_damping > 0 && effects.ringing_damping <= 2)) {
    return fail("ringing must be in [0, 1e5] Hz, its damping in (0, 2]");
  }
  for (double a :
       {effects.mu_variation, effects.mu_trend, effects.mu_soft_spot}) {
    if (!(std::abs(a) <= 0.3))
      return fail(
          "mu_variation, mu_trend, mu_soft_spot must be in [-0.3, 0.3]");
  }
  if (!(effects.pickup_hz > 0 && effects.wobble_hz > 0 &&
        effects.dwell_distance_mm > 0 && effects.thermal_time_s > 0)) {
    return fail(
        "pickup_hz, wobble_hz, dwell_distance, thermal_time must be > 0");
  }
  if (!(noise_scale >= 0 && noise_scale <= 1000))
    return fail("noise_scale must be in [0, 1000]");
  if (!(q_noise_n >= 0 && p_noise_n >= 0 && x_noise_mm >= 0))
    return fail("sensor noise must be >= 0");
  if (!(elastic_fraction <= 10)) return fail("elastic_fraction must be <= 10");
  return true;
}

namespace {

// The specimen along the stroke: the worn track's shape (mean 1 over the
// stroke) and slope, and the elastic compliance's shape (zero mean, unit
// sd), from hardness and stiffness with earlywood / latewood bands across
// the rings and a random texture.
struct Specimen {
  Grid wear_shape, wear_slope, elastic_shape;
  double wear_sd = 0;  // sd of wear_shape over the stroke (its mean is 1)
  // mu_eff / mu along the stroke from the local hardness (mean 1 over the
  // stroke; 1 everywhere without a friction pattern).
  Grid friction;
  // The fibres' tooth angle relative to its mean over the stroke (the
  // ratchet's, laws::RatchetMu): the stiff latewood cell walls spring back
  // upright behind the sphere, the earlywood's stay crushed; the contact
  // meets the teeth under its footprint.
  Grid teeth;
};

// The density across one growth ring at phase p in [0, 1): it rises
// gradually from the earlywood to the latewood and falls sharply at the
// ring's boundary (1% of a ring).
double RingDensity(double p) {
  const double rise = p * p * p;
  const double fall = 1.0 / (1.0 + std::exp((p - 0.99) / 0.003));
  return rise * fall;
}

// mu / mean(mu) along the grid from the friction patterns: mu ~ H^-gamma
// with each pattern's ln H scaled to the strength's sd over the stroke.
// The soft spot's place is drawn from `rng`.
Eigen::VectorXd FrictionFactor(const SimulationOptions& o,
                               const Eigen::VectorXd& xg,
                               const Eigen::VectorXd& texture,
                               const Eigen::VectorXd& ring_phase,
                               Rng& rng) {
  const HiddenEffects& fx = o.effects;
  const Eigen::Index ng = xg.size();
  Eigen::VectorXd log_mu = Eigen::VectorXd::Zero(ng);
  auto add = [&](double strength, const Eigen::VectorXd& log_h) {
    if (strength == 0) return;
    double m = 0, m2 = 0;
    int n = 0;
    for (Eigen::Index i = 0; i < ng; ++i) {
      if (std::abs(xg[i]) > o.amplitude_mm) continue;
      m += log_h[i];
      m2 += log_h[i] * log_h[i];
      ++n;
    }
    m /= n;
    const double sd = std::sqrt(std::max(0.0, m2 / n - m * m));
    if (sd > 0) log_mu -= strength * (log_h.array() - m).matrix() / sd;
  };
  Eigen::VectorXd bands(ng), trend(ng), spot(ng);
  const double centre = (rng.Uniform() - 0.5) * 1.2 * o.amplitude_mm;
  for (Eigen::Index i = 0; i < ng; ++i) {
    const double density = o.across_rings ? RingDensity(ring_phase[i]) : 0.0;
    bands[i] = std::log(1.0 + (o.hardness_contrast - 1.0) * density) +
               o.texture * texture[i];
    trend[i] = xg[i] / o.amplitude_mm;
    const double u = (xg[i] - centre) / 0.25;
    spot[i] = -std::exp(-0.5 * u * u);
  }
  add(fx.mu_variation, bands);
  add(fx.mu_trend, trend);
  add(fx.mu_soft_spot, spot);
  Eigen::VectorXd factor = log_mu.array().exp().matrix();
  double sum = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < ng; ++i) {
    if (std::abs(xg[i]) <= o.amplitude_mm) sum += factor[i], ++n;
  }
  return factor / (sum / n);
}

// The fraction of latewood at ring phase p: smooth band edges (logistic,
// 4% of a ring), the band wrapping around the ring.
double Latewood(const SimulationOptions& o, double p) {
  const double edge = 0.04;
  const double start = 1.0 - o.latewood_fraction;
  return 1.0 / (1.0 + std::exp(-(p - start) / edge)) *
             (1.0 / (1.0 + std::exp((p - 1.0) / edge))) +
         1.0 / (1.0 + std::exp(-(p + 1.0 - start) / edge)) *
             (1.0 / (1.0 + std::exp(p / edge)));
}

Specimen MakeSpecimen(const SimulationOptions& o, Rng& rng, Rng& extra) {
  const double margin = o.sphere_radius_mm;
  const double step = 0.002;
  const Eigen::Index ng = static_cast<Eigen::Index>(
                              std::ceil(2 * (o.amplitude_mm + margin) / step)) +
                          1;
  const double x0 = -(o.amplitude_mm + margin);
  const Eigen::VectorXd xg =
      Eigen::VectorXd::LinSpaced(ng, x0, x0 + (ng - 1) * step);
  // Each ring's widths from a stream of its own, so that nothing else a
  // seed makes changes with ring_width_cv.
  Rng widths(o.seed ^ 0xD1B54A32D192ED03ULL);
  const Eigen::VectorXd ring_phase =
      internal::RingPhase(xg,
                          o.ring_period_mm,
                          o.ring_width_cv,
                          o.ring_period_mm * rng.Uniform(),
                          widths);
  const Eigen::VectorXd texture = Texture(xg, rng);
  const Eigen::VectorXd texture_e = Texture(xg, rng);
  Eigen::VectorXd hardness(ng), stiffness(ng);
  for (Eigen::Index i = 0; i < ng; ++i) {
    const double latewood = o.across_rings ? Latewood(o, ring_phase[i]) : 0.0;
    hardness[i] = (1.0 + (o.hardness_contrast - 1.0) * latewood) *
                  (1.0 + o.texture * texture[i]);
    stiffness[i] = (1.0 + (o.hardness_contrast - 1.0) * latewood) *
                   (1.0 + o.texture * texture_e[i]);
  }
  const double sigma = 0.5 * o.footprint_mm / step;
  Eigen::VectorXd wear = GaussianSmooth(hardness.cwiseInverse(), sigma);
  // Mean 1 over the stroke (the sum over the count, as it always was).
  double wear_sum = 0;
  int nin = 0;
  for (Eigen::Index i = 0; i < ng; ++i) {
    if (std::abs(xg[i]) <= o.amplitude_mm) wear_sum += wear[i], ++nin;
  }
  wear /= wear_sum / nin;
  Eigen::VectorXd elastic =
      GaussianSmooth(stiffness.cwiseInverse(), 1.6 * sigma);
  const auto [m, sd] = internal::StrokeMoments(o.amplitude_mm, xg, elastic);
  elastic = sd > 0 ? Eigen::VectorXd((elastic.array() - m) / sd)
                   : Eigen::VectorXd::Zero(ng);
  Specimen s;
  s.wear_shape = Grid{x0, step, wear};
  s.wear_slope = s.wear_shape.Derivative();
  s.elastic_shape = Grid{x0, step, elastic};
  s.friction =
      Grid{x0, step, FrictionFactor(o, xg, texture, ring_phase, extra)};
  const Eigen::VectorXd teeth = GaussianSmooth(stiffness, sigma);
  s.teeth =
      Grid{x0,
           step,
           teeth / internal::StrokeMoments(o.amplitude_mm, xg, teeth).first};
  // The sd by the one-pass formula the elastic fraction always used.
  double w1 = 0, w2 = 0;
  for (Eigen::Index i = 0; i < ng; ++i) {
    if (std::abs(xg[i]) > o.amplitude_mm) continue;
    w1 += wear[i];
    w2 += wear[i] * wear[i];
  }
  w1 /= nin;
  s.wear_sd = std::sqrt(std::max(0.0, w2 / nin - w1 * w1));
  return s;
}

// How the test evolves: depth of the track (running-in, then slow linear
// growth, reaching final_depth after the last cycle), mu per cycle, and the
// elastic part's amplitude (given, or relative to the final profile).
struct Schedule {
  const SimulationOptions& o;
  double depth_scale = 0, elastic_sd_mm = 0;
  // A rigid sphere's path on the worn profile (rigid_sphere only).
  std::optional<internal::RidingPath> riding;

  Schedule(const SimulationOptions& options, const Specimen& s) : o(options) {
    if (o.rigid_sphere) riding.emplace(o, s.wear_shape);
    depth_scale = o.final_depth_mm / Growth(o.cycles - 1);
    elastic_sd_mm = o.elastic_fraction >= 0
                        ? o.elastic_fraction * depth_scale *
                              Growth(o.cycles - 1) * s.wear_sd
                        : o.elastic_mm;
  }
  double Growth(double n) const {
    return (1.0 - std::exp(-(n + 1) / o.running_in_cycles)) +
           0.3 * (n + 1) / o.cycles;
  }
  double DepthAmp(int cycle) const { return depth_scale * Growth(cycle); }
  double Mu(int n) const {
    return o.mu_steady +
           (o.mu_initial - o.mu_steady) * std::exp(-n / o.running_in_cycles) +
           o.mu_drift * n / std::max(1, o.cycles - 1);
  }
};

// The contact: the sphere slides on a plane tilted by a = atan(k), k the
// slope dz/dx of its worn path. The specimen pushes on it with a force
// resolved along the plane's normal (N) and, against the motion s = +-1,
// along its tangent (mu N); the frame measures the horizontal part Q and
// the vertical part P:
//   Q = N (sin a + s mu cos a),  P = N (cos a - s mu sin a).
// The spring sets P; dividing the two by N cos a leaves
//   Q = P (tan a + s mu) / (1 - s mu tan a).
double TiltedContactQ(double p, double k, double mu, int s) {
  const double tan_a = k;
  const double s_mu = static_cast<double>(s) * mu;
  return p * (tan_a + s_mu) / (1.0 - s_mu * tan_a);
}

// The true forces at one instant: the wear-scar model with the hidden
// effects (from their physical laws, samples/effect_laws.h), before the
// Jenkins element bounds the stick.
struct SlidingBounds {
  double p, upper, lower;
  double height;  // the sphere's, mm (up positive)
};

// The slow state of the contact: the specimen's temperature rise (0 to 1
// of its equilibrium) and the counter-face's wobble phase.
struct ContactState {
  double t = 0, warmth = 0;
  double wobble_phase = 0;
};

SlidingBounds ForcesAt(const SimulationOptions& o,
                       const Specimen& s,
                       const Schedule& schedule,
                       int c,
                       double pc,
                       double x,
                       double v,
                       const ContactState& state) {
  const HiddenEffects& fx = o.effects;
  const double depth_amp = schedule.DepthAmp(c);
  const double mu =
      schedule.Mu(c) * s.friction(x) * (1.0 + fx.thermal_drift * state.warmth);
  const double depth = depth_amp * s.wear_shape(x);
  // Sphere height f = -(worn depth + elastic penetration); the spring turns
  // it into P. The contact tilt k follows the worn (geometric) path only:
  // the elastic part moves the sphere, not the contact plane.
  const double elastic = schedule.elastic_sd_mm * s.elastic_shape(x);
  const auto* path =
      schedule.riding ? &schedule.riding->At(depth_amp) : nullptr;
  const double f = path ? path->first(x) - elastic : -(depth + elastic);
  // A dead weight presses with its weight wherever the sphere is.
  const double p =
      o.rig == Rig::kSpring ? pc + o.spring_n_per_mm * f : o.target_normal_n;
  // A wobbling counter-face adds its own tilt to the contact's.
  const double k = (path ? path->second(x) : -depth_amp * s.wear_slope(x)) +
                   fx.wobble_rad * std::sin(2 * kPi * fx.wobble_hz * state.t +
                                            state.wobble_phase);
  const double speed = std::abs(v);
  const double boundary =
      fx.stribeck_rise != 0
          ? laws::BoundaryFrictionFactor(
                speed, fx.stribeck_rise, fx.stribeck_speed_mm_s)
          : 1.0;
  // Adhesion grown at the last reversal, broken over the distance slid.
  const double slid = v >= 0 ? x + o.amplitude_mm : o.amplitude_mm - x;
  const double dwell = fx.dwell_adhesion != 0
                           ? laws::DwellAdhesionFactor(
                                 slid, fx.dwell_adhesion, fx.dwell_distance_mm)
                           : 1.0;
  const double mu_b = mu * boundary * dwell;
  constexpr double kRatchetMu = 0.11;
  const double teeth = fx.direction_asymmetry != 0 ? s.teeth(x) : 0.0;
  const double mu_f =
      fx.direction_asymmetry != 0
          ? laws::RatchetMu(mu_b, +1, fx.direction_asymmetry, kRatchetMu, teeth)
          : mu_b;
  const double mu_r =
      fx.direction_asymmetry != 0
          ? laws::RatchetMu(mu_b, -1, fx.direction_asymmetry, kRatchetMu, teeth)
          : mu_b;
  double upper = TiltedContactQ(p, k, mu_f, +1);
  double lower = TiltedContactQ(p, k, mu_r, -1);
  constexpr double kFilmSpeed = 10.0;  // mm/s, where c is stated
  const double extra =
      (fx.ploughing_n_per_mm != 0
           ? laws::PloughingForce(
                 depth, fx.ploughing_n_per_mm, o.final_depth_mm)
           : 0.0) +
      (fx.viscous_n_s_per_mm != 0
           ? laws::FilmShearForce(speed, fx.viscous_n_s_per_mm, kFilmSpeed)
           : 0.0);
  upper += extra;
  lower -= extra;
  if (fx.hook_n != 0) {
    const double reach = 3 * fx.hook_length_mm;
    upper += laws::EndWallResistance(o.amplitude_mm - x, fx.hook_n, reach);
    lower -= laws::EndWallResistance(x + o.amplitude_mm, fx.hook_n, reach);
  }
  return {p, upper, lower, f};
}

// The tribometer: x = A sin(2 pi f t) starts at 0 going up; complete cycles
// run from minimum to minimum (t = 0.75/f, 1.75/f, ...), so cycles + 1
// periods hold `cycles` complete ones. The load controller is slow: once
// per cycle it removes part of the error of the last cycle's mean. Writes
// time and x to the record and the true Q and P.
void RunTribometer(const SimulationOptions& o,
                   const Specimen& s,
                   const Schedule& schedule,
                   SimulatedChannels* rec,
                   Eigen::VectorXd* q_true,
                   Eigen::VectorXd* p_true,
                   Eigen::VectorXd* height_true,
                   double wobble_phase) {
  const Eigen::Index n = static_cast<Eigen::Index>(
      std::llround((o.cycles + 1) * o.sampling_rate_hz / o.frequency_hz));
  rec->time_s.resize(n);
  rec->x_mm.resize(n);
  q_true->resize(n);
  p_true->resize(n);
  height_true->resize(n);
  double pc = o.target_normal_n;  // controller's set point for the spring
  double q = 0.0, x_prev = 0.0, p_sum = 0;
  int cycle = -1;
  long p_count = 0;
  ContactState state;
  state.wobble_phase = wobble_phase;
  // Frictional heating: the power |Q v| against its steady mean warms the
  // specimen with the thermal time constant.
  const double steady_power =
      o.mu_steady * o.target_normal_n * 4 * o.amplitude_mm * o.frequency_hz;
  const double dt = 1.0 / o.sampling_rate_hz;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / o.sampling_rate_hz;
    state.t = t;
    double x, v;
    DriveAt(o, t, &x, &v);
    const int c =
        std::clamp(static_cast<int>(std::floor(t * o.frequency_hz - 0.75)),
                   0,
                   o.cycles - 1);
    if (c != cycle) {
      if (p_count > 0)
        pc += o.control_gain * (o.target_normal_n - p_sum / p_count);
      p_sum = 0;
      p_count = 0;
      cycle = c;
    }
    const SlidingBounds b = ForcesAt(o, s, schedule, c, pc, x, v, state);
    // Jenkins element: elastic stick, bounded by the sliding forces.
    if (i > 0) q += o.contact_stiffness_n_per_mm * (x - x_prev);
    q = std::clamp(q, b.lower, b.upper);
    x_prev = x;
    if (o.effects.thermal_drift != 0) {
      state.warmth = laws::FirstOrderStep(state.warmth,
                                          std::abs(q * v) / steady_power,
                                          dt,
                                          o.effects.thermal_time_s);
    }
    (*q_true)[i] = q;
    (*p_true)[i] = b.p;
    (*height_true)[i] = b.height;
    p_sum += b.p;
    ++p_count;
    rec->time_s[i] = t;
    rec->x_mm[i] = x;
  }
}

// The sensors: Q's lag, Q's crosstalk into P, noise and resolution.
void Measure(const SimulationOptions& o,
             const Eigen::VectorXd& q_true,
             const Eigen::VectorXd& p_true,
             const Eigen::VectorXd& height_true,
             Rng& rng,
             double pickup_phase,
             SimulatedChannels* rec) {
  const HiddenEffects& fx = o.effects;
  const Eigen::Index n = q_true.size();
  rec->tangential_n.resize(n);
  rec->normal_n.resize(n);
  const double dt = 1.0 / o.sampling_rate_hz;
  double qm = n > 0 ? q_true[0] : 0.0;
  laws::Resonator arm{qm, 0.0};
  for (Eigen::Index i = 0; i < n; ++i) {
    // The Q channel behind a first-order sensor, and a resonance.
    qm = fx.q_lag_s > 0 ? laws::FirstOrderStep(qm, q_true[i], dt, fx.q_lag_s)
                        : q_true[i];
    if (fx.ringing_hz > 0) {
      laws::ResonatorStep(&arm, qm, dt, fx.ringing_hz, fx.ringing_damping);
      qm = arm.y;
    }
    double q_out = qm;
    double pm = p_true[i] + fx.crosstalk_q_into_p * q_true[i];
    if (fx.pickup_n != 0) {
      // Mains picked up by both channels' cables (P's a little later).
      const double w = 2 * kPi * fx.pickup_hz * rec->time_s[i] + pickup_phase;
      q_out += fx.pickup_n * std::sin(w);
      pm += fx.pickup_n * std::sin(w - 0.6);
    }
    rec->tangential_n[i] = Quantise(
        q_out + o.noise_scale * o.q_noise_n * rng.Normal(), o.q_resolution_n);
    rec->normal_n[i] = Quantise(pm + o.noise_scale * o.p_noise_n * rng.Normal(),
                                o.p_resolution_n);
    rec->x_mm[i] += o.x_noise_mm * rng.Normal();
  }
  // The depth sensor reads the penetration (the sphere's height turned
  // over) with its offset and drift; drawn after the forces' noise, so that
  // the force channels do not change with it.
  if (o.depth_channel) {
    rec->depth_mm.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double drift = o.depth_drift_mm * static_cast<double>(i) /
                           std::max<Eigen::Index>(1, n - 1);
      rec->depth_mm[i] =
          Quantise(-height_true[i] + o.depth_offset_mm + drift +
                       o.noise_scale * o.depth_noise_mm * rng.Normal(),
                   o.depth_resolution_mm);
    }
  }
  rec->source = "simulator:" + o.name;
  rec->sampling_rate_hz = o.sampling_rate_hz;
}

// What the analysis should recover: mu per cycle, the final worn profile
// and the elastic part along the stroke, and whether the wear-scar
// hypothesis holds.
void FillTruth(const SimulationOptions& o,
               const Specimen& s,
               const Schedule& schedule,
               GroundTruth* truth) {
  truth->mu_per_cycle.resize(o.cycles);
  for (int c = 0; c < o.cycles; ++c) truth->mu_per_cycle[c] = schedule.Mu(c);
  const double final_amp = schedule.DepthAmp(o.cycles - 1);
  const int np = static_cast<int>(std::round(2 * o.amplitude_mm / 0.01)) + 1;
  truth->profile_x_mm =
      Eigen::VectorXd::LinSpaced(np, -o.amplitude_mm, o.amplitude_mm);
  truth->worn_depth_mm.resize(np);
  truth->elastic_mm.resize(np);
  truth->mu_factor.resize(np);
  for (int i = 0; i < np; ++i) {
    truth->mu_factor[i] = s.friction(truth->profile_x_mm[i]);
    truth->worn_depth_mm[i] = final_amp * s.wear_shape(truth->profile_x_mm[i]);
    truth->elastic_mm[i] =
        schedule.elastic_sd_mm * s.elastic_shape(truth->profile_x_mm[i]);
  }
  // The wear-scar hypothesis holds while the elastic part stays small next
  // to the waviness of the worn profile: the verdict must pass an elastic
  // part of 10% of the profile's sd and flag one of 25%; the truth puts the
  // line between them.
  constexpr double kElasticLimit = 0.175;
  const Eigen::ArrayXd d = truth->worn_depth_mm.array();
  auto sd_of = [](const Eigen::ArrayXd& v) {
    return std::sqrt((v - v.mean()).square().mean());
  };
  truth->explained_by_wear_scar =
      schedule.elastic_sd_mm < kElasticLimit * sd_of(d);
  const Eigen::ArrayXd f = d + truth->elastic_mm.array();
  truth->waviness_sd_mm.resize(o.cycles);
  for (int c = 0; c < o.cycles; ++c) {
    truth->waviness_sd_mm[c] = sd_of(d * (schedule.DepthAmp(c) / final_amp) +
                                     truth->elastic_mm.array());
  }
  truth->force_profile_sd_mm = sd_of(f);
  truth->force_profile_range_mm = f.maxCoeff() - f.minCoeff();
  truth->scan_profile_sd_mm = sd_of(d);
  truth->scan_profile_range_mm = d.maxCoeff() - d.minCoeff();
}

// Correlated isotropic roughness of the unworn surface, sd roughness_mm.
scan::HeightMap::Heights Roughness(const SimulationOptions& o, Rng& rng) {
  scan::HeightMap::Heights t(o.scan_rows, o.scan_cols);
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    t.data()[i] = static_cast<float>(rng.Normal());
  }
  BlurInPlace(&t, o.roughness_length_mm / o.scan_pitch_mm);
  const double sd =
      std::sqrt((t.cast<double>() - t.cast<double>().mean()).square().mean());
  if (sd > 0) t *= static_cast<float>(o.roughness_mm / sd);
  return t;
}

// Fibres: a random ridge profile across the fibre direction.
Grid Fibres(const SimulationOptions& o, Rng& rng) {
  Grid fibres{0.0, 1.0, Eigen::VectorXd::Zero(2)};
  if (!(o.fibre_amplitude_mm > 0)) return fibres;
  const double pitch = o.scan_pitch_mm;
  const double half =
      std::hypot(o.scan_cols * pitch, o.scan_rows * pitch) + pitch;
  fibres.step = std::min(pitch, o.fibre_width_mm) / 2;
  fibres.x0 = -half;
  const Eigen::Index nf =
      static_cast<Eigen::Index>(std::ceil(2 * half / fibres.step)) + 1;
  Eigen::VectorXd white(nf);
  for (Eigen::Index i = 0; i < nf; ++i) white[i] = rng.Normal();
  Eigen::VectorXd f = GaussianSmooth(white, o.fibre_width_mm / fibres.step);
  const double m = f.mean();
  const double sd = std::sqrt((f.array() - m).square().mean());
  fibres.v =
      sd > 0 ? Eigen::VectorXd((f.array() - m) * (o.fibre_amplitude_mm / sd))
             : Eigen::VectorXd::Zero(nf);
  return fibres;
}

// The plate frame of the scan: track centre, direction, and its truth.
struct ScanFrame {
  double ct, st, cx, cy, sf, cf;
};

ScanFrame MakeScanFrame(const SimulationOptions& o) {
  const double pitch = o.scan_pitch_mm;
  const double theta = o.scan_angle_deg * kPi / 180.0;
  const double phi = theta + o.fibre_angle_deg * kPi / 180.0;
  ScanFrame f;
  f.ct = std::cos(theta);
  f.st = std::sin(theta);
  f.cx = 0.5 * (o.scan_cols - 1) * pitch + o.scan_track_offset_mm * f.ct;
  f.cy = 0.5 * (o.scan_rows - 1) * pitch + o.scan_track_offset_mm * f.st;
  f.cf = std::cos(phi);
  f.sf = std::sin(phi);
  return f;
}

// Depth of the groove a sphere of radius r leaves at (u along, w across)
// the track of final depth profile d0, and the rim pushed up beside it.
struct Groove {
  double depth, rim;
};

Groove GrooveAt(const SimulationOptions& o,
                const Specimen& s,
                double final_amp,
                double u,
                double w) {
  const double r = o.sphere_radius_mm;
  const double ue = std::clamp(u, -o.amplitude_mm, o.amplitude_mm);
  const double d0 = final_amp * s.wear_shape(ue);
  const double du = std::abs(u) - o.amplitude_mm;
  const double r2 = w * w + (du > 0 ? du * du : 0.0);
  const double depth =
      r2 < r * r ? std::max(0.0, d0 - (r - std::sqrt(r * r - r2))) : 0.0;
  double rim = 0.0;
  if (o.rim_fraction > 0 && d0 > 0 && d0 < r) {
    const double edge = std::sqrt(r * r - (r - d0) * (r - d0));
    const double t = (std::sqrt(r2) - edge) / o.rim_width_mm;
    rim = o.rim_fraction * d0 * std::exp(-t * t);
  }
  return {depth, rim};
}

// Invalid pixels: small scattered clusters (steep walls, dark latewood)
// and one large cluster (a pore, a shadow), then a few spikes.
void AddScanDefects(const SimulationOptions& o,
                    Rng& rng,
                    scan::HeightMap* map) {
  const int rows = o.scan_rows, cols = o.scan_cols;
  const double pitch = o.scan_pitch_mm;
  const float kNaN = std::numeric_limits<float>::quiet_NaN();
  const long pixels = static_cast<long>(rows) * cols;
  const long clusters =
      static_cast<long>(o.scan_invalid_fraction * pixels / 5.0);
  for (long k = 0; k < clusters; ++k) {
    const int rr = static_cast<int>(rng.Uniform() * rows);
    const int cc = static_cast<int>(rng.Uniform() * cols);
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int r2i = rr + dr, c2i = cc + dc;
        if (std::abs(dr) + std::abs(dc) > 1 || r2i < 0 || c2i < 0 ||
            r2i >= rows || c2i >= cols) {
          continue;
        }
        map->height_mm(r2i, c2i) = kNaN;
      }
    }
  }
  if (o.scan_invalid_cluster_mm > 0) {
    const double ccx = rng.Uniform() * cols * pitch;
    const double ccy = rng.Uniform() * rows * pitch;
    const double rad = o.scan_invalid_cluster_mm;
    for (int row = 0; row < rows; ++row) {
      for (int col = 0; col < cols; ++col) {
        // A blob, not a disc: the radius wobbles with the angle.
        const double dx = col * pitch - ccx, dy = row * pitch - ccy;
        const double rr =
            rad * (1.0 + 0.25 * std::sin(3 * std::atan2(dy, dx) + 1.0));
        if (dx * dx + dy * dy < rr * rr) map->height_mm(row, col) = kNaN;
      }
    }
  }
  const long spikes = static_cast<long>(o.scan_spike_fraction * pixels);
  for (long k = 0; k < spikes; ++k) {
    const int rr = static_cast<int>(rng.Uniform() * rows);
    const int cc = static_cast<int>(rng.Uniform() * cols);
    map->height_mm(rr, cc) +=
        static_cast<float>((rng.Uniform() < 0.5 ? -1 : 1) * 0.04);
  }
}

// The scanner: the worn track at the end of the test on a tilted plane,
// with roughness, fibres (mostly worn away inside the track), noise and
// defects; the frame's truth goes to `truth`.
scan::HeightMap ScanTrack(const SimulationOptions& o,
                          const Specimen& s,
                          const Schedule& schedule,
                          Rng& rng,
                          GroundTruth* truth) {
  scan::HeightMap map;
  const int rows = o.scan_rows, cols = o.scan_cols;
  const double pitch = o.scan_pitch_mm;
  map.height_mm.resize(rows, cols);
  map.valid.resize(rows, cols);
  map.dx_mm = map.dy_mm = pitch;
  const ScanFrame f = MakeScanFrame(o);
  const double final_amp = schedule.DepthAmp(o.cycles - 1);
  const scan::HeightMap::Heights roughness = Roughness(o, rng);
  const Grid fibres = Fibres(o, rng);
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const double X = col * pitch, Y = row * pitch;
      const double along = (X - f.cx) * f.ct + (Y - f.cy) * f.st;
      const double across = -(X - f.cx) * f.st + (Y - f.cy) * f.ct;
      const Groove g =
          GrooveAt(o, s, final_amp, o.scan_flipped ? -along : along, across);
      // The worn surface keeps little of the texture.
      const double surface =
          (roughness(row, col) +
           (o.fibre_amplitude_mm > 0 ? fibres(-X * f.sf + Y * f.cf) : 0.0)) /
          (1.0 + g.depth / 0.01);
      const double z = o.plane_z0_mm + o.plane_dzdx * X + o.plane_dzdy * Y -
                       g.depth + g.rim + surface +
                       o.scan_noise_mm * rng.Normal();
      map.height_mm(row, col) = static_cast<float>(z);
    }
  }
  AddScanDefects(o, rng, &map);
  scan::SyncValidity(&map);
  map.metadata.source = "simulator:" + o.name;
  map.metadata.format = "simulated";
  map.metadata.instrument = "wearscar virtual scanner";
  truth->scan_centre_x_mm = f.cx;
  truth->scan_centre_y_mm = f.cy;
  truth->scan_angle_deg = o.scan_angle_deg;
  truth->scan_flipped = o.scan_flipped;
  truth->plane_dzdx = o.plane_dzdx;
  truth->plane_dzdy = o.plane_dzdy;
  truth->plane_z0_mm = o.plane_z0_mm;
  truth->scan_pitch_mm = pitch;
  truth->origin_col = f.cx / pitch;
  truth->origin_row = f.cy / pitch;
  const double flip = o.scan_flipped ? -1.0 : 1.0;
  truth->col_per_mm = flip * f.ct / pitch;
  truth->row_per_mm = flip * f.st / pitch;
  return map;
}

}  // namespace

SimulatedTest Simulate(const SimulationOptions& o) {
  std::string why;
  if (!o.IsValid(&why))
    throw std::invalid_argument("simulation options: " + why);
  if (o.record_from_cycle > 0) return internal::SimulateFrom(o);
  // The random numbers are drawn in this order (specimen, sensors, scanner):
  // the committed samples depend on it.
  Rng rng(o.seed);
  SimulatedTest out;
  // The newer effects draw from their own stream, so that the committed
  // samples (drawn from `rng`) stay as they were.
  Rng extra(o.seed ^ 0x9E3779B97F4A7C15ULL);
  const Specimen specimen = MakeSpecimen(o, rng, extra);
  const double wobble_phase = 2 * kPi * extra.Uniform();
  const double pickup_phase = 2 * kPi * extra.Uniform();
  const Schedule schedule(o, specimen);
  Eigen::VectorXd q_true, p_true;
  Eigen::VectorXd height_true;
  RunTribometer(o,
                specimen,
                schedule,
                &out.record,
                &q_true,
                &p_true,
                &height_true,
                wobble_phase);
  Measure(o, q_true, p_true, height_true, rng, pickup_phase, &out.record);
  FillTruth(o, specimen, schedule, &out.truth);
  out.scan = ScanTrack(o, specimen, schedule, rng, &out.truth);
  return out;
}

}  // namespace wearscar::samples
