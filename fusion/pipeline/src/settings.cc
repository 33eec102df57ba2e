#include "wearscar/fusion/settings.h"

#include <fmt/format.h>

#include <algorithm>

#include "scan_settings.h"

namespace wearscar::fusion {
namespace {

using internal::ScanFileSettings;
using internal::TrackSettings;

using support::FlagSetting;
using support::IntegerSetting;
using support::NumberSetting;
using support::SettingError;
using support::TextSetting;
using S = support::Setting<TestSettings>;
using T = TestSettings;

S In(unsigned sections, S s) {
  s.sections = sections;
  return s;
}

// A unit of the force file, checked as the reader checks it.
S UnitSetting(std::string name,
              std::string help,
              std::string force::ReadForceOptions::*field) {
  return {std::move(name),
          "Force file",
          std::move(help),
          "TEXT",
          ~0u,
          [field](T* t, const std::string& text) {
            force::ReadForceOptions probe;
            probe.*field = text;
            std::string why;
            if (!probe.IsValid(&why))
              throw SettingError(fmt::format("found '{}': {}", text, why));
            t->read_force.*field = text;
          },
          [](const T&) { return std::string(); }};
}

// --columns time=NAME,x=NAME:UNIT,...: the column overrides and units (a
// column name may hold a colon; the unit is after the last one).
void ApplyColumns(const std::string& columns, force::ReadForceOptions* r) {
  std::string rest = columns;
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value =
        eq == std::string::npos ? "" : item.substr(eq + 1);
    std::string* slot = key == "time"    ? &r->time_column
                        : key == "x"     ? &r->x_column
                        : key == "q"     ? &r->tangential_column
                        : key == "p"     ? &r->normal_column
                        : key == "depth" ? &r->depth_column
                                         : nullptr;
    std::string column = value, unit;
    const size_t colon = value.rfind(':');
    if (colon != std::string::npos && colon > 0 && colon + 1 < value.size()) {
      column = value.substr(0, colon);
      unit = value.substr(colon + 1);
    }
    if (!slot || column.empty()) {
      throw SettingError(fmt::format(
          "found '{}' in '{}'; expected time=, x=, q=, p= or depth= followed "
          "by a column name or #N (and :UNIT)",
          item,
          columns));
    }
    *slot = column;
    if (unit.empty()) continue;
    std::string* unit_slot = key == "time"    ? &r->time_unit
                             : key == "x"     ? &r->x_unit
                             : key == "depth" ? &r->depth_unit
                                              : &r->force_unit;
    if (!unit_slot->empty() && *unit_slot != unit) {
      throw SettingError(fmt::format(
          "'{}' gives unit '{}' but another setting says '{}'; expected one "
          "unit for both forces",
          item,
          unit,
          *unit_slot));
    }
    *unit_slot = unit;
  }
}

// --notch: comma-separated frequencies, Hz.
S NotchSetting(const char* group) {
  return {"notch",
          group,
          "Periodic lines to remove from Q and P before the analysis, Hz, "
          "comma-separated (mains pick-up: 50 or 60): a sinusoid fitted in "
          "blocks of about 2 s and subtracted. Without it, the lines found "
          "that the drive does not make are removed, said first; 'none' "
          "keeps them (warned about)",
          "TEXT",
          ~0u,
          [](T* t, const std::string& text) {
            t->fuse.notch_hz.clear();
            t->fuse.notch_found_lines = text != "none";
            if (text == "none") return;
            size_t at = 0;
            while (at <= text.size()) {
              const size_t comma = std::min(text.find(',', at), text.size());
              t->fuse.notch_hz.push_back(support::ParseNumber(
                  std::string_view(text).substr(at, comma - at), 0.001, 1e6));
              at = comma + 1;
            }
          },
          [](const T&) { return std::string(); }};
}

std::vector<S> ForceFileSettings() {
  const char* g = "Force file";
  auto column = [g](const char* name, const char* help, auto member) {
    return TextSetting<T>(name, g, help, [member](T& t) -> std::string& {
      return t.read_force.*member;
    });
  };
  using R = force::ReadForceOptions;
  return {
      column("time-column",
             "Time column name or #N; none: the clock from the file's "
             "sampling rate or --rate",
             &R::time_column),
      column("x-column", "Displacement column name or #N", &R::x_column),
      column("q-column",
             "Friction force column name or #N",
             &R::tangential_column),
      column("p-column", "Normal force column name or #N", &R::normal_column),
      column("depth-column",
             "Depth column (the ball's vertical position: penetration "
             "depth, Z, LVDT) name or #N; none: read none",
             &R::depth_column),
      UnitSetting("x-unit",
                  "Unit of the displacement (mm, um, m); default: the "
                  "file's, else inferred from a plausible stroke with a "
                  "warning",
                  &R::x_unit),
      UnitSetting("force-unit",
                  "Unit of both forces (N, mN, kN, gf); default: the "
                  "file's, else inferred",
                  &R::force_unit),
      UnitSetting("time-unit",
                  "Unit of the time column (s, ms, min); default: the "
                  "file's, else inferred",
                  &R::time_unit),
      {"columns",
       g,
       "Column overrides in one go: time=NAME,x=NAME,q=NAME,p=NAME,"
       "depth=NAME (names or #N; any subset), each optionally with its "
       "unit: x=Pos:um",
       "TEXT",
       ~0u,
       [](T* t, const std::string& text) {
         ApplyColumns(text, &t->read_force);
       },
       [](const T&) { return std::string(); }},
      NotchSetting(g),
      NumberSetting<T>(
          "rate",
          g,
          "Sampling rate (Hz) when there is no time "
          "column",
          0,
          1e8,
          [](T& t) -> double& { return t.read_force.sampling_rate_hz; }),
      FlagSetting<T>("lenient",
                     g,
                     "Drop isolated bad rows with a warning",
                     [](T& t) -> bool& { return t.read_force.lenient; }),
      FlagSetting<T>(
          "force-channels-as-given",
          g,
          "Read Q and P as they are even when |Q| exceeds |P| on most "
          "samples or the load changes sign (refused otherwise as swapped "
          "channels)",
          [](T& t) -> bool& { return t.read_force.channels_as_given; }),
  };
}

std::vector<S> AllSettings() {
  std::vector<S> all;
  auto add = [&all](unsigned sections, std::vector<S> part) {
    for (S& s : part) all.push_back(In(sections, std::move(s)));
  };
  add(kForceFileSettings, ForceFileSettings());
  // FuseOptions' own (fuse_settings.h), set on the test's `fuse`.
  for (const support::Setting<FuseOptions>& f : FuseSettingList()) {
    all.push_back(
        {f.name,
         f.group,
         f.help,
         f.type,
         f.sections,
         [set = f.set](T* t, const std::string& text) { set(&t->fuse, text); },
         [show = f.show](const T& t) { return show(t.fuse); },
         f.repeatable});
  }
  add(kLevelTrackSettings, TrackSettings<T>([](T& t) -> scan::TrackOptions& {
        return t.fuse.track;
      }));
  add(kScanFileSettings,
      ScanFileSettings<T>(
          [](T& t) -> scan::ReadScanOptions& { return t.read_scan; }));
  return all;
}

}  // namespace

const std::vector<support::Setting<TestSettings>>& TestSettingList() {
  static const std::vector<S> list = AllSettings();
  return list;
}

TestSettings MakeTestSettings(
    const std::vector<std::pair<std::string, std::string>>& given) {
  TestSettings t;
  support::ApplySettings(TestSettingList(), given, &t);
  t.fuse.spring_given =
      std::any_of(given.begin(), given.end(), [](const auto& g) {
        return g.first == "spring";
      });
  const auto& fp = t.fuse.force_profile;
  if (fp.first_cycle >= 0 && fp.last_cycle >= 0 &&
      fp.first_cycle > fp.last_cycle) {
    throw support::SettingFailed(
        "compare-first",
        fmt::format("cycle {} is after the last compared cycle {}; expected "
                    "first <= last",
                    fp.first_cycle + 1,
                    fp.last_cycle + 1));
  }
  std::string why;
  if (!t.fuse.IsValid(&why) || !t.read_force.IsValid(&why) ||
      !t.read_scan.IsValid(&why)) {
    throw support::SettingFailed("", why);
  }
  return t;
}

}  // namespace wearscar::fusion
