// The simulator's switches and ground truth as text: --effect name=value
// and <case>.truth.json.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::samples {
namespace {

// The hidden effects by name, for --effect name=value.
struct EffectField {
  const char* name;
  double HiddenEffects::*field;
  const char* unit;
};
constexpr EffectField kEffectFields[] = {
    {"ploughing", &HiddenEffects::ploughing_n_per_mm, "N/mm"},
    {"stribeck", &HiddenEffects::stribeck_rise, "relative"},
    {"stribeck_speed", &HiddenEffects::stribeck_speed_mm_s, "mm/s"},
    {"asymmetry", &HiddenEffects::direction_asymmetry, "relative"},
    {"q_lag", &HiddenEffects::q_lag_s, "s"},
    {"crosstalk", &HiddenEffects::crosstalk_q_into_p, "N/N"},
    {"hook", &HiddenEffects::hook_n, "N"},
    {"hook_length", &HiddenEffects::hook_length_mm, "mm"},
    {"viscous", &HiddenEffects::viscous_n_s_per_mm, "N s/mm"},
    {"mu_variation", &HiddenEffects::mu_variation, "sd of ln mu"},
    {"mu_trend", &HiddenEffects::mu_trend, "sd of ln mu"},
    {"mu_soft_spot", &HiddenEffects::mu_soft_spot, "sd of ln mu"},
    {"pickup", &HiddenEffects::pickup_n, "N"},
    {"pickup_hz", &HiddenEffects::pickup_hz, "Hz"},
    {"dwell_adhesion", &HiddenEffects::dwell_adhesion, "relative"},
    {"dwell_distance", &HiddenEffects::dwell_distance_mm, "mm"},
    {"wobble", &HiddenEffects::wobble_rad, "rad"},
    {"wobble_hz", &HiddenEffects::wobble_hz, "Hz"},
    {"thermal_drift", &HiddenEffects::thermal_drift, "relative"},
    {"thermal_time", &HiddenEffects::thermal_time_s, "s"},
    {"ringing", &HiddenEffects::ringing_hz, "Hz"},
    {"ringing_damping", &HiddenEffects::ringing_damping, "ratio"},
};

}  // namespace

std::string HiddenEffectNames() {
  std::string names;
  for (const auto& f : kEffectFields) {
    if (!names.empty()) names += ", ";
    names += fmt::format("{} ({})", f.name, f.unit);
  }
  return names;
}

void ApplyEffectSetting(const std::string& setting, HiddenEffects* effects) {
  const size_t eq = setting.find('=');
  std::string name = setting.substr(0, eq);
  std::replace(name.begin(), name.end(), '-', '_');
  if (eq == std::string::npos) {
    throw std::invalid_argument(fmt::format(
        "--effect '{}': expected name=value, e.g. ploughing=1.0", setting));
  }
  const std::string value = setting.substr(eq + 1);
  double v = 0;
  size_t used = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != value.size() || !std::isfinite(v)) {
    throw std::invalid_argument(
        fmt::format("--effect '{}': '{}' is not a number", setting, value));
  }
  for (const auto& f : kEffectFields) {
    if (name == f.name) {
      effects->*(f.field) = v;
      return;
    }
  }
  throw std::invalid_argument(
      fmt::format("--effect '{}': unknown effect '{}'; expected one of {}",
                  setting,
                  name,
                  HiddenEffectNames()));
}

namespace {

// The hidden effects and, with a friction pattern, mu along the track.
void AddEffects(const HiddenEffects& e,
                const SimulatedTest& t,
                nlohmann::json* out) {
  nlohmann::json& j = *out;
  j["effects"] = {{"ploughing_n_per_mm", e.ploughing_n_per_mm},
                  {"stribeck_rise", e.stribeck_rise},
                  {"stribeck_speed_mm_s", e.stribeck_speed_mm_s},
                  {"direction_asymmetry", e.direction_asymmetry},
                  {"q_lag_s", e.q_lag_s},
                  {"crosstalk_q_into_p", e.crosstalk_q_into_p},
                  {"hook_n", e.hook_n},
                  {"hook_length_mm", e.hook_length_mm},
                  {"viscous_n_s_per_mm", e.viscous_n_s_per_mm}};
  // The newer effects only when on (the committed samples' truth stays).
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"mu_trend", e.mu_trend},
        {"mu_soft_spot", e.mu_soft_spot},
        {"pickup_n", e.pickup_n},
        {"dwell_adhesion", e.dwell_adhesion},
        {"wobble_rad", e.wobble_rad},
        {"thermal_drift", e.thermal_drift},
        {"ringing_hz", e.ringing_hz}}) {
    if (value != 0) j["effects"][key] = value;
  }
  if (e.pickup_n != 0) j["effects"]["pickup_hz"] = e.pickup_hz;
  if (e.wobble_rad != 0) j["effects"]["wobble_hz"] = e.wobble_hz;
  if (e.ringing_hz != 0) j["effects"]["ringing_damping"] = e.ringing_damping;
  if (e.mu_variation != 0 || e.mu_trend != 0 || e.mu_soft_spot != 0) {
    // The along-track pattern of mu (every 0.05 mm of the stroke).
    if (e.mu_variation != 0) j["effects"]["mu_variation"] = e.mu_variation;
    std::vector<double> x, factor;
    for (Eigen::Index i = 0; i < t.truth.profile_x_mm.size(); i += 5) {
      x.push_back(t.truth.profile_x_mm[i]);
      factor.push_back(t.truth.mu_factor[i]);
    }
    j["mu_along_track"] = {{"x_mm", x}, {"mu_factor", factor}};
  }
}

}  // namespace

nlohmann::json TruthJson(const SimulationOptions& o, const SimulatedTest& t) {
  nlohmann::json j;
  j["case"] = o.name;
  j["seed"] = o.seed;
  j["mu_per_cycle"] = std::vector<double>(
      t.truth.mu_per_cycle.data(),
      t.truth.mu_per_cycle.data() + t.truth.mu_per_cycle.size());
  j["explained_by_wear_scar"] = t.truth.explained_by_wear_scar;
  j["elastic_mm"] = o.elastic_mm;
  j["elastic_fraction"] =
      o.elastic_fraction >= 0 ? nlohmann::json(o.elastic_fraction) : nullptr;
  j["noise"] = {{"scale", o.noise_scale},
                {"p_noise_n", o.noise_scale * o.p_noise_n},
                {"q_noise_n", o.noise_scale * o.q_noise_n},
                {"p_resolution_n", o.p_resolution_n},
                {"q_resolution_n", o.q_resolution_n}};
  j["spring_n_per_mm"] = o.spring_n_per_mm;
  j["rig"] = o.rig == Rig::kSpring ? "spring" : "dead-weight";
  if (o.rigid_sphere) j["sphere"] = "rigid";
  j["amplitudes"] = {{"force_profile_sd_mm", t.truth.force_profile_sd_mm},
                     {"force_profile_range_mm", t.truth.force_profile_range_mm},
                     {"force_profile_range_n",
                      t.truth.force_profile_range_mm * o.spring_n_per_mm},
                     {"scan_profile_sd_mm", t.truth.scan_profile_sd_mm},
                     {"scan_profile_range_mm", t.truth.scan_profile_range_mm}};
  j["plate_to_pixel"] = {
      {"note",
       "col = origin_col + col_per_mm * x, row = origin_row + "
       "row_per_mm * x; pixel centres at index * pitch"},
      {"origin_col", t.truth.origin_col},
      {"origin_row", t.truth.origin_row},
      {"col_per_mm", t.truth.col_per_mm},
      {"row_per_mm", t.truth.row_per_mm},
      {"angle_deg", t.truth.scan_angle_deg},
      {"flipped", t.truth.scan_flipped}};
  j["scan"] = {{"pitch_mm", t.truth.scan_pitch_mm},
               {"cols", o.scan_cols},
               {"rows", o.scan_rows},
               {"center_x_mm", t.truth.scan_centre_x_mm},
               {"center_y_mm", t.truth.scan_centre_y_mm},
               {"angle_deg", t.truth.scan_angle_deg},
               {"flipped", t.truth.scan_flipped},
               {"plane_dzdx", t.truth.plane_dzdx},
               {"plane_dzdy", t.truth.plane_dzdy},
               {"plane_z0_mm", t.truth.plane_z0_mm}};
  AddEffects(o.effects, t, &j);
  return j;
}

}  // namespace wearscar::samples
