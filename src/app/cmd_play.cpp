// `proxygrasp play`: registered so --help lists it; issue #7 builds it.
#include "commands.h"

#include <iostream>

namespace pg {

void AddPlayCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd =
      app.add_subcommand("play", "Play a level in a window on the table (not built yet)");
  cmd->allow_extras();
  cmd->callback([&exitCode] {
    std::cerr << "proxygrasp play: not built yet (issue #7)\n";
    exitCode = kExitFailed;
  });
}

}  // namespace pg
