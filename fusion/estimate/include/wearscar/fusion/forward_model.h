#pragma once

#include <cmath>

#include "wearscar/fusion/error.h"

namespace wearscar::fusion {

// Wear-scar interaction (paper Eqs. 1-2 with N eliminated): the tangential
// force measured while sliding in direction s = sign(dx/dt) over a path of
// slope k = tan(theta) with Coulomb coefficient mu under measured normal
// force P:
//   Q_w = P (k + s mu) / (1 - s mu k)  (= P tan(theta + s atan mu)).
// The denominator stays positive for the small slopes the hypothesis needs
// (|mu k| < 1); callers check it.
template <typename T>
T WearScarTangentialForce(const T& normal_n,
                          const T& slope,
                          const T& mu,
                          int s) {
  const T sm = static_cast<double>(s) * mu;
  return normal_n * (slope + sm) / (1.0 - sm * slope);
}

// Stribeck-type rise of friction at low speed:
//   mu_eff = mu (1 + a exp(-(v / v_s)^2)).
template <typename T>
T StribeckFactor(const T& speed_mm_s,
                 const T& rise,
                 const T& stribeck_speed_mm_s) {
  using std::exp;
  const T r = speed_mm_s / stribeck_speed_mm_s;
  return 1.0 + rise * exp(-r * r);
}

// End-of-stroke hook: extra resistance growing as the slider approaches the
// end of the stroke in its direction of motion,
//   F_hook = s H exp(-(x_end - s x) / lambda),
// with x_end = s * (stroke end in the direction s) so that x_end - s x >= 0.
template <typename T>
T HookForce(const T& distance_to_end_mm,
            const T& strength_n,
            const T& length_mm,
            int s) {
  using std::exp;
  return static_cast<double>(s) * strength_n *
         exp(-distance_to_end_mm / length_mm);
}

}  // namespace wearscar::fusion
