#include "results.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "output.h"
#include "wearscar/fusion/forward_model.h"

// A broken invariant of the program itself (not of its input).
#define WEARSCAR_APP_CHECK(condition)         \
  do {                                        \
    if (!(condition)) {                       \
      fmt::print(stderr,                      \
                 "{}:{}: check failed: {}\n", \
                 __FILE__,                    \
                 __LINE__,                    \
                 #condition);                 \
      std::abort();                           \
    }                                         \
  } while (false)

namespace wearscar::app {
namespace {

nlohmann::json Stat(const fusion::Statistic& s) {
  return {{"mean", s.mean}, {"sd", s.sd}, {"count", s.count}};
}

double Nan() { return std::nan(""); }

nlohmann::json Split(const fusion::CostSplit& s) {
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

nlohmann::json Range(const fusion::Interval& i) {
  return {{"mean", i.mean},
          {"interval", {i.low, i.high}},
          {"count", i.count},
          {"batches", i.batches}};
}

std::string Path(const std::string& dir, const char* file) {
  return (std::filesystem::path(dir) / file).string();
}

}  // namespace

const std::vector<std::string>& CycleColumns() {
  static const std::vector<std::string> kColumns = {
      "cycle",          "mu_hat_force", "J_force",        "J_force_floor",
      "J_force_excess", "mu_hat_scan",  "J_scan",         "J_scan_floor",
      "J_scan_excess",  "samples",      "mu_mean",        "mu_energy_max",
      "mu_energy_g",    "E_d_Nmm",      "delta_max_mm",   "delta_g_mm",
      "P_mean_N",       "Q_max_N",      "Q_min_N",        "P_max_N",
      "P_min_N",        "P_range_N",    "QP_correlation", "running_in",
      "slip_fallback"};
  return kColumns;
}

int CycleColumn(const std::string& name) {
  const auto& c = CycleColumns();
  const auto it = std::find(c.begin(), c.end(), name);
  WEARSCAR_APP_CHECK(it != c.end());
  return static_cast<int>(it - c.begin()) + 1;
}

nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const fusion::TestResult& r,
                          const fusion::FuseOptions& o) {
  nlohmann::json j;
  j["specimen"] = name;
  j["force_file"] = record.metadata.source;
  j["force_layout"] = record.metadata.layout;
  j["samples"] = record.size();
  j["sampling_rate_hz"] = record.metadata.sampling_rate_hz;
  j["cycles"] = r.force.cycles.cycles.size();
  j["stroke_mm"] = r.force.cycles.stroke_mm;
  j["slip_fallback_half_cycles"] = r.force.slip_fallbacks;
  j["options"] = {
      {"spring_n_per_mm", o.analysis.friction.slope.spring_stiffness_n_per_mm},
      {"k_estimate", fusion::KEstimateName(o.analysis.friction.k_estimate)},
      {"ensemble_cycles", o.analysis.friction.ensemble.cycles},
      {"ensemble_bin_mm", o.analysis.friction.ensemble.bin_mm},
      {"ensemble_span_mm", o.analysis.friction.ensemble.span_mm},
      {"derivative",
       force::DerivativeMethodName(o.analysis.friction.slope.method)},
      {"window_samples",
       o.analysis.friction.slope.ForSamplingRate(fusion::SamplingRateOf(record))
           .window},
      {"window_ms", o.analysis.friction.slope.window_ms},
      {"difference_half_span_ms", o.analysis.friction.slope.half_span_ms},
      {"min_span_mm", o.analysis.friction.slope.min_span_mm},
      {"noise_template_cycles",
       o.analysis.friction.repeatability.template_cycles},
      {"running_in_cycles",
       o.analysis.running_in_cycles < 0
           ? nlohmann::json("auto")
           : nlohmann::json(o.analysis.running_in_cycles)},
      {"running_in_tolerance", o.analysis.running_in_tolerance},
      {"mu_interval",
       {o.analysis.friction.fit.mu_min, o.analysis.friction.fit.mu_max}},
      {"verdict_cost", fusion::CostCriterionName(o.verdict.cost_criterion)},
      {"max_excess", o.verdict.max_cost_excess},
      {"max_cost", o.verdict.max_cost},
      {"max_amplitude_ratio", o.verdict.max_amplitude_ratio},
      {"min_correlation", o.verdict.min_correlation},
      {"max_method_difference", o.verdict.max_method_difference}};
  j["running_in"] = {
      {"cycles", r.force.running_in.cycles},
      {"detected", r.force.running_in.detected},
      {"tolerance", r.force.running_in.tolerance},
      {"steady_slope_per_cycle", r.force.running_in.steady_slope},
      {"rule", r.force.running_in.rule}};
  j["slope_estimate"] = r.force.slope_estimate;
  j["k_rms"] = {{"repeatable", r.force.k_signal_rms},
                {"noise", r.force.k_noise_rms}};
  j["after_running_in"] = {{"mu_hat", Stat(r.force.mu_hat)},
                           {"J", Stat(r.force.cost)},
                           {"mu_mean", Stat(r.force.mu_mean)},
                           {"mu_energy", Stat(r.force.mu_energy)}};
  const auto& m = r.mismatch;
  j["comparison"] = {{"first_cycle", m.first_cycle},
                     {"last_cycle", m.last_cycle},
                     {"mu_hat_force", Stat(m.mu_force)},
                     {"J_force", Stat(m.cost_force)},
                     {"mu_mean", Stat(m.mu_mean)},
                     {"mu_energy", Stat(m.mu_energy)},
                     {"mu_hat_minus_mu_mean", Stat(m.mu_force_minus_mean)},
                     {"mu_hat_minus_mu_energy", Stat(m.mu_force_minus_energy)},
                     {"J_force_split", Split(m.split_force)},
                     {"method_difference", Range(m.method_difference)}};
  if (r.scan) {
    const auto& s = *r.scan;
    j["comparison"]["mu_hat_scan"] = Stat(m.mu_scan);
    j["comparison"]["J_scan"] = Stat(m.cost_scan);
    j["comparison"]["J_scan_split"] = Split(m.split_scan);
    j["comparison"]["amplitude_ratio_interval"] = {m.amplitude_ratio_low,
                                                   m.amplitude_ratio_high};
    j["comparison"]["mu_hat_force_minus_scan"] = m.mu_force_minus_scan;
    j["comparison"]["k_rms_difference"] = m.k_rms_difference;
    j["comparison"]["profile_correlation"] = m.correlation;
    j["comparison"]["profile_correlation_noise_corrected"] =
        m.correlation_noise_corrected;
    j["comparison"]["amplitude_ratio"] = m.amplitude_ratio;
    j["scan"] = {{"level",
                  {{"order", s.level.order},
                   {"coefficients",
                    std::vector<double>(s.level.coefficients.data(),
                                        s.level.coefficients.data() +
                                            s.level.coefficients.size())},
                   {"inliers", s.level.inliers},
                   {"rms_mm", s.level.rms_mm}}},
                 {"spikes_removed", s.spikes_removed},
                 {"track",
                  {{"center_x_mm", s.track.center_x_mm},
                   {"center_y_mm", s.track.center_y_mm},
                   {"angle_deg", s.track.angle_deg},
                   {"length_mm", s.track.length_mm},
                   {"width_mm", s.track.width_mm},
                   {"mean_depth_mm", s.track.mean_depth_mm},
                   {"max_depth_mm", s.track.max_depth_mm},
                   {"volume_mm3", s.track.volume_mm3},
                   {"manual", s.track.manual}}},
                 {"alignment",
                  {{"shift_mm", s.alignment.shift_mm},
                   {"flipped", s.alignment.flipped},
                   {"correlation", s.alignment.correlation},
                   {"correlation_forward", s.alignment.correlation_forward},
                   {"correlation_reverse", s.alignment.correlation_reverse},
                   {"scale", s.alignment.scale},
                   {"amplitude_ratio", s.alignment.amplitude_ratio},
                   {"overlap_samples", s.alignment.overlap_samples}}}};
  }
  if (r.lugre) {
    const auto& p = r.lugre->parameters;
    j["lugre"] = {
        {"cycle", r.detail_cycle},
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
        {"message", r.lugre->message}};
  }
  j["verdict"] = {{"explained", r.verdict.explained},
                  {"summary", r.verdict.Summary()},
                  {"reasons", r.verdict.reasons}};
  std::vector<std::string> warnings = record.metadata.warnings;
  warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
  j["warnings"] = warnings;
  return j;
}

std::vector<std::string> WriteTestResults(const std::string& dir,
                                          const std::string& name,
                                          const force::ForceRecord& record,
                                          const fusion::TestResult& r,
                                          const fusion::FuseOptions& o,
                                          const WriteOptions& w) {
  EnsureDirectory(dir);
  std::vector<std::string> files;
  auto write = [&](const char* file, const std::string& text) {
    const std::string p = Path(dir, file);
    WriteTextAtomically(p, text);
    files.push_back(p);
  };
  const auto& cycles = r.force.cycles.cycles;
  const int n = static_cast<int>(cycles.size());
  // Per cycle.
  Table t;
  t.columns = CycleColumns();
  for (int c = 0; c < n; ++c) {
    const auto& f = r.force.fit_force[c];
    const auto& cof = r.force.cof[c];
    const fusion::MuFit* s = r.scan ? &r.scan->fit_scan[c] : nullptr;
    t.rows.push_back({static_cast<double>(c),
                      f.converged ? f.mu_hat : Nan(),
                      f.converged ? f.cost : Nan(),
                      f.converged ? f.cost_floor : Nan(),
                      f.converged ? f.cost_excess : Nan(),
                      s && s->converged ? s->mu_hat : Nan(),
                      s && s->converged ? s->cost : Nan(),
                      s && s->converged ? s->cost_floor : Nan(),
                      s && s->converged ? s->cost_excess : Nan(),
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
                      c < r.force.running_in.cycles ? 1.0 : 0.0,
                      static_cast<double>(cycles[c].forward.slip_fallback +
                                          cycles[c].reverse.slip_fallback)});
  }
  write("cycles.csv", t.ToCsv());
  // Hysteresis loops.
  std::vector<int> loops = w.loop_cycles;
  if (loops.empty())
    loops = {0, std::min(2, n - 1), std::min(10, n - 1), n - 1};
  Table l;
  l.columns = {"cycle", "time_s", "x_mm", "Q_N", "P_N"};
  for (int c : loops) {
    if (c < 0 || c >= n) continue;
    for (Eigen::Index i = cycles[c].forward.begin; i < cycles[c].reverse.end;
         ++i) {
      l.rows.push_back({static_cast<double>(c),
                        record.time_s[i],
                        record.x_mm[i],
                        record.tangential_n[i],
                        record.normal_n[i]});
    }
  }
  write("loops.csv", l.ToCsv());
  // Detail of one cycle: slopes, measured and reconstructed Q (Figs. 10, 12).
  const int dc =
      w.detail_cycle >= 0 && w.detail_cycle < n ? w.detail_cycle : n - 1;
  const auto& fopt = o.analysis.friction;
  const fusion::ForceSlopes force_slopes(record, r.force.cycles, fopt, dc, dc);
  const fusion::CycleSamples kf = force_slopes.Gather(dc);
  const double mu_f = r.force.fit_force[dc].mu_hat;
  const double mu_s = r.scan ? r.scan->fit_scan[dc].mu_hat : Nan();
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
  for (const fusion::SlipSamples* s : {&kf.forward, &kf.reverse}) {
    for (Eigen::Index i = 0; i < s->q_n.size(); ++i) {
      const double ks = r.scan ? r.scan->slope.At(s->x_mm[i]) : Nan();
      d.rows.push_back({static_cast<double>(dc),
                        static_cast<double>(s->direction),
                        s->x_mm[i],
                        s->q_n[i],
                        s->p_n[i],
                        s->k[i],
                        ks,
                        fusion::WearScarTangentialForce(
                            s->p_n[i], s->k[i], mu_f, s->direction),
                        std::isfinite(ks)
                            ? fusion::WearScarTangentialForce(
                                  s->p_n[i], ks, mu_s, s->direction)
                            : Nan()});
    }
  }
  write("detail.csv", d.ToCsv());
  // J(mu) (Fig. 11).
  const Eigen::VectorXd grid =
      Eigen::VectorXd::LinSpaced(201, fopt.fit.mu_min, fopt.fit.mu_max);
  const Eigen::VectorXd jf = fusion::CostCurve(kf, grid);
  Eigen::VectorXd js = Eigen::VectorXd::Constant(grid.size(), Nan());
  if (r.scan) {
    js = fusion::CostCurve(fusion::GatherCycle(record,
                                               cycles[dc],
                                               fusion::SlopeSource::kScan,
                                               fopt,
                                               &r.scan->slope),
                           grid);
  }
  Table cc;
  cc.columns = {"mu", "J_force", "J_scan"};
  for (Eigen::Index i = 0; i < grid.size(); ++i)
    cc.rows.push_back({grid[i], jf[i], js[i]});
  write("cost_curve.csv", cc.ToCsv());
  if (r.scan) {
    const auto& fp = r.scan->force_profile;
    const Eigen::VectorXd h =
        fusion::ScanHeightAtPlate(r.scan->profile, r.scan->alignment, fp.x_mm);
    Table p;
    p.columns = {"x_mm",
                 "f_forward_mm",
                 "f_reverse_mm",
                 "f_mean_mm",
                 "h_scan_mm",
                 "h_scan_scaled_mm",
                 "k_scan"};
    const auto& a = r.scan->alignment;
    for (Eigen::Index i = 0; i < fp.x_mm.size(); ++i) {
      p.rows.push_back({fp.x_mm[i],
                        fp.forward_mm[i],
                        fp.reverse_mm[i],
                        fp.mean_mm[i],
                        h[i],
                        a.scale * h[i] + a.offset_mm,
                        r.scan->slope.At(fp.x_mm[i])});
    }
    write("profiles.csv", p.ToCsv());
    Table sp;
    sp.columns = {"s_mm", "h_mm", "n_valid"};
    for (Eigen::Index i = 0; i < r.scan->profile.s_mm.size(); ++i) {
      sp.rows.push_back(
          {r.scan->profile.s_mm[i],
           r.scan->profile.height_mm[i],
           static_cast<double>(r.scan->profile.valid_samples[i])});
    }
    write("centreline.csv", sp.ToCsv());
  }
  if (r.lugre) {
    // LuGre against wear-scar on the detail cycle (Fig. 17); the wear-scar
    // model describes gross slip only.
    const auto& lg = *r.lugre;
    Table lt;
    lt.columns = {"time_s", "x_mm", "Q_N", "Q_lugre_N", "Q_wearscar_N"};
    // The wear-scar model at the gross-slip samples of the detail cycle
    // (detail.csv's k). The gathered samples keep the record's order, so
    // one pointer per direction walks them alongside.
    const auto& c = cycles[dc];
    Eigen::Index next[2] = {0, 0};
    auto model_at = [&](Eigen::Index src) {
      const bool forward = src < c.forward.end;
      const force::HalfCycle& h = forward ? c.forward : c.reverse;
      if (src < h.slip_begin || src >= h.slip_end) return Nan();
      const fusion::SlipSamples& s = forward ? kf.forward : kf.reverse;
      Eigen::Index& j = next[forward ? 0 : 1];
      if (j < s.x_mm.size() && s.x_mm[j] == record.x_mm[src] &&
          s.p_n[j] == record.normal_n[src]) {
        ++j;
        return fusion::WearScarTangentialForce(
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
    write("lugre.csv", lt.ToCsv());
  }
  write("result.json", ResultJson(name, record, r, o).dump(2) + "\n");
  return files;
}

void AddWarningToResult(const std::string& dir, const std::string& warning) {
  const std::string path = Path(dir, "result.json");
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return;
  j["warnings"].push_back(warning);
  WriteTextAtomically(path, j.dump(2) + "\n");
}

void PrintSummary(const std::string& name, const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  fmt::print("{}: {} cycles; compared over cycles {}-{}\n  {}\n",
             name,
             r.force.cycles.cycles.size(),
             m.first_cycle,
             m.last_cycle,
             r.force.running_in.rule);
  if (m.mu_force.count > 0) {
    fmt::print(
        "  mu-hat, k from P     {:.4f} +- {:.4f}   J {:.3f} (noise floor "
        "{:.3f}, excess {:.3f})\n",
        m.mu_force.mean,
        m.mu_force.sd,
        m.cost_force.mean,
        m.split_force.floor,
        m.split_force.excess);
    fmt::print("    {}\n", r.force.slope_estimate);
  } else {
    fmt::print("  mu-hat, k from P     not fitted (--slope scan)\n");
  }
  if (m.has_scan) {
    if (m.mu_scan.count > 0) {
      fmt::print(
          "  mu-hat, k from scan  {:.4f} +- {:.4f}   J {:.3f} (noise floor "
          "{:.3f}, excess {:.3f})\n",
          m.mu_scan.mean,
          m.mu_scan.sd,
          m.cost_scan.mean,
          m.split_scan.floor,
          m.split_scan.excess);
    } else {
      fmt::print("  mu-hat, k from scan  not fitted (--slope force)\n");
    }
    const auto& a = r.scan->alignment;
    fmt::print(
        "  profiles: r = {:.3f}, amplitude ratio {:.2f}, shift {:.3f} mm{}, "
        "RMS(k_P - "
        "k_scan) {:.3f}\n",
        a.correlation,
        a.amplitude_ratio,
        a.shift_mm,
        a.flipped ? " (flipped)" : "",
        m.k_rms_difference);
  }
  fmt::print(
      "  mu mean {:.4f}, mu energy {:.4f}\n", m.mu_mean.mean, m.mu_energy.mean);
  if (r.lugre) {
    fmt::print(
        "  LuGre, cycle {}: {}\n", r.detail_cycle, r.lugre->BriefReport());
  }
  fmt::print("  verdict: {}\n", r.verdict.Summary());
  for (const auto& w : r.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace wearscar::app
