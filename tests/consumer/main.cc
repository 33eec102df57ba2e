// Levels a tilted plane (wearscar::scan, PCL inside) and fits mu on samples
// made by the wear-scar model (wearscar::fusion): exit 0 when both come back.
#include <cmath>
#include <cstdio>

#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/scan/level.h"

int main() {
  wearscar::scan::HeightMap map;
  map.dx_mm = map.dy_mm = 0.01;
  map.height_mm.resize(64, 96);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 96; ++c)
      map.height_mm(r, c) =
          static_cast<float>(0.002 * c * 0.01 - 0.001 * r * 0.01);
  wearscar::scan::SyncValidity(&map);
  const auto level = wearscar::scan::LevelHeightMap(&map);

  wearscar::fusion::CycleSamples s;
  const double mu = 0.12;
  for (auto* d : {&s.forward, &s.reverse}) {
    d->direction = d == &s.forward ? +1 : -1;
    d->q_n.resize(200);
    d->p_n.resize(200);
    d->k.resize(200);
    d->x_mm.resize(200);
    for (int i = 0; i < 200; ++i) {
      d->x_mm[i] = -2.5 + 5.0 * i / 199;
      d->k[i] = 0.1 * std::cos(d->x_mm[i] * 4);
      d->p_n[i] = 30;
      d->q_n[i] = wearscar::fusion::WearScarTangentialForce(
          d->p_n[i], d->k[i], mu, d->direction);
    }
  }
  const auto fit = wearscar::fusion::FitMu(s);
  std::printf("dz/dx %.5f, dz/dy %.5f; %s\n",
              level.dzdx(),
              level.dzdy(),
              fit.BriefReport().c_str());
  const bool ok = std::abs(level.dzdx() - 0.002) < 1e-6 &&
                  std::abs(level.dzdy() + 0.001) < 1e-6 &&
                  std::abs(fit.mu_hat - mu) < 1e-6;
  return ok ? 0 : 1;
}
