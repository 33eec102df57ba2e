// wearscar: identify the sliding friction coefficient of reciprocating
// friction tests from the force record and a profilometer scan.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#if WEARSCAR_MIMALLOC
#include <mimalloc.h>
#endif
#include <cstring>
#include <exception>

#include "commands.h"
#include "wearscar/fusion/logging.h"
#include "wearscar/fusion/provenance.h"

namespace {

std::string VersionText() {
  return fmt::format("wearscar {} (commit {})",
                     wearscar::fusion::Version(),
                     wearscar::fusion::GitCommit());
}

void AddVersionCommand(CLI::App& app) {
  app.add_subcommand("version", "Print the version and git commit")
      ->callback([] { fmt::print("{}\n", VersionText()); });
}

// The subcommands, in the order --help lists them.
struct Command {
  const char* name;
  void (*add)(CLI::App&);
};
constexpr Command kCommands[] = {
    {"version", AddVersionCommand},
    {"simulate", wearscar::app::AddSimulateCommand},
    {"force", wearscar::app::AddForceCommand},
    {"fuse", wearscar::app::AddFuseCommand},
    {"audit", wearscar::app::AddAuditCommand},
    {"diagnose", wearscar::app::AddDiagnoseCommand},
    {"scan", wearscar::app::AddScanCommand},
    {"watch", wearscar::app::AddWatchCommand},
};

const Command* FindCommand(const char* name) {
  for (const Command& c : kCommands) {
    if (std::strcmp(c.name, name) == 0) return &c;
  }
  return nullptr;
}

// The subcommands' names, for the message about an unknown one.
std::string CommandNames() {
  std::string names;
  for (const Command& c : kCommands)
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  return names;
}

}  // namespace

int main(int argc, char** argv) {
#if WEARSCAR_MIMALLOC
  // 2 MiB pages (transparent huge pages where the kernel allows them) for
  // the large arrays of a full-size test: on a virtual machine a fresh
  // 4 KiB page costs microseconds, and a fuse touches 140 MB of them
  // (docs/performance.md).
  mi_option_set_enabled(mi_option_large_os_pages, true);
#endif
  CLI::App app{
      "wearscar: identify the sliding friction coefficient (mu-hat) of "
      "reciprocating friction tests whose loops look non-Coulomb, from the "
      "tribometer's force record and a profilometer scan of the worn track "
      "(wear-scar interaction, Q = P (k + s mu) / (1 - s mu k)).",
      "wearscar"};
  app.require_subcommand(1);
  app.set_version_flag("--version", VersionText());
  app.footer(
      "Examples:\n"
      "  wearscar fuse test.csv --scan track.zon -o out\n"
      "  wearscar audit lab/ -o audit\n"
      "  wearscar simulate --all -o samples\n"
      "Every command's options: wearscar COMMAND --help");
  // One line on stderr for an error, nothing from the solvers' own logs.
  wearscar::fusion::QuietSolverLogging();
  // A command named first is the only one made (the others' options are
  // a millisecond of every start); otherwise all, for --help.
  const Command* named = argc > 1 ? FindCommand(argv[1]) : nullptr;
  if (named != nullptr) {
    named->add(app);
  } else if (argc > 1 && argv[1][0] != '-') {
    fmt::print(stderr,
               "wearscar: unknown command '{}'; expected one of {} "
               "(wearscar --help)\n",
               argv[1],
               CommandNames());
    return 2;
  } else {
    for (const Command& c : kCommands) c.add(app);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
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
