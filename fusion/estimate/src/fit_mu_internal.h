#pragma once
// What fit_mu.cc and fit_friction.cc share.

#include "wearscar/fusion/fit_mu.h"

namespace wearscar::fusion::internal {

// mu-hat's second-order bias per unit variance of the noise in k (about
// -3 mu for small k): mu-hat - mu = var(k noise) times this.
double KNoiseBiasPerVariance(const CycleSamples& samples, double mu);

// The options with the derivative's spans resolved for `rate_hz`.
FrictionFitOptions Resolved(const FrictionFitOptions& o, double rate_hz);

}  // namespace wearscar::fusion::internal
