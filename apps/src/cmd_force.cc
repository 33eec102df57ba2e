#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "commands.h"
#include "output.h"
#include "setting_flags.h"
#include "summaries.h"
#include "wearscar/force/layouts.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/specimen_folder.h"

namespace wearscar::app {
namespace {

struct ForceArgs {
  std::string file;
  std::string out;
  bool no_figures = false;
  report::FigureFormats figure_formats;
  GivenSettings given;  // the settings as written
};

void RunForce(ForceArgs a) {
  fusion::TestSettings settings =
      WithFlagNames([&] { return fusion::MakeTestSettings(a.given); });
  const force::ForceRecord record =
      force::ReadForceFile(a.file, settings.read_force);
  const fusion::TestResult r =
      fusion::AnalyzeTest(record, std::nullopt, settings.fuse);
  Say("{}: {} samples at {:.0f} Hz ({} layout), stroke {:.3f} mm\n",
      a.file,
      record.size(),
      record.metadata.sampling_rate_hz,
      record.metadata.layout,
      r.force.cycles.stroke_mm);
  for (const auto& w : record.metadata.warnings) Say("  note: {}\n", w);
  PrintSummary(a.file, r);
  if (a.out.empty()) {
    // A short per-cycle table: the first cycles, every n-th, the last ones.
    const int n = static_cast<int>(r.force.cycles.cycles.size());
    const int every = std::max(1, n / 10);
    Say("\n  {:>5} {:>8} {:>7} {:>8} {:>9} {:>9} {:>8}\n",
        "cycle",
        "mu_hat",
        "J",
        "mu_mean",
        "mu_energy",
        "P_range_N",
        "QP_corr");
    for (int c = 0; c < n; ++c) {
      if (!(c < 3 || c >= n - 3 || c % every == 0)) continue;
      const auto& f = r.ForceFits().cycles.at(c);
      const auto& cof = r.units.Get<fusion::ClassicCofs>().cycles.at(c);
      Say("  {:>5} {:>8.4f} {:>7.3f} {:>8.4f} {:>9.4f} {:>9.3f} {:>8.2f}{}\n",
          c + 1,
          f.converged ? f.mu_hat : std::nan(""),
          f.converged ? f.cost : std::nan(""),
          cof.mu_mean,
          cof.mu_energy_g,
          cof.p_range_n,
          cof.qp_correlation,
          c < r.force.running_in.cycles ? "  running-in" : "");
    }
    Say("  (all cycles and more columns: --out DIR)\n");
    PrintJsonSummary(
        fusion::MakeTestProducts(a.file, record, r, settings.fuse).result);
    return;
  }
  const OutputLock lock(a.out, OutputLock::kExclusive, BreakLock());
  StagedOutput stage(a.out, "force");
  fusion::TestProducts products =
      report::WriteTestTables(stage.dir(), a.file, record, r, settings.fuse);
  report::FigureSet figs;
  if (!a.no_figures) {
    figs = report::DrawTestFigures(stage.dir(),
                                   fusion::SpecimenName(a.file),
                                   r,
                                   settings.fuse,
                                   products,
                                   a.figure_formats);
    if (!figs.missing.empty())
      products.result["warnings"].push_back(figs.message);
  }
  report::WriteResult(stage.dir(), products);
  const nlohmann::json& summary = products.result;
  const size_t written = stage.Commit();
  Say("wrote {} files to {}/\n", written, a.out);
  if (!a.no_figures) {
    if (!figs.message.empty())
      fmt::print(stderr, "wearscar: warning: {}\n", figs.message);
    SayFiguresDrawn(figs, a.figure_formats, a.out);
    if (!figs.missing.empty()) SetExitStatus(kExitFiguresMissing);
  }
  PrintJsonSummary(summary);
}

}  // namespace

void AddForceCommand(CLI::App& app) {
  auto args = std::make_shared<ForceArgs>();
  auto* cmd = app.add_subcommand(
      "force",
      "Analyse a force record alone: cycles, gross slip, mean and energy COFs, "
      "mu-hat per "
      "cycle with the slope from the normal force (k = (1/S) dP/dx)");
  cmd->add_option("file,--force",
                  args->file,
                  "Force export, CSV/TSV/semicolon (positional or --force)")
      ->required();
  cmd->add_option("-o,--out", args->out, "Directory for the results");
  AddTestCommandOptions(cmd,
                        &args->no_figures,
                        &args->figure_formats,
                        fusion::kForceCommandSettings,
                        /*break_lock=*/true,
                        &args->given);
  std::string layouts = "Layouts read (told apart by the file itself):\n";
  for (const force::ForceLayout& l : force::ForceLayouts())
    layouts += fmt::format("  {:<11} {}\n", l.name, l.instruments);
  cmd->footer(
      layouts +
      "\nExamples:\n"
      "  wearscar force B-RT-R.force.csv\n"
      "  wearscar force rtec_export.csv --spring 8.5 -o out/force\n"
      "  wearscar force rig.txt --columns x=Pos:um,q=Ff,p=Fn --rate 2000 "
      "--json");
  cmd->callback([args] { RunForce(*args); });
}

}  // namespace wearscar::app
