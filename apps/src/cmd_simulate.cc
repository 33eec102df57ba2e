#include <fmt/format.h>

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
  int scan_cols = -1, scan_rows = -1;
  double scan_pitch_mm = -1;
  bool no_elastic = false;
  samples::HiddenEffects effects;
  bool triangle = false;
};

nlohmann::json TruthJson(const samples::SimulationOptions& o,
                         const samples::SimulatedTest& t) {
  nlohmann::json j;
  j["case"] = o.name;
  j["seed"] = o.seed;
  j["mu_per_cycle"] = std::vector<double>(
      t.truth.mu_per_cycle.data(),
      t.truth.mu_per_cycle.data() + t.truth.mu_per_cycle.size());
  j["explained_by_wear_scar"] = t.truth.explained_by_wear_scar;
  j["elastic_mm"] = o.elastic_mm;
  j["spring_n_per_mm"] = o.spring_n_per_mm;
  j["scan"] = {{"center_x_mm", t.truth.scan_center_x_mm},
               {"center_y_mm", t.truth.scan_center_y_mm},
               {"angle_deg", t.truth.scan_angle_deg},
               {"flipped", t.truth.scan_flipped},
               {"plane_dzdx", t.truth.plane_dzdx},
               {"plane_dzdy", t.truth.plane_dzdy},
               {"plane_z0_mm", t.truth.plane_z0_mm}};
  const auto& e = o.effects;
  j["effects"] = {{"ploughing_n_per_mm", e.ploughing_n_per_mm},
                  {"stribeck_rise", e.stribeck_rise},
                  {"stribeck_speed_mm_s", e.stribeck_speed_mm_s},
                  {"direction_asymmetry", e.direction_asymmetry},
                  {"q_lag_s", e.q_lag_s},
                  {"crosstalk_q_into_p", e.crosstalk_q_into_p},
                  {"hook_n", e.hook_n},
                  {"hook_length_mm", e.hook_length_mm},
                  {"viscous_n_s_per_mm", e.viscous_n_s_per_mm}};
  return j;
}

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
  EnsureDirectory(a.out);
  Progress progress("simulate", static_cast<long>(cases.size()));
  long done = 0;
  for (auto& o : cases) {
    if (a.cycles > 0) o.cycles = a.cycles;
    if (a.rate_hz > 0) o.sampling_rate_hz = a.rate_hz;
    if (a.scan_cols > 0) o.scan_cols = a.scan_cols;
    if (a.scan_rows > 0) o.scan_rows = a.scan_rows;
    if (a.scan_pitch_mm > 0) o.scan_pitch_mm = a.scan_pitch_mm;
    if (a.triangle) o.drive = samples::Drive::kTriangle;
    o.effects = a.effects;
    std::string why;
    if (!o.IsValid(&why)) throw UsageError("simulate: " + why);
    const samples::SimulatedTest test = samples::Simulate(o);
    const std::string base = (std::filesystem::path(a.out) / o.name).string();
    force::WriteForceCsv(test.record, base + ".force.csv");
    scan::WriteGsf(test.scan, base + ".scan.gsf");
    WriteTextAtomically(base + ".truth.json",
                        TruthJson(o, test).dump(2) + "\n");
    progress.Update(++done);
  }
  progress.Finish();
  fmt::print(
      "wrote {} case(s) to {}/ (<case>.force.csv, <case>.scan.gsf, "
      "<case>.truth.json)\n",
      cases.size(),
      a.out);
}

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd = app.add_subcommand("simulate",
                                 "Run the virtual tribometer and profilometer: "
                                 "the paper's 12 cases (B|S x RT-R, "
                                 "RT-T, RL-R, RL-L, TL-T, TL-L) with ground "
                                 "truth and optional hidden effects");
  cmd->add_option("--case", args->cases, "Case name, e.g. B-RT-R (repeatable)");
  cmd->add_flag("--all", args->all, "All 12 cases");
  cmd->add_option("-o,--out", args->out, "Output directory")
      ->capture_default_str();
  cmd->add_option("--cycles", args->cycles, "Cycles (default 600)");
  cmd->add_option(
      "--rate", args->rate_hz, "Sampling rate in Hz (default 2000)");
  cmd->add_option(
      "--scan-cols", args->scan_cols, "Scan width in pixels (default 1024)");
  cmd->add_option(
      "--scan-rows", args->scan_rows, "Scan height in pixels (default 768)");
  cmd->add_option("--scan-pitch",
                  args->scan_pitch_mm,
                  "Scan pixel size, mm (default 0.0074)");
  cmd->add_flag(
      "--triangle", args->triangle, "Triangular drive instead of sine");
  cmd->add_flag(
      "--no-elastic",
      args->no_elastic,
      "No elastic part in S-RL-R (every case explained by wear-scar)");
  auto& e = args->effects;
  cmd->add_option(
      "--ploughing", e.ploughing_n_per_mm, "Hidden ploughing, N per mm depth");
  cmd->add_option(
      "--stribeck", e.stribeck_rise, "Hidden Stribeck rise (relative)");
  cmd->add_option(
      "--stribeck-speed", e.stribeck_speed_mm_s, "Stribeck speed, mm/s");
  cmd->add_option(
      "--asymmetry", e.direction_asymmetry, "Hidden direction asymmetry");
  cmd->add_option("--q-lag", e.q_lag_s, "Hidden time lag of Q, s");
  cmd->add_option(
      "--crosstalk", e.crosstalk_q_into_p, "Hidden crosstalk of Q into P");
  cmd->add_option("--hook", e.hook_n, "Hidden end-of-stroke hook, N");
  cmd->add_option("--hook-length", e.hook_length_mm, "Hook decay length, mm");
  cmd->add_option(
      "--viscous", e.viscous_n_s_per_mm, "Hidden viscous term, N s/mm");
  cmd->callback([args] { RunSimulate(*args); });
}

}  // namespace wearscar::app
