// `proxygrasp sense`: registered so --help lists it; issue #3 builds it.
#include "commands.h"

#include <iostream>

namespace pg {

void AddSenseCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "sense", "Print what the table sees: tracked contacts per frame as JSON (not built yet)");
  cmd->allow_extras();
  cmd->callback([&exitCode] {
    std::cerr << "proxygrasp sense: not built yet (issue #3)\n";
    exitCode = kExitFailed;
  });
}

}  // namespace pg
