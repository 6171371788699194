// `proxygrasp calibrate`: registered so --help lists it; issue #7 builds it.
#include "commands.h"

#include <iostream>

namespace pg {

void AddCalibrateCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd =
      app.add_subcommand("calibrate", "Calibrate camera, table and projector (not built yet)");
  cmd->allow_extras();
  cmd->callback([&exitCode] {
    std::cerr << "proxygrasp calibrate: not built yet (issue #7)\n";
    exitCode = kExitFailed;
  });
}

}  // namespace pg
