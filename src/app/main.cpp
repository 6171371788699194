// proxygrasp: a thin main over the subcommands.
#include "commands.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "proxygrasp: grasp virtual objects on an imaging touch table with persistent "
      "particle proxies (Wilson, ITS 2009)."};
  // at most one subcommand; a missing one is reported after parsing so that an unknown word is
  // named as such rather than as a missing subcommand
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", "proxygrasp 0.1.0");

  int exitCode = pg::kExitOk;
  pg::AddParamsCommand(app, exitCode);
  pg::AddSenseCommand(app, exitCode);
  pg::AddRunCommand(app, exitCode);
  pg::AddPlayCommand(app, exitCode);
  pg::AddCalibrateCommand(app, exitCode);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // unknown subcommands and options, missing or malformed arguments
    std::cerr << "proxygrasp: " << e.what() << "\nRun 'proxygrasp --help' for usage.\n";
    return pg::kExitBadInput;
  }
  if (app.get_subcommands().empty()) {
    std::cerr << "proxygrasp: a subcommand is required\nRun 'proxygrasp --help' for usage.\n";
    return pg::kExitBadInput;
  }
  return exitCode;
}
