#include "wearscar/report/audit.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "audit_parts.h"
#include "methods.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/wear.h"
#include "wearscar/report/html_report.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/report/specimen_folder.h"
#include "wearscar/report/workbooks.h"

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
    // k as the analysis took it (the spring a file states included): the
    // diagnosis reads TestResult::options and ::profile.
    const fusion::Diagnosis d = fusion::DiagnoseTest(record, r, o.fuse, dopt);
    const FigureSet shown =
        WriteDiagnosis(dir, name, d, o.figures, o.figure_formats);
    sec->row["missing_effects"] = d.named;
    sec->row["diagnosis"] = d.message;
    for (size_t i = 0; i < shown.shown.size(); ++i) {
      sec->figures.shown.push_back(shown.shown[i]);
      sec->figures.titles.push_back(shown.titles[i]);
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
                   const std::vector<std::string>& shared_inputs,
                   ReportSection* sec,
                   SpecimenSeries* series,
                   std::atomic<bool>* figures_missing) {
  sec->name = s.name;
  sec->row = fusion::SpecimenIdentity(s, o.batch);
  const std::string final_dir = (fs::path(out) / s.name).string();
  try {
    StagedOutput stage(final_dir, "audit");
    const std::string& dir = stage.dir();
    const fusion::SpecimenAnalysis a =
        fusion::AnalyzeSpecimen(s, o.read_force, o.read_scan, o.fuse);
    const force::ForceRecord& record = a.record;
    const fusion::TestResult& r = a.result;
    fusion::TestProducts products =
        WriteTestTables(dir, s.name, record, r, o.fuse);
    if (s.scan_expected)
      products.result["warnings"].push_back(s.PairingWarning());
    for (const std::string& w : shared_inputs)
      products.result["warnings"].push_back(w);
    nlohmann::json row = products.result;
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
               r.units.Get<fusion::Wear>().specific_rate_mm3_per_n_m};
    if (o.figures) {
      sec->figures =
          DrawTestFigures(dir, s.name, r, o.fuse, products, o.figure_formats);
    }
    if (o.diagnose) AuditDiagnosis(o, s.name, dir, record, r, sec);
    if (!sec->figures.missing.empty()) {
      products.result["warnings"].push_back(sec->figures.message);
      sec->row["warnings"].push_back(sec->figures.message);
      *figures_missing = true;
    }
    WriteResult(dir, products);
    stage.Commit();
    // The report and the batch figures read the files where they are now.
    for (std::string& shown : sec->figures.shown) shown = stage.Final(shown);
    sec->viewer = stage.Final((fs::path(dir) / "loop_viewer.json").string());
  } catch (const std::exception& e) {
    sec->failed = true;
    sec->flagged = false;
    sec->row["error"] = e.what();
    sec->row["quote"] = {{"status", "failed"},
                         {"reason", "the specimen could not be analysed"}};
  }
}

// The audit folder's manifest: the tables, the report, the batch figures
// and their data, one folder per specimen of the batch. An unsharded run
// removes what an earlier audit wrote there and the batch does not hold
// (the batch keeps the earlier specimens unless replace_batch); a shard
// adds to it.
void RecordAuditOutputs(const std::string& out,
                        bool sharded,
                        const std::vector<ReportSection>& sections,
                        const FigureSet& batch,
                        const std::vector<std::string>& parts) {
  std::vector<std::string> entries = {"summary.csv",
                                      "summary.jsonl",
                                      "summary.json",
                                      "groups.csv",
                                      "group_differences.csv",
                                      "groups.tex",
                                      "groups.json",
                                      "report.html"};
  entries.insert(entries.end(), parts.begin(), parts.end());
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

// summary.csv, summary.jsonl (one row per line), summary.json and
// summary.xlsx; the groups compared (groups.csv, group_differences.csv,
// groups.tex, groups.json and groups.xlsx), which it returns. The CSV in
// the locale asked for.
std::vector<fusion::GroupComparison> WriteSummaries(
    const std::string& out,
    const std::vector<ReportSection>& sections,
    const AuditOptions& o) {
  std::vector<nlohmann::json> rows;
  std::string jsonl;
  for (const auto& sec : sections) {
    rows.push_back(sec.row);
    jsonl += sec.row.dump() + "\n";
  }
  const std::string summary = fusion::SummaryCsv(rows, true);
  WriteTextAtomically((fs::path(out) / "summary.csv").string(),
                      LocaleCsv(summary, o.csv_locale));
  WriteTextAtomically((fs::path(out) / "summary.jsonl").string(), jsonl);
  WriteTextAtomically((fs::path(out) / "summary.json").string(),
                      nlohmann::json(rows).dump(2) + "\n");
  auto groups = fusion::CompareGroups(rows, o.groups);
  const std::string levels = fusion::GroupsCsv(groups),
                    differences = fusion::GroupDifferencesCsv(groups);
  WriteTextAtomically((fs::path(out) / "groups.csv").string(),
                      LocaleCsv(levels, o.csv_locale));
  WriteTextAtomically((fs::path(out) / "group_differences.csv").string(),
                      LocaleCsv(differences, o.csv_locale));
  WriteTextAtomically((fs::path(out) / "groups.tex").string(),
                      fusion::GroupsLatex(groups));
  WriteTextAtomically((fs::path(out) / "groups.json").string(),
                      fusion::GroupsJson(groups).dump(2) + "\n");
  WriteTextAtomically((fs::path(out) / "methods.md").string(),
                      internal::MethodsText(rows, groups));
  WriteTextAtomically((fs::path(out) / "references.bib").string(),
                      internal::References(rows));
  WriteWorkbook((fs::path(out) / "summary.xlsx").string(),
                {{"summary", summary}});
  WriteWorkbook((fs::path(out) / "groups.xlsx").string(),
                {{"groups", levels}, {"differences", differences}});
  return groups;
}

// What an earlier audit wrote into `out`: its batch record, else the
// parts its shards wrote; none when neither is there.
std::optional<internal::Parts> EarlierBatch(const std::string& out) {
  std::optional<internal::Parts> earlier = internal::ReadBatchRecord(out);
  std::error_code ec;
  if (!earlier && fs::exists(fs::path(out) / "parts", ec)) {
    try {
      earlier = internal::ReadParts(out);
    } catch (const OutputError&) {  // no shard's part there either
    }
  }
  return earlier;
}

// The inputs this run's specimens share with each other, with the other
// shards' or with the earlier specimens the batch keeps, found before any
// is analysed (fusion::SharedInputsBefore): each one's result.json is
// written once, with them.
std::map<std::string, std::vector<std::string>> SharedInputsOf(
    const std::vector<fusion::Specimen>& mine,
    const std::string& out,
    const AuditOptions& o) {
  std::vector<nlohmann::json> earlier;
  if (!o.replace_batch && o.batch.shard_count <= 1) {
    try {
      if (auto batch = EarlierBatch(out))
        for (const ReportSection& sec : batch->sections)
          earlier.push_back(sec.row);
    } catch (const std::exception&) {  // the batch's writing says why
    }
  }
  return fusion::SharedInputsBefore(mine, o.other_shards, earlier);
}

// Inputs shared by specimens of the batch as written (the same SHA-256):
// a warning in each one's row naming the others, where its result.json
// did not have one for that input (fusion::SharedInputWarnings). Only a
// specimen an earlier run analysed, kept beside a new one sharing its
// file, lacks it there: its result.json stays as its run wrote it.
void WarnOfSharedInputs(std::vector<ReportSection>* sections) {
  std::vector<nlohmann::json> rows;
  for (const ReportSection& sec : *sections) rows.push_back(sec.row);
  const auto warnings = fusion::SharedInputWarnings(rows);
  for (size_t i = 0; i < sections->size(); ++i) {
    nlohmann::json& list = (*sections)[i].row["warnings"];
    for (const std::string& w : warnings[i]) {
      // ("the force file is byte-identical to that of ...": one per role.)
      const std::string role = w.substr(0, w.find(" to that of "));
      const bool said = std::any_of(
          list.begin(), list.end(), [&role](const nlohmann::json& had) {
            return had.is_string() &&
                   had.get<std::string>().rfind(role + " to that of ", 0) == 0;
          });
      if (!said) list.push_back(w);
    }
  }
}

// The batch's summaries, figures, manifest and report over `sections`
// (`analysed`: the series of those not failed); fills the result's
// batch figures and report path.
void WriteBatch(const std::string& out,
                const std::string& title,
                const AuditOptions& o,
                bool sharded,
                std::vector<ReportSection>* specimens,
                const std::vector<SpecimenSeries>& analysed,
                const std::vector<std::string>& parts,
                AuditResult* result) {
  WarnOfSharedInputs(specimens);
  const std::vector<ReportSection>& sections = *specimens;
  const auto groups = WriteSummaries(out, sections, o);
  if (o.figures)
    result->batch_figures = DrawAuditFigures(out, analysed, o.figure_formats);
  RecordAuditOutputs(out, sharded, sections, result->batch_figures, parts);
  result->report_path = (fs::path(out) / "report.html").string();
  WriteReport(out, title, sections, result->batch_figures, groups);
}

// The batch an unsharded run writes: the earlier audit's specimens (its
// record, parts/audit.json, or its shards' parts) with this run's in their
// place and the new ones after them; an earlier specimen this run does not
// analyse is kept while its folder holds its result.json. `series[k]`
// belongs to `sections[k]` (empty for a failed one).
struct Batch {
  std::vector<ReportSection> sections;
  std::vector<SpecimenSeries> series;
  std::vector<std::string> kept;
  std::vector<SpecimenSeries> Analysed() const {
    std::vector<SpecimenSeries> out;
    for (size_t k = 0; k < sections.size(); ++k)
      if (!sections[k].failed) out.push_back(series[k]);
    return out;
  }
};

Batch WithEarlierSpecimens(const std::string& out,
                           const std::vector<ReportSection>& now,
                           const std::vector<SpecimenSeries>& now_series) {
  Batch b;
  std::optional<internal::Parts> earlier = EarlierBatch(out);
  std::error_code ec;
  std::map<std::string, size_t> in_run;
  for (size_t i = 0; i < now.size(); ++i) in_run[now[i].name] = i;
  std::set<std::string> placed;
  if (earlier) {
    size_t next_series = 0;
    for (const ReportSection& sec : earlier->sections) {
      SpecimenSeries series;
      if (!sec.failed && next_series < earlier->analysed.size())
        series = earlier->analysed[next_series++];
      const auto again = in_run.find(sec.name);
      if (again != in_run.end()) {
        b.sections.push_back(now[again->second]);
        b.series.push_back(now_series[again->second]);
        placed.insert(sec.name);
      } else if (fs::exists(fs::path(out) / sec.name / "result.json", ec) ||
                 sec.failed) {
        b.sections.push_back(sec);
        b.series.push_back(std::move(series));
        b.kept.push_back(sec.name);
      }
    }
  }
  for (size_t i = 0; i < now.size(); ++i) {
    if (placed.count(now[i].name)) continue;
    b.sections.push_back(now[i]);
    b.series.push_back(now_series[i]);
  }
  return b;
}

// An unsharded run's batch (WithEarlierSpecimens, or this run's alone
// with replace_batch): its record, tables, figures and report; this run's
// rows as the batch holds them (with the warnings of inputs shared with
// any specimen of it).
void WriteUnshardedBatch(const std::string& out,
                         const std::string& title,
                         const AuditOptions& o,
                         const std::vector<SpecimenSeries>& series,
                         AuditResult* result) {
  Batch batch = o.replace_batch
                    ? Batch{result->specimens, series, {}}
                    : WithEarlierSpecimens(out, result->specimens, series);
  result->kept = batch.kept;
  internal::WriteBatchRecord(out, batch.sections, batch.series);
  WriteBatch(out,
             title,
             o,
             false,
             &batch.sections,
             batch.Analysed(),
             {std::string("parts/") + internal::kBatchRecord},
             result);
  for (ReportSection& mine : result->specimens) {
    for (const ReportSection& sec : batch.sections)
      if (sec.name == mine.name) mine.row = sec.row;
  }
}

// What the shards of a sharded audit wrote, merged (the merge lock held).
internal::Parts Merge(const std::string& out,
                      const std::string& title,
                      const AuditOptions& o,
                      AuditResult* result) {
  internal::Parts parts = internal::ReadParts(out);
  result->shard_count = parts.count;
  result->missing_shards = parts.missing;
  result->merged = static_cast<int>(parts.sections.size());
  std::string heading = title;
  if (!parts.missing.empty()) {
    heading += fmt::format(" (shard{} {} of {} missing: not in this report)",
                           parts.missing.size() > 1 ? "s" : "",
                           fmt::join(parts.missing, ", "),
                           parts.count);
  }
  WriteBatch(out,
             heading,
             o,
             true,
             &parts.sections,
             parts.analysed,
             parts.files,
             result);
  return parts;
}

}  // namespace

AuditResult MergeAudit(const std::string& out,
                       const std::string& title,
                       const AuditOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw fusion::FusionError("audit options: " + why);
  const OutputLock merge_lock(out, OutputLock::kMerge, o.break_lock);
  AuditResult result;
  result.specimens = Merge(out, title, o, &result).sections;
  for (const ReportSection& sec : result.specimens) {
    result.failed += sec.failed;
    result.flagged += sec.flagged;
  }
  return result;
}

int ShardPlan::ShardOf(long id) const {
  if (step < 1 || id < first || (id - first) % step != 0) return 0;
  const long k = (id - first) / step;
  return k < count ? static_cast<int>(k) + 1 : 0;
}

bool AuditOptions::IsValid(std::string* why) const {
  return batch.IsValid(why) && read_force.IsValid(why) &&
         read_scan.IsValid(why) && fuse.IsValid(why) &&
         (!figures || figure_formats.IsValid(why)) &&
         (!diagnose || diagnose_options.IsValid(why)) && groups.IsValid(why);
}

AuditResult Audit(const std::vector<fusion::Specimen>& specimens,
                  const std::string& out,
                  const std::string& title,
                  const AuditOptions& o,
                  const std::function<void(long)>& progress) {
  std::string why;
  if (!o.IsValid(&why)) throw fusion::FusionError("audit options: " + why);
  EnsureDirectory(out);
  // One audit per folder at a time (two would interleave summary.csv and
  // the specimen folders), but the shards of one audit together: each
  // writes its own specimens, then its part and the merge in turn.
  const bool sharded = o.batch.shard_count > 1;
  const OutputLock out_lock(
      out, sharded ? OutputLock::kShard : OutputLock::kExclusive, o.break_lock);
  AuditResult result;
  result.specimens.resize(specimens.size());
  std::vector<SpecimenSeries> series(specimens.size());
  std::atomic<bool> figures_missing{false};
  // As many workers as cores also analyse each specimen on their own
  // thread: more threads than cores were only switched between.
  AuditOptions worker_options = o;
  if (fusion::WorkersFillCores(specimens.size(), o.batch.jobs))
    worker_options.fuse.parallel = false;
  const auto shared = SharedInputsOf(specimens, out, o);
  static const std::vector<std::string> kNone;
  fusion::ForEachSpecimen(
      specimens.size(),
      o.batch.jobs,
      [&](size_t i) {
        const auto found = shared.find(specimens[i].name);
        AuditSpecimen(worker_options,
                      out,
                      specimens[i],
                      found == shared.end() ? kNone : found->second,
                      &result.specimens[i],
                      &series[i],
                      &figures_missing);
      },
      [&](long done) {
        if (progress) progress(done);
      });
  for (size_t i = 0; i < specimens.size(); ++i) {
    result.failed += result.specimens[i].failed;
    result.flagged += result.specimens[i].flagged;
  }
  result.figures_missing = figures_missing;
  if (sharded) {
    const OutputLock merge_lock(out, OutputLock::kMerge, o.break_lock);
    internal::WritePart(out,
                        o.batch.shard_index,
                        o.batch.shard_count,
                        result.specimens,
                        series);
    result.shard_count = o.batch.shard_count;
    if (o.merge_shards) {
      Merge(out, title, o, &result);
    } else {  // what it wrote, for a later unsharded run to replace
      std::vector<std::string> entries = {
          "parts/" +
              internal::PartName(o.batch.shard_index, o.batch.shard_count),
          "parts/plan.json"};
      for (const auto& sec : result.specimens)
        entries.push_back(sec.name + "/");
      RecordOutputs(out, "audit", entries, false);
    }
    return result;
  }
  WriteUnshardedBatch(out, title, o, series, &result);
  return result;
}

}  // namespace wearscar::report
