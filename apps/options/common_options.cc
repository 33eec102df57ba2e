#include "common_options.h"

#include <fmt/format.h>

#include "usage_error.h"

namespace wearscar::app {

namespace {

// Numeric options out of range are refused by CLI11 naming the option
// ("--spring: Value 0 not in range ..."), before anything runs.
struct Range {
  const char* option;
  double lo, hi;
};
void AddRangeChecks(CLI::App* cmd, std::initializer_list<Range> ranges) {
  for (const Range& r : ranges) {
    if (CLI::Option* o = cmd->get_option_no_throw(r.option))
      o->check(CLI::Range(r.lo, r.hi));
  }
}

}  // namespace

namespace {

// The force export: columns, units, rate, leniency.
void AddForceFileOptions(CLI::App* cmd, CommonArgs* a) {
  auto& r = a->read_force;
  cmd->add_option("--time-column",
                  r.time_column,
                  "Time column name or #N; none: the clock from the file's "
                  "sampling rate or --rate")
      ->group("Force file");
  cmd->add_option("--x-column", r.x_column, "Displacement column name or #N")
      ->group("Force file");
  cmd->add_option(
         "--q-column", r.tangential_column, "Friction force column name or #N")
      ->group("Force file");
  cmd->add_option(
         "--p-column", r.normal_column, "Normal force column name or #N")
      ->group("Force file");
  cmd->add_option("--columns",
                  a->columns,
                  "Column overrides in one go: time=NAME,x=NAME,q=NAME,p=NAME "
                  "(names or #N; any subset), each optionally with its unit: "
                  "x=Pos:um")
      ->group("Force file");
  cmd->add_option("--x-unit",
                  r.x_unit,
                  "Unit of the displacement (mm, um, m); default: the file's, "
                  "else inferred from a plausible stroke with a warning")
      ->group("Force file");
  cmd->add_option("--force-unit",
                  r.force_unit,
                  "Unit of both forces (N, mN, kN, gf); default: the file's, "
                  "else inferred")
      ->group("Force file");
  cmd->add_option("--time-unit",
                  r.time_unit,
                  "Unit of the time column (s, ms, min); default: the file's, "
                  "else inferred")
      ->group("Force file");
  cmd->add_option("--rate",
                  r.sampling_rate_hz,
                  "Sampling rate (Hz) when there is no time column")
      ->group("Force file");
  cmd->add_flag("--lenient", r.lenient, "Drop isolated bad rows with a warning")
      ->group("Force file");
}

// How k is estimated from P: spring, ensemble or per cycle, stencil.
void AddSlopeOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  auto& s = o.analysis.friction.slope;
  cmd->add_option(
         "--spring", s.spring_n_per_mm, "Loading spring stiffness S, N/mm")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--k-estimate",
                  a->k_estimate,
                  "Slope of P: ensemble (P(x) averaged over neighbouring "
                  "cycles) | cycle (each cycle's own P, the paper)")
      ->check(CLI::IsMember({"ensemble", "cycle"}))
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--ensemble-cycles",
                  o.analysis.friction.ensemble.cycles,
                  "Cycles averaged for the ensemble slope (odd)")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--ensemble-span",
                  o.analysis.friction.ensemble.span_mm,
                  "Span of x of the ensemble slope's local fit, mm")
      ->capture_default_str()
      ->group("Method");
  cmd->add_flag("--no-k-noise-correction",
                a->no_k_noise_correction,
                "Keep mu-hat's second-order bias from the noise in the "
                "ensemble's k (about -3 mu var(k noise); removed by default)")
      ->group("Method");
  cmd->add_option("--window-ms",
                  s.window_ms,
                  "Smoothing window of P in time, ms (cycle estimate; 5 ms = "
                  "the paper's 10 samples at 2 kHz)")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--window",
                  s.window,
                  "Smoothing window of P in samples instead of --window-ms "
                  "(the paper: 10)")
      ->group("Method");
  cmd->add_option("--difference-ms",
                  s.half_span_ms,
                  "Half span of the central difference, ms (0.5 ms = the "
                  "paper's Eq. 5 at 2 kHz)")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--derivative",
                  a->derivative,
                  "Slope of P: central (paper Eq. 5) | savgol")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option(
         "--min-span",
         s.min_span_mm,
         "Widen the difference stencil to span at least this x, mm (0 = paper)")
      ->capture_default_str()
      ->group("Method");
}

// Running-in and the bounds of the fit.
void AddRunningInOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_option("--running-in",
                  a->running_in,
                  "Running-in cycles excluded from statistics: a number, or "
                  "auto (the friction settles within --running-in-tolerance "
                  "of the steady trend)")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--running-in-tolerance",
                  o.analysis.running_in_tolerance,
                  "Band around the steady friction trend that ends "
                  "running-in (auto)")
      ->capture_default_str()
      ->group("Method");
  cmd->add_option("--mu-max",
                  o.analysis.friction.fit.mu_max,
                  "Upper end of the mu search")
      ->capture_default_str()
      ->group("Method");
}

// The verdict: cost criterion and its limits.
void AddVerdictOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_option("--verdict-cost",
                  a->verdict_cost,
                  "Verdict on J: excess (the part of J this test's noise "
                  "does not explain, --max-excess) | paper (J itself, "
                  "--max-cost)")
      ->check(CLI::IsMember({"excess", "paper"}))
      ->capture_default_str()
      ->group("Verdict");
  cmd->add_option("--max-excess",
                  o.verdict.max_cost_excess,
                  "Verdict: largest J above its noise floor (lower end of "
                  "its 95% interval)")
      ->capture_default_str()
      ->group("Verdict");
  cmd->add_option("--max-cost",
                  o.verdict.max_cost,
                  "Verdict with --verdict-cost paper: largest J after "
                  "running-in")
      ->capture_default_str()
      ->group("Verdict");
  cmd->add_option("--max-method-difference",
                  o.verdict.max_method_difference,
                  "Verdict: largest |mu-hat - mu_energy| (its whole 95% "
                  "interval beyond it)")
      ->capture_default_str()
      ->group("Verdict");
}

// The LuGre comparison.
void AddLugreOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_flag("--no-lugre", a->no_lugre, "Skip the LuGre comparison")
      ->group("Method");
  cmd->add_option(
         "--lugre-fc", o.lugre.coulomb_n, "LuGre F_c, N (0 = from the cycle)")
      ->group("Method");
  cmd->add_option(
         "--lugre-fs", o.lugre.static_n, "LuGre F_s, N (0 = from the cycle)")
      ->group("Method");
}

// The scan side of the comparison: slope choice, cycles compared.
void AddScanSlopeOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_option("--slope",
                  a->slope,
                  "Slope of the sliding path for mu-hat: force (k = dP/dx / "
                  "S), scan (the aligned centreline) or both")
      ->check(CLI::IsMember({"force", "scan", "both"}))
      ->capture_default_str()
      ->group("Method");
  cmd->add_option(
         "--compare-first",
         o.force_profile.first_cycle,
         "Compare from this cycle (from 1; with --compare-last) instead of "
         "the last N")
      ->group("Scan");
  cmd->add_option(
         "--compare-last", o.force_profile.last_cycle, "Last cycle compared")
      ->group("Scan");
  cmd->add_option("--max-amplitude-ratio",
                  o.verdict.max_amplitude_ratio,
                  "Verdict: largest std(P/S) / std(scan profile) (lower end "
                  "of its 95% interval)")
      ->capture_default_str()
      ->group("Verdict");
  cmd->add_option("--min-correlation",
                  o.verdict.min_correlation,
                  "Verdict: smallest correlation of the aligned profiles")
      ->capture_default_str()
      ->group("Verdict");
  cmd->add_option("--compare-cycles",
                  o.force_profile.cycles,
                  "Compare the scan with the last N cycles")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_flag("--scan-slope-history",
                o.scan_slope_history,
                "Scale the scan's slope of each cycle by that cycle's "
                "waviness from the spring over the final one, so the "
                "scan-side mu-hat does not carry the track's growth (borrows "
                "from the force side: the two slopes are then not "
                "independent)")
      ->group("Scan");
}

// Levelling, the centreline band and the scan slope.
void AddLevelOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_option("--level-order",
                  o.level.polynomial_order,
                  "Reference surface order (1-3)")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option(
         "--band", o.profile.band_width_mm, "Centreline band width, mm")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option("--scan-derivative",
                  a->scan_derivative,
                  "Slope of the scan: savgol | central")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option("--scan-window",
                  o.scan_slope.window,
                  "Scan slope window, scan samples")
      ->capture_default_str()
      ->group("Scan");
}

// Finding or placing the worn track.
void AddTrackOptions(CLI::App* cmd, CommonArgs* a) {
  auto& o = a->fuse;
  cmd->add_option("--min-depth", o.track.min_depth_mm, "Track: least depth, mm")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option("--min-elongation",
                  o.track.min_elongation,
                  "Track: least length/width of the depression")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option("--track-length",
                  o.track.manual_length_mm,
                  "Track length, mm (manual placement; 0 = across the field)")
      ->group("Scan");
  cmd->add_flag("--manual-track",
                o.track.manual,
                "Place the track by hand (--track-x, --track-y, --track-angle)")
      ->group("Scan");
  cmd->add_option("--track-angle",
                  o.track.angle_deg,
                  "Track angle, degrees (manual placement)")
      ->group("Scan");
  cmd->add_option("--track-x",
                  o.track.centre_x_mm,
                  "Track centre x, mm (manual placement)")
      ->group("Scan");
  cmd->add_option("--track-y",
                  o.track.centre_y_mm,
                  "Track centre y, mm (manual placement)")
      ->group("Scan");
}

// Reading the height map.
void AddScanFileOptions(CLI::App* cmd, CommonArgs* a) {
  cmd->add_flag("--large-maps",
                a->large_maps,
                "Raise the decompression limits for genuinely large maps "
                "(a member up to 8 GiB, a file 16 GiB, any ratio)")
      ->group("Scan");
  cmd->add_option("--max-pixel-aspect",
                  a->read_scan.max_pixel_aspect,
                  "Refuse scan pixels longer one way than this times the "
                  "other")
      ->capture_default_str()
      ->group("Scan");
  cmd->add_option("--measurement",
                  a->read_scan.measurement_index,
                  ".zag measurement index")
      ->group("Scan");
  cmd->add_option("--ascii-pitch",
                  a->read_scan.ascii_pitch_mm,
                  "ASCII matrix pixel size, mm")
      ->group("Scan");
  cmd->add_option(
         "--ascii-unit", a->read_scan.ascii_z_unit, "ASCII matrix height unit")
      ->group("Scan");
}

}  // namespace

void AddCommonOptions(CLI::App* cmd, CommonArgs* a, unsigned groups) {
  if (groups & kForceFileOptions) AddForceFileOptions(cmd, a);
  if (groups & kSlopeOptions) {
    AddSlopeOptions(cmd, a);
    AddRunningInOptions(cmd, a);
  }
  if (groups & kVerdictOptions) AddVerdictOptions(cmd, a);
  if (groups & kLugreOptions) AddLugreOptions(cmd, a);
  if (groups & kCompareOptions) AddScanSlopeOptions(cmd, a);
  if (groups & kLevelTrackOptions) {
    AddLevelOptions(cmd, a);
    AddTrackOptions(cmd, a);
  }
  if (groups & kScanFileOptions) AddScanFileOptions(cmd, a);
  // Options a command does not have are skipped.
  AddRangeChecks(cmd,
                 {{"--rate", 0.0, 1e8},
                  {"--spring", 1e-6, 1e6},
                  {"--ensemble-cycles", 1, 10001},
                  {"--ensemble-span", 1e-3, 10},
                  {"--window-ms", 1e-3, 1e4},
                  {"--window", 0, 1e5},
                  {"--difference-ms", 1e-3, 1e4},
                  {"--min-span", 0, 10},
                  {"--running-in-tolerance", 1e-9, 1},
                  {"--mu-max", 1e-3, 10},
                  {"--max-excess", 1e-9, 100},
                  {"--max-cost", 1e-9, 100},
                  {"--max-method-difference", 1e-9, 10},
                  {"--lugre-fc", 0, 1e5},
                  {"--lugre-fs", 0, 1e5},
                  {"--compare-first", 1, 1e7},
                  {"--compare-last", 1, 1e7},
                  {"--compare-cycles", 1, 1e7},
                  {"--max-amplitude-ratio", 1e-9, 1e3},
                  {"--min-correlation", -1, 1},
                  {"--level-order", 1, 3},
                  {"--band", 0, 100},
                  {"--scan-window", 3, 1e5},
                  {"--min-depth", 1e-9, 100},
                  {"--min-elongation", 1, 1e3},
                  {"--max-pixel-aspect", 1, 1e6}});
}

namespace {

// --running-in: "auto" (-1) or a number of cycles >= 0.
int ParseRunningIn(const std::string& text) {
  if (text == "auto") return -1;
  size_t used = 0;
  int n = -1;
  try {
    n = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || n < 0) {
    throw UsageError(fmt::format(
        "--running-in '{}': expected auto or a number of cycles >= 0", text));
  }
  return n;
}

// --columns time=NAME,x=NAME:UNIT,...: the column overrides and units.
void ApplyColumns(const std::string& columns, force::ReadForceOptions* r) {
  std::string rest = columns;
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value =
        eq == std::string::npos ? "" : item.substr(eq + 1);
    std::string* slot = key == "time" ? &r->time_column
                        : key == "x"  ? &r->x_column
                        : key == "q"  ? &r->tangential_column
                        : key == "p"  ? &r->normal_column
                                      : nullptr;
    // NAME:UNIT (a column name may hold a colon; the unit is after the
    // last one when it reads as a unit).
    std::string column = value, unit;
    const size_t colon = value.rfind(':');
    if (colon != std::string::npos && colon > 0 && colon + 1 < value.size()) {
      column = value.substr(0, colon);
      unit = value.substr(colon + 1);
    }
    if (!slot || column.empty()) {
      throw UsageError(fmt::format(
          "--columns '{}': found '{}', expected time=, x=, q= or p= "
          "followed by a column name or #N (and :UNIT)",
          columns,
          item));
    }
    *slot = column;
    if (!unit.empty()) {
      std::string* unit_slot = key == "time" ? &r->time_unit
                               : key == "x"  ? &r->x_unit
                                             : &r->force_unit;
      if (!unit_slot->empty() && *unit_slot != unit) {
        throw UsageError(fmt::format(
            "--columns '{}': '{}' gives unit '{}' but another setting "
            "says '{}'; expected one unit for both forces",
            columns,
            item,
            unit,
            *unit_slot));
      }
      *unit_slot = unit;
    }
  }
}

}  // namespace

void FinaliseCommonOptions(CommonArgs* a) {
  a->fuse.fit_lugre = !a->no_lugre;
  a->fuse.analysis.friction.correct_k_noise_bias = !a->no_k_noise_correction;
  if (!force::ParseDerivativeMethod(a->derivative,
                                    &a->fuse.analysis.friction.slope.method)) {
    throw UsageError(fmt::format(
        "--derivative '{}': expected central or savgol", a->derivative));
  }
  if (!force::ParseDerivativeMethod(a->scan_derivative,
                                    &a->fuse.scan_slope.method)) {
    throw UsageError(
        fmt::format("--scan-derivative '{}': expected savgol or central",
                    a->scan_derivative));
  }
  if (!fusion::ParseKEstimate(a->k_estimate,
                              &a->fuse.analysis.friction.k_estimate)) {
    throw UsageError(fmt::format(
        "--k-estimate '{}': expected ensemble or cycle", a->k_estimate));
  }
  if (!fusion::ParseCostCriterion(a->verdict_cost,
                                  &a->fuse.verdict.cost_criterion)) {
    throw UsageError(fmt::format(
        "--verdict-cost '{}': expected excess or paper", a->verdict_cost));
  }
  if (!fusion::ParseSlopeChoice(a->slope, &a->fuse.slopes)) {
    throw UsageError(
        fmt::format("--slope '{}': expected force, scan or both", a->slope));
  }
  if (a->large_maps) AllowLargeMaps(&a->read_scan);
  const auto& fp = a->fuse.force_profile;
  if (fp.first_cycle >= 0 && fp.last_cycle >= 0 &&
      fp.first_cycle > fp.last_cycle) {
    throw UsageError(fmt::format(
        "--compare-first {} is after --compare-last {}; expected first <= last",
        fp.first_cycle,
        fp.last_cycle));
  }
  a->fuse.analysis.running_in_cycles = ParseRunningIn(a->running_in);
  // Cycles are numbered from 1 on the command line, from 0 in the library.
  for (int* c : {&a->fuse.force_profile.first_cycle,
                 &a->fuse.force_profile.last_cycle}) {
    if (*c >= 1) *c -= 1;
  }
  if (!a->columns.empty()) ApplyColumns(a->columns, &a->read_force);
  std::string why;
  // Units by the option's own name.
  for (auto [option, field] :
       {std::pair<const char*, std::string force::ReadForceOptions::*>{
            "--x-unit", &force::ReadForceOptions::x_unit},
        {"--force-unit", &force::ReadForceOptions::force_unit},
        {"--time-unit", &force::ReadForceOptions::time_unit}}) {
    force::ReadForceOptions probe;
    probe.*field = a->read_force.*field;
    if (!probe.IsValid(&why)) {
      throw UsageError(
          fmt::format("{} '{}': {}", option, a->read_force.*field, why));
    }
  }
  if (!a->fuse.IsValid(&why) || !a->read_force.IsValid(&why) ||
      !a->read_scan.IsValid(&why)) {
    throw UsageError(why);
  }
}

}  // namespace wearscar::app
