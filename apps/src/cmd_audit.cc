#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <thread>

#include "commands.h"
#include "common_options.h"
#include "diagnosis_output.h"
#include "figures.h"
#include "output.h"
#include "report.h"
#include "results.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/scan/formats.h"
#include "wearscar/support/text.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

struct AuditArgs {
  std::string input;
  std::string out = "audit";
  std::string shard;
  bool no_figures = false;
  bool diagnose = false;
  fusion::DiagnoseOptions diagnose_options;
  fusion::BatchOptions batch;
  CommonArgs common;
};

nlohmann::json Dig(const nlohmann::json& j,
                   std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return nullptr;
    p = &(*p)[k];
  }
  return *p;
}

// The diagnosis of one specimen into its folder and report section; a
// diagnosis that cannot run is reported, the analysis stands.
void AuditDiagnosis(const AuditArgs& a,
                    const std::string& name,
                    const std::string& dir,
                    const force::ForceRecord& record,
                    const fusion::TestResult& r,
                    ReportSection* sec) {
  try {
    fusion::DiagnoseOptions dopt = a.diagnose_options;
    dopt.running_in_cycles = r.force.running_in.cycles;
    const fusion::Diagnosis d = DiagnoseTest(record, r, a.common.fuse, dopt);
    const std::string png = WriteDiagnosis(dir, name, d, !a.no_figures);
    sec->row["missing_effects"] = d.named;
    sec->row["diagnosis"] = d.message;
    if (!png.empty()) {
      sec->figures.png.push_back(png);
      sec->figures.titles.push_back(
          name + ": diagnosis, residual map before and after");
    }
  } catch (const std::exception& e) {
    sec->row["diagnosis"] = std::string("not run: ") + e.what();
  }
}

// One specimen: read, analyse, write its folder (staged: its files appear
// together or not at all), draw its figures and, when asked, diagnose it.
// Failures are the section's error; the batch goes on.
void AuditSpecimen(const AuditArgs& a,
                   const fusion::Specimen& s,
                   ReportSection* sec,
                   SpecimenSeries* series,
                   std::atomic<bool>* figures_missing) {
  sec->name = s.name;
  sec->row = fusion::SpecimenIdentity(s.name, a.batch.naming);
  const std::string final_dir = (fs::path(a.out) / s.name).string();
  try {
    StagedOutput stage(final_dir, "audit");
    const std::string& dir = stage.dir();
    if (!s.error.empty()) throw UsageError(s.error);
    const force::ForceRecord record =
        force::ReadForceFile(s.force, a.common.read_force);
    std::optional<scan::HeightMap> map;
    if (!s.scan.empty()) map = scan::ReadScan(s.scan, a.common.read_scan);
    const fusion::TestResult r =
        fusion::AnalyzeTest(record, std::move(map), a.common.fuse);
    nlohmann::json row =
        WriteTestResults(dir, s.name, record, r, a.common.fuse);
    row.update(sec->row);
    row["scan_file"] = s.scan;
    sec->row = row;
    sec->flagged = !r.verdict.explained;
    *series = {s.name,
               final_dir,
               r.mismatch.mu_force_minus_mean,
               r.mismatch.mu_force_minus_energy,
               r.mismatch.mu_force,
               r.wear.specific_rate_mm3_per_n_m};
    if (!a.no_figures)
      sec->figures = DrawTestFigures(dir, s.name, r, a.common.fuse);
    if (a.diagnose) AuditDiagnosis(a, s.name, dir, record, r, sec);
    if (!sec->figures.missing.empty()) {
      AddWarningToResult(dir, sec->figures.message);
      *figures_missing = true;
    }
    stage.Commit();
    // The report and the batch figures read the files where they are now.
    for (std::string& png : sec->figures.png) png = stage.Final(png);
  } catch (const std::exception& e) {
    sec->failed = true;
    sec->flagged = false;
    sec->row["error"] = e.what();
  }
}

// The audit folder's manifest: the tables, the report, the batch figures
// and their data, one folder per specimen. An unsharded run removes what
// an earlier audit wrote there and this one did not; a shard adds to it.
void RecordAuditOutputs(const AuditArgs& a,
                        const std::vector<ReportSection>& sections,
                        const FigureSet& batch) {
  std::vector<std::string> entries = {
      "summary.csv", "summary.jsonl", "summary.json", "report.html"};
  for (const auto& sec : sections) entries.push_back(sec.name + "/");
  for (const std::string& png : batch.png) {
    const fs::path p = fs::path(png).filename();
    entries.push_back(p.string());
    entries.push_back(fs::path(p).replace_extension(".svg").string());
  }
  std::error_code ec;
  for (const char* data : {"method_differences.csv", "wear_and_mu.csv"}) {
    if (fs::exists(fs::path(a.out) / data, ec)) entries.push_back(data);
  }
  for (const auto& e :
       fs::directory_iterator(fs::path(a.out) / kFigureData, ec)) {
    entries.push_back((fs::path(kFigureData) / e.path().filename()).string());
  }
  RecordOutputs(a.out, "audit", entries, a.batch.shard_count == 1);
}

// One line per specimen: failed, flagged or ok, with mu-hat and J.
void PrintSections(const std::vector<ReportSection>& sections) {
  for (const auto& sec : sections) {
    if (sec.failed) {
      Say("  FAILED   {}: {}\n", sec.name, sec.row["error"].get<std::string>());
    } else {
      Say("  {:8} {}: mu-hat {:.4f}, J {:.3f} (noise floor {:.3f}){}\n",
          sec.flagged ? "FLAGGED" : "ok",
          sec.name,
          Dig(sec.row, {"comparison", "mu_hat_force", "mean"}).get<double>(),
          Dig(sec.row, {"comparison", "J_force", "mean"}).get<double>(),
          Dig(sec.row, {"comparison", "J_force_split", "noise_floor"})
              .get<double>(),
          sec.flagged ? " - " + sec.row["verdict"]["summary"].get<std::string>()
                      : "");
    }
  }
}

void RunAudit(AuditArgs a) {
  FinaliseCommonOptions(&a.common);
  if (!a.shard.empty() && (std::sscanf(a.shard.c_str(),
                                       "%d/%d",
                                       &a.batch.shard_index,
                                       &a.batch.shard_count) != 2 ||
                           a.batch.shard_count < 1 || a.batch.shard_index < 1 ||
                           a.batch.shard_index > a.batch.shard_count)) {
    throw UsageError(
        fmt::format("--shard '{}': expected i/n with 1 <= i <= n", a.shard));
  }
  const std::vector<fusion::Specimen> mine =
      fusion::FindSpecimens(a.input, a.batch);
  EnsureDirectory(a.out);
  // One audit per folder at a time: two would interleave summary.csv and
  // the specimen folders.
  const OutputLock out_lock(a.out);
  std::vector<ReportSection> sections(mine.size());
  std::vector<SpecimenSeries> series(mine.size());
  std::atomic<bool> figures_missing{false};
  const unsigned jobs = a.batch.jobs > 0
                            ? static_cast<unsigned>(a.batch.jobs)
                            : std::max(1u, std::thread::hardware_concurrency());
  Progress progress(
      fmt::format("audit ({} specimens, {} jobs)", mine.size(), jobs),
      static_cast<long>(mine.size()));
  fusion::ForEachSpecimen(
      mine.size(),
      a.batch.jobs,
      [&](size_t i) {
        AuditSpecimen(a, mine[i], &sections[i], &series[i], &figures_missing);
      },
      [&](long done) { progress.Update(done); });
  progress.Finish();
  // Tables: shard 1 (or an unsharded run) writes the CSV header, so the
  // shards' summary.csv files concatenate into one table; summary.jsonl
  // concatenates as it is.
  std::vector<nlohmann::json> rows;
  std::string jsonl;
  int failed = 0, flagged = 0;
  for (const auto& sec : sections) {
    rows.push_back(sec.row);
    jsonl += sec.row.dump() + "\n";
    failed += sec.failed;
    flagged += sec.flagged;
  }
  WriteTextAtomically((fs::path(a.out) / "summary.csv").string(),
                      fusion::SummaryCsv(rows, a.batch.shard_index == 1));
  WriteTextAtomically((fs::path(a.out) / "summary.jsonl").string(), jsonl);
  WriteTextAtomically((fs::path(a.out) / "summary.json").string(),
                      nlohmann::json(rows).dump(2) + "\n");
  FigureSet batch;
  if (!a.no_figures) {
    std::vector<SpecimenSeries> ok;
    for (size_t i = 0; i < sections.size(); ++i) {
      if (!sections[i].failed) ok.push_back(series[i]);
    }
    batch = DrawAuditFigures(a.out, ok);
  }
  RecordAuditOutputs(a, sections, batch);
  const std::string title =
      a.batch.shard_count > 1
          ? fmt::format("wearscar audit of {} (shard {}/{})",
                        a.input,
                        a.batch.shard_index,
                        a.batch.shard_count)
          : fmt::format("wearscar audit of {}", a.input);
  WriteTextAtomically((fs::path(a.out) / "report.html").string(),
                      RenderReport(title, sections, batch));
  PrintSections(sections);
  Say("{} specimens: {} explained, {} not explained, {} failed\n",
      sections.size(),
      sections.size() - flagged - failed,
      flagged,
      failed);
  Say("report: {}\n", fs::absolute(fs::path(a.out) / "report.html").string());
  Say("tables: {} and summary.json\n",
      (fs::path(a.out) / "summary.csv").string());
  if (!batch.message.empty())
    fmt::print(stderr, "wearscar: {}\n", batch.message);
  PrintJsonSummary(nlohmann::json(rows));
  SetExitStatus(failed > 0        ? kExitSpecimensFailed
                : figures_missing ? kExitFiguresMissing
                                  : 0);
}

}  // namespace

void AddAuditCommand(CLI::App& app) {
  auto args = std::make_shared<AuditArgs>();
  auto* cmd = app.add_subcommand(
      "audit",
      "Batch over specimens: pair each force file with its scan (by name or a "
      "manifest), "
      "analyse them in parallel, write a summary table, one folder per "
      "specimen and "
      "report.html. Exit status: 0 when every specimen was analysed, 2 for a "
      "usage error, 3 when any specimen failed (the others are complete), 4 "
      "when figures asked for were not drawn.");
  cmd->add_option("input",
                  args->input,
                  "Folder of files, or manifest.csv (specimen,force,scan)")
      ->required();
  cmd->add_option("-o,--out", args->out, "Output folder")
      ->capture_default_str();
  cmd->add_option(
      "-j,--jobs", args->batch.jobs, "Parallel specimens (default: all cores)");
  cmd->add_option(
      "--shard", args->shard, "Process shard i of n (1-based), e.g. 2/4");
  cmd->add_option("--name-pattern",
                  args->batch.name_pattern,
                  "Regular expression naming a specimen in file names")
      ->capture_default_str();
  cmd->add_flag("--recursive,!--no-recursive",
                args->batch.recursive,
                "Look for specimens in sub-folders too (default; folders "
                "wearscar wrote are skipped)");
  cmd->add_flag("--no-figures", args->no_figures, "Skip the figures");
  cmd->add_flag(
      "--diagnose",
      args->diagnose,
      "Also diagnose each specimen (named missing effects, residual maps)");
  AddPrintModeOptions(cmd);
  AddCommonOptions(cmd, &args->common, kFuseOptions);
  cmd->footer(
      "Examples:\n"
      "  wearscar audit lab/ -o audit\n"
      "  wearscar audit manifest.csv -o audit --diagnose -j 2\n"
      "  wearscar audit lab/ -o audit --shard 2/4 --no-figures --quiet");
  cmd->callback([args] { RunAudit(*args); });
}

}  // namespace wearscar::app
