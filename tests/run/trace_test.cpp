#include "proxygrasp/run/trace.h"

#include "proxygrasp/run/simulation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "run/test_levels.h"

namespace pg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// two boxes and a fingertip moving towards one of them
Level TwoBoxes() {
  return test::ParseOrFail(test::BoxToml("left", 20, 23) + test::BoxToml("right", 40, 23) +
                               test::FingerToml("finger", 30, 23, 0, 35, 23, 1),
                           "trace.toml");
}

TEST(Trace, RecordingTraceDirSitsBesideTheVideo) {
  EXPECT_EQ(RecordingTraceDir("runs/push.mkv"), "runs/push_trace");
  EXPECT_EQ(RecordingTraceDir("push.mkv"), "push_trace");
}

TEST(Trace, StreamsOneRowPerObjectAndOnePerFrame) {
  const Level level = TwoBoxes();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  const std::string dir = (fs::temp_directory_path() / "pg_trace_rows").string();
  fs::remove_all(dir);
  TraceWriter trace;
  ASSERT_FALSE(trace.Open(dir + "/nested"));  // parents are created
  EXPECT_TRUE(trace.IsOpen());
  for (int i = 0; i < 3; ++i) {
    ASSERT_FALSE(sim.StepScript());
    ASSERT_FALSE(trace.Write(sim));
  }
  EXPECT_EQ(trace.frames(), 3);
  ASSERT_FALSE(trace.Close());
  EXPECT_FALSE(trace.IsOpen());
  EXPECT_FALSE(trace.Close()) << "closing twice is safe";

  const std::string objects = ReadText(dir + "/nested/objects.csv");
  EXPECT_THAT(objects, StartsWith(std::string(kObjectsCsvHeader) + "\n"));
  EXPECT_EQ(std::count(objects.begin(), objects.end(), '\n'), 1 + 3 * 2);
  // the last frame is frame 2, at the end of its 1/60 s: t = 3/60 s; boxes at rest keep exactly
  // their starting pose
  EXPECT_THAT(objects, HasSubstr("\n2,0.050000,left,20.000000,23.000000,0.000000,"));
  EXPECT_THAT(objects, HasSubstr("\n2,0.050000,right,40.000000,23.000000,0.000000,"));
  const std::string frames = ReadText(dir + "/nested/frames.csv");
  EXPECT_THAT(frames, StartsWith(std::string(kFramesCsvHeader) + "\n"));
  EXPECT_EQ(std::count(frames.begin(), frames.end(), '\n'), 1 + 3);
  EXPECT_EQ(frames.substr(frames.rfind("\n2,")).substr(0, 14), "\n2,0.050000,1,");
  EXPECT_EQ(FrameRow(sim.stats(), sim.Time()).substr(0, 13), "2,0.050000,1,");
  fs::remove_all(dir);
}

TEST(Trace, RecordsTheCameraFramesBesideTheRows) {
  const Level level = TwoBoxes();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  const std::string dir = (fs::temp_directory_path() / "pg_trace_video").string();
  fs::remove_all(dir);
  fs::create_directories(dir);
  TraceWriter trace;
  ASSERT_FALSE(trace.Open(dir, dir + "/input.mkv", sim.CameraSize(), 60.0));
  for (int i = 0; i < 4; ++i) {
    ASSERT_FALSE(sim.StepScript());
    ASSERT_FALSE(trace.Write(sim));
  }
  ASSERT_FALSE(trace.Close());
  EXPECT_GT(fs::file_size(dir + "/input.mkv"), 0u);
  EXPECT_TRUE(fs::exists(dir + "/objects.csv"));
  fs::remove_all(dir);
}

TEST(Trace, UnwritablePlacesAreErrorsNamingThem) {
  TraceWriter trace;
  const MaybeError folder = trace.Open("/proc/pg_no_trace_here");
  ASSERT_TRUE(folder);
  EXPECT_THAT(folder->Format(), HasSubstr("/proc/pg_no_trace_here"));
  EXPECT_FALSE(trace.IsOpen());

  const std::string dir = (fs::temp_directory_path() / "pg_trace_badvideo").string();
  fs::remove_all(dir);
  const MaybeError video =
      trace.Open(dir, "/proc/pg_no_video_here/input.mkv", cv::Size(640, 480), 60);
  ASSERT_TRUE(video);
  EXPECT_THAT(video->Format(), HasSubstr("/proc/pg_no_video_here/input.mkv"));
  EXPECT_FALSE(trace.IsOpen()) << "nothing stays open after a failed Open";

  Simulation sim;
  const MaybeError closed = trace.Write(sim);
  ASSERT_TRUE(closed);
  EXPECT_THAT(closed->Format(), HasSubstr("not open"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pg
