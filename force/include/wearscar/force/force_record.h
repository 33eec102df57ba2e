#pragma once

#include <Eigen/Core>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wearscar::force {

// Raised for bad force files and bad user input. The message names the file,
// the line (and column where it applies), what was found and what was
// expected.
class ForceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A test condition the file's header states in words ("Track length 5 mm",
// "Cycles: 3000"): what, its value in mm (stroke: peak to peak), a count
// (cycles), N (load) or Hz (frequency), and the line it was read from.
struct StatedFact {
  // "stroke" (mm), "cycles", "load" (N), "frequency" (Hz), "spring" (N/mm),
  // "radius" (mm: a rotary test's track)
  std::string what;
  double value = 0.0;
  std::string line;     // as written: its label, number and unit
  int line_number = 0;  // from 1
};

// Where a record came from and what the reader saw on the way.
struct ForceMetadata {
  std::string source;             // file path, or "simulator"
  std::string layout;             // "delimited", "rtec", "bruker", ...
  double sampling_rate_hz = 0.0;  // 0 when unknown
  // Channel header and unit as found in the file, for time, x, Q and P
  // (and the depth when the file has one).
  std::vector<std::string> channel_names;
  std::vector<std::string> channel_units;
  // Units the file did not state, guessed from the values (time, x, Q, P,
  // depth; each guess is also a warning saying why).
  std::array<bool, 5> unit_guessed = {false, false, false, false, false};
  // The depth channel's sign as read: true when its name says it grows
  // into the specimen (a penetration depth), false for a height (Z).
  bool depth_is_penetration = true;
  bool time_rebuilt = false;  // no time column; built from a rate
  // The line (from 0) of the first data row: the lines before it are the
  // header, units and metadata (what rows appended later are read with).
  int first_data_line = 0;
  bool normal_sign_flipped = false;  // P was negative in compression
  int clock_restarts_joined = 0;     // Rtec RecipeStep, CETR step restarts
  int blocks_joined = 0;             // repeated header blocks (CETR test steps)
  int rows_dropped = 0;              // lenient mode only
  // Rows a second thread parsed (ReadForceOptions::threads); the record is
  // the same whoever parsed them.
  long rows_on_second_thread = 0;
  std::vector<std::string> warnings;
  // Test conditions the header states; the analysis checks them against
  // the data.
  std::vector<StatedFact> stated;
  // The file's SHA-256 (64 hex digits) when its reader's caller computed
  // it from the bytes read (ReadForceOptions::on_bytes); empty otherwise.
  std::string sha256;
};

// A reciprocating test in the library's units: seconds, mm, N. Q is the
// tangential (friction) force, P the normal force, compression positive.
// Invalid samples are NaN; every vector has the same length.
struct ForceRecord {
  Eigen::VectorXd time_s;
  Eigen::VectorXd x_mm;
  Eigen::VectorXd tangential_n;  // Q
  Eigen::VectorXd normal_n;      // P
  // The ball's vertical position where the rig logs it (an LVDT, a
  // "Penetration Depth"), mm, positive into the specimen; empty without.
  Eigen::VectorXd depth_mm;
  ForceMetadata metadata;

  Eigen::Index size() const { return time_s.size(); }
  bool has_depth() const { return depth_mm.size() > 0; }
  // The channels have one length (what every analysis requires).
  bool IsConsistent() const {
    return x_mm.size() == time_s.size() &&
           tangential_n.size() == time_s.size() &&
           normal_n.size() == time_s.size() &&
           (depth_mm.size() == 0 || depth_mm.size() == time_s.size());
  }
};

// A record from four channels already in s, mm and N (arrays in memory, a
// simulator's output): the metadata names the source, the layout and the
// channels (time_s, x_mm, Q_N, P_N). Throws ForceError when the four lengths
// differ.
inline ForceRecord RecordFromChannels(Eigen::VectorXd time_s,
                                      Eigen::VectorXd x_mm,
                                      Eigen::VectorXd tangential_n,
                                      Eigen::VectorXd normal_n,
                                      std::string source,
                                      std::string layout,
                                      double sampling_rate_hz = 0.0) {
  ForceRecord r;
  r.time_s = std::move(time_s);
  r.x_mm = std::move(x_mm);
  r.tangential_n = std::move(tangential_n);
  r.normal_n = std::move(normal_n);
  if (!r.IsConsistent()) {
    throw ForceError(source + ": the channels time_s, x_mm, Q and P have " +
                     "different lengths; expected one length");
  }
  r.metadata.source = std::move(source);
  r.metadata.layout = std::move(layout);
  r.metadata.sampling_rate_hz = sampling_rate_hz;
  r.metadata.channel_names = {"time_s", "x_mm", "Q_N", "P_N"};
  r.metadata.channel_units = {"s", "mm", "N", "N"};
  return r;
}

// The same from any struct with the four channels, a depth_mm (empty
// without one) and `source` and `sampling_rate_hz` members (the
// simulator's SimulatedChannels): moved from when given as an rvalue,
// copied otherwise.
template <class Channels>
ForceRecord RecordFromChannels(Channels&& c, std::string layout) {
  const double rate = c.sampling_rate_hz;
  std::string source = c.source;
  Eigen::VectorXd depth = std::forward<Channels>(c).depth_mm;
  ForceRecord r = RecordFromChannels(std::forward<Channels>(c).time_s,
                                     std::forward<Channels>(c).x_mm,
                                     std::forward<Channels>(c).tangential_n,
                                     std::forward<Channels>(c).normal_n,
                                     std::move(source),
                                     std::move(layout),
                                     rate);
  if (depth.size() > 0) {
    if (depth.size() != r.size())
      throw ForceError(r.metadata.source +
                       ": the depth channel's length differs from the "
                       "others'; expected one length");
    r.depth_mm = std::move(depth);
    r.metadata.channel_names.push_back("depth_mm");
    r.metadata.channel_units.push_back("mm");
  }
  return r;
}

}  // namespace wearscar::force
