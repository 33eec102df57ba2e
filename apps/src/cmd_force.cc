#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "output.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/analysis.h"

namespace wearscar::app {
namespace {

struct ForceArgs {
  std::string file;
  std::string out;
  force::ReadForceOptions read;
  fusion::AnalysisOptions analysis;
  std::string derivative = "central";
};

void RunForce(ForceArgs a) {
  if (!force::ParseDerivativeMethod(a.derivative,
                                    &a.analysis.friction.slope.method)) {
    throw UsageError(fmt::format(
        "--derivative '{}': expected central or savgol", a.derivative));
  }
  std::string why;
  if (!a.analysis.IsValid(&why)) throw UsageError("force: " + why);
  const force::ForceRecord record = force::ReadForceFile(a.file, a.read);
  const fusion::ForceAnalysis r = fusion::AnalyzeForce(record, a.analysis);
  fmt::print(
      "{}: {} samples at {:.0f} Hz ({} layout), {} complete cycles, stroke "
      "{:.3f} mm\n",
      a.file,
      record.size(),
      record.metadata.sampling_rate_hz,
      record.metadata.layout,
      r.cycles.cycles.size(),
      r.cycles.stroke_mm);
  for (const auto& w : record.metadata.warnings) fmt::print("  note: {}\n", w);
  fmt::print("after running-in ({} cycles):\n", r.mu_hat.count);
  fmt::print("  mu-hat (wear-scar, k from P)  {:.4f} +- {:.4f}\n",
             r.mu_hat.mean,
             r.mu_hat.sd);
  fmt::print("  J                             {:.4f} +- {:.4f}\n",
             r.cost.mean,
             r.cost.sd);
  fmt::print("  mu mean method                {:.4f} +- {:.4f}\n",
             r.mu_mean.mean,
             r.mu_mean.sd);
  fmt::print("  mu energy method (delta_g)    {:.4f} +- {:.4f}\n",
             r.mu_energy.mean,
             r.mu_energy.sd);
  fmt::print("  slope: {}, window {}, S = {} N/mm\n",
             force::DerivativeMethodName(a.analysis.friction.slope.method),
             a.analysis.friction.slope.window,
             a.analysis.friction.slope.spring_stiffness_n_per_mm);
  if (a.out.empty()) return;
  EnsureDirectory(a.out);
  Table t;
  t.columns = {"cycle",
               "mu_hat",
               "J",
               "samples",
               "mu_mean",
               "mu_energy_max",
               "mu_energy_g",
               "E_d_Nmm",
               "delta_max_mm",
               "delta_g_mm",
               "P_mean_N",
               "Q_max_N",
               "Q_min_N",
               "P_max_N",
               "P_min_N"};
  for (size_t i = 0; i < r.cycles.cycles.size(); ++i) {
    const auto& f = r.fit_force[i];
    const auto& c = r.cof[i];
    t.rows.push_back({static_cast<double>(i),
                      f.converged ? f.mu_hat : NAN,
                      f.converged ? f.cost : NAN,
                      static_cast<double>(f.samples),
                      c.mu_mean,
                      c.mu_energy_max,
                      c.mu_energy_g,
                      c.dissipated_energy_nmm,
                      c.delta_max_mm,
                      c.delta_g_mm,
                      c.mean_normal_n,
                      c.q_max_n,
                      c.q_min_n,
                      c.p_max_n,
                      c.p_min_n});
  }
  const std::string csv =
      (std::filesystem::path(a.out) / "cycles.csv").string();
  WriteTextAtomically(csv, t.ToCsv());
  fmt::print("wrote {}\n", csv);
}

}  // namespace

void AddForceCommand(CLI::App& app) {
  auto args = std::make_shared<ForceArgs>();
  auto* cmd = app.add_subcommand(
      "force",
      "Analyse a force record alone: cycles, gross slip, mean and energy COFs, "
      "mu-hat per "
      "cycle with the slope from the normal force (k = (1/S) dP/dx)");
  cmd->add_option("file", args->file, "Force export (CSV/TSV/semicolon)")
      ->required();
  cmd->add_option("-o,--out", args->out, "Directory for cycles.csv");
  auto& r = args->read;
  cmd->add_option("--time-column", r.time_column, "Time column name or #N");
  cmd->add_option("--x-column", r.x_column, "Displacement column name or #N");
  cmd->add_option(
      "--q-column", r.tangential_column, "Friction force column name or #N");
  cmd->add_option(
      "--p-column", r.normal_column, "Normal force column name or #N");
  cmd->add_option("--rate",
                  r.sampling_rate_hz,
                  "Sampling rate (Hz) when there is no time column");
  cmd->add_flag(
      "--lenient", r.lenient, "Drop isolated bad rows with a warning");
  auto& o = args->analysis;
  cmd->add_option("--spring",
                  o.friction.slope.spring_stiffness_n_per_mm,
                  "Loading spring stiffness S, N/mm")
      ->capture_default_str();
  cmd->add_option(
         "--window", o.friction.slope.window, "Smoothing window, samples")
      ->capture_default_str();
  cmd->add_option(
         "--derivative", args->derivative, "Slope derivative: central | savgol")
      ->capture_default_str();
  cmd->add_option("--running-in",
                  o.running_in_cycles,
                  "Running-in cycles excluded from stats")
      ->capture_default_str();
  cmd->callback([args] { RunForce(*args); });
}

}  // namespace wearscar::app
