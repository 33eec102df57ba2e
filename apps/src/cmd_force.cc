#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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
  if (a.out.empty()) {
    // A short per-cycle table: the first cycles, every n-th, the last ones.
    const int n = static_cast<int>(r.force.cycles.cycles.size());
    const int every = std::max(1, n / 10);
    fmt::print("\n  {:>5} {:>8} {:>7} {:>8} {:>9} {:>9} {:>8}\n",
               "cycle",
               "mu_hat",
               "J",
               "mu_mean",
               "mu_energy",
               "P_range_N",
               "QP_corr");
    for (int c = 0; c < n; ++c) {
      if (!(c < 3 || c >= n - 3 || c % every == 0)) continue;
      const auto& f = r.force.fit_force[c];
      const auto& cof = r.force.cof[c];
      fmt::print(
          "  {:>5} {:>8.4f} {:>7.3f} {:>8.4f} {:>9.4f} {:>9.3f} {:>8.2f}{}\n",
          c,
          f.converged ? f.mu_hat : std::nan(""),
          f.converged ? f.cost : std::nan(""),
          cof.mu_mean,
          cof.mu_energy_g,
          cof.p_range_n,
          cof.qp_correlation,
          c < r.force.running_in.cycles ? "  running-in" : "");
    }
    fmt::print("  (all cycles and more columns: --out DIR)\n");
    return;
  }
  const OutputLock lock(a.out);
  StagedOutput stage(a.out);
  const auto files =
      WriteTestResults(stage.dir(), a.file, record, r, a.common.fuse);
  stage.Commit();
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
