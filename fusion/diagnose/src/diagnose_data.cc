#include "diagnose_data.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "wearscar/force/slope.h"
#include "wearscar/force/turn_delay.h"
#include "wearscar/fusion/error.h"

namespace wearscar::fusion::internal {

// Up to max_cycles cycles spread evenly over those after running-in.
std::vector<int> ChooseCycles(int n, int first, int max_cycles) {
  const int available = n - first;
  const int m = std::min(max_cycles, available);
  std::vector<int> chosen;
  for (int i = 0; i < m; ++i) {
    chosen.push_back(first +
                     static_cast<int>(static_cast<long>(i) * (available - 1) /
                                      std::max(1, m - 1)));
  }
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

namespace {

ProfileGrid MakeProfileGrid(const force::ForceRecord& record,
                            const force::CycleSet& cycles,
                            const std::vector<int>& chosen,
                            double profile_step_mm) {
  ProfileGrid g;
  double max_step = 0;
  for (int c : chosen) {
    for (Eigen::Index i = cycles.cycles[c].forward.begin;
         i < cycles.cycles[c].reverse.end;
         ++i) {
      if (!std::isfinite(record.x_mm[i])) continue;
      g.x_lo = std::min(g.x_lo, record.x_mm[i]);
      g.x_hi = std::max(g.x_hi, record.x_mm[i]);
      if (i == cycles.cycles[c].forward.begin) continue;
      const double dx = std::abs(record.x_mm[i] - record.x_mm[i - 1]);
      if (std::isfinite(dx)) max_step = std::max(max_step, dx);
    }
  }
  g.bin = std::max(profile_step_mm, 1.05 * max_step);
  g.bins = static_cast<Eigen::Index>(std::ceil((g.x_hi - g.x_lo) / g.bin)) + 1;
  g.centres = Eigen::VectorXd::LinSpaced(
      g.bins, g.x_lo + 0.5 * g.bin, g.x_lo + (g.bins - 0.5) * g.bin);
  return g;
}

// Base slope of one cycle: its own P (and Q, for crosstalk) binned along x
// per direction over the cycle and its neighbours (the ensemble of
// FrictionFitOptions: the track changes slowly, and at the paper's noise
// one cycle's slope is noisy enough that shrinking it, an apparent elastic
// compliance, would lower the cost on clean data), smoothed by a cubic
// Savitzky-Golay filter and differentiated once: k = (1/S) dP/dx and
// (1/S) dQ/dx. Binning and smoothing keep the noise of a sample-wise
// derivative out of the comparison (no effect can win by shrinking noisy
// slopes), while each cycle keeps its own track. A rig whose P carries no
// profile (a dead weight) gives k from its depth channel the same way
// (k = -d(depth)/dx, no Q in it), or from a fixed profile (the scan's
// centreline) for every cycle.
class CycleSlopes {
 public:
  CycleSlopes(const force::ForceRecord& record,
              const force::CycleSet& cycles,
              const ProfileGrid& grid,
              const FrictionFitOptions& friction,
              const PlateProfile* fixed,
              const DiagnoseOptions& o)
      : record_(record),
        cycles_(cycles),
        grid_(grid),
        o_(o),
        fixed_(fixed),
        from_depth_(friction.k_from_depth),
        profile_(friction.k_from_depth ? record.depth_mm : record.normal_n) {
    if (from_depth_ && !record.has_depth())
      throw FusionError("k from the depth channel, but the record has none");
    sg_ = friction.slope;
    sg_.method = force::DerivativeMethod::kSavitzkyGolay;
    sg_.window = std::max(
        7,
        2 * static_cast<int>(std::round(0.5 * o.profile_span_mm / grid.bin)) +
            1);
    sg_.polynomial_order = o.slope_polynomial_order;
    sg_.min_span_mm = 0;
    per_mm_ =
        from_depth_ ? -friction.depth_sign : friction.slope.spring_n_per_mm;
    half_ = friction.k_estimate == KEstimate::kEnsemble
                ? std::max(friction.ensemble.cycles, o.slope_cycles) / 2
                : 0;
  }

  void operator()(int c, PlateProfile kp[2], PlateProfile kq[2]) const {
    if (fixed_ != nullptr) {
      Eigen::VectorXd k(grid_.bins);
      for (Eigen::Index b = 0; b < grid_.bins; ++b)
        k[b] = fixed_->At(grid_.centres[b]);
      for (int row = 0; row < 2; ++row) {
        kp[row] = {grid_.centres, k};
        kq[row] = {grid_.centres, Eigen::VectorXd::Zero(grid_.bins)};
      }
      return;
    }
    const int n = static_cast<int>(cycles_.cycles.size());
    std::vector<int> window;
    for (int j = std::max(0, c - half_); j <= std::min(n - 1, c + half_); ++j)
      window.push_back(j);
    const Eigen::MatrixXd pc = Bin(window, profile_);
    // Q enters k only through P (crosstalk); a depth channel holds none.
    const Eigen::MatrixXd qc = from_depth_
                                   ? Eigen::MatrixXd::Zero(2, grid_.bins).eval()
                                   : Bin(window, record_.tangential_n);
    Eigen::VectorXd kpd[2], kqd[2];
    for (int row = 0; row < 2; ++row) {
      const Eigen::VectorXd pr = pc.row(row).transpose(),
                            qr = qc.row(row).transpose();
      kpd[row] =
          force::DerivativeAlongX(grid_.centres, pr, 0, grid_.bins, sg_) /
          per_mm_;
      kqd[row] =
          force::DerivativeAlongX(grid_.centres, qr, 0, grid_.bins, sg_) /
          per_mm_;
    }
    // Both directions slide over the same geometry: their mean slope halves
    // the noise variance. Crosstalk then enters through the mean of the two
    // Q slopes (P_dir = P + c Q_dir).
    const Eigen::VectorXd kp_mean = 0.5 * (kpd[0] + kpd[1]);
    const Eigen::VectorXd kq_mean = 0.5 * (kqd[0] + kqd[1]);
    for (int row = 0; row < 2; ++row) {
      kp[row] = {grid_.centres, o_.average_directions ? kp_mean : kpd[row]};
      kq[row] = {grid_.centres, o_.average_directions ? kq_mean : kqd[row]};
    }
  }

  Eigen::MatrixXd Bin(const std::vector<int>& which,
                      const Eigen::VectorXd& channel) const {
    return BinProfile(
        record_, cycles_, which, channel, grid_.x_lo, grid_.bin, grid_.bins);
  }
  // The channel k comes from and its units per mm of height (S for P).
  const Eigen::VectorXd& profile() const { return profile_; }
  double per_mm() const { return per_mm_; }

 private:
  const force::ForceRecord& record_;
  const force::CycleSet& cycles_;
  const ProfileGrid& grid_;
  const DiagnoseOptions& o_;
  const PlateProfile* fixed_;
  bool from_depth_;
  const Eigen::VectorXd& profile_;
  force::SlopeOptions sg_;
  double per_mm_ = 0;
  int half_ = 0;
};

// Depth without a scan: the force side's mean profile (P/S, or the depth
// channel's height) below its highest point (the constant part is absorbed
// by mu).
PlateProfile ForceSideDepth(const Eigen::MatrixXd& p_prof,
                            const ProfileGrid& grid,
                            double spring) {
  Eigen::VectorXd f(grid.bins);
  double top = -INFINITY;
  for (Eigen::Index b = 0; b < grid.bins; ++b) {
    const double a = p_prof(0, b), c = p_prof(1, b);
    f[b] = std::isfinite(a) && std::isfinite(c) ? 0.5 * (a + c) / spring
           : std::isfinite(a)                   ? a / spring
                                                : c / spring;
    if (std::isfinite(f[b])) top = std::max(top, f[b]);
  }
  return {grid.centres, (top - f.array()).matrix()};
}

// The gross-slip samples of cycle c (every o.decimation-th) with their
// slopes, depth, speed and distance to the stroke end.
DiagCycle GatherCycle(const force::ForceRecord& record,
                      const force::Cycle& cy,
                      int c,
                      const CycleSlopes& slopes,
                      const PlateProfile& depth,
                      int decimation) {
  double cmin = INFINITY, cmax = -INFINITY;
  for (Eigen::Index i = cy.forward.begin; i < cy.reverse.end; ++i) {
    if (!std::isfinite(record.x_mm[i])) continue;
    cmin = std::min(cmin, record.x_mm[i]);
    cmax = std::max(cmax, record.x_mm[i]);
  }
  DiagCycle dc;
  dc.cycle = c;
  PlateProfile kp[2], kq[2];
  slopes(c, kp, kq);
  double f2 = 0, r2 = 0;
  for (const force::HalfCycle* h : {&cy.forward, &cy.reverse}) {
    const int row = h->direction > 0 ? 0 : 1;
    for (Eigen::Index i = h->slip_begin; i < h->slip_end; i += decimation) {
      const Eigen::Index a = std::max<Eigen::Index>(0, i - 2),
                         b = std::min(record.size() - 1, i + 2);
      Sample s;
      s.index = i;
      s.s = h->direction;
      s.x = record.x_mm[i];
      s.t = record.time_s[i];
      s.speed = std::abs((record.x_mm[b] - record.x_mm[a]) /
                         (record.time_s[b] - record.time_s[a]));
      s.p = record.normal_n[i];
      s.q = record.tangential_n[i];
      s.k = kp[row].At(s.x);
      s.q_slope = kq[row].At(s.x);
      s.depth = depth.At(s.x);
      s.to_end = h->direction > 0 ? cmax - s.x : s.x - cmin;
      if (!std::isfinite(s.x) || !std::isfinite(s.p) || !std::isfinite(s.q) ||
          !std::isfinite(s.k) || !std::isfinite(s.q_slope) ||
          !std::isfinite(s.depth) || !std::isfinite(s.speed)) {
        continue;
      }
      (h->direction > 0 ? f2 : r2) += s.q * s.q;
      dc.samples.push_back(s);
    }
  }
  dc.norm_forward = std::sqrt(std::max(f2, 1e-12));
  dc.norm_reverse = std::sqrt(std::max(r2, 1e-12));
  return dc;
}

// Crosstalk as the P channel shows it: over the bins where both
// directions slid (`p` and `q` binned per direction, BinProfile), P's
// difference between the directions regressed on Q's (through zero:
// P_measured = P + c Q, sample by sample), with the standard error of
// the slope from the bins' scatter about it.
DirectEvidence ChannelEvidence(const Eigen::MatrixXd& p,
                               const Eigen::MatrixXd& q) {
  std::vector<double> dp, dq;
  for (Eigen::Index b = 0; b < p.cols(); ++b) {
    const double d_p = p(0, b) - p(1, b), d_q = q(0, b) - q(1, b);
    if (!std::isfinite(d_p) || !std::isfinite(d_q)) continue;
    dp.push_back(d_p);
    dq.push_back(d_q);
  }
  DirectEvidence e;
  double pq = 0, qq = 0;
  for (size_t i = 0; i < dp.size(); ++i)
    pq += dp[i] * dq[i], qq += dq[i] * dq[i];
  if (dp.size() < 3 || !(qq > 0)) return e;
  const double c = pq / qq;
  double rr = 0;
  for (size_t i = 0; i < dp.size(); ++i)
    rr += (dp[i] - c * dq[i]) * (dp[i] - c * dq[i]);
  e.crosstalk_from_p = c;
  e.crosstalk_from_p_se =
      std::sqrt(rr / static_cast<double>(dp.size() - 1) / qq);
  return e;
}

}  // namespace

void ReversalDelay(const force::ForceRecord& record,
                   const force::CycleSet& cycles,
                   const std::vector<int>& chosen,
                   DirectEvidence* e) {
  if (chosen.empty()) return;
  const auto [lo, hi] = std::minmax_element(chosen.begin(), chosen.end());
  const force::TurnDelay t = force::MeasureTurnDelay(record, cycles, *lo, *hi);
  e->q_delay_s = t.delay_s;
  e->q_delay_se_s = t.delay_se_s;
  e->reversals = t.turns;
}

void Prepare(const force::ForceRecord& record,
             const force::CycleSet& cycles,
             const FrictionFitOptions& friction,
             const PlateProfile* depth,
             const PlateProfile* slope,
             const std::vector<int>& chosen,
             const DiagnoseOptions& o,
             Prepared* p) {
  p->grid = MakeProfileGrid(record, cycles, chosen, o.profile_step_mm);
  const CycleSlopes slopes(record, cycles, p->grid, friction, slope, o);
  p->depth = depth ? *depth
                   : ForceSideDepth(slopes.Bin(chosen, slopes.profile()),
                                    p->grid,
                                    slopes.per_mm());
  Data& data = p->data;
  data.record = &record;
  data.options = &o;
  data.x_lo = p->grid.x_lo;
  data.x_hi = p->grid.x_hi;
  data.dt = record.size() > 1
                ? (record.time_s[record.size() - 1] - record.time_s[0]) /
                      (record.size() - 1)
                : 1e-3;
  for (int c : chosen) {
    DiagCycle dc = GatherCycle(
        record, cycles.cycles[c], c, slopes, p->depth, o.decimation);
    if (static_cast<int>(dc.samples.size()) >= o.min_samples_per_cycle)
      data.cycles.push_back(std::move(dc));
  }
  if (static_cast<int>(data.cycles.size()) < 2 * o.folds) {
    throw FusionError("too few usable cycles for the diagnosis");
  }
  // Only where P is the spring's: a load held by a servo (a rig whose k
  // comes from a depth channel or the scan) holds the measured P, so
  // there P cannot show a crosstalk.
  if (slope == nullptr && !friction.k_from_depth) {
    data.evidence = ChannelEvidence(slopes.Bin(chosen, record.normal_n),
                                    slopes.Bin(chosen, record.tangential_n));
  }
  ReversalDelay(record, cycles, chosen, &data.evidence);
  // A shape along the track spans where the samples slide.
  for (const DiagCycle& dc : data.cycles) {
    for (const Sample& s : dc.samples) {
      p->slip_lo = std::min(p->slip_lo, s.x);
      p->slip_hi = std::max(p->slip_hi, s.x);
    }
  }
  for (DiagCycle& dc : data.cycles) {
    for (Sample& s : dc.samples)
      s.u = (s.x - p->slip_lo) / std::max(1e-9, p->slip_hi - p->slip_lo);
  }
}

}  // namespace wearscar::fusion::internal
