#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"

namespace wearscar::fusion {

// What repeats from cycle to cycle at the same place on the track, and what
// does not. The track changes slowly, so a quantity measured along the
// stroke (P, k, the misfit of the model) is, in neighbouring cycles, the
// same function of x plus independent sensor noise. Averaging neighbouring
// cycles at the same x lowers the noise; correlating one cycle with the
// others at the same x measures the part that is not noise.

// Bins of equal width along the plate coordinate.
struct PlateGrid {
  double x0_mm = 0.0;  // left edge of bin 0
  double bin_mm = 0.01;
  int bins = 0;
  // Bin of x, or -1 outside the grid (or x not finite).
  int Bin(double x_mm) const;
  // A grid covering the samples of the complete cycles (at most max_bins).
  static PlateGrid Covering(const force::ForceRecord& record,
                            const force::CycleSet& cycles,
                            double bin_mm,
                            int max_bins = 200000);
};

// Per cycle and direction, the sum of a quantity, of x and the count of
// samples in each bin. Cycles are added in any order; a range of cycles is
// summed from them on demand. Without `with_x` the sums of x are left out
// (Sums::x stays zero, MeanX is meaningless), for where only the values
// are needed (the noise split's bins).
class CycleBins {
 public:
  // With `ring_cycles` > 0 only that many cycles are stored at once: cycle
  // c shares its storage with c +- ring_cycles, and the caller clears a
  // cycle (ClearCycle) before adding the one that takes its place; the
  // range [first_cycle, last_cycle] still bounds the cycles accepted. A
  // sliding window of cycles then costs the window's memory, not the
  // test's (ForceSlopes).
  CycleBins(const PlateGrid& grid,
            int first_cycle,
            int last_cycle,
            bool with_x = true,
            int ring_cycles = 0);
  // Zeroes the storage of cycle's slot (both directions).
  void ClearCycle(int cycle);

  // direction +1 (forward) or -1 (reverse); samples outside the grid or the
  // cycle range, or with a non-finite value, are ignored.
  void Add(int cycle, int direction, double x_mm, double value);
  // Add for the samples [begin, end) of x and value, one cycle and
  // direction (the same sums; the cycle's place is found once).
  void AddRange(int cycle,
                int direction,
                const double* x_mm,
                const double* value,
                Eigen::Index begin,
                Eigen::Index end);

  // Sums per bin; x relative to the bin's left edge (MeanX gives plate x).
  struct Sums {
    std::vector<double> value, x;
    std::vector<int> count;
  };
  double MeanX(const Sums& sums, int bin) const {
    return grid_.x0_mm + bin * grid_.bin_mm + sums.x[bin] / sums.count[bin];
  }
  // Adds (sign +1) or removes (sign -1) one cycle's sums of one direction.
  void Accumulate(Sums* sums, int cycle, int direction, int sign) const;
  // Sums over the cycles in [first, last] (clipped to the range held),
  // skipping those in [skip_first, skip_last] (an empty skip when
  // skip_first > skip_last), for one direction.
  Sums Window(int direction,
              int first,
              int last,
              int skip_first = 1,
              int skip_last = 0) const;
  // One cycle's own sums.
  Sums Cycle(int cycle, int direction) const {
    return Window(direction, cycle, cycle);
  }
  // The same, read where they are stored: grid().bins values and counts
  // (nulls for a cycle outside the range held).
  std::pair<const float*, const std::uint16_t*> Stored(int cycle,
                                                       int direction) const;

  const PlateGrid& grid() const { return grid_; }
  int first_cycle() const { return first_; }
  int last_cycle() const { return last_; }

 private:
  std::size_t Offset(int cycle, int direction) const;
  PlateGrid grid_;
  int first_ = 0, last_ = -1;
  int ring_ = 0;  // cycles stored (0: all of [first_, last_])
  std::vector<float> value_, x_;
  std::vector<std::uint16_t> count_;
};

// A quantity known along the plate coordinate, linearly interpolated, NaN
// outside: the slope k of the sliding path (from the scan, or from an
// ensemble of cycles) or a groove depth (the diagnosis).
struct PlateProfile {
  Eigen::VectorXd x_mm;  // increasing
  Eigen::VectorXd k;     // the values at x_mm (a slope, or a depth in mm)
  // Linear interpolation at x; NaN outside [x_mm[0], x_mm[n - 1]].
  double At(double x) const;
  // The same value, the interval searched from *hint (updated) outwards:
  // for x that moves little from one call to the next, as along a stroke.
  double AtNear(double x, Eigen::Index* hint) const;
  // AtNear's values at x[0..n) into out, walked from one to the next in one
  // call (a stroke's samples: millions of calls a test otherwise).
  void AtEach(const double* x, Eigen::Index n, double* out) const;
};
using SlopeProfile = PlateProfile;  // the former name

struct EnsembleSlopeOptions {
  // Neighbouring cycles averaged, centred on the cycle (odd; fewer at the
  // ends of the test). The noise of k falls about as 1/sqrt(cycles).
  int cycles = 11;
  double bin_mm = 0.01;  // P(x) is averaged in bins this wide, mm
  // dP/dx is the slope of a weighted local quadratic over this span of x,
  // mm, widened until it holds min_bins non-empty bins.
  double span_mm = 0.1;
  int min_bins = 5;
  // Degree of the local polynomial, 2 or 3. Its slope at the centre of a
  // symmetric span is biased by about span^2 P'''(x) / 40 at degree 2 (the
  // track's curvature of slope, largest at its steepest flanks) and by a
  // term in span^4 at degree 3 (as at 4: on a symmetric span the slopes of
  // degrees 3 and 4 are one), for about 2x the noise at one span.
  int polynomial_order = 2;
  bool IsValid(std::string* why) const;
};

// k = (1/S) dP/dx of one cycle per direction ([0] forward, [1] reverse)
// from P(x) averaged over the cycles of `normal_bins` (P binned per cycle
// and direction) around `cycle`.
std::array<PlateProfile, 2> EnsembleSlopeAt(
    const CycleBins& normal_bins,
    int cycle,
    double spring_n_per_mm,
    const EnsembleSlopeOptions& options);
// The cycles [first, last] averaged for `cycle`: centred, narrower at the
// ends of the test rather than shifted, so that the windows of two cycles
// share P samples only when the cycles are less than options.cycles apart.
std::pair<int, int> EnsembleWindow(const CycleBins& normal_bins,
                                   int cycle,
                                   const EnsembleSlopeOptions& options);
// k per direction from P summed over a window (sums[0] forward, [1] reverse).
std::array<PlateProfile, 2> EnsembleSlopeFromSums(
    const CycleBins& normal_bins,
    const std::array<CycleBins::Sums, 2>& sums,
    double spring_n_per_mm,
    const EnsembleSlopeOptions& options);
// The same for one direction's sums.
PlateProfile EnsembleSlopeOfSums(const CycleBins& normal_bins,
                                 const CycleBins::Sums& sums,
                                 double spring_n_per_mm,
                                 const EnsembleSlopeOptions& options);

// How the force side's k = (1/S) dP/dx is estimated.
enum class KEstimate {
  // From each cycle's own P (the paper's Eqs. 4-5: smoothing, then a
  // central difference; force::SlopeOptions).
  kCycle,
  // From P(x) averaged per direction over neighbouring cycles at the same x
  // (EnsembleSlopeOptions): a fraction of the noise of one cycle, at the
  // cost of following the track's change only over that many cycles.
  kEnsemble,
};
const char* KEstimateName(KEstimate estimate);  // "cycle", "ensemble"
bool ParseKEstimate(const std::string& text, KEstimate* estimate);

// How much of a quantity repeats at the same x in other cycles.
struct RepeatabilityOptions {
  double bin_mm = 0.01;
  // Other cycles in the template, the nearest ones whose estimate shares no
  // sample with the cycle judged (an ensemble slope of N cycles shares
  // samples with its N - 1 neighbours on either side).
  int template_cycles = 10;
  bool IsValid(std::string* why) const;
};

// One cycle and direction of a quantity v along the stroke: total = sum of
// v^2 over its samples; repeat = sum of v times the mean of v at the same x
// in the template cycles. With v = s(x) + noise and noise independent
// between cycles, E[repeat] = sum s^2 (the template's own noise averages
// out), E[total - repeat] = sum noise^2.
struct RepeatSplit {
  double total = 0.0;
  double repeat = 0.0;
  int samples = 0;
};

// For every cycle of `bins` (and each direction, [0] forward, [1] reverse),
// `total` given per cycle and direction (sum of v^2 over the cycle's
// samples), returns the split. Cycles within `min_separation` - 1 of the
// cycle judged are not in its template (min_separation 1: all others).
// With `two_threads` the reverse direction on a thread of its own (the
// same split).
//
// With `parity`, the direction split too, from the same pass of the
// templates: each direction's template against its values less the other
// direction's at the same x, [d].repeat = sum over the bins where both
// directions slid in the cycle of w (m_d - m_other) T_d, m the cycle's
// mean in the bin, T_d direction d's template, w the fewer samples of the
// two (total 0). With a quantity v = e(x) + s o(x) (e the same in both
// directions, o changing sign with the motion), the two directions' sum is
// 4 sum w o^2: the part that acts as friction does. Bins one direction
// alone slid in (near the reversals, where the other is still turning)
// and unequal counts would count e there as o; they are left out and
// weighted alike.
std::vector<std::array<RepeatSplit, 2>> SplitRepeatable(
    const CycleBins& bins,
    const std::vector<std::array<double, 2>>& total,
    int min_separation,
    const RepeatabilityOptions& options,
    bool two_threads = false,
    std::vector<std::array<RepeatSplit, 2>>* parity = nullptr);

}  // namespace wearscar::fusion
