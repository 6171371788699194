#include "proxygrasp/level/level.h"

#include "proxygrasp/core/units.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace pg {
namespace {

using ::testing::HasSubstr;

const std::string kData = PROXYGRASP_TESTDATA_DIR;

// the formatted error of loading text as "inline.toml", or "(loaded)" when it loads
std::string ErrorOf(std::string_view text) {
  const Result<Level> r = ParseLevel(text, "inline.toml");
  return r.ok() ? std::string("(loaded)") : r.error().Format();
}

// a valid object to put in front of a snippet that needs one
constexpr const char* kBox = R"(
[[objects]]
name = "box"
shape = "box"
pos = [30, 20]
)";

std::vector<std::string> Values(const ParamSection& s) {
  std::vector<std::string> values;
  for (const FieldInfo& f : ListFields(s)) values.push_back(f.key + "=" + f.value);
  return values;
}

TEST(Level, LoadsEveryPartOfACompleteLevel) {
  const Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const Level& level = r.value();
  EXPECT_EQ(level.name, "Grasp and turn");
  EXPECT_EQ(level.description, "Two fingers grasp the box from its sides and turn it in place.");
  EXPECT_EQ(level.path, kData + "/complete.toml");
  EXPECT_EQ(level.files, std::vector<std::string>{kData + "/complete.toml"});

  // parameters: the level's values, the code's defaults elsewhere
  EXPECT_EQ(level.params.physics.stackSize, 3);
  EXPECT_EQ(level.params.physics.particleFriction, 1.2);
  EXPECT_EQ(level.params.physics.layers, PhysicsParams{}.layers);

  // objects, angles converted to radians
  ASSERT_EQ(level.objects.size(), 3u);
  const ObjectSpec& box = level.objects[0];
  EXPECT_EQ(box.name, "box");
  EXPECT_EQ(box.shape, ObjectShape::kBox);
  EXPECT_EQ(box.sizeX, 6);
  EXPECT_EQ(box.sizeY, 4);
  EXPECT_EQ(box.height, 3);
  EXPECT_EQ(box.mass, 80);
  EXPECT_EQ(box.tableStatic, 0.5);
  EXPECT_EQ(box.tableKinetic, 0.4);
  EXPECT_EQ(box.pose.pos, Vec2(30, 23));
  EXPECT_DOUBLE_EQ(box.pose.angle, 0.5 * kPi);
  EXPECT_EQ(box.loc.Format(), kData + "/complete.toml:12:1");
  const ObjectSpec& puck = level.objects[1];
  EXPECT_EQ(puck.shape, ObjectShape::kCylinder);
  EXPECT_EQ(puck.radius, 2.5);
  EXPECT_EQ(puck.density, 1.5);
  EXPECT_EQ(puck.velocity, Vec2(5, -2));
  EXPECT_DOUBLE_EQ(puck.angularVelocity, kPi);
  const ObjectSpec& wedge = level.objects[2];
  EXPECT_EQ(wedge.shape, ObjectShape::kConvexPrism);
  ASSERT_EQ(wedge.points.size(), 3u);
  EXPECT_EQ(wedge.points[1], Vec2(4, 0));
  EXPECT_EQ(wedge.particleFriction, 0.3);

  // script: duration defaults to the last keyframe plus the settle time
  const Script& script = level.script;
  EXPECT_EQ(script.interpolation, Interpolation::kSmooth);
  EXPECT_DOUBLE_EQ(script.duration, 2.0 + kScriptSettleTime);
  ASSERT_EQ(script.contacts.size(), 2u);
  const ScriptContact& thumb = script.contacts[0];
  EXPECT_EQ(thumb.name, "thumb");
  EXPECT_EQ(thumb.shape.kind, ShapeKind::kCircle);
  EXPECT_EQ(thumb.shape.radius, 0.9);
  EXPECT_EQ(thumb.interpolation, Interpolation::kSmooth);
  ASSERT_EQ(thumb.keys.size(), 3u);
  EXPECT_EQ(thumb.keys[1].t, 1.0);
  EXPECT_EQ(thumb.keys[1].pose.pos, Vec2(26.5, 23));
  EXPECT_EQ(thumb.keys[1].pose.angle, 0.0);
  EXPECT_DOUBLE_EQ(thumb.keys[2].pose.angle, 0.25 * kPi);
  EXPECT_EQ(thumb.keys[1].loc.Format(), kData + "/complete.toml:51:3");
  const ScriptContact& index = script.contacts[1];
  EXPECT_EQ(index.shape.kind, ShapeKind::kEllipse);
  EXPECT_EQ(index.shape.radiusX, 1.1);
  EXPECT_EQ(index.shape.radiusY, 0.7);
  EXPECT_EQ(index.shape.pressure, 0.9);
  EXPECT_EQ(index.interpolation, Interpolation::kLinear);
  EXPECT_DOUBLE_EQ(index.keys[0].pose.angle, -kPi / 6);

  // variants carry the level's parameters with their overrides
  ASSERT_EQ(level.variants.size(), 1u);
  EXPECT_EQ(level.variants[0].name, "single");
  EXPECT_EQ(level.variants[0].params.physics.stackSize, 1);
  EXPECT_EQ(level.variants[0].params.physics.particleFriction, 1.2);

  // expectations
  ASSERT_EQ(level.expectations.size(), 5u);
  const Expectation& turn = level.expectations[0];
  EXPECT_EQ(turn.kind, ExpectKind::kRotation);
  EXPECT_EQ(turn.object, "box");
  EXPECT_DOUBLE_EQ(turn.minAngle, kPi / 6);
  EXPECT_DOUBLE_EQ(turn.maxAngle, kPi / 3);
  EXPECT_FALSE(turn.at.has_value());
  EXPECT_FALSE(turn.mode.has_value());
  EXPECT_EQ(turn.label, "the box turns");
  const Expectation& position = level.expectations[1];
  EXPECT_EQ(position.region.kind, Region::Kind::kCircle);
  EXPECT_EQ(position.region.center, Vec2(30, 23));
  EXPECT_EQ(position.region.radius, 1.5);
  EXPECT_EQ(position.at, 2.0);
  const Expectation& moved = level.expectations[2];
  EXPECT_EQ(moved.kind, ExpectKind::kDisplacement);
  EXPECT_EQ(moved.above, 0.5);
  EXPECT_TRUE(std::isinf(moved.below));
  const Expectation& held = level.expectations[3];
  EXPECT_EQ(held.kind, ExpectKind::kHeld);
  EXPECT_FALSE(held.held);
  EXPECT_EQ(held.mode, ProxyMode::kInstant);
  const Expectation& resting = level.expectations[4];
  EXPECT_EQ(resting.kind, ExpectKind::kResting);
  EXPECT_EQ(resting.contact, "thumb");
  EXPECT_TRUE(resting.OnTable());
  EXPECT_EQ(resting.fraction, kDefaultRestingFraction);
  EXPECT_EQ(resting.at, 2.0) << "a resting check defaults to the contact's last keyframe";
  EXPECT_EQ(resting.variant, "single");

  // goals
  ASSERT_EQ(level.goals.size(), 2u);
  ASSERT_TRUE(level.goals[0].zone.has_value());
  EXPECT_EQ(level.goals[0].zone->kind, Region::Kind::kRect);
  EXPECT_EQ(level.goals[0].zone->min, Vec2(40, 5));
  EXPECT_EQ(level.goals[0].zone->max, Vec2(55, 15));
  EXPECT_DOUBLE_EQ(*level.goals[0].angle, 0.5 * kPi);
  EXPECT_DOUBLE_EQ(level.goals[0].tolerance, DegToRad(5));
  EXPECT_EQ(level.goals[0].label, "put the box here, turned");
  EXPECT_FALSE(level.goals[1].angle.has_value());
  EXPECT_EQ(level.goals[1].zone->kind, Region::Kind::kCircle);
}

TEST(Level, DefaultsComeFromTheCode) {
  const Result<Level> r = ParseLevel(kBox, "inline.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  Level level = r.value();
  EXPECT_EQ(level.name, "inline") << "the name defaults to the file's stem";
  LevelParams defaults;
  const auto loaded = Sections(level.params);
  const auto expected = Sections(defaults);
  for (size_t i = 0; i < loaded.size(); ++i) {
    EXPECT_EQ(Values(loaded[i]), Values(expected[i])) << loaded[i].name;
  }
  ObjectSpec object = level.objects[0];
  ObjectSpec defaultObject;
  defaultObject.name = "box";
  defaultObject.pose.pos = Vec2(30, 20);
  EXPECT_EQ(Values({"o", [&](ParamVisitor& v) { DescribeObject(object, v); }}),
            Values({"o", [&](ParamVisitor& v) { DescribeObject(defaultObject, v); }}));
  EXPECT_EQ(level.script.duration, kScriptSettleTime);
  EXPECT_TRUE(level.script.contacts.empty());
}

TEST(Level, AnEmptyFileIsAValidLevel) {
  const Result<Level> r = ParseLevel("", "empty.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_TRUE(r.value().objects.empty());
}

// ---- syntax ----

TEST(LevelErrors, SyntaxErrorHasTheParsersLocation) {
  const std::string e = ErrorOf("name = \"x\"\n[physics]\nsubsteps = = 4\n");
  EXPECT_THAT(e, HasSubstr("inline.toml:3:12: "));
  EXPECT_THAT(e, HasSubstr("could not determine value type"));
}

TEST(LevelErrors, RedefinedTableIsASyntaxError) {
  EXPECT_THAT(ErrorOf("[physics]\nlayers = 2\n[physics]\n"),
              HasSubstr("inline.toml:3:1: Error while parsing table header: cannot redefine "
                        "existing table 'physics'"));
}

// ---- unknown keys, with did-you-mean ----

TEST(LevelErrors, UnknownTopLevelKey) {
  EXPECT_EQ(ErrorOf("name = \"x\"\n[physic]\nlayers = 2\n"),
            "inline.toml:2:2: unknown key 'physic' (did you mean 'physics'?)");
  EXPECT_EQ(ErrorOf("\n[[object]]\nname = \"a\"\n"),
            "inline.toml:2:3: unknown key 'object' (did you mean 'objects'?)");
}

TEST(LevelErrors, UnknownParameterKey) {
  EXPECT_EQ(ErrorOf("[physics]\nlayers = 2\nsubstep = 4\n"),
            "inline.toml:3:1: unknown key 'substep' in [physics] (did you mean 'substeps'?)");
  EXPECT_EQ(ErrorOf("[camera]\nzzz = 4\n"), "inline.toml:2:1: unknown key 'zzz' in [camera]");
}

TEST(LevelErrors, UnknownObjectKey) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nfriction = 0.2\n"),
            "inline.toml:4:1: unknown key 'friction' in an object");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nresitution = 0.2\n"),
            "inline.toml:4:1: unknown key 'resitution' in an object (did you mean "
            "'restitution'?)");
}

TEST(LevelErrors, UnknownScriptContactAndKeyframeKeys) {
  EXPECT_EQ(ErrorOf("[script]\nduraton = 3\n"),
            "inline.toml:2:1: unknown key 'duraton' in [script] (did you mean 'duration'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nradus = 1\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:1: unknown key 'radus' in a contact (did you mean 'radius'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1], angel = 3}]\n"),
            "inline.toml:4:31: unknown key 'angel' in a keyframe (did you mean 'angle'?)");
}

TEST(LevelErrors, UnknownExpectationGoalAndVariantKeys) {
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nhel = true\n"),
      "inline.toml:9:1: unknown key 'hel' in a held expectation (did you mean 'held'?)");
  // keys of earlier versions of the format name their new names
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nvalue = true\n"),
      "inline.toml:9:1: unknown key 'value' in a held expectation (did you mean 'held'? 'value' "
      "was renamed)");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\nmin_deg = 10\n"),
            "inline.toml:9:1: unknown key 'min_deg' in a rotation expectation (did you mean "
            "'above'? 'min_deg' was renamed)");
  // a key of another kind is unknown in this one
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nabove = 1\n"),
      "inline.toml:9:1: unknown key 'above' in a held expectation");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"box\"\nangle_deg = 90\n"),
            "inline.toml:8:1: unknown key 'angle_deg' in a goal (did you mean 'angle'? 'angle_deg' "
            "was renamed)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[variants.physics]\nlayer = 2\n"),
            "inline.toml:4:1: unknown key 'layer' in [variants.physics] (did you mean 'layers'?)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[variants.physic]\nlayers = 2\n"),
            "inline.toml:3:11: unknown key 'physic' in a variant (did you mean 'physics'?)");
}

// ---- wrong types name the expected type ----

TEST(LevelErrors, WrongTypes) {
  EXPECT_EQ(ErrorOf("[physics]\nsubsteps = \"4\"\n"),
            "inline.toml:2:12: physics.substeps must be an integer, got a string");
  EXPECT_EQ(ErrorOf("[physics]\nsubsteps = 4.5\n"),
            "inline.toml:2:12: physics.substeps must be an integer, got a floating-point number");
  EXPECT_EQ(ErrorOf("[physics]\ncapsule = 1\n"),
            "inline.toml:2:11: physics.capsule must be true or false, got an integer");
  EXPECT_EQ(ErrorOf("[proxies]\nmode = 1\n"),
            "inline.toml:2:8: proxies.mode must be one of persistent, instant, got an integer");
  EXPECT_EQ(ErrorOf("[sensing]\ncalibration = 3\n"),
            "inline.toml:2:15: sensing.calibration must be a string, got an integer");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = \"heavy\"\n"),
            "inline.toml:4:8: mass must be a number, got a string");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [1, 2, 3]\n"),
            "inline.toml:4:7: pos must be an array of two numbers [x, y]");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [1, 0], 5]\n"),
            "inline.toml:4:27: points must be an array of points [[x, y], ...]");
  EXPECT_EQ(ErrorOf("physics = 3\n"),
            "inline.toml:1:11: physics must be a table [physics], got an integer");
  EXPECT_EQ(ErrorOf("name = 3\n"), "inline.toml:1:8: name must be a string, got an integer");
  EXPECT_EQ(ErrorOf("[objects]\nname = \"a\"\n"),
            "inline.toml:1:1: objects must be an array of tables [[objects]], got a table");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = [3]\n"),
            "inline.toml:4:9: a keyframe must be a table {t = ..., pos = [x, y], angle = ...}, got "
            "an integer");
}

TEST(LevelErrors, UnknownChoiceNamesTheChoices) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"boks\"\n"),
            "inline.toml:3:9: shape 'boks' is not one of: box, cylinder, sphere, frustum, "
            "convex_prism, concave_prism (did you mean 'box'?)");
  EXPECT_EQ(ErrorOf("[script]\ninterpolation = \"cubic\"\n"),
            "inline.toml:2:17: script.interpolation 'cubic' is not one of: linear, smooth");
}

// ---- out of range names the allowed range ----

TEST(LevelErrors, OutOfRange) {
  EXPECT_EQ(ErrorOf("[physics]\nlayers = 17\n"),
            "inline.toml:2:10: physics.layers must be in [1, 16] (got 17)");
  EXPECT_EQ(ErrorOf("[physics]\nlayer_height = 0\n"),
            "inline.toml:2:16: physics.layer_height must be in [0.05, 100] cm (got 0)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\ntable_static = -0.2\n"),
            "inline.toml:4:16: table_static must be in [0, 10] (got -0.2)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nangle = 400\n"),
            "inline.toml:4:9: angle must be in [-360, 360] deg (got 400)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nsize_x = 0\n"),
            "inline.toml:4:10: size_x must be in [0.1, 200] cm (got 0)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nheight = nan\n"),
            "inline.toml:4:10: height must be in [0.1, 100] cm (got nan)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [2000, 1]\n"),
            "inline.toml:4:7: pos must have each coordinate in [-1000, 1000] cm (got [2000, 1])");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = -1, pos = [1, 1]}]\n"),
            "inline.toml:4:14: t must be in [0, 3600] s (got -1)");
}

// ---- required fields name the field and the table's location ----

TEST(LevelErrors, MissingRequiredFields) {
  EXPECT_EQ(ErrorOf("\n[[objects]]\nshape = \"box\"\n"),
            "inline.toml:2:1: object is missing required key 'name'");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\n"),
            "inline.toml:1:1: object is missing required key 'shape'");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\npos = [5, 5]\n"),
            "inline.toml:1:1: a concave_prism object needs 'points', its outline");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\n"),
            "inline.toml:1:1: object is missing required key 'pos'");
  // a mistake in a key that is there is reported before a key left out, wherever it is
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = -1\n"),
            "inline.toml:4:8: mass must be in [0, 1e+06] g (got -1)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"),
            "inline.toml:1:1: contact is missing required key 'keys'");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1]}, {t = 1}]\n"),
            "inline.toml:4:32: keyframe is missing required key 'pos'");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = []\n"),
            "inline.toml:4:8: keys must be a non-empty array of keyframes [{t = 0, pos = [x, y]}, "
            "...]");
  EXPECT_EQ(ErrorOf("[[expect]]\nobject = \"box\"\n"),
            "inline.toml:1:1: expectation is missing required key 'kind'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\n"),
            "inline.toml:6:1: a held expectation is missing required key 'object'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"),
            "inline.toml:6:1: a position expectation needs a region: min and max, or center and "
            "radius");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"position\"\nobject = \"box\"\nmin = [0, 0]\n"),
            "inline.toml:6:1: a position expectation is missing required key 'max'");
  EXPECT_EQ(ErrorOf("[[variants]]\n[variants.physics]\nlayers = 2\n"),
            "inline.toml:1:1: variant is missing required key 'name'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"box\"\n"),
            "inline.toml:6:1: a goal needs a zone (min and max, or center and radius), angle or "
            "both");
}

// ---- keyframes ----

TEST(LevelErrors, KeyframeOutOfOrder) {
  EXPECT_EQ(
      ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = [\n"
              "  {t = 0, pos = [1, 1]},\n  {t = 1, pos = [2, 1]},\n  {t = 0.5, pos = [3, 1]},\n"
              "]\n"),
      "inline.toml:7:3: keyframe out of order: t = 0.5 s is not after the previous "
      "keyframe's t = 1 s");
  // equal times are out of order too: a contact cannot be in two places at once
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 1, pos = [1, 1]}, {t = 1, pos = [2, 1]}]\n"),
            "inline.toml:4:32: keyframe out of order: t = 1 s is not after the previous "
            "keyframe's t = 1 s");
}

TEST(LevelErrors, DurationBeforeTheLastKeyframe) {
  EXPECT_EQ(ErrorOf("[script]\nduration = 1\n[[script.contacts]]\nname = \"f\"\n"
                    "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}, {t = 2, pos = [2, 1]}]\n"),
            "inline.toml:2:12: duration 1 s ends before the last keyframe at 2 s");
}

// ---- shapes ----

TEST(LevelErrors, SizeKeysMustFitTheShape) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nradius = 2\n"),
            "inline.toml:4:1: 'radius' does not apply to a box (its size keys: size_x, size_y, "
            "height)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"sphere\"\nheight = 2\n"),
            "inline.toml:4:1: 'height' does not apply to a sphere (its size keys: radius)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"hand_five\"\nradius = 1\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:1: 'radius' does not apply to a hand_five contact (its size keys: "
            "scale)");
}

TEST(LevelErrors, PrismOutlines) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [1, 0]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points needs at least 3 points, got 2");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [4, 0], [1, 1], [0, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not convex: it turns the other way at "
            "point 3");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [4, 0], [0, 4], [4, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not a simple polygon: edge 2-3 meets "
            "edge 4-1");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [2, 0], [4, 0]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points encloses no area");
  // a vertex touching a non-neighbouring edge makes it not simple either
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [4, 0], [2, 0], [2, 2]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not a simple polygon: edge 1-2 meets "
            "edge 3-4");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [0, 0], [4, 0], [0, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points has coincident points 1 and 2");
  // a concave L is fine as a concave prism, either winding
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\npos = [5, 5]\n"
                    "points = [[0, 0], [0, 4], [1, 4], [1, 1], [3, 1], [3, 0]]\n"),
            "(loaded)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"convex\"\n"
                    "points = [[0, 0], [4, 0], [1, 1], [0, 4]]\nkeys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:10: points of a convex contact is not convex: it turns the other way "
            "at point 3");
}

// ---- meaning ----

TEST(LevelErrors, DuplicateNames) {
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[objects]]\nname = \"box\"\nshape = \"sphere\"\npos = [5, 5]\n"),
            "inline.toml:7:8: duplicate object name 'box' (first defined at inline.toml:2:1)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n[[script.contacts]]\nname = \"f\"\n"
                    "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:6:8: duplicate contact name 'f' (first defined at inline.toml:1:1)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[[variants]]\nname = \"v\"\n"),
            "inline.toml:4:8: duplicate variant name 'v' (first defined at inline.toml:1:1)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"\"\nshape = \"box\"\npos = [5, 5]\n"),
            "inline.toml:2:8: name must not be empty");
}

TEST(LevelErrors, ObjectConsistency) {
  EXPECT_EQ(
      ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\ntable_kinetic = 0.6\npos = [5, 5]\n"),
      "inline.toml:4:17: object 'a': table_kinetic must be <= table_static (0.6 > 0.4)");
  EXPECT_EQ(
      ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = 5\ndensity = 1\npos = [5, 5]\n"),
      "inline.toml:5:1: give either mass or density, not both");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [70, 10]\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [68, 72] x [8, "
            "12] cm, the table [0, 61] x [0, 46] cm");
  // the footprint counts, not the centre: a box 4 cm wide at x = 1 overhangs the edge, a turned
  // one reaches further, a frustum's wide top overhangs even when its base fits
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [1, 10]\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [-1, 3] x [8, "
            "12] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [2.5, 10]\nangle = 45\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [-0.328, "
            "5.328] x [7.172, 12.828] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"frustum\"\nradius = 1\ntop_radius = 3\n"
                    "pos = [2, 10]\n"),
            "inline.toml:6:7: object 'a' reaches off the table: its footprint spans [-1, 5] x [7, "
            "13] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\npos = [59, 10]\n"
                    "points = [[0, 0], [2, 0], [0, 2]]\n"),
            "(loaded)");
  // the table's size comes from the level
  EXPECT_EQ(ErrorOf("[table]\nwidth = 80\n[[objects]]\nname = \"a\"\nshape = \"box\"\n"
                    "pos = [70, 10]\n"),
            "(loaded)");
}

TEST(LevelErrors, NamesMustExist) {
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"bx\"\n"),
            "inline.toml:8:10: unknown object 'bx' (did you mean 'box'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"ball\"\nangle = 30\n"),
            "inline.toml:7:10: unknown object 'ball'");
  const std::string finger =
      "[[script.contacts]]\nname = \"finger\"\nshape = \"circle\"\n"
      "keys = [{t = 0, pos = [1, 1]}, {t = 2, pos = [3, 1]}]\n";
  EXPECT_EQ(ErrorOf(std::string(kBox) + finger +
                    "[[expect]]\nkind = \"resting\"\ncontact = \"fingr\"\non = \"box\"\n"),
            "inline.toml:12:11: unknown contact 'fingr' (did you mean 'finger'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + finger +
                    "[[expect]]\nkind = \"resting\"\ncontact = \"finger\"\non = \"tabel\"\n"),
            "inline.toml:13:6: unknown object 'tabel' (did you mean 'table'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"held\"\nobject = \"box\"\nvariant = \"single\"\n"),
            "inline.toml:9:11: unknown variant 'single'");
}

TEST(LevelErrors, ExpectationTimesAndBounds) {
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nat = 5\n"),
            "inline.toml:9:6: at = 5 s is after the end of the level at 1 s");
  const std::string finger =
      "[[script.contacts]]\nname = \"finger\"\nshape = \"circle\"\n"
      "keys = [{t = 1, pos = [1, 1]}, {t = 2, pos = [3, 1]}]\n";
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + finger +
              "[[expect]]\nkind = \"resting\"\ncontact = \"finger\"\non = \"box\"\nat = 0.5\n"),
      "inline.toml:14:6: at = 0.5 s is outside contact 'finger', which exists from 1 s to 2 s");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\n"),
            "inline.toml:6:1: a rotation expectation needs above, below or both");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\nabove = 10\nbelow = 5\n"),
            "inline.toml:10:9: below (5 deg) must not be less than above (10 deg)");
  EXPECT_EQ(
      ErrorOf(std::string(kBox) +
              "[[expect]]\nkind = \"displacement\"\nobject = \"box\"\nabove = 3\nbelow = 2\n"),
      "inline.toml:10:9: below (2 cm) must be greater than above (3 cm)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"
                                        "min = [0, 0]\nmax = [10, -1]\n"),
            "inline.toml:10:7: max [10, -1] must be above min [0, 0] in both x and y");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"
                                        "min = [0, 0]\nmax = [10, 10]\nradius = 3\n"),
            "inline.toml:11:1: give a region as min and max, or as center and radius, not both");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"wobble\"\n"),
            "inline.toml:7:8: kind 'wobble' is not one of: position, rotation, displacement, "
            "held, resting");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[goals]]\nobject = \"box\"\ncenter = [3, 3]\nradius = 2\ntolerance = 4\n"),
            "inline.toml:10:1: tolerance needs angle");
}

TEST(LevelErrors, FirstErrorInTheFileWins) {
  // two errors in one table: the earlier line is reported, whatever the order of the keys in code
  EXPECT_EQ(ErrorOf("[physics]\nstack_size = 0\nframe_rate = 0\n"),
            "inline.toml:2:14: physics.stack_size must be in [1, 16] (got 0)");
}

// ---- includes ----

TEST(LevelInclude, IncludedTablesAreDefaultsAndArraysComeFirst) {
  const Result<Level> r = LoadLevel(kData + "/with_include.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const Level& level = r.value();
  // key by key: the including file wins, the included file fills in, the code does the rest
  EXPECT_EQ(level.params.physics.layers, 6);
  EXPECT_EQ(level.params.physics.substeps, 6);
  EXPECT_EQ(level.params.camera.noise, 0.0);
  EXPECT_EQ(level.params.physics.stackSize, PhysicsParams{}.stackSize);
  EXPECT_EQ(level.name, "shared") << "top-level keys are inherited too";
  EXPECT_EQ(level.script.duration, 5.0);
  // the included file's objects and contacts come first
  ASSERT_EQ(level.objects.size(), 2u);
  EXPECT_EQ(level.objects[0].name, "base_box");
  EXPECT_EQ(level.objects[0].loc.Format(), kData + "/shared.toml:11:1");
  EXPECT_EQ(level.objects[1].name, "ball");
  EXPECT_EQ(level.objects[1].loc.Format(), kData + "/with_include.toml:6:1");
  ASSERT_EQ(level.script.contacts.size(), 2u);
  EXPECT_EQ(level.script.contacts[0].name, "base_finger");
  EXPECT_EQ(level.script.contacts[1].name, "finger");
  EXPECT_EQ(level.script.contacts[1].shape.length, 2.5);
  ASSERT_EQ(level.expectations.size(), 1u);
  EXPECT_EQ(level.expectations[0].object, "base_box");
  EXPECT_EQ(level.files,
            (std::vector<std::string>{kData + "/shared.toml", kData + "/with_include.toml"}));
}

TEST(LevelInclude, IncludesNestAndAreRelativeToTheIncludingFile) {
  const Result<Level> r = LoadLevel(kData + "/sub/nested.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value().name, "nested");
  EXPECT_EQ(r.value().params.camera.noise, 2.0);
  EXPECT_EQ(r.value().params.physics.layers, 6);
  EXPECT_EQ(r.value().params.physics.substeps, 6);
  EXPECT_EQ(r.value().objects.size(), 2u);
  EXPECT_EQ(r.value().files.size(), 3u);
}

TEST(LevelInclude, CycleIsReportedAtTheInclude) {
  const Result<Level> r = LoadLevel(kData + "/cycle_a.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), kData + "/cycle_b.toml:2:11: include cycle: " + kData +
                                    "/cycle_a.toml -> " + kData + "/cycle_b.toml -> " + kData +
                                    "/cycle_a.toml");
}

TEST(LevelInclude, SelfIncludeIsACycle) {
  const Result<Level> r = ParseLevel("include = \"self.toml\"\n", kData + "/self.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), kData + "/self.toml:1:11: include cycle: " + kData +
                                    "/self.toml -> " + kData + "/self.toml");
}

TEST(LevelInclude, ErrorsInAnIncludedFileNameThatFile) {
  const Result<Level> r = LoadLevel(kData + "/includes_bad_base.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), kData +
                                    "/bad_base.toml:4:1: unknown key 'layer_hieght' in [physics] "
                                    "(did you mean 'layer_height'?)");
  const Result<Level> syntax = LoadLevel(kData + "/syntax_in_base.toml");
  ASSERT_FALSE(syntax.ok());
  EXPECT_THAT(syntax.error().Format(), HasSubstr(kData + "/syntax_error.toml:2:12: "));
}

TEST(LevelInclude, MissingIncludeIsReportedAtTheInclude) {
  const Result<Level> r = LoadLevel(kData + "/includes_missing.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), kData + "/includes_missing.toml:2:11: cannot open included file '" +
                                    kData + "/no_such_file.toml'");
  EXPECT_EQ(ErrorOf("include = 3\n"),
            "inline.toml:1:11: include must be a string (a path relative to this file), got an "
            "integer");
}

TEST(Level, MissingFile) {
  const Result<Level> r = LoadLevel(kData + "/does_not_exist.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), kData + "/does_not_exist.toml: cannot open level file");
}

TEST(Level, NothingIsHalfLoaded) {
  // an error in the very last line still rejects the whole level, and loading is pure: the same
  // text loads the same level before and after a failed load
  const std::string good = std::string(kBox) + "[physics]\nlayers = 3\n";
  const Result<Level> first = ParseLevel(good, "inline.toml");
  ASSERT_TRUE(first.ok());
  const Result<Level> bad =
      ParseLevel(good + "[[goals]]\nobject = \"nope\"\nangle = 3\n", "inline.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().Format(), "inline.toml:9:10: unknown object 'nope'");
  const Result<Level> again = ParseLevel(good, "inline.toml");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.value().params.physics.layers, 3);
  EXPECT_EQ(again.value().objects.size(), first.value().objects.size());
}

TEST(Level, TheDocsExampleLoads) {
  // docs/levels.md ends with a complete example; it must stay a valid level
  std::ifstream in(std::string(PROXYGRASP_SOURCE_DIR) + "/docs/levels.md");
  ASSERT_TRUE(in);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string doc = buffer.str();
  const std::string begin = "<!-- example:begin -->\n```toml\n";
  const size_t b = doc.find(begin);
  const size_t e = doc.find("```\n<!-- example:end -->");
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  const std::string example = doc.substr(b + begin.size(), e - b - begin.size());
  const Result<Level> r =
      ParseLevel(example, std::string(PROXYGRASP_SOURCE_DIR) + "/levels/example.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const Level& level = r.value();
  EXPECT_EQ(level.objects.size(), 2u);
  EXPECT_EQ(level.script.contacts.size(), 3u);
  EXPECT_EQ(level.expectations.size(), 5u);
  EXPECT_EQ(level.goals.size(), 2u);
  EXPECT_EQ(level.variants.size(), 1u);
  EXPECT_EQ(level.files.size(), 2u) << "it includes levels/shared/base.toml";
}

TEST(Level, SharedBaseOfThePapersLevelsLoads) {
  const Result<Level> r =
      LoadLevel(std::string(PROXYGRASP_SOURCE_DIR) + "/levels/shared/base.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_TRUE(r.value().objects.empty());
}

TEST(Goal, MetInTheZoneAndWithinTheAngleModuloATurn) {
  Goal g;
  Region zone;
  zone.min = Vec2(0, 0);
  zone.max = Vec2(10, 10);
  g.zone = zone;
  g.angle = DegToRad(90);
  g.tolerance = DegToRad(5);
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), DegToRad(94)}));
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), DegToRad(90 + 360)})) << "a full extra turn is the same mark";
  EXPECT_FALSE(g.IsMet({Vec2(5, 5), DegToRad(96)}));
  EXPECT_FALSE(g.IsMet({Vec2(11, 5), DegToRad(90)}));
  g.angle.reset();
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), 2.0}));
}

TEST(Region, ContainsRectAndCircle) {
  Region rect;
  rect.min = Vec2(0, 0);
  rect.max = Vec2(2, 1);
  EXPECT_TRUE(rect.Contains(Vec2(2, 1)));
  EXPECT_FALSE(rect.Contains(Vec2(2.01, 0.5)));
  Region circle;
  circle.kind = Region::Kind::kCircle;
  circle.center = Vec2(1, 1);
  circle.radius = 1;
  EXPECT_TRUE(circle.Contains(Vec2(1.6, 1.6)));
  EXPECT_FALSE(circle.Contains(Vec2(1.8, 1.8)));
}

}  // namespace
}  // namespace pg
