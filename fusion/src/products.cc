#include "wearscar/fusion/products.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "wearscar/fusion/effects.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion {
namespace {

double Nan() { return std::nan(""); }

// Cycles are numbered from 1 in every output, as in the paper (0-based
// inside the library); a cycle not set (-1) is null.
std::vector<int> OneBased(std::vector<int> cycles) {
  for (int& c : cycles) ++c;
  return cycles;
}
nlohmann::json CycleNumber(int zero_based) {
  return zero_based >= 0 ? nlohmann::json(zero_based + 1) : nlohmann::json();
}

// mean, sd, count; with the mean's 95% interval and the effective number
// of independent cycles where they were estimated.
nlohmann::json Stat(const Statistic& s) {
  nlohmann::json j = {{"mean", s.mean}, {"sd", s.sd}, {"count", s.count}};
  if (std::isfinite(s.low)) {
    j["interval95"] = {s.low, s.high};
    j["effective_cycles"] = s.effective_count;
  }
  return j;
}

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
  return {{"spring_n_per_mm", f.slope.spring_n_per_mm},
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
          {"centreline_extend_mm", o.profile.extend_mm},
          {"scan_derivative", force::DerivativeMethodName(o.scan_slope.method)},
          {"scan_window_samples", o.scan_slope.window},
          {"compare_cycles", o.force_profile.cycles},
          {"compare_first", CycleNumber(o.force_profile.first_cycle)},
          {"compare_last", CycleNumber(o.force_profile.last_cycle)},
          {"profile_step_mm", o.force_profile.step_mm},
          {"scan_slope_history", o.scan_slope_history}};
}

// The track's size, the load and distance, and the specific wear rate
// (null where there was no usable scan).
nlohmann::json WearJson(const Wear& w) {
  return {{"volume_mm3", w.volume_mm3},
          {"mean_depth_mm", w.mean_depth_mm},
          {"max_depth_mm", w.max_depth_mm},
          {"width_mm", w.width_mm},
          {"length_mm", w.length_mm},
          {"normal_load_n", w.normal_load_n},
          {"sliding_distance_m", w.sliding_distance_m},
          {"specific_wear_rate_mm3_per_n_m", w.specific_rate_mm3_per_n_m}};
}

// The force file as read: layout, channels and their units.
nlohmann::json ForceFileJson(const force::ForceMetadata& m) {
  return {{"layout", m.layout},
          {"channels", m.channel_names},
          {"units", m.channel_units},
          {"time_rebuilt", m.time_rebuilt},
          {"normal_sign_flipped", m.normal_sign_flipped}};
}

// The comparison of the slopes over the compared cycles.
nlohmann::json ComparisonJson(const TestResult& r) {
  const auto& m = r.mismatch;
  nlohmann::json j = {{"first_cycle", CycleNumber(m.first_cycle)},
                      {"last_cycle", CycleNumber(m.last_cycle)},
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
  return j;
}

// The scan side: levelling, spikes, track, alignment.
nlohmann::json ScanJson(const ScanAnalysis& s) {
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
  if (!s.slope_scale.empty()) j["slope_scale"] = s.slope_scale;
  return j;
}

nlohmann::json LugreJson(const TestResult& r) {
  const auto& p = r.lugre->parameters;
  return {{"cycle", CycleNumber(r.detail_cycle)},
          {"sigma0_n_per_mm", p.sigma0_n_per_mm},
          {"sigma1_n_s_per_mm", p.sigma1_n_s_per_mm},
          {"sigma2_n_s_per_mm", p.sigma2_n_s_per_mm},
          {"sigma2_negative", p.sigma2_n_s_per_mm < 0},
          {"stribeck_speed_mm_s", p.stribeck_speed_mm_s},
          {"F_c_N", p.coulomb_n},
          {"F_s_N", p.static_n},
          {"J", r.lugre->cost},
          {"J_wearscar_same_cycle", r.force.fit_force[r.detail_cycle].cost},
          {"converged", r.lugre->converged},
          {"physically_plausible", r.lugre->physically_plausible},
          {"message", r.lugre->message}};
}

// The normal distribution's two-sided 95% quantile: mu-hat's interval per
// cycle is mu_hat +- kZ95 MuFit::standard_error.
constexpr double kZ95 = 1.96;

// cycles.csv: one row per cycle.
Table CycleTable(const TestResult& r) {
  const auto& cycles = r.force.cycles.cycles;
  Table t;
  t.columns = CycleColumns();
  for (size_t c = 0; c < cycles.size(); ++c) {
    const auto& f = r.force.fit_force[c];
    const auto& cof = r.force.cof[c];
    const MuFit* s = r.scan ? &r.scan->fit_scan[c] : nullptr;
    const bool sok = s && s->converged;
    t.rows.push_back(
        {static_cast<double>(c + 1),
         f.converged ? f.mu_hat : Nan(),
         f.converged ? f.cost : Nan(),
         f.converged ? f.cost_floor : Nan(),
         f.converged ? f.cost_excess : Nan(),
         sok ? s->mu_hat : Nan(),
         sok ? s->cost : Nan(),
         sok ? s->cost_floor : Nan(),
         sok ? s->cost_excess : Nan(),
         static_cast<double>(f.samples),
         cof.mu_mean,
         cof.mu_energy_max,
         cof.mu_energy_g,
         cof.dissipated_energy_nmm,
         cof.delta_max_mm,
         cof.delta_g_mm,
         cof.mean_normal_n,
         cof.q_max_n,
         cof.q_min_n,
         cof.p_max_n,
         cof.p_min_n,
         cof.p_range_n,
         cof.qp_correlation,
         static_cast<int>(c) < r.force.running_in.cycles ? 1.0 : 0.0,
         static_cast<double>(cycles[c].forward.slip_fallback +
                             cycles[c].reverse.slip_fallback),
         c < r.track_history.waviness_sd_mm.size()
             ? r.track_history.waviness_sd_mm[c]
             : Nan(),
         f.converged ? f.mu_hat - kZ95 * f.standard_error : Nan(),
         f.converged ? f.mu_hat + kZ95 * f.standard_error : Nan(),
         sok ? s->mu_hat - kZ95 * s->standard_error : Nan(),
         sok ? s->mu_hat + kZ95 * s->standard_error : Nan()});
  }
  return t;
}

// friction_map.csv: mu along the stroke per cycle and direction, raw and
// corrected for the slope (cycles from 1, direction +1 forward, -1
// reverse; empty bins left out).
Table FrictionMapTable(const FrictionMap& m) {
  Table t;
  t.columns = {"cycle", "direction", "x_mm", "mu_raw", "mu_corrected", "n"};
  for (int c = 0; c < m.cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      for (size_t b = 0; b < m.x_mm.size(); ++b) {
        const size_t i = m.Index(c, d, b);
        if (!std::isfinite(m.mu_corrected[i])) continue;
        t.rows.push_back({static_cast<double>(c + 1),
                          d == 0 ? 1.0 : -1.0,
                          m.x_mm[b],
                          m.mu_raw[i],
                          m.mu_corrected[i],
                          static_cast<double>(m.samples[i])});
      }
    }
  }
  return t;
}

// track_history.csv: h = P/S about its mean along the stroke, per cycle
// and direction (cycles from 1; empty bins left out).
Table TrackHistoryTable(const TrackHistory& h) {
  Table t;
  t.columns = {"cycle", "direction", "x_mm", "h_mm"};
  for (int c = 0; c < h.cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      for (size_t b = 0; b < h.x_mm.size(); ++b) {
        const double v = h.height_mm[h.Index(c, d, b)];
        if (std::isfinite(v))
          t.rows.push_back(
              {static_cast<double>(c + 1), d == 0 ? 1.0 : -1.0, h.x_mm[b], v});
      }
    }
  }
  return t;
}

// loops.csv: the samples of the chosen cycles' hysteresis loops.
Table LoopTable(const force::ForceRecord& record,
                const TestResult& r,
                std::vector<int> loops) {
  const auto& cycles = r.force.cycles.cycles;
  const int n = static_cast<int>(cycles.size());
  if (loops.empty()) {
    loops = {0, std::min(2, n - 1), std::min(10, n - 1), n - 1};
  }
  Table l;
  l.columns = {"cycle", "time_s", "x_mm", "Q_N", "P_N"};
  for (int c : loops) {
    if (c < 0 || c >= n) continue;
    for (Eigen::Index i = cycles[c].forward.begin; i < cycles[c].reverse.end;
         ++i) {
      l.rows.push_back({static_cast<double>(c + 1),
                        record.time_s[i],
                        record.x_mm[i],
                        record.tangential_n[i],
                        record.normal_n[i]});
    }
  }
  return l;
}

// detail.csv: the detail cycle's gross-slip samples, both slopes and Q
// reconstructed with each (paper Figs. 10, 12).
Table DetailTable(const TestResult& r,
                  const CycleSamples& kf,
                  int dc,
                  double mu_f,
                  double mu_s) {
  Table d;
  d.columns = {"cycle",
               "direction",
               "x_mm",
               "Q_N",
               "P_N",
               "k_force",
               "k_scan",
               "Q_model_force_N",
               "Q_model_scan_N"};
  for (const SlipSamples* s : {&kf.forward, &kf.reverse}) {
    for (Eigen::Index i = 0; i < s->q_n.size(); ++i) {
      const double ks = r.scan ? r.scan->slope.At(s->x_mm[i]) : Nan();
      d.rows.push_back(
          {static_cast<double>(dc + 1),
           static_cast<double>(s->direction),
           s->x_mm[i],
           s->q_n[i],
           s->p_n[i],
           s->k[i],
           ks,
           WearScarTangentialForce(s->p_n[i], s->k[i], mu_f, s->direction),
           std::isfinite(ks)
               ? WearScarTangentialForce(s->p_n[i], ks, mu_s, s->direction)
               : Nan()});
    }
  }
  return d;
}

// cost_curve.csv: J(mu) on the detail cycle with each slope (Fig. 11).
Table CostCurveTable(const force::ForceRecord& record,
                     const TestResult& r,
                     const FrictionFitOptions& fopt,
                     const CycleSamples& kf,
                     int dc,
                     int points) {
  const Eigen::VectorXd grid =
      Eigen::VectorXd::LinSpaced(points, fopt.fit.mu_min, fopt.fit.mu_max);
  const Eigen::VectorXd jf = CostCurve(kf, grid);
  Eigen::VectorXd js = Eigen::VectorXd::Constant(grid.size(), Nan());
  if (r.scan) {
    js = CostCurve(GatherCycle(record,
                               r.force.cycles.cycles[dc],
                               SlopeSource::kScan,
                               fopt,
                               &r.scan->slope),
                   grid);
  }
  Table cc;
  cc.columns = {"mu", "J_force", "J_scan"};
  for (Eigen::Index i = 0; i < grid.size(); ++i)
    cc.rows.push_back({grid[i], jf[i], js[i]});
  return cc;
}

// profiles.csv: the force side's profiles and the aligned scan profile
// along the plate; centreline.csv: the scan's centreline.
void AddProfileTables(const ScanAnalysis& scan, TestProducts* out) {
  const auto& fp = scan.force_profile;
  const Eigen::VectorXd h =
      ScanHeightAtPlate(scan.profile, scan.alignment, fp.x_mm);
  Table p;
  p.columns = {"x_mm",
               "f_forward_mm",
               "f_reverse_mm",
               "f_mean_mm",
               "h_scan_mm",
               "h_scan_scaled_mm",
               "k_scan"};
  const auto& a = scan.alignment;
  for (Eigen::Index i = 0; i < fp.x_mm.size(); ++i) {
    p.rows.push_back({fp.x_mm[i],
                      fp.forward_mm[i],
                      fp.reverse_mm[i],
                      fp.mean_mm[i],
                      h[i],
                      a.scale * h[i] + a.offset_mm,
                      scan.slope.At(fp.x_mm[i])});
  }
  out->tables.emplace_back("profiles.csv", std::move(p));
  Table sp;
  sp.columns = {"s_mm", "h_mm", "n_valid"};
  for (Eigen::Index i = 0; i < scan.profile.s_mm.size(); ++i) {
    sp.rows.push_back({scan.profile.s_mm[i],
                       scan.profile.height_mm[i],
                       static_cast<double>(scan.profile.valid_samples[i])});
  }
  out->tables.emplace_back("centreline.csv", std::move(sp));
}

// lugre.csv: LuGre against the wear-scar model on the detail cycle (Fig.
// 17); the wear-scar model describes gross slip only. The gathered samples
// keep the record's order, so one pointer per direction walks them
// alongside.
Table LugreTable(const force::ForceRecord& record,
                 const TestResult& r,
                 const CycleSamples& kf,
                 int dc,
                 double mu_f) {
  const auto& lg = *r.lugre;
  const auto& c = r.force.cycles.cycles[dc];
  Table lt;
  lt.columns = {"time_s", "x_mm", "Q_N", "Q_lugre_N", "Q_wearscar_N"};
  Eigen::Index next[2] = {0, 0};
  auto model_at = [&](Eigen::Index src) {
    const bool forward = src < c.forward.end;
    const force::HalfCycle& h = forward ? c.forward : c.reverse;
    if (src < h.slip_begin || src >= h.slip_end) return Nan();
    const SlipSamples& s = forward ? kf.forward : kf.reverse;
    Eigen::Index& j = next[forward ? 0 : 1];
    if (j < s.x_mm.size() && s.x_mm[j] == record.x_mm[src] &&
        s.p_n[j] == record.normal_n[src]) {
      ++j;
      return WearScarTangentialForce(
          s.p_n[j - 1], s.k[j - 1], mu_f, s.direction);
    }
    return Nan();  // a sample the fit did not use (no finite k)
  };
  for (Eigen::Index i = 0; i < lg.time_s.size(); ++i) {
    lt.rows.push_back({lg.time_s[i],
                       lg.x_mm[i],
                       lg.q_measured_n[i],
                       lg.q_lugre_n[i],
                       model_at(c.forward.begin + i)});
  }
  return lt;
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
          {"block_mean_abs_r_N", vec(m.block_mean_abs_n)}};
}

nlohmann::json CandidateJson(const CandidateResult& c) {
  const Effect* e = FindEffect(c.effect);
  return {{"effect", c.effect},
          {"key", e ? e->Key() : std::string()},
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

Table ResidualMapTable(const ResidualMap& m) {
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
  return t;
}

nlohmann::json DiagnosisJson(const std::string& name, const Diagnosis& d) {
  nlohmann::json j;
  j["specimen"] = name;
  std::vector<int> numbers;
  for (int c : d.cycles) numbers.push_back(c + 1);
  j["cycles"] = numbers;
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
                           {"tried", nlohmann::json::array()}};
    for (const auto& c : s.tried) step["tried"].push_back(CandidateJson(c));
    j["steps"].push_back(step);
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

}  // namespace

std::vector<std::pair<std::string, std::string>> DiagnosisFiles(
    const std::string& name, const Diagnosis& d) {
  return {{"diagnosis.json", DiagnosisJson(name, d).dump(2) + "\n"},
          {"residual_map_before.csv", ResidualMapTable(d.before).ToCsv()},
          {"residual_map_after.csv", ResidualMapTable(d.after).ToCsv()}};
}

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
          {"manual", t.manual}};
}

nlohmann::json LevelJson(const scan::LevelSummary& l) {
  return {{"order", l.order},
          {"coefficients",
           std::vector<double>(l.coefficients.data(),
                               l.coefficients.data() + l.coefficients.size())},
          {"inliers", l.inliers},
          {"rms_mm", l.rms_mm}};
}

std::string Table::ToCsv() const {
  fmt::memory_buffer buf;
  for (size_t c = 0; c < columns.size(); ++c) {
    fmt::format_to(std::back_inserter(buf), "{}{}", c ? "," : "", columns[c]);
  }
  buf.push_back('\n');
  // printf's %.8g, by std::to_chars (Ryu): about three times as fast as
  // fmt's precision formatting, the same characters. Whole numbers below
  // 10^8 (cycles, directions, counts: half the cells of the friction map
  // and the track's history) are the same digits as an integer's, written
  // as one in a third of the time.
  char cell[32];
  for (const auto& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) {
      if (c) buf.push_back(',');
      const double v = row[c];
      if (!std::isfinite(v)) continue;
      const bool whole = std::abs(v) < 1e8 && v == std::trunc(v) &&
                         !(v == 0 && std::signbit(v));
      const auto r =
          whole
              ? std::to_chars(cell, cell + sizeof cell, static_cast<long>(v))
              : std::to_chars(
                    cell, cell + sizeof cell, v, std::chars_format::general, 8);
      buf.append(cell, r.ptr);
    }
    buf.push_back('\n');
  }
  return fmt::to_string(buf);
}

bool ProductOptions::IsValid(std::string* why) const {
  if (cost_curve_points < 2 || cost_curve_points > 1000000) {
    if (why) *why = "cost_curve_points must be 2 to 10^6";
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> TestProducts::Files() const {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, table] : tables)
    files.emplace_back(name, table.ToCsv());
  files.emplace_back(result_name, ResultText());
  return files;
}

std::string TestProducts::ResultText() const { return result.dump(2) + "\n"; }

const std::vector<std::string>& CycleColumns() {
  static const std::vector<std::string> kColumns = {"cycle",
                                                    "mu_hat_force",
                                                    "J_force",
                                                    "J_force_floor",
                                                    "J_force_excess",
                                                    "mu_hat_scan",
                                                    "J_scan",
                                                    "J_scan_floor",
                                                    "J_scan_excess",
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
                                                    "P_min_N",
                                                    "P_range_N",
                                                    "QP_correlation",
                                                    "running_in",
                                                    "slip_fallback",
                                                    "waviness_sd_mm",
                                                    "mu_hat_force_low",
                                                    "mu_hat_force_high",
                                                    "mu_hat_scan_low",
                                                    "mu_hat_scan_high"};
  return kColumns;
}

int CycleColumn(const std::string& name) {
  const auto& c = CycleColumns();
  const auto it = std::find(c.begin(), c.end(), name);
  return it == c.end() ? -1 : static_cast<int>(it - c.begin()) + 1;
}

nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const TestResult& r,
                          const FuseOptions& o,
                          const Provenance* provenance) {
  nlohmann::json j;
  j["specimen"] = name;
  j["force_file"] = record.metadata.source;
  j["force_layout"] = record.metadata.layout;
  j["samples"] = record.size();
  j["sampling_rate_hz"] = record.metadata.sampling_rate_hz;
  j["cycles"] = r.force.cycles.cycles.size();
  j["stroke_mm"] = r.force.cycles.stroke_mm;
  j["slip_fallback_half_cycles"] = r.force.slip_fallbacks;
  j["force_file_read"] = ForceFileJson(record.metadata);
  if (!r.scan_file.empty()) j["scan_file"] = r.scan_file;
  j["options"] = OptionsJson(record, o);
  j["running_in"] = {
      {"cycles", r.force.running_in.cycles},
      {"detected", r.force.running_in.detected},
      {"tolerance", r.force.running_in.tolerance},
      {"steady_slope_per_cycle", r.force.running_in.steady_slope},
      {"rule", r.force.running_in.rule}};
  j["slope_estimate"] = r.force.slope_estimate;
  j["k_rms"] = {{"repeatable", r.force.k_signal_rms},
                {"noise", r.force.k_noise_rms},
                {"noise_from_ensemble_halves", r.force.k_ensemble_noise_rms},
                {"mu_hat_bias_removed", r.force.k_noise_correction}};
  j["after_running_in"] = {{"mu_hat", Stat(r.force.mu_hat)},
                           {"J", Stat(r.force.cost)},
                           {"mu_mean", Stat(r.force.mu_mean)},
                           {"mu_energy", Stat(r.force.mu_energy)}};
  j["comparison"] = ComparisonJson(r);
  j["wear"] = WearJson(r.wear);
  j["friction_map"] = {
      {"bin_mm", o.friction_map.bin_mm},
      {"slope_polynomial_order",
       o.friction_map.slope_polynomial_order != 0
           ? o.friction_map.slope_polynomial_order
           : o.analysis.friction.ensemble.polynomial_order},
      {"slope_span_mm",
       o.friction_map.slope_span_mm > 0 ? o.friction_map.slope_span_mm
                                        : o.analysis.friction.ensemble.span_mm},
      {"bins", r.friction_map.x_mm.size()},
      {"first_steady_cycle", r.friction_map.first_steady_cycle + 1},
      {"spatial_sd_raw", r.friction_map.spatial_sd_raw},
      {"spatial_sd_corrected", r.friction_map.spatial_sd_corrected},
      {"spatial_sd_noise_floor", r.friction_map.spatial_sd_noise},
      {"spatial_sd_excess", r.friction_map.spatial_sd_excess}};
  const TrackHistory& h = r.track_history;
  j["track_history"] = {
      {"bin_mm", o.track_history.bin_mm},
      {"steady_from_cycle", h.cycles > 0 ? h.steady_cycle + 1 : 0},
      {"final_waviness_sd_mm", h.final_waviness_sd_mm},
      {"growth_per_cycle_mm", h.growth_per_cycle_mm},
      {"first_waviness_sd_mm",
       h.waviness_sd_mm.empty() ? Nan() : h.waviness_sd_mm.front()}};
  if (r.scan) {
    // The final state against the scan: the alignment's amplitude ratio
    // (P/S over the compared cycles against the scanned profile).
    j["track_history"]["final_vs_scan_amplitude_ratio"] =
        r.scan->alignment.amplitude_ratio;
  }
  if (r.scan) j["scan"] = ScanJson(*r.scan);
  if (r.lugre) j["lugre"] = LugreJson(r);
  j["verdict"] = {{"explained", r.verdict.explained},
                  {"summary", r.verdict.Summary()},
                  {"reasons", r.verdict.reasons}};
  std::vector<std::string> warnings = record.metadata.warnings;
  warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
  j["warnings"] = warnings;
  if (provenance) j["provenance"] = provenance->ToJson();
  return j;
}

Provenance TestProvenance(const force::ForceRecord& record,
                          const TestResult& result) {
  std::vector<InputFile> inputs;
  namespace fs = std::filesystem;
  std::error_code ec;
  for (auto [role, path] : {std::pair<const char*, const std::string*>{
                                "force", &record.metadata.source},
                            {"scan", &result.scan_file}}) {
    if (path->empty() || !fs::is_regular_file(*path, ec)) continue;
    // The force file's checksum taken as it was read, when it was.
    const std::string& read_sum = record.metadata.sha256;
    if (std::string(role) == "force" && !read_sum.empty()) {
      inputs.push_back({role, *path, fs::file_size(*path, ec), read_sum});
    } else {
      inputs.push_back(DescribeInputFile(role, *path));
    }
  }
  return CurrentProvenance(std::move(inputs));
}

TestProducts MakeTestProducts(const std::string& name,
                              const force::ForceRecord& record,
                              const TestResult& r,
                              const FuseOptions& o,
                              const ProductOptions& p) {
  std::string why;
  if (!p.IsValid(&why)) throw FusionError("product options: " + why);
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  for (int c : p.loop_cycles) {
    if (c >= n) {
      throw FusionError(fmt::format(
          "the loops of cycle {} were asked for, but the test has {} "
          "complete cycles; expected 1 to {}",
          c + 1,
          n,
          n));
    }
  }
  TestProducts out;
  out.tables.emplace_back("cycles.csv", CycleTable(r));
  out.tables.emplace_back("loops.csv", LoopTable(record, r, p.loop_cycles));
  out.tables.emplace_back("friction_map.csv", FrictionMapTable(r.friction_map));
  out.tables.emplace_back("track_history.csv",
                          TrackHistoryTable(r.track_history));
  const int dc = p.detail_cycle >= 0 && p.detail_cycle < n   ? p.detail_cycle
                 : r.detail_cycle >= 0 && r.detail_cycle < n ? r.detail_cycle
                                                             : n - 1;
  const auto& fopt = o.analysis.friction;
  const ForceSlopes force_slopes(record, r.force.cycles, fopt, dc, dc);
  const CycleSamples kf = force_slopes.Gather(dc);
  const double mu_f = r.force.fit_force[dc].mu_hat;
  const double mu_s = r.scan ? r.scan->fit_scan[dc].mu_hat : Nan();
  out.tables.emplace_back("detail.csv", DetailTable(r, kf, dc, mu_f, mu_s));
  out.tables.emplace_back(
      "cost_curve.csv",
      CostCurveTable(record, r, fopt, kf, dc, p.cost_curve_points));
  if (r.scan) AddProfileTables(*r.scan, &out);
  if (r.lugre) {
    out.tables.emplace_back("lugre.csv", LugreTable(record, r, kf, dc, mu_f));
  }
  if (p.provenance) {
    const Provenance prov = TestProvenance(record, r);
    out.result = ResultJson(name, record, r, o, &prov);
  } else {
    out.result = ResultJson(name, record, r, o);
  }
  return out;
}

bool MapAnalysisOptions::IsValid(std::string* why) const {
  if (!level.IsValid(why) || !track.IsValid(why) || !profile.IsValid(why))
    return false;
  if (!(section_half_width_mm > 0)) {
    if (why) *why = "section_half_width_mm must be > 0";
    return false;
  }
  return true;
}

MapAnalysis AnalyzeMap(scan::HeightMap map, const MapAnalysisOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw scan::ScanError("scan analysis options: " + why);
  MapAnalysis a;
  a.level = scan::LevelHeightMap(&map, o.level);
  a.spikes_removed = scan::RemoveSpikes(&map, o.spikes);
  try {
    a.track = scan::FindTrack(map, o.track);
  } catch (const scan::NoTrackError& e) {
    a.no_track = e.what();
  }
  if (a.track) {
    a.centreline = scan::ExtractCentreline(map, *a.track, o.profile);
    a.sections_mm = o.sections_mm;
    if (a.sections_mm.empty()) {
      const double l = a.track->length_mm;
      a.sections_mm = {-0.25 * l, 0.0, 0.25 * l};
    }
    for (double s : a.sections_mm) {
      a.sections.push_back(
          scan::ExtractCrossSection(map, *a.track, s, o.section_half_width_mm));
    }
  }
  a.levelled = std::move(map);
  return a;
}

TestProducts MakeMapProducts(const std::string& file, const MapAnalysis& a) {
  TestProducts out;
  if (a.track) {
    Table c;
    c.columns = {"s_mm", "h_mm", "n_valid"};
    const scan::WearProfile& p = a.centreline;
    for (Eigen::Index i = 0; i < p.s_mm.size(); ++i) {
      c.rows.push_back(
          {p.s_mm[i], p.height_mm[i], static_cast<double>(p.valid_samples[i])});
    }
    out.tables.emplace_back("centreline.csv", std::move(c));
    Table x;
    x.columns = {"s_mm", "w_mm", "h_mm"};
    for (size_t k = 0; k < a.sections.size(); ++k) {
      const scan::WearProfile& cs = a.sections[k];
      for (Eigen::Index i = 0; i < cs.s_mm.size(); ++i)
        x.rows.push_back({a.sections_mm[k], cs.s_mm[i], cs.height_mm[i]});
    }
    out.tables.emplace_back("cross_sections.csv", std::move(x));
  }
  const scan::HeightMap& map = a.levelled;
  out.result_name = "scan.json";
  out.result = {{"file", file},
                {"format", map.metadata.format},
                {"instrument", map.metadata.instrument},
                {"date", map.metadata.date},
                {"size_px", {map.cols(), map.rows()}},
                {"pitch_mm", {map.dx_mm, map.dy_mm}},
                {"valid_points", map.ValidCount()},
                {"level", LevelJson(a.level)},
                {"spikes_removed", a.spikes_removed},
                {"track", a.track ? TrackJson(*a.track) : nlohmann::json()},
                {"warnings", map.metadata.warnings}};
  if (!a.track) out.result["track_missing"] = a.no_track;
  return out;
}

}  // namespace wearscar::fusion
