#include "wearscar/fusion/live.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

#include "wearscar/force/cycles.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/verdict.h"

namespace wearscar::fusion {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The k noise's variance estimated every this many reported cycles; the
// mean of this many latest estimates is used.
constexpr int kKNoiseEvery = 10;
constexpr std::size_t kKNoiseKept = 8;

// Samples held before the first cycles were found, at most: a record that
// shows no reversal in this many samples is no reciprocating test.
constexpr Eigen::Index kMaxSamplesBeforeCycles = Eigen::Index{4} << 20;

// Rows [from, end) of `head` and the pieces after them as one record, in
// one copy (the depth only where every row has one; the metadata the
// first rows').
template <typename Pieces>
force::ForceRecord JoinRows(const force::ForceRecord& head,
                            Eigen::Index from,
                            const Pieces& more) {
  force::ForceRecord out;
  const Eigen::Index kept = head.size() - from;
  Eigen::Index n = kept;
  bool depth = kept == 0 || head.has_depth();
  for (const auto& p : more) {
    n += p->size();
    depth = depth && p->has_depth();
  }
  if (n == 0) return out;
  out.metadata = kept > 0 ? head.metadata : more.front()->metadata;
  const auto join = [&](Eigen::VectorXd force::ForceRecord::*channel) {
    Eigen::VectorXd v(n);
    if (kept > 0) v.head(kept) = (head.*channel).tail(kept);
    Eigen::Index at = kept;
    for (const auto& p : more) {
      v.segment(at, p->size()) = (*p).*channel;
      at += p->size();
    }
    return v;
  };
  out.time_s = join(&force::ForceRecord::time_s);
  out.x_mm = join(&force::ForceRecord::x_mm);
  out.tangential_n = join(&force::ForceRecord::tangential_n);
  out.normal_n = join(&force::ForceRecord::normal_n);
  if (depth) out.depth_mm = join(&force::ForceRecord::depth_mm);
  return out;
}

double MeanOf(const std::deque<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) /
         static_cast<double>(v.size());
}

}  // namespace

bool LiveOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (window_cycles < 3 || window_cycles > 200)
    return fail("the live window must be 3 to 200 cycles");
  if (steady_cycles < 5) return fail("steady needs at least 5 cycles");
  if (!(steady_band > 0)) return fail("the steady band must be > 0");
  if (steady_hold_cycles < 1 || steady_hold_cycles > steady_cycles)
    return fail("steady's hold must be 1 to steady_cycles cycles");
  if (verdict_cycles < 10) return fail("the verdict needs at least 10 cycles");
  if (!(max_depth_mm > 0) && !std::isnan(max_depth_mm))
    return fail("the maximum depth must be > 0 mm");
  if (!(depth_bin_mm > 0)) return fail("the depth bins must be > 0 mm");
  if (map_bins < 4 || map_bins > 1000)
    return fail("the friction map needs 4 to 1000 bins");
  if (max_map_rows < 10) return fail("the friction map needs >= 10 rows");
  if (periodic_every < 1) return fail("periodic_every must be >= 1 cycle");
  if (decision_cycles < 20 || decision_cycles > 10000)
    return fail("the profile's decision needs 20 to 10000 cycles");
  return true;
}

LiveAnalysis::LiveAnalysis(FuseOptions options, LiveOptions live)
    : options_(std::move(options)), live_(live) {
  std::string why;
  if (!live_.IsValid(&why)) throw FusionError("live options: " + why);
}

// The rows that came since the last analysis joined to those it kept: one
// copy per analysis, however many pieces the rows came in.
void LiveAnalysis::Join() {
  if (pending_.empty() && cut_ == 0) return;
  buffer_ = JoinRows(buffer_, cut_, pending_);
  cut_ = 0;
  pending_.clear();
  pending_rows_ = 0;
}

Eigen::Index LiveAnalysis::samples_held() const {
  return buffer_.size() - cut_ + pending_rows_;
}

// The reversal rule of force::SegmentCycles (a minimum of x counts once x
// has come back from it by the hysteresis), on the n samples of x that
// follow those seen: true when a minimum, a cycle's end, was passed.
bool LiveAnalysis::CycleCompleted(const double* x_mm, Eigen::Index n) {
  const double h = options_.analysis.segment.hysteresis_fraction * stroke_mm_;
  bool completed = false;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = x_mm[i];
    if (!std::isfinite(x)) continue;
    if (!extreme_set_) {
      extreme_ = x;
      extreme_set_ = true;
      continue;
    }
    if (seeking_min_) {
      extreme_ = std::min(extreme_, x);
      if (x > extreme_ + h) {
        completed = true;
        seeking_min_ = false;
        extreme_ = x;
      }
    } else {
      extreme_ = std::max(extreme_, x);
      if (x < extreme_ - h) {
        seeking_min_ = true;
        extreme_ = x;
      }
    }
  }
  return completed;
}

std::vector<LiveCycle> LiveAnalysis::Add(force::ForceRecord given) {
  std::vector<LiveCycle> out;
  if (given.size() == 0) return out;
  // The rows held once, by the window's pieces and the history.
  auto piece = std::make_shared<const force::ForceRecord>(std::move(given));
  const force::ForceRecord& rows = *piece;
  history_.push_back(piece);
  pending_.push_back(std::move(piece));
  pending_rows_ += rows.size();
  if (stroke_mm_ <= 0) {
    // Before the first cycles, tried again once the rows held grew by a
    // quarter (or by 4096): the tries' cost stays a few times the rows',
    // and a look's rows are never left untried for the next look's.
    since_try_ += rows.size();
    if (since_try_ < std::min<Eigen::Index>(4096, samples_held() / 4))
      return out;
    since_try_ = 0;
    Join();
    Analyse(&out);
    if (stroke_mm_ <= 0 && buffer_.size() > kMaxSamplesBeforeCycles) {
      throw force::ForceError(fmt::format(
          "{}: no two complete cycles in the first {} samples; expected a "
          "reciprocating test (x going back and forth)",
          buffer_.metadata.source,
          buffer_.size()));
    }
    return out;
  }
  if (CycleCompleted(rows.x_mm.data(), rows.size())) {
    Join();
    Analyse(&out);
  }
  return out;
}

void LiveAnalysis::Analyse(std::vector<LiveCycle>* out) {
  AnalysisOptions o = options_.analysis;
  o.running_in_cycles = 0;  // decided over the whole test (UpdateRunningIn)
  o.friction.narrow_ensemble_to_record = false;  // the template is kept
  ForceAnalysis a;
  std::vector<MuFit> fitted;          // mu-hat per cycle of the window
  std::vector<force::CycleCof> cof;   // the classic COFs of the new cycles
  std::vector<CycleSamples> samples;  // per cycle, those fitted
  std::vector<char> fresh;            // per cycle, not reported before
  force::ForceRecord notched;         // the window without its lines
  try {
    // SegmentForce's segmentation and gross slip over the window; the
    // COFs and fits of the new cycles alone.
    a.cycles = SegmentWindow(o);
    if (a.cycles.cycles.empty()) return;
    fresh = NewCycles(a.cycles);
    period_s_ = WindowPeriod(a.cycles);
    // Lines the drive does not make, sought before the new cycles are
    // fitted and removed from them (WithoutLines).
    SeekPeriodicLines(static_cast<int>(a.cycles.cycles.size()));
    const force::ForceRecord& window = WithoutLines(&notched);
    DecideSlopeBefore(fresh, &o.friction);
    cof = NewCyclesCof(window, a.cycles, fresh);
    o.friction.fit_cycle = fresh;
    o.friction.keep_samples = true;
    o.friction.split_noise = false;  // SplitNoise, against earlier windows
    const int n = static_cast<int>(reported_.size());
    const bool estimate =
        k_noise_estimates_.empty() || n - k_noise_at_ >= kKNoiseEvery;
    if (!estimate) o.friction.k_noise_variance = MeanOf(k_noise_estimates_);
    FrictionFits fits =
        FitFriction(window, a.cycles, SlopeSource::kForce, o.friction);
    if (estimate && std::isfinite(fits.k_ensemble_noise_rms)) {
      k_noise_estimates_.push_back(fits.k_ensemble_noise_rms *
                                   fits.k_ensemble_noise_rms);
      if (k_noise_estimates_.size() > kKNoiseKept)
        k_noise_estimates_.pop_front();
      k_noise_at_ = n;
    }
    fitted = std::move(fits.cycles);
    samples = std::move(fits.samples);
  } catch (const force::ForceError&) {
    return;  // too few cycles yet
  } catch (const FusionError&) {
    return;
  }
  const auto& cycles = a.cycles.cycles;
  const bool first = stroke_mm_ <= 0;
  stroke_mm_ = a.cycles.stroke_mm;
  int shown = -1;  // the loop shown: the latest new cycle's that converged
  for (size_t i = 0; i < cycles.size(); ++i) {
    if (!fresh[i]) continue;
    MuFit& f = fitted[i];
    if (f.converged) {
      SplitNoise(samples[i], o.friction, &f);
      shown = static_cast<int>(i);
      loop_.cycle = static_cast<int>(reported_.size()) + 1;
    }
    Report(notched.size() > 0 ? notched : buffer_,
           a,
           f,
           cof[i],
           static_cast<int>(i),
           out);
    last_end_s_ = buffer_.time_s[cycles[i].reverse.end - 1];
  }
  if (shown >= 0) ShowLoop(samples[shown], fitted[shown].mu_hat);
  KeepLatestCycles(a);
  KeepHistory();
  if (first) {
    // The reversal detector starts from the samples kept.
    seeking_min_ = true;
    extreme_set_ = false;
    CycleCompleted(buffer_.x_mm.data() + cut_, buffer_.size() - cut_);
  }
}

// Where k comes from, decided before the cycles that reach the first
// verdict are fitted, and taken from a depth channel when a later decision
// found it gives the slope P does not.
void LiveAnalysis::DecideSlopeBefore(const std::vector<char>& fresh,
                                     FrictionFitOptions* friction) {
  const int reach = static_cast<int>(reported_.size()) +
                    static_cast<int>(std::count(fresh.begin(), fresh.end(), 1));
  if ((decided_at_ < 0 && reach >= std::min(20, live_.verdict_cycles)) ||
      (depth_decided_ && !options_.analysis.friction.k_from_depth)) {
    DecideSlope(true);
    friction->k_from_depth = options_.analysis.friction.k_from_depth;
    friction->depth_sign = options_.analysis.friction.depth_sign;
  }
}

// The window's cycles with their gross slip: those of the last analysis
// and those completed since (force::ExtendCycles), or the whole window's.
force::CycleSet LiveAnalysis::SegmentWindow(const AnalysisOptions& o) const {
  force::CycleSet set =
      force::ExtendCycles(buffer_, segmented_, o.segment, o.slip);
  if (!set.cycles.empty()) return set;
  set = force::SegmentCycles(buffer_.x_mm, o.segment, buffer_.metadata.source);
  force::FindGrossSlip(buffer_, &set, o.slip);
  return set;
}

// The loop of a new cycle against the wear-scar model with its mu-hat.
void LiveAnalysis::ShowLoop(const CycleSamples& s, double mu_hat) {
  loop_.x_mm.clear();
  loop_.q_n.clear();
  loop_.q_model_n.clear();
  loop_.direction.clear();
  for (const SlipSamples* h : {&s.forward, &s.reverse}) {
    for (Eigen::Index i = 0; i < h->q_n.size(); ++i) {
      loop_.x_mm.push_back(h->x_mm[i]);
      loop_.q_n.push_back(h->q_n[i]);
      loop_.q_model_n.push_back(
          WearScarTangentialForce(h->p_n[i], h->k[i], mu_hat, h->direction));
      loop_.direction.push_back(h->direction > 0 ? 1 : -1);
    }
  }
}

double LiveAnalysis::WindowPeriod(const force::CycleSet& set) const {
  const auto& cycles = set.cycles;
  return (buffer_.time_s[cycles.back().reverse.end - 1] -
          buffer_.time_s[cycles.front().forward.begin]) /
         static_cast<double>(cycles.size());
}

// Per cycle of the window: whether it ends after the last one reported.
std::vector<char> LiveAnalysis::NewCycles(const force::CycleSet& set) const {
  const auto& cycles = set.cycles;
  const double period = WindowPeriod(set);
  std::vector<char> fresh(cycles.size(), 0);
  for (size_t c = 0; c < cycles.size(); ++c) {
    fresh[c] =
        buffer_.time_s[cycles[c].reverse.end - 1] > last_end_s_ + 0.25 * period;
  }
  return fresh;
}

// The classic COFs of the new cycles (default values for the others).
std::vector<force::CycleCof> LiveAnalysis::NewCyclesCof(
    const force::ForceRecord& window,
    const force::CycleSet& set,
    const std::vector<char>& fresh) const {
  force::CycleSet only = set;
  only.cycles.clear();
  for (size_t c = 0; c < set.cycles.size(); ++c) {
    if (fresh[c]) only.cycles.push_back(set.cycles[c]);
  }
  const std::vector<force::CycleCof> some =
      force::ComputeClassicCof(window, only);
  std::vector<force::CycleCof> all(set.cycles.size());
  for (size_t c = 0, k = 0; c < set.cycles.size(); ++c) {
    if (fresh[c]) all[c] = some[k++];
  }
  return all;
}

// J's noise split (SplitRepeatable's) of a new cycle: its misfit along the
// stroke against the mean misfit at the same x of the template, the
// template_cycles reported cycles that end an ensemble's width before it
// (their k shares no P sample with its), as they were when reported. NaN
// before there is a template.
void LiveAnalysis::SplitNoise(const CycleSamples& s,
                              const FrictionFitOptions& friction,
                              MuFit* f) {
  const double bin = friction.repeatability.bin_mm;
  if (misfit_bins_ == 0) {
    // The stroke as the first cycle covers it, a fifth of it beyond either
    // end (the track's ends move little).
    const double lo = s.forward.x_mm.minCoeff(), hi = s.forward.x_mm.maxCoeff();
    misfit_x0_mm_ = lo - 0.2 * (hi - lo);
    misfit_bins_ = std::clamp(
        static_cast<int>(std::ceil(1.4 * (hi - lo) / bin)), 1, 1 << 20);
  }
  MisfitRow row;
  row.cycle = static_cast<int>(reported_.size()) + 1;
  std::array<double, 2> total{0, 0}, qq{0, 0};
  for (int k = 0; k < 2; ++k) {
    const SlipSamples& h = k == 0 ? s.forward : s.reverse;
    row.sum[k].assign(misfit_bins_, 0.0);
    row.count[k].assign(misfit_bins_, 0);
    for (Eigen::Index i = 0; i < h.q_n.size(); ++i) {
      const double r = h.q_n[i] - WearScarTangentialForce(
                                      h.p_n[i], h.k[i], f->mu_hat, h.direction);
      if (!std::isfinite(r)) continue;
      total[k] += r * r;
      qq[k] += h.q_n[i] * h.q_n[i];
      const double b = std::floor((h.x_mm[i] - misfit_x0_mm_) / bin);
      if (!(b >= 0 && b < misfit_bins_)) continue;
      row.sum[k][static_cast<size_t>(b)] += r;
      ++row.count[k][static_cast<size_t>(b)];
    }
  }
  const int sep = friction.k_estimate == KEstimate::kEnsemble
                      ? std::max(1, friction.ensemble.cycles)
                      : 1;
  const int t = friction.repeatability.template_cycles;
  SlideTemplate(row.cycle - sep - t + 1, row.cycle - sep);
  std::array<RepeatSplit, 2> split;
  for (int k = 0; k < 2; ++k) {
    const std::vector<double>& sum = template_.sum[k];
    const std::vector<int>& count = template_.count[k];
    split[k].total = total[k];
    split[k].repeat = template_.rows > 0 ? 0.0 : kNaN;
    for (int b = 0; b < misfit_bins_; ++b) {
      if (row.count[k][b] > 0 && count[b] > 0)
        split[k].repeat += row.sum[k][b] * (sum[b] / count[b]);
    }
  }
  ApplyRepeatSplit(split, qq, f);
  if (template_.rows == 0) f->cost_floor = f->cost_excess = kNaN;
  misfits_.push_back(std::move(row));
  while (static_cast<int>(misfits_.size()) > sep + t) misfits_.pop_front();
}

// The template's sums moved to the reported cycles [first, last]: rows
// enter at its end and leave at its start (both only move on).
void LiveAnalysis::SlideTemplate(int first, int last) {
  for (int k = 0; k < 2; ++k) {
    template_.sum[k].resize(misfit_bins_, 0.0);
    template_.count[k].resize(misfit_bins_, 0);
  }
  auto move = [&](int cycle, int sign) {
    for (const MisfitRow& m : misfits_) {
      if (m.cycle != cycle) continue;
      for (int k = 0; k < 2; ++k) {
        for (int b = 0; b < misfit_bins_; ++b) {
          template_.sum[k][b] += sign * m.sum[k][b];
          template_.count[k][b] += sign * m.count[k][b];
        }
      }
      template_.rows += sign;
    }
  };
  while (template_.last < last) move(++template_.last, +1);
  while (template_.first < first) {
    if (template_.first <= template_.last) move(template_.first, -1);
    ++template_.first;
  }
}

// Drops the samples before the window's cycles: the next analysis holds
// window_cycles - 1 complete cycles and the one completing. The cut falls
// in the middle of a reverse half, so that the first cycle's minimum is
// found again.
void LiveAnalysis::KeepLatestCycles(const ForceAnalysis& a) {
  segmented_ = a.cycles;
  auto& cycles = segmented_.cycles;
  const int n = static_cast<int>(cycles.size());
  const int keep_from = n - (live_.window_cycles - 1);
  if (keep_from < 1) return;
  const force::HalfCycle& r = cycles[keep_from - 1].reverse;
  const Eigen::Index cut = r.begin + (r.end - r.begin) / 2;
  if (cut <= 0) return;
  cut_ = cut;  // dropped when the next rows are joined
  // The cycles kept, where the rows now are.
  cycles.erase(cycles.begin(), cycles.begin() + keep_from);
  for (force::Cycle& c : cycles) {
    c.index -= keep_from;
    for (force::HalfCycle* h : {&c.forward, &c.reverse}) {
      h->begin -= cut;
      h->end -= cut;
      h->slip_begin -= cut;
      h->slip_end -= cut;
    }
  }
  segmented_.x_range_of = nullptr;
}

force::ForceRecord LiveAnalysis::LatestRows() const {
  return JoinRows(force::ForceRecord{}, 0, history_);
}

// history_ back to about the latest decision_cycles cycles (and 10 more):
// the pieces that ended before them dropped.
void LiveAnalysis::KeepHistory() {
  if (history_.empty() || !(period_s_ > 0)) return;
  const force::ForceRecord& last = *history_.back();
  const double keep_from =
      last.time_s[last.size() - 1] - (live_.decision_cycles + 10) * period_s_;
  while (history_.size() > 1 && history_.front()->size() > 0 &&
         history_.front()->time_s[history_.front()->size() - 1] < keep_from)
    history_.pop_front();
}

void LiveAnalysis::Report(const force::ForceRecord& window,
                          const ForceAnalysis& a,
                          const MuFit& f,
                          const force::CycleCof& cof,
                          int i,
                          std::vector<LiveCycle>* out) {
  const force::Cycle& cycle = a.cycles.cycles[i];
  LiveCycle c;
  c.cycle = static_cast<int>(reported_.size()) + 1;
  c.end_time_s = window.time_s[cycle.reverse.end - 1];
  c.mu_hat = f.converged ? f.mu_hat : kNaN;
  const double half = 1.959964 * f.standard_error;
  c.mu_low = c.mu_hat - half;
  c.mu_high = c.mu_hat + half;
  c.mu_mean = cof.mu_mean;
  c.mu_energy = cof.mu_energy_g;
  c.cost = f.converged ? f.cost : kNaN;
  c.cost_floor = f.cost_floor;
  c.cost_excess = f.cost_excess;
  // P/S along the stroke, both directions pooled, in bins: its peak to
  // valley is the track's depth under load as the spring sees it.
  const double bin = live_.depth_bin_mm;
  const double x0 = a.cycles.x_min_mm;
  const int bins = std::max(
      1, static_cast<int>(std::ceil((a.cycles.x_max_mm - x0) / bin)) + 1);
  std::vector<double> sum(bins, 0.0);
  std::vector<int> count(bins, 0);
  // With k from a depth channel, the depth along the stroke instead.
  const bool depth =
      options_.analysis.friction.k_from_depth && window.has_depth();
  const double spring = options_.analysis.friction.slope.spring_n_per_mm;
  const Eigen::VectorXd& along = depth ? window.depth_mm : window.normal_n;
  for (const force::HalfCycle* h : {&cycle.forward, &cycle.reverse}) {
    for (Eigen::Index s = h->slip_begin; s < h->slip_end; ++s) {
      const double x = window.x_mm[s], p = along[s];
      if (!std::isfinite(x) || !std::isfinite(p)) continue;
      const int b = std::clamp(static_cast<int>((x - x0) / bin), 0, bins - 1);
      sum[b] += p;
      ++count[b];
    }
  }
  double lo = INFINITY, hi = -INFINITY;
  for (int b = 0; b < bins; ++b) {
    if (count[b] < 3) continue;
    lo = std::min(lo, sum[b] / count[b]);
    hi = std::max(hi, sum[b] / count[b]);
  }
  c.depth_mm = hi > lo ? (hi - lo) / (depth ? 1.0 : spring) : kNaN;
  reported_.push_back(c);
  mu_mean_series_.push_back(c.mu_mean);
  mu_hat_series_.push_back(c.mu_hat);
  recent_fits_.push_back(f);
  recent_energy_.push_back(c.mu_energy);
  recent_mean_.push_back(c.mu_mean);
  while (static_cast<int>(recent_fits_.size()) > live_.verdict_cycles) {
    recent_fits_.pop_front();
    recent_energy_.pop_front();
    recent_mean_.pop_front();
  }
  AddMapRow(window, cycle, c.cycle);
  UpdateRunningIn();
  reported_.back().running_in = !running_in_ended_ || c.cycle <= running_in_;
  UpdateSteady();
  UpdateVerdict();
  UpdateDepth(reported_.back());
  out->push_back(reported_.back());
}

namespace {

// Two rows of a map merged: their mean where both have a value.
std::vector<double> MergedRow(const std::vector<double>& u,
                              const std::vector<double>& v) {
  std::vector<double> m(u.size());
  for (size_t b = 0; b < u.size(); ++b)
    m[b] = std::isnan(u[b])   ? v[b]
           : std::isnan(v[b]) ? u[b]
                              : 0.5 * (u[b] + v[b]);
  return m;
}

}  // namespace

void LiveAnalysis::AddMapRow(const force::ForceRecord& window,
                             const force::Cycle& cycle,
                             int number) {
  if (map_.x_mm.empty()) {
    // The stroke as the first cycles found it, 5% beyond either end.
    const double lo = -0.55 * stroke_mm_, width = 1.1 * stroke_mm_;
    const double mid = 0.5 * (window.x_mm.minCoeff() + window.x_mm.maxCoeff());
    for (int b = 0; b < live_.map_bins; ++b)
      map_.x_mm.push_back(mid + lo + (b + 0.5) * width / live_.map_bins);
  }
  const int bins = live_.map_bins;
  const double width = map_.x_mm[1] - map_.x_mm[0];
  const double x0 = map_.x_mm[0] - 0.5 * width;
  std::vector<double> mu(bins, 0.0), p_sum(bins, 0.0);
  std::vector<int> count(bins, 0);
  double p_all = 0;
  int n_all = 0;
  for (const force::HalfCycle* h : {&cycle.forward, &cycle.reverse}) {
    for (Eigen::Index s = h->slip_begin; s < h->slip_end; ++s) {
      const double x = window.x_mm[s], q = window.tangential_n[s],
                   p = window.normal_n[s];
      const int b = static_cast<int>(std::floor((x - x0) / width));
      if (b < 0 || b >= bins || !std::isfinite(q) || !(p > 0)) continue;
      mu[b] += std::abs(q) / p;
      p_sum[b] += p;
      ++count[b];
      p_all += p;
      ++n_all;
    }
  }
  // The track's shape as the spring sees it: P/S relative to the cycle's
  // mean, mm (negative where the ball sits lower, in the deeper track).
  const double spring = options_.analysis.friction.slope.spring_n_per_mm;
  std::vector<double> row(bins, kNaN), track(bins, kNaN);
  for (int b = 0; b < bins; ++b) {
    if (count[b] == 0) continue;
    row[b] = mu[b] / count[b];
    track[b] = (p_sum[b] / count[b] - p_all / n_all) / spring;
  }
  map_.rows.push_back(std::move(row));
  map_.track_rows.push_back(std::move(track));
  map_.first_cycle.push_back(number);
  map_.last_cycle.push_back(number);
  if (static_cast<int>(map_.rows.size()) < live_.max_map_rows) return;
  // Merge neighbouring rows in pairs: the maps keep the whole test at
  // half the resolution in cycles.
  LiveMap merged;
  merged.x_mm = map_.x_mm;
  for (size_t r = 0; r + 1 < map_.rows.size(); r += 2) {
    merged.rows.push_back(MergedRow(map_.rows[r], map_.rows[r + 1]));
    merged.track_rows.push_back(
        MergedRow(map_.track_rows[r], map_.track_rows[r + 1]));
    merged.first_cycle.push_back(map_.first_cycle[r]);
    merged.last_cycle.push_back(map_.last_cycle[r + 1]);
  }
  if (map_.rows.size() % 2 == 1) {
    merged.rows.push_back(map_.rows.back());
    merged.track_rows.push_back(map_.track_rows.back());
    merged.first_cycle.push_back(map_.first_cycle.back());
    merged.last_cycle.push_back(map_.last_cycle.back());
  }
  map_ = std::move(merged);
}

void LiveAnalysis::Restart(const std::string& why, double time_s) {
  LiveEvent e;
  e.kind = "restart";
  e.cycle = 0;
  e.time_s = time_s;
  e.message = why;
  const LiveOptions live = live_;
  FuseOptions options = std::move(options_);
  *this = LiveAnalysis(std::move(options), live);
  events_.push_back(std::move(e));
}

}  // namespace wearscar::fusion
