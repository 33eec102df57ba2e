#include "shards.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "usage_error.h"
#include "wearscar/report/audit.h"

namespace wearscar::app {
namespace {

// An integer environment variable; `fallback` when unset.
long EnvNumber(const char* name, long fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0') {
    throw UsageError(
        fmt::format("--shard slurm: {}='{}'; expected an integer", name, text));
  }
  return value;
}

// The array of the Slurm task this runs in, and its index.
report::ShardPlan SlurmPlan(long* id) {
  if (std::getenv("SLURM_ARRAY_TASK_ID") == nullptr) {
    throw UsageError(
        "--shard slurm: SLURM_ARRAY_TASK_ID is not set; expected a task of "
        "a Slurm job array (sbatch --array=...), or --shard i/n");
  }
  *id = EnvNumber("SLURM_ARRAY_TASK_ID", 0);
  report::ShardPlan plan;
  plan.first = EnvNumber("SLURM_ARRAY_TASK_MIN", *id);
  plan.step = EnvNumber("SLURM_ARRAY_TASK_STEP", 1);
  const long max = EnvNumber("SLURM_ARRAY_TASK_MAX", plan.first);
  const long count =
      EnvNumber("SLURM_ARRAY_TASK_COUNT",
                plan.step > 0 ? (max - plan.first) / plan.step + 1 : 0);
  plan.count = static_cast<int>(count);
  plan.by = fmt::format("Slurm array job {}",
                        std::getenv("SLURM_ARRAY_JOB_ID") != nullptr
                            ? std::getenv("SLURM_ARRAY_JOB_ID")
                            : "?");
  return plan;
}

std::string PlanText(const report::ShardPlan& p) {
  return fmt::format("{} shards, indices from {}{}",
                     p.count,
                     p.first,
                     p.step != 1 ? fmt::format(" by {}", p.step) : "");
}

// Why task `id` is no shard of `plan`.
std::string NotInPlan(const std::string& spec,
                      int base,
                      long id,
                      const report::ShardPlan& plan,
                      bool slurm) {
  if (!slurm && base == 1 && id == 0) {
    return fmt::format(
        "--shard '{}': shard 0 counting from 1; expected 1 <= i <= {} "
        "(--shard-base 0 for indices from 0, as Slurm's --array=0-{} gives)",
        spec,
        plan.count,
        plan.count - 1);
  }
  return fmt::format(
      "--shard {}: index {} is not one of the {}; expected one of {}, {}, "
      "... up to {}{}",
      spec,
      id,
      PlanText(plan),
      plan.first,
      plan.first + plan.step,
      plan.first + plan.step * (plan.count - 1),
      slurm ? " (an irregular --array list: give --shard i/n in the script)"
            : "");
}

}  // namespace

ShardChoice ChooseShard(const std::string& spec,
                        int base,
                        const std::string& out) {
  long id = 0;
  report::ShardPlan asked;
  const bool slurm = spec == "slurm";
  if (slurm) {
    asked = SlurmPlan(&id);
  } else {
    int i = 0, n = 0;
    char tail = 0;
    if (std::sscanf(spec.c_str(), "%d/%d%c", &i, &n, &tail) != 2 || n < 1) {
      throw UsageError(fmt::format(
          "--shard '{}': expected i/n (shard i of n), or slurm", spec));
    }
    id = i;
    asked = {n, base, 1, "--shard"};
  }
  if (asked.count < 1 || asked.step < 1) {
    throw UsageError(fmt::format(
        "--shard {}: an array of {} tasks by {}; expected at least one",
        spec,
        asked.count,
        asked.step));
  }
  const std::optional<report::ShardPlan> kept = report::ReadShardPlan(out);
  const report::ShardPlan plan = kept ? *kept : asked;
  const bool followed = plan.count != asked.count ||
                        plan.first != asked.first || plan.step != asked.step;
  if (followed && !slurm) {
    throw UsageError(fmt::format(
        "--shard '{}' (from {}): {} holds the parts of an audit split into "
        "{} ({}; {}/parts/plan.json); expected that split, or another --out",
        spec,
        base,
        out,
        PlanText(plan),
        plan.by,
        out));
  }
  ShardChoice c;
  c.index = plan.ShardOf(id);
  c.count = plan.count;
  c.follows_plan = followed;
  if (c.index == 0) throw UsageError(NotInPlan(spec, base, id, plan, slurm));
  if (!kept) report::RecordShardPlan(out, plan);
  c.said = fmt::format("shard {} of {} (index {}; {}{})",
                       c.index,
                       c.count,
                       id,
                       PlanText(plan),
                       followed ? fmt::format(", the plan of {} in {}/parts/"
                                              "plan.json, which this re-run "
                                              "follows",
                                              plan.by,
                                              out)
                                : ", from " + plan.by);
  return c;
}

}  // namespace wearscar::app
