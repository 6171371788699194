// Loader: [[expect]] (expectations the runner checks) and [[goals]] (targets drawn in play).
#include "describe.h"
#include "loader.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace pg::levelfile {

namespace fs = std::filesystem;

// reads an optional region: min + max, or center + radius
MaybeError Loader::ReadRegion(const toml::table& t, bool required, const std::string& what,
                              std::optional<Region>& region) {
  const bool rect = t.contains("min") || t.contains("max");
  const bool circle = t.contains("center") || t.contains("radius");
  if (rect && circle) {
    return MakeError(KeyLoc(t, t.contains("center") ? "center" : "radius"),
                     "give a region as min and max, or as center and radius, not both");
  }
  if (!rect && !circle) {
    if (!required) return std::nullopt;
    return MakeError(Loc(t.source()), what + " needs a region: min and max, or center and radius");
  }
  Region r;
  TableReader reader(t, "");
  DescribeRegion(r, reader);
  const Errors errors = reader.errors;
  Errors missing;
  if (rect) {
    r.kind = Region::Kind::kRect;
    Missing(t, "min", what, missing);
    Missing(t, "max", what, missing);
  } else {
    r.kind = Region::Kind::kCircle;
    Missing(t, "center", what, missing);
    Missing(t, "radius", what, missing);
  }
  if (!errors.empty()) {
    // the earliest in the file
    return *std::min_element(errors.begin(), errors.end(), [](const Error& a, const Error& b) {
      return std::tie(a.loc.line, a.loc.col) < std::tie(b.loc.line, b.loc.col);
    });
  }
  if (!missing.empty()) return missing.front();
  if (rect && !(r.min.x() < r.max.x() && r.min.y() < r.max.y())) {
    return MakeError(ValueLoc(t, "max"), "max " + VecText(r.max) + " must be above min " +
                                             VecText(r.min) + " in both x and y");
  }
  region = r;
  return std::nullopt;
}

MaybeError Loader::CheckObjectName(const toml::table& t, const char* key, const std::string& name,
                                   const Level& level, bool allowTable) {
  if (allowTable && name == "table") return std::nullopt;
  if (level.FindObject(name)) return std::nullopt;
  std::vector<std::string> names;
  for (const ObjectSpec& o : level.objects) names.push_back(o.name);
  if (allowTable) names.emplace_back("table");
  return MakeError(ValueLoc(t, key), "unknown object '" + name + "'" + DidYouMean(name, names));
}

MaybeError Loader::BuildExpectations(const toml::table& root, Level& level) {
  return EachTable(root.get("expect"), "expect", [&](const toml::table& t) -> MaybeError {
    Expectation e;
    if (MaybeError s = ReadExpectation(t, level, e)) return s;
    level.expectations.push_back(std::move(e));
    return std::nullopt;
  });
}

MaybeError Loader::ReadExpectation(const toml::table& t, const Level& level, Expectation& e) {
  e.loc = Loc(t.source());
  // the kind decides which keys belong
  const toml::node* kindNode = t.get("kind");
  if (!kindNode) return MakeError(e.loc, "expectation is missing required key 'kind'");
  {
    TableReader reader(t, "");
    DescribeExpectKind(e.kind, reader);
    if (!reader.errors.empty()) return reader.errors.front();
  }
  const std::string kindName = kExpectKindNames[static_cast<int>(e.kind)];
  const std::string what = "a " + kindName + " expectation";

  // types and ranges; the keys of the kind (a position's region keys too) are known
  ExpectationKeys keys;
  TableReader reader(t, "");
  DescribeExpectation(e, keys, reader);
  std::vector<std::string> known;
  for (const std::string& key : reader.known) {
    if (ExpectKeyApplies(e.kind, key)) known.push_back(key);
  }
  if (e.kind == ExpectKind::kPosition) {
    const std::vector<std::string> region = RegionKeys();
    known.insert(known.end(), region.begin(), region.end());
  }
  const std::vector<std::string> required = e.kind == ExpectKind::kResting
                                                ? std::vector<std::string>{"contact", "on"}
                                                : std::vector<std::string>{"object"};
  Errors errors = reader.errors;
  UnknownKeys(t, known, " in " + what, errors);
  Errors missing;
  for (const std::string& key : required) Missing(t, key.c_str(), what, missing);
  if (MaybeError s = Earliest(errors, missing)) return s;
  if (t.contains("at")) e.at = keys.at;
  if (t.contains("mode")) e.mode = keys.mode;
  if (e.kind == ExpectKind::kRotation && t.contains("above")) e.minAngle = DegToRad(keys.aboveDeg);
  if (e.kind == ExpectKind::kRotation && t.contains("below")) e.maxAngle = DegToRad(keys.belowDeg);

  // kind-specific meaning
  switch (e.kind) {
    case ExpectKind::kPosition: {
      std::optional<Region> region;
      if (MaybeError s = ReadRegion(t, true, what, region)) return s;
      e.region = *region;
      break;
    }
    case ExpectKind::kRotation:
      if (!t.contains("above") && !t.contains("below")) {
        return MakeError(e.loc, what + " needs above, below or both");
      }
      if (t.contains("above") && t.contains("below") && keys.aboveDeg > keys.belowDeg) {
        return MakeError(ValueLoc(t, "below"), "below (" + FormatDouble(keys.belowDeg) +
                                                   " deg) must not be less than above (" +
                                                   FormatDouble(keys.aboveDeg) + " deg)");
      }
      break;
    case ExpectKind::kDisplacement:
      if (!t.contains("above") && !t.contains("below")) {
        return MakeError(e.loc, what + " needs above, below or both");
      }
      if (t.contains("above") && t.contains("below") && e.above >= e.below) {
        return MakeError(ValueLoc(t, "below"), "below (" + FormatDouble(e.below) +
                                                   " cm) must be greater than above (" +
                                                   FormatDouble(e.above) + " cm)");
      }
      break;
    case ExpectKind::kSpeed:
      if (!t.contains("below")) return MakeError(e.loc, what + " needs below");
      break;
    case ExpectKind::kHeld:
      break;
    case ExpectKind::kResting:
      break;
  }

  // names refer to things the level defines
  if (!e.object.empty()) {
    if (MaybeError s = CheckObjectName(t, "object", e.object, level, false)) return s;
  }
  if (e.kind == ExpectKind::kResting) {
    if (MaybeError s = CheckObjectName(t, "on", e.on, level, true)) return s;
    const ScriptContact* contact = nullptr;
    std::vector<std::string> names;
    for (const ScriptContact& c : level.script.contacts) {
      names.push_back(c.name);
      if (c.name == e.contact) contact = &c;
    }
    if (!contact) {
      return MakeError(ValueLoc(t, "contact"),
                       "unknown contact '" + e.contact + "'" + DidYouMean(e.contact, names));
    }
    // particles exist only while the contact does: by default at its last keyframe
    if (!e.at) {
      e.at = contact->End();
    } else if (*e.at < contact->Start() || *e.at > contact->End()) {
      return MakeError(ValueLoc(t, "at"),
                       "at = " + FormatDouble(*e.at) + " s is outside contact '" + contact->name +
                           "', which exists from " + FormatDouble(contact->Start()) + " s to " +
                           FormatDouble(contact->End()) + " s");
    }
  }
  if (!e.variant.empty() && !level.FindVariant(e.variant)) {
    std::vector<std::string> names;
    for (const Variant& v : level.variants) names.push_back(v.name);
    return MakeError(ValueLoc(t, "variant"),
                     "unknown variant '" + e.variant + "'" + DidYouMean(e.variant, names));
  }
  if (e.at && *e.at > level.script.duration) {
    return MakeError(ValueLoc(t, "at"), "at = " + FormatDouble(*e.at) +
                                            " s is after the end of the level at " +
                                            FormatDouble(level.script.duration) + " s");
  }
  return std::nullopt;
}

MaybeError Loader::BuildGoals(const toml::table& root, Level& level) {
  return EachTable(root.get("goals"), "goals", [&](const toml::table& t) -> MaybeError {
    Goal g;
    g.loc = Loc(t.source());
    GoalKeys keys{0.0, RadToDeg(g.tolerance)};
    Errors errors, missing;
    const auto describe = [&g, &keys](TableReader& r) {
      DescribeGoal(g, keys, r);
      const std::vector<std::string> region = RegionKeys();
      r.known.insert(r.known.end(), region.begin(), region.end());
    };
    ReadKeys(t, describe, " in a goal", "goal", {"object"}, errors, missing);
    if (MaybeError s = Earliest(errors, missing)) return s;
    if (MaybeError s = ReadRegion(t, false, "a goal", g.zone)) return s;
    if (t.contains("angle")) g.angle = DegToRad(keys.angleDeg);
    if (t.contains("tolerance") && !g.angle) {
      return MakeError(KeyLoc(t, "tolerance"), "tolerance needs angle");
    }
    g.tolerance = DegToRad(keys.toleranceDeg);
    if (!g.zone && !g.angle) {
      return MakeError(g.loc,
                       "a goal needs a zone (min and max, or center and radius), angle or both");
    }
    if (MaybeError s = CheckObjectName(t, "object", g.object, level, false)) return s;
    level.goals.push_back(std::move(g));
    return std::nullopt;
  });
}

}  // namespace pg::levelfile
