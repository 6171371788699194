// The keys of every level table but the parameter tables ([[objects]], [script], its contacts and
// keyframes, regions, [[expect]], [[goals]]), described through the same reflection as the
// parameter tables, so the loader's checks and docs/levels.md come from one place.
#include "describe.h"

#include "proxygrasp/core/units.h"

#include <algorithm>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <string>

namespace pg {

namespace {

bool OneOf(ObjectShape s, std::initializer_list<ObjectShape> shapes) {
  return std::find(shapes.begin(), shapes.end(), s) != shapes.end();
}

bool OneOf(ShapeKind s, std::initializer_list<ShapeKind> shapes) {
  return std::find(shapes.begin(), shapes.end(), s) != shapes.end();
}

// the described keys that apply to `shape` but not to every shape, joined with ", "
template <typename Shape, typename Spec, typename Applies, typename DescribeFn>
std::string SizeKeys(Shape shape, int shapes, Spec spec, Applies applies, DescribeFn describe) {
  const ParamSection section{"", [&spec, describe](ParamVisitor& v) { describe(spec, v); }};
  std::string keys;
  for (const FieldInfo& f : ListFields(section)) {
    if (!applies(shape, f.key)) continue;
    bool everywhere = true;
    for (int s = 0; s < shapes; ++s)
      everywhere = everywhere && applies(static_cast<Shape>(s), f.key);
    if (!everywhere) keys += (keys.empty() ? "" : ", ") + f.key;
  }
  return keys;
}

// a section that describes its own copy of value
template <typename T, typename DescribeFn>
ParamSection Owned(std::string name, T value, DescribeFn describe) {
  auto owned = std::make_shared<T>(std::move(value));
  return {std::move(name), [owned, describe](ParamVisitor& v) { describe(*owned, v); }};
}

}  // namespace

void DescribeObject(ObjectSpec& o, ParamVisitor& v) {
  v.Text("name", o.name, "unique name, used by expectations and goals (required)");
  VisitEnum(v, "shape", o.shape, kObjectShapeNames, "the solid (required)");
  v.Real("size_x", o.sizeX, 0.1, 200, "cm", "box: width along local x");
  v.Real("size_y", o.sizeY, 0.1, 200, "cm", "box: depth along local y");
  v.Real("radius", o.radius, 0.1, 100, "cm", "cylinder, sphere: radius; frustum: bottom radius");
  v.Real("top_radius", o.topRadius, 0, 100, "cm", "frustum: top radius (0 makes a cone)");
  v.Real("patch_radius", o.patchRadius, 0, 100, "cm",
         "sphere: radius of its contact patch on the table, at most its radius; table friction "
         "resists its spin over the patch (0: a point that spins freely)");
  v.Real("height", o.height, 0.1, 100, "cm", "box, cylinder, frustum, prisms: height");
  v.Points("points", o.points, -100, 100, "cm",
           "prisms: outline in the local frame, any winding (required for prisms)");
  v.Real("mass", o.mass, 0, 1e6, "g", "mass; 0 computes it from the density");
  v.Real("density", o.density, 0.001, 100, "g/cm^3", "density, used when mass is 0");
  v.Real("particle_friction", o.particleFriction, -1, 10, "1",
         "friction against particles; < 0 uses [physics] particle_friction");
  v.Real("table_static", o.tableStatic, 0, 10, "1", "static friction against the table");
  v.Real("table_kinetic", o.tableKinetic, 0, 10, "1",
         "kinetic friction against the table, at most table_static");
  v.Real("object_friction", o.objectFriction, 0, 10, "1", "friction against objects and walls");
  v.Real("restitution", o.restitution, 0, 1, "1", "bounciness");
  v.Vector("pos", o.pose.pos, -1000, 1000, "cm",
           "starting position on the table (required; the footprint must lie on the table)");
  v.Angle("angle", o.pose.angle, -360, 360, "deg", "starting angle, counter-clockwise");
  v.Vector("velocity", o.velocity, -10000, 10000, "cm/s", "starting velocity");
  v.Angle("angular_velocity", o.angularVelocity, -36000, 36000, "deg/s",
          "starting angular velocity, counter-clockwise");
}

void DescribeContactShape(ContactShape& c, ParamVisitor& v) {
  VisitEnum(v, "shape", c.kind, kShapeKindNames, "the shape the table camera sees (required)");
  v.Real("radius", c.radius, 0.05, 20, "cm", "circle, capsule: radius");
  v.Real("radius_x", c.radiusX, 0.05, 50, "cm", "ellipse: semi-axis along local x");
  v.Real("radius_y", c.radiusY, 0.05, 50, "cm", "ellipse: semi-axis along local y");
  v.Real("length", c.length, 0, 100, "cm", "capsule: length between the cap centres, along x");
  v.Real("scale", c.scale, 0.1, 5, "1", "hands: size; 1 is an adult hand about 19 cm long");
  v.Points("points", c.points, -100, 100, "cm",
           "convex, concave: outline in the local frame, any winding (required)");
  v.Real("pressure", c.pressure, 0, 1, "1", "brightness of the contact, fraction of full contact");
}

bool ObjectKeyApplies(ObjectShape shape, std::string_view key) {
  using S = ObjectShape;
  if (key == "size_x" || key == "size_y") return shape == S::kBox;
  if (key == "radius") return OneOf(shape, {S::kCylinder, S::kSphere, S::kFrustum});
  if (key == "top_radius") return shape == S::kFrustum;
  if (key == "patch_radius") return shape == S::kSphere;
  if (key == "height") return shape != S::kSphere;
  if (key == "points") return OneOf(shape, {S::kConvexPrism, S::kConcavePrism});
  return true;
}

bool ContactKeyApplies(ShapeKind shape, std::string_view key) {
  using S = ShapeKind;
  if (key == "radius") return OneOf(shape, {S::kCircle, S::kCapsule});
  if (key == "radius_x" || key == "radius_y") return shape == S::kEllipse;
  if (key == "length") return shape == S::kCapsule;
  if (key == "scale") return OneOf(shape, {S::kHandFive, S::kHandFlat, S::kHandCupped});
  if (key == "points") return OneOf(shape, {S::kConvexPolygon, S::kConcavePolygon});
  return true;
}

namespace levelfile {

void DescribeScript(Script& s, ParamVisitor& v) {
  v.Real("duration", s.duration, 0.01, 3600, "s",
         "length of the level; default: the last keyframe plus 1 s");
  VisitEnum(v, "interpolation", s.interpolation, kInterpolationNames,
            "how contacts move between keyframes");
  v.Text("recording", s.recording,
         "a recorded video that replaces the contacts, relative to this file");
  v.Text("tuio", s.tuio,
         "a recorded TUIO stream (touchlib XML) whose contacts replace the script's, relative to "
         "this file");
}

void DescribeScriptContact(ScriptContact& c, ParamVisitor& v) {
  v.Text("name", c.name, "unique name, used by resting expectations (required)");
  VisitEnum(v, "interpolation", c.interpolation, kInterpolationNames,
            "how contacts move between keyframes");
  DescribeContactShape(c.shape, v);
}

void DescribeKeyframe(Keyframe& k, ParamVisitor& v) {
  v.Real("t", k.t, 0, 3600, "s", "time of the keyframe from the start of the level (required)");
  v.Vector("pos", k.pose.pos, -1000, 1000, "cm",
           "position of the contact's centre on the table (required)");
  v.Angle("angle", k.pose.angle, -36000, 36000, "deg",
          "the contact's angle, counter-clockwise; not wrapped");
  v.Real("height", k.height, 0, 100, "cm",
         "from the table to the contact's underside (0 = touching); the depth camera sees it, "
         "the IR camera dims the contact");
}

void DescribeVariant(Variant& variant, ParamVisitor& v) {
  v.Text("name", variant.name, "the variant's name, used by expectations (required)");
}

void DescribeRegion(Region& r, ParamVisitor& v) {
  v.Vector("min", r.min, -1000, 1000, "cm",
           "region: the rectangle corner with the smallest x and y");
  v.Vector("max", r.max, -1000, 1000, "cm",
           "region: the rectangle corner with the largest x and y");
  v.Vector("center", r.center, -1000, 1000, "cm", "region: the circle's centre");
  v.Real("radius", r.radius, 0.001, 1000, "cm", "region: the circle's radius");
}

std::vector<std::string> RegionKeys() {
  Region r;
  std::vector<std::string> keys;
  for (const FieldInfo& f : ListFields({"region", [&r](ParamVisitor& v) { DescribeRegion(r, v); }}))
    keys.push_back(f.key);
  return keys;
}

void DescribeExpectKind(ExpectKind& kind, ParamVisitor& v) {
  VisitEnum(v, "kind", kind, kExpectKindNames, "what the expectation checks (required)");
}

bool ExpectKeyApplies(ExpectKind kind, std::string_view key) {
  using K = ExpectKind;
  if (key == "object") return kind != K::kResting;
  if (key == "contact" || key == "on" || key == "fraction") return kind == K::kResting;
  if (key == "above") return kind == K::kRotation || kind == K::kDisplacement;
  if (key == "below") {
    return kind == K::kRotation || kind == K::kDisplacement || kind == K::kSpeed;
  }
  if (key == "held") return kind == K::kHeld;
  return true;
}

void DescribeExpectation(Expectation& e, ExpectationKeys& k, ParamVisitor& v) {
  DescribeExpectKind(e.kind, v);
  v.Real("at", k.at, 0, 3600, "s",
         "time of the check from the start of the level; default: the end of the run "
         "(resting: the contact's last keyframe)");
  VisitEnum(v, "mode", k.mode, kProxyModeNames, "check only in runs of this proxy mode");
  v.Text("variant", e.variant, "check only in runs of this variant; default: the base level");
  v.Text("label", e.label, "free text shown beside the result");
  v.Text("object", e.object, "the object's name");
  v.Text("contact", e.contact, "resting: the script contact's name");
  v.Text("on", e.on, "resting: an object's name, or \"table\"");
  if (e.kind == ExpectKind::kRotation) {
    v.Real("above", k.aboveDeg, -36000, 36000, "deg",
           "rotation: lower bound of the total signed rotation since the start");
    v.Real("below", k.belowDeg, -36000, 36000, "deg",
           "rotation: upper bound of the total signed rotation since the start");
  } else if (e.kind == ExpectKind::kSpeed) {
    v.Real("below", e.below, 0, 100000, "cm/s",
           "speed: the object's centre of mass stays slower than this, every frame from the start "
           "to the check");
  } else {
    v.Real("above", e.above, 0, 10000, "cm",
           "displacement: lower bound of the distance moved from the start");
    v.Real("below", e.below, 0, 10000, "cm",
           "displacement: upper bound of the distance moved from the start");
  }
  v.Boolean("held", e.held, "held: whether the object must be held (true) or not (false)");
  v.Real("fraction", e.fraction, 0.01, 1, "1",
         "resting: the smallest fraction of the contact's particles that must rest there");
}

void DescribeGoal(Goal& g, GoalKeys& k, ParamVisitor& v) {
  v.Text("object", g.object, "the object's name");
  v.Text("label", g.label, "text drawn beside the goal");
  v.Real("angle", k.angleDeg, -360, 360, "deg",
         "the object's absolute angle to reach, compared modulo 360");
  v.Real("tolerance", k.toleranceDeg, 0, 180, "deg", "allowed angle error; only with angle");
}

}  // namespace levelfile

std::vector<ParamSection> FileSections() {
  struct ExpectationEntry {
    Expectation e;
    levelfile::ExpectationKeys k;
  };
  Expectation rotation;
  rotation.kind = ExpectKind::kRotation;
  const auto describeExpectation = [](ExpectationEntry& x, ParamVisitor& v) {
    levelfile::DescribeExpectation(x.e, x.k, v);
  };
  struct GoalEntry {
    Goal g;
    levelfile::GoalKeys k{0.0, RadToDeg(Goal{}.tolerance)};
  };
  return {
      Owned("script", Script{}, levelfile::DescribeScript),
      Owned("script.contacts", ScriptContact{}, levelfile::DescribeScriptContact),
      Owned("keys", Keyframe{}, levelfile::DescribeKeyframe),
      Owned("variants", Variant{}, levelfile::DescribeVariant),
      Owned("region", Region{}, levelfile::DescribeRegion),
      Owned("expect", ExpectationEntry{}, describeExpectation),
      Owned("expect.rotation", ExpectationEntry{rotation, {}}, describeExpectation),
      Owned("goals", GoalEntry{},
            [](GoalEntry& x, ParamVisitor& v) { levelfile::DescribeGoal(x.g, x.k, v); }),
  };
}

std::string ObjectSizeKeys(ObjectShape shape) {
  return SizeKeys(shape, static_cast<int>(std::size(kObjectShapeNames)), ObjectSpec{},
                  ObjectKeyApplies, DescribeObject);
}

std::string ContactSizeKeys(ShapeKind shape) {
  return SizeKeys(shape, static_cast<int>(std::size(kShapeKindNames)), ContactShape{},
                  ContactKeyApplies, DescribeContactShape);
}

}  // namespace pg
