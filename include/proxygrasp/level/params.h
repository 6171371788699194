// Every parameter table of a level in one struct, and the sections that map it onto TOML.
#pragma once

#include "proxygrasp/core/params.h"
#include "proxygrasp/physics/types.h"
#include "proxygrasp/proxies/types.h"
#include "proxygrasp/sensing/depth_sensor.h"
#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tracking/types.h"

#include <string>
#include <vector>

namespace pg {

/// All stage parameters of a level; each member is one TOML table.
struct LevelParams {
  TableParams table;
  PhysicsParams physics;
  ProxyParams proxies;
  SensingParams sensing;
  TrackingParams tracking;
  SyntheticCameraParams camera;
  DepthParams depth;
};

/// The sections of p, in the order docs/levels.md lists them. The sections refer to p.
std::vector<ParamSection> Sections(LevelParams& p);

/// Checks every parameter against its described range, section by section (CheckFields). The
/// first problem is an Error "physics.substeps must be in [1, 64] (got 0)".
MaybeError CheckParams(const LevelParams& p);

/// Every "section.key" whose description says a change needs a new run (Apply::kRestart), in
/// section and description order.
std::vector<std::string> RestartKeys();

/// Sets "section.key" to a value given as text, as `--set section.key=value` does.
MaybeError SetParam(LevelParams& p, const std::string& dottedKey, const std::string& text);

}  // namespace pg
