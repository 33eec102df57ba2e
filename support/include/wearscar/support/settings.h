#pragma once

// Settings as users write them, as text: one list per options struct says
// each setting's name, help and how its text sets the struct, so that the
// command line only registers the list as flags and Python maps keyword
// arguments onto it, and both give the same checks and messages.

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wearscar::support {

// A bad value: what was found and what was expected, without the
// setting's name (the front end names it as its users write it: --spring
// on the command line, spring= in Python).
class SettingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A setting that failed, with its name.
class SettingFailed : public std::runtime_error {
 public:
  SettingFailed(std::string setting, const std::string& message)
      : std::runtime_error(message), name(std::move(setting)) {}
  std::string name;  // "" for a check across settings
};

// One setting of a `Target` struct.
template <class Target>
struct Setting {
  std::string name;   // "spring", "k-estimate"
  std::string group;  // the help's heading
  std::string help;
  // How the help names its value: "NUMBER", "INTEGER", "TEXT"; empty for
  // a flag, which takes no value on the command line ("true"/"false" as
  // text).
  std::string type;
  unsigned sections = ~0u;  // which commands take it (the front end's bits)
  // Sets the struct from the text; throws SettingError.
  std::function<void(Target*, const std::string&)> set;
  // The value as text for the help ("" for none).
  std::function<std::string(const Target&)> show;
  // Whether giving it again adds to it (a list); otherwise a second value
  // is refused rather than silently replacing the first.
  bool repeatable = false;
};

// The whole text as a finite number in [lo, hi] (an integer with
// `integer`); throws SettingError saying what was found and expected.
double ParseNumber(std::string_view text, double lo, double hi);
long ParseInteger(std::string_view text, long lo, long hi);
// "true"/"false" (and 1/0, yes/no, on/off).
bool ParseFlag(std::string_view text);
// `text` when it is one of `choices`; throws SettingError listing them.
std::string ParseChoice(std::string_view text,
                        const std::vector<std::string>& choices);
// A number as the help shows it (%g).
std::string ShowNumber(double v);

// The names of `names` closest to `name` by edit distance (at most 2
// edits, or a name that starts with it), best first: for "did you mean".
std::vector<std::string> ClosestNames(const std::vector<std::string>& names,
                                      std::string_view name);

// Applies `given` (name, text) to `target`: in the list's order (a setting
// given twice, in the order given), so that the outcome does not depend on
// the order the user wrote them in. Throws SettingFailed naming the
// setting for an unknown name or a bad value.
template <class Target>
void ApplySettings(
    const std::vector<Setting<Target>>& list,
    const std::vector<std::pair<std::string, std::string>>& given,
    Target* target) {
  for (const auto& [name, text] : given) {
    const Setting<Target>* setting = nullptr;
    for (const Setting<Target>& s : list)
      if (s.name == name) setting = &s;
    if (setting == nullptr) throw SettingFailed(name, "not a setting");
    std::string values;
    int count = 0;
    for (const auto& [other, value] : given) {
      if (other != name) continue;
      values += (count++ ? ", " : "") + value;
    }
    if (count > 1 && !setting->repeatable) {
      throw SettingFailed(name,
                          "given " + std::to_string(count) + " values (" +
                              values + "); it takes one");
    }
  }
  for (const Setting<Target>& s : list) {
    for (const auto& [name, text] : given) {
      if (name != s.name) continue;
      try {
        s.set(target, text);
      } catch (const SettingError& e) {
        throw SettingFailed(name, e.what());
      }
    }
  }
}

// A number setting of the field `field` returns a reference to.
template <class Target>
Setting<Target> NumberSetting(std::string name,
                              std::string group,
                              std::string help,
                              double lo,
                              double hi,
                              std::function<double&(Target&)> field) {
  return {std::move(name),
          std::move(group),
          std::move(help),
          "NUMBER",
          ~0u,
          [field, lo, hi](Target* t, const std::string& text) {
            field(*t) = ParseNumber(text, lo, hi);
          },
          [field](const Target& t) {
            return ShowNumber(field(const_cast<Target&>(t)));
          }};
}

template <class Target>
Setting<Target> IntegerSetting(std::string name,
                               std::string group,
                               std::string help,
                               long lo,
                               long hi,
                               std::function<int&(Target&)> field) {
  return {std::move(name),
          std::move(group),
          std::move(help),
          "INTEGER",
          ~0u,
          [field, lo, hi](Target* t, const std::string& text) {
            field(*t) = static_cast<int>(ParseInteger(text, lo, hi));
          },
          [field](const Target& t) {
            return std::to_string(field(const_cast<Target&>(t)));
          }};
}

template <class Target>
Setting<Target> TextSetting(std::string name,
                            std::string group,
                            std::string help,
                            std::function<std::string&(Target&)> field) {
  return {std::move(name),
          std::move(group),
          std::move(help),
          "TEXT",
          ~0u,
          [field](Target* t, const std::string& text) { field(*t) = text; },
          [field](const Target& t) { return field(const_cast<Target&>(t)); }};
}

template <class Target>
Setting<Target> FlagSetting(std::string name,
                            std::string group,
                            std::string help,
                            std::function<bool&(Target&)> field,
                            bool when_given = true) {
  return {std::move(name),
          std::move(group),
          std::move(help),
          "",
          ~0u,
          [field, when_given](Target* t, const std::string& text) {
            field(*t) = ParseFlag(text) ? when_given : !when_given;
          },
          [](const Target&) { return std::string(); }};
}

}  // namespace wearscar::support
