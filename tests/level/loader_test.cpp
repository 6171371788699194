#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "level/level_test_util.h"

namespace pg {
namespace {

using test::ErrorOf;
using test::kBox;
using test::kData;
using ::testing::HasSubstr;

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

}  // namespace
}  // namespace pg
