#include "proxygrasp/level/level.h"

#include "test_paths.h"

#include "proxygrasp/core/units.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "level/level_test_util.h"

namespace pg {
namespace {

using test::kBox;
using test::kData;
using test::Values;

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

TEST(Level, TheDocsExampleLoads) {
  // docs/levels.md ends with a complete example; it must stay a valid level
  std::ifstream in(std::string(pg::test::SourceDir()) + "/docs/levels.md");
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
      ParseLevel(example, std::string(pg::test::SourceDir()) + "/levels/example.toml");
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
      LoadLevel(std::string(pg::test::SourceDir()) + "/levels/shared/base.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_TRUE(r.value().objects.empty());
}

}  // namespace
}  // namespace pg
