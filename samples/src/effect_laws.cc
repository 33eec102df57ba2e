#include "wearscar/samples/effect_laws.h"

#include <algorithm>
#include <cmath>

namespace wearscar::samples::laws {

double BoundaryFrictionFactor(double speed_mm_s, double rise, double v_s) {
  const double r = speed_mm_s / v_s;
  return 1.0 + rise / (1.0 + r * r);
}

double PloughingForce(double depth_mm,
                      double strength_n_per_mm,
                      double reference_depth_mm) {
  if (!(reference_depth_mm > 0) || !(depth_mm > 0)) return 0.0;
  return strength_n_per_mm * reference_depth_mm *
         std::pow(depth_mm / reference_depth_mm, 1.5);
}

double RatchetMu(
    double mu, int direction, double asymmetry, double mu_ref, double tooth) {
  const double theta =
      tooth * (std::atan(mu_ref * (1.0 + asymmetry)) - std::atan(mu_ref));
  return std::tan(std::atan(mu) + direction * theta);
}

double FilmShearForce(double speed_mm_s, double c_n_s_per_mm, double v_ref) {
  return c_n_s_per_mm * v_ref * std::pow(std::abs(speed_mm_s) / v_ref, 0.8);
}

double EndWallResistance(double distance_to_end_mm,
                         double strength_n,
                         double reach_mm) {
  if (!(distance_to_end_mm < reach_mm)) return 0.0;
  const double overlap = 1.0 - std::max(0.0, distance_to_end_mm) / reach_mm;
  return strength_n * overlap * overlap;
}

double FirstOrderStep(double y, double input, double dt_s, double tau_s) {
  if (!(tau_s > 0)) return input;
  return y + (1.0 - std::exp(-dt_s / tau_s)) * (input - y);
}

double DwellAdhesionFactor(double slid_mm, double b, double d_c_mm) {
  return 1.0 + b * std::exp(-std::max(0.0, slid_mm) / d_c_mm);
}

void ResonatorStep(
    Resonator* r, double input, double dt_s, double f_hz, double zeta) {
  const double w = 2.0 * 3.14159265358979323846 * f_hz;
  const int steps =
      std::max(1, static_cast<int>(std::ceil(dt_s * f_hz * 50.0)));
  const double h = dt_s / steps;
  for (int i = 0; i < steps; ++i) {
    r->v += h * (w * w * (input - r->y) - 2.0 * zeta * w * r->v);
    r->y += h * r->v;
  }
}

}  // namespace wearscar::samples::laws
