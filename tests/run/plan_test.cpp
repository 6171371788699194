#include "proxygrasp/run/plan.h"

#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace pg {
namespace {

using ::testing::HasSubstr;

// the level test data: a level naming variants, modes and every kind of expectation
const std::string kData = std::string(pg::test::SourceDir()) + "/tests/level/testdata";

TEST(LevelRuns, OneRunPerVariantAndModeTheExpectationsName) {
  const Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const Level& level = r.value();
  const std::vector<LevelRun> runs = LevelRuns(level);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].variant, "");
  EXPECT_EQ(runs[0].mode, ProxyMode::kPersistent);
  EXPECT_EQ(runs[1].variant, "");
  EXPECT_EQ(runs[1].mode, ProxyMode::kInstant);
  EXPECT_EQ(runs[2].variant, "single");
  EXPECT_EQ(runs[2].mode, ProxyMode::kPersistent);

  // each expectation belongs to exactly the runs it names
  const Expectation& turn = level.expectations[0];
  const Expectation& instantHeld = level.expectations[3];
  const Expectation& singleResting = level.expectations[4];
  EXPECT_TRUE(AppliesTo(turn, runs[0], level));
  EXPECT_FALSE(AppliesTo(turn, runs[1], level));
  EXPECT_FALSE(AppliesTo(turn, runs[2], level));
  EXPECT_FALSE(AppliesTo(instantHeld, runs[0], level));
  EXPECT_TRUE(AppliesTo(instantHeld, runs[1], level));
  EXPECT_TRUE(AppliesTo(singleResting, runs[2], level));
  EXPECT_FALSE(AppliesTo(singleResting, runs[0], level));

  EXPECT_EQ(RunParams(level, runs[1]).proxies.mode, ProxyMode::kInstant);
  EXPECT_EQ(RunParams(level, runs[1]).physics.stackSize, 3);
  EXPECT_EQ(RunParams(level, runs[2]).physics.stackSize, 1);
}

TEST(LevelRuns, ForcedModeRunsOnlyThatMode) {
  const Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const Level& level = r.value();
  const std::vector<LevelRun> runs = LevelRuns(level, ProxyMode::kInstant);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].variant, "");
  EXPECT_EQ(runs[0].mode, ProxyMode::kInstant);
  EXPECT_EQ(runs[1].variant, "single");
  EXPECT_EQ(runs[1].mode, ProxyMode::kInstant);
  // under --mode, expectations without a mode are checked in the forced mode
  EXPECT_TRUE(AppliesTo(level.expectations[0], runs[0], level));
  EXPECT_TRUE(AppliesTo(level.expectations[3], runs[0], level));
  const std::vector<LevelRun> persistent = LevelRuns(level, ProxyMode::kPersistent);
  ASSERT_EQ(persistent.size(), 2u);
  EXPECT_FALSE(AppliesTo(level.expectations[3], persistent[0], level));
}

TEST(LevelRuns, RunNamesGiveVariantAndMode) {
  EXPECT_EQ(RunName({"", ProxyMode::kPersistent, false}), "base/persistent");
  EXPECT_EQ(RunName({"single", ProxyMode::kInstant, true}), "single/instant");
}

TEST(LevelRuns, TheExampleOfTheFormatReferenceNeedsThreeRuns) {
  const Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(LevelRuns(r.value()).size(), 3u);
}

}  // namespace
}  // namespace pg
