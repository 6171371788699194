#include "proxygrasp/run/overrides.h"

#include "proxygrasp/sensing/calibration.h"

#include <cassert>

namespace pg {

namespace {

// an error of one argument reads "--set ARG: message" and keeps no location of its own
Error ArgumentError(const std::string& argument, const std::string& message) {
  return MakeError({}, "--set " + argument + ": " + message);
}

// applies each argument through set(key, value) to a copy, and keeps the copy only when all pass
template <typename T, typename SetFn>
MaybeError ApplyAll(T& target, const std::vector<std::string>& arguments, SetFn set) {
  T probe = target;
  for (const std::string& argument : arguments) {
    Result<Override> o = ParseOverride(argument);
    if (!o.ok()) return o.error();
    if (MaybeError s = set(probe, o.value().key, o.value().value)) {
      return ArgumentError(argument, s->Format());
    }
  }
  target = std::move(probe);
  return std::nullopt;
}

}  // namespace

Result<Override> ParseOverride(const std::string& argument) {
  const size_t eq = argument.find('=');
  if (eq == std::string::npos) return ArgumentError(argument, "expected section.key=value");
  return Override{argument.substr(0, eq), argument.substr(eq + 1)};
}

MaybeError SetLevelParam(Level& level, const std::string& dottedKey, const std::string& text) {
  // check on a copy first so an error leaves every parameter set as it was
  LevelParams probe = level.params;
  if (MaybeError s = SetParam(probe, dottedKey, text)) return s;
  level.params = probe;
  for (Variant& v : level.variants) {
    const MaybeError s = SetParam(v.params, dottedKey, text);
    assert(!s && "a key valid for the level is valid for its variants");
    (void)s;
  }
  return std::nullopt;
}

MaybeError ApplyCalibrationSensing(LevelParams& params) {
  const std::string path = params.sensing.calibration;
  if (path.empty()) return std::nullopt;
  Result<Calibration> calibration = LoadCalibration(path);
  if (!calibration) return calibration.error();
  LevelParams probe = params;
  for (const auto& [key, text] : calibration.value().sensing) {
    if (key == "calibration")
      return MakeError({path}, "field 'sensing.calibration': a calibration cannot name another");
    if (MaybeError s = SetParam(probe, "sensing." + key, text))
      return MakeError({path}, "field 'sensing." + key + "': " + s->message);
  }
  params = std::move(probe);
  return std::nullopt;
}

MaybeError ApplyOverrides(Level& level, const std::vector<std::string>& arguments) {
  Level probe = level;
  if (MaybeError s = ApplyAll(probe, arguments, SetLevelParam)) return s;
  // the calibration's sensing values, in the level and in every variant (which may name another
  // calibration), then --set again so that it wins
  if (MaybeError s = ApplyCalibrationSensing(probe.params)) return s;
  for (Variant& v : probe.variants) {
    if (MaybeError s = ApplyCalibrationSensing(v.params)) return s;
  }
  if (MaybeError s = ApplyAll(probe, arguments, SetLevelParam)) return s;
  level = std::move(probe);
  return std::nullopt;
}

MaybeError ApplyOverrides(LevelParams& params, const std::vector<std::string>& arguments) {
  LevelParams probe = params;
  if (MaybeError s = ApplyAll(probe, arguments, SetParam)) return s;
  if (MaybeError s = ApplyCalibrationSensing(probe)) return s;
  if (MaybeError s = ApplyAll(probe, arguments, SetParam)) return s;
  params = std::move(probe);
  return std::nullopt;
}

}  // namespace pg
