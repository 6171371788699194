// Headless pictures: a level's first run drawn into a video and a PNG, the same drawing as the
// window's.
#include "proxygrasp/app/video.h"

#include "pixels.h"
#include "test_paths.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>

namespace pg {
namespace {

const std::string kLevel = std::string(pg::test::TestDataDir()) + "/box_goal.toml";

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("pg_video_" + std::to_string(getpid()) + "_" + name))
      .string();
}

TEST(RunLevelToVideo, WritesEveryFrameOfTheFirstRunAndAPng) {
  Result<Level> level = LoadLevel(kLevel);
  ASSERT_TRUE(level.ok()) << level.error().Format();
  RunOptions options;
  options.frames = 24;
  VideoOptions video;
  video.videoPath = TempPath("run.mp4");
  video.pngPath = TempPath("run.png");
  video.size = {640, 480};
  Result<LevelResult> result = RunLevelToVideo(level.value(), options, video);
  ASSERT_TRUE(result.ok()) << result.error().Format();
  ASSERT_EQ(result.value().runs.size(), 1u);
  EXPECT_EQ(result.value().runs[0].frames, 24);

  cv::VideoCapture capture(video.videoPath);
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  cv::Mat frame;
  cv::Mat first;
  while (capture.read(frame)) {
    if (frames == 0) first = frame.clone();
    ++frames;
  }
  EXPECT_EQ(frames, 24);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first.size(), cv::Size(640, 480));

  // the PNG is a lossless drawing: the box is there in its exact colour, where the level puts it
  const cv::Mat png = cv::imread(video.pngPath);
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.size(), cv::Size(640, 480));
  const DisplayMap map = DisplayMap::Fit(level.value().params.table, {640, 480});
  const test::ColorPixels box = test::FindColor(png, view_colors::Object(0), 12);
  const Vec2 centre = map.ToTable(box.centroid - cv::Point2d(0.5, 0.5));
  // at 10 px per cm, 0.15 cm is 1.5 px: the outline and the turn tick move the centroid less
  EXPECT_NEAR(centre.x(), 30.0, 0.15);
  EXPECT_NEAR(centre.y(), 23.0, 0.15);
  // mp4v is lossy, yet the box's colour survives in the video's frames to within a few levels
  const cv::Vec3b inVideo = first.at<cv::Vec3b>(cv::Point(map.ToDisplay({29, 22})));
  const cv::Scalar expected = view_colors::Object(0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(inVideo[c], expected[c], 20) << "channel " << c;

  std::filesystem::remove(video.videoPath);
  std::filesystem::remove(video.pngPath);
}

TEST(RunLevelToVideo, AnUnwritableFileIsAnErrorNamingIt) {
  Result<Level> level = LoadLevel(kLevel);
  ASSERT_TRUE(level.ok());
  RunOptions options;
  options.frames = 2;
  VideoOptions video;
  video.pngPath = "/proc/not_here/run.png";
  Result<LevelResult> result = RunLevelToVideo(level.value(), options, video);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().Format().find("/proc/not_here/run.png"), std::string::npos)
      << result.error().Format();
}

}  // namespace
}  // namespace pg
