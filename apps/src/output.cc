#include "output.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

#include "commands.h"
#include "wearscar/fusion/settings.h"

namespace wearscar::app {

namespace {
int g_exit_status = 0;
PrintMode g_print_mode = PrintMode::kText;
bool g_break_lock = false;
}  // namespace

PrintMode CurrentPrintMode() { return g_print_mode; }

bool BreakLock() { return g_break_lock; }

void AddBreakLockOption(CLI::App* cmd) {
  cmd->add_flag_callback(
      "--break-lock",
      [] { g_break_lock = true; },
      "Remove a lock file of the output folder left by a wearscar that was "
      "killed (where the file system has no flock; the message names it)");
}

void AddPrintModeOptions(CLI::App* cmd) {
  auto* quiet = cmd->add_flag_callback(
      "-q,--quiet",
      [] { g_print_mode = PrintMode::kQuiet; },
      "Print nothing on stdout (warnings and errors still go to stderr)");
  cmd->add_flag_callback(
         "--json",
         [] { g_print_mode = PrintMode::kJson; },
         "Print the summary as JSON on stdout instead of text")
      ->excludes(quiet);
}

void WithoutFigureData(fusion::FuseOptions* options) {
  options->friction_map.loop_bins = 0;
}

void AddTestCommandOptions(CLI::App* cmd,
                           bool* no_figures,
                           report::FigureFormats* formats,
                           unsigned sections,
                           bool break_lock,
                           GivenSettings* given) {
  AddFigureOptions(cmd, no_figures, formats);
  AddPrintModeOptions(cmd);
  if (break_lock) AddBreakLockOption(cmd);
  AddSettingFlags(
      cmd, fusion::TestSettingList(), sections, fusion::TestSettings{}, given);
}

void AddFigureOptions(CLI::App* cmd,
                      bool* no_figures,
                      report::FigureFormats* formats,
                      const std::string& skip_help) {
  cmd->add_flag("--no-figures", *no_figures, skip_help);
  cmd->add_option_function<std::string>(
         "--figure-format",
         [formats](const std::string& text) {
           report::FigureFormats::Parse(text, formats);
         },
         "Figure files: svg (the default: vector, drawn in a quarter of "
         "PNG's time), png, or svg,png")
      ->check(CLI::Validator(
          [](std::string& text) {
            report::FigureFormats f;
            return report::FigureFormats::Parse(text, &f)
                       ? std::string()
                       : "expected svg, png or svg,png; found '" + text + "'";
          },
          "svg|png|svg,png"));
}

void SayFiguresDrawn(const report::FigureSet& figures,
                     const report::FigureFormats& formats,
                     const std::string& out) {
  Say("drew {} figures ({}) in {}/\n",
      figures.shown.size(),
      formats.png && formats.svg ? "SVG and PNG"
      : formats.png              ? "PNG"
                                 : "SVG",
      out);
}

void PrintJsonSummary(const nlohmann::json& summary) {
  if (g_print_mode == PrintMode::kJson) fmt::print("{}\n", summary.dump(2));
}

void SetExitStatus(int status) { g_exit_status = status; }
int ExitStatus() { return g_exit_status; }

Progress::Progress(std::string label, long total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::Update(long done) {
  if (g_print_mode != PrintMode::kText) return;  // --quiet, --json
  const int percent = total_ > 0 ? static_cast<int>(100 * done / total_) : 100;
  if (tty_) {
    if (percent == last_percent_) return;
    const int width = 30, filled = width * percent / 100;
    fmt::print(stderr,
               "\r{} [{}{}] {:3d}% ({}/{})",
               label_,
               std::string(filled, '#'),
               std::string(width - filled, '.'),
               percent,
               done,
               total_);
    std::fflush(stderr);
  } else if (percent / 25 != last_percent_ / 25) {
    fmt::print(stderr, "{}: {}/{} ({}%)\n", label_, done, total_, percent);
  }
  last_percent_ = percent;
}

void Progress::Finish() {
  Update(total_);
  if (tty_ && g_print_mode == PrintMode::kText) fmt::print(stderr, "\n");
}

}  // namespace wearscar::app
