#pragma once

// The audit of a batch: every specimen analysed (in parallel), its folder
// written, its figures drawn and, when asked, its diagnosis; then the
// batch's tables (summary.csv, summary.jsonl, summary.json), its figures
// and report.html. What `wearscar audit` does, for any program.

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "wearscar/force/read_force.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/groups.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/html_report.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::report {

struct AuditOptions {
  fusion::BatchOptions batch;
  force::ReadForceOptions read_force;
  scan::ReadScanOptions read_scan;
  fusion::FuseOptions fuse;
  // The batch's groups and factors compared (groups.csv, the report's
  // section), with the specimen as the unit.
  fusion::GroupOptions groups;
  // The CSV tables' convention: "" (commas, decimal points) or "de"
  // (semicolons, decimal commas: what a German Excel opens).
  std::string csv_locale;
  bool figures = true;  // each specimen's and the batch's (gnuplot)
  FigureFormats figure_formats;
  bool diagnose = false;  // name the effects a flagged model misses
  fusion::DiagnoseOptions diagnose_options;
  // A shard also merges every part present when it ends (false: it writes
  // its part only, and a merge job merges once; see MergeAudit).
  bool merge_shards = true;
  // Lock files left by a killed wearscar are removed (OutputLock).
  bool break_lock = false;
  // An unsharded run into a folder an earlier audit wrote: false keeps the
  // earlier specimens this run does not analyse (their folders, rows and
  // figures stay in the batch's tables and report); true makes the batch
  // this run's alone and removes what the earlier audit wrote for the
  // others.
  bool replace_batch = false;
  // A shard's run: the batch's specimens the other shards analyse
  // (FindSpecimens' `others`), whose inputs this shard's may share.
  std::vector<fusion::Specimen> other_shards;

  // Every part valid (the batch's, the readers', the analysis's and, when
  // diagnosing, the diagnosis's); `why` names the first that is not.
  bool IsValid(std::string* why) const;
};

struct AuditResult {
  // One per specimen in the order given: its summary row (result.json with
  // its identity, or its error), verdict and figures.
  std::vector<ReportSection> specimens;
  FigureSet batch_figures;
  int failed = 0;   // specimens that could not be analysed
  int flagged = 0;  // not explained by wear-scar interaction
  // Figures asked for and not drawn for some specimen.
  bool figures_missing = false;
  std::string report_path;  // <out>/report.html
  // A shard's run (and MergeAudit): the shards of the audit, those whose
  // part is not there yet, and the specimens the merged summary holds.
  int shard_count = 1;
  std::vector<int> missing_shards;
  int merged = 0;
  // An unsharded run: the earlier audit's specimens kept beside this run's
  // (replace_batch false), by name.
  std::vector<std::string> kept;
};

// Audits `specimens` (fusion::FindSpecimens) into `out`, which it locks
// (OutputLock; a shard shares it with the other shards) for the run:
// <out>/<specimen>/ per specimen, staged so that its files appear together; a
// specimen that fails is its section's error and the rest complete. `title`
// heads report.html. progress(done) is called after each specimen, one call at
// a time. Throws fusion::FusionError for invalid options (naming them) and
// OutputError when `out` cannot be written.
AuditResult Audit(const std::vector<fusion::Specimen>& specimens,
                  const std::string& out,
                  const std::string& title,
                  const AuditOptions& options,
                  const std::function<void(long)>& progress = {});

// The shards of an audit run at once into one folder (--shard i/n, as the
// tasks of a cluster job array): each writes its specimens' folders, then,
// one at a time, its part (<out>/parts/shard-i-of-n.json) and the summary,
// batch figures and report of every part present. MergeAudit does that
// last step again, alone (`wearscar audit --merge OUT`): idempotent; the
// result's specimens are the merged ones, missing_shards those absent.
AuditResult MergeAudit(const std::string& out,
                       const std::string& title,
                       const AuditOptions& options);

// How the indices of a scheduler's job array map to the shards of one
// audit: `count` shards, the first numbered `first`, the next first +
// step, ... (Slurm's --array=0-15 is {16, 0, 1}; --array=1-31:2 is
// {16, 1, 2}). `by` says where it came from ("--shard", "Slurm array job
// 1234").
struct ShardPlan {
  int count = 0;
  long first = 1, step = 1;
  std::string by;
  // The 1-based shard of task `id`, or 0 when the plan has no such task.
  int ShardOf(long id) const;
};
// The plan <out>/parts/plan.json holds, which every shard and re-run of
// the audit follows (none before the first shard has run); the first
// records its own. Throw OutputError when the file cannot be read or
// written.
std::optional<ShardPlan> ReadShardPlan(const std::string& out);
void RecordShardPlan(const std::string& out, const ShardPlan& plan);

}  // namespace wearscar::report
