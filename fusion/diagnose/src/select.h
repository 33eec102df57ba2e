#pragma once
// The diagnosis's selection: each step's candidates tried on held-out
// cycles and the one kept (the parsimony and signature rules,
// PickCandidate in diagnose.h), then the shape along the track refined
// where it changes fastest with its edges kept.

#include <memory>
#include <vector>

#include "diagnose_model.h"
#include "wearscar/fusion/diagnosis.h"
#include "wearscar/fusion/effects.h"

namespace wearscar::fusion::internal {

// The edge-keeping shapes tried once the smooth shape along the track is
// named, owned here for the models that hold them: half their knots
// evenly spaced, half in the smooth shape's intervals in proportion to its
// squared change over each, so that they gather where a band's edge is.
class EdgeShapes {
 public:
  explicit EdgeShapes(int knots) : knots_(knots) {}
  const Effect* From(const Effect& smooth, const std::vector<double>& a);

 private:
  int knots_;
  std::vector<std::unique_ptr<Effect>> made_;
};

// Greedy forward selection: each round tries every candidate of `pool` not
// yet in the model and keeps the one PickCandidate picks if it passes;
// stops at the first round whose pick fails, or at max_effects. The named
// effects and the steps go to *out, the model and its held-out J per
// cycle to *model and *base.
void SelectEffects(const Data& data,
                   const std::vector<const Effect*>& pool,
                   const DiagnoseOptions& o,
                   Diagnosis* out,
                   Model* model,
                   std::vector<double>* base);

// Once the smooth shape along the track is named, the shape refined where
// it changes fastest with edges kept (EdgeShapes, o.edge_penalties) takes
// its place when it predicts the held-out cycles better; then an effect
// named after the shape that no longer lowers the held-out J by the share
// a further effect needs (o.later_share) was mimicking the rounded edges
// (a lag blurs the measured edge as the smooth shape rounds its own) and
// is withdrawn. Selecting with the refined shape from the start would
// carry its knots through every later candidate's fits.
void KeepEdges(const Data& data,
               const DiagnoseOptions& o,
               EdgeShapes* edges,
               Model* model,
               std::vector<double>* base,
               Diagnosis* out);

}  // namespace wearscar::fusion::internal
