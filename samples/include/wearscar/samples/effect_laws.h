#pragma once
// The physical laws by which the virtual tribometer hides its effects.
// Each is written from the physics it stands for, not from the formula the
// diagnosis fits (wearscar::fusion::EffectLibrary): a diagnosis that names
// these effects has found a physical cause, not its own model. A test
// checks, effect by effect, that the library's formula does not reproduce
// the law below, but for two: a load cell's crosstalk has one form, and a
// first-order sensor is a delay on the loops (HiddenEffects tests say so).

namespace wearscar::samples::laws {

// Boundary friction at low speed: the share of the load the asperities
// carry falls as a film builds up with speed (a Hersey-type transition),
// mu_eff / mu = 1 + rise / (1 + (v / v_s)^2).
double BoundaryFrictionFactor(double speed_mm_s, double rise, double v_s);

// Ploughing: the sphere pushes the groove's cross-section ahead of it; a
// sphere's segment of depth d has an area growing as d^1.5. The force is
// scaled to strength * reference_depth at the reference depth (so the
// strength reads as N per mm of depth there).
double PloughingForce(double depth_mm,
                      double strength_n_per_mm,
                      double reference_depth_mm);

// Fibres inclined to the surface act as a ratchet: sliding with them the
// friction angle is atan(mu) - theta, against them atan(mu) + theta. The
// mean angle comes from the asymmetry a at the reference mu,
// atan(mu_ref (1 + a)) - atan(mu_ref); `tooth` scales it where the teeth
// stand higher or lower than their mean (1). The angle adds to the
// friction's, so the friction's difference between the directions stays
// about 2 theta (1 + mu^2) where mu changes, and follows the teeth.
double RatchetMu(double mu,
                 int direction,
                 double asymmetry,
                 double mu_ref,
                 double tooth = 1.0);

// A film sheared between the sphere and the wood thins with speed
// (shear-thinning, flow index 0.8): force = c v_ref (v / v_ref)^0.8, c in
// N s/mm at v_ref.
double FilmShearForce(double speed_mm_s, double c_n_s_per_mm, double v_ref);

// The end of the groove is an unworn wall: the contact circle of radius
// `reach` overlaps it as the sphere approaches, the resistance growing with
// the overlap squared and zero beyond it.
double EndWallResistance(double distance_to_end_mm,
                         double strength_n,
                         double reach_mm);

// A first-order sensor (charge amplifier, filter) responding to its input
// with time constant tau: y += (1 - exp(-dt / tau)) (u - y).
double FirstOrderStep(double y, double input, double dt_s, double tau_s);

// Adhesion grows while the contact dwells at a reversal and is broken
// within a slip distance d_c (rate-and-state): after a reversal,
// mu_eff / mu = 1 + b exp(-slid / d_c).
double DwellAdhesionFactor(double slid_mm, double b, double d_c_mm);

// A sensor behind a resonance: y'' + 2 zeta w y' + w^2 y = w^2 input,
// advanced by dt with the input held (semi-implicit Euler in substeps of
// at most 1/(50 f)).
struct Resonator {
  double y = 0, v = 0;
};
void ResonatorStep(
    Resonator* r, double input, double dt_s, double f_hz, double zeta);

}  // namespace wearscar::samples::laws
