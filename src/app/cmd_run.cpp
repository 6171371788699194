// `proxygrasp run`: registered so --help lists it; issue #6 builds it.
#include "commands.h"

#include <iostream>

namespace pg {

void AddRunCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd =
      app.add_subcommand("run", "Run levels headless and check their expectations (not built yet)");
  cmd->allow_extras();
  cmd->callback([&exitCode] {
    std::cerr << "proxygrasp run: not built yet (issue #6)\n";
    exitCode = kExitFailed;
  });
}

}  // namespace pg
