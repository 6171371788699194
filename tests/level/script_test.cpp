#include "proxygrasp/level/script.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

namespace pg {
namespace {

Keyframe Key(double t, double x, double y, double angle = 0.0) {
  Keyframe k;
  k.t = t;
  k.pose.pos = Vec2(x, y);
  k.pose.angle = angle;
  return k;
}

ScriptContact Finger(Interpolation interpolation) {
  ScriptContact c;
  c.name = "finger";
  c.interpolation = interpolation;
  c.keys = {Key(1, 0, 0), Key(3, 4, 2, kPi), Key(4, 4, 6, kPi)};
  return c;
}

TEST(Script, LinearInterpolatesPositionAndAngle) {
  const ScriptContact c = Finger(Interpolation::kLinear);
  const auto mid = PoseAt(c, 2.0);
  ASSERT_TRUE(mid);
  EXPECT_DOUBLE_EQ(mid->pos.x(), 2.0);
  EXPECT_DOUBLE_EQ(mid->pos.y(), 1.0);
  EXPECT_DOUBLE_EQ(mid->angle, 0.5 * kPi);
  const auto second = PoseAt(c, 3.25);
  ASSERT_TRUE(second);
  EXPECT_DOUBLE_EQ(second->pos.y(), 3.0);
}

TEST(Script, SmoothEasesInAndOut) {
  // smoothstep(0.25) = 3/16 - 2/64 = 0.15625 of the segment; at a key the pose is the key's
  const ScriptContact c = Finger(Interpolation::kSmooth);
  const auto quarter = PoseAt(c, 1.5);
  ASSERT_TRUE(quarter);
  EXPECT_DOUBLE_EQ(quarter->pos.x(), 4 * 0.15625);
  EXPECT_DOUBLE_EQ(quarter->angle, kPi * 0.15625);
  const auto half = PoseAt(c, 2.0);
  EXPECT_DOUBLE_EQ(half->pos.x(), 2.0);
  EXPECT_DOUBLE_EQ(PoseAt(c, 3.0)->pos.x(), 4.0);
}

TEST(Script, ContactExistsFromFirstToLastKeyframeInclusive) {
  const ScriptContact c = Finger(Interpolation::kLinear);
  EXPECT_FALSE(PoseAt(c, 0.999));
  ASSERT_TRUE(PoseAt(c, 1.0));
  EXPECT_EQ(PoseAt(c, 1.0)->pos, Vec2(0, 0));
  ASSERT_TRUE(PoseAt(c, 4.0));
  EXPECT_EQ(PoseAt(c, 4.0)->pos, Vec2(4, 6));
  EXPECT_FALSE(PoseAt(c, 4.001));
  EXPECT_EQ(c.Start(), 1.0);
  EXPECT_EQ(c.End(), 4.0);
}

TEST(Script, SingleKeyframeExistsAtThatInstantOnly) {
  ScriptContact c;
  c.keys = {Key(2, 5, 5)};
  EXPECT_FALSE(PoseAt(c, 1.9));
  ASSERT_TRUE(PoseAt(c, 2.0));
  EXPECT_EQ(PoseAt(c, 2.0)->pos, Vec2(5, 5));
  EXPECT_FALSE(PoseAt(c, 2.1));
}

TEST(Script, AnglesAreNotWrapped) {
  // a key at 360 degrees after one at 0 turns a full circle, it does not stay put
  ScriptContact c;
  c.keys = {Key(0, 0, 0, 0.0), Key(1, 0, 0, 2 * kPi)};
  EXPECT_DOUBLE_EQ(PoseAt(c, 0.5)->angle, kPi);
}

TEST(Script, ShapesAtListsPresentContactsWithTheirShapes) {
  Script script;
  ScriptContact a = Finger(Interpolation::kLinear);
  a.shape.kind = ShapeKind::kEllipse;
  a.shape.radiusX = 2.0;
  ScriptContact b;
  b.name = "late";
  b.shape.kind = ShapeKind::kHandFlat;
  b.keys = {Key(3.5, 10, 10), Key(5, 12, 10)};
  script.contacts = {a, b};
  std::vector<int> indices;

  EXPECT_TRUE(ShapesAt(script, 0.5, &indices).empty());
  EXPECT_TRUE(indices.empty());

  const auto one = ShapesAt(script, 2.0, &indices);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].kind, ShapeKind::kEllipse);
  EXPECT_EQ(one[0].radiusX, 2.0);
  EXPECT_DOUBLE_EQ(one[0].pose.pos.x(), 2.0);
  EXPECT_EQ(indices, std::vector<int>{0});

  const auto both = ShapesAt(script, 3.5, &indices);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[1].kind, ShapeKind::kHandFlat);
  EXPECT_EQ(both[1].pose.pos, Vec2(10, 10));
  EXPECT_EQ(indices, (std::vector<int>{0, 1}));

  const auto last = ShapesAt(script, 4.25, &indices);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(indices, std::vector<int>{1});
  EXPECT_DOUBLE_EQ(last[0].pose.pos.x(), 11.0);
  EXPECT_EQ(LastKeyframeTime(script), 5.0);
}

TEST(Script, HeightIsInterpolatedLikeThePose) {
  // heights 0 (touching), 4 and 1 cm at t = 1, 3 and 4 s
  ScriptContact c = Finger(Interpolation::kLinear);
  c.keys[1].height = 4.0;
  c.keys[2].height = 1.0;
  EXPECT_FALSE(HeightAt(c, 0.5));
  EXPECT_DOUBLE_EQ(*HeightAt(c, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(*HeightAt(c, 2.0), 2.0);  // halfway up the first segment
  EXPECT_DOUBLE_EQ(*HeightAt(c, 3.5), 2.5);  // halfway down the second
  EXPECT_DOUBLE_EQ(*HeightAt(c, 4.0), 1.0);  // the last keyframe's
  EXPECT_FALSE(HeightAt(c, 4.5));
  // smooth: smoothstep(0.25) = 0.15625 of the way, as the position
  c.interpolation = Interpolation::kSmooth;
  EXPECT_DOUBLE_EQ(*HeightAt(c, 1.5), 4.0 * 0.15625);
  EXPECT_DOUBLE_EQ(PoseAt(c, 1.5)->pos.x(), 4.0 * 0.15625);
  // the shapes carry it
  Script script;
  script.contacts = {c};
  const std::vector<ContactShape> shapes = ShapesAt(script, 1.5);
  ASSERT_EQ(shapes.size(), 1u);
  EXPECT_DOUBLE_EQ(shapes[0].height, 4.0 * 0.15625);
}

}  // namespace
}  // namespace pg
