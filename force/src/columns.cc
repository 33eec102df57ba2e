#include "columns.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>

#include "fields.h"
#include "wearscar/force/layouts.h"
#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

using support::Lower;
using support::Printable;

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
      : lower(Lower(name)), words(Words(lower)) {}
  bool HasWord(const std::string& w) const {
    return std::find(words.begin(), words.end(), w) != words.end();
  }
  bool Matches(const ColumnWord& p) const {
    if (!p.unless_word.empty() && HasWord(p.unless_word)) return false;
    switch (p.match) {
      case WordMatch::kEquals:
        return lower == p.text;
      case WordMatch::kWord:
        return HasWord(p.text);
      case WordMatch::kPart:
        return lower.find(p.text) != std::string::npos;
    }
    return false;
  }
  std::string lower;
  std::vector<std::string> words;
};

// A friction coefficient the instrument computed (COF, mu): never a
// channel.
bool IsComputedCoefficient(const std::string& name) {
  const Name n(name);
  for (const ForceLayout& l : ForceLayouts()) {
    for (const ColumnWord& w : l.column_words) {
      if (w.channel == ForceChannel::kNotAChannel && n.Matches(w)) return true;
    }
  }
  return false;
}

// The best score over every layout's words for `channel`; 0 for a column
// the instrument computed (a friction coefficient is never a channel).
int MatchScore(ForceChannel channel, const std::string& name) {
  if (IsComputedCoefficient(name)) return 0;
  const Name n(name);
  int best = 0;
  for (const ForceLayout& l : ForceLayouts()) {
    for (const ColumnWord& w : l.column_words) {
      if (w.channel == channel && w.score > best && n.Matches(w))
        best = w.score;
    }
  }
  return best;
}

ForceChannel Public(Channel channel) {
  constexpr ForceChannel kPublic[] = {ForceChannel::kTime,
                                      ForceChannel::kX,
                                      ForceChannel::kTangential,
                                      ForceChannel::kNormal,
                                      ForceChannel::kDepth};
  return kPublic[channel];
}

int FindOverride(const std::string& spec,
                 const Layout& layout,
                 const std::string& file,
                 Channel channel) {
  if (spec.size() > 1 && spec[0] == '#') {
    int col = 0;
    const auto r =
        std::from_chars(spec.data() + 1, spec.data() + spec.size(), col);
    if (r.ec != std::errc() || col < 1 ||
        col > static_cast<int>(layout.names.size())) {
      throw ForceError(
          fmt::format("{}: column override '{}' for {} is not a "
                      "column number between 1 and {}",
                      file,
                      spec,
                      ChannelLabel(channel),
                      layout.names.size()));
    }
    return col - 1;
  }
  // The name as the reader split it ("x" of "x_mm"), or as the header
  // wrote it with its unit: x_mm, "x (mm)", "x [mm]", x/mm.
  const std::string wanted = Lower(spec);
  std::string known;
  for (std::size_t c = 0; c < layout.names.size(); ++c) {
    const std::string name = Lower(layout.names[c]);
    const std::string unit =
        c < layout.units.size() ? Lower(layout.units[c]) : std::string();
    if (wanted == name) return static_cast<int>(c);
    if (!unit.empty()) {
      for (const std::string& form : {name + "_" + unit,
                                      name + " (" + unit + ")",
                                      name + " [" + unit + "]",
                                      name + "/" + unit}) {
        if (wanted == form) return static_cast<int>(c);
      }
    }
    known += (known.empty() ? "" : ", ") + layout.names[c];
    if (!unit.empty()) known += " (" + layout.units[c] + ")";
  }
  throw ForceError(
      fmt::format("{}: no column named '{}' for {}; the header has: {}",
                  file,
                  spec,
                  ChannelLabel(channel),
                  known));
}

// "a, b or c".
std::string ListOf(const std::vector<std::string>& items) {
  std::string list;
  for (std::size_t i = 0; i < items.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
  }
  return list;
}

}  // namespace

const char* ChannelLabel(Channel channel) {
  constexpr const char* kLabel[] = {
      "time", "position x", "tangential force Q", "normal force P", "depth"};
  return kLabel[channel];
}

Columns ChooseColumns(const Layout& layout,
                      const ReadForceOptions& options,
                      const std::string& name) {
  Columns column = {-1, -1, -1, -1, -1};
  const std::string* overrides[kChannels] = {&options.time_column,
                                             &options.x_column,
                                             &options.tangential_column,
                                             &options.normal_column,
                                             &options.depth_column};
  // "none" for the time: no time column, the clock from the sampling rate;
  // for the depth: none read.
  auto none = [&](int ch) {
    return (ch == kTime || ch == kDepth) && Lower(*overrides[ch]) == "none";
  };
  for (int ch = 0; ch < kChannels; ++ch) {
    if (!overrides[ch]->empty() && !none(ch))
      column[ch] = FindOverride(*overrides[ch], layout, name, Channel(ch));
  }
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column[ch] >= 0 || none(ch)) continue;
    int best = -1, best_score = 0;
    for (int c = 0; c < static_cast<int>(layout.names.size()); ++c) {
      if (std::find(column.begin(), column.end(), c) != column.end()) continue;
      const int s = MatchScore(Public(Channel(ch)), layout.names[c]);
      if (s > best_score) best = c, best_score = s;
    }
    column[ch] = best;
  }
  return column;
}

void RequireChannels(const Columns& column,
                     const Layout& layout,
                     const std::string& name) {
  std::vector<std::string> missing;
  for (int ch = kX; ch <= kP; ++ch) {
    if (column[ch] < 0) missing.push_back(ChannelLabel(Channel(ch)));
  }
  if (missing.empty()) return;
  // The named columns (at most 12) and how many have no name: a height
  // map's CSV has one name and a thousand empty cells.
  std::string known;
  int named = 0, unnamed = 0;
  for (const auto& nm : layout.names) {
    if (nm.find_first_not_of(" \t") == std::string::npos) {
      ++unnamed;
    } else if (++named <= 12) {
      known += (known.empty() ? "" : ", ") + nm;
    }
  }
  if (named > 12) known += fmt::format(" and {} more", named - 12);
  if (unnamed > 0) {
    known += fmt::format("{}{} unnamed column{}",
                         known.empty() ? "" : ", with ",
                         unnamed,
                         unnamed == 1 ? "" : "s");
  }
  if (layout.header_line < 0) known = "(no header row)";
  const bool has_cof = std::any_of(
      layout.names.begin(), layout.names.end(), IsComputedCoefficient);
  throw ForceError(fmt::format(
      "{}: line {}: no column for {}; the method needs a reciprocating "
      "displacement and the tangential and normal forces, and the file "
      "has: {}{} ({})",
      name,
      (layout.header_line >= 0 ? layout.header_line : 0) + 1,
      ListOf(missing),
      known,
      has_cof && column[kQ] < 0
          ? "; a friction coefficient alone cannot carry the method"
          : "",
      layout.header_line < 0
          ? "name the columns by number, e.g. --columns "
            "time=#1,x=#2,q=#3,p=#4"
          : "give a column explicitly if it is there under another name, "
            "e.g. --columns x=NAME"));
}

Clock FindClock(const std::vector<std::string>& head,
                const Columns& column,
                const Layout& layout) {
  Clock clock;
  if (column[kTime] < 0) return clock;
  std::vector<std::string_view> cells;
  Split(head[layout.first_data_line], layout.delimiter, &cells);
  if (column[kTime] >= static_cast<int>(cells.size())) return clock;
  const std::string_view cell = cells[column[kTime]];
  double number;
  if (ParseCell(cell, layout.decimal, &number)) return clock;
  if (ParseClock(cell, &clock.origin_days, &clock.origin_seconds, &clock.dated))
    clock.field = column[kTime];
  return clock;
}

void RequireNumbers(const std::vector<std::string>& head,
                    const Columns& column,
                    const Layout& layout,
                    const Clock& clock,
                    const std::string& name) {
  std::vector<std::string_view> cells;
  const int n = static_cast<int>(head.size());
  for (int i = layout.first_data_line;
       i < std::min(n, layout.first_data_line + 3);
       ++i) {
    Split(head[i], layout.delimiter, &cells);
    for (int ch = 0; ch < kChannels; ++ch) {
      if (column[ch] < 0 || column[ch] >= static_cast<int>(cells.size()))
        continue;
      const std::string_view cell = cells[column[ch]];
      double value;
      if (column[ch] == clock.field ? ClockSeconds(clock, cell, &value)
                                    : ParseCell(cell, layout.decimal, &value))
        continue;
      throw ForceError(fmt::format(
          "{}: line {}, column {} ('{}', taken as {}): found text '{}'; "
          "expected a number{} (give the {} column explicitly if another "
          "holds it{})",
          name,
          i + 1,
          column[ch] + 1,
          Printable(layout.names[column[ch]]),
          ChannelLabel(Channel(ch)),
          Printable(cell),
          layout.decimal == ',' ? " with a decimal comma" : "",
          ChannelLabel(Channel(ch)),
          ch == kTime ? ", or --time-column none and the sampling rate" : ""));
    }
  }
}

int FindStepColumn(const Layout& layout) {
  int step_column = -1;
  for (int c = 0; c < static_cast<int>(layout.names.size()); ++c) {
    if (MatchScore(ForceChannel::kStep, layout.names[c]) > 0) step_column = c;
  }
  return step_column;
}

}  // namespace wearscar::force::internal
