// result.json and diagnosis.json: every number of a test's summary, the
// options that shaped it, and the diagnosis's steps.

#include "wearscar/fusion/result_json.h"

#include <cmath>

#include "wearscar/fusion/unit.h"

namespace wearscar::fusion {
namespace {

// Cycles are numbered from 1 in every output, as in the paper (0-based
// inside the library); a cycle not set (-1) is null.
nlohmann::json CycleNumber(int zero_based) {
  return zero_based >= 0 ? nlohmann::json(zero_based + 1) : nlohmann::json();
}

nlohmann::json Stat(const Statistic& s) { return StatisticJson(s); }

nlohmann::json Split(const CostSplit& s) {
  return {{"J", s.cost},
          {"noise_floor", s.floor},
          {"excess", s.excess},
          {"excess_interval", {s.excess_low, s.excess_high}},
          {"cycles", s.cycles},
          {"note",
           "J^2 = floor^2 + excess^2 per direction; the floor is what "
           "this test's measurement noise explains, the excess what "
           "repeats at the same x from cycle to cycle"}};
}

nlohmann::json Range(const Interval& i) {
  return {{"mean", i.mean},
          {"interval", {i.low, i.high}},
          {"count", i.count},
          {"batches", i.batches}};
}

nlohmann::json ScanOptionsJson(const FuseOptions& o);

// Every option that shaped the analysis.
nlohmann::json OptionsJson(const force::ForceRecord& record,
                           const FuseOptions& o) {
  const auto& f = o.analysis.friction;
  // The spring as given (or the default), and as used: the stiffness the
  // friction's path implies when a test without a scan was analysed again
  // at it.
  const bool again = o.spring_before_friction_n_per_mm > 0;
  return {{"spring_n_per_mm",
           again ? o.spring_before_friction_n_per_mm : f.slope.spring_n_per_mm},
          {"spring_used_n_per_mm", f.slope.spring_n_per_mm},
          {"k_estimate", KEstimateName(f.k_estimate)},
          {"ensemble_cycles", f.ensemble.cycles},
          {"ensemble_bin_mm", f.ensemble.bin_mm},
          {"ensemble_span_mm", f.ensemble.span_mm},
          {"correct_k_noise_bias", f.correct_k_noise_bias},
          {"derivative", force::DerivativeMethodName(f.slope.method)},
          {"window_samples",
           f.slope.ForSamplingRate(SamplingRateOf(record)).window},
          {"window_ms", f.slope.window_ms},
          {"difference_half_span_ms", f.slope.half_span_ms},
          {"min_span_mm", f.slope.min_span_mm},
          {"noise_template_cycles", f.repeatability.template_cycles},
          {"running_in_cycles",
           o.analysis.running_in_cycles < 0
               ? nlohmann::json("auto")
               : nlohmann::json(o.analysis.running_in_cycles)},
          {"running_in_tolerance", o.analysis.running_in_tolerance},
          {"mu_interval", {f.fit.mu_min, f.fit.mu_max}},
          {"verdict_cost", CostCriterionName(o.verdict.cost_criterion)},
          {"max_excess", o.verdict.max_cost_excess},
          {"screen_excess_to_floor", o.verdict.screen_excess_to_floor},
          {"max_cost", o.verdict.max_cost},
          {"max_amplitude_ratio", o.verdict.max_amplitude_ratio},
          {"min_correlation", o.verdict.min_correlation},
          {"max_method_difference", o.verdict.max_method_difference},
          {"slope", SlopeChoiceName(o.slopes)},
          {"lugre", o.fit_lugre},
          {"scan", ScanOptionsJson(o)}};
}

// The options of the scan side (used when a scan was given).
nlohmann::json ScanOptionsJson(const FuseOptions& o) {
  const auto& t = o.track;
  nlohmann::json track = {{"min_depth_mm", t.min_depth_mm},
                          {"depth_fraction", t.depth_fraction},
                          {"min_elongation", t.min_elongation},
                          {"smoothing_sigma_px", t.smoothing_sigma_px},
                          {"manual", t.manual}};
  if (t.manual) {
    track["centre_x_mm"] = t.centre_x_mm;
    track["centre_y_mm"] = t.centre_y_mm;
    track["angle_deg"] = t.angle_deg;
    track["length_mm"] = t.manual_length_mm;
  }
  return {{"level_order", o.level.polynomial_order},
          {"level_ransac_threshold_mm", o.level.ransac_threshold_mm},
          {"spike_threshold_mm", o.spikes.threshold_mm},
          {"spike_kernel_px", o.spikes.kernel},
          {"track", track},
          {"band_mm", o.profile.band_width_mm},
          {"sphere_radius_mm", o.sphere.radius_mm},
          {"centreline_extend_mm", o.profile.extend_mm},
          {"scan_derivative", force::DerivativeMethodName(o.scan_slope.method)},
          {"scan_window_samples", o.scan_slope.window},
          {"compare_cycles", o.force_profile.cycles},
          {"compare_first", CycleNumber(o.force_profile.first_cycle)},
          {"compare_last", CycleNumber(o.force_profile.last_cycle)},
          {"profile_step_mm", o.force_profile.step_mm},
          {"scan_slope_history", o.scan_slope_history}};
}

// The force file as read: layout, channels and their units.
nlohmann::json ForceFileJson(const force::ForceMetadata& m) {
  return {{"layout", m.layout},
          {"channels", m.channel_names},
          {"units", m.channel_units},
          {"units_guessed", m.unit_guessed},
          {"time_rebuilt", m.time_rebuilt},
          {"normal_sign_flipped", m.normal_sign_flipped}};
}

// Where the force side's profile came from, given and used, and why.
nlohmann::json ProfileJson(const ProfileDecision& d) {
  return {{"given", ProfileSourceName(d.given)},
          {"source", ProfileSourceName(d.used)},
          {"why", d.reason},
          {"depth_sign", d.depth_sign},
          {"p_slope_significance", d.p_slope_significance},
          {"depth_against_friction", d.depth_agreement},
          {"spring_against_depth", d.spring_depth_agreement},
          {d.ratio_against_friction ? "spring_against_friction_path"
                                    : "spring_against_scan",
           d.spring_amplitude_ratio}};
}

// What each rule rested on and how it fared on the data: each analysis
// unit's premises, in the registry's order.
nlohmann::json PremisesJson(const TestResult& r) {
  nlohmann::json premises = nlohmann::json::array();
  std::vector<Premise> all;
  for (const auto& [unit, result] : UnitsThatRan(r)) {
    for (Premise& p : unit->PremisesErased(result, r))
      all.push_back(std::move(p));
  }
  for (const Premise& p : all) {
    premises.push_back({{"rule", p.rule},
                        {"premise", p.statement},
                        {"state", p.StateName()},
                        {"evidence", p.evidence},
                        {"otherwise", p.otherwise}});
  }
  return premises;
}

// The comparison of the slopes over the compared cycles.
nlohmann::json ComparisonJson(const TestResult& r) {
  const auto& m = r.mismatch;
  nlohmann::json j = {{"first_cycle", CycleNumber(m.first_cycle)},
                      {"last_cycle", CycleNumber(m.last_cycle)},
                      {"cycles_why", r.window.why},
                      {"mu_hat_force", Stat(m.mu_force)},
                      {"J_force", Stat(m.cost_force)},
                      {"mu_mean", Stat(m.mu_mean)},
                      {"mu_energy", Stat(m.mu_energy)},
                      {"mu_hat_minus_mu_mean", Stat(m.mu_force_minus_mean)},
                      {"mu_hat_minus_mu_energy", Stat(m.mu_force_minus_energy)},
                      {"J_force_split", Split(m.split_force)},
                      {"method_difference", Range(m.method_difference)}};
  if (!r.scan) return j;
  j["mu_hat_scan"] = Stat(m.mu_scan);
  j["J_scan"] = Stat(m.cost_scan);
  j["J_scan_split"] = Split(m.split_scan);
  j["amplitude_ratio_interval"] = {m.amplitude_ratio_low,
                                   m.amplitude_ratio_high};
  j["mu_hat_force_minus_scan"] = m.mu_force_minus_scan;
  j["k_rms_difference"] = m.k_rms_difference;
  j["profile_correlation"] = m.correlation;
  j["profile_correlation_noise_corrected"] = m.correlation_noise_corrected;
  j["amplitude_ratio"] = m.amplitude_ratio;
  if (r.scan) {
    j["waviness_correlation"] = r.scan->alignment.waviness_correlation;
    j["waviness_to_noise"] = r.scan->alignment.waviness_to_noise;
    j["track_centre_offset_mm"] = m.centre_offset_mm;
    j["reversals_offset_mm"] = m.ends_offset_mm;
    j["reversals_stroke_mm"] = m.ends_stroke_mm;
    j["reversal_walls"] = m.walls;
    j["waviness_runner_up"] = m.waviness_runner_up;
    j["waviness_runner_up_shift_mm"] = m.waviness_runner_up_shift_mm;
  }
  return j;
}

// The scan side: levelling, spikes, track, alignment.
nlohmann::json ScanJson(const ScanAnalysis& s, const ScanFits& fits) {
  const auto& t = s.track;
  const auto& a = s.alignment;
  nlohmann::json j = {{"level", LevelJson(s.level)},
                      {"spikes_removed", s.spikes_removed},
                      {"track", TrackJson(t)},
                      {"alignment",
                       {{"shift_mm", a.shift_mm},
                        {"flipped", a.flipped},
                        {"correlation", a.correlation},
                        {"correlation_forward", a.correlation_forward},
                        {"correlation_reverse", a.correlation_reverse},
                        {"scale", a.scale},
                        {"amplitude_ratio", a.amplitude_ratio},
                        {"overlap_samples", a.overlap_samples}}}};
  // --scan-slope-history: the factor on the scan's slope per cycle.
  if (!fits.slope_scale.empty()) j["slope_scale"] = fits.slope_scale;
  return j;
}

// Each analysis unit's section under its kind (a unit may have none, or
// join an object of the core's: UnitSpec::json_section), and
// which ran, what each read and its choices as given and used.
void AddUnitSections(const TestResult& r, nlohmann::json* j) {
  (*j)["units"] = nlohmann::json::array();
  for (const auto& [unit, result] : UnitsThatRan(r)) {
    nlohmann::json section = unit->JsonErased(result, r);
    if (const char* within = unit->Spec().json_section) {
      for (auto& [key, value] : section.items()) (*j)[within][key] = value;
    } else if (!section.is_null()) {
      (*j)[unit->Kind()] = std::move(section);
    }
    nlohmann::json entry = {{"kind", unit->Kind()},
                            {"what", unit->Spec().what},
                            {"reads", unit->Spec().reads}};
    for (const UnitChoice& c : unit->ChoicesErased(result, r)) {
      entry["given"][c.name] = c.given;
      entry["used"][c.name] = c.used;
      if (!c.why.empty()) entry["why"][c.name] = c.why;
    }
    (*j)["units"].push_back(std::move(entry));
  }
}

}  // namespace

nlohmann::json TrackJson(const scan::Track& t) {
  return {{"center_x_mm", t.centre_x_mm},
          {"center_y_mm", t.centre_y_mm},
          {"angle_deg", t.angle_deg},
          {"length_mm", t.length_mm},
          {"width_mm", t.width_mm},
          {"mean_depth_mm", t.mean_depth_mm},
          {"max_depth_mm", t.max_depth_mm},
          {"volume_mm3", t.volume_mm3},
          {"elongation", t.elongation},
          {"roughness_mm", t.roughness_mm},
          {"depth_to_roughness", t.depth_to_roughness},
          {"low_confidence", t.low_confidence},
          {"message", t.message},
          {"manual", t.manual},
          {"reaches_edge", t.reaches_edge}};
}

nlohmann::json LevelJson(const scan::LevelSummary& l) {
  return {{"order", l.order},
          {"coefficients",
           std::vector<double>(l.coefficients.data(),
                               l.coefficients.data() + l.coefficients.size())},
          {"inliers", l.inliers},
          {"rms_mm", l.rms_mm}};
}

nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const TestResult& r,
                          const Provenance* provenance) {
  nlohmann::json j;
  j["specimen"] = name;
  j["force_file"] = record.metadata.source;
  j["force_layout"] = record.metadata.layout;
  j["samples"] = record.size();
  j["sampling_rate_hz"] = record.metadata.sampling_rate_hz;
  j["cycles"] = r.force.cycles.cycles.size();
  j["stroke_mm"] = r.force.cycles.stroke_mm;
  // The drive's frequency over the complete cycles, and the mean sliding
  // speed it gives (two strokes a cycle).
  const auto& cycles = r.force.cycles.cycles;
  if (!cycles.empty() && cycles.back().reverse.end - 1 < record.size()) {
    const double span = record.time_s[cycles.back().reverse.end - 1] -
                        record.time_s[cycles.front().forward.begin];
    if (span > 0) {
      const double hz = static_cast<double>(cycles.size()) / span;
      j["frequency_hz"] = hz;
      j["mean_speed_mm_s"] = 2.0 * r.force.cycles.stroke_mm * hz;
    }
  }
  j["slip_fallback_half_cycles"] = r.force.slip_fallbacks;
  j["force_file_read"] = ForceFileJson(record.metadata);
  if (!r.scan_file.empty()) j["scan_file"] = r.scan_file;
  j["options"] = OptionsJson(record, r.options);
  j["running_in"] = {
      {"cycles", r.force.running_in.cycles},
      {"detected", r.force.running_in.detected},
      {"tolerance", r.force.running_in.tolerance},
      {"steady_slope_per_cycle", r.force.running_in.steady_slope},
      {"rule", r.force.running_in.rule}};
  const SlopeFits& f = r.ForceFits();
  j["slope_estimate"] = f.slope_estimate;
  j["k_rms"] = {{"repeatable", f.k_signal_rms},
                {"noise", f.k_noise_rms},
                {"noise_from_ensemble_halves", f.k_ensemble_noise_rms},
                {"mu_hat_bias_removed", f.k_noise_correction}};
  j["after_running_in"] = {{"mu_hat", Stat(f.mu_hat)}, {"J", Stat(f.cost)}};
  j["comparison"] = ComparisonJson(r);
  j["premises"] = PremisesJson(r);
  if (r.scan) j["scan"] = ScanJson(*r.scan, r.ScanSlopeFits());
  AddUnitSections(r, &j);
  j["headline"] = Headline(r);
  const Quote quote = QuoteOf(r);
  j["quote"] = {{"status", quote.status},
                {"mu", quote.mu},
                {"interval95", {quote.low, quote.high}},
                {"k_from", quote.k_from},
                {"reason", quote.reason}};
  j["profile"] = ProfileJson(r.profile);
  j["verdict"] = {
      {"explained", r.verdict.explained},
      {"judged_slope",
       r.mismatch.JudgesForceSlope() ? r.profile.SlopeName()
                                     : std::string("k from the scan")},
      {"summary", r.verdict.Summary()},
      {"judged", r.verdict.not_judged.empty()},
      {"reasons", r.verdict.reasons},
      // An explained test's repeating misfit, when above the screen's
      // limit ("" otherwise): mu is then quoted as not settled.
      {"screen", r.verdict.screen}};
  std::vector<std::string> warnings = record.metadata.warnings;
  warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
  j["warnings"] = warnings;
  j["assumptions"] = r.assumptions;
  if (provenance) j["provenance"] = provenance->ToJson();
  return j;
}

}  // namespace wearscar::fusion
