#include "units.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

std::string Trim(std::string_view s) { return std::string(support::Trim(s)); }

std::string Normalise(std::string_view unit) {
  std::string u = Trim(unit);
  // Strip brackets a units row may keep: "(N)", "[mm]".
  if (u.size() >= 2 && (u.front() == '(' || u.front() == '[')) {
    u = Trim(std::string_view(u).substr(1, u.size() - 2));
  }
  // Micro sign (U+00B5) and Greek mu (U+03BC) in UTF-8, and Greek mu in
  // Shift-JIS (a Japanese Windows export) -> 'u'.
  for (const char* micro : {"\xC2\xB5", "\xCE\xBC", "\x83\xCA"}) {
    size_t pos;
    while ((pos = u.find(micro)) != std::string::npos) u.replace(pos, 2, "u");
  }
  // The micro sign alone in Latin-1 / Windows-1252 (0xB5), what a Windows
  // program writes for "µm" in an ANSI file.
  for (char& c : u) {
    if (static_cast<unsigned char>(c) == 0xB5) c = 'u';
  }
  return u;
}

template <size_t N>
std::optional<double> Lookup(
    std::string_view unit,
    const std::array<std::pair<const char*, double>, N>& table) {
  const std::string u = Normalise(unit);
  for (const auto& [name, factor] : table) {
    if (u == name) return factor;
  }
  std::string lower = u;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  for (const auto& [name, factor] : table) {
    std::string n = name;
    std::transform(n.begin(), n.end(), n.begin(), [](char c) {
      return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    });
    if (lower == n) return factor;
  }
  return std::nullopt;
}

}  // namespace

std::optional<double> LengthToMm(std::string_view unit) {
  static constexpr std::array<std::pair<const char*, double>, 8> kTable{{
      {"mm", 1.0},
      {"um", 1e-3},
      {"micron", 1e-3},
      {"microns", 1e-3},
      {"m", 1e3},
      {"cm", 10.0},
      {"nm", 1e-6},
      {"in", 25.4},
  }};
  return Lookup(unit, kTable);
}

std::optional<double> ForceToN(std::string_view unit) {
  static constexpr std::array<std::pair<const char*, double>, 8> kTable{{
      {"N", 1.0},
      {"mN", 1e-3},
      {"kN", 1e3},
      {"uN", 1e-6},
      {"gf", 9.80665e-3},
      {"g", 9.80665e-3},
      {"kgf", 9.80665},
      {"lbf", 4.4482216152605},
  }};
  return Lookup(unit, kTable);
}

std::optional<double> TimeToS(std::string_view unit) {
  static constexpr std::array<std::pair<const char*, double>, 6> kTable{{
      {"s", 1.0},
      {"sec", 1.0},
      {"ms", 1e-3},
      {"us", 1e-6},
      {"min", 60.0},
      {"h", 3600.0},
  }};
  return Lookup(unit, kTable);
}

void SplitNameAndUnit(std::string_view header,
                      std::string* name,
                      std::string* unit) {
  std::string h = Trim(header);
  unit->clear();
  if (!h.empty() && (h.back() == ')' || h.back() == ']')) {
    const char open = h.back() == ')' ? '(' : '[';
    const size_t pos = h.rfind(open);
    if (pos != std::string::npos) {
      *unit = Normalise(std::string_view(h).substr(pos));
      h = Trim(std::string_view(h).substr(0, pos));
    }
  }
  // "Time, s" (a quoted header cell holding the delimiter), "Position / mm".
  for (const char* sep : {",", "/"}) {
    const size_t at = h.rfind(sep);
    if (!unit->empty() || at == std::string::npos || at == 0) continue;
    const std::string tail = Trim(std::string_view(h).substr(at + 1));
    if (LengthToMm(tail) || ForceToN(tail) || TimeToS(tail)) {
      *unit = tail;
      h = Trim(std::string_view(h).substr(0, at));
    }
  }
  // Our own writers (and many scripts) use a unit suffix: "x_mm", "Q_N".
  const size_t us = h.rfind('_');
  if (unit->empty() && us != std::string::npos && us > 0 && us + 1 < h.size()) {
    const std::string_view suffix = std::string_view(h).substr(us + 1);
    if (LengthToMm(suffix) || ForceToN(suffix) || TimeToS(suffix)) {
      *unit = std::string(suffix);
      h = h.substr(0, us);
    }
  }
  *name = h;
}

}  // namespace wearscar::force::internal
