#pragma once

#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/read_force.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/fusion/fuse_settings.h"
#include "wearscar/fusion/map_analysis.h"
#include "wearscar/scan/read_scan.h"
#include "wearscar/support/settings.h"

namespace wearscar::fusion {

// Everything the reading and the analysis of one test take.
struct TestSettings {
  force::ReadForceOptions read_force;
  scan::ReadScanOptions read_scan;
  FuseOptions fuse;
};

// Every setting of a test as text: "spring" (--spring 8.5 on the command
// line, spring=8.5 in Python), "running-in" (auto or a number of cycles),
// "columns" (time=NAME,x=NAME:UNIT,q=...,p=...), the units, the slope
// choice, the verdict's limits, the scan's levelling and track. Cycles are
// counted from 1 in the text, from 0 in the structs.
const std::vector<support::Setting<TestSettings>>& TestSettingList();

// The settings from the defaults with `given` (name, text) applied, then
// checked across settings (the first compared cycle before the last, every
// option struct valid). Throws support::SettingFailed naming the setting
// (its name empty for a check across settings).
TestSettings MakeTestSettings(
    const std::vector<std::pair<std::string, std::string>>& given);

// Everything a height map analysed alone (wearscar scan) takes.
struct MapSettings {
  scan::ReadScanOptions read_scan;
  MapAnalysisOptions analysis;
};

// The map's settings as text: reading, levelling, spikes, the track, the
// centreline and the cross-sections ("sections": positions along the
// track, comma-separated or repeated).
const std::vector<support::Setting<MapSettings>>& MapSettingList();

// The defaults with `given` applied, checked; throws
// support::SettingFailed.
MapSettings MakeMapSettings(
    const std::vector<std::pair<std::string, std::string>>& given);

}  // namespace wearscar::fusion
