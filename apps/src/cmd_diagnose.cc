#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common_options.h"
#include "output.h"
#include "wearscar/fusion/diagnose.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

struct DiagnoseArgs {
  std::string force_file;
  std::string scan_file;
  std::string out;
  fusion::DiagnoseOptions diagnose;
  bool no_figures = false;
  CommonArgs common;
};

nlohmann::json MapJson(const fusion::ResidualMap& m) {
  auto vec = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  auto row = [](const Eigen::MatrixXd& a, int r) {
    std::vector<double> v;
    for (Eigen::Index c = 0; c < a.cols(); ++c) v.push_back(a(r, c));
    return v;
  };
  return {{"where", m.where},
          {"mean_abs_r_N", m.mean_abs_n_all},
          {"x_mm", vec(m.x_mm)},
          {"forward_mean_abs_r_N", row(m.mean_abs_n, 0)},
          {"reverse_mean_abs_r_N", row(m.mean_abs_n, 1)},
          {"forward_mean_r_N", row(m.mean_n, 0)},
          {"reverse_mean_r_N", row(m.mean_n, 1)},
          {"from_reversal_mm", vec(m.from_reversal_mm)},
          {"forward_by_reversal_mean_abs_r_N", row(m.reversal_mean_abs_n, 0)},
          {"reverse_by_reversal_mean_abs_r_N", row(m.reversal_mean_abs_n, 1)},
          {"block_first_cycle", m.block_first_cycle},
          {"block_mean_abs_r_N", vec(m.block_mean_abs_n)}};
}

nlohmann::json CandidateJson(const fusion::CandidateResult& c) {
  return {{"effect", c.effect},
          {"parameter_names", c.parameter_names},
          {"parameters", c.parameters},
          {"uncertainties", c.uncertainties},
          {"heldout_J_before", c.heldout_before},
          {"heldout_J_after", c.heldout_after},
          {"relative_gain", c.relative_gain},
          {"improved_fraction", c.improved_fraction},
          {"delta_bic", c.delta_bic},
          {"accepted", c.accepted}};
}

std::string ParameterText(const fusion::CandidateResult& c) {
  std::string s;
  for (size_t i = 0; i < c.parameters.size(); ++i) {
    s += fmt::format("{}{} = {:.4g} +- {:.2g}",
                     i ? ", " : "",
                     c.parameter_names[i],
                     c.parameters[i],
                     c.uncertainties[i]);
  }
  return s;
}

void WriteMapCsv(const std::string& path, const fusion::ResidualMap& m) {
  Table t;
  t.columns = {"x_mm",
               "forward_mean_abs_r_N",
               "reverse_mean_abs_r_N",
               "forward_mean_r_N",
               "reverse_mean_r_N"};
  for (Eigen::Index i = 0; i < m.x_mm.size(); ++i) {
    t.rows.push_back({m.x_mm[i],
                      m.mean_abs_n(0, i),
                      m.mean_abs_n(1, i),
                      m.mean_n(0, i),
                      m.mean_n(1, i)});
  }
  WriteTextAtomically(path, t.ToCsv());
}

void RunDiagnose(DiagnoseArgs a) {
  FinaliseCommonOptions(&a.common);
  a.diagnose.running_in_cycles = a.common.fuse.analysis.running_in_cycles;
  std::string why;
  if (!a.diagnose.IsValid(&why)) throw UsageError("diagnose: " + why);
  const force::ForceRecord record =
      force::ReadForceFile(a.force_file, a.common.read_force);
  std::optional<scan::HeightMap> map;
  if (!a.scan_file.empty())
    map = scan::ReadScan(a.scan_file, a.common.read_scan);
  fusion::FuseOptions fo = a.common.fuse;
  fo.fit_lugre = false;
  const fusion::TestResult r = fusion::AnalyzeTest(record, std::move(map), fo);
  // Groove depth along the plate from the aligned scan (levelled: 0 = unworn).
  fusion::SlopeProfile depth;
  if (r.scan) {
    const auto& fp = r.scan->force_profile;
    depth.x_mm = fp.x_mm;
    depth.k =
        -fusion::ScanHeightAtPlate(r.scan->profile, r.scan->alignment, fp.x_mm);
  }
  const fusion::Diagnosis d = fusion::Diagnose(record,
                                               r.force.cycles,
                                               fo.analysis.friction,
                                               r.scan ? &depth : nullptr,
                                               a.diagnose);
  fmt::print(
      "{}: diagnosis on {} cycles ({}-{}), slope from each cycle's binned P "
      "profile, depth from "
      "the {}\n",
      SpecimenName(a.force_file),
      d.cycles.size(),
      d.cycles.front(),
      d.cycles.back(),
      r.scan ? "scan" : "force side");
  fmt::print("where the wear-scar model misses: {}\n\n", d.before.where);
  fmt::print("{:<5} {:<34} {:>10} {:>10} {:>7} {:>8} {:>9}  {}\n",
             "step",
             "best candidate",
             "J before",
             "J after",
             "gain",
             "cycles+",
             "dBIC",
             "parameters");
  for (size_t i = 0; i < d.steps.size(); ++i) {
    const auto& c = d.steps[i].chosen;
    fmt::print(
        "{:<5} {:<34} {:>10.4f} {:>10.4f} {:>6.0f}% {:>7.0f}% {:>9.1f}  {} "
        "{}\n",
        i + 1,
        c.effect,
        c.heldout_before,
        c.heldout_after,
        100 * c.relative_gain,
        100 * c.improved_fraction,
        c.delta_bic,
        ParameterText(c),
        c.accepted ? "NAMED" : "(rejected: stop)");
  }
  fmt::print("\n{}\n", d.message);
  if (!d.named.empty()) fmt::print("after: {}\n", d.after.where);
  if (a.out.empty()) return;
  EnsureDirectory(a.out);
  nlohmann::json j;
  j["specimen"] = SpecimenName(a.force_file);
  j["cycles"] = d.cycles;
  j["named"] = d.named;
  j["heldout_J_initial"] = d.heldout_initial;
  j["heldout_J_final"] = d.heldout_final;
  j["message"] = d.message;
  j["model"] = nlohmann::json::array();
  for (const auto& c : d.model) j["model"].push_back(CandidateJson(c));
  j["steps"] = nlohmann::json::array();
  for (const auto& s : d.steps) {
    nlohmann::json step = {{"chosen", CandidateJson(s.chosen)},
                           {"tried", nlohmann::json::array()}};
    for (const auto& c : s.tried) step["tried"].push_back(CandidateJson(c));
    j["steps"].push_back(step);
  }
  j["residual_map_before"] = MapJson(d.before);
  j["residual_map_after"] = MapJson(d.after);
  j["library"] = nlohmann::json::array();
  for (const auto& e : fusion::EffectLibrary()) {
    j["library"].push_back({{"name", e->Name()},
                            {"formula", e->Formula()},
                            {"parameters", e->ParameterNames()}});
  }
  WriteTextAtomically((fs::path(a.out) / "diagnosis.json").string(),
                      j.dump(2) + "\n");
  WriteMapCsv((fs::path(a.out) / "residual_map_before.csv").string(), d.before);
  WriteMapCsv((fs::path(a.out) / "residual_map_after.csv").string(), d.after);
  if (!a.no_figures && std::system("gnuplot --version > /dev/null 2>&1") == 0) {
    const std::string body =
        "set datafile separator ','\nset grid\nset xlabel 'x (mm)'\nset ylabel "
        "'mean |r| (N)'\n"
        "set key outside right top\n";
    std::string gp;
    for (const char* term :
         {"pngcairo size 960,560", "svg size 960,560 background 'white'"}) {
      const std::string ext =
          std::string(term).rfind("png", 0) == 0 ? "png" : "svg";
      gp += fmt::format(
          "set terminal {0}\nset output 'diagnosis_residual_map.{1}'\n{2}set "
          "title "
          "'residual |Q_measured - Q_model| along the stroke, before and after "
          "the named "
          "effects'\nplot 'residual_map_before.csv' skip 1 using 1:2 with "
          "lines lw 2 title "
          "'before, forward', '' skip 1 using 1:3 with lines lw 2 title "
          "'before, reverse', "
          "'residual_map_after.csv' skip 1 using 1:2 with lines dt 2 title "
          "'after, forward', '' "
          "skip 1 using 1:3 with lines dt 2 title 'after, reverse'\nunset "
          "output\n",
          term,
          ext,
          body);
    }
    WriteTextAtomically((fs::path(a.out) / "diagnosis.gp").string(), gp);
    const std::string cmd =
        fmt::format("cd '{}' && gnuplot diagnosis.gp > diagnosis.log 2>&1",
                    fs::absolute(a.out).string());
    if (std::system(cmd.c_str()) != 0)
      fmt::print(stderr, "wearscar: gnuplot failed\n");
  }
  fmt::print("wrote {}/diagnosis.json and the residual maps\n", a.out);
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
  cmd->add_option("--force", args->force_file, "Force export")->required();
  cmd->add_option(
      "--scan", args->scan_file, "Height map (optional: depth for ploughing)");
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
                  "Effects to try (default: the whole library)");
  cmd->add_option("--max-effects", d.max_effects, "At most this many effects")
      ->capture_default_str();
  cmd->add_option("--profile-window",
                  d.profile_window,
                  "Base slope smoothing, bins of 0.01 mm")
      ->capture_default_str();
  cmd->add_flag("--no-figures", args->no_figures, "Skip the figures");
  AddCommonOptions(cmd, &args->common, true);
  cmd->callback([args] { RunDiagnose(*args); });
}

}  // namespace wearscar::app
