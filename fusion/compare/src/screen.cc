// The screen of an explained test (screen.h), decided once.
#include "wearscar/fusion/screen.h"

#include <fmt/format.h>

#include "interval_text.h"
#include "wearscar/fusion/mismatch.h"
#include "wearscar/fusion/verdict_options.h"

namespace wearscar::fusion {
namespace {

// The premise, checked on the split: the misfit split by direction.
Premise ScreenPremise(const CostSplit& split) {
  Premise p;
  p.rule = "the screen";
  p.statement =
      "only a repeating misfit that changes sign with the motion biases "
      "mu-hat; one the same in both directions acts as a slope and cancels";
  p.state = std::isfinite(split.odd_excess) ? Premise::State::kHeld
                                            : Premise::State::kNotChecked;
  p.evidence = std::isfinite(split.odd_excess)
                   ? fmt::format(
                         "of J's excess {:.3f}, {:.3f} changes sign with the "
                         "motion (noise floor {:.3f})",
                         split.excess,
                         split.odd_excess,
                         split.floor)
                   : "the misfit was not split by direction";
  p.otherwise = "the whole excess is screened";
  return p;
}

}  // namespace

const ScreenFinding& MismatchReport::Screen() const {
  static const ScreenFinding kNone{};
  return screen ? *screen : kNone;
}

ScreenFinding ScreenTheLoops(const MismatchReport& r, const VerdictOptions& o) {
  ScreenFinding s;
  s.with_force_slope = r.JudgesForceSlope();
  const CostSplit& split = s.with_force_slope ? r.split_force : r.split_scan;
  s.premise = ScreenPremise(split);
  s.by_direction = std::isfinite(split.odd_excess);
  s.excess = s.by_direction ? split.odd_excess : split.excess;
  s.excess_low = s.by_direction ? split.odd_excess_low : split.excess_low;
  s.excess_high = s.by_direction ? split.odd_excess_high : split.excess_high;
  s.floor = split.floor;
  // The lower end of the excess's 95% interval, as the verdict's: a few
  // cycles' excess is no repeating misfit yet.
  const double excess = std::isfinite(s.excess_low) ? s.excess_low : s.excess;
  if (!s.with_force_slope || split.cycles == 0 || !(split.floor > 0) ||
      !(excess >= o.screen_excess_to_floor * split.floor))
    return s;
  s.finding = fmt::format(
      "the loops repeat a misfit above their noise that acts as friction "
      "does, changing sign with the motion (J's excess {:.3f}{}, at least "
      "{:.2f} of its noise floor {:.3f}; the screen's limit {:.2f}): an "
      "effect the wear-scar model misses may bias mu-hat; `wearscar "
      "diagnose` names it",
      s.excess,
      internal::IntervalText(s.excess_low, s.excess_high, "{:.3f}"),
      excess / split.floor,
      split.floor,
      o.screen_excess_to_floor);
  return s;
}

}  // namespace wearscar::fusion
