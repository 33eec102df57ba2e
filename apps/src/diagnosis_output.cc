#include "diagnosis_output.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "output.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

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

}  // namespace

fusion::Diagnosis DiagnoseTest(const force::ForceRecord& record,
                               const fusion::TestResult& r,
                               const fusion::FuseOptions& fuse,
                               const fusion::DiagnoseOptions& options) {
  fusion::SlopeProfile depth;
  if (r.scan) {
    const auto& fp = r.scan->force_profile;
    depth.x_mm = fp.x_mm;
    depth.k =
        -fusion::ScanHeightAtPlate(r.scan->profile, r.scan->alignment, fp.x_mm);
  }
  return fusion::Diagnose(record,
                          r.force.cycles,
                          fuse.analysis.friction,
                          r.scan ? &depth : nullptr,
                          options);
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

void PrintDiagnosis(const std::string& name,
                    const fusion::Diagnosis& d,
                    bool from_scan) {
  fmt::print(
      "{}: diagnosis on {} cycles ({}-{}), slope from each cycle's binned P "
      "profile, "
      "depth from the {}\n",
      name,
      d.cycles.size(),
      d.cycles.front(),
      d.cycles.back(),
      from_scan ? "scan" : "force side");
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
}

std::string WriteDiagnosis(const std::string& dir,
                           const std::string& name,
                           const fusion::Diagnosis& d,
                           bool figures) {
  EnsureDirectory(dir);
  nlohmann::json j;
  j["specimen"] = name;
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
  WriteTextAtomically((fs::path(dir) / "diagnosis.json").string(),
                      j.dump(2) + "\n");
  WriteMapCsv((fs::path(dir) / "residual_map_before.csv").string(), d.before);
  WriteMapCsv((fs::path(dir) / "residual_map_after.csv").string(), d.after);
  if (!figures || std::system("gnuplot --version > /dev/null 2>&1") != 0)
    return "";
  std::string gp;
  for (const char* term :
       {"pngcairo size 960,560", "svg size 960,560 background 'white'"}) {
    const std::string ext =
        std::string(term).rfind("png", 0) == 0 ? "png" : "svg";
    gp += fmt::format(
        "set terminal {0}\nset output 'diagnosis_residual_map.{1}'\nset "
        "datafile separator "
        "','\nset grid\nset xlabel 'x (mm)'\nset ylabel 'mean |Q_measured - "
        "Q_model| (N)'\nset "
        "key outside right top\nset title '{2}: residual along the stroke "
        "before and after the "
        "named effects ({3})' noenhanced\nplot 'residual_map_before.csv' skip "
        "1 using 1:2 with "
        "lines lw 2 title 'before, forward', '' skip 1 using 1:3 with lines lw "
        "2 title 'before, "
        "reverse', 'residual_map_after.csv' skip 1 using 1:2 with lines dt 2 "
        "title 'after, "
        "forward', '' skip 1 using 1:3 with lines dt 2 title 'after, "
        "reverse'\nunset output\n",
        term,
        ext,
        name,
        d.named.empty() ? std::string("none named")
                        : fmt::format("{}", fmt::join(d.named, ", ")));
  }
  WriteTextAtomically((fs::path(dir) / "diagnosis.gp").string(), gp);
  const std::string cmd =
      fmt::format("cd '{}' && gnuplot diagnosis.gp > diagnosis.log 2>&1",
                  fs::absolute(dir).string());
  if (std::system(cmd.c_str()) != 0) return "";
  return (fs::path(dir) / "diagnosis_residual_map.png").string();
}

}  // namespace wearscar::app
