// The keys of the level file's own tables ([script], its contacts and keyframes, regions,
// [[expect]] and [[goals]]), each described once: the loader reads through these descriptions and
// FileSections lists them for docs/levels.md. Private to the level module.
#pragma once

#include "proxygrasp/level/level.h"

#include <string>
#include <string_view>
#include <vector>

namespace pg::levelfile {

/// [script]'s own keys: duration, interpolation and recording.
void DescribeScript(Script& s, ParamVisitor& v);

/// A [[script.contacts]] entry's keys but `keys`: name, interpolation and the shape's.
void DescribeScriptContact(ScriptContact& c, ParamVisitor& v);

/// A keyframe's keys: t, pos and angle (degrees).
void DescribeKeyframe(Keyframe& k, ParamVisitor& v);

/// A [[variants]] entry's own key, its name; its parameter tables are the level's.
void DescribeVariant(Variant& variant, ParamVisitor& v);

/// A region's keys: min and max, or center and radius.
void DescribeRegion(Region& r, ParamVisitor& v);

/// The keys DescribeRegion visits, in its order.
std::vector<std::string> RegionKeys();

/// The values of an [[expect]] entry that the file writes otherwise than Expectation holds them.
struct ExpectationKeys {
  double at = 0.0;  ///< s; the loader sets Expectation::at only when the file gives it
  ProxyMode mode = ProxyMode::kPersistent;  ///< the same for Expectation::mode
  double aboveDeg = 0.0;                    ///< rotation: lower bound, deg
  double belowDeg = 0.0;                    ///< rotation: upper bound, deg
};

/// An [[expect]] entry's kind, which decides the keys that belong.
void DescribeExpectKind(ExpectKind& kind, ParamVisitor& v);

/// True when a key DescribeExpectation visits belongs to an expectation of this kind (held to
/// held expectations, above and below to rotation and displacement, ...).
bool ExpectKeyApplies(ExpectKind kind, std::string_view key);

/// An [[expect]] entry's kind and the keys of every kind but the region's; above and below are in
/// degrees for a rotation (into k) and in cm otherwise (into e).
void DescribeExpectation(Expectation& e, ExpectationKeys& k, ParamVisitor& v);

/// The angles of a [[goals]] entry as the file writes them, in degrees.
struct GoalKeys {
  double angleDeg = 0.0;
  double toleranceDeg = 0.0;
};

/// A [[goals]] entry's keys but the region's.
void DescribeGoal(Goal& g, GoalKeys& k, ParamVisitor& v);

}  // namespace pg::levelfile
