// The proxygrasp subcommands. Each Add*Command registers one subcommand on the CLI11 app; its
// callback stores the exit code in `exitCode` (0 ok, 1 a check failed, 2 bad input).
#pragma once

#include <CLI/CLI.hpp>

namespace pg {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadInput = 2;

void AddParamsCommand(CLI::App& app, int& exitCode);
void AddSenseCommand(CLI::App& app, int& exitCode);
void AddRunCommand(CLI::App& app, int& exitCode);
void AddPlayCommand(CLI::App& app, int& exitCode);
void AddCalibrateCommand(CLI::App& app, int& exitCode);
void AddBenchCommand(CLI::App& app, int& exitCode);
void AddTuneCommand(CLI::App& app, int& exitCode);

}  // namespace pg
