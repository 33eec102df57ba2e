#pragma once
// Periodic lines in the force channels that the drive's motion does not
// make: mains pick-up (50/60 Hz and harmonics), a rig's resonance. A line
// at an exact harmonic of the drive repeats every cycle like the friction
// loop itself, so it is found in the spectrum, not by averaging cycles: a
// harmonic of the drive stands out against the harmonics of the same
// parity around it (the loop's harmonics fall smoothly), any other line
// against the spectrum's floor around it.

#include <string>
#include <vector>

#include "wearscar/force/force_record.h"

namespace wearscar::force {

struct PeriodicLine {
  double frequency_hz = 0;
  double q_amplitude_n = 0, p_amplitude_n = 0;  // least-squares sinusoids
  // The line's spectral amplitude over its neighbours' median (the larger
  // of the two channels).
  double prominence = 0;
  int drive_harmonic = 0;        // n when the line sits at n x the drive's rate
  std::string Describe() const;  // "50.00 Hz (Q 0.030 N, P 0.030 N, ...)"
};

struct PeriodicLineOptions {
  // Lines are sought above this multiple of the drive's rate (below it the
  // loop's own harmonics dominate) and below 0.9 x Nyquist.
  double min_harmonic = 20.0;
  // A line stands this far above its neighbours' median ...
  double min_prominence = 8.0;
  // ... and above this many times the spectrum's floor around it.
  double min_over_floor = 8.0;
  int max_lines = 5;
  // The spectrum's window, samples (at most; rounded down to a length
  // whose prime factors are 2, 3, 5): a longer record is covered by
  // windows whose amplitudes are averaged. 2^18 resolves 0.008 Hz at 2 kHz,
  // far finer than the drive's harmonics are apart.
  Eigen::Index window_samples = Eigen::Index{1} << 18;
  // The window rounded down to a power of two instead (a record longer
  // than it is covered by two or more): records of slightly different
  // lengths, a live window's, then share one FFT plan.
  bool power_of_two = false;
};

// The lines of Q and P over the record (Hann-windowed spectra averaged
// over windows that cover the whole record), strongest first. drive_hz: the
// drive's cycle rate.
std::vector<PeriodicLine> FindPeriodicLines(
    const ForceRecord& record,
    double drive_hz,
    const PeriodicLineOptions& options = {});

// Removes a line from Q and P: a sinusoid at `frequency_hz` fitted by least
// squares in blocks of about two seconds (a mains frequency drifts) and
// subtracted. At an exact harmonic of the drive it takes the loop's own
// content at that frequency with it (small at the harmonics lines are
// sought at). Returns the mean amplitudes removed (Q, P) in N.
std::pair<double, double> NotchLine(ForceRecord* record, double frequency_hz);

}  // namespace wearscar::force
