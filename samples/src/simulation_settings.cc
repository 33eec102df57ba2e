#include "wearscar/samples/simulation_settings.h"

#include <fmt/format.h>

#include <stdexcept>

namespace wearscar::samples {
namespace {

using support::FlagSetting;
using support::NumberSetting;
using support::SettingFailed;
using R = SimulationRequest;
using S = support::Setting<R>;

// A setting given more than once adds to a list.
S Repeated(std::string name,
           std::string help,
           std::vector<std::string> R::*list) {
  return {std::move(name),
          "Simulation",
          std::move(help),
          "TEXT",
          ~0u,
          [list](R* r, const std::string& text) { (r->*list).push_back(text); },
          [](const R&) { return std::string(); },
          true};
}

// An override: a positive number, or nothing (each case's own value).
S Override(std::string name,
           std::string help,
           double lo,
           double hi,
           double R::*field) {
  S s = NumberSetting<R>(std::move(name),
                         "Simulation",
                         std::move(help),
                         lo,
                         hi,
                         [field](R& r) -> double& { return r.*field; });
  s.show = [](const R&) { return std::string(); };
  return s;
}

S IntOverride(
    std::string name, std::string help, long lo, long hi, int R::*field) {
  return {std::move(name),
          "Simulation",
          std::move(help),
          "INTEGER",
          ~0u,
          [field, lo, hi](R* r, const std::string& text) {
            r->*field = static_cast<int>(support::ParseInteger(text, lo, hi));
          },
          [](const R&) { return std::string(); }};
}

// The scan, the drive's shape and the rig (the help shows each default).
std::vector<S> ScanAndRigSettings();

// The cases and their drive and sampling, then the scan and the rig (the
// help shows each default).
std::vector<S> CaseSettings() {
  const SimulationOptions d;
  std::vector<S> settings = {
      Repeated("case", "Case name, e.g. B-RT-R (repeatable)", &R::cases),
      FlagSetting<R>("all",
                     "Simulation",
                     "All 12 cases",
                     [](R& r) -> bool& { return r.all; }),
      IntOverride("cycles",
                  fmt::format("Cycles (default {})", d.cycles),
                  1,
                  10000000,
                  &R::cycles),
      Override(
          "rate",
          fmt::format("Sampling rate in Hz (default {})", d.sampling_rate_hz),
          1e-3,
          1e8,
          &R::rate_hz),
      Override("amplitude",
               fmt::format("Stroke amplitude A, mm: x = +-A (default {})",
                           d.amplitude_mm),
               1e-6,
               1e3,
               &R::amplitude_mm),
      Override("spring",
               fmt::format("The rig's loading spring S, N/mm (default {})",
                           d.spring_n_per_mm),
               1e-3,
               1e6,
               &R::spring_n_per_mm),
      Override("frequency",
               fmt::format("Drive frequency, Hz (default {})", d.frequency_hz),
               1e-6,
               1e5,
               &R::frequency_hz),
  };
  for (S& s : ScanAndRigSettings()) settings.push_back(std::move(s));
  return settings;
}

std::vector<S> ScanAndRigSettings() {
  const SimulationOptions d;
  return {
      IntOverride("scan-cols",
                  fmt::format("Scan width in pixels (default {})", d.scan_cols),
                  2,
                  100000,
                  &R::scan_cols),
      IntOverride(
          "scan-rows",
          fmt::format("Scan height in pixels (default {})", d.scan_rows),
          2,
          100000,
          &R::scan_rows),
      Override("scan-pitch",
               fmt::format("Scan pixel size, mm (default {})", d.scan_pitch_mm),
               1e-7,
               100,
               &R::scan_pitch_mm),
      FlagSetting<R>("triangle",
                     "Simulation",
                     "Triangular drive instead of sine",
                     [](R& r) -> bool& { return r.triangle; }),
      IntOverride("record-from",
                  "The record starts at this cycle of the test (a pre-worn "
                  "or resumed specimen, a later block of a long test; "
                  "default 0: from the first contact)",
                  0,
                  100000,
                  &R::record_from),
      FlagSetting<R>("rigid-sphere",
                     "Simulation",
                     "The sphere rides the worn track as a rigid ball (its "
                     "path bridges what curves tighter than its radius; the "
                     "scan shows the worn profile)",
                     [](R& r) -> bool& { return r.rigid_sphere; }),
      {"rig",
       "Simulation",
       "How the ball is loaded: spring (the paper's; P follows the track) or "
       "dead-weight (P constant)",
       "TEXT",
       ~0u,
       [](R* r, const std::string& text) {
         r->dead_weight = support::ParseChoice(
                              text, {"spring", "dead-weight"}) == "dead-weight";
       },
       [](const R& r) {
         return std::string(r.dead_weight ? "dead-weight" : "spring");
       }},
      {"depth-channel",
       "Simulation",
       "Log the ball's penetration as a depth channel (depth_mm, with a "
       "sensor's noise, offset and drift): on or off (default: on for a "
       "dead-weight rig)",
       "TEXT",
       ~0u,
       [](R* r, const std::string& text) {
         r->depth_channel =
             support::ParseChoice(text, {"on", "off"}) == "on" ? 1 : 0;
       },
       [](const R&) { return std::string(); }},
  };
}

// The noise, the elastic part, the seed and the hidden effects.
std::vector<S> NoiseSettings() {
  const SimulationOptions d;
  return {
      FlagSetting<R>("no-elastic",
                     "Simulation",
                     "No elastic part in S-RL-R (every case explained by "
                     "wear-scar)",
                     [](R& r) -> bool& { return r.no_elastic; }),
      Override("noise",
               fmt::format("Scale of the sensor noise; 1 = calibrated to the "
                           "paper's J (P {} N, Q {} N sd on beech, more on "
                           "spruce)",
                           d.p_noise_n,
                           d.q_noise_n),
               0,
               1000,
               &R::noise),
      Override("elastic",
               "Elastic part of the normal displacement as a fraction of the "
               "worn profile's sd (0.25 = 25%), in every case",
               0,
               10,
               &R::elastic_fraction),
      Override("ring-width-cv",
               "Growth rings of varying width: each ring's width varies about "
               "the case's ring period by this (sd over the mean; default 0, "
               "every ring alike), so that specimens differ in where their "
               "rings fall",
               0,
               0.5,
               &R::ring_width_cv),
      {"seed",
       "Simulation",
       "Random seed for every case (default: each case's own)",
       "INTEGER",
       ~0u,
       [](R* r, const std::string& text) {
         r->seed = support::ParseInteger(text, 0, 2147483647L);
       },
       [](const R&) { return std::string(); }},
      Repeated(
          "effect",
          "Hidden effect as name=value (repeatable): " + HiddenEffectNames(),
          &R::effects),
  };
}

// The request's overrides on one case.
void Override(const SimulationRequest& r,
              const HiddenEffects& effects,
              SimulationOptions* o) {
  if (r.cycles > 0) o->cycles = r.cycles;
  if (r.rate_hz > 0) o->sampling_rate_hz = r.rate_hz;
  if (r.amplitude_mm > 0) o->amplitude_mm = r.amplitude_mm;
  if (r.frequency_hz > 0) o->frequency_hz = r.frequency_hz;
  if (r.spring_n_per_mm > 0) o->spring_n_per_mm = r.spring_n_per_mm;
  if (r.scan_cols > 0) o->scan_cols = r.scan_cols;
  if (r.scan_rows > 0) o->scan_rows = r.scan_rows;
  if (r.scan_pitch_mm > 0) o->scan_pitch_mm = r.scan_pitch_mm;
  if (r.triangle) o->drive = Drive::kTriangle;
  if (r.rigid_sphere) o->rigid_sphere = true;
  if (r.record_from >= 0) o->record_from_cycle = r.record_from;
  if (r.dead_weight) o->rig = Rig::kDeadWeight;
  o->depth_channel =
      r.depth_channel >= 0 ? r.depth_channel == 1 : r.dead_weight;
  if (r.noise >= 0) o->noise_scale = r.noise;
  if (r.elastic_fraction >= 0) o->elastic_fraction = r.elastic_fraction;
  if (r.ring_width_cv >= 0) o->ring_width_cv = r.ring_width_cv;
  o->effects = effects;
  if (r.seed >= 0) o->seed = static_cast<std::uint64_t>(r.seed);
}

}  // namespace

const std::vector<support::Setting<SimulationRequest>>&
SimulationSettingList() {
  static const std::vector<S> list = [] {
    std::vector<S> all = CaseSettings(), noise = NoiseSettings();
    all.insert(all.end(), noise.begin(), noise.end());
    return all;
  }();
  return list;
}

std::vector<SimulationOptions> SimulationCases(const SimulationRequest& r) {
  std::vector<SimulationOptions> cases;
  if (r.all) {
    cases = PaperCases(!r.no_elastic);
  } else {
    if (r.cases.empty())
      throw SettingFailed(
          "case",
          "no case asked for; expected a case name (repeatable) or all");
    for (const auto& name : r.cases) {
      try {
        cases.push_back(PaperCase(name, !r.no_elastic));
      } catch (const std::invalid_argument& e) {
        throw SettingFailed("case", e.what());
      }
    }
  }
  HiddenEffects effects;
  for (const auto& setting : r.effects) {
    try {
      ApplyEffectSetting(setting, &effects);
    } catch (const std::invalid_argument& e) {
      throw SettingFailed("effect", e.what());
    }
  }
  for (auto& o : cases) {
    Override(r, effects, &o);
    std::string why;
    if (!o.IsValid(&why)) throw SettingFailed("", why);
  }
  return cases;
}

}  // namespace wearscar::samples
