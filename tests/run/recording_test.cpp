// Recording and replay: a run's camera frames recorded with its trace, then fed back to the runner
// as a level's input ([script] recording), give the same object trajectory.
#include "proxygrasp/run/runner.h"
#include "proxygrasp/run/trace.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/run_command.h"

namespace pg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// a box pushed by a fingertip, 0.8 s = 48 frames at 60 Hz
constexpr const char* kObjects = R"(
[[objects]]
name = "box"
shape = "box"
size_x = 6
size_y = 6
height = 3
mass = 100
pos = [30, 23]
)";

constexpr const char* kScript = R"(
[script]
duration = 0.8

[[script.contacts]]
name = "finger"
shape = "circle"
radius = 0.8
keys = [
  {t = 0.0, pos = [24, 23]},
  {t = 0.6, pos = [30, 23]},
]
)";

constexpr const char* kExpect = R"(
[[expect]]
kind = "displacement"
object = "box"
above = 1
)";

std::string Dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/recording_test_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// the box's x in the last row of an objects.csv
double LastX(const std::string& csv) {
  const size_t lastLine = csv.rfind('\n', csv.size() - 2);
  std::stringstream row(csv.substr(lastLine + 1));
  std::string field;
  for (int i = 0; i < 4; ++i) std::getline(row, field, ',');
  return std::stod(field);
}

TEST(Recording, ReplayedRunMatchesTheRecordedTrace) {
  const std::string dir = Dir("replay");
  const std::string levelPath =
      Write(dir + "/push.toml", std::string(kObjects) + kScript + kExpect);
  Result<Level> level = LoadLevel(levelPath);
  ASSERT_TRUE(level.ok()) << level.error().Format();

  // record
  RunOptions record;
  record.record = dir + "/push.mkv";
  Result<LevelResult> recorded = RunLevel(level.value(), record);
  ASSERT_TRUE(recorded.ok()) << recorded.error().Format();
  ASSERT_EQ(recorded.value().runs.size(), 1u);
  EXPECT_EQ(RecordingTraceDir(record.record), dir + "/push_trace");
  const std::string trace = Read(dir + "/push_trace/objects.csv");
  EXPECT_EQ(recorded.value().runs[0].traceDir, "");  // no --trace: only the recording's own
  EXPECT_TRUE(fs::exists(dir + "/push_trace/frames.csv"));
  // the finger really pushed the box, so matching trajectories mean something
  EXPECT_GT(LastX(trace), 31.0);

  // replay: the same level with the recording instead of the contacts
  const std::string replayPath =
      Write(dir + "/replay.toml",
            std::string(kObjects) + "[script]\nrecording = \"push.mkv\"\n" + kExpect);
  Result<Level> replay = LoadLevel(replayPath);
  ASSERT_TRUE(replay.ok()) << replay.error().Format();
  EXPECT_EQ(replay.value().script.recordingFrames, 48);
  EXPECT_DOUBLE_EQ(replay.value().script.duration, 0.8);
  RunOptions replayTrace;
  replayTrace.traceDir = dir + "/replay_trace";
  Result<LevelResult> replayed = RunLevel(replay.value(), replayTrace);
  ASSERT_TRUE(replayed.ok()) << replayed.error().Format();
  ASSERT_EQ(replayed.value().runs.size(), 1u);
  EXPECT_EQ(replayed.value().runs[0].frames, 48);
  // exact: FFV1 is lossless, so the sensor gets the same bytes, with the same background (the
  // synthetic camera of the same [camera] table), and every later stage is deterministic; any
  // difference at all would mean the replay is not the recorded input
  EXPECT_EQ(Read(dir + "/replay_trace/objects.csv"), trace);
  // expectations still apply
  ASSERT_EQ(replayed.value().runs[0].results.size(), 1u);
  EXPECT_TRUE(replayed.value().Passed()) << FormatReport(replay.value(), replayed.value());

  // asking for more frames than were recorded stops at the recording's end
  RunOptions longer;
  longer.frames = 100;
  replayed = RunLevel(replay.value(), longer);
  ASSERT_TRUE(replayed.ok());
  EXPECT_EQ(replayed.value().runs[0].frames, 48);
}

TEST(Recording, LoaderRejectsMissingUnreadableAndMixedInputs) {
  const std::string dir = Dir("errors");
  auto load = [&](const std::string& script) {
    return LoadLevel(Write(dir + "/level.toml", std::string(kObjects) + script));
  };
  // missing: the error sits at the value, naming the file
  Result<Level> level = load("[script]\nrecording = \"nowhere.mkv\"\n");
  ASSERT_FALSE(level.ok());
  EXPECT_THAT(level.error().Format(),
              HasSubstr("level.toml:11:13: recording 'nowhere.mkv' not found"));

  // a file that is not a video
  Write(dir + "/text.mkv", "not a video\n");
  level = load("[script]\nrecording = \"text.mkv\"\n");
  ASSERT_FALSE(level.ok());
  EXPECT_THAT(level.error().Format(), HasSubstr("level.toml:11:13: recording 'text.mkv'"));

  // a recording replaces the contacts
  std::string mixed = kScript;
  mixed.replace(mixed.find("duration"), 0, "recording = \"text.mkv\"\n");
  level = load(mixed);
  ASSERT_FALSE(level.ok());
  EXPECT_THAT(level.error().message, HasSubstr("give one or the other"));

  // not a string
  level = load("[script]\nrecording = 3\n");
  ASSERT_FALSE(level.ok());
  EXPECT_THAT(level.error().message, HasSubstr("recording must be a string"));
}

TEST(Recording, RunCommandRecordsAndReportsAnUnwritableFile) {
  const std::string dir = Dir("command");
  const std::string levelPath =
      Write(dir + "/push.toml", std::string(kObjects) + kScript + kExpect);
  auto r = test::RunProxygrasp("run " + levelPath + " --record " + dir + "/clip.mkv");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/clip.mkv"));
  EXPECT_TRUE(fs::exists(dir + "/clip_trace/objects.csv"));

  r = test::RunProxygrasp("run " + levelPath + " --record " + dir + "/no/such/dir/clip.mkv");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no/such/dir/clip.mkv"));

  r = test::RunProxygrasp("run " + levelPath + " " + levelPath + " --record " + dir + "/two.mkv");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("record one level at a time"));
}

}  // namespace
}  // namespace pg
