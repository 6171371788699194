#include "proxygrasp/run/plan.h"

#include <cassert>

namespace pg {

namespace {

// the mode a run of the variant (or the base level, "") takes by default
ProxyMode OwnMode(const Level& level, const std::string& variant) {
  const Variant* v = level.FindVariant(variant);
  return v ? v->params.proxies.mode : level.params.proxies.mode;
}

}  // namespace

std::vector<LevelRun> LevelRuns(const Level& level, std::optional<ProxyMode> forcedMode) {
  std::vector<LevelRun> runs;
  auto add = [&runs, forcedMode](const std::string& variant, ProxyMode mode) {
    for (const LevelRun& r : runs) {
      if (r.variant == variant && r.mode == mode) return;
    }
    runs.push_back({variant, mode, forcedMode.has_value()});
  };
  add("", forcedMode.value_or(level.params.proxies.mode));
  for (const Expectation& e : level.expectations) {
    if (forcedMode && e.mode && *e.mode != *forcedMode) continue;
    add(e.variant, forcedMode.value_or(e.mode.value_or(OwnMode(level, e.variant))));
  }
  return runs;
}

LevelParams RunParams(const Level& level, const LevelRun& run) {
  const Variant* v = level.FindVariant(run.variant);
  assert((run.variant.empty() || v) && "a run names a variant the level defines");
  LevelParams params = v ? v->params : level.params;
  params.proxies.mode = run.mode;
  return params;
}

bool AppliesTo(const Expectation& e, const LevelRun& run, const Level& level) {
  if (e.variant != run.variant) return false;
  if (e.mode) return *e.mode == run.mode;
  return run.forcedMode || run.mode == OwnMode(level, e.variant);
}

std::string RunName(const LevelRun& run) {
  return (run.variant.empty() ? std::string("base") : run.variant) + "/" +
         kProxyModeNames[static_cast<int>(run.mode)];
}

}  // namespace pg
