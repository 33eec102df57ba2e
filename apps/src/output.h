#pragma once

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "setting_flags.h"
#include "usage_error.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/output_folder.h"

namespace wearscar::app {

using report::EnsureDirectory;
using report::OutputLock;
using report::RecordOutputs;
using report::StagedOutput;
using report::WriteTextAtomically;

// What an analysing command prints on stdout: its human summary (the
// default), nothing (--quiet) or its summary as JSON (--json). Warnings
// and errors go to stderr in every mode.
enum class PrintMode { kText, kQuiet, kJson };
PrintMode CurrentPrintMode();
// Adds -q,--quiet and --json to a command.
void AddPrintModeOptions(CLI::App* cmd);

// --break-lock: the output folder's lock files (on a file system without
// flock) are removed rather than obeyed (report::OutputLock).
bool BreakLock();
void AddBreakLockOption(CLI::App* cmd);

// fmt::print to stdout in text mode only.
template <typename... Args>
void Say(fmt::format_string<Args...> format, Args&&... args) {
  if (CurrentPrintMode() == PrintMode::kText)
    fmt::print(format, std::forward<Args>(args)...);
}

// Adds --no-figures and --figure-format (svg, png or svg,png) to a
// command.
void AddFigureOptions(CLI::App* cmd,
                      bool* no_figures,
                      report::FigureFormats* formats,
                      const std::string& skip_help = "Skip the figures");

// What every command that analyses a test adds after its own options:
// --no-figures and --figure-format, --quiet and --json, --break-lock where
// it writes a folder another run may hold, and the test's settings of
// `sections` (fusion::TestSettingList) as flags into `given`.
void AddTestCommandOptions(CLI::App* cmd,
                           bool* no_figures,
                           report::FigureFormats* formats,
                           unsigned sections,
                           bool break_lock,
                           GivenSettings* given);

// --no-figures: none of what only a figure draws is computed or written
// either (the friction map's binned loops, loop_viewer.json: the report's
// cycle slider).
void WithoutFigureData(fusion::FuseOptions* options);

// "drew 14 figures (SVG) in out/" in text mode.
void SayFiguresDrawn(const report::FigureSet& figures,
                     const report::FigureFormats& formats,
                     const std::string& out);

// The command's summary on stdout in --json mode (indented, one document).
void PrintJsonSummary(const nlohmann::json& summary);

// Progress on a terminal (a bar on stderr), plain lines otherwise; nothing
// with --quiet or --json.
class Progress {
 public:
  Progress(std::string label, long total);
  void Update(long done);
  void Finish();

 private:
  std::string label_;
  long total_;
  bool tty_;
  int last_percent_ = -1;
};

}  // namespace wearscar::app
