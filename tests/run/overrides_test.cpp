#include "proxygrasp/run/overrides.h"

#include "test_paths.h"

#include "proxygrasp/sensing/calibration.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace pg {
namespace {

using ::testing::HasSubstr;

// the level test data: a level naming variants, modes and every kind of expectation
const std::string kData = std::string(pg::test::SourceDir()) + "/tests/level/testdata";

TEST(Overrides, SetOverridesTheLevelAndEveryVariant) {
  Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  Level& level = r.value();
  EXPECT_FALSE(SetLevelParam(level, "physics.stack_size", "5"));
  EXPECT_EQ(level.params.physics.stackSize, 5);
  EXPECT_EQ(level.variants[0].params.physics.stackSize, 5) << "the command line wins";
  EXPECT_FALSE(SetLevelParam(level, "physics.substeps", "2"));
  EXPECT_EQ(level.variants[0].params.physics.substeps, 2);
  const MaybeError bad = SetLevelParam(level, "physics.stack_size", "99");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->message, "physics.stack_size: value 99 is out of range [1, 16]");
  EXPECT_EQ(level.params.physics.stackSize, 5);
  EXPECT_EQ(level.variants[0].params.physics.stackSize, 5);
}

TEST(Overrides, ParseSplitsAtTheFirstEqualsSign) {
  const Result<Override> o = ParseOverride("sensing.calibration=a=b.yaml");
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o.value().key, "sensing.calibration");
  EXPECT_EQ(o.value().value, "a=b.yaml");
  const Result<Override> bad = ParseOverride("physics.substeps");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().Format(), "--set physics.substeps: expected section.key=value");
}

TEST(Overrides, ApplyAllOrNothingAndNameTheBadArgument) {
  Result<Level> r = LoadLevel(kData + "/complete.toml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  Level& level = r.value();
  const int substeps = level.params.physics.substeps;
  // the second argument is bad: the first is not applied either
  const MaybeError bad = ApplyOverrides(level, {"physics.substeps=7", "physics.stack_size=99"});
  ASSERT_TRUE(bad);
  EXPECT_THAT(bad->Format(), HasSubstr("--set physics.stack_size=99: "));
  EXPECT_THAT(bad->Format(), HasSubstr("out of range [1, 16]"));
  EXPECT_EQ(level.params.physics.substeps, substeps);
  EXPECT_FALSE(ApplyOverrides(level, {"physics.substeps=7", "tracking.max_distance=2"}));
  EXPECT_EQ(level.params.physics.substeps, 7);
  EXPECT_EQ(level.variants[0].params.physics.substeps, 7) << "variants follow the command line";

  LevelParams params;
  const MaybeError unknown = ApplyOverrides(params, {"physics.substep=2"});
  ASSERT_TRUE(unknown);
  EXPECT_THAT(unknown->Format(), HasSubstr("--set physics.substep=2: "));
  EXPECT_FALSE(ApplyOverrides(params, {"sensing.threshold=50"}));
  EXPECT_EQ(params.sensing.threshold, 50);
}

TEST(Overrides, ACalibrationsTunedValuesWinOverTheLevelAndSetWinsOverThem) {
  Calibration c = LinearCalibration({640, 480}, TableParams());
  c.sensing = {{"gain", "8.5"}, {"threshold", "40"}};
  const std::string path = ::testing::TempDir() + "/overrides_tuned.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  LevelParams params;
  params.sensing.gain = 2.0;  // as a level file would set it
  params.sensing.calibration = path;
  ASSERT_FALSE(ApplyOverrides(params, {"sensing.threshold=50"}));
  EXPECT_EQ(params.sensing.gain, 8.5);
  EXPECT_EQ(params.sensing.threshold, 50);
  // --set may name the calibration itself
  LevelParams other;
  ASSERT_FALSE(ApplyOverrides(other, {"sensing.calibration=\"" + path + "\""}));
  EXPECT_EQ(other.sensing.gain, 8.5);
  EXPECT_EQ(other.sensing.threshold, 40);
}

TEST(Overrides, ABadTunedValueNamesTheCalibrationFileAndKeyAndChangesNothing) {
  Calibration c = LinearCalibration({640, 480}, TableParams());
  c.sensing = {{"gain", "8.5"}, {"gian", "2"}};
  const std::string path = ::testing::TempDir() + "/overrides_bad.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  LevelParams params;
  params.sensing.calibration = path;
  MaybeError s = ApplyOverrides(params, {});
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr(path + ": field 'sensing.gian'"));
  EXPECT_EQ(params.sensing.gain, 1.0);
  c.sensing = {{"gain", "900"}};
  ASSERT_FALSE(SaveCalibration(path, c));
  s = ApplyCalibrationSensing(params);
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr("field 'sensing.gain'"));
  params.sensing.calibration = ::testing::TempDir() + "/no_such_calibration.yaml";
  s = ApplyCalibrationSensing(params);
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr("calibration file not found"));
}

}  // namespace
}  // namespace pg
