#include "run_command.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pg {
namespace {

using test::RunProxygrasp;
using ::testing::HasSubstr;
using ::testing::Not;

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

  r = RunProxygrasp("bench --frames 1 --clock sundial");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--clock sundial: must be cpu or wall"));

  r = RunProxygrasp("bench --frames 1 --json /nonexistent-dir/out.json");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("cannot write"));
}

TEST(BenchCommand, GraspSweepRunsItsScenesAndWritesTheFailingOnesAsLevels) {
  const auto dir = std::filesystem::temp_directory_path() / "proxygrasp_cmd_bench_grasp";
  std::filesystem::remove_all(dir);
  const std::string json = (dir / "grasp.json").string();
  std::filesystem::create_directories(dir);
  const auto r = RunProxygrasp("bench grasp --count 2 --substeps 4 --threads 1 --json " + json +
                               " --failures " + (dir / "failures").string());
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("grasp sweep: seed 1, 2 scenes"));
  EXPECT_THAT(r.output, HasSubstr("held&followed"));
  std::stringstream text;
  text << std::ifstream(json).rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("\"rates\""));
  EXPECT_THAT(text.str(), HasSubstr("\"substeps\": 4"));
  // every scene written out is a level `proxygrasp run` accepts
  if (std::filesystem::exists(dir / "failures")) {
    for (const auto& entry : std::filesystem::directory_iterator(dir / "failures")) {
      const auto run = RunProxygrasp("run " + entry.path().string());
      EXPECT_NE(run.exitCode, 2) << run.output;
    }
  }
}

TEST(BenchCommand, GraspSweepBadValuesExitTwoWithAMessage) {
  auto r = RunProxygrasp("bench grasp --count 0");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--count must be at least 1"));
  r = RunProxygrasp("bench grasp --substeps 4,x");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--substeps 4,x"));
  r = RunProxygrasp("bench nonsense");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("unknown suite 'nonsense'"));
  r = RunProxygrasp("bench grasp --rule-only --set physics.bogus=1");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--set physics.bogus=1"));
  r = RunProxygrasp("bench grasp --rule-only --hold-share 0.3");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--hold-share must be in [0.5, 1] (got 0.3)"));
  r = RunProxygrasp("bench grasp --rule-only --count 5");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("5 scenes: the rule says"));
}

TEST(BenchCommand, ItsJsonBecomesThePerformanceDocsSection) {
  // scripts/bench-docs.py writes a run's figures between the markers of a copy of the doc, with
  // issue 17's targets beside them, and keeps the rest of the doc
  if (std::system("command -v python3 >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3 is not installed: scripts/bench-docs.py cannot run";
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::string json = (dir / "proxygrasp_bench_docs.json").string();
  const std::string doc = (dir / "proxygrasp_bench_docs.md").string();
  const auto r = RunProxygrasp("bench --frames 2 --scenes flat_hands2_s3_k8 --json " + json);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ofstream(doc) << "# before\n<!-- bench:begin -->\nold figures\n<!-- bench:end -->\nafter\n";
  const std::string script = std::string(pg::test::SourceDir()) + "/scripts/bench-docs.py";
  ASSERT_EQ(std::system(("python3 " + script + " " + json + " " + doc + " >/dev/null").c_str()), 0);
  std::stringstream text;
  text << std::ifstream(doc).rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("# before\n<!-- bench:begin -->\nGenerated by"));
  EXPECT_THAT(text.str(), Not(HasSubstr("old figures")));
  EXPECT_THAT(text.str(), HasSubstr("| `flat_hands2_s3_k8` |"));
  EXPECT_THAT(text.str(), HasSubstr("2.000 ms: "));  // the scene's p99 target
  EXPECT_THAT(text.str(), HasSubstr("| sensing_vs_bare_opencv | `flat_hands2_s3_k8` |"));
  EXPECT_THAT(text.str(), HasSubstr("rendering two hands"));
  EXPECT_THAT(text.str(), HasSubstr("<!-- bench:end -->\nafter\n"));
  // a doc without the markers is an error, and is left as it was
  std::ofstream(doc) << "no markers\n";
  EXPECT_NE(std::system(("python3 " + script + " " + json + " " + doc + " 2>/dev/null").c_str()),
            0);
  std::stringstream same;
  same << std::ifstream(doc).rdbuf();
  EXPECT_EQ(same.str(), "no markers\n");
}

}  // namespace
}  // namespace pg
