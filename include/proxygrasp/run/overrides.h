// `--set section.key=value`: the one parser of parameter overrides, shared by `run`, `play`,
// `sense` and the app. The command line wins over the level file, variants included.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/level/params.h"

#include <string>
#include <vector>

namespace pg {

/// One `--set` argument split at its first '=': "physics.substeps=8" -> {"physics.substeps", "8"}.
struct Override {
  std::string key;    ///< "section.key"
  std::string value;  ///< the value as TOML text
};

/// Splits "section.key=value"; an argument without '=' is an Error naming it.
Result<Override> ParseOverride(const std::string& argument);

/// Sets "section.key" from text in the level's parameters and in every variant's. Nothing changes
/// on error.
MaybeError SetLevelParam(Level& level, const std::string& dottedKey, const std::string& text);

/// Applies every `--set` argument in order to the level (and its variants), then the sensing values
/// of the calibration file that sensing.calibration names (ApplyCalibrationSensing), then the
/// `--set` arguments again: --set wins over the calibration file, which wins over the level file.
/// The first bad argument is an Error "--set ARG: message"; the level is left as it was.
MaybeError ApplyOverrides(Level& level, const std::vector<std::string>& arguments);

/// The same for a level's parameters alone (`sense` on a camera has no level).
MaybeError ApplyOverrides(LevelParams& params, const std::vector<std::string>& arguments);

/// Sets the [sensing] values a calibration file holds (its `sensing` map, written by `proxygrasp
/// tune`) when params.sensing.calibration names one; nothing when it is "". An unreadable file or a
/// bad key or value is an Error naming the file and the key; params are left as they were.
MaybeError ApplyCalibrationSensing(LevelParams& params);

}  // namespace pg
