// A diagnosis as files: diagnosis.json and the residual maps along the
// stroke (diagnosis_files.h), formatted only.

#include "wearscar/fusion/diagnosis_files.h"

#include <cmath>

#include "wearscar/fusion/effects.h"
#include "wearscar/fusion/table.h"

namespace wearscar::fusion {
namespace {

// Cycles are numbered from 1 in every output (0-based inside).
std::vector<int> OneBased(std::vector<int> cycles) {
  for (int& c : cycles) ++c;
  return cycles;
}

nlohmann::json MapJson(const ResidualMap& m) {
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
          {"block_first_cycle", OneBased(m.block_first_cycle)},
          {"block_mean_abs_r_N", vec(m.block_mean_abs_n)},
          {"direction_odd_r_N", vec(m.odd_n)},
          {"direction_even_r_N", vec(m.even_n)},
          {"direction_odd_rms_N", m.odd_rms_n},
          {"direction_even_rms_N", m.even_rms_n},
          {"repeatable_rms_N", m.repeatable_rms_n},
          {"repeatable_z", m.repeatable_z}};
}

nlohmann::json PremisesJson(const std::vector<Premise>& premises) {
  nlohmann::json j = nlohmann::json::array();
  for (const Premise& p : premises) {
    j.push_back({{"premise", p.statement},
                 {"state", p.StateName()},
                 {"evidence", p.evidence},
                 {"otherwise", p.otherwise}});
  }
  return j;
}

nlohmann::json CandidateJson(const CandidateResult& c) {
  const Effect* e = FindEffect(c.effect);
  return {{"effect", c.effect},
          {"key",
           e                                     ? e->Key()
           : c.effect == "periodic interference" ? "periodic_interference"
                                                 : ""},
          // What its contribution does between the two directions
          // (odd, even, mixed), beside the residual map's odd and even
          // parts.
          {"direction_parity", e ? ParityName(e->DirectionParity()) : "mixed"},
          {"parameter_names", c.parameter_names},
          {"parameters", c.parameters},
          {"uncertainties", c.uncertainties},
          {"heldout_J_before", c.heldout_before},
          {"heldout_J_after", c.heldout_after},
          {"relative_gain", c.relative_gain},
          {"improved_fraction", c.improved_fraction},
          {"delta_bic", c.delta_bic},
          {"plausible", c.plausible},
          {"contradicted_by", c.contradicted},
          {"premises", PremisesJson(c.premises)},
          // What it removed of the residual map's odd and even parts, and
          // whether that is the part dominating the residual.
          {"removes_direction_odd_rms_N", c.odd_removed_n},
          {"removes_direction_even_rms_N", c.even_removed_n},
          {"matches_signature", c.matches_signature},
          {"accepted", c.accepted}};
}

Table AlongTrackTable(const AlongTrackFrictionShape& a) {
  Table t({"x_mm", "mu_factor_minus_1", "groove_depth_mm"});
  const PlateProfile shape{a.x_mm, a.a};
  for (Eigen::Index i = 0; i < a.depth_x_mm.size(); ++i)
    t.rows.push_back(
        {a.depth_x_mm[i], shape.At(a.depth_x_mm[i]), a.depth_mm[i]});
  return t;
}

Table MapPatternTable(const AlongTrackFrictionShape& a) {
  Table t({"x_mm", "forward_minus_1", "reverse_minus_1"});
  for (Eigen::Index i = 0; i < a.map_x_mm.size(); ++i)
    t.rows.push_back({a.map_x_mm[i], a.map_forward[i], a.map_reverse[i]});
  return t;
}

Table ResidualMapTable(const ResidualMap& m) {
  Table t({"x_mm",
           "forward_mean_abs_r_N",
           "reverse_mean_abs_r_N",
           "forward_mean_r_N",
           "reverse_mean_r_N",
           "odd_r_N",
           "even_r_N"});
  for (Eigen::Index i = 0; i < m.x_mm.size(); ++i) {
    t.rows.push_back({m.x_mm[i],
                      m.mean_abs_n(0, i),
                      m.mean_abs_n(1, i),
                      m.mean_n(0, i),
                      m.mean_n(1, i),
                      i < m.odd_n.size() ? m.odd_n[i] : std::nan(""),
                      i < m.even_n.size() ? m.even_n[i] : std::nan("")});
  }
  return t;
}

}  // namespace

nlohmann::json DiagnosisJson(const std::string& name, const Diagnosis& d) {
  nlohmann::json j;
  j["specimen"] = name;
  std::vector<int> numbers;
  for (int c : d.cycles) numbers.push_back(c + 1);
  j["cycles"] = numbers;
  j["slope_source"] = d.slope_source;
  j["named"] = d.named;
  j["heldout_J_initial"] = d.heldout_initial;
  j["heldout_J_final"] = d.heldout_final;
  j["message"] = d.message;
  j["joint_fits"] = {{"solves", d.solves},
                     {"not_converged", d.solves_not_converged}};
  j["model"] = nlohmann::json::array();
  for (const auto& c : d.model) j["model"].push_back(CandidateJson(c));
  j["steps"] = nlohmann::json::array();
  for (const auto& s : d.steps) {
    nlohmann::json step = {{"chosen", CandidateJson(s.chosen)},
                           {"note", s.note},
                           {"tried", nlohmann::json::array()}};
    for (const auto& c : s.tried) step["tried"].push_back(CandidateJson(c));
    j["steps"].push_back(step);
  }
  j["unexplained"] = d.unexplained;
  j["periodic_lines"] = nlohmann::json::array();
  for (const auto& l : d.lines) {
    j["periodic_lines"].push_back({{"frequency_Hz", l.frequency_hz},
                                   {"Q_amplitude_N", l.q_amplitude_n},
                                   {"P_amplitude_N", l.p_amplitude_n},
                                   {"prominence", l.prominence},
                                   {"drive_harmonic", l.drive_harmonic}});
  }
  j["notched_Hz"] = d.notched_hz > 0 ? nlohmann::json(d.notched_hz) : nullptr;
  if (!d.along_track.empty()) {
    const auto& a = d.along_track;
    j["friction_along_track"] = {
        {"x_mm",
         std::vector<double>(a.x_mm.data(), a.x_mm.data() + a.x_mm.size())},
        {"a", std::vector<double>(a.a.data(), a.a.data() + a.a.size())},
        {"roughness_penalty", a.penalty},
        {"r_with_groove_depth", a.correlation_depth},
        {"r_with_depth_texture", a.correlation_texture},
        {"r_with_friction_map", a.correlation_map}};
  }
  j["residual_map_before"] = MapJson(d.before);
  j["residual_map_after"] = MapJson(d.after);
  j["library"] = nlohmann::json::array();
  for (const auto& e : EffectLibrary()) {
    j["library"].push_back({{"name", e->Name()},
                            {"key", e->Key()},
                            {"formula", e->Formula()},
                            {"parameters", e->ParameterNames()}});
  }
  return j;
}

std::vector<std::pair<std::string, std::string>> DiagnosisFiles(
    const std::string& name, const Diagnosis& d) {
  std::vector<std::pair<std::string, std::string>> files = {
      {"diagnosis.json", DiagnosisJson(name, d).dump(2) + "\n"},
      {"residual_map_before.csv", ResidualMapTable(d.before).ToCsv()},
      {"residual_map_after.csv", ResidualMapTable(d.after).ToCsv()}};
  if (!d.along_track.empty()) {
    files.emplace_back("friction_along_track.csv",
                       AlongTrackTable(d.along_track).ToCsv());
    if (d.along_track.map_x_mm.size() > 0)
      files.emplace_back("friction_map_along_track.csv",
                         MapPatternTable(d.along_track).ToCsv());
  }
  return files;
}

}  // namespace wearscar::fusion
