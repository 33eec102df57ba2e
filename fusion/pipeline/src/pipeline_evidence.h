#pragma once
// The pipeline's evidence for the profile's decision (fuse.cc's
// PipelineEvidence), apart from the pipeline that runs it.

#include <future>
#include <optional>

#include "scan_side.h"
#include "wearscar/fusion/profile_decision.h"

namespace wearscar::fusion::internal {

// The pipeline's figures for DecideProfile, each computed when first asked
// for, and what the decision needed kept for the analysis after it: the
// fit with k from P/S, the scan (prepared on another thread) and its
// alignment with P/S. Where the decision will ask for that alignment
// whatever it finds (a scan, no depth channel, the profile from the spring
// or auto), it is made on the scan's thread as soon as the scan is ready.
// The fits with k from P/S as the pipeline's unit makes them (UnitRunner:
// mu_fit_spring), awaited where the decision asks for them.
using SpringFitsFuture = std::shared_future<std::shared_ptr<const SpringFits>>;

class PipelineEvidence : public ProfileEvidence {
 public:
  PipelineEvidence(const force::ForceRecord& record,
                   const ForceAnalysis& segmented,
                   const AnalysisOptions& analysis,
                   const FuseOptions& options,
                   std::future<ScanAnalysis> prepared,
                   std::shared_future<TrackHistory> history = {},
                   SpringFitsFuture spring_fits = {})
      : record_(record),
        segmented_(segmented),
        analysis_(analysis),
        options_(options),
        has_scan_(prepared.valid()),
        history_(std::move(history)),
        spring_fits_(std::move(spring_fits)) {
    // (The scan's thread holds `this`.)
    if (!has_scan_) return;
    const bool spring_sure =
        !record.has_depth() && (options.profile_from == ProfileSource::kAuto ||
                                options.profile_from == ProfileSource::kSpring);
    scan_side_ = std::async(
        spring_sure && options.parallel ? std::launch::async
                                        : std::launch::deferred,
        [this, spring_sure, o = options, p = std::move(prepared)]() mutable {
          ScanSide side;
          try {
            side.prepared = p.get();
          } catch (...) {
            side.scan_error = std::current_exception();
            return side;
          }
          if (spring_sure) AlignWithSpring(o, &side);
          return side;
        });
  }

  PipelineEvidence(const PipelineEvidence&) = delete;
  PipelineEvidence& operator=(const PipelineEvidence&) = delete;

  bool HasDepthChannel() const override { return record_.has_depth(); }
  std::string DepthColumn() const override {
    const auto& names = record_.metadata.channel_names;
    return names.size() > 4 ? names[4] : "depth";
  }
  bool DepthIsPenetration() const override {
    return record_.metadata.depth_is_penetration;
  }
  bool HasScan() const override { return has_scan_; }
  bool ForceSlopeFitted() const override { return analysis_.fit_force_slope; }
  double PSlopeSignificance() override {
    return ProfileSignificance(SpringFit());
  }
  int FittedCycles() override {
    return static_cast<int>(SpringFit().cycles.size());
  }
  int CorrelatedCycles() override { return SpringFit().correlated_cycles; }
  double SpringDepthAgreement() override {
    return fusion::SpringDepthAgreement(
        record_, segmented_, analysis_.friction.slope.spring_n_per_mm);
  }
  double DepthAgreement() override {
    return fusion::DepthAgreement(record_, segmented_);
  }
  double SpringPathRatio() override {
    if (!history_.valid()) return NAN;
    const ForceProfileOptions last = LastCycles();
    return SpringOverFrictionPath(
        history_.get(), last.first_cycle, last.last_cycle);
  }
  double SpringAmplitudeRatio() override {
    const ScanSide& side = AlignedWithSpring();
    return side.spring ? side.spring->alignment.amplitude_ratio : NAN;
  }

  // The scan aligned with the decided profile; throws what its preparation
  // or its alignment threw. Requires HasScan().
  ScanAnalysis TakeAlignedScan(const ProfileDecision& d) {
    if (d.FromSpring()) {
      ScanSide& side = AlignedWithSpring();
      if (side.align_error) std::rethrow_exception(side.align_error);
      return std::move(*side.spring);
    }
    return AlignScan(
        record_, segmented_, Prepared(), options_, d.used, d.depth_sign);
  }

 private:
  // The prepared scan, or what its reading or preparation threw; its
  // alignment with P/S once made, or what that threw.
  struct ScanSide {
    std::optional<ScanAnalysis> prepared;
    std::exception_ptr scan_error;
    std::optional<ScanAnalysis> spring;
    std::exception_ptr align_error;
  };

  // The last cycles after running-in, as AlignScan compares (at most
  // ForceProfileOptions::cycles).
  ForceProfileOptions LastCycles() const {
    return ComparedCycles(segmented_, options_);
  }
  // The fits with k from P/S: the unit's where the pipeline runs it, else
  // made here (DecideForceProfile).
  const SlopeFits& SpringFit() {
    if (spring_fits_.valid()) return *spring_fits_.get();
    if (!spring_fit_) {
      AnalysisOptions spring = analysis_;
      spring.friction.k_from_depth = false;
      spring_fit_ = FitForceSide(record_, spring, segmented_);
    }
    return *spring_fit_;
  }
  ScanSide& Side() {
    if (!side_) side_ = scan_side_.get();
    return *side_;
  }
  const ScanAnalysis& Prepared() {
    const ScanSide& side = Side();
    if (side.scan_error) std::rethrow_exception(side.scan_error);
    return *side.prepared;
  }
  // (`options` the pipeline's as they were before the decision: the
  // decision writes its choice into them while this may run.)
  void AlignWithSpring(const FuseOptions& options, ScanSide* side) const {
    if (side->spring || side->align_error) return;
    try {
      if (side->scan_error) std::rethrow_exception(side->scan_error);
      side->spring = AlignScan(record_,
                               segmented_,
                               *side->prepared,
                               options,
                               ProfileSource::kSpring,
                               1.0);
    } catch (...) {
      side->align_error = std::current_exception();
    }
  }
  ScanSide& AlignedWithSpring() {
    ScanSide& side = Side();
    AlignWithSpring(options_, &side);
    return side;
  }

  const force::ForceRecord& record_;
  const ForceAnalysis& segmented_;
  const AnalysisOptions& analysis_;
  const FuseOptions& options_;
  const bool has_scan_;
  std::shared_future<TrackHistory> history_;
  SpringFitsFuture spring_fits_;
  std::optional<SlopeFits> spring_fit_;
  std::future<ScanSide> scan_side_;
  std::optional<ScanSide> side_;
};

}  // namespace wearscar::fusion::internal
