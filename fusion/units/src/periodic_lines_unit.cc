// Periodic lines in Q and P that the drive does not make (mains pick-up, a
// resonance) as an analysis unit (force/periodic.h).

#include <fmt/format.h>

#include <algorithm>

#include "units.h"
#include "wearscar/force/periodic.h"

namespace wearscar::fusion::internal {
namespace {

using Lines = std::vector<force::PeriodicLine>;

class PeriodicLinesUnit : public TypedUnit<Lines> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "periodic_lines",
        "lines in the spectra of Q and P that the drive's rate does not "
        "make: removed before the analysis (a second pass, said first), or "
        "with --notch none each a warning, and a verdict not explained says "
        "its excess may come from them",
        {"the record", "the cycles (the drive's rate)"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCycles;
  }
  bool WorthAThread() const override { return true; }
  // Sought unless asked not to (result.json then lists none).
  Lines Run(const UnitInput& in) const override {
    const auto& c = in.force.cycles.cycles;
    if (!in.options.find_periodic_lines || c.size() < 2) return {};
    const double span = in.record.time_s[c.back().reverse.end - 1] -
                        in.record.time_s[c.front().forward.begin];
    if (!(span > 0)) return {};
    return force::FindPeriodicLines(in.record,
                                    static_cast<double>(c.size()) / span);
  }
  void Say(const Lines& lines, TestResult* r) const override {
    for (const force::PeriodicLine& l : lines) {
      r->warnings.push_back(fmt::format(
          "a periodic line at {} that the drive's motion does not make "
          "(mains pick-up, a resonance): it corrupts P's slope and the "
          "verdict; --notch {:.2f} removes it from Q and P",
          l.Describe(),
          l.frequency_hz));
    }
    if (!lines.empty() && !r->verdict.explained) {
      r->verdict.reasons.push_back(fmt::format(
          "the excess may come from the periodic line at {:.2f} Hz (see the "
          "warnings; analyse again with --notch {:.2f})",
          lines.front().frequency_hz,
          lines.front().frequency_hz));
    }
  }
  // The lines of the record as read: where they were removed before the
  // analysis (found, or given with --notch), "removed" says so.
  nlohmann::json Json(const Lines& lines, const TestResult& r) const override {
    nlohmann::json j = nlohmann::json::array();
    const auto& notched = r.options.notch_hz;
    for (const force::PeriodicLine& l : lines) {
      const bool removed =
          std::find(notched.begin(), notched.end(), l.frequency_hz) !=
          notched.end();
      j.push_back({{"frequency_Hz", l.frequency_hz},
                   {"Q_amplitude_N", l.q_amplitude_n},
                   {"P_amplitude_N", l.p_amplitude_n},
                   {"prominence", l.prominence},
                   {"drive_harmonic", l.drive_harmonic},
                   {"removed", removed}});
    }
    return j;
  }
};

}  // namespace

const AnalysisUnit& PeriodicLinesAnalysis() {
  static const PeriodicLinesUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
