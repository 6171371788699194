// Loader: [[objects]], checked by the physics module (ValidateObject, FootprintBounds).
#include "loader.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/physics/shapes.h"

#include <filesystem>

namespace pg::levelfile {

namespace fs = std::filesystem;

MaybeError Loader::BuildObjects(const toml::table& root, Level& level) {
  return EachTable(root.get("objects"), "objects", [&](const toml::table& t) -> MaybeError {
    ObjectSpec o;
    o.loc = Loc(t.source());
    if (MaybeError s = ReadObject(t, level, o)) return s;
    level.objects.push_back(std::move(o));
    return std::nullopt;
  });
}

MaybeError Loader::ReadObject(const toml::table& t, const Level& level, ObjectSpec& o) {
  // types and ranges of every key, then keys that do not fit the shape
  Errors errors, missing;
  const std::set<std::string> bad = ReadKeys(
      t, [&o](TableReader& r) { DescribeObject(o, r); }, " in an object", "object",
      {"name", "shape", "pos"}, errors, missing);
  const std::string shapeName = kObjectShapeNames[static_cast<int>(o.shape)];
  if (t.contains("shape") && !bad.count("shape")) {
    CheckShapeKeys(
        t, [&o](std::string_view key) { return ObjectKeyApplies(o.shape, key); }, shapeName,
        shapeName + " object", ObjectSizeKeys(o.shape), errors, missing);
  }
  if (MaybeError s = Earliest(errors, missing)) return s;

  // meaning: a unique name, a valid outline, consistent friction and mass, on the table
  if (o.name.empty()) return MakeError(ValueLoc(t, "name"), "name must not be empty");
  if (const ObjectSpec* first = level.FindObject(o.name)) {
    return MakeError(ValueLoc(t, "name"), "duplicate object name '" + o.name +
                                              "' (first defined at " + first->loc.Format() + ")");
  }
  if (t.contains("mass") && t.contains("density")) {
    return MakeError(KeyLoc(t, "density"), "give either mass or density, not both");
  }
  // the physics module's own checks of the shape, mass and friction, at the key they are about
  std::string field;
  if (MaybeError s = ValidateObject(o, level.params.physics, &field)) {
    const bool atKey = t.contains(field);
    return MakeError(atKey ? ValueLoc(t, field) : Loc(t.source()), s->message);
  }
  // the whole footprint, not just the centre, must be on the table
  const TableParams& table = level.params.table;
  const auto [low, high] = FootprintBounds(o);
  if (low.x() < 0 || low.y() < 0 || high.x() > table.width || high.y() > table.height) {
    return MakeError(ValueLoc(t, "pos"),
                     "object '" + o.name + "' reaches off the table: its footprint spans " +
                         Span(low.x(), high.x()) + " x " + Span(low.y(), high.y()) +
                         " cm, the table [0, " + FormatDouble(table.width) + "] x [0, " +
                         FormatDouble(table.height) + "] cm");
  }
  return std::nullopt;
}

}  // namespace pg::levelfile
