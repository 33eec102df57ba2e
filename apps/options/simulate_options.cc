#include "simulate_options.h"

#include <fmt/format.h>

#include <stdexcept>

#include "usage_error.h"

namespace wearscar::app {

std::vector<samples::SimulationOptions> SimulationCases(const SimulateArgs& a) {
  std::vector<samples::SimulationOptions> cases;
  if (a.all) {
    cases = samples::PaperCases(!a.no_elastic);
  } else {
    if (a.cases.empty())
      throw UsageError("simulate: give --case NAME (repeatable) or --all");
    for (const auto& name : a.cases) {
      try {
        cases.push_back(samples::PaperCase(name, !a.no_elastic));
      } catch (const std::invalid_argument& e) {
        throw UsageError(fmt::format("simulate: {}", e.what()));
      }
    }
  }
  samples::HiddenEffects effects;
  for (const auto& setting : a.effect_settings) {
    try {
      samples::ApplyEffectSetting(setting, &effects);
    } catch (const std::invalid_argument& e) {
      throw UsageError(fmt::format("simulate: {}", e.what()));
    }
  }
  for (auto& o : cases) {
    if (a.cycles > 0) o.cycles = a.cycles;
    if (a.rate_hz > 0) o.sampling_rate_hz = a.rate_hz;
    if (a.amplitude_mm > 0) o.amplitude_mm = a.amplitude_mm;
    if (a.frequency_hz > 0) o.frequency_hz = a.frequency_hz;
    if (a.scan_cols > 0) o.scan_cols = a.scan_cols;
    if (a.scan_rows > 0) o.scan_rows = a.scan_rows;
    if (a.scan_pitch_mm > 0) o.scan_pitch_mm = a.scan_pitch_mm;
    if (a.triangle) o.drive = samples::Drive::kTriangle;
    if (a.noise >= 0) o.noise_scale = a.noise;
    if (a.elastic_fraction >= 0) o.elastic_fraction = a.elastic_fraction;
    o.effects = effects;
    if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
    std::string why;
    if (!o.IsValid(&why)) throw UsageError("simulate: " + why);
  }
  return cases;
}

void AddSimulationOptions(CLI::App* cmd, SimulateArgs* args) {
  const samples::SimulationOptions defaults;  // the help shows its values
  cmd->add_option("--case", args->cases, "Case name, e.g. B-RT-R (repeatable)");
  cmd->add_flag("--all", args->all, "All 12 cases");
  cmd->add_option("--cycles",
                  args->cycles,
                  fmt::format("Cycles (default {})", defaults.cycles));
  cmd->add_option("--rate",
                  args->rate_hz,
                  fmt::format("Sampling rate in Hz (default {})",
                              defaults.sampling_rate_hz));
  cmd->add_option("--amplitude",
                  args->amplitude_mm,
                  fmt::format("Stroke amplitude A, mm: x = +-A (default {})",
                              defaults.amplitude_mm))
      ->check(CLI::PositiveNumber);
  cmd->add_option(
         "--frequency",
         args->frequency_hz,
         fmt::format("Drive frequency, Hz (default {})", defaults.frequency_hz))
      ->check(CLI::PositiveNumber);
  cmd->add_option(
      "--scan-cols",
      args->scan_cols,
      fmt::format("Scan width in pixels (default {})", defaults.scan_cols));
  cmd->add_option(
      "--scan-rows",
      args->scan_rows,
      fmt::format("Scan height in pixels (default {})", defaults.scan_rows));
  cmd->add_option(
      "--scan-pitch",
      args->scan_pitch_mm,
      fmt::format("Scan pixel size, mm (default {})", defaults.scan_pitch_mm));
  cmd->add_flag(
      "--triangle", args->triangle, "Triangular drive instead of sine");
  cmd->add_flag(
      "--no-elastic",
      args->no_elastic,
      "No elastic part in S-RL-R (every case explained by wear-scar)");
  cmd->add_option("--noise",
                  args->noise,
                  fmt::format("Scale of the sensor noise; 1 = calibrated to "
                              "the paper's J (P {} N, Q {} N sd on beech, "
                              "more on spruce)",
                              defaults.p_noise_n,
                              defaults.q_noise_n))
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--elastic",
                  args->elastic_fraction,
                  "Elastic part of the normal displacement as a fraction of "
                  "the worn profile's sd (0.25 = 25%), in every case")
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--seed",
                  args->seed,
                  "Random seed for every case (default: each case's own)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--effect",
                  args->effect_settings,
                  "Hidden effect as name=value (repeatable): " +
                      samples::HiddenEffectNames());
}

}  // namespace wearscar::app
