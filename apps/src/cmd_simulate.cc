#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "output.h"
#include "wearscar/force/read_force.h"
#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::app {
namespace {

struct SimulateArgs {
  std::vector<std::string> cases;
  bool all = false;
  std::string out = "simulated";
  int cycles = -1;
  double rate_hz = -1;
  double amplitude_mm = -1, frequency_hz = -1;
  int scan_cols = -1, scan_rows = -1;
  double scan_pitch_mm = -1;
  bool no_elastic = false;
  double noise = -1;             // scale of the calibrated sensor noise
  double elastic_fraction = -1;  // S-RL-R-like elastic part, of the profile
  std::vector<std::string> effect_settings;  // name=value
  bool triangle = false;
  long long seed = -1;
  std::vector<std::string> formats = {"csv", "rtec", "gsf", "keyence-csv"};
};

void RunSimulate(const SimulateArgs& a) {
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
  auto wants = [&](const char* f) {
    return std::find(a.formats.begin(), a.formats.end(), f) != a.formats.end();
  };
  EnsureDirectory(a.out);
  Progress progress("simulate", static_cast<long>(cases.size()));
  long done = 0;
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
    const samples::SimulatedTest test = samples::Simulate(o);
    const std::string base = (std::filesystem::path(a.out) / o.name).string();
    if (wants("csv")) force::WriteForceCsv(test.record, base + ".force.csv");
    if (wants("rtec")) force::WriteRtecCsv(test.record, base + ".rtec.csv");
    if (wants("gsf")) scan::WriteGsf(test.scan, base + ".scan.gsf");
    if (wants("keyence-csv"))
      scan::WriteKeyenceCsv(test.scan, base + ".keyence.csv");
    WriteTextAtomically(base + ".truth.json",
                        samples::TruthJson(o, test).dump(2) + "\n");
    progress.Update(++done);
  }
  progress.Finish();
  std::vector<std::string> files;
  if (wants("csv")) files.push_back("<case>.force.csv");
  if (wants("rtec")) files.push_back("<case>.rtec.csv");
  if (wants("gsf")) files.push_back("<case>.scan.gsf");
  if (wants("keyence-csv")) files.push_back("<case>.keyence.csv");
  files.push_back("<case>.truth.json");
  Say("wrote {} case(s) to {}/ ({})\n",
      cases.size(),
      a.out,
      fmt::join(files, ", "));
}

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  const samples::SimulationOptions defaults;  // the help shows its values
  auto* cmd = app.add_subcommand("simulate",
                                 "Run the virtual tribometer and profilometer: "
                                 "the paper's 12 cases (B|S x RT-R, "
                                 "RT-T, RL-R, RL-L, TL-T, TL-L) with ground "
                                 "truth and optional hidden effects");
  cmd->add_option("--case", args->cases, "Case name, e.g. B-RT-R (repeatable)");
  cmd->add_flag("--all", args->all, "All 12 cases");
  cmd->add_option("-o,--out", args->out, "Output directory")
      ->capture_default_str();
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
  cmd->add_option("--formats",
                  args->formats,
                  "Files to write: csv (time_s,x_mm,Q_N,P_N), rtec (Rtec "
                  "MFT-like), gsf, keyence-csv (Keyence VR height export)")
      ->delimiter(',')
      ->check(CLI::IsMember({"csv", "rtec", "gsf", "keyence-csv"}))
      ->capture_default_str();
  cmd->footer(
      "Examples:\n"
      "  wearscar simulate --all -o samples\n"
      "  wearscar simulate --case S-RL-R --cycles 600 --rate 2000 -o full\n"
      "  wearscar simulate --case B-RT-R --effect ploughing=1.0 --seed 7 -o "
      "hidden");
  cmd->callback([args] { RunSimulate(*args); });
}

}  // namespace wearscar::app
