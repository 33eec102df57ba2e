#include <fmt/format.h>

#include "commands.h"
#include "output.h"
#include "setting_flags.h"
#include "summaries.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/specimen_folder.h"

namespace wearscar::app {
namespace {

struct DiagnoseArgs {
  std::string force_file;
  std::string scan_file;
  std::string out;
  fusion::DiagnoseOptions diagnose;
  bool no_figures = false;
  report::FigureFormats figure_formats;
  GivenSettings given;  // the settings as written
};

void RunDiagnose(DiagnoseArgs a) {
  if (a.force_file.empty()) {
    throw UsageError(
        "diagnose: no force file; expected wearscar diagnose FORCE [SCAN] "
        "(or --force FORCE --scan SCAN)");
  }
  fusion::TestSettings settings =
      WithFlagNames([&] { return fusion::MakeTestSettings(a.given); });
  std::string why;
  if (!a.diagnose.IsValid(&why)) throw UsageError("diagnose: " + why);
  const force::ForceRecord record =
      force::ReadForceFile(a.force_file, settings.read_force);
  std::optional<scan::HeightMap> map;
  if (!a.scan_file.empty())
    map = scan::ReadScan(a.scan_file, settings.read_scan);
  // The analysis applies a spring the file states; the diagnosis reads
  // the options it ran with (TestResult::options).
  fusion::FuseOptions fo = settings.fuse;
  fo.fit_lugre = false;
  const fusion::TestResult r = fusion::AnalyzeTest(record, std::move(map), fo);
  fusion::DiagnoseOptions dopt = a.diagnose;
  dopt.running_in_cycles = r.force.running_in.cycles;  // given or detected
  const fusion::Diagnosis d = fusion::DiagnoseTest(record, r, fo, dopt);
  const std::string name = fusion::SpecimenName(a.force_file);
  PrintDiagnosis(name, d, r.scan.has_value());
  if (CurrentPrintMode() == PrintMode::kJson) {
    for (const auto& [file, text] : fusion::DiagnosisFiles(name, d)) {
      if (file == "diagnosis.json")
        PrintJsonSummary(nlohmann::json::parse(text));
    }
  }
  if (a.out.empty()) return;
  const OutputLock lock(a.out, OutputLock::kExclusive, BreakLock());
  StagedOutput stage(a.out, "diagnose");
  report::WriteDiagnosis(stage.dir(), name, d, !a.no_figures, a.figure_formats);
  stage.Commit();
  Say("wrote {}/diagnosis.json and the residual maps\n", a.out);
}

}  // namespace

void AddDiagnoseCommand(CLI::App& app) {
  auto args = std::make_shared<DiagnoseArgs>();
  auto* cmd = app.add_subcommand("diagnose",
                                 "Find where the wear-scar model and the "
                                 "measured Q disagree, name the missing effect "
                                 "from a library (greedy forward selection, "
                                 "block cross-validation over cycles), add it, "
                                 "and show the held-out gap shrink");
  cmd->add_option("force,--force",
                  args->force_file,
                  "Force export (first positional or --force)");
  cmd->add_option("scan,--scan",
                  args->scan_file,
                  "Height map (second positional or --scan; optional: depth "
                  "for ploughing)");
  cmd->add_option(
      "-o,--out", args->out, "Directory for diagnosis.json and the maps");
  auto& d = args->diagnose;
  cmd->add_option("--max-cycles", d.max_cycles, "Diagnosis cycles")
      ->capture_default_str();
  cmd->add_option("--folds", d.folds, "Cross-validation folds")
      ->capture_default_str();
  cmd->add_option("--min-gain",
                  d.min_relative_gain,
                  "Smallest held-out J reduction to name")
      ->capture_default_str();
  cmd->add_option("--bic-margin", d.bic_margin, "BIC drop needed to name")
      ->capture_default_str();
  cmd->add_option("--candidates",
                  d.candidates,
                  "Effects to try, by name or key, comma-separated "
                  "(default: the whole library)")
      ->delimiter(',');
  cmd->add_option("--knots",
                  d.along_track_knots,
                  "Knots of friction along the track over the sliding range")
      ->capture_default_str();
  cmd->add_option("--edge-knots",
                  d.edge_knots,
                  "Knots of the edge-keeping shape tried once the smooth one "
                  "is named (a band's sharp boundary); 0: none")
      ->capture_default_str();
  cmd->add_option("--max-effects", d.max_effects, "At most this many effects")
      ->capture_default_str();
  cmd->add_option(
         "--profile-span", d.profile_span_mm, "Base slope smoothing span, mm")
      ->capture_default_str();
  AddTestCommandOptions(cmd,
                        &args->no_figures,
                        &args->figure_formats,
                        fusion::kDiagnoseSettings,
                        /*break_lock=*/true,
                        &args->given);
  cmd->footer(
      "Examples:\n"
      "  wearscar diagnose S-RL-R.force.csv --scan S-RL-R.scan.gsf -o diag\n"
      "  wearscar diagnose test.csv --candidates ploughing,viscous --json\n"
      "  wearscar diagnose test.csv --max-cycles 40 --folds 5");
  cmd->callback([args] { RunDiagnose(*args); });
}

}  // namespace wearscar::app
