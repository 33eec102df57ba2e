#include "wearscar/force/cycles.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

namespace wearscar::force {
namespace {

// Two quantiles of the finite values (0 <= lo <= hi <= 1): the order
// statistics of ranks lo (n - 1) and hi (n - 1). A series longer than
// `max_values` is read with a stride (every 2nd, 3rd, ... sample; hundreds
// of cycles of a periodic x still cover every phase; the paper's 1.2 M
// samples are read whole). NaN when nothing is finite.
std::pair<double, double> Quantiles(const Eigen::Ref<const Eigen::VectorXd>& v,
                                    double lo,
                                    double hi,
                                    Eigen::Index max_values = 1 << 21) {
  // The values taken: every stride-th finite one (all up to max_values).
  const Eigen::Index stride =
      std::max<Eigen::Index>(1, (v.size() + max_values - 1) / max_values);
  // Their order statistics of ranks q (n - 1), found without copying them
  // all: a sample of every 64th brackets each rank, a pass counts the
  // values below the bracket and keeps those in it, and the rank is
  // selected among those (the same value as a selection over all; a
  // bracket that misses falls back to that).
  std::vector<double> sample;
  sample.reserve(static_cast<size_t>(v.size() / (64 * stride) + 1));
  for (Eigen::Index i = 0; i < v.size(); i += 64 * stride) {
    if (std::isfinite(v[i])) sample.push_back(v[i]);
  }
  std::sort(sample.begin(), sample.end());
  const auto bracket = [&](double q) -> std::pair<double, double> {
    if (sample.size() < 64) return {-INFINITY, INFINITY};
    // Six standard errors of the sample's quantile, and ten values.
    const double m = static_cast<double>(sample.size());
    const double margin = 6 * std::sqrt(q * (1 - q) / m) + 10 / m;
    const auto at = [&](double f) {
      const double r = std::clamp(f, 0.0, 1.0) * (m - 1);
      return sample[static_cast<size_t>(r)];
    };
    return {q - margin <= 0 ? -INFINITY : at(q - margin),
            q + margin >= 1 ? INFINITY : at(q + margin)};
  };
  const auto [lo_a, lo_b] = bracket(lo);
  const auto [hi_a, hi_b] = bracket(hi);
  long n = 0, below_lo = 0, below_hi = 0;
  std::vector<double> in_lo, in_hi;
  for (Eigen::Index i = 0; i < v.size(); i += stride) {
    const double x = v[i];
    if (!std::isfinite(x)) continue;
    ++n;
    if (x < lo_a) {
      ++below_lo;
    } else if (x <= lo_b) {
      in_lo.push_back(x);
    }
    if (x < hi_a) {
      ++below_hi;
    } else if (x <= hi_b) {
      in_hi.push_back(x);
    }
  }
  if (n == 0) return {std::nan(""), std::nan("")};
  const auto rank = [&](double q) {
    return static_cast<long>(q * static_cast<double>(n - 1));
  };
  const auto select = [](std::vector<double>* values, long k) {
    std::nth_element(values->begin(), values->begin() + k, values->end());
    return (*values)[static_cast<size_t>(k)];
  };
  const long a = rank(lo), b = rank(hi);
  const bool lo_held =
      a >= below_lo && a < below_lo + static_cast<long>(in_lo.size());
  const bool hi_held =
      b >= below_hi && b < below_hi + static_cast<long>(in_hi.size());
  if (lo_held && hi_held)
    return {select(&in_lo, a - below_lo), select(&in_hi, b - below_hi)};
  std::vector<double> finite;
  finite.reserve(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < v.size(); i += stride) {
    if (std::isfinite(v[i])) finite.push_back(v[i]);
  }
  const double low = select(&finite, a);
  std::nth_element(finite.begin() + a, finite.begin() + b, finite.end());
  return {low, finite[static_cast<size_t>(b)]};
}

// Least-squares slope of q over x on [b, e); NaN when x does not spread.
double LocalSlope(const Eigen::VectorXd& x,
                  const Eigen::VectorXd& q,
                  Eigen::Index b,
                  Eigen::Index e) {
  double sx = 0, sq = 0, n = 0;
  for (Eigen::Index i = b; i < e; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(q[i])) continue;
    sx += x[i];
    sq += q[i];
    ++n;
  }
  if (n < 2) return std::nan("");
  const double mx = sx / n, mq = sq / n;
  double sxx = 0, sxq = 0;
  for (Eigen::Index i = b; i < e; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(q[i])) continue;
    sxx += (x[i] - mx) * (x[i] - mx);
    sxq += (x[i] - mx) * (q[i] - mq);
  }
  return sxx > 0 ? sxq / sxx : std::nan("");
}

void CentralFallback(const Eigen::VectorXd& x,
                     double fraction,
                     HalfCycle* half) {
  const double x0 = x[half->begin];
  const double x1 = x[half->end - 1];
  const double lo = std::min(x0, x1), hi = std::max(x0, x1);
  const double margin = 0.5 * (1.0 - fraction) * (hi - lo);
  half->slip_begin = half->end;
  half->slip_end = half->begin;
  for (Eigen::Index i = half->begin; i < half->end; ++i) {
    if (x[i] >= lo + margin && x[i] <= hi - margin) {
      half->slip_begin = std::min(half->slip_begin, i);
      half->slip_end = std::max(half->slip_end, i + 1);
    }
  }
  if (half->slip_end < half->slip_begin) half->slip_end = half->slip_begin;
  half->slip_fallback = true;
}

// Q's sliding level in the direction of motion: its median over the
// central half of the stroke (NaN when no sample is finite there).
double SlidingLevel(const Eigen::VectorXd& x,
                    const Eigen::VectorXd& q,
                    const HalfCycle& half,
                    double stroke) {
  const Eigen::Index b = half.begin, e = half.end;
  const double s = half.direction;
  std::vector<double> central;
  for (Eigen::Index i = b; i < e; ++i) {
    const double t = std::abs(x[i] - x[b]) / stroke;
    if (t > 0.25 && t < 0.75 && std::isfinite(q[i]))
      central.push_back(s * q[i]);
  }
  if (central.empty()) return std::nan("");
  std::nth_element(
      central.begin(), central.begin() + central.size() / 2, central.end());
  return central[central.size() / 2];
}

// The stick's stiffness dQ/dx after the reversal, and the sample from which
// slip is sought.
struct Stick {
  double k_stick;
  Eigen::Index search_from;
};

Stick StickAfterReversal(const Eigen::VectorXd& x,
                         const Eigen::VectorXd& q,
                         const HalfCycle& half,
                         double q_rev,
                         double swing,
                         const GrossSlipOptions& o) {
  const Eigen::Index b = half.begin, e = half.end;
  const double s = half.direction;
  // The first samples from which Q has climbed `lo` and then `hi` of the
  // swing after the reversal (-1 when it does not).
  const auto climb = [&](double lo, double hi) {
    std::pair<Eigen::Index, Eigen::Index> run{-1, -1};
    for (Eigen::Index i = b; i < e; ++i) {
      const double frac = (s * q[i] - q_rev) / swing;
      if (run.first < 0 && frac >= lo) run.first = i;
      if (run.first >= 0 && frac >= hi) {
        run.second = i;
        break;
      }
    }
    return run;
  };
  // Stick stiffness: slope of Q over x while Q climbs from 20% to 80% of the
  // swing (the first contiguous run after the reversal).
  auto [i20, i80] = climb(0.2, 0.8);
  if (i20 < 0 || i80 < 0 || i80 - i20 < 2) {
    // Too few samples in the transition: estimate with a short window.
    i20 = b;
    i80 = std::min(e - 1, b + o.stick_samples);
  }
  Stick stick{LocalSlope(x, q, i20, i80 + 1), i80};
  // On a worn track whose wall near the stroke end is steep (k near mu or
  // above) the sliding level moves with the slope after the stick, so Q's
  // climb to the central median runs on into gross slip: the 20-80% slope
  // then understates the stick's, and slip would be found only where the
  // track flattens (1.5 mm on). The first part of the climb (5-30%) is
  // stick on any track; when it is clearly stiffer, the stick is that part.
  const auto [i05, i30] = climb(0.05, 0.3);
  if (i05 >= 0 && i30 - i05 >= 2) {
    const double k_early = LocalSlope(x, q, i05, i30 + 1);
    if (std::isfinite(k_early) &&
        k_early > o.early_stick_ratio * stick.k_stick) {
      stick.k_stick = k_early;
      stick.search_from = std::min(stick.search_from, i30);
    }
  }
  return stick;
}

void FindHalfSlip(const Eigen::VectorXd& x,
                  const Eigen::VectorXd& q,
                  const GrossSlipOptions& o,
                  HalfCycle* half) {
  const Eigen::Index b = half->begin, e = half->end;
  const Eigen::Index n = e - b;
  const double s = half->direction;
  const double stroke = std::abs(x[e - 1] - x[b]);
  if (n < 4 * o.slope_window || !(stroke > 0)) {
    CentralFallback(x, o.fallback_central_fraction, half);
    return;
  }
  // Q at the reversal and the sliding level (median over the central half of
  // the stroke), in the direction of motion.
  const double q_rev = s * q.segment(b, std::min<Eigen::Index>(3, n)).mean();
  const double swing = SlidingLevel(x, q, *half, stroke) - q_rev;
  if (!(swing > 0) || !std::isfinite(q_rev)) {
    CentralFallback(x, o.fallback_central_fraction, half);
    return;
  }
  const auto [k_stick, search_from] =
      StickAfterReversal(x, q, *half, q_rev, swing, o);
  if (!std::isfinite(k_stick) || k_stick <= 0) {
    CentralFallback(x, o.fallback_central_fraction, half);
    return;
  }
  const double threshold = o.stiffness_fraction * k_stick;
  const Eigen::Index h = o.slope_window / 2;
  Eigen::Index start = -1;
  for (Eigen::Index i = std::max(search_from, b + h); i + h < e; ++i) {
    // dQ/dx is positive in stick whichever way x moves.
    const double k_local = LocalSlope(x, q, i - h, i + h + 1);
    if (std::isfinite(k_local) && k_local < threshold) {
      start = i;
      break;
    }
  }
  const Eigen::Index stop = e - o.end_margin_samples;
  if (start < 0 || stop <= start ||
      std::abs(x[stop - 1] - x[start]) < o.min_window_fraction * stroke) {
    CentralFallback(x, o.fallback_central_fraction, half);
    return;
  }
  half->slip_begin = start;
  half->slip_end = stop;
  half->slip_fallback = false;
}

}  // namespace

bool SegmentOptions::IsValid(std::string* why) const {
  if (!(hysteresis_fraction > 0 && hysteresis_fraction < 0.5)) {
    if (why) *why = "hysteresis_fraction must be in (0, 0.5)";
    return false;
  }
  if (min_cycles < 1) {
    if (why) *why = "min_cycles must be >= 1";
    return false;
  }
  return true;
}

bool GrossSlipOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(stiffness_fraction > 0 && stiffness_fraction < 1)) {
    return fail("stiffness_fraction must be in (0, 1)");
  }
  if (slope_window < 3) return fail("slope_window must be >= 3");
  if (stick_samples < 2) return fail("stick_samples must be >= 2");
  if (!(fallback_central_fraction > 0 && fallback_central_fraction <= 1)) {
    return fail("fallback_central_fraction must be in (0, 1]");
  }
  if (!(min_window_fraction >= 0 && min_window_fraction < 1)) {
    return fail("min_window_fraction must be in [0, 1)");
  }
  if (end_margin_samples < 0) return fail("end_margin_samples must be >= 0");
  if (!(early_stick_ratio >= 1)) return fail("early_stick_ratio must be >= 1");
  return true;
}

namespace {

// A reversal: its index and kind (+1 maximum, -1 minimum).
struct Reversal {
  Eigen::Index index;
  int kind;
};

// The reversals of x: an extreme counts only once x has come back from it
// by h; the first extreme seen before any direction is known is the start
// of the data, not a reversal.
std::vector<Reversal> FindReversals(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm, double h) {
  std::vector<Reversal> reversals;
  int state = 0;  // +1 rising, -1 falling, 0 unknown
  double hi = -INFINITY, lo = INFINITY;
  Eigen::Index hi_i = -1, lo_i = -1;
  for (Eigen::Index i = 0; i < x_mm.size(); ++i) {
    const double v = x_mm[i];
    if (!std::isfinite(v)) continue;
    if (v > hi) {
      hi = v;
      hi_i = i;
    }
    if (v < lo) {
      lo = v;
      lo_i = i;
    }
    if (state >= 0 && v < hi - h) {
      if (state == 1) reversals.push_back({hi_i, +1});
      state = -1;
      lo = v;
      lo_i = i;
    } else if (state <= 0 && v > lo + h) {
      if (state == -1) reversals.push_back({lo_i, -1});
      state = 1;
      hi = v;
      hi_i = i;
    }
  }
  return reversals;
}

// Complete cycles, minimum to minimum, and what was dropped about them.
void CyclesFromReversals(const std::vector<Reversal>& reversals,
                         Eigen::Index n,
                         CycleSet* set) {
  size_t first = 0;
  while (first < reversals.size() && reversals[first].kind != -1) ++first;
  for (size_t j = first; j + 2 < reversals.size(); j += 2) {
    Cycle c;
    c.index = static_cast<int>(set->cycles.size());
    c.forward = {reversals[j].index, reversals[j + 1].index, +1};
    c.reverse = {reversals[j + 1].index, reversals[j + 2].index, -1};
    set->cycles.push_back(c);
  }
  if (set->cycles.empty()) return;
  set->leading_samples_dropped = set->cycles.front().forward.begin;
  set->trailing_samples_dropped = n - set->cycles.back().reverse.end;
  if (set->leading_samples_dropped > 0) {
    set->notes.push_back(
        fmt::format("dropped {} samples before the first complete cycle",
                    set->leading_samples_dropped));
  }
  if (set->trailing_samples_dropped > 0) {
    set->notes.push_back(
        fmt::format("dropped {} samples after the last complete cycle",
                    set->trailing_samples_dropped));
  }
}

}  // namespace

CycleSet SegmentCycles(const Eigen::Ref<const Eigen::VectorXd>& x_mm,
                       const SegmentOptions& options,
                       const std::string& source) {
  std::string why;
  if (!options.IsValid(&why))
    throw ForceError("invalid segment options: " + why);
  CycleSet set;
  const Eigen::Index n = x_mm.size();
  const auto [p01, p99] = Quantiles(x_mm, 0.01, 0.99);
  set.stroke_mm = p99 - p01;
  if (!(set.stroke_mm > 0)) {
    throw ForceError(fmt::format(
        "{}: the displacement does not move (robust stroke {} mm); expected a "
        "reciprocating x",
        source,
        set.stroke_mm));
  }
  CyclesFromReversals(
      FindReversals(x_mm, options.hysteresis_fraction * set.stroke_mm),
      n,
      &set);
  if (static_cast<int>(set.cycles.size()) < options.min_cycles) {
    throw ForceError(fmt::format(
        "{}: found {} complete cycle(s) in {} samples (stroke {:.3g} mm); "
        "expected at least {}",
        source,
        set.cycles.size(),
        n,
        set.stroke_mm,
        options.min_cycles));
  }
  std::tie(set.x_min_mm, set.x_max_mm) = CyclesXRange(x_mm, set);
  set.x_range_of = x_mm.data();
  return set;
}

std::pair<double, double> CyclesXRange(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm, const CycleSet& cycles) {
  if (cycles.x_range_of != nullptr && cycles.x_range_of == x_mm.data())
    return {cycles.x_min_mm, cycles.x_max_mm};
  // Four running minima and maxima (the comparisons leave NaN out), so
  // that each waits on the one four samples back; an infinite x, rare,
  // is left out by a second pass.
  double lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
  double hi[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  const double* x = x_mm.data();
  for (const Cycle& c : cycles.cycles) {
    const Eigen::Index e = std::min(c.reverse.end, x_mm.size());
    Eigen::Index i = c.forward.begin;
    for (; i + 3 < e; i += 4) {
      for (int j = 0; j < 4; ++j) {
        lo[j] = x[i + j] < lo[j] ? x[i + j] : lo[j];
        hi[j] = x[i + j] > hi[j] ? x[i + j] : hi[j];
      }
    }
    for (; i < e; ++i) {
      lo[0] = x[i] < lo[0] ? x[i] : lo[0];
      hi[0] = x[i] > hi[0] ? x[i] : hi[0];
    }
  }
  double low = std::min({lo[0], lo[1], lo[2], lo[3]});
  double high = std::max({hi[0], hi[1], hi[2], hi[3]});
  if (low == -INFINITY || high == INFINITY) {
    low = INFINITY, high = -INFINITY;
    for (const Cycle& c : cycles.cycles) {
      const Eigen::Index e = std::min(c.reverse.end, x_mm.size());
      for (Eigen::Index i = c.forward.begin; i < e; ++i) {
        if (!std::isfinite(x[i])) continue;
        low = std::min(low, x[i]);
        high = std::max(high, x[i]);
      }
    }
  }
  return {low, high};
}

void FindGrossSlip(const ForceRecord& record,
                   CycleSet* cycles,
                   const GrossSlipOptions& options) {
  std::string why;
  if (!options.IsValid(&why))
    throw ForceError("invalid gross-slip options: " + why);
  for (Cycle& c : cycles->cycles) {
    for (HalfCycle* half : {&c.forward, &c.reverse}) {
      if (options.central_fraction_only) {
        CentralFallback(record.x_mm, options.fallback_central_fraction, half);
        half->slip_fallback = false;  // asked for, not a fallback
      } else {
        FindHalfSlip(record.x_mm, record.tangential_n, options, half);
      }
    }
  }
}

CycleSet ExtendCycles(const ForceRecord& record,
                      const CycleSet& known,
                      const SegmentOptions& segment,
                      const GrossSlipOptions& slip) {
  if (known.cycles.empty() || !(known.stroke_mm > 0)) return {};
  const HalfCycle& r = known.cycles.back().reverse;
  const Eigen::Index from = r.begin + (r.end - r.begin) / 2;
  if (from >= record.size()) return {};
  // The reversal rule with the known cycles' stroke: the new samples'
  // order statistics are not needed.
  std::string why;
  if (!segment.IsValid(&why))
    throw ForceError("invalid segment options: " + why);
  CycleSet added;
  CyclesFromReversals(
      FindReversals(record.x_mm.tail(record.size() - from),
                    segment.hysteresis_fraction * known.stroke_mm),
      record.size() - from,
      &added);
  if (added.cycles.empty()) return known;  // none completed since
  if (added.cycles.front().forward.begin + from != r.end) return {};
  for (Cycle& c : added.cycles) {
    for (HalfCycle* h : {&c.forward, &c.reverse}) {
      h->begin += from;
      h->end += from;
    }
  }
  FindGrossSlip(record, &added, slip);
  CycleSet set = known;
  for (Cycle& c : added.cycles) {
    c.index = static_cast<int>(set.cycles.size());
    set.cycles.push_back(c);
  }
  set.leading_samples_dropped = set.cycles.front().forward.begin;
  set.trailing_samples_dropped = record.size() - set.cycles.back().reverse.end;
  set.notes.clear();
  set.x_range_of = nullptr;
  std::tie(set.x_min_mm, set.x_max_mm) = CyclesXRange(record.x_mm, set);
  set.x_range_of = record.x_mm.data();
  return set;
}

}  // namespace wearscar::force
