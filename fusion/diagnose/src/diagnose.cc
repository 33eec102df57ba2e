#include "wearscar/fusion/diagnose.h"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "diagnose_data.h"
#include "diagnose_model.h"
#include "select.h"
#include "wearscar/force/periodic.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/friction_map.h"
#include "wearscar/fusion/profile_decision.h"
#include "wearscar/support/interpolate.h"

namespace wearscar::fusion {

using internal::ChooseCycles;
using internal::CycleBic;
using internal::Data;
using internal::DiagCycle;
using internal::EdgeShapes;
using internal::FitModel;
using internal::HeldOut;
using internal::KeepEdges;
using internal::Map;
using internal::Mean;
using internal::Model;
using internal::ParameterCount;
using internal::Prepare;
using internal::Prepared;
using internal::ProfileGrid;
using internal::Sample;
using internal::SelectEffects;

bool DiagnoseOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (max_cycles < 2 * folds || folds < 2)
    return fail("need folds >= 2 and max_cycles >= 2 folds");
  if (decimation < 1) return fail("decimation must be >= 1");
  if (!(min_relative_gain > 0 && min_relative_gain < 1))
    return fail("min_relative_gain in (0,1)");
  if (!(parsimony > 0 && parsimony <= 1)) return fail("parsimony in (0, 1]");
  if (!(later_share >= 0 && later_share <= 1))
    return fail("later_share in [0, 1]");
  if (!(unexplained_z > 0)) return fail("unexplained_z must be > 0");
  if (!(unexplained_share >= 0 && unexplained_share < 1))
    return fail("unexplained_share in [0, 1)");
  if (!(scan_scale_warning > 0)) return fail("scan_scale_warning > 0");
  if (along_track_knots < 3 || along_track_knots > 200)
    return fail("along_track_knots must be 3 to 200");
  if (!(signature_dominance >= 1)) return fail("signature_dominance >= 1");
  if (!(signature_margin >= 1)) return fail("signature_margin >= 1");
  if (edge_knots != 0 && (edge_knots < 3 || edge_knots > 400))
    return fail("edge_knots must be 0 (none) or 3 to 400");
  for (double w : edge_penalties) {
    if (!(w >= 0)) return fail("edge_penalties must be >= 0");
  }
  if (edge_knots != 0 && edge_penalties.empty())
    return fail("edge_penalties is empty");
  if (shape_penalties.empty()) return fail("shape_penalties is empty");
  for (double w : shape_penalties) {
    if (!(w >= 0) || !std::isfinite(w))
      return fail("shape_penalties must be >= 0");
  }
  if (!(min_improved_fraction > 0 && min_improved_fraction <= 1)) {
    return fail("min_improved_fraction in (0, 1]");
  }
  if (position_bins < 2 || reversal_bins < 2 || cycle_blocks < 1)
    return fail("bins must be >= 2");
  if (slope_cycles < 1 || slope_cycles > 10001)
    return fail("slope_cycles must be in [1, 10001]");
  if (!(profile_step_mm > 0) || !(profile_span_mm > 0)) {
    return fail("profile_step_mm and profile_span_mm must be > 0");
  }
  for (const auto& c : candidates) {
    if (FindEffect(c) == nullptr) {
      std::string keys;
      for (const auto& e : EffectLibrary())
        keys += (keys.empty() ? "" : ", ") + e->Key();
      return fail(("unknown candidate effect '" + c + "' (expected one of " +
                   keys + ", or an effect's name)")
                      .c_str());
    }
  }
  std::string inner;
  if (!mu_fit.IsValid(&inner)) return fail(("mu_fit: " + inner).c_str());
  if (solver_iterations < 1) return fail("solver_iterations must be >= 1");
  if (!(undefined_model_residual_n > 0))
    return fail("undefined_model_residual_n must be > 0");
  if (min_samples_per_cycle < 2)
    return fail("min_samples_per_cycle must be >= 2");
  if (slope_polynomial_order < 1 || slope_polynomial_order > 5)
    return fail("slope_polynomial_order must be 1 to 5");
  return true;
}

std::string Diagnosis::BriefReport() const {
  std::string s = message;
  if (solves > 0) {
    s += fmt::format(
        "; {} joint fits, {} not converged", solves, solves_not_converged);
  }
  return s;
}

namespace {

// The library's effect that scales the slope as a whole (elastic
// compliance): on a fixed slope, the scan's depth scale.
const Effect* SlopeScale() {
  for (const auto& e : EffectLibrary())
    if (e->ScalesTheSlope()) return e.get();
  throw FusionError("the effect library has no slope scale");
}

// The library's effects the options ask for; friction along the track
// with the options' knots (owned by `along_track`). With a fixed slope
// (the scan's centreline) the elastic compliance is left out: it is what
// P/S sees beyond the track's geometry, the scan holds none, and its
// formula is the depth scale Diagnose has already fitted to the scan.
std::vector<const Effect*> CandidatePool(const DiagnoseOptions& o,
                                         bool fixed_slope,
                                         std::unique_ptr<Effect>* along_track) {
  *along_track = AlongTrackFriction(o.along_track_knots);
  std::vector<const Effect*> pool;
  for (const auto& e : EffectLibrary()) {
    if (fixed_slope && e->ScalesTheSlope()) continue;
    if (std::find(o.ruled_out.begin(), o.ruled_out.end(), e->Key()) !=
        o.ruled_out.end())
      continue;
    if (!o.candidates.empty() && std::find_if(o.candidates.begin(),
                                              o.candidates.end(),
                                              [&](const std::string& c) {
                                                return c == e->Name() ||
                                                       c == e->Key();
                                              }) == o.candidates.end()) {
      continue;
    }
    pool.push_back(e->Key() == (*along_track)->Key() ? along_track->get()
                                                     : e.get());
  }
  return pool;
}

// The recovered a(x) at its knots and its correlations with the groove's
// depth and with the depth's short-wave part (the depth less its 1 mm
// running mean).
AlongTrackFrictionShape RecoveredShape(const Effect& effect,
                                       const std::vector<double>& knots,
                                       double penalty,
                                       double x_lo,
                                       double x_hi,
                                       const ProfileGrid& grid,
                                       const PlateProfile& depth) {
  AlongTrackFrictionShape shape;
  const Eigen::Index n = static_cast<Eigen::Index>(knots.size());
  const std::vector<double> u = effect.Knots();
  shape.x_mm =
      x_lo +
      (x_hi - x_lo) * Eigen::Map<const Eigen::VectorXd>(u.data(), n).array();
  shape.a = Eigen::Map<const Eigen::VectorXd>(knots.data(), n);
  shape.penalty = penalty;
  Eigen::VectorXd d(grid.bins), texture(grid.bins);
  for (Eigen::Index b = 0; b < grid.bins; ++b) d[b] = depth.At(grid.centres[b]);
  const Eigen::Index half =
      std::max<Eigen::Index>(1, static_cast<Eigen::Index>(0.5 / grid.bin));
  for (Eigen::Index b = 0; b < grid.bins; ++b) {
    double sum = 0;
    int count = 0;
    for (Eigen::Index j = std::max<Eigen::Index>(0, b - half);
         j <= std::min(grid.bins - 1, b + half);
         ++j) {
      if (std::isfinite(d[j])) sum += d[j], ++count;
    }
    texture[b] = count > 0 ? d[b] - sum / count : std::nan("");
  }
  std::vector<double> dx, dd;
  for (Eigen::Index b = 0; b < grid.bins; ++b) {
    if (grid.centres[b] < x_lo || grid.centres[b] > x_hi) continue;
    dx.push_back(grid.centres[b]);
    dd.push_back(d[b]);
  }
  shape.depth_x_mm = Eigen::Map<Eigen::VectorXd>(dx.data(), dx.size());
  shape.depth_mm = Eigen::Map<Eigen::VectorXd>(dd.data(), dd.size());
  shape.correlation_depth = ShapeCorrelation(shape, grid.centres, d);
  shape.correlation_texture = ShapeCorrelation(shape, grid.centres, texture);
  return shape;
}

}  // namespace

double ShapeCorrelation(const AlongTrackFrictionShape& shape,
                        const Eigen::VectorXd& x_mm,
                        const Eigen::VectorXd& v) {
  if (shape.empty() || x_mm.size() != v.size()) return std::nan("");
  const PlateProfile a{shape.x_mm, shape.a};
  double sa = 0, sv = 0, saa = 0, svv = 0, sav = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < x_mm.size(); ++i) {
    if (x_mm[i] < shape.x_mm[0] ||
        x_mm[i] > shape.x_mm[shape.x_mm.size() - 1] || !std::isfinite(v[i])) {
      continue;
    }
    const double ai = a.At(x_mm[i]);
    sa += ai, sv += v[i], saa += ai * ai, svv += v[i] * v[i], sav += ai * v[i];
    ++n;
  }
  if (n < 3) return std::nan("");
  const double cov = sav - sa * sv / n, va = saa - sa * sa / n,
               vv = svv - sv * sv / n;
  return va > 0 && vv > 0 ? cov / std::sqrt(va * vv) : std::nan("");
}

namespace {

// The drive's cycle rate over the record's complete cycles (0 if none).
double DriveRate(const force::ForceRecord& record,
                 const force::CycleSet& cycles) {
  const auto& c = cycles.cycles;
  if (c.size() < 2) return 0.0;
  const double span = record.time_s[c.back().reverse.end - 1] -
                      record.time_s[c.front().forward.begin];
  return span > 0 ? static_cast<double>(c.size()) / span : 0.0;
}

// "Periodic interference": the strongest line that the drive does not make
// notched out of Q and P, the diagnosis's data prepared again from the
// notched record, and the plain model's held-out J compared. Named (and
// the rest of the diagnosis run on the notched record) when it passes the
// acceptance rules without the information criterion (a line's removal
// fits nothing per cycle).
CandidateResult TryNotch(const force::PeriodicLine& line,
                         const std::vector<double>& base,
                         const DiagnoseOptions& o,
                         const Data& notched_data,
                         std::vector<double>* heldout) {
  *heldout = HeldOut(notched_data, Model{}, o.folds, nullptr);
  CandidateResult r;
  r.effect = "periodic interference";
  r.parameter_names = {"frequency_Hz", "Q_amplitude_N", "P_amplitude_N"};
  r.parameters = {line.frequency_hz, line.q_amplitude_n, line.p_amplitude_n};
  r.uncertainties.assign(3, 0.0);
  r.heldout_before = Mean(base);
  r.heldout_after = Mean(*heldout);
  r.relative_gain = (r.heldout_before - r.heldout_after) / r.heldout_before;
  int better = 0;
  for (size_t i = 0; i < heldout->size() && i < base.size(); ++i)
    better += (*heldout)[i] < base[i];
  r.improved_fraction =
      static_cast<double>(better) / static_cast<double>(heldout->size());
  r.accepted = r.relative_gain >= o.min_relative_gain &&
               r.improved_fraction >= o.min_improved_fraction;
  return r;
}

}  // namespace

namespace {

// The slope's source in words: the scan's centreline, each cycle's depth
// channel or each cycle's P.
std::string SlopeSourceWords(const FrictionFitOptions& friction,
                             bool fixed_slope) {
  if (fixed_slope) {
    return "the scan's centreline, every cycle (the track at the test's "
           "end: the last cycles)";
  }
  if (friction.k_from_depth)
    return "each cycle's binned depth channel (k = -d(depth)/dx)";
  return fmt::format(
      "each cycle's binned P profile (k = (1/S) dP/dx, S = {:g} N/mm)",
      friction.slope.spring_n_per_mm);
}

// A fixed slope is the track when it was scanned; the diagnosed cycles
// slid on a shallower one (the track still deepens: k about 3% steeper
// in the scan over the last 40 of 200 cycles). One depth scale for those
// cycles, k = k_scan / (1 + g), fitted before any effect, stands in for
// the spring's S (a clean test otherwise showed the growth as 23% of the
// held-out J and an effect could be named for it). Returns the scaled
// slope; says so in the diagnosis's slope source.
PlateProfile ScaleTheScanSlope(const PlateProfile& slope,
                               const DiagnoseOptions& o,
                               Prepared* prepared,
                               Diagnosis* out) {
  Model scale;
  scale.effects = {SlopeScale()};
  scale.params = {scale.effects[0]->Initial()};
  scale.penalty = {0.0};
  std::vector<int> all(prepared->data.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  FitModel(prepared->data, all, &scale);
  const double g = scale.params[0][0];
  for (DiagCycle& c : prepared->data.cycles) {
    for (Sample& smp : c.samples) smp.k /= 1.0 + g;
  }
  out->slope_source += fmt::format(
      ", k = k_scan / {:.3f} for the diagnosed cycles' track (fitted: "
      "the scan shows it after the last cycle{}); elastic compliance, the "
      "same formula, not tried",
      1.0 + g,
      std::abs(g) > o.scan_scale_warning
          ? "; far from 1: is the scan this test's track, in its units?"
          : "");
  return {slope.x_mm, slope.k / (1.0 + g)};
}

// What the diagnosis's data are prepared from (Prepare's inputs).
struct Inputs {
  const force::ForceRecord* record;
  const force::CycleSet* cycles;
  const FrictionFitOptions* friction;
  const PlateProfile* depth;
  const PlateProfile* slope;
};

// A periodic line the drive does not make, tried first: it corrupts P's
// slope, and every effect fitted on top of it would be wrong. `notched`
// holds the record without it (the prepared data point into it).
void TryPeriodicLine(const Inputs& in,
                     const DiagnoseOptions& o,
                     force::ForceRecord* notched,
                     std::unique_ptr<Prepared>* prepared,
                     std::vector<double>* base,
                     Diagnosis* out) {
  const std::vector<force::PeriodicLine> lines =
      force::FindPeriodicLines(*in.record, DriveRate(*in.record, *in.cycles));
  out->lines = lines;
  if (lines.empty()) return;
  *notched = *in.record;
  force::NotchLine(notched, lines.front().frequency_hz);
  auto again = std::make_unique<Prepared>();
  Prepare(*notched,
          *in.cycles,
          *in.friction,
          in.depth,
          in.slope,
          out->cycles,
          o,
          again.get());
  std::vector<double> h;
  DiagnosisStep step;
  step.chosen = TryNotch(lines.front(), *base, o, again->data, &h);
  step.tried.push_back(step.chosen);
  out->steps.push_back(step);
  if (!step.chosen.accepted) return;
  out->named.push_back(step.chosen.effect);
  out->model.push_back(step.chosen);
  out->notched_hz = lines.front().frequency_hz;
  *prepared = std::move(again);
  *base = std::move(h);
}

// After named effects, what is left counts when it is a fair part of
// what repeated before (a quarter of its rms); names that leave most of
// it (over half its power) explain too little of it to be trusted: they
// are withdrawn, and "none of these" said (the withdrawal's words
// returned).
std::string JudgeWhatIsLeft(const Data& data,
                            const DiagnoseOptions& o,
                            Diagnosis* out) {
  double q2 = 0;
  long nq = 0;
  for (const DiagCycle& dc : data.cycles) {
    for (const Sample& smp : dc.samples) q2 += smp.q * smp.q, ++nq;
  }
  const double q_rms = nq > 0 ? std::sqrt(q2 / nq) : 0.0;
  const double before = out->before.repeatable_rms_n;
  const double after = out->after.repeatable_rms_n;
  out->unexplained = out->after.repeatable_z > o.unexplained_z &&
                     after >= o.unexplained_share * q_rms &&
                     (out->named.empty() || after >= 0.25 * before);
  if (!out->unexplained || out->named.empty() ||
      !(after * after > 0.5 * before * before))
    return "";
  const std::string withdrawn = fmt::format(
      " ({} lowered the held-out J by {:.0f}% but left {:.0f}% of the "
      "repeating residual's power: not named)",
      fmt::join(out->named, ", "),
      100 * (1 - out->heldout_final / out->heldout_initial),
      100 * std::pow(after / before, 2));
  out->named.clear();
  out->model.clear();
  out->along_track = {};
  return withdrawn;
}

// The diagnosis's one line: what was named and how much lower the held-out
// J is, or "none of these", or nothing to name.
std::string DiagnosisMessage(const Diagnosis& out,
                             const std::string& withdrawn) {
  const std::string left = fmt::format(
      "a repeatable residual that no effect in the library "
      "explains ({:.3f} N rms, {:.0f} standard errors above its "
      "noise; direction-odd {:.3f} N, even {:.3f} N)",
      out.after.repeatable_rms_n,
      out.after.repeatable_z,
      out.after.odd_rms_n,
      out.after.even_rms_n);
  if (out.named.empty()) {
    return out.unexplained
               ? fmt::format(
                     "none of these: {}; held-out J {:.4f}, nothing named{}",
                     left,
                     out.heldout_initial,
                     withdrawn)
               : fmt::format(
                     "no effect named: the wear-scar model leaves nothing a "
                     "candidate explains (held-out J {:.4f})",
                     out.heldout_initial);
  }
  std::vector<std::string> named = out.named;
  if (out.notched_hz > 0) {
    named.front() += fmt::format(" at {:.2f} Hz (notched; --notch {:.2f})",
                                 out.notched_hz,
                                 out.notched_hz);
  }
  std::string message =
      fmt::format("named {}; held-out J {:.4f} -> {:.4f} ({:.0f}% lower)",
                  fmt::join(named, ", "),
                  out.heldout_initial,
                  out.heldout_final,
                  100 * (1 - out.heldout_final / out.heldout_initial));
  if (out.unexplained) message += "; left: " + left;
  return message;
}

// The effects named on the prepared data, their final parameters, the
// held-out J and the residual map after them.
void NameEffects(const Prepared& prepared,
                 const PlateProfile* slope,
                 const DiagnoseOptions& o,
                 std::vector<double>* base,
                 Diagnosis* out) {
  const Data& data = prepared.data;
  const ProfileGrid& grid = prepared.grid;
  Model model;
  std::unique_ptr<Effect> along_track;
  EdgeShapes edges(o.edge_knots);
  SelectEffects(data,
                CandidatePool(o, slope != nullptr, &along_track),
                o,
                out,
                &model,
                base);
  if (o.edge_knots > 0) KeepEdges(data, o, &edges, &model, base, out);
  // Report the final parameters of every named effect from the last fit
  // (after the notch, when one was named).
  const size_t offset = out->model.size() - model.params.size();
  for (size_t e = 0; e < model.params.size(); ++e)
    out->model[offset + e].parameters = model.params[e];
  out->heldout_final = Mean(*base);
  out->after = Map(data, model, o, grid.x_lo, grid.x_hi);
  out->solves = data.solves;
  out->solves_not_converged = data.not_converged;
  for (size_t e = 0; e < model.effects.size(); ++e) {
    if (model.effects[e]->Key() == along_track->Key()) {
      out->along_track = RecoveredShape(*model.effects[e],
                                        model.params[e],
                                        model.penalty[e],
                                        prepared.slip_lo,
                                        prepared.slip_hi,
                                        grid,
                                        prepared.depth);
    }
  }
}

}  // namespace

Diagnosis Diagnose(const force::ForceRecord& record,
                   const force::CycleSet& cycles,
                   const FrictionFitOptions& friction,
                   const PlateProfile* depth,
                   const PlateProfile* slope,
                   const DiagnoseOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw FusionError("diagnose options: " + why);
  Diagnosis out;
  const int n = static_cast<int>(cycles.cycles.size());
  const int first = std::min(o.running_in_cycles, n / 2);
  if (n - first < 2 * o.folds) {
    throw FusionError(
        fmt::format("diagnosis needs at least {} cycles after running-in; the "
                    "record has {} of {}",
                    2 * o.folds,
                    n - first,
                    n));
  }
  // A fixed slope is the track at the test's end: the last cycles.
  out.cycles = ChooseCycles(
      n, slope ? std::max(first, n - o.max_cycles) : first, o.max_cycles);
  out.slope_source = SlopeSourceWords(friction, slope != nullptr);
  if (!o.ruled_out_why.empty()) out.slope_source += "; " + o.ruled_out_why;
  auto prepared = std::make_unique<Prepared>();
  Prepare(
      record, cycles, friction, depth, slope, out.cycles, o, prepared.get());
  PlateProfile scaled;
  if (slope != nullptr) {
    scaled = ScaleTheScanSlope(*slope, o, prepared.get(), &out);
    slope = &scaled;  // for a notched record's data
  }
  std::vector<double> base = HeldOut(prepared->data, Model{}, o.folds, nullptr);
  out.heldout_initial = Mean(base);
  out.before =
      Map(prepared->data, Model{}, o, prepared->grid.x_lo, prepared->grid.x_hi);
  force::ForceRecord notched;
  if (o.periodic_lines) {
    TryPeriodicLine({&record, &cycles, &friction, depth, slope},
                    o,
                    &notched,
                    &prepared,
                    &base,
                    &out);
  }
  NameEffects(*prepared, slope, o, &base, &out);
  const std::string withdrawn = JudgeWhatIsLeft(prepared->data, o, &out);
  out.message = DiagnosisMessage(out, withdrawn);
  return out;
}

namespace {

// Of the two effects that scale k (one formula), the ones the test's
// track history leaves open (SpringCheck): where the groove's growth splits
// P/S, the stiffness it measured is tried only when it contradicts the one
// used, and an elastic part only when the split resolves one; where the
// groove did not change, neither is tried: the data cannot tell them
// apart.
DiagnoseOptions WithTheSpringsEvidence(const TestResult& r, DiagnoseOptions o) {
  const SpringCheck& c = r.mismatch.Spring();
  if (!c.judged && c.q_in_time.Failed()) {
    o.ruled_out.push_back("spring");
    o.ruled_out.push_back("elastic");
    o.ruled_out_why =
        "a scale of k is not tried: the spring check could not "
        "judge P/S against the friction's path, " +
        c.q_in_time.evidence;
    return o;
  }
  if (!c.judged) return o;
  if (!c.changing_groove.Held()) {
    o.ruled_out.push_back("spring");
    o.ruled_out.push_back("elastic");
    o.ruled_out_why = fmt::format(
        "a scale of k is not tried: P/S is the path the friction shows "
        "times {:.2f}, a spring's or an elastic part's alike, and {} (the "
        "groove did not change during the record to tell them apart)",
        c.path_ratio,
        c.changing_groove.evidence);
    return o;
  }
  std::vector<std::string> why;
  if (!c.contradicted) {
    o.ruled_out.push_back("spring");
    why.push_back(fmt::format(
        "the spring's stiffness is not tried: the groove's growth measures it "
        "at {:.2f} (95%: {:.2f}-{:.2f}) times the one used",
        c.stiffness_ratio,
        c.stiffness_ratio_low,
        c.stiffness_ratio_high));
  }
  if (!(c.elastic_share_low > 0)) {
    o.ruled_out.push_back("elastic");
    why.push_back(fmt::format(
        "elastic compliance is not tried: the groove's growth leaves none "
        "of P/S beside the path (an elastic part of {:.0f}% of the worn "
        "track's profile, 95%: {:.0f} to {:.0f}%)",
        100 * c.elastic_share,
        100 * c.elastic_share_low,
        100 * c.elastic_share_high));
  }
  o.ruled_out_why = fmt::format("{}", fmt::join(why, "; "));
  return o;
}

// A named spring's stiffness in N/mm, in the message.
void SayTheSpring(double used_n_per_mm, Diagnosis* d) {
  for (const CandidateResult& c : d->model) {
    if (c.effect != FindEffect("spring")->Name() || c.parameters.empty())
      continue;
    const double ratio = c.parameters[0];
    const double se = c.uncertainties.empty() ? NAN : c.uncertainties[0];
    d->message += fmt::format(
        "; the rig's spring appears to be {:.3g} N/mm{}, not the {:g} N/mm "
        "used",
        ratio * used_n_per_mm,
        std::isfinite(se) ? fmt::format(" (+- {:.2g})", se * used_n_per_mm)
                          : std::string(),
        used_n_per_mm);
  }
}

}  // namespace

namespace {

// The friction map's steady pattern beside a(x) (AlongTrackFrictionShape),
// relative to the mean mu-hat of the map's steady cycles.
void AddMapPattern(const TestResult& r, AlongTrackFrictionShape* shape) {
  const FrictionMap& m = r.units.Get<FrictionMap>();
  const size_t bins = m.x_mm.size();
  if (bins < 3 || m.steady_corrected.size() != 2 * bins) return;
  const std::vector<MuFit>& fits = r.ForceFits().cycles;
  double sum = 0;
  int n = 0;
  for (size_t c = static_cast<size_t>(m.first_steady_cycle); c < fits.size();
       ++c) {
    if (fits[c].converged) sum += fits[c].mu_hat, ++n;
  }
  if (n == 0 || !(sum > 0)) return;
  const double mu = sum / n;
  const auto b = static_cast<Eigen::Index>(bins);
  shape->map_x_mm = Eigen::Map<const Eigen::VectorXd>(m.x_mm.data(), b);
  shape->map_forward =
      Eigen::Map<const Eigen::VectorXd>(m.steady_corrected.data(), b) / mu;
  shape->map_reverse =
      Eigen::Map<const Eigen::VectorXd>(m.steady_corrected.data() + b, b) / mu;
  // a(x) averaged over each bin (the map's are means over its width),
  // against the directions' mean where both have one.
  const PlateProfile a{shape->x_mm, shape->a};
  const double lo = shape->x_mm[0], hi = shape->x_mm[shape->x_mm.size() - 1];
  const double w = bins > 1 ? m.x_mm[1] - m.x_mm[0] : 0.0;
  std::vector<double> av, mv;
  for (Eigen::Index i = 0; i < b; ++i) {
    const double f = shape->map_forward[i], v = shape->map_reverse[i];
    const double x = m.x_mm[static_cast<size_t>(i)];
    if (!std::isfinite(f) || !std::isfinite(v) || x - w / 2 < lo ||
        x + w / 2 > hi)
      continue;
    double mean_a = 0;
    for (int k = 0; k <= 10; ++k) mean_a += a.At(x - w / 2 + w * k / 10.0);
    av.push_back(mean_a / 11);
    mv.push_back(0.5 * (f + v));
  }
  const auto count = static_cast<Eigen::Index>(av.size());
  if (count < 3) return;
  const Eigen::ArrayXd da =
      Eigen::Map<const Eigen::ArrayXd>(av.data(), count) -
      Eigen::Map<const Eigen::ArrayXd>(av.data(), count).mean();
  const Eigen::ArrayXd dm =
      Eigen::Map<const Eigen::ArrayXd>(mv.data(), count) -
      Eigen::Map<const Eigen::ArrayXd>(mv.data(), count).mean();
  const double scale = std::sqrt(da.square().sum() * dm.square().sum());
  if (scale > 0) shape->correlation_map = (da * dm).sum() / scale;
}

}  // namespace

namespace {

// DiagnoseTest on the record as the analysis read it (its lines notched).
Diagnosis DiagnoseAsAnalysed(const force::ForceRecord& record,
                             const TestResult& r,
                             const DiagnoseOptions& options) {
  PlateProfile depth;
  if (r.scan) {
    const auto& fp = r.scan->force_profile;
    depth.x_mm = fp.x_mm;
    depth.k = -ScanHeightAtPlate(r.scan->profile, r.scan->alignment, fp.x_mm);
  }
  // k where the analysis took it (its ProfileDecision, recorded with the
  // options it ran with): P/S, the depth channel with its sign, or on a
  // rig whose P carries no profile the scan's centreline.
  const FrictionFitOptions& friction = r.options.analysis.friction;
  const PlateProfile* slope = nullptr;
  if (r.profile.FromFriction() && r.scan) {
    slope = &r.scan->slope;
  } else if (r.profile.FromSpring() &&
             r.profile.given == ProfileSource::kAuto && !r.scan &&
             ClassifyPSlope(r.profile.p_slope_significance, r.options) !=
                 PSlope::kVaries) {
    // (Not split, P's slope is not shown to vary either.)
    throw FusionError(fmt::format(
        "{}: if the rig loads the ball with a dead weight, k from P is "
        "noise and every effect the diagnosis named would be fitted to it; "
        "give the track's scan or the depth channel (or --profile-from "
        "spring to diagnose with k from P regardless)",
        PSlopeNoiseText(r.profile.p_slope_significance)));
  }
  Diagnosis d = Diagnose(record,
                         r.force.cycles,
                         friction,
                         r.scan ? &depth : nullptr,
                         slope,
                         WithTheSpringsEvidence(r, options));
  SayTheSpring(friction.slope.spring_n_per_mm, &d);
  if (!d.along_track.empty()) AddMapPattern(r, &d.along_track);
  return d;
}

}  // namespace

Diagnosis DiagnoseTest(const force::ForceRecord& record,
                       const TestResult& r,
                       const FuseOptions& fuse,
                       const DiagnoseOptions& options) {
  // The lines the analysis removed (given, or found: the result's
  // options), removed here too.
  const std::vector<double>& removed =
      fuse.notch_hz.empty() ? r.options.notch_hz : fuse.notch_hz;
  if (removed.empty()) return DiagnoseAsAnalysed(record, r, options);
  force::ForceRecord notched = record;
  for (double f : removed) force::NotchLine(&notched, f);
  Diagnosis d = DiagnoseAsAnalysed(notched, r, options);
  d.slope_source +=
      fmt::format("; Q and P notched at {:.2f} Hz as the analysis's were ({})",
                  fmt::join(removed, ", "),
                  fuse.notch_hz.empty()
                      ? "lines found in the record; --notch none keeps them"
                      : "--notch");
  return d;
}

}  // namespace wearscar::fusion
