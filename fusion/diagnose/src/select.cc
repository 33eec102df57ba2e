#include "select.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "wearscar/support/interpolate.h"

namespace wearscar::fusion {

using internal::CycleBic;
using internal::Data;
using internal::EdgeShapes;
using internal::FitModel;
using internal::HeldOut;
using internal::Mean;
using internal::Model;
using internal::ParameterCount;
using internal::ParitySplit;
using internal::SplitByParity;

namespace {

// The held-out J per cycle of `trial` (its last effect new), with the
// penalty weight of a penalised shape the held-out cycles prefer; each
// fold's parameters in *fold_params.
std::vector<double> HeldOutChoosingPenalty(
    const Data& data,
    const std::vector<double>& weights,
    int folds,
    Model* trial,
    std::vector<std::vector<double>>* fold_params) {
  if (trial->effects.back()->PenaltyCount() == 0)
    return HeldOut(data, *trial, folds, fold_params);
  std::vector<double> heldout;
  double best = INFINITY;
  for (double w : weights) {
    Model m = *trial;
    m.penalty.back() = w;
    std::vector<std::vector<double>> fp;
    std::vector<double> h = HeldOut(data, m, folds, &fp);
    if (Mean(h) < best) {
      best = Mean(h);
      heldout = std::move(h);
      *fold_params = std::move(fp);
      trial->penalty.back() = w;
    }
  }
  return heldout;
}

// The jackknife spread over the folds of the last effect's parameters.
std::vector<double> JackknifeSpread(
    const Model& trial, const std::vector<std::vector<double>>& fold_params) {
  size_t offset = 0;
  for (size_t i = 0; i + 1 < trial.params.size(); ++i)
    offset += trial.params[i].size();
  std::vector<double> spread(trial.params.back().size(), 0.0);
  const double k = static_cast<double>(fold_params.size());
  for (size_t q = 0; q < spread.size(); ++q) {
    double mean = 0;
    for (const auto& fp : fold_params) mean += fp[offset + q] / k;
    double var = 0;
    for (const auto& fp : fold_params)
      var += (fp[offset + q] - mean) * (fp[offset + q] - mean);
    spread[q] = std::sqrt((k - 1) / k * var);
  }
  return spread;
}

// One candidate added to `model`: held-out cost over the folds, parameters
// on all cycles with their jackknife spread over the folds, the change of
// the information criterion, and whether it passes the acceptance rules.
CandidateResult TryEffect(const Data& data,
                          const Model& model,
                          const std::vector<double>& base,
                          double base_bic,
                          const ParitySplit& split,
                          const Effect* e,
                          const DiagnoseOptions& o,
                          Model* trial,
                          std::vector<double>* heldout) {
  *trial = model;
  trial->effects.push_back(e);
  trial->params.push_back(e->Initial());
  trial->penalty.resize(trial->effects.size(), 0.0);
  std::vector<std::vector<double>> fold_params;
  *heldout = HeldOutChoosingPenalty(
      data, o.shape_penalties, o.folds, trial, &fold_params);
  const std::vector<double>& h = *heldout;
  CandidateResult r;
  r.effect = e->Name();
  r.parameter_names = e->ParameterNames();
  r.heldout_before = Mean(base);
  r.heldout_after = Mean(h);
  r.relative_gain = (r.heldout_before - r.heldout_after) / r.heldout_before;
  int better = 0;
  for (size_t i = 0; i < h.size(); ++i) better += h[i] < base[i];
  r.improved_fraction =
      static_cast<double>(better) / static_cast<double>(h.size());
  std::vector<int> all(data.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  const ParitySplit after =
      SplitByParity(data, *trial, FitModel(data, all, trial));
  r.odd_removed_n = split.odd_rms_n - after.odd_rms_n;
  r.even_removed_n = split.even_rms_n - after.even_rms_n;
  r.parameters = trial->params.back();
  r.uncertainties = JackknifeSpread(*trial, fold_params);
  r.delta_bic = CycleBic(data, *trial, ParameterCount(*trial)) - base_bic;
  // A penalised shape is judged on held-out cycles alone, at twice the
  // gain: the per-cycle information criterion (one observation per cycle)
  // cannot weigh a smoother's effective parameters.
  r.accepted = e->PenaltyCount() > 0
                   ? r.relative_gain >= 2 * o.min_relative_gain &&
                         r.improved_fraction >= o.min_improved_fraction
                   : r.relative_gain >= o.min_relative_gain &&
                         r.improved_fraction >= o.min_improved_fraction &&
                         r.delta_bic < -o.bic_margin;
  r.plausible = e->Plausible(r.parameters.data());
  r.contradicted = e->Contradiction(r.parameters.data(), data.evidence);
  r.premises = e->CheckPremises(r.parameters.data(), data.evidence);
  for (const Premise& premise : r.premises)
    r.accepted = r.accepted && !premise.Failed();
  return r;
}

// Appends to *note the candidates that would have lowered the held-out J
// more than the one kept, had the channels not contradicted them.
void SayContradicted(const std::vector<CandidateResult>& tried,
                     size_t kept_index,
                     std::string* note) {
  const double kept = tried[kept_index].heldout_after;
  for (const CandidateResult& c : tried) {
    if (c.contradicted.empty() || !(c.heldout_after < kept)) continue;
    *note += fmt::format("{}{} would lower the held-out J by {:.0f}%, but {}",
                         note->empty() ? "" : "; ",
                         c.effect,
                         100 * c.relative_gain,
                         c.contradicted);
  }
}

// The candidates' indices by held-out J, best first; those the channels
// contradict go last, so that the others are chosen from.
std::vector<size_t> Ranked(const std::vector<CandidateResult>& results) {
  std::vector<size_t> order(results.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const bool ca = !results[a].contradicted.empty(),
               cb = !results[b].contradicted.empty();
    if (ca != cb) return cb;
    return results[a].heldout_after < results[b].heldout_after;
  });
  return order;
}

// The parity dominating the residual's map, kMixed when neither does.
Parity Dominant(double odd, double even, double dominance) {
  if (odd >= dominance * even) return Parity::kOdd;
  if (even >= dominance * odd) return Parity::kEven;
  return Parity::kMixed;
}

}  // namespace

size_t PickCandidate(std::vector<CandidateResult>* tried,
                     double before,
                     const ResidualParity& split,
                     const DiagnoseOptions& o,
                     std::string* note) {
  std::vector<CandidateResult>& c = *tried;
  const Parity dominant =
      Dominant(split.odd_rms_n, split.even_rms_n, o.signature_dominance);
  for (CandidateResult& r : c) {
    const double odd = r.odd_removed_n, even = r.even_removed_n;
    r.matches_signature =
        dominant == Parity::kMixed ||
        (dominant == Parity::kOdd ? odd >= even : even >= odd);
  }
  const auto gain = [&](size_t i) { return before - c[i].heldout_after; };
  size_t pick = 0;
  for (size_t i = 1; i < c.size(); ++i) {
    if (c[i].accepted && c[0].accepted &&
        c[i].parameters.size() < c[0].parameters.size() &&
        gain(i) >= o.parsimony * gain(0)) {
      pick = i;  // the best of those with fewer parameters
      *note = fmt::format(
          "{} explains {:.0f}% of what {} does with fewer parameters; "
          "preferred",
          c[i].effect,
          100 * gain(i) / gain(0),
          c[0].effect);
      break;
    }
  }
  if (c[pick].matches_signature || !c[pick].accepted) return pick;
  const bool odd = dominant == Parity::kOdd;
  const std::string why = fmt::format(
      "{} lowers the held-out J by {:.0f}%, but of the residual's "
      "direction-{} part, which dominates it ({:.3f} N rms against {:.3f} "
      "N), it removes {:.3f} N, and {:.3f} N of the direction-{} part: not "
      "the residual's signature",
      c[pick].effect,
      100 * c[pick].relative_gain,
      odd ? "odd" : "even",
      odd ? split.odd_rms_n : split.even_rms_n,
      odd ? split.even_rms_n : split.odd_rms_n,
      odd ? c[pick].odd_removed_n : c[pick].even_removed_n,
      odd ? c[pick].even_removed_n : c[pick].odd_removed_n,
      odd ? "even" : "odd");
  size_t j = 0;
  while (j < c.size() && !(c[j].matches_signature && c[j].accepted)) ++j;
  if (j == c.size()) {
    *note = why + "; no candidate that removes it passes: not named";
    c[pick].accepted = false;
  } else if (gain(pick) >= o.signature_margin * gain(j)) {
    *note = why + fmt::format(
                      "; named all the same: its held-out gain is {:.1f} "
                      "times that of {}, the best that matches",
                      gain(pick) / gain(j),
                      c[j].effect);
  } else {
    *note = why + fmt::format("; {} removes {:.3f} N of it and is named",
                              c[j].effect,
                              odd ? c[j].odd_removed_n : c[j].even_removed_n);
    pick = j;
  }
  return pick;
}

}  // namespace wearscar::fusion

namespace wearscar::fusion::internal {

const Effect* EdgeShapes::From(const Effect& smooth,
                               const std::vector<double>& a) {
  const std::vector<double> uc = smooth.Knots();
  const int even = std::max(3, knots_ / 2);
  std::vector<double> u;
  for (int i = 0; i < even; ++i) u.push_back(double(i) / (even - 1));
  double total = 0;
  for (size_t j = 0; j + 1 < a.size(); ++j)
    total += (a[j + 1] - a[j]) * (a[j + 1] - a[j]);
  for (size_t j = 0; total > 0 && j + 1 < a.size(); ++j) {
    const double w = (a[j + 1] - a[j]) * (a[j + 1] - a[j]) / total;
    const int n = static_cast<int>(std::lround((knots_ - even) * w));
    for (int k = 1; k <= n; ++k)
      u.push_back(uc[j] + (uc[j + 1] - uc[j]) * k / (n + 1));
  }
  std::sort(u.begin(), u.end());
  u.erase(
      std::unique(
          u.begin(), u.end(), [](double p, double q) { return q - p < 1e-9; }),
      u.end());
  made_.push_back(AlongTrackFrictionAt(std::move(u), /*edges=*/true));
  return made_.back().get();
}

void SelectEffects(const Data& data,
                   const std::vector<const Effect*>& pool,
                   const DiagnoseOptions& o,
                   Diagnosis* out,
                   Model* model,
                   std::vector<double>* base) {
  double base_bic = CycleBic(data, *model, 0);
  std::vector<int> all(data.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  // The residual's parts before each step: after the model so far (each
  // kept candidate's removal taken off them).
  Model current = *model;
  ParitySplit split =
      SplitByParity(data, current, FitModel(data, all, &current));
  while (static_cast<int>(model->effects.size()) < o.max_effects) {
    std::vector<CandidateResult> results;
    std::vector<Model> models;
    std::vector<std::vector<double>> heldouts;
    for (const Effect* e : pool) {
      if (std::any_of(model->effects.begin(),
                      model->effects.end(),
                      [&](const Effect* m) { return m->Key() == e->Key(); }))
        continue;
      models.emplace_back();
      heldouts.emplace_back();
      results.push_back(TryEffect(data,
                                  *model,
                                  *base,
                                  base_bic,
                                  split,
                                  e,
                                  o,
                                  &models.back(),
                                  &heldouts.back()));
    }
    if (results.empty()) break;
    const std::vector<size_t> order = Ranked(results);
    DiagnosisStep step;
    for (size_t i : order) step.tried.push_back(results[i]);
    const size_t pick = PickCandidate(&step.tried,
                                      Mean(*base),
                                      {split.odd_rms_n, split.even_rms_n},
                                      o,
                                      &step.note);
    SayContradicted(step.tried, pick, &step.note);
    const size_t kept = order[pick];
    std::rotate(step.tried.begin(),
                step.tried.begin() + pick,
                step.tried.begin() + pick + 1);
    step.chosen = step.tried.front();
    // A further effect must also take a share of the initial gap: a first
    // effect's small misfit (a sensor's first-order lag fitted as a pure
    // delay also shrinks the profile's features) is no second effect.
    if (!out->named.empty() && step.chosen.accepted &&
        step.chosen.heldout_before - step.chosen.heldout_after <
            o.later_share * o.min_relative_gain * out->heldout_initial) {
      step.chosen.accepted = false;
      step.tried.front().accepted = false;
      step.note = fmt::format(
          "{} lowers the held-out J by {:.1f}% of its initial value, less "
          "than the {:.1f}% a further effect needs; not named",
          step.chosen.effect,
          100 * (step.chosen.heldout_before - step.chosen.heldout_after) /
              out->heldout_initial,
          100 * o.later_share * o.min_relative_gain);
    }
    out->steps.push_back(step);
    if (!step.chosen.accepted) break;
    *model = std::move(models[kept]);
    *base = std::move(heldouts[kept]);
    split.odd_rms_n -= step.chosen.odd_removed_n;
    split.even_rms_n -= step.chosen.even_removed_n;
    base_bic += step.chosen.delta_bic;
    out->named.push_back(step.chosen.effect);
    out->model.push_back(step.chosen);
  }
}

namespace {

// The held-out J per cycle of `m` with the penalty weight of its shape
// (if any) the held-out cycles prefer of `weights`, and the model fitted
// on all cycles (*m).
std::vector<double> Refit(const Data& data,
                          const std::vector<double>& weights,
                          int folds,
                          Model* m) {
  std::vector<std::vector<double>> unused;
  std::vector<double> h;
  size_t shape = m->effects.size();
  for (size_t e = 0; e < m->effects.size(); ++e)
    if (m->effects[e]->PenaltyCount() > 0) shape = e;
  if (shape == m->effects.size()) {
    h = HeldOut(data, *m, folds, nullptr);
  } else {
    double best = INFINITY;
    for (double w : weights) {
      Model t = *m;
      t.penalty[shape] = w;
      std::vector<double> ht = HeldOut(data, t, folds, nullptr);
      if (Mean(ht) < best) best = Mean(ht), h = std::move(ht), *m = t;
    }
  }
  std::vector<int> all(data.cycles.size());
  std::iota(all.begin(), all.end(), 0);
  FitModel(data, all, m);
  return h;
}

// Appends words to the note of the step that named `effect`.
void AddToStep(Diagnosis* out,
               const std::string& effect,
               const std::string& words) {
  for (DiagnosisStep& step : out->steps) {
    if (step.chosen.effect != effect || !step.chosen.accepted) continue;
    step.note = step.note.empty() ? words : step.note + "; " + words;
  }
}

}  // namespace

void KeepEdges(const Data& data,
               const DiagnoseOptions& o,
               EdgeShapes* edges,
               Model* model,
               std::vector<double>* base,
               Diagnosis* out) {
  size_t shape = model->effects.size();
  for (size_t e = 0; e < model->effects.size(); ++e)
    if (model->effects[e]->PenaltyCount() > 0) shape = e;
  if (shape == model->effects.size()) return;
  const Effect* smooth = model->effects[shape];
  const Effect* fine = edges->From(*smooth, model->params[shape]);
  Model refined = *model;
  refined.effects[shape] = fine;
  // Started from the smooth shape (its knots are evenly spaced).
  const std::vector<double> u = fine->Knots();
  const Eigen::Map<const Eigen::VectorXd> a(
      model->params[shape].data(),
      static_cast<Eigen::Index>(model->params[shape].size()));
  refined.params[shape].resize(u.size());
  for (size_t i = 0; i < u.size(); ++i) {
    refined.params[shape][i] = support::InterpolateAtIndex(
        a, u[i] * static_cast<double>(a.size() - 1));
  }
  std::vector<double> h = Refit(data, o.edge_penalties, o.folds, &refined);
  if (!(Mean(h) < Mean(*base))) return;
  AddToStep(out,
            smooth->Name(),
            fmt::format("refined to {} knots gathered where it changes "
                        "fastest, edges kept: held-out J {:.4f} -> {:.4f}",
                        u.size(),
                        Mean(*base),
                        Mean(h)));
  for (CandidateResult& c : out->model) {
    if (c.effect == smooth->Name()) c.parameter_names = fine->ParameterNames();
  }
  *model = std::move(refined);
  *base = std::move(h);
  const double share =
      o.later_share * o.min_relative_gain * out->heldout_initial;
  for (size_t e = shape + 1; e < model->effects.size();) {
    Model without = *model;
    without.effects.erase(without.effects.begin() + e);
    without.params.erase(without.params.begin() + e);
    without.penalty.erase(without.penalty.begin() + e);
    std::vector<double> hw =
        Refit(data, {model->penalty[shape]}, o.folds, &without);
    if (Mean(hw) - Mean(*base) >= share) {
      ++e;
      continue;
    }
    const std::string name = model->effects[e]->Name();
    AddToStep(out,
              name,
              fmt::format("withdrawn: with the shape's edges kept it lowers "
                          "the held-out J by {:.1f}% of its initial value, "
                          "less than the {:.1f}% a further effect needs (it "
                          "stood in for the rounded edges)",
                          100 * (Mean(hw) - Mean(*base)) / out->heldout_initial,
                          100 * o.later_share * o.min_relative_gain));
    for (size_t i = 0; i < out->model.size(); ++i) {
      if (out->model[i].effect != name) continue;
      out->model.erase(out->model.begin() + static_cast<long>(i));
      out->named.erase(out->named.begin() + static_cast<long>(i));
      break;
    }
    *model = std::move(without);
    *base = std::move(hw);
  }
}

}  // namespace wearscar::fusion::internal
