#include "run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace pg {
namespace {

using test::RunProxygrasp;
using ::testing::HasSubstr;

TEST(BenchCommand, WritesTheTableAndTheJson) {
  const std::string json =
      (std::filesystem::temp_directory_path() / "proxygrasp_cmd_bench.json").string();
  std::filesystem::remove(json);
  const auto r = RunProxygrasp("bench --frames 2 --scenes flat_hands2_s3_k8 --json " + json);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("flat_hands2_s3_k8"));
  EXPECT_THAT(r.output, HasSubstr("sensing_vs_bare_opencv"));
  EXPECT_THAT(r.output, HasSubstr("json: " + json));
  std::stringstream text;
  text << std::ifstream(json).rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("\"name\": \"flat_hands2_s3_k8\""));
  EXPECT_THAT(text.str(), HasSubstr("\"baselines\""));
}

TEST(BenchCommand, BadValuesExitTwoWithAMessage) {
  auto r = RunProxygrasp("bench --frames 0");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--frames must be >= 1 (got 0)"));

  r = RunProxygrasp("bench --frames ten");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--frames"));

  r = RunProxygrasp("bench --frames 1 --scenes nowhere");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("unknown scene 'nowhere'"));

  r = RunProxygrasp("bench --frames 1 --json /nonexistent-dir/out.json");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("cannot write"));
}

}  // namespace
}  // namespace pg
