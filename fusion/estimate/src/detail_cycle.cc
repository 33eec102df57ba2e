#include "wearscar/fusion/detail_cycle.h"

#include <cmath>
#include <limits>

#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion {
namespace {

using support::kNaN;

// The gross-slip samples of both directions with both slopes and both
// models.
void FillSamples(const CycleSamples& kf,
                 double mu_force,
                 double mu_scan,
                 const PlateProfile* scan_slope,
                 DetailCycle* d) {
  const Eigen::Index n = kf.forward.q_n.size() + kf.reverse.q_n.size();
  for (Eigen::VectorXd* v : {&d->direction,
                             &d->x_mm,
                             &d->q_n,
                             &d->p_n,
                             &d->k_force,
                             &d->k_scan,
                             &d->q_model_force_n,
                             &d->q_model_scan_n})
    v->resize(n);
  Eigen::Index at = 0;
  for (const SlipSamples* s : {&kf.forward, &kf.reverse}) {
    for (Eigen::Index i = 0; i < s->q_n.size(); ++i, ++at) {
      const double ks = scan_slope ? scan_slope->At(s->x_mm[i]) : kNaN;
      d->direction[at] = s->direction;
      d->x_mm[at] = s->x_mm[i];
      d->q_n[at] = s->q_n[i];
      d->p_n[at] = s->p_n[i];
      d->k_force[at] = s->k[i];
      d->k_scan[at] = ks;
      d->q_model_force_n[at] =
          WearScarTangentialForce(s->p_n[i], s->k[i], mu_force, s->direction);
      d->q_model_scan_n[at] =
          std::isfinite(ks)
              ? WearScarTangentialForce(s->p_n[i], ks, mu_scan, s->direction)
              : kNaN;
    }
  }
}

// The wear-scar model along LuGre's trace of the cycle: the gathered
// samples keep the record's order, so one pointer per direction walks
// them alongside.
Eigen::VectorXd ModelAlongTrace(const force::ForceRecord& record,
                                const force::Cycle& c,
                                const CycleSamples& kf,
                                double mu_force,
                                const LugreFit& lugre) {
  Eigen::Index next[2] = {0, 0};
  auto model_at = [&](Eigen::Index src) {
    const bool forward = src < c.forward.end;
    const force::HalfCycle& h = forward ? c.forward : c.reverse;
    if (src < h.slip_begin || src >= h.slip_end) return kNaN;
    const SlipSamples& s = forward ? kf.forward : kf.reverse;
    Eigen::Index& j = next[forward ? 0 : 1];
    if (j < s.x_mm.size() && s.x_mm[j] == record.x_mm[src] &&
        s.p_n[j] == record.normal_n[src]) {
      ++j;
      return WearScarTangentialForce(
          s.p_n[j - 1], s.k[j - 1], mu_force, s.direction);
    }
    return kNaN;  // a sample the fit did not use (no finite k)
  };
  Eigen::VectorXd q(lugre.time_s.size());
  for (Eigen::Index i = 0; i < q.size(); ++i)
    q[i] = model_at(c.forward.begin + i);
  return q;
}

}  // namespace

DetailCycle ComputeDetailCycle(const force::ForceRecord& record,
                               const ForceAnalysis& force,
                               const SlopeFits& force_fits,
                               const FrictionFitOptions& options,
                               int cycle,
                               int cost_points,
                               const MuFit* fit_scan,
                               const PlateProfile* scan_slope,
                               const LugreFit* lugre) {
  DetailCycle d;
  const int n = static_cast<int>(force.cycles.cycles.size());
  if (cycle < 0 || cycle >= n) return d;
  d.cycle = cycle;
  const ForceSlopes force_slopes(record, force.cycles, options, cycle, cycle);
  const CycleSamples kf = force_slopes.Gather(cycle);
  const double mu_force = force_fits.cycles[cycle].mu_hat;
  const double mu_scan = fit_scan ? fit_scan->mu_hat : kNaN;
  FillSamples(kf, mu_force, mu_scan, scan_slope, &d);
  d.cost_mu = Eigen::VectorXd::LinSpaced(
      cost_points, options.fit.mu_min, options.fit.mu_max);
  d.cost_force = CostCurve(kf, d.cost_mu);
  d.cost_scan = Eigen::VectorXd::Constant(d.cost_mu.size(), kNaN);
  if (scan_slope != nullptr) {
    d.cost_scan = CostCurve(GatherCycle(record,
                                        force.cycles.cycles[cycle],
                                        SlopeSource::kScan,
                                        options,
                                        scan_slope),
                            d.cost_mu);
  }
  if (lugre != nullptr) {
    d.lugre_q_wearscar_n = ModelAlongTrace(
        record, force.cycles.cycles[cycle], kf, mu_force, *lugre);
  }
  return d;
}

}  // namespace wearscar::fusion
