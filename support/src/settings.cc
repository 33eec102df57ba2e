#include "wearscar/support/settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "wearscar/support/text.h"

namespace wearscar::support {
namespace {

// Levenshtein's distance between two short names.
size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1,
                         row[j - 1] + 1,
                         diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

double ParseNumber(std::string_view text, double lo, double hi) {
  const std::string s(Trim(text));
  char* end = nullptr;
  errno = 0;
  const double v = s.empty() ? NAN : std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
    throw SettingError(
        fmt::format("found '{}'; expected a number from {} to {}",
                    Printable(text),
                    ShowNumber(lo),
                    ShowNumber(hi)));
  }
  if (v < lo || v > hi) {
    throw SettingError(fmt::format("found {}; expected a number from {} to {}",
                                   ShowNumber(v),
                                   ShowNumber(lo),
                                   ShowNumber(hi)));
  }
  return v;
}

long ParseInteger(std::string_view text, long lo, long hi) {
  const std::string s(Trim(text));
  char* end = nullptr;
  errno = 0;
  const long v = s.empty() ? 0 : std::strtol(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE) {
    throw SettingError(
        fmt::format("found '{}'; expected a whole number from {} to {}",
                    Printable(text),
                    lo,
                    hi));
  }
  if (v < lo || v > hi) {
    throw SettingError(fmt::format(
        "found {}; expected a whole number from {} to {}", v, lo, hi));
  }
  return v;
}

bool ParseFlag(std::string_view text) {
  const std::string s = Lower(Trim(text));
  if (s == "true" || s == "1" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "0" || s == "no" || s == "off") return false;
  throw SettingError(
      fmt::format("found '{}'; expected true or false", Printable(text)));
}

std::string ParseChoice(std::string_view text,
                        const std::vector<std::string>& choices) {
  const std::string s(Trim(text));
  if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
  std::string list;
  for (size_t i = 0; i < choices.size(); ++i) {
    list += (i == 0                    ? ""
             : i + 1 == choices.size() ? " or "
                                       : ", ") +
            choices[i];
  }
  throw SettingError(
      fmt::format("found '{}'; expected {}", Printable(text), list));
}

std::string ShowNumber(double v) { return fmt::format("{:g}", v); }

std::vector<std::string> ClosestNames(const std::vector<std::string>& names,
                                      std::string_view name) {
  std::vector<std::pair<size_t, std::string>> scored;
  for (const std::string& n : names) {
    const size_t d = EditDistance(n, name);
    const bool prefix = name.size() >= 3 && n.rfind(name, 0) == 0;
    if (d <= 2 || prefix) scored.emplace_back(prefix ? 0 : d, n);
  }
  std::stable_sort(scored.begin(), scored.end(), [](auto& a, auto& b) {
    return a.first < b.first;
  });
  std::vector<std::string> out;
  for (auto& [d, n] : scored) out.push_back(n);
  return out;
}

}  // namespace wearscar::support
