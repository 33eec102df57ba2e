#include <fmt/format.h>

#include "commands.h"
#include "common_options.h"
#include "output.h"
#include "results.h"

namespace wearscar::app {
namespace {

struct ForceArgs {
  std::string file;
  std::string out;
  CommonArgs common;
};

void RunForce(ForceArgs a) {
  FinaliseCommonOptions(&a.common);
  const force::ForceRecord record =
      force::ReadForceFile(a.file, a.common.read_force);
  const fusion::TestResult r =
      fusion::AnalyzeTest(record, std::nullopt, a.common.fuse);
  fmt::print("{}: {} samples at {:.0f} Hz ({} layout), stroke {:.3f} mm\n",
             a.file,
             record.size(),
             record.metadata.sampling_rate_hz,
             record.metadata.layout,
             r.force.cycles.stroke_mm);
  for (const auto& w : record.metadata.warnings) fmt::print("  note: {}\n", w);
  PrintSummary(a.file, r);
  if (a.out.empty()) return;
  const auto files = WriteTestResults(a.out, a.file, record, r, a.common.fuse);
  fmt::print("wrote {} files to {}/\n", files.size(), a.out);
}

}  // namespace

void AddForceCommand(CLI::App& app) {
  auto args = std::make_shared<ForceArgs>();
  auto* cmd = app.add_subcommand(
      "force",
      "Analyse a force record alone: cycles, gross slip, mean and energy COFs, "
      "mu-hat per "
      "cycle with the slope from the normal force (k = (1/S) dP/dx)");
  cmd->add_option("file", args->file, "Force export (CSV/TSV/semicolon)")
      ->required();
  cmd->add_option("-o,--out", args->out, "Directory for the results");
  AddCommonOptions(cmd, &args->common, false);
  cmd->callback([args] { RunForce(*args); });
}

}  // namespace wearscar::app
