#pragma once
// The pipeline of one test: AnalyzeTest takes a force record and a scan
// and returns everything (result.h) with the options it was given
// (fuse_options.h).

#include <future>
#include <memory>
#include <optional>
#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/fusion/result.h"
#include "wearscar/scan/height_map.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// Force analysis, then (when a scan is given) levelling, spikes, track,
// centreline, alignment, scan slope and mu-hat with it; then the mismatch
// report and the verdict. The scan is taken by value (it is levelled). A
// scan without a findable track, or whose profile cannot be aligned with
// the stroke, is left out with the reason in scan_skipped and the warnings
// (with SlopeChoice::kScan it is an error).
// Requires record.IsConsistent() and a consistent map (checked in debug
// and sanitizer builds; the readers return only such data).
TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::optional<scan::HeightMap> height_map,
                       const FuseOptions& options = {});

// The options a record is analysed with: when the spring's stiffness was
// not given and the force file states one, that one (spring_given set,
// spring_stated saying where). AnalyzeTest and the result's options block
// apply it.
FuseOptions WithStatedSpring(const FuseOptions& options,
                             const force::ForceRecord& record);

// PrepareScan's scan::NoTrackError, with the map as levelled (drawn so that
// the user sees why no track was found).
class NoTrackInMap : public scan::NoTrackError {
 public:
  NoTrackInMap(const scan::NoTrackError& e, scan::HeightMap levelled_map)
      : scan::NoTrackError(e),
        levelled(
            std::make_shared<const scan::HeightMap>(std::move(levelled_map))) {}
  std::shared_ptr<const scan::HeightMap> levelled;
};

// The profile's decision AnalyzeTest makes, on the force record alone (no
// scan): where k comes from (P/S or the depth channel) and P's slope's
// significance. LiveAnalysis asks it of the latest cycles. Throws what the
// segmentation throws (force::ForceError: too few cycles).
ProfileDecision DecideForceProfile(const force::ForceRecord& record,
                                   const FuseOptions& options);

// The scan's own stages, which need nothing of the force record: levelling,
// spikes, track, centreline (`levelled` holds the map; the rest of
// ScanAnalysis is filled by AnalyzeTest). Throws NoTrackInMap when the map
// holds no track.
ScanAnalysis PrepareScan(scan::HeightMap map, const FuseOptions& options);

// AnalyzeTest with the scan prepared elsewhere (PrepareScan), possibly
// still under way (a caller reading the force file meanwhile), and the
// scan's source; an invalid future: no scan.
TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::future<ScanAnalysis> prepared_scan,
                       const std::string& scan_file,
                       const FuseOptions& options = {});

}  // namespace wearscar::fusion
