// What a test's result rests on that its files did not state, and the
// conditions they state that the data contradict: the words of
// TestResult::assumptions and of some warnings.

#include "wearscar/fusion/assumptions.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/fusion/scan_identity.h"

namespace wearscar::fusion {

std::string SpringOrigin(const FuseOptions& o) {
  return !o.spring_stated.empty() ? "the force file states"
         : o.spring_given         ? "given"
                                  : "assumed (the default: not given)";
}

namespace {

// What the result rests on that the files did not state.
// How the force file was read: its layout and each channel's unit, stated
// or guessed from the values.
std::string ReadAssumption(const force::ForceMetadata& m) {
  static const char* const kChannel[5] = {"time", "x", "Q", "P", "depth"};
  std::string units;
  for (int ch = 0; ch < 5; ++ch) {
    if (static_cast<std::size_t>(ch) >= m.channel_units.size() ||
        m.channel_units[ch].empty())
      continue;
    units +=
        fmt::format("{}{} {}{}",
                    units.empty() ? "" : ", ",
                    kChannel[ch],
                    m.channel_units[ch],
                    m.unit_guessed[ch] ? " (guessed: no unit stated)" : "");
  }
  if (m.time_rebuilt) units += ", time from the sampling rate";
  return fmt::format("the force file read as the '{}' layout; units: {}",
                     m.layout,
                     units.empty() ? "none read" : units);
}

// The spring's stiffness, where it came from, and what P/S against the
// friction's path says of it (SpringCheck).
std::string SpringAssumption(const TestResult& r, const FuseOptions& o) {
  const double s = o.analysis.friction.slope.spring_n_per_mm;
  std::string spring =
      !o.spring_from_friction.empty()
          ? fmt::format(
                "spring S = {:.3g} N/mm, the stiffness that carries P/S onto "
                "the path the friction shows (no scan to quote k from: {})",
                s,
                o.spring_from_friction)
      : !o.spring_stated.empty()
          ? fmt::format("spring S = {:g} N/mm, as the force file states ({})",
                        s,
                        o.spring_stated)
      : o.spring_given
          ? fmt::format("spring S = {:g} N/mm (given)", s)
          : fmt::format(
                "spring S = {:g} N/mm: the default (the paper's "
                "rig), not given; k from P and the verdict depend on "
                "it",
                s);
  // What P/S against the friction's path says of S (SpringCheck).
  const SpringCheck& c = r.mismatch.Spring();
  if (!o.spring_from_friction.empty()) {
  } else if (c.contradicted) {
    spring += fmt::format(
        "; the friction's path contradicts it: {}{:.3g} N/mm (95%: "
        "{:.3g}-{:.3g}; see the warnings)",
        c.changing_groove.Held() ? "" : "at most ",
        c.ImpliedStiffness(),
        c.ImpliedLow(),
        c.ImpliedHigh());
  } else if (c.undecided) {
    spring += fmt::format(
        "; P/S is the friction's path times {:.2f}: a spring of {:.3g} "
        "N/mm or an elastic part, which the data cannot tell apart (see "
        "the warnings)",
        c.path_ratio,
        c.ImpliedStiffness());
  } else if (c.changing_groove.Held()) {
    spring += fmt::format(
        "; the friction's path agrees: P/S is the path times {:.2f} (95%: "
        "{:.2f}-{:.2f}), and the groove's growth splits off an elastic part "
        "of {:.0f}% of the worn track's profile (95%: {:.0f} to {:.0f}%)",
        c.StiffnessRatio(),
        c.ImpliedLow() / c.used_n_per_mm,
        c.ImpliedHigh() / c.used_n_per_mm,
        100 * c.elastic_share,
        100 * c.elastic_share_low,
        100 * c.elastic_share_high);
  } else if (c.judged) {
    spring += fmt::format(
        "; the friction's path agrees: P/S is the path times {:.2f} (95%: "
        "{:.2f}-{:.2f}; the groove did not change during the record, so "
        "an elastic part of up to {:.0f}% is not told from the stiffness)",
        c.path_ratio,
        c.path_ratio_low,
        c.path_ratio_high,
        100 * std::max(0.0, 1 - 1 / c.path_ratio_high));
  }
  return spring;
}

// Which of the scan's profiles k from the scan is the slope of, and why.
std::string ScanPathAssumption(const TestResult& r, const FuseOptions& o) {
  const Premise& sphere = r.scan->rigid_sphere;
  if (!r.scan->centreline_used) {
    return fmt::format(
        "k from the scan is the slope of the path of a sphere of radius {:g} "
        "mm riding the scanned track (--sphere-radius); {}",
        o.sphere.radius_mm,
        sphere.evidence);
  }
  if (!sphere.Failed()) {
    return "k from the scan is the track centreline's slope (--sphere-radius "
           "0)";
  }
  return fmt::format(
      "k from the scan is the track centreline's slope, not the path of a "
      "rigid sphere of radius {:g} mm (the sphere conforms to the track): {}",
      o.sphere.radius_mm,
      sphere.evidence);
}

}  // namespace

std::vector<std::string> Assumptions(const force::ForceRecord& record,
                                     const TestResult& r,
                                     const FuseOptions& o) {
  const std::string spring =
      r.profile.FromSpring() ? SpringAssumption(r, o) : r.profile.reason;
  std::string slope =
      r.profile.FromDepth()
          ? (r.scan ? "the verdict judges mu-hat with k from the depth "
                      "channel; the scan's k is compared with it"
                    : "k from the depth channel alone (no scan)")
      : r.profile.FromFriction()
          ? "the verdict judges mu-hat with k from the scan, aligned with the "
            "profile from the friction; k from P is not used"
      : o.slopes == SlopeChoice::kScan ? "mu-hat with k from the scan alone"
      : r.scan && !r.mismatch.JudgesForceSlope()
          ? (r.mismatch.Spring().undecided
                 ? "the verdict judges mu-hat with k from the scan: "
                   "P/S's amplitude is a spring's or an elastic "
                   "part's, which k from the scan needs neither of"
                 : "the verdict judges mu-hat with k from the scan: "
                   "the friction's path contradicts the spring that "
                   "k from P is divided by")
      : r.scan ? "the verdict judges mu-hat with k from P; the scan's k is "
                 "compared with it"
      : r.scan_file.empty() ? "k from P alone (no scan)"
                            : "k from P alone (the scan was not used)";
  std::vector<std::string> said = {
      spring, slope, ReadAssumption(record.metadata), r.force.running_in.rule};
  if (r.scan) said.push_back(ScanPathAssumption(r, o));
  if (r.scan && ShortStrokesTrack(r.scan->track,
                                  r.force.cycles.stroke_mm,
                                  r.mismatch.scan_pixel_mm,
                                  o.track,
                                  o.verdict)) {
    const scan::Track& t = r.scan->track;
    said.push_back(fmt::format(
        "the scan's track is taken as the wear track although it is only "
        "{:.1f} times as long as wide (below {:g} a track may be texture): its "
        "length, "
        "{:.2f} mm, is what the stroke of {:.2f} mm wears with the track's "
        "width, {:.2f} mm, beside it (a short stroke); its outline does not "
        "place it",
        t.elongation,
        o.track.confident_elongation,
        t.length_mm,
        r.force.cycles.stroke_mm,
        t.width_mm));
  }
  return said;
}

namespace {

// The median of P over about 4096 samples.
double MedianLoad(const force::ForceRecord& record) {
  std::vector<double> p;
  const Eigen::Index n = record.size();
  for (Eigen::Index i = 0; i < n; i += std::max<Eigen::Index>(1, n / 4096)) {
    if (std::isfinite(record.normal_n[i])) p.push_back(record.normal_n[i]);
  }
  if (p.empty()) return NAN;
  std::nth_element(p.begin(), p.begin() + p.size() / 2, p.end());
  return p[p.size() / 2];
}

}  // namespace

// The test conditions the file's header states that the data contradict
// by more than 10% (the cycles' count by more than that and one cycle).
std::vector<std::string> StatedButNotFound(const force::ForceRecord& record,
                                           const ForceAnalysis& force) {
  std::vector<std::string> out;
  const auto& cycles = force.cycles.cycles;
  for (const force::StatedFact& f : record.metadata.stated) {
    double found = NAN;
    std::string shown;
    if (f.what == "spring" && !(f.value >= 0.01 && f.value <= 1e5)) {
      out.push_back(fmt::format(
          "the file states \"{}\" (line {}): a spring of {:.3g} N/mm, "
          "outside 0.01-1e5 N/mm, was not used",
          f.line,
          f.line_number,
          f.value));
    } else if (f.what == "stroke") {
      found = force.cycles.stroke_mm;
      shown = fmt::format("a stroke of {:.3g} mm (peak to peak)", found);
    } else if (f.what == "cycles") {
      found = static_cast<double>(cycles.size());
      shown = fmt::format("{} complete cycles", cycles.size());
    } else if (f.what == "load") {
      found = MedianLoad(record);
      shown = fmt::format("a load of {:.3g} N (median P)", found);
    } else if (f.what == "frequency" && cycles.size() >= 2) {
      const double t0 = record.time_s[cycles.front().forward.begin];
      const double t1 = record.time_s[cycles.back().reverse.end - 1];
      found = t1 > t0 ? static_cast<double>(cycles.size()) / (t1 - t0) : NAN;
      shown = fmt::format("{:.3g} Hz", found);
    }
    if (!std::isfinite(found)) continue;
    const double tolerance = f.what == "cycles" ? 0.1 + 1.0 / f.value : 0.1;
    if (std::abs(found - f.value) > tolerance * f.value) {
      out.push_back(
          fmt::format("the file states \"{}\" (line {}), but the data show {}",
                      f.line,
                      f.line_number,
                      shown));
    }
  }
  return out;
}

}  // namespace wearscar::fusion
