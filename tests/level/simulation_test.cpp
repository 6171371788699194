#include "proxygrasp/level/simulation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace pg {
namespace {

using ::testing::HasSubstr;

Level BoxLevel() {
  const Result<Level> level = ParseLevel(R"(
[[objects]]
name = "box"
shape = "box"
size_x = 4
size_y = 4
height = 2
pos = [30, 23]

[[script.contacts]]
name = "left"
shape = "circle"
radius = 0.8
keys = [{t = 0, pos = [20, 23]}, {t = 1, pos = [20, 30]}]

[[script.contacts]]
name = "right"
shape = "circle"
radius = 0.8
keys = [{t = 0, pos = [40, 23]}, {t = 1, pos = [40, 30]}]
)",
                                         "sim.toml");
  EXPECT_TRUE(level.ok()) << level.error().Format();
  return level.value();
}

TEST(Simulation, ScriptRunsTheWholePipeline) {
  const Level level = BoxLevel();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  ASSERT_FALSE(sim.StepScript());
  // two fingertips: two new contacts, each seeded with particles on the table
  EXPECT_EQ(sim.stats().contacts, 2);
  EXPECT_GT(sim.stats().particles, 20);
  EXPECT_EQ(sim.stats().created, sim.stats().particles);
  EXPECT_EQ(sim.stats().bodies, sim.stats().particles + 2);  // 2 slices of a 2 cm box
  EXPECT_EQ(sim.Frame(), 1);
  EXPECT_DOUBLE_EQ(sim.Time(), 1.0 / 60.0);
  for (const ParticleState& p : sim.world().Particles()) EXPECT_EQ(p.restingOn, -1);
}

TEST(Simulation, AttributesTrackedContactsToScriptContacts) {
  const Level level = BoxLevel();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  for (int i = 0; i < 10; ++i) ASSERT_FALSE(sim.StepScript());
  int left = 0, right = 0;
  for (const Contact& c : sim.contacts().contacts) {
    const int script = sim.ScriptContactOf(c.id);
    // contact 0 is "left" (x = 20), contact 1 is "right" (x = 40)
    if (script == 0) {
      ++left;
      EXPECT_LT(c.blob.centroid.x(), 30.0);
    } else if (script == 1) {
      ++right;
      EXPECT_GT(c.blob.centroid.x(), 30.0);
    }
  }
  EXPECT_EQ(left, 1);
  EXPECT_EQ(right, 1);
  EXPECT_EQ(sim.ScriptContactOf(12345), -1);
}

TEST(Simulation, ShapesInputGoesThroughTheCamera) {
  const Level level = BoxLevel();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  ContactShape finger;
  finger.radius = 1.0;
  finger.pose.pos = Vec2(30, 23);  // on the box's top
  ASSERT_FALSE(sim.StepShapes(std::span<const ContactShape>(&finger, 1)));
  ASSERT_EQ(sim.stats().contacts, 1);
  // a new contact over the box is seeded on its top by raycast
  for (const ParticleState& p : sim.world().Particles()) EXPECT_EQ(p.restingOn, 0);
  EXPECT_EQ(sim.cameraImage().cols, level.params.camera.width);
}

TEST(Simulation, BadFrameIsAnErrorNamingTheFrame) {
  const Level level = BoxLevel();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  const Status bad = sim.StepImage(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)));
  ASSERT_TRUE(bad);
  EXPECT_THAT(bad->Format(), HasSubstr("frame 0"));
  EXPECT_EQ(sim.Frame(), 0) << "a rejected frame does not advance the simulation";
}

TEST(Simulation, FailedStartKeepsNothing) {
  Level level = BoxLevel();
  level.params.sensing.calibration = "/nonexistent/calibration.yaml";
  Simulation sim;
  const Status bad = sim.Start(level, level.params);
  ASSERT_TRUE(bad);
  EXPECT_THAT(bad->Format(), HasSubstr("/nonexistent/calibration.yaml"));
}

}  // namespace
}  // namespace pg
