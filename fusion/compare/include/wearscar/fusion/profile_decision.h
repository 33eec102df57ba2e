#pragma once
// Where the force side's profile of the sliding path comes from (P/S, the
// depth channel, or the friction on a rig without a spring): decided once,
// by DecideProfile, from the figures it asks an evidence for.

#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/fusion/result.h"

namespace wearscar::fusion {

// The figures the decision reads, each computed when it is first asked for
// (a test whose P varies never aligns its scan for the decision, one
// without a depth channel never builds the depth's profile). The pipeline
// implements it over its record; tests implement it with fixed figures.
class ProfileEvidence {
 public:
  virtual ~ProfileEvidence() = default;
  virtual bool HasDepthChannel() const = 0;
  virtual std::string DepthColumn() const = 0;
  virtual bool DepthIsPenetration() const = 0;
  virtual bool HasScan() const = 0;
  // Whether mu-hat is fitted with the force side's k at all
  // (FuseOptions::slopes is not kScan).
  virtual bool ForceSlopeFitted() const = 0;
  // P's repeatable slope in its standard errors (ProfileSignificance of
  // the fit with k from P/S; NaN without the k split).
  virtual double PSlopeSignificance() = 0;
  // The fit's cycles and how many successive ones share their noise (the
  // words of the reason).
  virtual int FittedCycles() = 0;
  virtual int CorrelatedCycles() = 0;
  // SpringDepthAgreement and DepthAgreement of the record.
  virtual double SpringDepthAgreement() = 0;
  virtual double DepthAgreement() = 0;
  // P/S's amplitude against the path the friction shows over the last
  // cycles after running-in (SpringOverFrictionPath; NaN on a flat track),
  // and against the scanned profile once aligned (Alignment::
  // amplitude_ratio; NaN when the scan cannot be aligned).
  virtual double SpringPathRatio() = 0;
  virtual double SpringAmplitudeRatio() = 0;
};

// The decision, with FuseOptions' thresholds (each written there once):
// - given depth: the depth channel (an error without one); given friction:
//   the friction's profile (an error without a scan); given spring: P/S.
// - auto with a depth channel: the depth when P's slope is within
//   dead_weight_significance standard errors of nothing, or when P/S's
//   profile follows the depth's by less than spring_depth_agreement (Q's
//   crosstalk into P on a dead weight).
// - auto with a scan: the friction when P's slope is insignificant and P/S
//   varies less than dead_weight_ratio of the path the friction shows (of
//   the scanned profile where the friction's path is flat: the scan's
//   ratio rests on its alignment, which another specimen's scan upsets).
// - the depth is turned over (depth_sign -1) when its profile runs against
//   the friction's by more than depth_turn_agreement.
// Throws FusionError for a source given that the data cannot give.
ProfileDecision DecideProfile(ProfileEvidence* evidence,
                              const FuseOptions& options);

// How far P's repeatable slope is from nothing, in its standard errors
// (the k split's repeatable rms against its noise over the root of the
// independent cycles); NaN without the split.
double ProfileSignificance(const SlopeFits& force);

// The fit's options as the decision says (k from the depth, with its
// sign, or from P): the one place the decision reaches the fit; fuse and
// watch apply it, the diagnosis reads the options the result records.
void ApplyProfile(const ProfileDecision& decision,
                  FrictionFitOptions* friction);

// The rule "P's slope is noise", in one place for fuse, watch, the
// diagnosis and the profile's choice: P's repeatable slope within
// FuseOptions::dead_weight_significance standard errors of nothing
// (kNoise), so on a rig that may load the ball with a dead weight k from
// P is noise; kNotSplit where the slope was not split into signal and
// noise (k per cycle), which each user treats as it must say.
enum class PSlope { kVaries, kNoise, kNotSplit };
PSlope ClassifyPSlope(double significance, const FuseOptions& options);
// "P does not vary along the stroke beyond its noise (1.2 standard
// errors)": the rule's words.
std::string PSlopeNoiseText(double significance);

// The correlation of the depth channel's profile with the friction's over
// the last cycles after running-in (the signs as read); NaN when either
// cannot be built. Reads only the cycles and the running-in of `force`.
double DepthAgreement(const force::ForceRecord& record,
                      const ForceAnalysis& force);

// The correlation of P/S's profile with the depth channel's over the same
// cycles (a spring's P follows the depth: near +-1); NaN when either cannot
// be built.
double SpringDepthAgreement(const force::ForceRecord& record,
                            const ForceAnalysis& force,
                            double spring_n_per_mm);

}  // namespace wearscar::fusion
