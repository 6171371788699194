#include "run_command.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace pg {
namespace {

using test::RunProxygrasp;
using ::testing::HasSubstr;

std::string Level(const std::string& name) {
  return std::string(pg::test::SourceDir()) + "/levels/" + name;
}

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(RunCommand, PassingLevelExitsZeroWithAReport) {
  const auto r = RunProxygrasp("run " + Level("side_push.toml") + " --profile");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("PASS"));
  EXPECT_THAT(r.output, HasSubstr("=> PASS"));
  EXPECT_THAT(r.output, HasSubstr("median ms"));
}

TEST(RunCommand, FailingExpectationExitsOne) {
  // 20 frames (a third of a second) end before the finger reaches the box: nothing has moved
  const auto r = RunProxygrasp("run " + Level("side_push.toml") + " --frames 20");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("FAIL"));
}

TEST(RunCommand, BadLevelExitsTwoWithLocation) {
  const std::string path = WriteTemp("pg_bad_level.toml", "[physics]\nsubstep = 4\n");
  const auto r = RunProxygrasp("run " + path);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr(path + ":2:1:"));
  EXPECT_THAT(r.output, HasSubstr("did you mean 'substeps'"));
  std::filesystem::remove(path);
}

TEST(RunCommand, BadSetExitsTwo) {
  const auto r = RunProxygrasp("run " + Level("side_push.toml") + " --set physics.layers=99");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("physics.layers"));
  EXPECT_THAT(r.output, HasSubstr("[1, 16]"));
  const auto noEq = RunProxygrasp("run " + Level("side_push.toml") + " --set physics.layers");
  EXPECT_EQ(noEq.exitCode, 2);
  EXPECT_THAT(noEq.output, HasSubstr("section.key=value"));
}

TEST(RunCommand, ALevelNameIsFoundInTheSourceTreeOfTheBuildFolder) {
  // the tests run in build/<preset>/tests, which has no levels/: the command, at the top of its
  // build folder, finds the name in the source tree's levels (app/level_search.h)
  auto r = RunProxygrasp("run side_push");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("=> PASS"));
  r = RunProxygrasp("run side_psuh");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("level side_psuh: not a file, and no side_psuh.toml in "));
  EXPECT_THAT(r.output, HasSubstr("did you mean 'side_push'?"));
}

TEST(RunCommand, MissingFileAndBadModeExitTwo) {
  const auto missing = RunProxygrasp("run /nonexistent/level.toml");
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_THAT(missing.output, HasSubstr("level /nonexistent/level.toml: no such file"));
  EXPECT_EQ(RunProxygrasp("run " + Level("side_push.toml") + " --mode sideways").exitCode, 2);
}

TEST(RunCommand, ABadInputExitsTwoNamingTheOption) {
  // a TUIO spec that does not parse, and an address this machine does not have
  auto r = RunProxygrasp("run " + Level("side_push.toml") + " --input tuio:abc");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--input tuio:abc: expected tuio:PORT or tuio:ADDRESS:PORT"));
  r = RunProxygrasp("run " + Level("side_push.toml") + " --input tuio:192.0.2.1:3333");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--input tuio:192.0.2.1:3333: cannot listen for TUIO"));
}

TEST(RunCommand, TraceFolderHoldsBothFiles) {
  const std::string dir = (std::filesystem::temp_directory_path() / "pg_cmd_run_trace").string();
  std::filesystem::remove_all(dir);
  const auto r = RunProxygrasp("run " + Level("side_push.toml") + " --frames 10 --trace " + dir);
  EXPECT_EQ(r.exitCode, 1) << r.output;  // 10 frames are too few for the push: expectations fail
  EXPECT_TRUE(std::filesystem::exists(dir + "/objects.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/frames.csv"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pg
