// The friction map as an analysis unit: mu along the stroke per cycle and
// direction, corrected with the force side's k (friction_map.h).

#include <fmt/format.h>

#include <cmath>

#include "units.h"
#include "wearscar/fusion/friction_map.h"

namespace wearscar::fusion::internal {
namespace {

class FrictionMapUnit : public TypedUnit<FrictionMap> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "friction_map",
        "mu along the stroke per cycle and direction, raw and corrected for "
        "the force side's slope; its spatial variation after running-in",
        {"the record", "the cycles", "the decision (its k)"},
        {{"friction_map.csv",
          {"cycle", "direction", "x_mm", "mu_raw", "mu_corrected", "n"},
          "mu along the stroke per cycle and direction, raw and corrected "
          "for the slope"}}};
    return kSpec;
  }
  // Its k is P/S's unless the decision puts it on a depth channel: without
  // one it runs beside the decision.
  UnitStage Stage(const force::ForceRecord& record) const override {
    return record.has_depth() ? UnitStage::kDecided : UnitStage::kCycles;
  }
  bool WorthAThread() const override { return true; }
  FrictionMap Run(const UnitInput& in) const override {
    return ComputeFrictionMap(in.record,
                              in.force.cycles,
                              in.options.analysis.friction,
                              in.force.running_in.cycles,
                              in.options.friction_map);
  }
  // The slope fit's span and order: the map's own where given (the span
  // at least two of the fit's bins), else the force side's.
  std::vector<UnitChoice> Choices(const FrictionMap& m,
                                  const TestResult& r) const override {
    const FrictionMapOptions& fm = r.options.friction_map;
    const auto given = [](auto v) {
      return v > 0 ? nlohmann::json(v) : nlohmann::json("the force side's");
    };
    const double bin = r.options.analysis.friction.ensemble.bin_mm;
    return {
        {"slope_span_mm",
         given(fm.slope_span_mm),
         m.slope_span_mm,
         fm.slope_span_mm > 0 && m.slope_span_mm > fm.slope_span_mm
             ? fmt::format("at least two of the slope fit's {:g} mm bins", bin)
             : ""},
        {"slope_polynomial_order",
         given(fm.slope_polynomial_order),
         m.slope_polynomial_order,
         ""}};
  }
  nlohmann::json Json(const FrictionMap& m,
                      const TestResult& r) const override {
    const FuseOptions& o = r.options;
    const FrictionMapOptions& fm = o.friction_map;
    return {{"bin_mm", fm.bin_mm},
            {"slope_polynomial_order", m.slope_polynomial_order},
            {"slope_span_mm", m.slope_span_mm},
            {"bins", m.x_mm.size()},
            {"loop_bins", m.loop_x_mm.size()},
            {"first_steady_cycle", m.first_steady_cycle + 1},
            {"spatial_sd_raw", m.spatial_sd_raw},
            {"spatial_sd_corrected", m.spatial_sd_corrected},
            {"spatial_sd_noise_floor", m.spatial_sd_noise},
            {"spatial_sd_excess", m.spatial_sd_excess}};
  }
  // Cycles from 1, direction +1 forward, -1 reverse; empty bins left out.
  std::vector<UnitTable> Tables(const FrictionMap& m,
                                const force::ForceRecord&,
                                const TestResult&) const override {
    Table t(Spec().tables[0].columns);
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
    return MovedList(UnitTable{"friction_map.csv", std::move(t)});
  }
  std::vector<UnitFigure> Figures(const FrictionMap& m,
                                  const std::string& name,
                                  const TestResult& r) const override;
};

// The map, forward sliding, as an image of (cycle, bin).
UnitGrid Forward(const char* file,
                 const FrictionMap& m,
                 const std::vector<double>& mu) {
  UnitGrid g{file, m.x_mm, m.cycles, {}};
  g.values.resize(m.x_mm.size() * static_cast<size_t>(m.cycles));
  for (int c = 0; c < m.cycles; ++c) {
    for (size_t b = 0; b < m.x_mm.size(); ++b)
      g.values[static_cast<size_t>(c) * m.x_mm.size() + b] =
          static_cast<float>(mu[m.Index(c, 0, b)]);
  }
  return g;
}

// mu along the stroke and over the cycles, raw (s Q / P) above corrected
// for the slope; below them the track along the same x.
std::vector<UnitFigure> FrictionMapUnit::Figures(const FrictionMap& m,
                                                 const std::string& name,
                                                 const TestResult& r) const {
  if (m.x_mm.size() < 2 || m.cycles < 1) return {};
  const std::string ranges = GridRanges(m.x_mm, m.cycles) + "unset key\n";
  UnitFigure fig{
      "fig_friction_map",
      name + ": friction map mu(x, cycle)",
      {{fmt::format("raw: s Q / P (forward); its sd along x after running-in "
                    "{:.4f}, corrected {:.4f} ({})",
                    m.spatial_sd_raw,
                    m.spatial_sd_corrected,
                    std::isfinite(m.spatial_sd_noise)
                        ? fmt::format("noise floor {:.4f}", m.spatial_sd_noise)
                        : std::string("too few steady cycles for a noise "
                                      "floor")),
        "x (mm)",
        "cycle",
        ranges,
        Forward("friction_map_raw.f32", m, m.mu_raw),
        "mu (-)",
        {}},
       {"corrected for the slope: s (Q - P k) / (P + k Q) (forward)",
        "x (mm)",
        "cycle",
        ranges,
        Forward("friction_map_corrected.f32", m, m.mu_corrected),
        "mu (-)",
        {}}}};
  if (r.scan) {
    UnitSeries spring{
        "profiles.csv", "x_mm", "f_mean_mm", "-P/S (mean of both directions)"};
    UnitSeries scan{"profiles.csv",
                    "x_mm",
                    "h_scan_scaled_mm",
                    "scan (aligned, scaled)",
                    UnitSeries::Role::kScan,
                    2.5};
    spring.y_scale = scan.y_scale = -1;
    fig.panels.push_back({"the track along x",
                          "x (mm)",
                          "height (mm)",
                          "set autoscale y\nset key inside top right\n",
                          std::nullopt,
                          "",
                          {spring, scan}});
  }
  return MovedList(std::move(fig));
}

}  // namespace

const AnalysisUnit& FrictionMapAnalysis() {
  static const FrictionMapUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
