#pragma once
// Units and plausibility: each channel's unit from the options, the file
// or its layout, else inferred from what a reciprocating tribometer can
// have measured; values no tribometer measured are refused.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "columns.h"
#include "layout_detection.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

// A channel's unit and its factor to s, mm or N.
struct Scale {
  double factor = 1.0;
  std::string unit;
  // No unit in the file or the options: inferred after the rows are read
  // (InferUnits), the layout's unit (`preferred`, if any) first.
  bool inferred = false;
  std::string preferred;
};

// The unit of `channel`'s column: the options', else the file's (`found`);
// a warning when both are given and differ. Throws ForceError for a unit
// that is not one of the channel's quantity.
Scale ResolveUnit(Channel channel,
                  const std::string& found,
                  const ReadForceOptions& options,
                  const std::string& file,
                  const std::string& column,
                  const ForceLayout& layout,
                  std::vector<std::string>* warnings);

// Units of the channels that state none, from plausibility: the layout's
// unit when it brings the channel's figure (stroke, median load, sampling
// rate) into the plausible range, else the first unit of the channel's
// list that does. The values are scaled in place; a warning names each
// assumption, and a channel no unit makes plausible is refused.
void InferUnits(Eigen::VectorXd* data,
                Scale* scale,
                const Columns& column,
                const Layout& layout,
                const std::string& file,
                ForceMetadata* meta);

// A depth channel whose name says it grows into the specimen (a
// "Penetration Depth", "Depth", "Wear depth") rather than a height or a
// position (Z, "Fz position", "Height").
bool NamesAPenetration(const std::string& column_name);

// What the checks below need of the samples, from one pass over them
// (millions in a long test): counts of comparisons, without a branch per
// sample; the pass is bound by reading the three channels from memory.
struct SampleCensus {
  static constexpr double kMaxForceN = 1e5, kMaxAbsXMm = 1e4;
  // The first sample with a force or x beyond these limits; size() if none.
  Eigen::Index first_beyond = 0;
  double median_abs_p = 0;           // P's median magnitude (a subsample's)
  long q_finite = 0, q_nonzero = 0;  // finite Q samples; those not 0
  // Samples with Q and P finite; of them, |Q| above |P|, and P below minus
  // or above plus a quarter of its median magnitude.
  long pairs = 0, q_above_p = 0, p_below = 0, p_above = 0;
};
SampleCensus TakeCensus(const ForceRecord& r);

// What a reciprocating tribometer can have measured: refused outside the
// hard limits (a unit or file error), warned of outside the usual ranges.
void CheckPlausible(ForceRecord& r,
                    const SampleCensus& census,
                    const std::string& file);

// Refuses channels that cannot be a friction force and a load: |Q| above
// |P| on most samples (swapped channels, or mu above 1), or a "load" that
// changes sign with the motion (P as it stands after a negative load was
// negated). The message names both columns and the fix (--columns, or
// --force-channels-as-given).
void CheckChannelRoles(const ForceRecord& r,
                       const SampleCensus& census,
                       const std::string& file);

// Throws ForceError when the friction channel is zero in every sample: no
// friction force was recorded (a constant offset is analysed, and said by
// its figures).
void CheckFrictionRecorded(const ForceRecord& r,
                           const SampleCensus& census,
                           const std::string& file);

}  // namespace wearscar::force::internal
