#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.h"
#include "output.h"
#include "setting_flags.h"
#include "wearscar/fusion/products.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/figures.h"
#include "wearscar/scan/formats.h"
#include "wearscar/scan/gsf.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/preview.h"
#include "wearscar/scan/read_scan.h"
#include "wearscar/scan/track.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

struct ScanArgs {
  std::string file;
  std::string out;
  GivenSettings given;  // the map's settings as written
  bool no_figures = false;
  report::FigureFormats figure_formats;
};

void PrintTrack(const std::string& file, const scan::Track& t) {
  Say("  track: centre ({:.3f}, {:.3f}) mm, angle {:.2f} deg, length {:.3f} "
      "mm, width {:.3f} mm, mean depth {:.1f} um, max depth {:.1f} um, "
      "volume {:.4g} mm^3 ({})\n",
      t.centre_x_mm,
      t.centre_y_mm,
      t.angle_deg,
      t.length_mm,
      t.width_mm,
      1e3 * t.mean_depth_mm,
      1e3 * t.max_depth_mm,
      t.volume_mm3,
      t.message);
  if (t.low_confidence)
    fmt::print(stderr, "wearscar: warning: {}: {}\n", file, t.message);
}

void RunScan(const ScanArgs& a) {
  const fusion::MapSettings settings =
      WithFlagNames([&] { return fusion::MakeMapSettings(a.given); });
  scan::HeightMap map = scan::ReadScan(a.file, settings.read_scan);
  Say("{}: {} x {} pixels, pitch {:.4g} x {:.4g} um ({}{}{}), {} valid\n",
      a.file,
      map.cols(),
      map.rows(),
      1e3 * map.dx_mm,
      1e3 * map.dy_mm,
      map.metadata.format,
      map.metadata.instrument.empty() ? "" : ", ",
      map.metadata.instrument,
      map.ValidCount());
  for (const std::string& w : map.metadata.warnings) Say("  note: {}\n", w);
  // No track: everything that does not need one is still written, with
  // "track": null and the reason, and the command exits 0 with a warning.
  const fusion::MapAnalysis r =
      fusion::AnalyzeMap(std::move(map), settings.analysis);
  Say("  levelled: {}; {} spikes removed\n", r.level.message, r.spikes_removed);
  if (r.track) {
    PrintTrack(a.file, *r.track);
  } else {
    fmt::print(stderr, "wearscar: warning: {}\n", r.no_track);
  }
  if (a.out.empty()) {
    PrintJsonSummary(fusion::MakeMapProducts(a.file, r).result);
    return;
  }
  // Staged: a run that fails late (a full disk, a map too small for the
  // preview) leaves nothing new in the folder.
  const OutputLock lock(a.out, OutputLock::kExclusive, BreakLock());
  StagedOutput stage(a.out, "scan");
  std::vector<std::string> written;
  auto path = [&](const std::string& file) {
    written.push_back(file);
    return (fs::path(stage.dir()) / file).string();
  };
  const auto files = fusion::MakeMapProducts(a.file, r).Files();
  for (size_t i = 0; i + 1 < files.size(); ++i)
    WriteTextAtomically(path(files[i].first), files[i].second);
  scan::WriteGsf(r.levelled, path("levelled.gsf"));
  scan::WriteTrackPreviewPng(
      r.levelled, r.track ? *r.track : scan::Track{}, path("preview.png"));
  WriteTextAtomically(path(files.back().first), files.back().second);
  report::FigureSet figs;
  if (!a.no_figures) {
    figs = report::DrawMapFigure(
        stage.dir(), fs::path(a.file).filename().string(), r, a.figure_formats);
    for (const std::string& file : figs.files)
      written.push_back(fs::path(file).filename().string());
  }
  stage.Commit();
  if (!figs.message.empty())
    fmt::print(stderr, "wearscar: warning: {}\n", figs.message);
  Say("wrote {} to {}/\n", fmt::join(written, ", "), a.out);
  PrintJsonSummary(nlohmann::json::parse(files.back().second));
}

}  // namespace

void AddScanCommand(CLI::App& app) {
  auto args = std::make_shared<ScanArgs>();
  auto* cmd =
      app.add_subcommand("scan",
                         "Analyse a height map alone: level on the unworn "
                         "area, remove spikes, find the worn "
                         "track, extract its centreline and cross-sections");
  cmd->add_option(
         "file", args->file, "Height map (" + scan::ScanExtensionList() + ")")
      ->required();
  cmd->add_option("-o,--out", args->out, "Directory for the results");
  AddSettingFlags(
      cmd, fusion::MapSettingList(), ~0u, fusion::MapSettings{}, &args->given);
  AddFigureOptions(
      cmd, &args->no_figures, &args->figure_formats, "Skip the map figure");
  AddPrintModeOptions(cmd);
  AddBreakLockOption(cmd);
  cmd->footer(
      "Examples:\n"
      "  wearscar scan track.zon -o out/scan\n"
      "  wearscar scan map.x3p --level-order 2 --sections -2,0,2\n"
      "  wearscar scan flat.gsf --manual-track --track-x 3.8 --track-y 2.8 "
      "--track-angle 0 --json");
  cmd->callback([args] { RunScan(*args); });
}

}  // namespace wearscar::app
