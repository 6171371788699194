// A level as loaded from its TOML file: parameters, objects, a script of contacts, expectations
// (checked by the run module's Evaluator, run/expectations.h), goals for play, and named parameter
// variants. This module is the file format only; running a level is the run module's (RunLevel,
// run/runner.h). docs/levels.md is the reference of the file format. Loading parses, validates and
// builds; on any error it returns the Error (file:line:col: message) and no Level, so nothing is
// ever half-loaded.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/level/params.h"
#include "proxygrasp/level/script.h"
#include "proxygrasp/physics/types.h"
#include "proxygrasp/proxies/types.h"

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pg {

/// A region of the table: an axis-aligned rectangle or a circle, cm.
struct Region {
  enum class Kind { kRect, kCircle };
  Kind kind = Kind::kRect;
  Vec2 min = Vec2::Zero();     ///< rectangle corner with the smallest x and y, cm
  Vec2 max = Vec2::Zero();     ///< rectangle corner with the largest x and y, cm
  Vec2 center = Vec2::Zero();  ///< circle centre, cm
  double radius = 0.0;         ///< circle radius, cm

  /// True when p (cm) lies inside or on the boundary.
  bool Contains(const Vec2& p) const;
};

/// What an expectation checks.
enum class ExpectKind {
  kPosition,      ///< the object's position lies inside a region
  kRotation,      ///< the object's total signed rotation since the start lies in a range
  kDisplacement,  ///< the distance the object moved from its start is above and/or below a value
  kHeld,          ///< the object is (or is not) held by the contacts
  kResting,       ///< a fraction of a contact's particles rest on an object's top or the table
  kSpeed,         ///< the object's peak speed from the start up to the check stays below a value
};
inline constexpr const char* kExpectKindNames[] = {"position", "rotation", "displacement",
                                                   "held",     "resting",  "speed"};

/// Default fraction of a contact's particles that must rest where a "resting" expectation says.
inline constexpr double kDefaultRestingFraction = 0.8;

/// A condition checked at a time or at the end of a run (run/expectations.h). Angles in radians.
struct Expectation {
  ExpectKind kind = ExpectKind::kPosition;
  std::string object;   ///< position, rotation, displacement, held: the object's name
  std::string contact;  ///< resting: the script contact's name
  std::string on;       ///< resting: an object's name, or "table"
  Region region;        ///< position
  double minAngle = -std::numeric_limits<double>::infinity();  ///< rotation, rad
  double maxAngle = std::numeric_limits<double>::infinity();   ///< rotation, rad
  double above = -std::numeric_limits<double>::infinity();     ///< displacement lower bound, cm
  double below = std::numeric_limits<double>::infinity();      ///< displacement upper bound,
                                                               ///< cm; speed: the bound, cm/s
  bool held = true;                                            ///< held: the state expected
  double fraction = kDefaultRestingFraction;  ///< resting: fraction of particles, 0..1
  std::optional<double> at;                   ///< s; nullopt checks at the end of the run
  std::optional<ProxyMode> mode;              ///< only in runs of this proxy mode
  std::string variant;                        ///< only in runs of this variant; "" the base level
  std::string label;                          ///< free text for reports
  SourceLoc loc;

  /// True when the resting expectation asks for the table rather than an object.
  bool OnTable() const { return on == "table"; }
};

/// A target drawn on the table for play: a zone for an object and/or an angle to turn it to.
struct Goal {
  std::string object;                   ///< the object's name
  std::optional<Region> zone;           ///< where the object's position must be
  std::optional<double> angle;          ///< absolute object angle, rad
  double tolerance = 10.0 * kPi / 180;  ///< allowed angle error, rad
  std::string label;                    ///< text drawn beside the goal
  SourceLoc loc;

  /// True when an object at pose (cm, rad) is in the zone and within tolerance of the angle,
  /// comparing angles modulo a full turn.
  bool IsMet(const Pose2& pose) const;
};

/// A named set of parameter overrides on top of the level's own; expectations may name it.
struct Variant {
  std::string name;
  LevelParams params;  ///< the level's parameters with the variant's overrides applied
  SourceLoc loc;
};

/// A loaded, validated level.
struct Level {
  std::string path;         ///< the file it was loaded from
  std::string name;         ///< `name`, or the file's stem
  std::string description;  ///< `description`, or ""
  LevelParams params;
  std::vector<ObjectSpec> objects;
  Script script;
  std::vector<Expectation> expectations;
  std::vector<Goal> goals;
  std::vector<Variant> variants;
  std::vector<std::string> files;  ///< the level file and every file it includes

  /// The object with this name, or nullptr.
  const ObjectSpec* FindObject(std::string_view objectName) const;
  /// The variant with this name, or nullptr.
  const Variant* FindVariant(std::string_view variantName) const;
};

/// Reads, validates and builds the level in the file at path.
Result<Level> LoadLevel(const std::string& path);

/// The same from text; path names the text in messages and anchors relative includes.
Result<Level> ParseLevel(std::string_view text, const std::string& path);

/// Describes every ObjectSpec key of an [[objects]] entry (angles in degrees).
void DescribeObject(ObjectSpec& o, ParamVisitor& v);

/// Describes the size keys of a [[script.contacts]] entry (shape, radius, ..., pressure).
void DescribeContactShape(ContactShape& c, ParamVisitor& v);

/// The level file's own tables as the loader describes their keys, for docs and listings:
/// "script", "script.contacts" (every shape's keys), "keys" (a keyframe), "variants" (the name),
/// "region" (of positions and goals), "expect" (above and below in cm, as displacement takes them),
/// "expect.rotation" (in degrees) and "goals". Each section describes defaults of its own.
std::vector<ParamSection> FileSections();

/// True when an [[objects]] key is meaningful for the shape (size_x applies to boxes only, ...).
bool ObjectKeyApplies(ObjectShape shape, std::string_view key);

/// True when a contact size key is meaningful for the shape (radius_x applies to ellipses, ...).
bool ContactKeyApplies(ShapeKind shape, std::string_view key);

/// The size keys of an object shape: the described keys that apply to it but not to every shape
/// ("size_x, size_y, height" for a box), as a list for messages.
std::string ObjectSizeKeys(ObjectShape shape);

/// The same for a contact shape ("radius_x, radius_y" for an ellipse).
std::string ContactSizeKeys(ShapeKind shape);

}  // namespace pg
