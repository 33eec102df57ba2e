#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/scan/height_map.h"

namespace wearscar::samples {

// Hidden effects the simulator can switch on; each has a strength (0 = off).
// The diagnosis stage must find them. Each is generated from the physics it
// stands for (samples/effect_laws.h), never from the formula the diagnosis
// fits; the last four are not in the diagnosis's library at all.
struct HiddenEffects {
  // Ploughing: the groove's cross-section pushed ahead of the sphere
  // (laws::PloughingForce, ~ depth^1.5); N per mm of depth at the final
  // mean depth.
  double ploughing_n_per_mm = 0.0;
  // Boundary friction rising at low speed (laws::BoundaryFrictionFactor):
  // mu (1 + rise / (1 + (v/v_s)^2)).
  double stribeck_rise = 0.0;
  double stribeck_speed_mm_s = 8.0;  // the paper's LuGre fit: 8.09 mm/s
  // Fibres as a ratchet (laws::RatchetMu): relative asymmetry at mu 0.11
  // where the teeth stand at their mean angle; the angle follows the
  // wood's stiffness along the track.
  double direction_asymmetry = 0.0;
  // Q channel behind a first-order sensor of this time constant.
  double q_lag_s = 0.0;
  // Crosstalk: P_measured = P + c Q (a load cell's cross-sensitivity).
  double crosstalk_q_into_p = 0.0;
  // The groove's unworn end wall (laws::EndWallResistance): N at the wall,
  // reaching 3 hook_length_mm before it.
  double hook_n = 0.0;
  double hook_length_mm = 0.3;
  // A shear-thinning film (laws::FilmShearForce): N s/mm at 10 mm/s.
  double viscous_n_s_per_mm = 0.0;
  // Friction following the wood's local hardness H(x), not smoothed by
  // wear: mu ~ H^-gamma, gamma set so that the sd of ln(mu) along the
  // stroke is the strength. mu_variation: the growth rings' bands (a
  // gradual rise through each ring, a sharp fall at its boundary; on
  // along-ring specimens the texture alone); mu_trend: a linear change of
  // hardness across the stroke; mu_soft_spot: one soft spot 0.25 mm wide.
  double mu_variation = 0.0;
  double mu_trend = 0.0;
  double mu_soft_spot = 0.0;
  // Mains pick-up on both force channels: amplitude (N) and frequency.
  double pickup_n = 0.0;
  double pickup_hz = 50.0;
  // Not in the library: adhesion grown during the dwell at each reversal,
  // broken within dwell_distance_mm (laws::DwellAdhesionFactor).
  double dwell_adhesion = 0.0;
  double dwell_distance_mm = 0.1;
  // Not in the library: a counter-face wobbling at its own frequency,
  // tilting the contact by wobble_rad sin(2 pi f_w t).
  double wobble_rad = 0.0;
  double wobble_hz = 0.73;
  // Not in the library: mu rising with the specimen's temperature as
  // frictional heating warms it (first order, time constant thermal_time_s).
  double thermal_drift = 0.0;
  double thermal_time_s = 60.0;
  // The Q channel behind a lightly damped resonance (the friction arm's
  // mass on the load cell's stiffness, laws::ResonatorStep): natural
  // frequency (Hz; 0 = none) and damping ratio. Each reversal's step in
  // friction rings at it, the same every cycle.
  double ringing_hz = 0.0;
  double ringing_damping = 0.05;
};

enum class Drive { kSine, kTriangle };

// How the ball is loaded: through the paper's spring (P follows the
// sphere's height along the track) or by a dead weight or a
// force-controlled actuator (P constant: the weight; the height is not in
// P).
enum class Rig { kSpring, kDeadWeight };

// The test case: specimen, machine and sensors. Defaults are the paper's
// test conditions (Table 1) on a beech RT-R-like specimen.
struct SimulationOptions {
  std::string name = "B-RT-R";
  std::uint64_t seed = 1;
  // Machine.
  Drive drive = Drive::kSine;
  double amplitude_mm = 2.85;  // stroke +-A
  double frequency_hz = 1.0;
  double sampling_rate_hz = 2000.0;
  int cycles = 600;
  // The record starts at this cycle of the test (0: at its first contact):
  // a pre-worn specimen, a resumed test, a record that starts after
  // running-in or a later block of a long test. The groove and friction
  // are the recorded cycles', the scan the test's end; time restarts at 0.
  int record_from_cycle = 0;
  double target_normal_n = 30.0;   // cycle mean held by a slow control
  double spring_n_per_mm = 10.19;  // S
  Rig rig = Rig::kSpring;          // kDeadWeight: P = target_normal_n
  // A depth sensor (an LVDT, a "Penetration Depth") logs the ball's
  // vertical position: white noise and resolution (at noise_scale 1), an
  // offset and a linear drift over the test, mm.
  bool depth_channel = false;
  double depth_noise_mm = 0.0003;
  double depth_resolution_mm = 0.0001;
  double depth_offset_mm = 0.05;
  double depth_drift_mm = 0.002;
  double control_gain = 0.5;  // fraction of the mean error removed per cycle
  double contact_stiffness_n_per_mm = 150.0;  // tangential (Jenkins element)
  double sphere_radius_mm = 3.25;
  // The sphere rides the worn track as a rigid ball: its path is the worn
  // profile dilated by the sphere (it bridges what curves tighter than
  // 1/R), and P/S and the contact's tilt follow that path while the scan
  // shows the worn profile. false: the sphere follows the worn profile.
  bool rigid_sphere = false;
  // Specimen along the stroke.
  bool across_rings = true;  // R sliding crosses earlywood/latewood
  double ring_period_mm = 1.6;
  // Each ring's width varies about ring_period_mm by this (sd over the
  // mean): one year's growth differs from the next, so two specimens of
  // the same wood differ in where their rings fall. 0: every ring alike.
  double ring_width_cv = 0.0;
  double latewood_fraction = 0.3;
  double hardness_contrast = 1.6;  // latewood / earlywood hardness
  double texture = 0.05;         // along-ring random hardness variation (rel.)
  double footprint_mm = 0.5;     // wear averaged over this contact width
  double final_depth_mm = 0.12;  // mean groove depth after all cycles
  double running_in_cycles = 40.0;  // depth and mu transients
  // Elastic penetration varying along the stroke (std, mm): seen by the
  // spring, invisible to the scan. Large only in the S-RL-R-like case.
  double elastic_mm = 0.0;
  // When >= 0, the elastic part's sd as a fraction of the sd of the final
  // worn profile over the stroke instead of elastic_mm (0.25 = 25% of the
  // profile's amplitude).
  double elastic_fraction = -1.0;
  // Friction.
  double mu_initial = 0.16;
  double mu_steady = 0.11;
  double mu_drift = 0.01;  // change over the whole test
  // Sensors: resolution (the paper's piezo sensors) and white noise.
  double q_resolution_n = 0.0045;
  double p_resolution_n = 0.015;
  // Noise sd at noise_scale 1, calibrated to the paper: its procedure
  // (moving average 10, Eq. 5, gross slip the central 80% of the stroke,
  // Eq. 6) gives J at cycle 599 of 0.32-0.34 on B-RT-R (paper 0.3085) with
  // these beech values and 0.34-0.36 on S-RT-R (paper 0.3748) with the
  // spruce values of PaperCases (0.027 N, 0.008 N: the softer wood's contact
  // fluctuates more). Q's noise is P's times the ratio of the resolutions.
  double q_noise_n = 0.0048;
  double p_noise_n = 0.016;
  double x_noise_mm = 0.0002;
  // Multiplies q_noise_n and p_noise_n (1 = calibrated to the paper).
  double noise_scale = 1.0;
  HiddenEffects effects;
  // Scanner.
  int scan_cols = 1024;
  int scan_rows = 768;
  double scan_pitch_mm = 0.007413;  // Keyence VR-6000, low magnification
  double scan_angle_deg = 2.0;      // track axis against the scan x axis
  bool scan_flipped = false;        // scan s runs against plate x
  double scan_track_offset_mm =
      0.15;                       // track centre from the field centre, along
  double scan_noise_mm = 0.0005;  // white instrument noise (sd)
  // Surface texture of the unworn wood (also inside the track, where it is
  // partly worn away): isotropic roughness correlated over a few um, and
  // fibres (ridges along the fibre direction) where the surface holds them.
  double roughness_mm = 0.0015;           // sd
  double roughness_length_mm = 0.012;     // correlation length
  double fibre_amplitude_mm = 0.002;      // sd; 0 on end grain (RT)
  double fibre_width_mm = 0.025;          // across-fibre correlation length
  double fibre_angle_deg = 90.0;          // against the sliding direction
  double scan_invalid_fraction = 0.01;    // small scattered clusters
  double scan_invalid_cluster_mm = 0.12;  // radius of one large cluster
  double scan_spike_fraction = 0.0005;
  // Rims along the groove edges: height as a fraction of the local depth.
  double rim_fraction = 0.08;
  double rim_width_mm = 0.06;
  double plane_dzdx = 0.004, plane_dzdy = -0.003;  // specimen tilt
  double plane_z0_mm = 0.05;

  bool IsValid(std::string* why) const;
};

// What the simulator knows and the analysis must recover.
struct GroundTruth {
  Eigen::VectorXd mu_per_cycle;  // Coulomb mu of each complete cycle
  // Final worn depth and elastic part along the stroke, on a grid.
  Eigen::VectorXd profile_x_mm;
  Eigen::VectorXd worn_depth_mm;  // > 0 into the surface
  Eigen::VectorXd elastic_mm;     // varying part of the penetration
  Eigen::VectorXd mu_factor;      // mu_eff / mu along the stroke (mean 1)
  // Per cycle: the sd along the stroke of the sphere's path under load
  // (worn depth at that cycle plus the elastic part): what P/S shows.
  Eigen::VectorXd waviness_sd_mm;
  // Scan placement: plate x = flip * (s - along_offset) where s is the
  // along-track coordinate from the track centre (cx, cy) in the scan.
  double scan_centre_x_mm = 0.0, scan_centre_y_mm = 0.0;
  double scan_angle_deg = 0.0;
  bool scan_flipped = false;
  double plane_dzdx = 0.0, plane_dzdy = 0.0, plane_z0_mm = 0.0;
  double scan_pitch_mm = 0.0;
  // Plate x to scan pixel: col = origin_col + col_per_mm * x, row likewise
  // (pixel centres at col * pitch); the flip is in the sign.
  double origin_col = 0.0, origin_row = 0.0;
  double col_per_mm = 0.0, row_per_mm = 0.0;
  // Amplitudes of the final profiles over the stroke (sd and peak to peak):
  // the force side sees worn depth plus elastic part, the scan the worn
  // depth alone.
  double force_profile_sd_mm = 0.0, force_profile_range_mm = 0.0;
  double scan_profile_sd_mm = 0.0, scan_profile_range_mm = 0.0;
  // False when the elastic part's sd exceeds 17.5% of the worn profile's
  // (between the 10% the verdict must pass and the 25% it must flag).
  bool explained_by_wear_scar = true;
};

// What the virtual tribometer logged, in the library's units (s, mm, N):
// the four channels a force file holds, before any reader or analysis.
// force::ForceRecord is built from it where the analysis needs one.
struct SimulatedChannels {
  Eigen::VectorXd time_s;
  Eigen::VectorXd x_mm;
  Eigen::VectorXd tangential_n;  // Q
  Eigen::VectorXd normal_n;      // P, compression positive
  // The ball's penetration into the specimen as the rig's sensor logs it
  // (mm, with the sensor's offset, drift, noise and resolution); empty
  // unless SimulationOptions::depth_channel.
  Eigen::VectorXd depth_mm;
  double sampling_rate_hz = 0.0;
  std::string source;  // "simulator:<case>"
  Eigen::Index size() const { return time_s.size(); }
};

struct SimulatedTest {
  SimulatedChannels record;
  scan::HeightMap scan;
  GroundTruth truth;
};

// Runs the virtual tribometer then scans the worn track. Deterministic for a
// given seed.
SimulatedTest Simulate(const SimulationOptions& options);

// The paper's 12 cases (B and S x RT-R, RT-T, RL-R, RL-L, TL-T, TL-L) as
// option presets; S-RL-R carries a large elastic part when
// `elastic_in_srlr` is true.
std::vector<SimulationOptions> PaperCases(bool elastic_in_srlr = true);

// One named case from PaperCases ("B-RT-R", ...); throws std::invalid_argument.
SimulationOptions PaperCase(const std::string& name,
                            bool elastic_in_srlr = true);

// The switch names of the hidden effects with their units, for messages:
// "ploughing (N/mm), stribeck (relative), ...".
std::string HiddenEffectNames();

// Sets one hidden effect from "name=value" (a switch name of
// HiddenEffectNames; '-' reads as '_'). Throws std::invalid_argument saying
// what was wrong and what is expected.
void ApplyEffectSetting(const std::string& setting, HiddenEffects* effects);

// The ground truth of a simulated test (<case>.truth.json): mu per cycle,
// noise, amplitudes of the profiles, the scan's frame and plane, the hidden
// effects.
nlohmann::json TruthJson(const SimulationOptions& options,
                         const SimulatedTest& test);

}  // namespace wearscar::samples
