#include "proxygrasp/run/trace.h"

#include "test_paths.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/sensing/depth_source.h"
#include "proxygrasp/sensing/synthetic_camera.h"

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

// field k (from 0) of a CSV line, without its newline
std::string Field(const std::string& line, int k) {
  // a comma after the last field, so that an empty last field reads as one
  std::stringstream in(line.substr(0, line.find('\n')) + ",");
  std::string field;
  for (int i = 0; i <= k; ++i)
    if (!std::getline(in, field, ',')) return "<missing>";
  return field;
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

TEST(Trace, ADepthRecordingsTraceSitsBesideItsFolder) {
  EXPECT_EQ(RecordingTraceDir("depth:runs/push"), "runs/push_trace");
  EXPECT_EQ(RecordingTraceDir("fakenect:runs/push/"), "runs/push_trace");
}

TEST(Trace, RecordsDepthFramesAsDepthAndFakenectRecordings) {
  // the synthetic depth camera's frames through the trace writer, read back through the depth
  // sources: PNGs keep the mm, fakenect the raw disparity every reading lies on
  SyntheticCameraParams params;
  params.kind = CameraKind::kDepth;
  SyntheticCamera camera(params, TableParams{});
  ContactShape finger;
  finger.pose.pos = {20, 20};
  std::vector<cv::Mat> frames;
  for (int f = 0; f < 3; ++f) {
    finger.height = 0.5 * f;
    frames.push_back(camera.Render({&finger, 1}));
  }
  const std::string root = (fs::temp_directory_path() / "pg_trace_depth").string();
  fs::remove_all(root);
  for (const std::string format : {"depth", "fakenect"}) {
    const std::string spec = format + ":" + root + "/" + format;
    TraceWriter trace;
    ASSERT_FALSE(trace.Open(RecordingTraceDir(spec), spec, cv::Size(640, 480), 60.0));
    for (size_t f = 0; f < frames.size(); ++f) ASSERT_FALSE(trace.WriteCamera(frames[f], f / 60.0));
    // an IR frame is refused, naming the recording
    const MaybeError ir = trace.WriteCamera(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), 0.05);
    ASSERT_TRUE(ir);
    EXPECT_THAT(ir->Format(), HasSubstr(spec));
    EXPECT_THAT(ir->Format(), HasSubstr("kind = \"depth\""));
    ASSERT_FALSE(trace.Close());
    EXPECT_TRUE(fs::exists(root + "/" + format + "_trace/objects.csv"));
    Result<std::unique_ptr<FrameSource>> source = OpenDepthSource(spec);
    ASSERT_TRUE(source.ok()) << source.error().Format();
    for (const cv::Mat& frame : frames) {
      cv::Mat back;
      ASSERT_EQ(source.value()->Read(back), FrameStatus::kOk) << format;
      EXPECT_EQ(cv::countNonZero(back != frame), 0) << format;
    }
    cv::Mat end;
    EXPECT_EQ(source.value()->Read(end), FrameStatus::kEnd) << format;
  }
  // and a video refuses depth frames, saying where they go
  TraceWriter video;
  ASSERT_FALSE(video.Open(root + "/video_trace", root + "/input.mkv", cv::Size(640, 480), 60.0));
  const MaybeError depth = video.WriteCamera(frames[0], 0.0);
  ASSERT_TRUE(depth);
  EXPECT_THAT(depth->Format(), HasSubstr("depth:DIR or fakenect:DIR"));
  ASSERT_FALSE(video.Close());
  fs::remove_all(root);
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
  EXPECT_EQ(FrameRow(sim).substr(0, 13), "2,0.050000,1,");
  // the IR camera measures no heights and no hover: height and hover_height empty, hover 0
  const std::string last = frames.substr(frames.rfind("\n2,") + 1);
  EXPECT_EQ(Field(last, 9), "");
  EXPECT_EQ(Field(last, 10), "0");
  EXPECT_EQ(Field(last, 11), "");
  // contacts.csv: the fingertip in each frame, new then continuing, without a height
  const std::string contacts = ReadText(dir + "/nested/contacts.csv");
  EXPECT_THAT(contacts, StartsWith(std::string(kContactsCsvHeader) + "\n"));
  EXPECT_EQ(std::count(contacts.begin(), contacts.end(), '\n'), 1 + 3);
  EXPECT_THAT(contacts, HasSubstr("\n0,0.016667,1,new,"));
  const std::string lastContact = contacts.substr(contacts.rfind("\n2,") + 1);
  EXPECT_EQ(Field(lastContact, 3), "continuing");
  EXPECT_EQ(Field(lastContact, 7), "");
  EXPECT_EQ(ContactRows(sim), lastContact);
  fs::remove_all(dir);
}

TEST(Trace, ADepthRecordingsTraceKeepsTheHeights) {
  // side_push on the synthetic depth camera, recorded as `run --record depth:DIR` records it
  Result<Level> loaded = LoadLevel(std::string(pg::test::SourceDir()) + "/levels/side_push.toml");
  ASSERT_TRUE(loaded.ok()) << loaded.error().Format();
  Level level = std::move(loaded.value());
  ASSERT_FALSE(ApplyOverrides(level, {"camera.kind=depth"}));
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  const std::string root = (fs::temp_directory_path() / "pg_trace_heights").string();
  fs::remove_all(root);
  const std::string spec = "depth:" + root + "/push";
  TraceWriter trace;
  ASSERT_FALSE(trace.Open(RecordingTraceDir(spec), spec, sim.CameraSize(), 60.0));
  const int kFrames = 40;
  std::vector<std::string> expected(kFrames);  // each frame's mean contact height, as written
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_FALSE(sim.StepScript());
    ASSERT_FALSE(trace.Write(sim));
    double sum = 0.0;
    int n = 0;
    for (const Contact& c : sim.contacts().contacts) {
      // touches: hover regions, tracked too for measured placement, are not counted
      if (c.state == ContactState::kLifted || c.blob.heights.empty() || c.blob.hover) continue;
      double own = 0.0;
      for (double h : c.blob.heights) own += h;
      sum += own / static_cast<double>(c.blob.heights.size());
      ++n;
    }
    if (n > 0) expected[i] = FormatFixed(sum / n, 4);
  }
  ASSERT_FALSE(trace.Close());

  const DepthParams& depth = level.params.depth;
  std::stringstream frames(ReadText(root + "/push_trace/frames.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(frames, line));
  EXPECT_EQ(line, kFramesCsvHeader);
  int withHeight = 0, withHover = 0;
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_TRUE(std::getline(frames, line)) << i;
    SCOPED_TRACE(line);
    EXPECT_EQ(Field(line, 9), expected[i]);
    if (!expected[i].empty()) {
      ++withHeight;
      // a touch region's heights are medians of pixels inside the touch band, so their means lie
      // in it: [touch_low, touch_high] = [0.5, 2.0] cm
      EXPECT_GE(std::stod(expected[i]), depth.touchLow);
      EXPECT_LE(std::stod(expected[i]), depth.touchHigh);
    }
    const int hover = std::stoi(Field(line, 10));
    EXPECT_EQ(Field(line, 11).empty(), hover == 0);
    if (hover > 0) {
      ++withHover;
      // hover pixels lie above touch_high and at most hover_ceiling
      EXPECT_GT(std::stod(Field(line, 11)), depth.touchHigh);
      EXPECT_LE(std::stod(Field(line, 11)), depth.hoverCeiling);
    }
  }
  // the level gives the depth chain the synthetic camera's clear table as its surface, so the
  // fingertip touching from the first frame is a contact in every frame, and the finger rising
  // from it (25 degrees, 6 cm long) reaches above the band: a hover region in every frame
  EXPECT_EQ(withHeight, kFrames);
  EXPECT_EQ(withHover, kFrames);
  // contacts.csv has each contact's own mean height
  const std::string contacts = ReadText(root + "/push_trace/contacts.csv");
  EXPECT_THAT(contacts, StartsWith(std::string(kContactsCsvHeader) + "\n"));
  EXPECT_EQ(ContactRows(sim),
            contacts.substr(contacts.find("\n" + std::to_string(kFrames - 1) + ",") + 1));
  fs::remove_all(root);
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
