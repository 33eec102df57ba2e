#include "plausibility.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "units.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

std::optional<double> UnitFactor(Channel channel, const std::string& unit) {
  return channel == kTime                     ? TimeToS(unit)
         : channel == kX || channel == kDepth ? LengthToMm(unit)
                                              : ForceToN(unit);
}

// Robust spread of a channel (99th minus 1st percentile of a subsample) and
// the median of its magnitude.
void Spread(const Eigen::VectorXd& v, double* span, double* median_abs) {
  std::vector<double> s, a;
  // About 20,000 samples, one from each stretch of `step`, at a place in
  // it that varies from stretch to stretch: a fixed stride aliases with a
  // periodic channel (1,000 samples are 5 cycles of a 1 Hz test at
  // 200 Hz, and x would be seen at one phase only).
  const Eigen::Index step = std::max<Eigen::Index>(1, v.size() / 20000);
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  for (Eigen::Index at = 0; at < v.size(); at += step) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const Eigen::Index i = std::min<Eigen::Index>(
        v.size() - 1, at + static_cast<Eigen::Index>((state >> 33) % step));
    if (!std::isfinite(v[i])) continue;
    s.push_back(v[i]);
    a.push_back(std::abs(v[i]));
  }
  *span = *median_abs = std::nan("");
  if (s.empty()) return;
  auto at = [](std::vector<double>& w, double q) {
    const std::size_t k = static_cast<std::size_t>(q * (w.size() - 1));
    std::nth_element(w.begin(), w.begin() + k, w.end());
    return w[k];
  };
  *span = at(s, 0.99) - at(s, 0.01);
  *median_abs = at(a, 0.5);
}

struct UnitGuess {
  const char* unit;
  double factor;  // to mm, N or s
};

struct Plausibility {
  std::vector<UnitGuess> units;
  double lo, hi;       // the figure's plausible range in mm, N or Hz
  bool divide;         // figure / factor (a rate) instead of figure * factor
  const char* range;   // "a stroke of 0.05-50 mm", for the refusal
  const char* option;  // the --columns key
};

const Plausibility& PlausibilityOf(Channel ch) {
  static const Plausibility kLength = {{{"mm", 1.0}, {"um", 1e-3}, {"m", 1e3}},
                                       0.05,
                                       50,
                                       false,
                                       "a stroke of 0.05-50 mm",
                                       "x"};
  static const Plausibility kForce = {{{"N", 1.0}, {"mN", 1e-3}, {"kN", 1e3}},
                                      0.01,
                                      5000,
                                      false,
                                      "a load of 0.01-5000 N",
                                      "p"};
  static const Plausibility kTimes = {
      {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"min", 60.0}},
      1,
      1e6,
      true,
      "sampling at 1 Hz-1 MHz",
      "time"};
  return ch == kX ? kLength : ch == kTime ? kTimes : kForce;
}

bool Plausible(const Plausibility& p, double figure, double factor) {
  const double v = p.divide ? figure / factor : figure * factor;
  return v >= p.lo && v <= p.hi;
}

// The figure a channel's unit is judged by, and how the message says it.
double Figure(Channel ch, const Eigen::VectorXd& v, std::string* said) {
  double span, median;
  if (ch == kTime) {
    const double raw = v.size() > 1 ? v[v.size() - 1] - v[0] : 0.0;
    const double rate = raw > 0 ? (v.size() - 1) / raw : 0.0;
    *said = fmt::format("its samples come {:.4g} per unit", rate);
    return rate;
  }
  Spread(v, &span, &median);
  if (ch == kX) {
    *said = fmt::format("its values span {:.4g}", span);
    return span;
  }
  *said = fmt::format("its median magnitude is {:.4g}", median);
  return median;
}

std::string Because(Channel ch, double scaled) {
  switch (ch) {
    case kX:
      return fmt::format(
          "a stroke of {:.3g} mm; tribometer strokes are 0.05-50 mm", scaled);
    case kTime:
      return fmt::format("sampling at {:.4g} Hz", scaled);
    default:
      return fmt::format("{} of {:.3g} N at the median; loads are 0.01-5000 N",
                         ch == kP ? "a load" : "a force",
                         scaled);
  }
}

ForceError NoPlausibleUnit(Channel ch,
                           const std::string& file,
                           const std::string& column,
                           const std::string& said) {
  const Plausibility& p = PlausibilityOf(ch);
  std::string units;
  for (const UnitGuess& g : p.units) {
    units += (units.empty()           ? ""
              : &g == &p.units.back() ? " or "
                                      : ", ") +
             std::string(g.unit);
  }
  return ForceError(fmt::format(
      "{}: column '{}' states no unit and {}: no unit makes it plausible "
      "({} as {}); give the unit (e.g. --columns {}=NAME:UNIT)",
      file,
      column,
      said,
      p.range,
      units,
      ch == kQ ? "q" : p.option));
}

// A rotary (pin-on-disk) export: the position does not reciprocate and
// the header states the track's radius.
void RefuseARotaryTest(const ForceRecord& r,
                       const std::string& file,
                       double span) {
  const auto radius =
      std::find_if(r.metadata.stated.begin(),
                   r.metadata.stated.end(),
                   [](const StatedFact& f) { return f.what == "radius"; });
  if (span < 0.01 && radius != r.metadata.stated.end()) {
    throw ForceError(fmt::format(
        "{}: a rotary test (pin-on-disk): the position does not reciprocate "
        "(a stroke of {:.4g} mm) and line {} states the track's radius "
        "('{}'); expected a reciprocating test, the only kind wearscar "
        "analyses",
        file,
        span,
        radius->line_number,
        radius->line));
  }
}

}  // namespace

Scale ResolveUnit(Channel channel,
                  const std::string& found,
                  const ReadForceOptions& options,
                  const std::string& file,
                  const std::string& column,
                  const ForceLayout& layout,
                  std::vector<std::string>* warnings) {
  const std::string& given = channel == kTime    ? options.time_unit
                             : channel == kX     ? options.x_unit
                             : channel == kDepth ? options.depth_unit
                                                 : options.force_unit;
  const std::string unit = given.empty() ? found : given;
  if (unit.empty()) {
    Scale s{1.0, "", true, {}};
    s.preferred = channel == kTime    ? layout.time_unit
                  : channel == kX     ? layout.x_unit
                  : channel == kDepth ? std::string("um")
                                      : layout.force_unit;
    return s;
  }
  const std::optional<double> f = UnitFactor(channel, unit);
  if (!f) {
    throw ForceError(
        fmt::format("{}: column '{}' has unit '{}'; expected a {} unit ({})",
                    file,
                    support::Printable(column),
                    support::Printable(unit),
                    channel == kTime                     ? "time"
                    : channel == kX || channel == kDepth ? "length"
                                                         : "force",
                    channel == kTime                     ? "s, ms, min"
                    : channel == kX || channel == kDepth ? "mm, um, m"
                                                         : "N, mN, kN, gf"));
  }
  if (!given.empty() && !found.empty()) {
    const std::optional<double> ff = UnitFactor(channel, found);
    if (!ff || std::abs(*ff - *f) > 1e-12 * std::abs(*f)) {
      warnings->push_back(
          fmt::format("column '{}' says '{}'; read as '{}' as the options ask",
                      column,
                      found,
                      given));
    }
  }
  return {*f, unit, false, {}};
}

void InferUnits(Eigen::VectorXd* data,
                Scale* scale,
                const Columns& column,
                const Layout& layout,
                const std::string& file,
                ForceMetadata* meta) {
  // (`unit` by value: it may be the scale's own `preferred`.)
  auto apply =
      [&](int ch, std::string unit, double factor, const std::string& because) {
        data[ch] *= factor;
        meta->warnings.push_back(
            fmt::format("column '{}' states no unit: taken as {} ({})",
                        layout.names[column[ch]],
                        unit,
                        because));
        scale[ch] = {factor, std::move(unit), false, {}};
        meta->unit_guessed[ch] = true;
      };
  // A depth without a unit: um, as depth channels are logged.
  if (column[kDepth] >= 0 && scale[kDepth].inferred) {
    const double factor = *LengthToMm("um");
    data[kDepth] *= factor;
    meta->warnings.push_back(fmt::format(
        "column '{}' states no unit: taken as um (depth channels are logged "
        "in um; --columns depth=NAME:mm if not)",
        layout.names[column[kDepth]]));
    scale[kDepth] = {factor, "um", false, {}};
    meta->unit_guessed[kDepth] = true;
  }
  // x, then the forces (P first: Q without a unit takes P's when P's was
  // stated), then time.
  for (Channel ch : {kX, kP, kQ, kTime}) {
    if (column[ch] < 0 || !scale[ch].inferred) continue;
    if (ch == kQ && !scale[kP].unit.empty() && !scale[kP].inferred) {
      double span, median;
      Spread(data[kQ], &span, &median);
      apply(kQ,
            scale[kP].unit,
            scale[kP].factor,
            fmt::format("the normal force's unit; |Q| {:.3g} N at the median",
                        median * scale[kP].factor));
      continue;
    }
    const Plausibility& p = PlausibilityOf(ch);
    std::string said;
    const double figure = Figure(ch, data[ch], &said);
    const auto scaled = [&](double factor) {
      return Because(ch, p.divide ? figure / factor : figure * factor);
    };
    const std::string& preferred = scale[ch].preferred;
    const std::optional<double> pf =
        preferred.empty() ? std::nullopt : UnitFactor(ch, preferred);
    if (pf && Plausible(p, figure, *pf)) {
      apply(ch,
            preferred,
            *pf,
            fmt::format(
                "the {} layout's unit; {}", layout.kind->name, scaled(*pf)));
      continue;
    }
    const auto g = std::find_if(p.units.begin(), p.units.end(), [&](auto& u) {
      return Plausible(p, figure, u.factor);
    });
    if (g == p.units.end())
      throw NoPlausibleUnit(ch, file, layout.names[column[ch]], said);
    apply(ch, g->unit, g->factor, scaled(g->factor));
  }
}

SampleCensus TakeCensus(const ForceRecord& r) {
  constexpr Eigen::Index kStretch = 4096;
  SampleCensus c;
  double span;
  Spread(r.normal_n, &span, &c.median_abs_p);
  // (NaN without a finite P: no sample counts as beyond it.)
  const double quarter = 0.25 * c.median_abs_p;
  const Eigen::Index n = r.size();
  const double *q = r.tangential_n.data(), *p = r.normal_n.data(),
               *x = r.x_mm.data();
  c.first_beyond = n;
  for (Eigen::Index b = 0; b < n; b += kStretch) {
    const Eigen::Index e = std::min(n, b + kStretch);
    long beyond = 0, q_finite = 0, q_nonzero = 0, pairs = 0, above = 0,
         below = 0, over = 0;
    for (Eigen::Index i = b; i < e; ++i) {
      const double aq = std::abs(q[i]), ap = std::abs(p[i]);
      beyond += static_cast<long>((aq > SampleCensus::kMaxForceN) |
                                  (ap > SampleCensus::kMaxForceN) |
                                  (std::abs(x[i]) > SampleCensus::kMaxAbsXMm));
      const bool fq = support::Finite(q[i]), ok = fq & support::Finite(p[i]);
      q_finite += static_cast<long>(fq);
      q_nonzero += static_cast<long>(fq & (q[i] != 0));
      pairs += static_cast<long>(ok);
      above += static_cast<long>(ok & (aq > ap));
      below += static_cast<long>(ok & (p[i] < -quarter));
      over += static_cast<long>(ok & (p[i] > quarter));
    }
    c.q_finite += q_finite;
    c.q_nonzero += q_nonzero;
    c.pairs += pairs;
    c.q_above_p += above;
    c.p_below += below;
    c.p_above += over;
    if (beyond == 0 || c.first_beyond < n) continue;
    for (Eigen::Index i = b; i < e && c.first_beyond == n; ++i) {
      if (std::abs(q[i]) > SampleCensus::kMaxForceN ||
          std::abs(p[i]) > SampleCensus::kMaxForceN ||
          std::abs(x[i]) > SampleCensus::kMaxAbsXMm)
        c.first_beyond = i;
    }
  }
  return c;
}

void CheckPlausible(ForceRecord& r,
                    const SampleCensus& census,
                    const std::string& file) {
  constexpr double kMaxForceN = SampleCensus::kMaxForceN;
  constexpr double kMaxAbsXMm = SampleCensus::kMaxAbsXMm;
  auto where = [&](Eigen::Index i) {
    return fmt::format("sample {} (t = {:.6g} s)", i + 1, r.time_s[i]);
  };
  if (const Eigen::Index i = census.first_beyond; i < r.size()) {
    if (std::abs(r.tangential_n[i]) > kMaxForceN ||
        std::abs(r.normal_n[i]) > kMaxForceN) {
      throw ForceError(fmt::format(
          "{}: {}: a force of {:.4g} N; expected at most {:.0e} N in "
          "magnitude",
          file,
          where(i),
          std::abs(r.tangential_n[i]) > kMaxForceN ? r.tangential_n[i]
                                                   : r.normal_n[i],
          kMaxForceN));
    }
    throw ForceError(fmt::format(
        "{}: {}: x = {:.4g} mm; expected a position within +-{:.0e} mm "
        "(check the x unit)",
        file,
        where(i),
        r.x_mm[i],
        kMaxAbsXMm));
  }
  double span, median;
  Spread(r.x_mm, &span, &median);
  RefuseARotaryTest(r, file, span);
  if (!(span >= 0.01 && span <= 100)) {
    throw ForceError(fmt::format(
        "{}: a stroke of {:.4g} mm (robust peak to peak of x); expected 0.05 "
        "to 50 mm for a reciprocating test (check the x unit)",
        file,
        span));
  }
  if (span < 0.05 || span > 50) {
    r.metadata.warnings.push_back(fmt::format(
        "a stroke of {:.4g} mm, outside the usual 0.05-50 mm", span));
  }
  median = census.median_abs_p;
  if (!(median >= 1e-3)) {
    throw ForceError(fmt::format(
        "{}: the normal force is {:.3g} N at the median; expected a load (the "
        "method divides by it)",
        file,
        median));
  }
  if (median < 0.01 || median > 5000) {
    r.metadata.warnings.push_back(fmt::format(
        "a load of {:.4g} N at the median, outside the usual 0.01-5000 N",
        median));
  }
  const Eigen::Index n = r.size();
  const double duration = n > 1 ? r.time_s[n - 1] - r.time_s[0] : 0.0;
  const double rate = duration > 0 ? (n - 1) / duration : 0.0;
  if (!(rate >= 0.1 && rate <= 1e7)) {
    throw ForceError(fmt::format(
        "{}: {} samples over {:.4g} s: a sampling rate of {:.4g} Hz; expected "
        "0.1 Hz to 10 MHz (check the time column and its unit)",
        file,
        n,
        duration,
        rate));
  }
}

void CheckFrictionRecorded(const ForceRecord& r,
                           const SampleCensus& census,
                           const std::string& file) {
  if (census.q_finite > 0 && census.q_nonzero == 0) {
    const auto& names = r.metadata.channel_names;
    throw ForceError(fmt::format(
        "{}: no friction force recorded: the friction channel{} is 0 N in "
        "every one of the {} samples; expected a friction force that "
        "reverses with the sliding (check the channel, or name its column "
        "with --columns q=NAME)",
        file,
        names.size() > 2 && !names[2].empty() ? " '" + names[2] + "'" : "",
        r.size()));
  }
}

void CheckChannelRoles(const ForceRecord& r,
                       const SampleCensus& census,
                       const std::string& file) {
  const long both = census.pairs;
  if (both == 0) return;
  // P as it now stands: negated when it was negative in compression.
  const long p_negative =
      r.metadata.normal_sign_flipped ? census.p_above : census.p_below;
  auto name = [&](size_t ch) {
    const auto& names = r.metadata.channel_names;
    return ch < names.size() && !names[ch].empty() ? "'" + names[ch] + "'"
                                                   : std::string("(none)");
  };
  const std::string fix =
      "name the columns with --columns q=NAME,p=NAME, or give "
      "--force-channels-as-given to read them as they are";
  const double above = static_cast<double>(census.q_above_p) / both;
  if (above > 0.5) {
    throw ForceError(fmt::format(
        "{}: the friction force Q {} exceeds the normal force P {} in "
        "magnitude on {:.0f}% of the samples: the two look swapped; expected "
        "|Q| below |P| (mu below 1): {}",
        file,
        name(2),
        name(3),
        100 * above,
        fix));
  }
  const double negative = static_cast<double>(p_negative) / both;
  if (negative > 0.2) {
    throw ForceError(fmt::format(
        "{}: the normal force P {} changes sign on {:.0f}% of the samples: "
        "it reverses like a friction force; expected a load of one sign: {}",
        file,
        name(3),
        100 * negative,
        fix));
  }
}

bool NamesAPenetration(const std::string& column_name) {
  const std::string lower = support::Lower(column_name);
  return lower.find("depth") != std::string::npos ||
         lower.find("penetration") != std::string::npos;
}

}  // namespace wearscar::force::internal
