#include "proxygrasp/run/expectations.h"

#include "test_paths.h"

#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/simulation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "run/test_levels.h"

namespace pg {
namespace {

using ::testing::HasSubstr;

// the level test data: a level naming variants, modes and every kind of expectation
const std::string kData = std::string(pg::test::SourceDir()) + "/tests/level/testdata";

TEST(ExpectationText, ExpectationsDescribeThemselves) {
  const Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const auto& e = r.value().expectations;
  EXPECT_EQ(ExpectationText(e[0]), "box turned >= 30 deg and <= 60 deg at the end");
  EXPECT_EQ(ExpectationText(e[1]), "box within 1.5 cm of [30, 23] at 2 s");
  EXPECT_EQ(ExpectationText(e[2]), "puck moved >= 0.5 cm at the end");
  EXPECT_EQ(ExpectationText(e[3]), "box not held at 1.5 s (instant)");
  EXPECT_EQ(ExpectationText(e[4]), "80% of thumb resting on the table at 2 s (single)");
}

// a box alone on the table, with expectations on it and no contact
const std::string kLoneBox = test::BoxToml("box", 30, 23) + R"(
[script]
duration = 1

[[expect]]
kind = "held"
object = "box"
held = false
at = 0.05

[[expect]]
kind = "held"
object = "box"
at = 0.5

[[expect]]
kind = "displacement"
object = "box"
below = 0.001

[[expect]]
kind = "position"
object = "box"
center = [30, 23]
radius = 0.01
at = 0.9
)";

TEST(Evaluator, ChecksEachExpectationWhenDueAndCountsOnlyTheLastHeldFrames) {
  const Level level = test::ParseOrFail(kLoneBox, "lone_box.toml");
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  const LevelRun run = LevelRuns(level)[0];
  Evaluator evaluator(level, run, sim);
  std::vector<ExpectationResult> results;
  // 0.05 s is the end of frame 3 at 60 Hz: the first expectation is due then, over 3 frames
  for (int i = 0; i < 3; ++i) {
    ASSERT_FALSE(sim.StepScript());
    evaluator.AfterFrame(sim, sim.Time(), results);
  }
  ASSERT_EQ(results.size(), 1u);
  EXPECT_TRUE(results[0].passed);
  EXPECT_EQ(results[0].measured, "not held (0/3 frames)");
  // 0.5 s: the held flags of only the last kHeldFrames frames count
  for (int i = 3; i < 30; ++i) {
    ASSERT_FALSE(sim.StepScript());
    evaluator.AfterFrame(sim, sim.Time(), results);
  }
  ASSERT_EQ(results.size(), 2u);
  EXPECT_FALSE(results[1].passed) << "nothing holds the box";
  EXPECT_EQ(results[1].measured, "not held (0/6 frames)");
  // at the end: the box never moved (no contact, at rest: exactly 0); the position check at
  // 0.9 s is past the end of this run, stopped at 0.5 s, and fails as not reached
  evaluator.Finish(sim, sim.Time(), results);
  ASSERT_EQ(results.size(), 4u);
  EXPECT_TRUE(results[2].passed) << results[2].measured;
  EXPECT_EQ(results[2].measured, "0.000 cm");
  EXPECT_FALSE(results[3].passed);
  EXPECT_EQ(results[3].measured, "run ended at 0.500 s");
}

TEST(Evaluator, ASpeedExpectationHoldsThePeakOfEveryFrameUpToItsTime) {
  // a fingertip (radius 0.8 cm) moves from x = 26 to 34 at 16 cm/s and stops: its edge meets the
  // 4 cm box's left side (x = 28) at 0.075 s, after the first check (0.05 s, the end of frame 3),
  // and then pushes the box at about its own speed, never faster than it plus the release bound
  // of 5 cm/s. The bound is measured from the finger's surface as the camera sees it (its
  // particles' fitted motion): the contour's points jitter by up to a pixel (0.1 cm) a frame, and
  // the mean of a fingertip's 17 or so points by 0.1 / sqrt(17) cm, 1.5 cm/s. So below 22.5
  const Level level = test::ParseOrFail(test::BoxToml("box", 30, 23) +
                                        test::FingerToml("finger", 26, 23, 0, 34, 23, 0.5) + R"(
[script]
duration = 1

[[expect]]
kind = "speed"
object = "box"
below = 0.001
at = 0.05

[[expect]]
kind = "speed"
object = "box"
below = 5

[[expect]]
kind = "speed"
object = "box"
below = 22.5
)");
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  Evaluator evaluator(level, LevelRuns(level)[0], sim);
  std::vector<ExpectationResult> results;
  while (sim.Time() < 1.0 - 1e-9) {
    ASSERT_FALSE(sim.StepScript());
    evaluator.AfterFrame(sim, sim.Time(), results);
  }
  evaluator.Finish(sim, sim.Time(), results);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].text, "box never faster than 0.001 cm/s at 0.05 s");
  EXPECT_TRUE(results[0].passed) << "untouched in its first three frames: " << results[0].measured;
  EXPECT_FALSE(results[1].passed) << "pushed at about 16 cm/s: " << results[1].measured;
  EXPECT_TRUE(results[2].passed) << results[2].measured;
}

TEST(Evaluator, ARestingContactThatLeftNoParticleSaysWhichContactItLookedFor) {
  // a level whose script has a fingertip, run from an input that does not draw the script (here
  // contours that hold no contact; a TUIO stream or a video is the same): the resting
  // expectation finds no particle of the fingertip, fails, and says whose particles it looked for
  const Level level = test::ParseOrFail(test::FingerToml("finger", 10, 10, 0, 12, 10, 0.5) + R"(
[script]
duration = 1

[[expect]]
kind = "resting"
contact = "finger"
on = "table"
at = 0.4
)",
                                        "resting.toml");
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  Evaluator evaluator(level, LevelRuns(level)[0], sim);
  std::vector<ExpectationResult> results;
  FrameInput nothing = FrameInput::Contours();
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(nothing.Step(sim).ok());
    evaluator.AfterFrame(sim, sim.Time(), results);
  }
  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].passed);
  EXPECT_EQ(results[0].measured, "0/0 particles (0%): none of script contact 'finger'");
}

}  // namespace
}  // namespace pg
