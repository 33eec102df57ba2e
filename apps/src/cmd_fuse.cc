#include <fmt/format.h>

#include <optional>

#include "commands.h"
#include "common_options.h"
#include "figures.h"
#include "output.h"
#include "results.h"
#include "wearscar/scan/formats.h"

namespace wearscar::app {
namespace {

struct FuseArgs {
  std::string force_file;
  std::string scan_file;
  std::string out;
  std::string name;
  fusion::ProductOptions write;
  bool no_figures = false;
  CommonArgs common;
};

void RunFuse(FuseArgs a) {
  FinaliseCommonOptions(&a.common);
  const force::ForceRecord record =
      force::ReadForceFile(a.force_file, a.common.read_force);
  std::optional<scan::HeightMap> map;
  if (!a.scan_file.empty()) {
    map = scan::ReadScan(a.scan_file, a.common.read_scan);
  } else if (a.common.fuse.slopes == fusion::SlopeChoice::kScan) {
    throw UsageError("fuse: --slope scan needs --scan");
  }
  const fusion::TestResult r =
      fusion::AnalyzeTest(record, std::move(map), a.common.fuse);
  const std::string name = a.name.empty() ? SpecimenName(a.force_file) : a.name;
  PrintSummary(name, r);
  if (a.out.empty()) {
    fmt::print("nothing written (give -o DIR for the tables and figures)\n");
    return;
  }
  // One writer per folder; everything is staged and moved into place only
  // when the whole set is there.
  const OutputLock lock(a.out);
  StagedOutput stage(a.out);
  const auto files =
      WriteTestResults(stage.dir(), name, record, r, a.common.fuse, a.write);
  FigureSet figs;
  if (!a.no_figures) {
    figs = DrawTestFigures(stage.dir(), name, r, a.common.fuse);
    if (!figs.missing.empty()) AddWarningToResult(stage.dir(), figs.message);
  }
  stage.Commit();
  fmt::print("wrote {} files to {}/\n", files.size(), a.out);
  if (!a.no_figures) {
    if (!figs.message.empty())
      fmt::print(stderr, "wearscar: warning: {}\n", figs.message);
    fmt::print(
        "drew {} figures (PNG and SVG) in {}/\n", 2 * figs.png.size(), a.out);
    if (!figs.missing.empty()) SetExitStatus(kExitFiguresMissing);
  }
}

}  // namespace

void AddFuseCommand(CLI::App& app) {
  auto args = std::make_shared<FuseArgs>();
  auto* cmd = app.add_subcommand("fuse",
                                 "Force record + scan of the worn track: align "
                                 "the scan centreline with the spring "
                                 "displacement P/S, fit mu-hat with the slope "
                                 "from either, report the mismatch and the "
                                 "wear-scar verdict");
  cmd->add_option("--force", args->force_file, "Force export")->required();
  cmd->add_option("--scan",
                  args->scan_file,
                  "Height map (" + scan::ScanExtensionList() +
                      "); without it, the force slope only");
  cmd->add_option("-o,--out", args->out, "Directory for the results");
  cmd->add_option("--name", args->name, "Specimen name in the outputs");
  cmd->add_option("--detail-cycle",
                  args->common.fuse.detail_cycle,
                  "Cycle for slopes, reconstruction and J(mu) (default: last)");
  cmd->add_option(
      "--loops", args->write.loop_cycles, "Cycles whose loops are exported");
  cmd->add_flag("--no-figures", args->no_figures, "Skip the figures");
  AddCommonOptions(cmd, &args->common, true);
  cmd->callback([args] { RunFuse(*args); });
}

}  // namespace wearscar::app
