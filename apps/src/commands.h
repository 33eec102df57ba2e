#pragma once

#include <CLI/CLI.hpp>

namespace wearscar::app {

// Each subcommand registers itself on the app and runs from the callback.
void AddSimulateCommand(CLI::App& app);
void AddForceCommand(CLI::App& app);
void AddFuseCommand(CLI::App& app);

}  // namespace wearscar::app
