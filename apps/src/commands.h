#pragma once

#include <CLI/CLI.hpp>

namespace wearscar::app {

// Each subcommand registers itself on the app and runs from the callback.
void AddSimulateCommand(CLI::App& app);
void AddForceCommand(CLI::App& app);
void AddFuseCommand(CLI::App& app);
void AddAuditCommand(CLI::App& app);
void AddDiagnoseCommand(CLI::App& app);
void AddScanCommand(CLI::App& app);
void AddWatchCommand(CLI::App& app);

// A subcommand's wish for the process exit status (0 unless set).
void SetExitStatus(int status);
int ExitStatus();

// Exit status of fuse and audit when the results were written but figures
// asked for were not drawn (README).
constexpr int kExitFiguresMissing = 4;
// Exit status of audit when any specimen failed (the rest are complete);
// 2 stays a usage error.
constexpr int kExitSpecimensFailed = 3;

}  // namespace wearscar::app
