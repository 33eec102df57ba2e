#include <fmt/format.h>

#include "commands.h"
#include "fuse_run.h"
#include "output.h"
#include "setting_flags.h"
#include "summaries.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/specimen_folder.h"
#include "wearscar/scan/formats.h"

namespace wearscar::app {

void RunFuse(FuseArgs a) {
  if (a.force_file.empty()) {
    throw UsageError(
        "fuse: no force file; expected wearscar fuse FORCE [SCAN] (or "
        "--force FORCE --scan SCAN)");
  }
  fusion::TestSettings settings =
      WithFlagNames([&] { return fusion::MakeTestSettings(a.given); });
  // Cycles are numbered from 1 on the command line, from 0 in the library.
  settings.fuse.detail_cycle = a.detail_cycle - 1;
  if (a.no_figures) WithoutFigureData(&settings.fuse);
  for (int c : a.loops) a.write.loop_cycles.push_back(c - 1);
  if (a.scan_file.empty() &&
      settings.fuse.slopes == fusion::SlopeChoice::kScan) {
    throw UsageError("fuse: --slope scan needs --scan");
  }
  const std::string name =
      a.name.empty() ? fusion::SpecimenName(a.force_file) : a.name;
  fusion::Specimen specimen;
  specimen.name = name;
  specimen.force = a.force_file;
  specimen.scan = a.scan_file;
  const fusion::SpecimenAnalysis analysis = fusion::AnalyzeSpecimen(
      specimen, settings.read_force, settings.read_scan, settings.fuse);
  const force::ForceRecord& record = analysis.record;
  const fusion::TestResult& r = analysis.result;
  PrintSummary(name, r);
  for (const auto& w : record.metadata.warnings) Say("  note: {}\n", w);
  if (a.out.empty()) {
    PrintJsonSummary(
        fusion::MakeTestProducts(name, record, r, settings.fuse, a.write)
            .result);
    Say("nothing written (give -o DIR for the tables and figures)\n");
    return;
  }
  // One writer per folder; everything is staged and moved into place only
  // when the whole set is there.
  const OutputLock lock(a.out, OutputLock::kExclusive, BreakLock());
  StagedOutput stage(a.out, "fuse");
  fusion::TestProducts products = report::WriteTestTables(
      stage.dir(), name, record, r, settings.fuse, a.write);
  report::FigureSet figs;
  if (!a.no_figures) {
    figs = report::DrawTestFigures(
        stage.dir(), name, r, settings.fuse, products, a.figure_formats);
    if (!figs.missing.empty())
      products.result["warnings"].push_back(figs.message);
  }
  report::WriteResult(stage.dir(), products);
  const nlohmann::json& summary = products.result;
  // The page an audit writes for a specimen, for this test alone.
  report::WriteTestPage(stage.dir(), name, summary, figs);
  const size_t written = stage.Commit();
  Say("wrote {} files to {}/ (report.html: its page)\n", written, a.out);
  PrintJsonSummary(summary);
  if (!a.no_figures) {
    if (!figs.message.empty())
      fmt::print(stderr, "wearscar: warning: {}\n", figs.message);
    SayFiguresDrawn(figs, a.figure_formats, a.out);
    if (!figs.missing.empty()) SetExitStatus(kExitFiguresMissing);
  }
}

void AddFuseCommand(CLI::App& app) {
  auto args = std::make_shared<FuseArgs>();
  auto* cmd = app.add_subcommand("fuse",
                                 "Force record + scan of the worn track: align "
                                 "the scan centreline with the spring "
                                 "displacement P/S, fit mu-hat with the slope "
                                 "from either, report the mismatch and the "
                                 "wear-scar verdict");
  cmd->add_option("force,--force",
                  args->force_file,
                  "Force export (first positional or --force)");
  cmd->add_option("scan,--scan",
                  args->scan_file,
                  "Height map (" + scan::ScanExtensionList() +
                      "; second positional or --scan); without it, the "
                      "force slope only");
  cmd->add_option("-o,--out", args->out, "Directory for the results");
  cmd->add_option("--name", args->name, "Specimen name in the outputs");
  cmd->add_option("--detail-cycle",
                  args->detail_cycle,
                  "Cycle (from 1) for slopes, reconstruction, J(mu) and LuGre "
                  "(default: last)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--loops",
                  args->loops,
                  "Cycles (from 1) whose loops are exported (default: 1, 3, 11 "
                  "and the last)")
      ->check(CLI::PositiveNumber);
  AddTestCommandOptions(cmd,
                        &args->no_figures,
                        &args->figure_formats,
                        fusion::kFuseSettings,
                        /*break_lock=*/true,
                        &args->given);
  cmd->footer(
      "Examples:\n"
      "  wearscar fuse B-RT-R.force.csv --scan B-RT-R.zon -o out/B-RT-R\n"
      "  wearscar fuse test.csv --scan track.x3p --slope scan --json\n"
      "  wearscar fuse rig.txt --columns x=Pos:um,q=Ff,p=Fn --spring 8.5 -o "
      "out");
  cmd->callback([args] { RunFuse(*args); });
}

}  // namespace wearscar::app
