#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace wearscar::force {

// The channels a force export's columns are matched to.
enum class ForceChannel {
  kTime,
  kX,           // the reciprocating displacement
  kTangential,  // Q, the friction force
  kNormal,      // P, the normal force
  kDepth,       // the ball's vertical position (penetration depth, Z)
  kStep,        // a recipe step: the clock may restart when it changes
  kNotAChannel  // a friction coefficient the instrument computed itself
};

// How a column word matches a header name, lower case: the whole name, a
// word of it (letters and digits between other characters) or any part.
enum class WordMatch { kEquals, kWord, kPart };

// A word that names a channel's column. Among the columns, the best score
// over every layout's words takes the channel (1-3: how sure).
struct ColumnWord {
  ForceChannel channel;
  int score;
  WordMatch match;
  std::string text;         // lower case; UTF-8
  std::string unless_word;  // no match when the name has this word
};

// How a layout's clock runs.
enum class ClockRule {
  kIncreasing,         // one clock, strictly increasing
  kRestartsWithStep,   // restarts when its kStep column changes: joined
  kRestartsWithBlock,  // each test step repeats the header block and
                       // restarts the clock: joined
};

// What the layout detection found in a file's head, for the layouts'
// detect scores.
struct LayoutFacts {
  char delimiter = ',';
  bool units_row = false;
  double metadata_rate_hz = 0;     // a rate stated above the data, or 0
  std::vector<std::string> names;  // the columns' names, lower case
  std::vector<std::string> units;  // their units, lower case ("" unknown)
};

// One tribometer export layout: what the reader's record names
// (ForceMetadata::layout), what the help, the audit and the fuzz seeds
// list. Every layout is read by the same core, which finds the delimiter,
// the decimal mark, the header, the units and the clock in the file
// itself; a layout adds the words of its columns, its units where the file
// states none, and its clock. A new tribometer layout is one entry in
// force/src/layouts.cc.
struct ForceLayout {
  std::string name;                     // "rtec": ForceMetadata::layout
  std::string instruments;              // who writes it, for help and docs
  std::vector<std::string> extensions;  // lower case, with the dot
  std::vector<ColumnWord> column_words;
  // Units taken where a column states none (and its values are plausible
  // in them); empty: inferred from plausibility alone.
  std::string time_unit, x_unit, force_unit;
  ClockRule clock = ClockRule::kIncreasing;
  // How sure the layout is that a file with these facts is its own: 0 no;
  // the highest score names the file's layout (ties: the earlier entry).
  int (*detect)(const LayoutFacts& facts) = nullptr;
  // The head of a file of this layout, as its instrument writes it (docs,
  // tests and the fuzzer's seeds).
  std::string example;
};

// Every layout; the last is the generic delimited export, which scores 1
// on any file.
const std::vector<ForceLayout>& ForceLayouts();

// The layout named `name`, or nullptr.
const ForceLayout* FindForceLayout(std::string_view name);

// The layout with the highest score for `facts`.
const ForceLayout& DetectForceLayout(const LayoutFacts& facts);

// The extensions of force exports over every layout (".csv", ".txt", ...),
// in the registry's order, each once.
std::vector<std::string> ForceExtensions();

}  // namespace wearscar::force
