// wearscar: identify the sliding friction coefficient of reciprocating
// friction tests from the force record and a profilometer scan.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "commands.h"
#include "wearscar/fusion/logging.h"

int main(int argc, char** argv) {
  CLI::App app{
      "wearscar: identify the sliding friction coefficient (mu-hat) of "
      "reciprocating "
      "friction tests whose loops look non-Coulomb, from the tribometer's "
      "force record "
      "and a profilometer scan of the worn track (wear-scar interaction, "
      "Q = P (k + s mu) / (1 - s mu k))."};
  app.require_subcommand(1);
  // One line on stderr for an error, nothing from the solvers' own logs.
  wearscar::fusion::QuietSolverLogging();
  auto* version = app.add_subcommand("version", "Print the version and exit");
  version->callback([] { fmt::print("wearscar {}\n", WEARSCAR_VERSION); });
  wearscar::app::AddSimulateCommand(app);
  wearscar::app::AddForceCommand(app);
  wearscar::app::AddFuseCommand(app);
  wearscar::app::AddAuditCommand(app);
  wearscar::app::AddDiagnoseCommand(app);
  wearscar::app::AddScanCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "wearscar: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    // Bad files and bad input from the libraries: one line, status 2.
    fmt::print(stderr, "wearscar: error: {}\n", e.what());
    return 2;
  }
  return wearscar::app::ExitStatus();
}
