#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "output.h"
#include "setting_flags.h"
#include "wearscar/force/read_force.h"
#include "wearscar/samples/simulation_settings.h"
#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::app {
namespace {

struct SimulateCommandArgs {
  GivenSettings given;  // the simulation's settings as written
  std::string out = "simulated";
  std::vector<std::string> formats = {"csv", "rtec", "gsf", "keyence-csv"};
};

void RunSimulate(const SimulateCommandArgs& a) {
  const std::vector<samples::SimulationOptions> cases = WithFlagNames([&] {
    samples::SimulationRequest request;
    support::ApplySettings(samples::SimulationSettingList(), a.given, &request);
    return samples::SimulationCases(request);
  });
  auto wants = [&](const char* f) {
    return std::find(a.formats.begin(), a.formats.end(), f) != a.formats.end();
  };
  EnsureDirectory(a.out);
  Progress progress("simulate", static_cast<long>(cases.size()));
  long done = 0;
  std::vector<std::string> written;  // for the folder's manifest
  for (const auto& o : cases) {
    const samples::SimulatedTest test = samples::Simulate(o);
    const std::string base = (std::filesystem::path(a.out) / o.name).string();
    if (wants("csv") || wants("rtec")) {
      const force::ForceRecord record =
          force::RecordFromChannels(test.record, "simulated");
      if (wants("csv")) force::WriteForceCsv(record, base + ".force.csv");
      if (wants("rtec")) force::WriteRtecCsv(record, base + ".rtec.csv");
    }
    if (wants("gsf")) scan::WriteGsf(test.scan, base + ".scan.gsf");
    if (wants("keyence-csv"))
      scan::WriteKeyenceCsv(test.scan, base + ".keyence.csv");
    WriteTextAtomically(base + ".truth.json",
                        samples::TruthJson(o, test).dump(2) + "\n");
    for (const auto& [format, suffix] :
         {std::pair<const char*, const char*>{"csv", ".force.csv"},
          {"rtec", ".rtec.csv"},
          {"gsf", ".scan.gsf"},
          {"keyence-csv", ".keyence.csv"}}) {
      if (wants(format)) written.push_back(o.name + suffix);
    }
    written.push_back(o.name + ".truth.json");
    progress.Update(++done);
  }
  progress.Finish();
  // A re-run with fewer cases or formats removes what this one no longer
  // writes (and nothing else).
  RecordOutputs(a.out, "simulate", written, true);
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
  auto args = std::make_shared<SimulateCommandArgs>();
  auto* cmd = app.add_subcommand("simulate",
                                 "Run the virtual tribometer and profilometer: "
                                 "the paper's 12 cases (B|S x RT-R, "
                                 "RT-T, RL-R, RL-L, TL-T, TL-L) with ground "
                                 "truth and optional hidden effects");
  AddSettingFlags(cmd,
                  samples::SimulationSettingList(),
                  ~0u,
                  samples::SimulationRequest{},
                  &args->given);
  cmd->add_option("-o,--out", args->out, "Output directory")
      ->capture_default_str();
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
