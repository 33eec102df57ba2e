#include "wearscar/force/periodic.h"

#include <fftw3.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>

#include "wearscar/support/numbers.h"

namespace wearscar::force {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The largest length <= n whose only prime factors are 2, 3 and 5 (fast
// for the FFT).
Eigen::Index SmoothLength(Eigen::Index n) {
  Eigen::Index best = 1;
  for (Eigen::Index a = 1; a <= n; a *= 2) {
    for (Eigen::Index b = a; b <= n; b *= 3) {
      for (Eigen::Index c = b; c <= n; c *= 5) best = std::max(best, c);
    }
  }
  return best;
}

// FFTW's real-to-complex plan of one length and its Hann window. Planning
// takes milliseconds (a length of 2, 3 and 5 up to 7 ms), the transform of
// a live window a tenth of one: plans are kept by length for the next
// search (a live window's every few cycles), at most kKept of them, the
// others made for the call alone. The planner is not thread-safe
// (fftwf_execute_dft_r2c is): a batch analyses specimens on several
// threads, so plans are made and destroyed under one lock. FFTW_ESTIMATE:
// measuring would take seconds per length. In single precision: the
// transform of a full-size test's 2^18 samples takes 0.7 ms against 1.6 ms
// in double, and its rounding (a part in 10^7 of the window's content) lies
// far below any sensor's noise floor, which the lines are judged against.
struct SpectrumPlan {
  Eigen::Index length = 0;
  fftwf_plan plan = nullptr;
  std::vector<double> hann;
};

std::mutex& Planner() {
  static std::mutex m;
  return m;
}

// The kept plans (never destroyed: in use until the process ends).
std::vector<const SpectrumPlan*>& KeptPlans() {
  static auto* kept = new std::vector<const SpectrumPlan*>;
  return *kept;
}

struct PlanDeleter {
  void operator()(const SpectrumPlan* p) const {
    if (p == nullptr) return;
    {
      std::lock_guard<std::mutex> lock(Planner());
      fftwf_destroy_plan(p->plan);
    }
    delete p;
  }
};
using PlanHandle = std::unique_ptr<const SpectrumPlan, PlanDeleter>;

// The plan of `n`: a kept one (*own stays empty), or one made for this
// call (owned by *own).
const SpectrumPlan* PlanFor(Eigen::Index n, PlanHandle* own) {
  constexpr std::size_t kKept = 4;
  std::lock_guard<std::mutex> lock(Planner());
  for (const SpectrumPlan* p : KeptPlans()) {
    if (p->length == n) return p;
  }
  auto* made = new SpectrumPlan;
  made->length = n;
  float* in = fftwf_alloc_real(static_cast<std::size_t>(n));
  fftwf_complex* out = fftwf_alloc_complex(static_cast<std::size_t>(n / 2 + 1));
  made->plan =
      fftwf_plan_dft_r2c_1d(static_cast<int>(n), in, out, FFTW_ESTIMATE);
  fftwf_free(in);
  fftwf_free(out);
  // (Symmetric about n / 2: half the cosines, a quarter million of them
  // for a full-size test's window.)
  made->hann.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i <= n / 2; ++i) {
    made->hann[i] = 0.5 - 0.5 * std::cos(2 * kPi * i / n);
    if (i > 0) made->hann[n - i] = made->hann[i];
  }
  if (KeptPlans().size() < kKept) {
    KeptPlans().push_back(made);
  } else {
    own->reset(made);
  }
  return made;
}

// The largest power of two <= n (n >= 1).
Eigen::Index PowerOfTwoLength(Eigen::Index n) {
  Eigen::Index p = 1;
  while (p * 2 <= n) p *= 2;
  return p;
}

// The mean of the finite values of x[0, n) (0 if none), summed in four
// running sums (x[i] into sum i mod 4; one waits on each addition's
// latency): two at a time in vectors of two doubles (GCC's vector
// extension; any target), a value that is not finite masked to +0 and
// not counted. The window's quarter million samples are summed ten times
// in a full-size test.
double FiniteMean(const double* x, Eigen::Index n) {
  using Pair = double __attribute__((vector_size(16)));
  using Mask = std::int64_t __attribute__((vector_size(16)));
  const Pair largest = {std::numeric_limits<double>::max(),
                        std::numeric_limits<double>::max()};
  const Pair one = {1.0, 1.0};
  const Mask magnitude = {std::numeric_limits<std::int64_t>::max(),
                          std::numeric_limits<std::int64_t>::max()};
  Pair sum[2] = {{0, 0}, {0, 0}}, finite[2] = {{0, 0}, {0, 0}};
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int h = 0; h < 2; ++h) {
      Pair v;
      std::memcpy(&v, x + i + 2 * h, sizeof v);
      const Mask keep = reinterpret_cast<Pair>(reinterpret_cast<Mask>(v) &
                                               magnitude) <= largest;
      sum[h] += reinterpret_cast<Pair>(reinterpret_cast<Mask>(v) & keep);
      finite[h] += reinterpret_cast<Pair>(reinterpret_cast<Mask>(one) & keep);
    }
  }
  double s[4] = {sum[0][0], sum[0][1], sum[1][0], sum[1][1]};
  double count = 0;
  for (; i < n; ++i) {
    const bool f = support::Finite(x[i]);
    s[0] += f ? x[i] : 0.0;
    count += f ? 1.0 : 0.0;
  }
  count += (finite[0][0] + finite[0][1]) + (finite[1][0] + finite[1][1]);
  return count > 0 ? ((s[0] + s[1]) + (s[2] + s[3])) / count : 0.0;
}

// Amplitude spectra (N per bin, a sinusoid's amplitude at its bin) of Q
// and P, each with its mean removed, under a Hann window of `length`
// samples; NaN read as the mean. A record longer than one window is
// covered by windows spread evenly from its start to its end (overlapping
// where the length does not divide it), their amplitudes averaged
// (Welch): a steady line keeps its amplitude, the floor's scatter shrinks,
// and the transform's buffers and twiddles stay a few MB however long the
// test. One FFTW plan serves every window of both channels.
std::array<std::vector<double>, 2> AmplitudeSpectra(const ForceRecord& record,
                                                    Eigen::Index length) {
  const Eigen::Index n = record.size();
  // A last window that would add under 5% of the record's samples is left
  // out (they are nearly all in the one before): a record just longer than
  // a window, as a live window of a few cycles is, takes one, not two.
  Eigen::Index windows = (n + length - 1) / length;
  if (windows > 1 && n - (windows - 1) * length < n / 20) --windows;
  PlanHandle own;
  const SpectrumPlan* plan = PlanFor(length, &own);
  const std::vector<double>& hann = plan->hann;
  const std::unique_ptr<float, decltype(&fftwf_free)> buffer(
      fftwf_alloc_real(static_cast<std::size_t>(length)), &fftwf_free);
  const std::unique_ptr<fftwf_complex, decltype(&fftwf_free)> spectrum(
      fftwf_alloc_complex(static_cast<std::size_t>(length / 2 + 1)),
      &fftwf_free);
  float* in = buffer.get();
  fftwf_complex* out = spectrum.get();
  std::array<std::vector<double>, 2> amp;
  const Eigen::VectorXd* channels[2] = {&record.tangential_n, &record.normal_n};
  const double scale = 4.0 / static_cast<double>(length * windows);
  const Eigen::Index bins = length / 2 + 1;
  Eigen::ArrayXd power(bins);
  for (int ch = 0; ch < 2; ++ch) {
    const Eigen::VectorXd& v = *channels[ch];
    for (Eigen::Index w = 0; w < windows; ++w) {
      const Eigen::Index begin =
          windows > 1 ? (n - length) * w / (windows - 1) : 0;
      const double mean = FiniteMean(v.data() + begin, length);
      // (A value that is not finite is replaced by the mean before the
      // arithmetic, not its product after: the compiler may then choose
      // between two values without a branch.)
      const double* x = v.data() + begin;
      for (Eigen::Index i = 0; i < length; ++i) {
        const double xi = support::Finite(x[i]) ? x[i] : mean;
        in[i] = static_cast<float>(hann[i] * (xi - mean));
      }
      fftwf_execute_dft_r2c(plan->plan, in, out);
      amp[ch].resize(static_cast<std::size_t>(bins), 0.0);
      // |X_k|: the squares summed, then the roots taken two at a time
      // (std::sqrt one by one keeps errno; not hypot, which was a quarter
      // of the search).
      for (Eigen::Index k = 0; k < bins; ++k) {
        const double re = out[k][0], im = out[k][1];
        power[k] = re * re + im * im;
      }
      Eigen::Map<Eigen::ArrayXd>(amp[ch].data(), bins) += scale * power.sqrt();
    }
  }
  return amp;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Per block of about two seconds (a whole number of the line's periods):
// the least-squares sine and cosine amplitudes at f with a constant.
struct BlockFit {
  Eigen::Index begin, end;
  double a, b;  // v ~ c + a sin(w t) + b cos(w t)
};

std::vector<BlockFit> FitBlocks(const Eigen::VectorXd& t,
                                const Eigen::VectorXd& v,
                                double f) {
  std::vector<BlockFit> fits;
  const Eigen::Index n = t.size();
  if (n < 8) return fits;
  const double dt = (t[n - 1] - t[0]) / static_cast<double>(n - 1);
  const double periods = std::max(1.0, std::round(2.0 * f));
  const Eigen::Index len = std::max<Eigen::Index>(
      8, static_cast<Eigen::Index>(std::llround(periods / f / dt)));
  const double w = 2 * kPi * f;
  for (Eigen::Index begin = 0; begin < n; begin += len) {
    const Eigen::Index end = std::min(n, begin + len);
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    for (Eigen::Index i = begin; i < end; ++i) {
      if (!std::isfinite(v[i]) || !std::isfinite(t[i])) continue;
      const Eigen::Vector3d row(1.0, std::sin(w * t[i]), std::cos(w * t[i]));
      ata += row * row.transpose();
      atb += row * v[i];
    }
    if (ata(0, 0) < 4) continue;
    const Eigen::Vector3d x = ata.ldlt().solve(atb);
    fits.push_back({begin, end, x[1], x[2]});
  }
  return fits;
}

double MeanAmplitude(const std::vector<BlockFit>& fits) {
  double sum = 0;
  for (const BlockFit& b : fits) sum += std::hypot(b.a, b.b);
  return fits.empty() ? 0.0 : sum / static_cast<double>(fits.size());
}

// A peak of one channel's spectrum: bin, amplitude, prominence, and its
// frequency between the bins (PeakFrequency).
struct Peak {
  Eigen::Index bin;
  double amplitude, prominence;
  int harmonic;
  double frequency_hz;
};

// The frequency of the peak at bin k between its neighbours: a Hann
// window's peak is nearly Gaussian, so a parabola through the logarithms
// of the three amplitudes places it within a few hundredths of a bin. A
// short record's bins are coarse (three cycles at 2 kHz, 4096 samples:
// 0.49 Hz apart), and a line removed at the bin's frequency leaves much of
// itself (0.2 Hz off drifts 0.4 of a turn in a 2 s block).
double PeakFrequency(const std::vector<double>& amp,
                     Eigen::Index k,
                     double df) {
  const double a = amp[k - 1], b = amp[k], c = amp[k + 1];
  if (!(a > 0 && b > 0 && c > 0)) return k * df;
  const double la = std::log(a), lb = std::log(b), lc = std::log(c);
  const double curve = la - 2 * lb + lc;
  if (!(curve < 0)) return k * df;
  const double d = std::clamp(0.5 * (la - lc) / curve, -0.5, 0.5);
  return (k + d) * df;
}

// The channel's lines: local maxima far above the floor and above their
// neighbours (harmonics of the same parity near a harmonic of the drive).
std::vector<Peak> ChannelPeaks(const std::vector<double>& amp,
                               double df,
                               double drive_hz,
                               const PeriodicLineOptions& o) {
  const Eigen::Index bins = static_cast<Eigen::Index>(amp.size());
  // The floor: medians of blocks of about 1 Hz.
  const Eigen::Index block =
      std::max<Eigen::Index>(16, static_cast<Eigen::Index>(1.0 / df));
  std::vector<double> floor((bins + block - 1) / block);
  for (size_t b = 0; b < floor.size(); ++b) {
    const Eigen::Index lo = static_cast<Eigen::Index>(b) * block;
    floor[b] = Median(std::vector<double>(
        amp.begin() + lo, amp.begin() + std::min(bins, lo + block)));
  }
  const Eigen::Index near = std::max<Eigen::Index>(
      3, static_cast<Eigen::Index>(std::ceil(0.05 * drive_hz / df)));
  auto peak_near = [&](double f) {
    const Eigen::Index c = static_cast<Eigen::Index>(std::llround(f / df));
    double m = 0;
    for (Eigen::Index k = std::max<Eigen::Index>(0, c - near);
         k <= std::min(bins - 1, c + near);
         ++k)
      m = std::max(m, amp[k]);
    return m;
  };
  std::vector<Peak> peaks;
  const Eigen::Index first =
      static_cast<Eigen::Index>(std::ceil(o.min_harmonic * drive_hz / df));
  const Eigen::Index last = static_cast<Eigen::Index>(0.9 * (bins - 1));
  for (Eigen::Index k = std::max<Eigen::Index>(1, first); k < last; ++k) {
    if (amp[k] < amp[k - 1] || amp[k] < amp[k + 1]) continue;
    const double fl = std::max(floor[k / block], 1e-12);
    if (amp[k] < o.min_over_floor * fl) continue;
    const double f = k * df;
    const int n = static_cast<int>(std::llround(f / drive_hz));
    Peak p{k, amp[k], amp[k] / fl, 0, PeakFrequency(amp, k, df)};
    if (std::abs(f - n * drive_hz) <= near * df) {
      // The loop's own harmonic, unless it stands above its neighbours.
      if (amp[k] < peak_near(n * drive_hz)) continue;  // not the top here
      std::vector<double> around;
      for (int j : {-6, -4, -2, 2, 4, 6}) {
        if (n + j > 0) around.push_back(peak_near((n + j) * drive_hz));
      }
      p.prominence = amp[k] / std::max(Median(around), 1e-12);
      // Locked to the drive: within two bins of its harmonic.
      if (std::abs(f - n * drive_hz) <= 2 * df) p.harmonic = n;
    }
    if (p.prominence >= o.min_prominence) peaks.push_back(p);
  }
  return peaks;
}

}  // namespace

std::string PeriodicLine::Describe() const {
  return fmt::format(
      "{:.2f} Hz (Q {:.3f} N, P {:.3f} N{}; {:.0f}x its neighbours)",
      frequency_hz,
      q_amplitude_n,
      p_amplitude_n,
      drive_harmonic > 0
          ? fmt::format(", at the drive's harmonic {}", drive_harmonic)
          : std::string(),
      prominence);
}

std::vector<PeriodicLine> FindPeriodicLines(const ForceRecord& record,
                                            double drive_hz,
                                            const PeriodicLineOptions& o) {
  std::vector<PeriodicLine> lines;
  const Eigen::Index most =
      std::min<Eigen::Index>(record.size(), o.window_samples);
  const Eigen::Index n =
      o.power_of_two ? PowerOfTwoLength(most) : SmoothLength(most);
  if (n < 1024 || !(drive_hz > 0)) return lines;
  const Eigen::Index all_n = record.size();
  const double duration = record.time_s[all_n - 1] - record.time_s[0];
  if (!(duration > 0)) return lines;
  const double df = (all_n - 1) / duration / n;  // fs / n
  std::vector<Peak> all;
  for (const std::vector<double>& amp : AmplitudeSpectra(record, n)) {
    const std::vector<Peak> p = ChannelPeaks(amp, df, drive_hz, o);
    all.insert(all.end(), p.begin(), p.end());
  }
  std::sort(all.begin(), all.end(), [](const Peak& a, const Peak& b) {
    return a.amplitude > b.amplitude;
  });
  for (const Peak& p : all) {
    const double f = p.bin * df;
    bool seen = false;
    for (PeriodicLine& l : lines) {
      if (std::abs(l.frequency_hz - f) <= 3 * df) {
        l.prominence = std::max(l.prominence, p.prominence);
        seen = true;
      }
    }
    if (seen || static_cast<int>(lines.size()) >= o.max_lines) continue;
    PeriodicLine l;
    l.frequency_hz = p.frequency_hz;
    l.prominence = p.prominence;
    l.drive_harmonic = p.harmonic;
    l.q_amplitude_n = MeanAmplitude(
        FitBlocks(record.time_s, record.tangential_n, l.frequency_hz));
    l.p_amplitude_n = MeanAmplitude(
        FitBlocks(record.time_s, record.normal_n, l.frequency_hz));
    lines.push_back(l);
  }
  return lines;
}

std::pair<double, double> NotchLine(ForceRecord* record, double f) {
  std::pair<double, double> removed{0.0, 0.0};
  if (!(f > 0)) return removed;
  const double w = 2 * kPi * f;
  int which = 0;
  for (Eigen::VectorXd* ch : {&record->tangential_n, &record->normal_n}) {
    const std::vector<BlockFit> fits = FitBlocks(record->time_s, *ch, f);
    for (const BlockFit& b : fits) {
      for (Eigen::Index i = b.begin; i < b.end; ++i) {
        const double t = record->time_s[i];
        (*ch)[i] -= b.a * std::sin(w * t) + b.b * std::cos(w * t);
      }
    }
    (which++ == 0 ? removed.first : removed.second) = MeanAmplitude(fits);
  }
  return removed;
}

}  // namespace wearscar::force
