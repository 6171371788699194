#include "proxygrasp/sensing/recorder.h"

#include "proxygrasp/core/rng.h"
#include "proxygrasp/sensing/frame_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>

namespace pg {
namespace {

using ::testing::HasSubstr;

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / name).string();
}

TEST(Recorder, ReplaysBitForBit) {
  // noisy frames are the hardest case for a codec: any loss would show as a nonzero difference
  const std::string path = TempPath("pg_recorder_test.mkv");
  Rng rng(5);
  std::vector<cv::Mat> frames;
  FrameRecorder recorder;
  ASSERT_FALSE(recorder.Open(path, cv::Size(64, 48), 60.0));
  for (int i = 0; i < 5; ++i) {
    cv::Mat f(48, 64, CV_8UC1);
    for (int p = 0; p < f.rows * f.cols; ++p) f.data[p] = static_cast<uchar>(rng.NextU64() & 255);
    frames.push_back(f);
    ASSERT_FALSE(recorder.Write(f));
  }
  EXPECT_EQ(recorder.frames(), 5);
  recorder.Close();
  recorder.Close();

  auto source = OpenFrameSource("video:" + path);
  ASSERT_TRUE(source.ok()) << source.error().Format();
  for (int i = 0; i < 5; ++i) {
    cv::Mat f;
    ASSERT_EQ(source.value()->Read(f), FrameStatus::kOk) << "frame " << i;
    ASSERT_EQ(f.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(f, frames[static_cast<size_t>(i)], cv::NORM_INF), 0.0) << "frame " << i;
  }
  cv::Mat end;
  EXPECT_EQ(source.value()->Read(end), FrameStatus::kEnd);
  // the level loader counts a recording's frames before it replays it
  const Result<int64_t> counted = CountRecordingFrames(path);
  ASSERT_TRUE(counted.ok()) << counted.error().Format();
  EXPECT_EQ(counted.value(), 5);
  std::filesystem::remove(path);
}

TEST(Recorder, CountingFramesOfWhatIsNoVideoIsAnErrorNamingIt) {
  const std::string path = TempPath("pg_recorder_not_a_video.mkv");
  std::ofstream(path) << "not a video";
  const Result<int64_t> counted = CountRecordingFrames(path);
  ASSERT_FALSE(counted.ok());
  EXPECT_THAT(counted.error().Format(), ::testing::HasSubstr(path));
  std::filesystem::remove(path);
}

TEST(Recorder, RejectsWrongFramesAndPaths) {
  FrameRecorder recorder;
  const MaybeError notOpen = recorder.Write(cv::Mat(48, 64, CV_8UC1, cv::Scalar(0)));
  ASSERT_TRUE(notOpen);
  EXPECT_THAT(notOpen->message, HasSubstr("not open"));

  const MaybeError badPath = recorder.Open("/nonexistent-dir/x.mkv", cv::Size(64, 48), 60.0);
  ASSERT_TRUE(badPath);
  EXPECT_THAT(badPath->Format(), HasSubstr("/nonexistent-dir/x.mkv"));

  const std::string path = TempPath("pg_recorder_bad.mkv");
  ASSERT_FALSE(recorder.Open(path, cv::Size(64, 48), 60.0));
  const MaybeError wrong = recorder.Write(cv::Mat(10, 10, CV_8UC3));
  ASSERT_TRUE(wrong);
  EXPECT_THAT(wrong->message, HasSubstr("frame 0 is 10x10"));
  recorder.Close();
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace pg
