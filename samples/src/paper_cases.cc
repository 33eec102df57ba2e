// The paper's twelve cases (Table 1) as simulation presets: beech and
// spruce, radial-tangential, radial-longitudinal and
// tangential-longitudinal planes, sliding along or across the rings.

#include <fmt/format.h>

#include <stdexcept>

#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::samples {

std::vector<SimulationOptions> PaperCases(bool elastic_in_srlr) {
  struct Preset {
    const char* name;
    bool across;
    double contrast, depth, mu0, mu_ss, drift, elastic, texture;
  };
  // Beech: rings 1.6 mm, latewood 30%, moderate contrast. Spruce: rings
  // 2.2 mm, latewood 25%, strong contrast, softer (deeper tracks). mu after
  // running-in in the paper's ranges (beech 0.10-0.12, spruce 0.08-0.16).
  const Preset presets[] = {
      {"B-RT-R", true, 1.9, 0.12, 0.15, 0.110, 0.008, 0.0, 0.04},
      {"B-RT-T", false, 1.6, 0.09, 0.15, 0.105, 0.008, 0.0, 0.05},
      {"B-RL-R", true, 1.8, 0.13, 0.14, 0.112, 0.006, 0.002, 0.04},
      {"B-RL-L", false, 1.8, 0.12, 0.08, 0.115, 0.005, 0.0, 0.05},
      {"B-TL-T", false, 1.6, 0.11, 0.08, 0.116, 0.005, 0.0, 0.08},
      {"B-TL-L", false, 1.6, 0.10, 0.15, 0.108, 0.008, 0.0, 0.05},
      {"S-RT-R", true, 3.0, 0.21, 0.18, 0.100, 0.024, 0.0, 0.04},
      {"S-RT-T", false, 3.0, 0.14, 0.18, 0.130, 0.030, 0.0, 0.05},
      {"S-RL-R", true, 3.2, 0.18, 0.12, 0.090, 0.005, 0.03, 0.04},
      {"S-RL-L", false, 3.0, 0.16, 0.18, 0.140, 0.005, 0.0, 0.05},
      {"S-TL-T", false, 3.0, 0.15, 0.08, 0.100, 0.005, 0.0, 0.06},
      {"S-TL-L", false, 3.0, 0.15, 0.18, 0.150, 0.005, 0.0, 0.05},
  };
  std::vector<SimulationOptions> cases;
  std::uint64_t seed = 1000;
  for (const Preset& p : presets) {
    SimulationOptions o;
    o.name = p.name;
    o.seed = ++seed;
    const bool spruce = p.name[0] == 'S';
    o.ring_period_mm = spruce ? 2.2 : 1.6;
    o.latewood_fraction = spruce ? 0.25 : 0.3;
    o.across_rings = p.across;
    o.hardness_contrast = p.contrast;
    o.final_depth_mm = p.depth;
    o.running_in_cycles = spruce ? 60 : 30;
    o.mu_initial = p.mu0;
    o.mu_steady = p.mu_ss;
    o.mu_drift = p.drift;
    o.elastic_mm =
        (std::string(p.name) == "S-RL-R" && !elastic_in_srlr) ? 0.0 : p.elastic;
    o.texture = p.texture;
    if (spruce) {  // calibrated to the paper's J (SimulationOptions)
      o.p_noise_n = 0.027;
      o.q_noise_n = 0.008;
    }
    // The cut plane decides the surface texture: end grain (RT) shows open
    // cells, no fibres; RL and TL planes hold fibres along L, so sliding in
    // R or T crosses them and sliding in L follows them.
    const std::string name = p.name;
    if (name.compare(2, 2, "RT") == 0) {
      o.fibre_amplitude_mm = 0.0;
      o.roughness_mm = 0.0025;
    } else {
      o.fibre_angle_deg = name.back() == 'L' ? 0.0 : 90.0;
    }
    o.scan_flipped = (seed % 3) == 0;
    o.scan_angle_deg = -3.0 + 6.0 * static_cast<double>((seed * 7) % 11) / 10.0;
    // The operator never centres the track exactly: -0.3 ... +0.3 mm.
    o.scan_track_offset_mm =
        -0.3 + 0.6 * static_cast<double>((seed * 5) % 7) / 6.0;
    cases.push_back(o);
  }
  return cases;
}

SimulationOptions PaperCase(const std::string& name, bool elastic_in_srlr) {
  for (const auto& c : PaperCases(elastic_in_srlr)) {
    if (c.name == name) return c;
  }
  throw std::invalid_argument(
      fmt::format("unknown case '{}'; expected one of B|S-RT-R, RT-T, RL-R, "
                  "RL-L, TL-T, TL-L",
                  name));
}

}  // namespace wearscar::samples
