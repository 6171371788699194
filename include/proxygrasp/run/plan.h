// Run planning: which runs a level's expectations need (the base level and its variants, each in
// a proxy mode), the parameters of each run, and which expectations each run checks.
#pragma once

#include "proxygrasp/level/level.h"

#include <optional>
#include <string>
#include <vector>

namespace pg {

/// One run of a level: its base parameters or a variant's, in one proxy mode.
struct LevelRun {
  std::string variant;  ///< "" the base level
  ProxyMode mode = ProxyMode::kPersistent;
  bool forcedMode = false;  ///< the mode was forced (the runner's --mode) for every run
};

/// The runs a level's expectations need: the base level in its own mode first, then every other
/// (variant, mode) pair some expectation names, in order of first mention. With forcedMode (the
/// runner's --mode) every run uses that mode and expectations naming another mode are left out.
std::vector<LevelRun> LevelRuns(const Level& level,
                                std::optional<ProxyMode> forcedMode = std::nullopt);

/// The parameters of a run: the variant's (or the level's) with proxies.mode set to run.mode.
LevelParams RunParams(const Level& level, const LevelRun& run);

/// True when expectation e is checked in run: same variant, and the run's mode is the one e names;
/// an expectation naming no mode is checked in its variant's own mode, or in a forced mode.
bool AppliesTo(const Expectation& e, const LevelRun& run, const Level& level);

/// The run's name in reports and trace folders: "base" or the variant, then the mode
/// ("base/persistent").
std::string RunName(const LevelRun& run);

}  // namespace pg
