#include "tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "wearscar/fusion/align.h"
#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/text.h"

namespace wearscar::fusion {
namespace {

using support::kNaN;

// The normal distribution's two-sided 95% quantile: mu-hat's interval per
// cycle is mu_hat +- kZ95 MuFit::standard_error.
constexpr double kZ95 = 1.96;

double Number(int v) { return static_cast<double>(v); }

}  // namespace

std::string Table::ToCsv() const { return ToCsv(0, rows.size()); }

std::string Table::ToCsv(std::size_t first, std::size_t last) const {
  last = std::min(last, rows.size());
  first = std::min(first, last);
  std::string buf;
  // About a dozen characters a cell, held once: growing by doubling wrote
  // a large table's text several times into fresh pages.
  buf.reserve(12 * columns.size() * (last - first + (first == 0)));
  for (size_t c = 0; first == 0 && c < columns.size(); ++c) {
    if (c) buf.push_back(',');
    buf += columns[c];
  }
  if (first == 0) buf.push_back('\n');
  // printf's %.8g (ToCharsGeneral: the characters std::to_chars writes,
  // faster); whole numbers below 10^8 (cycles, directions, counts) as
  // integers.
  char cell[32];
  for (std::size_t i = first; i < last; ++i) {
    const std::vector<double>& row = rows[i];
    for (size_t c = 0; c < row.size(); ++c) {
      if (c) buf.push_back(',');
      const double v = row[c];
      if (!std::isfinite(v)) continue;
      const bool whole = std::abs(v) < 1e8 && v == std::trunc(v) &&
                         !(v == 0 && std::signbit(v));
      const auto r =
          whole ? std::to_chars(cell, cell + sizeof cell, static_cast<long>(v))
                : support::ToCharsGeneral(cell, cell + sizeof cell, v, 8);
      buf.append(cell, r.ptr);
    }
    buf.push_back('\n');
  }
  return buf;
}

int Table::ColumnIndex(std::string_view name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

const std::vector<std::string>& CycleColumns() {
  return TableColumns("cycles.csv");
}

const std::vector<TableSchema>& TestTableSchemas() {
  static const std::vector<TableSchema> kSchemas = {
      {"cycles.csv",
       {"cycle",
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
        "mu_hat_scan_high"},
       "one row per cycle: mu-hat with each slope, J and its parts, the "
       "classic COFs, envelopes, running-in"},
      {"loops.csv",
       {"cycle", "time_s", "x_mm", "Q_N", "P_N"},
       "the samples of a few cycles' hysteresis loops"},
      {"friction_map.csv",
       {"cycle", "direction", "x_mm", "mu_raw", "mu_corrected", "n"},
       "mu along the stroke per cycle and direction, raw and corrected for "
       "the slope"},
      {"track_history.csv",
       {"cycle", "direction", "x_mm", "h_mm"},
       "the track's height from the spring, P/S about its mean, per cycle"},
      {"detail.csv",
       {"cycle",
        "direction",
        "x_mm",
        "Q_N",
        "P_N",
        "k_force",
        "k_scan",
        "Q_model_force_N",
        "Q_model_scan_N"},
       "the detail cycle's gross-slip samples, both slopes, Q reconstructed "
       "with each"},
      {"cost_curve.csv",
       {"mu", "J_force", "J_scan"},
       "J(mu) on the detail cycle with each slope"},
      {"profiles.csv",
       {"x_mm",
        "f_forward_mm",
        "f_reverse_mm",
        "f_mean_mm",
        "h_scan_mm",
        "h_scan_scaled_mm",
        "k_scan"},
       "P/S per direction and the aligned scan profile along the plate"},
      {"centreline.csv",
       {"s_mm", "h_mm", "n_valid"},
       "the scan's centreline along the track"},
      {"lugre.csv",
       {"time_s", "x_mm", "Q_N", "Q_lugre_N", "Q_wearscar_N"},
       "LuGre against the wear-scar model on the detail cycle"},
  };
  return kSchemas;
}

const std::vector<std::string>& TableColumns(std::string_view file) {
  static const std::vector<std::string> kResidual = {"x_mm",
                                                     "forward_mean_abs_r_N",
                                                     "reverse_mean_abs_r_N",
                                                     "forward_mean_r_N",
                                                     "reverse_mean_r_N",
                                                     "odd_r_N",
                                                     "even_r_N"};
  static const std::vector<std::string> kSections = {"s_mm", "w_mm", "h_mm"};
  static const std::vector<std::string> kNone;
  for (const TableSchema& s : TestTableSchemas()) {
    if (s.file == file) return s.columns;
  }
  if (file == "residual_map_before.csv" || file == "residual_map_after.csv")
    return kResidual;
  if (file == "cross_sections.csv") return kSections;
  static const std::vector<std::string> kAlong = {
      "x_mm", "mu_factor_minus_1", "groove_depth_mm"};
  if (file == "friction_along_track.csv") return kAlong;
  static const std::vector<std::string> kMapAlong = {
      "x_mm", "forward_minus_1", "reverse_minus_1"};
  if (file == "friction_map_along_track.csv") return kMapAlong;
  return kNone;
}

namespace internal {

Table CycleTable(const TestResult& r) {
  const auto& cycles = r.force.cycles.cycles;
  Table t(TableColumns("cycles.csv"));
  for (size_t c = 0; c < cycles.size(); ++c) {
    const auto& f = r.force.fit_force[c];
    const auto& cof = r.force.cof[c];
    const MuFit* s = r.scan ? &r.scan->fit_scan[c] : nullptr;
    const bool fok = f.converged, sok = s && s->converged;
    t.rows.push_back(
        {Number(static_cast<int>(c) + 1),
         fok ? f.mu_hat : kNaN,
         fok ? f.cost : kNaN,
         fok ? f.cost_floor : kNaN,
         fok ? f.cost_excess : kNaN,
         sok ? s->mu_hat : kNaN,
         sok ? s->cost : kNaN,
         sok ? s->cost_floor : kNaN,
         sok ? s->cost_excess : kNaN,
         Number(f.samples),
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
         Number(cycles[c].forward.slip_fallback +
                cycles[c].reverse.slip_fallback),
         c < r.track_history.waviness_sd_mm.size()
             ? r.track_history.waviness_sd_mm[c]
             : kNaN,
         fok ? f.mu_hat - kZ95 * f.standard_error : kNaN,
         fok ? f.mu_hat + kZ95 * f.standard_error : kNaN,
         sok ? s->mu_hat - kZ95 * s->standard_error : kNaN,
         sok ? s->mu_hat + kZ95 * s->standard_error : kNaN});
  }
  return t;
}

// Cycles from 1, direction +1 forward, -1 reverse; empty bins left out.
Table FrictionMapTable(const FrictionMap& m) {
  Table t(TableColumns("friction_map.csv"));
  for (int c = 0; c < m.cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      for (size_t b = 0; b < m.x_mm.size(); ++b) {
        const size_t i = m.Index(c, d, b);
        if (!std::isfinite(m.mu_corrected[i])) continue;
        t.rows.push_back({Number(c + 1),
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

Table TrackHistoryTable(const TrackHistory& h) {
  Table t(TableColumns("track_history.csv"));
  for (int c = 0; c < h.cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      for (size_t b = 0; b < h.x_mm.size(); ++b) {
        const double v = h.height_mm[h.Index(c, d, b)];
        if (std::isfinite(v))
          t.rows.push_back({Number(c + 1), d == 0 ? 1.0 : -1.0, h.x_mm[b], v});
      }
    }
  }
  return t;
}

Table LoopTable(const force::ForceRecord& record,
                const TestResult& r,
                std::vector<int> loops) {
  const auto& cycles = r.force.cycles.cycles;
  const int n = static_cast<int>(cycles.size());
  if (loops.empty()) {
    loops = {0, std::min(2, n - 1), std::min(10, n - 1), n - 1};
  }
  Table l(TableColumns("loops.csv"));
  for (int c : loops) {
    if (c < 0 || c >= n) continue;
    for (Eigen::Index i = cycles[c].forward.begin; i < cycles[c].reverse.end;
         ++i) {
      l.rows.push_back({Number(c + 1),
                        record.time_s[i],
                        record.x_mm[i],
                        record.tangential_n[i],
                        record.normal_n[i]});
    }
  }
  return l;
}

Table DetailTable(const DetailCycle& d) {
  Table t(TableColumns("detail.csv"));
  for (Eigen::Index i = 0; i < d.x_mm.size(); ++i) {
    t.rows.push_back({Number(d.cycle + 1),
                      d.direction[i],
                      d.x_mm[i],
                      d.q_n[i],
                      d.p_n[i],
                      d.k_force[i],
                      d.k_scan[i],
                      d.q_model_force_n[i],
                      d.q_model_scan_n[i]});
  }
  return t;
}

Table CostCurveTable(const DetailCycle& d) {
  Table t(TableColumns("cost_curve.csv"));
  for (Eigen::Index i = 0; i < d.cost_mu.size(); ++i)
    t.rows.push_back({d.cost_mu[i], d.cost_force[i], d.cost_scan[i]});
  return t;
}

Table ProfileTable(const ScanAnalysis& scan) {
  const auto& fp = scan.force_profile;
  const auto& a = scan.alignment;
  const Eigen::VectorXd h = ScanHeightAtPlate(scan.profile, a, fp.x_mm);
  Table p(TableColumns("profiles.csv"));
  for (Eigen::Index i = 0; i < fp.x_mm.size(); ++i) {
    p.rows.push_back({fp.x_mm[i],
                      fp.forward_mm[i],
                      fp.reverse_mm[i],
                      fp.mean_mm[i],
                      h[i],
                      a.scale * h[i] + a.offset_mm,
                      scan.slope.At(fp.x_mm[i])});
  }
  return p;
}

Table CentrelineTable(const scan::WearProfile& profile) {
  Table t(TableColumns("centreline.csv"));
  for (Eigen::Index i = 0; i < profile.s_mm.size(); ++i) {
    t.rows.push_back({profile.s_mm[i],
                      profile.height_mm[i],
                      static_cast<double>(profile.valid_samples[i])});
  }
  return t;
}

// The wear-scar model describes gross slip only (NaN elsewhere).
Table LugreTable(const LugreFit& lg, const DetailCycle& d) {
  WEARSCAR_CHECK(d.lugre_q_wearscar_n.size() == lg.time_s.size(),
                 "the detail cycle holds the model along LuGre's trace");
  Table t(TableColumns("lugre.csv"));
  for (Eigen::Index i = 0; i < lg.time_s.size(); ++i) {
    t.rows.push_back({lg.time_s[i],
                      lg.x_mm[i],
                      lg.q_measured_n[i],
                      lg.q_lugre_n[i],
                      d.lugre_q_wearscar_n[i]});
  }
  return t;
}

Table AlongTrackTable(const AlongTrackFrictionShape& a) {
  Table t(TableColumns("friction_along_track.csv"));
  const PlateProfile shape{a.x_mm, a.a};
  for (Eigen::Index i = 0; i < a.depth_x_mm.size(); ++i)
    t.rows.push_back(
        {a.depth_x_mm[i], shape.At(a.depth_x_mm[i]), a.depth_mm[i]});
  return t;
}

Table MapPatternTable(const AlongTrackFrictionShape& a) {
  Table t(TableColumns("friction_map_along_track.csv"));
  for (Eigen::Index i = 0; i < a.map_x_mm.size(); ++i)
    t.rows.push_back({a.map_x_mm[i], a.map_forward[i], a.map_reverse[i]});
  return t;
}

Table ResidualMapTable(const ResidualMap& m) {
  Table t(TableColumns("residual_map_before.csv"));
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

}  // namespace internal
}  // namespace wearscar::fusion
