// proxygrasp: a thin main over the subcommands.
#include "commands.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <malloc.h>

int main(int argc, char** argv) {
  // Every frame OpenCV allocates and frees images of a few hundred KB to a few MB (optical flow
  // pyramids, Sobel magnitudes, blurs). With glibc's adaptive thresholds those were, depending on
  // the order of earlier allocations, mapped fresh or trimmed off the heap each frame and faulted
  // in again: instant_fails ran 2.2x slower (2.6 s of system time) after an unrelated change of
  // allocation order. Keeping freed memory for reuse makes the cost independent of that order;
  // the peak stays what the largest frame needs (docs/performance.md, memory of a long run).
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
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
  pg::AddTuneCommand(app, exitCode);
  pg::AddBenchCommand(app, exitCode);

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
