#pragma once
// The settings of FuseOptions as users write them (support::Setting: the
// command line's flags, Python's keyword arguments): the slope and its
// stencil, the running-in, the verdict's limits, LuGre, the slope choice
// and the cycles compared, the scan's levelling and slope. One list beside
// the options it sets; a test's settings (settings.h, the pipeline) add
// the force file's and the scan file's to it.

#include <vector>

#include "wearscar/fusion/fuse_options.h"
#include "wearscar/support/settings.h"

namespace wearscar::fusion {

// Which commands take a setting (Setting::sections): a command lists only
// what it uses.
enum SettingSection : unsigned {
  kForceFileSettings = 1u << 0,  // columns, units, rate
  kSlopeSettings = 1u << 1,      // spring, k estimate, stencil, running-in
  kVerdictSettings = 1u << 2,    // the verdict's limits
  kLugreSettings = 1u << 3,
  kCompareSettings = 1u << 4,    // the slope choice, cycles compared
  kScanFileSettings = 1u << 5,   // reading a scan
  kLevelTrackSettings = 1u << 6  // levelling and the track of a scan
};
inline constexpr unsigned kForceCommandSettings =
    kForceFileSettings | kSlopeSettings | kVerdictSettings | kLugreSettings;
inline constexpr unsigned kFuseSettings = kForceCommandSettings |
                                          kCompareSettings | kScanFileSettings |
                                          kLevelTrackSettings;
inline constexpr unsigned kDiagnoseSettings =
    kForceFileSettings | kSlopeSettings | kScanFileSettings |
    kLevelTrackSettings;

// FuseOptions' settings, each with its sections, in the order they apply
// and the help lists them.
const std::vector<support::Setting<FuseOptions>>& FuseSettingList();

}  // namespace wearscar::fusion
