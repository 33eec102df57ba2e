#include "wearscar/report/audit.h"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <future>
#include <vector>

#include "wearscar/fusion/error.h"
#include "wearscar/report/html_report.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/report/test_folder.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;

// The diagnosis of one specimen into its folder and report section; a
// diagnosis that cannot run is reported, the analysis stands.
void AuditDiagnosis(const AuditOptions& o,
                    const std::string& name,
                    const std::string& dir,
                    const force::ForceRecord& record,
                    const fusion::TestResult& r,
                    ReportSection* sec) {
  try {
    fusion::DiagnoseOptions dopt = o.diagnose_options;
    dopt.running_in_cycles = r.force.running_in.cycles;
    const fusion::Diagnosis d = fusion::DiagnoseTest(record, r, o.fuse, dopt);
    const std::string shown =
        WriteDiagnosis(dir, name, d, o.figures, o.figure_formats);
    sec->row["missing_effects"] = d.named;
    sec->row["diagnosis"] = d.message;
    if (!shown.empty()) {
      sec->figures.shown.push_back(shown);
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
void AuditSpecimen(const AuditOptions& o,
                   const std::string& out,
                   const fusion::Specimen& s,
                   ReportSection* sec,
                   SpecimenSeries* series,
                   std::atomic<bool>* figures_missing) {
  sec->name = s.name;
  sec->row = fusion::SpecimenIdentity(s.name, o.batch.naming);
  const std::string final_dir = (fs::path(out) / s.name).string();
  try {
    StagedOutput stage(final_dir, "audit");
    const std::string& dir = stage.dir();
    const fusion::SpecimenAnalysis a =
        fusion::AnalyzeSpecimen(s, o.read_force, o.read_scan, o.fuse);
    const force::ForceRecord& record = a.record;
    const fusion::TestResult& r = a.result;
    const fusion::TestProducts products =
        WriteTestResults(dir, s.name, record, r, o.fuse);
    nlohmann::json row = products.result;
    if (s.scan_expected) {
      const std::string missing =
          "no scan paired, although other specimens of the batch have one (" +
          s.no_scan + "); the verdict is the force side's alone";
      AddWarningToResult(dir, missing);
      row["warnings"].push_back(missing);
    }
    row.update(sec->row);
    row["scan_file"] = s.scan;
    row["pairing"] = s.Pairing();
    sec->row = row;
    sec->flagged = !r.verdict.explained;
    *series = {s.name,
               *products.Find("cycles.csv"),
               r.mismatch.mu_force_minus_mean,
               r.mismatch.mu_force_minus_energy,
               r.mismatch.mu_force,
               r.wear.specific_rate_mm3_per_n_m};
    if (o.figures) {
      sec->figures =
          DrawTestFigures(dir, s.name, r, o.fuse, products, o.figure_formats);
    }
    if (o.diagnose) AuditDiagnosis(o, s.name, dir, record, r, sec);
    if (!sec->figures.missing.empty()) {
      AddWarningToResult(dir, sec->figures.message);
      *figures_missing = true;
    }
    stage.Commit();
    // The report and the batch figures read the files where they are now.
    for (std::string& shown : sec->figures.shown) shown = stage.Final(shown);
  } catch (const std::exception& e) {
    sec->failed = true;
    sec->flagged = false;
    sec->row["error"] = e.what();
  }
}

// The audit folder's manifest: the tables, the report, the batch figures
// and their data, one folder per specimen. An unsharded run removes what
// an earlier audit wrote there and this one did not; a shard adds to it.
void RecordAuditOutputs(const std::string& out,
                        bool sharded,
                        const std::vector<ReportSection>& sections,
                        const FigureSet& batch) {
  std::vector<std::string> entries = {
      "summary.csv", "summary.jsonl", "summary.json", "report.html"};
  for (const auto& sec : sections) entries.push_back(sec.name + "/");
  for (const std::string& file : batch.files)
    entries.push_back(fs::path(file).filename().string());
  std::error_code ec;
  for (const char* data : {"method_differences.csv", "wear_and_mu.csv"}) {
    if (fs::exists(fs::path(out) / data, ec)) entries.emplace_back(data);
  }
  for (const auto& e : fs::directory_iterator(fs::path(out) / kFigureData, ec))
    entries.push_back((fs::path(kFigureData) / e.path().filename()).string());
  RecordOutputs(out, "audit", entries, !sharded);
}

// summary.csv (shard 1, or an unsharded run, writes the header, so that
// the shards' files concatenate into one table), summary.jsonl (one row
// per line: it concatenates as it is) and summary.json.
void WriteSummaries(const std::string& out,
                    bool header,
                    const std::vector<ReportSection>& sections) {
  std::vector<nlohmann::json> rows;
  std::string jsonl;
  for (const auto& sec : sections) {
    rows.push_back(sec.row);
    jsonl += sec.row.dump() + "\n";
  }
  WriteTextAtomically((fs::path(out) / "summary.csv").string(),
                      fusion::SummaryCsv(rows, header));
  WriteTextAtomically((fs::path(out) / "summary.jsonl").string(), jsonl);
  WriteTextAtomically((fs::path(out) / "summary.json").string(),
                      nlohmann::json(rows).dump(2) + "\n");
}

}  // namespace

bool AuditOptions::IsValid(std::string* why) const {
  return batch.IsValid(why) && read_force.IsValid(why) &&
         read_scan.IsValid(why) && fuse.IsValid(why) &&
         (!figures || figure_formats.IsValid(why)) &&
         (!diagnose || diagnose_options.IsValid(why));
}

AuditResult Audit(const std::vector<fusion::Specimen>& specimens,
                  const std::string& out,
                  const std::string& title,
                  const AuditOptions& o,
                  const std::function<void(long)>& progress) {
  std::string why;
  if (!o.IsValid(&why)) throw fusion::FusionError("audit options: " + why);
  EnsureDirectory(out);
  // One audit per folder at a time: two would interleave summary.csv and
  // the specimen folders.
  const OutputLock out_lock(out);
  AuditResult result;
  result.specimens.resize(specimens.size());
  std::vector<SpecimenSeries> series(specimens.size());
  std::atomic<bool> figures_missing{false};
  // As many workers as cores also analyse each specimen on their own
  // thread: more threads than cores were only switched between.
  AuditOptions worker_options = o;
  if (fusion::WorkersFillCores(specimens.size(), o.batch.jobs))
    worker_options.fuse.parallel = false;
  fusion::ForEachSpecimen(
      specimens.size(),
      o.batch.jobs,
      [&](size_t i) {
        AuditSpecimen(worker_options,
                      out,
                      specimens[i],
                      &result.specimens[i],
                      &series[i],
                      &figures_missing);
      },
      [&](long done) {
        if (progress) progress(done);
      });
  std::vector<SpecimenSeries> analysed;
  for (size_t i = 0; i < specimens.size(); ++i) {
    result.failed += result.specimens[i].failed;
    result.flagged += result.specimens[i].flagged;
    if (!result.specimens[i].failed) analysed.push_back(series[i]);
  }
  result.figures_missing = figures_missing;
  WriteSummaries(out, o.batch.shard_index == 1, result.specimens);
  // The specimens' part of the report is rendered while gnuplot draws the
  // batch figures.
  std::future<FigureSet> batch_figures;
  if (o.figures) {
    batch_figures = std::async(std::launch::async, [&] {
      return DrawAuditFigures(out, analysed, o.figure_formats);
    });
  }
  const std::string sections = RenderSpecimenSections(result.specimens);
  if (o.figures) result.batch_figures = batch_figures.get();
  RecordAuditOutputs(
      out, o.batch.shard_count > 1, result.specimens, result.batch_figures);
  result.report_path = (fs::path(out) / "report.html").string();
  WriteReport(result.report_path,
              title,
              result.specimens,
              result.batch_figures,
              sections);
  return result;
}

}  // namespace wearscar::report
