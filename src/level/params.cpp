#include "proxygrasp/level/params.h"

#include "proxygrasp/core/text.h"

namespace pg {

std::vector<ParamSection> Sections(LevelParams& p) {
  return {
      {"table", [&p](ParamVisitor& v) { Describe(p.table, v); }},
      {"physics", [&p](ParamVisitor& v) { Describe(p.physics, v); }},
      {"proxies", [&p](ParamVisitor& v) { Describe(p.proxies, v); }},
      {"sensing", [&p](ParamVisitor& v) { Describe(p.sensing, v); }},
      {"tracking", [&p](ParamVisitor& v) { Describe(p.tracking, v); }},
      {"camera", [&p](ParamVisitor& v) { Describe(p.camera, v); }},
      {"depth", [&p](ParamVisitor& v) { Describe(p.depth, v); }},
  };
}

MaybeError CheckParams(const LevelParams& p) {
  // the sections refer to their struct: describe a copy
  LevelParams copy = p;
  for (const ParamSection& s : Sections(copy)) {
    if (MaybeError bad = CheckFields(s)) return bad;
  }
  return std::nullopt;
}

std::vector<std::string> RestartKeys() {
  LevelParams defaults;
  std::vector<std::string> keys;
  for (const ParamSection& s : Sections(defaults)) {
    for (const FieldInfo& f : ListFields(s)) {
      if (f.apply == Apply::kRestart) keys.push_back(s.name + "." + f.key);
    }
  }
  return keys;
}

MaybeError SetParam(LevelParams& p, const std::string& dottedKey, const std::string& text) {
  const size_t dot = dottedKey.find('.');
  if (dot == std::string::npos) {
    return MakeError({}, "'" + dottedKey + "' must be section.key, e.g. physics.substeps");
  }
  const std::string section = dottedKey.substr(0, dot);
  const std::string key = dottedKey.substr(dot + 1);
  std::vector<std::string> names;
  for (const ParamSection& s : Sections(p)) {
    if (s.name == section) return SetFieldFromText(s, key, text);
    names.push_back(s.name);
  }
  return MakeError({}, "unknown section '" + section + "'" + DidYouMean(section, names));
}

}  // namespace pg
