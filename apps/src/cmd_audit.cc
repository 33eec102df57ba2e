#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <thread>

#include "commands.h"
#include "output.h"
#include "setting_flags.h"
#include "shards.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/audit.h"
#include "wearscar/scan/formats.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

struct AuditArgs {
  std::string input;
  std::string out = "audit";
  std::string shard;
  int shard_base = 1;
  std::string merge;  // --merge OUT
  bool no_figures = false;
  bool dry_run = false;
  report::AuditOptions audit;
  GivenSettings given;  // the settings as written
};

// The value at `pointer` ("/comparison/J_force/mean"), null where a row
// lacks it.
nlohmann::json Dig(const nlohmann::json& j, const char* pointer) {
  const nlohmann::json::json_pointer p(pointer);
  return j.contains(p) ? j.at(p) : nlohmann::json();
}

// What a specimen's result rests on beyond the batch's settings: the force
// file's layout and units (those guessed named) and the running-in.
std::string ReadBrief(const nlohmann::json& row) {
  const nlohmann::json read = Dig(row, "/force_file_read");
  std::string units, guessed;
  static const char* const kChannel[5] = {"time", "x", "Q", "P", "depth"};
  if (read.is_object() && read.contains("units")) {
    const auto& u = read["units"];
    const nlohmann::json g = read.value("units_guessed", nlohmann::json());
    for (std::size_t ch = 0; ch < u.size() && ch < 5; ++ch) {
      const std::string unit = u[ch].get<std::string>();
      if (unit.empty()) continue;
      units += (units.empty() ? "" : ", ") + unit;
      if (g.is_array() && ch < g.size() && g[ch].get<bool>())
        guessed += fmt::format(
            "{}{} {}", guessed.empty() ? "" : ", ", kChannel[ch], unit);
    }
  }
  if (read.is_object() && read.value("time_rebuilt", false))
    units += ", time from the rate";
  const nlohmann::json running = Dig(row, "/running_in");
  return fmt::format(
      "read as '{}', units {}{}; running-in {} cycles ({})",
      read.is_object() ? read.value("layout", std::string("?")) : "?",
      units.empty() ? "none" : units,
      guessed.empty() ? "" : " (guessed: " + guessed + ")",
      running.is_object() ? running.value("cycles", 0) : 0,
      running.is_object() && running.value("detected", false)
          ? "detected"
          : "given or too few cycles");
}

// One line per specimen: failed, flagged or ok, with mu-hat and J, and a
// second with what it rests on (ReadBrief); then the counts.
void PrintSections(const std::vector<report::ReportSection>& sections,
                   const report::AuditResult& r) {
  for (const auto& sec : sections) {
    if (sec.failed) {
      Say("  FAILED   {}: {}\n", sec.name, sec.row["error"].get<std::string>());
    } else {
      Say("  {:8} {}: {}, mu-hat {:.4f}, J {:.3f} (noise floor {:.3f}){}\n",
          sec.flagged ? "FLAGGED" : "ok",
          sec.name,
          sec.row.value("pairing", std::string()),
          Dig(sec.row, "/comparison/mu_hat_force/mean").get<double>(),
          Dig(sec.row, "/comparison/J_force/mean").get<double>(),
          Dig(sec.row, "/comparison/J_force_split/noise_floor").get<double>(),
          sec.flagged ? " - " + sec.row["verdict"]["summary"].get<std::string>()
                      : "");
      Say("           {}\n", ReadBrief(sec.row));
    }
  }
  Say("{} specimens: {} explained, {} not explained, {} failed\n",
      sections.size(),
      sections.size() - r.flagged - r.failed,
      r.flagged,
      r.failed);
  if (!r.kept.empty()) {
    Say("kept from the earlier audit in this folder: {} specimen{} ({}); the "
        "tables and report hold them beside this run's (--replace makes the "
        "batch this run's alone)\n",
        r.kept.size(),
        r.kept.size() > 1 ? "s" : "",
        r.kept.size() > 6
            ? fmt::format("{}, ...",
                          fmt::join(r.kept.begin(), r.kept.begin() + 5, ", "))
            : fmt::format("{}", fmt::join(r.kept, ", ")));
  }
}

// A shard's or a merge's line on the merged summary.
void PrintMerged(const report::AuditResult& r, const std::string& out) {
  Say("merged into {}: {} specimens from {} of {} shards{}\n",
      out,
      r.merged,
      r.shard_count - static_cast<int>(r.missing_shards.size()),
      r.shard_count,
      r.missing_shards.empty()
          ? std::string()
          : fmt::format("; missing: {} {} (not in the summary yet; run "
                        "{}, or `wearscar audit --merge {}` once done)",
                        r.missing_shards.size() > 1 ? "shards" : "shard",
                        fmt::join(r.missing_shards, ", "),
                        r.missing_shards.size() > 1 ? "them" : "it",
                        out));
}

void RunMerge(const AuditArgs& a, const fusion::TestSettings& settings) {
  report::AuditOptions o = a.audit;
  o.read_force = settings.read_force;
  o.read_scan = settings.read_scan;
  o.fuse = settings.fuse;
  o.figures = !a.no_figures;
  o.break_lock = BreakLock();
  const report::AuditResult r = report::MergeAudit(
      a.merge, fmt::format("wearscar audit merged in {}", a.merge), o);
  PrintSections(r.specimens, r);
  PrintMerged(r, a.merge);
  Say("report: {}\n", fs::absolute(r.report_path).string());
  // A merge job that ran before every shard had written its part is not
  // a complete audit (an `afterany` dependency shows it as failed).
  if (!r.missing_shards.empty()) {
    fmt::print(stderr,
               "wearscar: {}: {} of {} shards missing ({}); their "
               "specimens are not in the summary\n",
               a.merge,
               r.missing_shards.size(),
               r.shard_count,
               fmt::join(r.missing_shards, ", "));
    SetExitStatus(kExitSpecimensFailed);
  }
}

// The default spring, for the specimens whose file states none.
void SayDefaultSpring(const report::AuditResult& r,
                      const fusion::TestSettings& settings) {
  std::size_t defaulted = 0, analysed = 0;
  for (const auto& sec : r.specimens) {
    if (sec.failed) continue;
    ++analysed;
    const nlohmann::json said = Dig(sec.row, "/assumptions");
    if (said.is_array() && !said.empty() && said[0].is_string() &&
        said[0].get<std::string>().find("the default") != std::string::npos)
      ++defaulted;
  }
  if (!settings.fuse.spring_given && defaulted > 0) {
    Say("assumed for {}: spring S = {:g} N/mm, the default (the paper's "
        "rig), neither given nor stated in the file; each result says the "
        "stiffness its scan implies (--spring to set it)\n",
        defaulted == analysed
            ? std::string("every specimen")
            : fmt::format("{} of {} specimens", defaulted, analysed),
        settings.fuse.analysis.friction.slope.spring_n_per_mm);
  }
}

void RunAudit(AuditArgs a) {
  fusion::TestSettings settings =
      WithFlagNames([&] { return fusion::MakeTestSettings(a.given); });
  if (!a.merge.empty()) return RunMerge(a, settings);
  if (a.input.empty()) {
    throw UsageError(
        "audit: no input; expected a folder or a manifest (or --merge OUT to "
        "merge the shards written into OUT)");
  }
  fusion::BatchOptions& batch = a.audit.batch;
  a.audit.break_lock = BreakLock();
  if (!a.shard.empty() && !a.dry_run) {
    const ShardChoice c = ChooseShard(a.shard, a.shard_base, a.out);
    batch.shard_index = c.index;
    batch.shard_count = c.count;
    // A re-run following the folder's plan is said in every print mode.
    if (c.follows_plan)
      fmt::print(stderr, "wearscar: {}\n", c.said);
    else
      Say("{}\n", c.said);
  }
  a.audit.read_force = settings.read_force;
  a.audit.read_scan = settings.read_scan;
  a.audit.fuse = settings.fuse;
  a.audit.figures = !a.no_figures;
  if (a.no_figures) WithoutFigureData(&a.audit.fuse);
  std::vector<std::string> skipped;
  const std::vector<fusion::Specimen> mine =
      fusion::FindSpecimens(a.input, batch, &skipped, &a.audit.other_shards);
  if (!skipped.empty()) {
    Say("skipped {} folder{} wearscar's analyses wrote: {} "
        "(--include-output-folders searches them)\n",
        skipped.size(),
        skipped.size() > 1 ? "s" : "",
        fmt::join(skipped, ", "));
  }
  if (a.dry_run) {
    const fs::path root = fs::is_directory(a.input)
                              ? fs::path(a.input)
                              : fs::path(a.input).parent_path();
    Say("{}", fusion::PairingTable(mine, root.string()));
    return;
  }
  const unsigned jobs = batch.jobs > 0
                            ? static_cast<unsigned>(batch.jobs)
                            : std::max(1u, std::thread::hardware_concurrency());
  Progress progress(
      fmt::format("audit ({} specimens, {} jobs)", mine.size(), jobs),
      static_cast<long>(mine.size()));
  const std::string title = fmt::format("wearscar audit of {}", a.input);
  const report::AuditResult r = report::Audit(
      mine, a.out, title, a.audit, [&](long done) { progress.Update(done); });
  progress.Finish();
  PrintSections(r.specimens, r);
  if (mine.empty())
    Say("no specimens fall to this shard (more shards than specimens): "
        "wrote an empty part\n");
  if (batch.shard_count > 1 && a.audit.merge_shards) PrintMerged(r, a.out);
  if (batch.shard_count > 1 && !a.audit.merge_shards)
    Say("wrote {}/parts/shard-{}-of-{}.json; `wearscar audit --merge {}` "
        "merges the parts\n",
        a.out,
        batch.shard_index,
        batch.shard_count,
        a.out);
  SayDefaultSpring(r, settings);
  if (!r.report_path.empty()) {
    Say("report: {}\n", fs::absolute(r.report_path).string());
    Say("tables: {} and summary.json\n",
        (fs::path(a.out) / "summary.csv").string());
  }
  if (!r.batch_figures.message.empty())
    fmt::print(stderr, "wearscar: {}\n", r.batch_figures.message);
  std::vector<nlohmann::json> rows;
  for (const auto& sec : r.specimens) rows.push_back(sec.row);
  PrintJsonSummary(nlohmann::json(rows));
  SetExitStatus(r.failed > 0        ? kExitSpecimensFailed
                : r.figures_missing ? kExitFiguresMissing
                                    : 0);
}

// --shard, --shard-base and --no-merge.
void AddShardOptions(CLI::App* cmd, AuditArgs* args) {
  cmd->add_option("--shard-base",
                  args->shard_base,
                  "What --shard i/n counts i from: 1 (the default) or 0 "
                  "(as a Slurm --array=0-15 numbers its tasks)")
      ->check(CLI::IsMember({0, 1}));
  cmd->add_flag_callback(
      "--no-merge",
      [args] { args->audit.merge_shards = false; },
      "A shard writes its part only; one `--merge` job merges them all "
      "(on a cluster: the shards do not queue on the report)");
  cmd->add_option("--shard",
                  args->shard,
                  "Process shard i of n (counted from 1, or --shard-base), "
                  "e.g. 2/4, or 'slurm': the task of a Slurm job array, "
                  "numbered by the array (the first task records the plan "
                  "in OUT/parts/plan.json; re-runs of a task follow it). "
                  "The shards may "
                  "run at once into one --out");
}

// --factors, --plan-difference, --plan-power and --csv-locale.
void AddGroupOptions(CLI::App* cmd, report::AuditOptions* audit) {
  fusion::GroupOptions* groups = &audit->groups;
  cmd->add_option("--factors",
                  groups->factors,
                  "The factors the groups are compared by (comma-separated: "
                  "species,plane,direction, a name pattern's named groups "
                  "'(?<load>...)', a manifest's extra columns); default: "
                  "every factor with two levels or more")
      ->delimiter(',');
  cmd->add_option("--plan-difference",
                  groups->plan_difference,
                  "The difference in mu the planning line sizes the next "
                  "batch for (replicates per group)")
      ->capture_default_str();
  cmd->add_option("--csv-locale",
                  audit->csv_locale,
                  "The CSV tables' convention: 'de' for semicolons and "
                  "decimal commas (a German Excel); default commas and "
                  "decimal points (summary.json and the .xlsx are the same "
                  "either way)")
      ->check(CLI::IsMember({"", "c", "de"}));
  cmd->add_option("--plan-power",
                  groups->plan_power,
                  "The power to find it with (two-sided, 5% level)")
      ->capture_default_str();
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
                  "Folder of files, or manifest.csv (specimen,force,scan)");
  cmd->add_option("--merge",
                  args->merge,
                  "Merge what the shards of an audit wrote into this folder "
                  "(summary, batch figures, report of every shard present; "
                  "each shard also does it when it ends)");
  cmd->add_option("-o,--out", args->out, "Output folder")
      ->capture_default_str();
  cmd->add_option("-j,--jobs",
                  args->audit.batch.jobs,
                  "Parallel specimens (default: all cores)");
  AddShardOptions(cmd, args.get());
  cmd->add_flag("--replace",
                args->audit.replace_batch,
                "The batch is this run's specimens alone: what an earlier "
                "audit wrote into --out for other specimens is removed (by "
                "default they are kept, and a re-run of some specimens "
                "updates their folders and the batch's tables)");
  AddGroupOptions(cmd, &args->audit);
  cmd->add_flag("--dry-run",
                args->dry_run,
                "Print how the files pair (specimen, force, scan, note) and "
                "stop: nothing is read or written");
  cmd->add_option("--name-pattern",
                  args->audit.batch.name_pattern,
                  "Regular expression naming a specimen in file names")
      ->capture_default_str();
  cmd->add_flag_callback(
      "--no-recursive",
      [args] { args->audit.batch.recursive = false; },
      "Look in the folder itself only (by default its sub-folders too, "
      "skipping hidden ones and the outputs of wearscar's analyses)");
  cmd->add_flag("--include-output-folders",
                args->audit.batch.output_folders,
                "Search the folders wearscar's analyses wrote too (fuse, "
                "audit, ...; `wearscar simulate`'s are always searched)");
  cmd->add_flag(
      "--diagnose",
      args->audit.diagnose,
      "Also diagnose each specimen (named missing effects, residual maps)");
  AddTestCommandOptions(cmd,
                        &args->no_figures,
                        &args->audit.figure_formats,
                        fusion::kFuseSettings,
                        /*break_lock=*/true,
                        &args->given);
  cmd->footer(
      "Examples:\n"
      "  wearscar audit lab/ -o audit\n"
      "  wearscar audit manifest.csv -o audit --diagnose --shard 2/4 -j 1\n"
      "  wearscar audit --merge audit");
  cmd->callback([args] { RunAudit(*args); });
}

}  // namespace wearscar::app
