#pragma once
// The libraries' settings (support::Setting lists) as command-line flags:
// --name VALUE for each, the defaults in the help, and a bad value named
// by its flag.

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "usage_error.h"
#include "wearscar/support/settings.h"

namespace wearscar::app {

using GivenSettings = std::vector<std::pair<std::string, std::string>>;

// Registers the settings of `list` whose sections meet `sections` as
// flags of `cmd`: each occurrence goes to `given` as (name, text); the help
// shows each one's value in `defaults`.
template <class Target>
void AddSettingFlags(CLI::App* cmd,
                     const std::vector<support::Setting<Target>>& list,
                     unsigned sections,
                     const Target& defaults,
                     GivenSettings* given) {
  for (const support::Setting<Target>& s : list) {
    if ((s.sections & sections) == 0) continue;
    const std::string flag = "--" + s.name, name = s.name;
    if (s.type.empty()) {
      cmd->add_flag_callback(
             flag, [given, name] { given->emplace_back(name, "true"); }, s.help)
          ->group(s.group);
      continue;
    }
    CLI::Option* o = cmd->add_option(
        flag,
        [given, name](const CLI::results_t& values) {
          for (const std::string& v : values) given->emplace_back(name, v);
          return true;
        },
        s.help);
    o->type_name(s.type)->group(s.group)->multi_option_policy(
        CLI::MultiOptionPolicy::TakeAll);
    const std::string shown = s.show(defaults);
    if (!shown.empty()) o->default_str(shown);
  }
}

// `make()`, a support::SettingFailed from it a UsageError naming the flag:
// "--spring: found 0; expected a number from 1e-06 to 1e+06".
template <class Make>
auto WithFlagNames(Make make) -> decltype(make()) {
  try {
    return make();
  } catch (const support::SettingFailed& e) {
    throw UsageError(e.name.empty() ? std::string(e.what())
                                    : "--" + e.name + ": " + e.what());
  }
}

}  // namespace wearscar::app
