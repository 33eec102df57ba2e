#pragma once
// The scan's settings shared by a test's (TestSettingList) and a map's
// alone (MapSettingList): finding the track and reading the scan file, in
// any settings struct.

#include <fmt/format.h>

#include <functional>
#include <string>
#include <vector>

#include "wearscar/scan/read_scan.h"
#include "wearscar/scan/track.h"
#include "wearscar/support/settings.h"

namespace wearscar::fusion::internal {

using support::FlagSetting;
using support::IntegerSetting;
using support::NumberSetting;
using support::SettingError;
using support::TextSetting;

// Finding or placing the worn track, in any settings struct.
template <class Target>
std::vector<support::Setting<Target>> TrackSettings(
    std::function<scan::TrackOptions&(Target&)> track) {
  const char* g = "Scan";
  auto manual = [g, track](const char* name, const char* help, auto member) {
    auto s = NumberSetting<Target>(
        name, g, help, -1e6, 1e6, [track, member](Target& t) -> double& {
          return track(t).*member;
        });
    s.show = [](const Target&) { return std::string(); };
    return s;
  };
  using O = scan::TrackOptions;
  return {
      NumberSetting<Target>(
          "min-depth",
          g,
          "Track: least depth, mm",
          1e-9,
          100,
          [track](Target& t) -> double& { return track(t).min_depth_mm; }),
      NumberSetting<Target>(
          "min-elongation",
          g,
          "Track: least length/width of the depression",
          1,
          1e3,
          [track](Target& t) -> double& { return track(t).min_elongation; }),
      manual("track-length",
             "Track length, mm (manual placement; 0 = across the field)",
             &O::manual_length_mm),
      FlagSetting<Target>(
          "manual-track",
          g,
          "Place the track by hand (--track-x, --track-y, --track-angle)",
          [track](Target& t) -> bool& { return track(t).manual; }),
      manual("track-angle",
             "Track angle, degrees (manual placement)",
             &O::angle_deg),
      manual(
          "track-x", "Track centre x, mm (manual placement)", &O::centre_x_mm),
      manual(
          "track-y", "Track centre y, mm (manual placement)", &O::centre_y_mm),
  };
}

// Reading the height map, in any settings struct.
template <class Target>
std::vector<support::Setting<Target>> ScanFileSettings(
    std::function<scan::ReadScanOptions&(Target&)> read) {
  const char* g = "Scan";
  return {
      {"large-maps",
       g,
       "Raise the decompression limits for genuinely large maps (a member "
       "up to 8 GiB, a file 16 GiB, any ratio)",
       "",
       ~0u,
       [read](Target* t, const std::string& text) {
         if (support::ParseFlag(text)) scan::AllowLargeMaps(&read(*t));
       },
       [](const Target&) { return std::string(); }},
      NumberSetting<Target>(
          "max-pixel-aspect",
          g,
          "Refuse scan pixels longer one way than this times the other "
          "(raise it for genuinely unequal pitches)",
          1,
          1e6,
          [read](Target& t) -> double& { return read(t).max_pixel_aspect; }),
      IntegerSetting<Target>(
          "measurement",
          g,
          ".zag measurement index",
          0,
          100000,
          [read](Target& t) -> int& { return read(t).measurement_index; }),
      NumberSetting<Target>(
          "ascii-pitch",
          g,
          "ASCII matrix pixel size, mm",
          0,
          1e3,
          [read](Target& t) -> double& { return read(t).ascii_pitch_mm; }),
      TextSetting<Target>(
          "ascii-unit",
          g,
          "ASCII matrix height unit",
          [read](Target& t) -> std::string& { return read(t).ascii_z_unit; }),
  };
}

}  // namespace wearscar::fusion::internal
