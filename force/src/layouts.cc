#include "layouts.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

// ---------------------------------------------------------------------------
// The instruments' layouts. The first whose rule matches names the layout.

struct LayoutDescription {
  const char* kind;
  bool (*matches)(const LayoutFacts& facts);
};

bool Has(const std::string& text, const char* part) {
  return text.find(part) != std::string::npos;
}

constexpr LayoutDescription kLayouts[] = {
    // Rtec MFT: DAQ.Fx, DAQ.Fz, Piezo X, RecipeStep.
    {"rtec",
     [](const LayoutFacts& f) {
       return Has(f.names, "daq.") || Has(f.names, "recipestep");
     }},
    // Bruker/CETR UMT: a units row in gram-force.
    {"bruker",
     [](const LayoutFacts& f) {
       return f.units_row && (Has(f.units, "gf|") || Has(f.units, "g|"));
     }},
    // Anton Paar TRB: tab separated, "Friction force".
    {"anton-paar",
     [](const LayoutFacts& f) {
       return f.delimiter == '\t' && Has(f.names, "friction force");
     }},
    // A home-built rig: no time column, the rate in the metadata.
    {"home-built", [](const LayoutFacts& f) { return f.metadata_rate_hz > 0; }},
};

// ---------------------------------------------------------------------------
// Column names. A name is matched as lower case, whole (kEquals), by a
// word of it (kWord: letters and digits between other characters) or by a
// part (kPart). The best score over the patterns of a channel is the
// name's score.

enum class Match { kEquals, kWord, kPart };

struct ColumnPattern {
  Channel channel;
  int score;
  Match match;
  const char* text;
  const char* unless_word = nullptr;  // no match when the name has it
};

constexpr ColumnPattern kColumnPatterns[] = {
    {kTime, 3, Match::kWord, "timestamp"},
    {kTime, 3, Match::kEquals, "time"},
    {kTime, 3, Match::kEquals, "t"},
    {kTime, 2, Match::kWord, "time"},
    {kTime, 2, Match::kWord, "zeit"},
    {kTime, 2, Match::kWord, "temps"},
    {kX, 3, Match::kPart, "piezo x"},  // Rtec
    {kX, 3, Match::kWord, "position"},
    {kX, 3, Match::kWord, "displacement"},
    {kX, 2, Match::kEquals, "x"},
    {kX, 2, Match::kWord, "pos"},
    {kX, 2, Match::kWord, "stroke"},
    {kX, 2, Match::kWord, "lvdt"},
    {kX, 2, Match::kWord, "weg"},
    {kX, 2, Match::kWord, "verschiebung"},
    {kX, 2, Match::kWord, "deplacement"},
    {kX, 2, Match::kPart, "d\xc3\xa9placement"},
    {kX, 1, Match::kWord, "x", "fx"},
    {kQ, 3, Match::kWord, "fx"},
    {kQ, 3, Match::kPart, "friction force"},
    {kQ, 3, Match::kPart, "tangential"},
    {kQ, 2, Match::kWord, "friction"},
    {kQ, 2, Match::kWord, "ff"},
    {kQ, 2, Match::kWord, "ft"},
    {kQ, 2, Match::kEquals, "q"},
    {kQ, 2, Match::kWord, "lateral"},
    {kQ, 3, Match::kWord, "reibkraft"},
    {kQ, 3, Match::kWord, "reibungskraft"},
    {kQ, 3, Match::kWord, "tangentialkraft"},
    {kQ, 2, Match::kWord, "frottement"},
    {kP, 3, Match::kWord, "fz"},
    {kP, 3, Match::kPart, "normal force"},
    {kP, 3, Match::kWord, "fn"},
    {kP, 2, Match::kWord, "normal"},
    {kP, 2, Match::kWord, "load"},
    {kP, 2, Match::kEquals, "p"},
    {kP, 3, Match::kWord, "normalkraft"},
    {kP, 3, Match::kPart, "force normale"},
    {kP, 2, Match::kWord, "auflast"},
};

// Never a channel: friction coefficients the instrument computed itself.
constexpr ColumnPattern kNotAChannel[] = {
    {kQ, 0, Match::kWord, "cof"},
    {kQ, 0, Match::kWord, "mu"},
    {kQ, 0, Match::kPart, "coefficient"},
};

// The column that lets the clock restart: Rtec's RecipeStep.
constexpr ColumnPattern kStepColumns[] = {
    {kTime, 1, Match::kPart, "recipestep"},
    {kTime, 1, Match::kEquals, "step"},
};

std::vector<std::string> Words(const std::string& lower) {
  std::vector<std::string> words;
  std::string cur;
  for (char ch : lower) {
    if (std::isalnum(static_cast<unsigned char>(ch))) {
      cur += ch;
    } else if (!cur.empty()) {
      words.push_back(cur);
      cur.clear();
    }
  }
  if (!cur.empty()) words.push_back(cur);
  return words;
}

// A column name, lower case and split into words once.
struct Name {
  explicit Name(const std::string& name)
      : lower(support::Lower(name)), words(Words(lower)) {}
  bool HasWord(const char* w) const {
    return std::find(words.begin(), words.end(), w) != words.end();
  }
  bool Matches(const ColumnPattern& p) const {
    if (p.unless_word != nullptr && HasWord(p.unless_word)) return false;
    switch (p.match) {
      case Match::kEquals:
        return lower == p.text;
      case Match::kWord:
        return HasWord(p.text);
      case Match::kPart:
        return lower.find(p.text) != std::string::npos;
    }
    return false;
  }
  std::string lower;
  std::vector<std::string> words;
};

}  // namespace

std::string LayoutKind(const LayoutFacts& facts) {
  for (const LayoutDescription& layout : kLayouts) {
    if (layout.matches(facts)) return layout.kind;
  }
  return "delimited";
}

bool IsComputedCoefficient(const std::string& name) {
  const Name n(name);
  return std::any_of(std::begin(kNotAChannel),
                     std::end(kNotAChannel),
                     [&](const ColumnPattern& p) { return n.Matches(p); });
}

int MatchScore(Channel channel, const std::string& name) {
  const Name n(name);
  if (IsComputedCoefficient(name)) return 0;
  int best = 0;
  for (const ColumnPattern& p : kColumnPatterns) {
    if (p.channel == channel && p.score > best && n.Matches(p)) best = p.score;
  }
  return best;
}

bool IsStepColumn(const std::string& name) {
  const Name n(name);
  return std::any_of(std::begin(kStepColumns),
                     std::end(kStepColumns),
                     [&](const ColumnPattern& p) { return n.Matches(p); });
}

}  // namespace wearscar::force::internal
