#include "proxygrasp/run/frame_input.h"

#include "proxygrasp/run/simulation.h"
#include "proxygrasp/run/trace.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "run/test_levels.h"

namespace pg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// a fingertip pushing a box 2 cm over half a second
Level Push() {
  return test::ParseOrFail(
      test::BoxToml("box", 30, 23) + test::FingerToml("finger", 26, 23, 0, 29.2, 23, 0.5),
      "frame_input.toml");
}

TEST(FrameInput, ScriptAndShapesStepThroughTheCamera) {
  const Level level = Push();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  FrameInput script = FrameInput::Script();
  EXPECT_EQ(script.Describe(), "script");
  Result<FrameStatus> stepped = script.Step(sim);
  ASSERT_TRUE(stepped.ok());
  EXPECT_EQ(stepped.value(), FrameStatus::kOk);
  EXPECT_EQ(sim.Frame(), 1);
  EXPECT_EQ(sim.stats().contacts, 1);

  FrameInput shapes = FrameInput::Shapes();
  ContactShape a;
  a.pose.pos = Vec2(10, 10);
  ContactShape b = a;
  b.pose.pos = Vec2(50, 10);
  const std::vector<ContactShape> two = {a, b};
  shapes.SetShapes(two);
  ASSERT_TRUE(shapes.Step(sim).ok());
  EXPECT_EQ(sim.Frame(), 2);
  EXPECT_EQ(sim.shapes().size(), 2u);
  // the two shapes, and the script's fingertip (at 26, 23), which the tracker keeps where it was
  // for keep_lost frames after it is gone
  EXPECT_EQ(sim.stats().contacts, 3);
}

TEST(FrameInput, ContoursSkipTheCameraAndGiveTheSameRun) {
  // contours sensed by one run, handed to a second run as contours (as a tracker speaking TUIO
  // would hand them): tracking, proxies and physics see the same input, so the object trace of
  // the second run equals the first byte for byte
  const Level level = Push();
  Simulation sensed;
  Simulation given;
  ASSERT_FALSE(sensed.Start(level, level.params));
  ASSERT_FALSE(given.Start(level, level.params));
  FrameInput script = FrameInput::Script();
  FrameInput contours = FrameInput::Contours();
  EXPECT_EQ(contours.Describe(), "contours");
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(script.Step(sensed).ok());
    contours.SetContours(sensed.contours());
    Result<FrameStatus> stepped = contours.Step(given);
    ASSERT_TRUE(stepped.ok());
    ASSERT_EQ(stepped.value(), FrameStatus::kOk);
    ASSERT_EQ(ObjectRows(given), ObjectRows(sensed)) << "frame " << i;
  }
  EXPECT_TRUE(given.cameraImage().empty()) << "no camera image for given contours";
  EXPECT_EQ(given.stats().senseMs, 0.0);
  // the push moved the box (so equal traces mean something)
  EXPECT_GT(given.world().Object(0).pose.pos.x(), 30.5);
}

TEST(FrameInput, SourceFramesOfTheWrongSizeAreBadFramesThatDoNotStep) {
  const std::string dir = (fs::temp_directory_path() / "pg_frame_input_folder").string();
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Level level = Push();
  ASSERT_TRUE(cv::imwrite(dir + "/frame_1.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(0))));
  ASSERT_TRUE(cv::imwrite(dir + "/frame_2.png", cv::Mat(240, 320, CV_8UC1, cv::Scalar(0))));
  Result<FrameInput> opened = FrameInput::Open("folder:" + dir);
  ASSERT_TRUE(opened.ok()) << opened.error().Format();
  FrameInput& input = opened.value();
  EXPECT_TRUE(input.HasSource());
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));

  // Peek reads the first frame ahead; the next Step delivers that frame, not the second
  EXPECT_EQ(input.Peek(), FrameStatus::kOk);
  EXPECT_EQ(input.PeekedSize(), cv::Size(640, 480));
  Result<FrameStatus> first = input.Step(sim);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first.value(), FrameStatus::kOk);
  EXPECT_EQ(sim.Frame(), 1);

  Result<FrameStatus> second = input.Step(sim);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second.value(), FrameStatus::kError);
  EXPECT_THAT(input.LastError(),
              HasSubstr("frame 1: frame is 320x240, expected 640x480 ([camera] width and height)"));
  EXPECT_EQ(sim.Frame(), 1) << "a bad frame does not step the run";

  Result<FrameStatus> end = input.Step(sim);
  ASSERT_TRUE(end.ok());
  EXPECT_EQ(end.value(), FrameStatus::kEnd);
  // a folder reopens from its first frame
  EXPECT_FALSE(input.Reconnect());
  EXPECT_EQ(input.Step(sim).value(), FrameStatus::kOk);
  fs::remove_all(dir);
}

TEST(FrameInput, AMissingCameraIsAnErrorOrKeptToBeRetried) {
  const Result<FrameInput> strict = FrameInput::Open("camera:97");
  ASSERT_FALSE(strict.ok());
  EXPECT_THAT(strict.error().Format(), HasSubstr("97"));

  Result<FrameInput> kept = FrameInput::Open("camera:97", /*keepMissing=*/true);
  ASSERT_TRUE(kept.ok());
  FrameInput& input = kept.value();
  EXPECT_FALSE(input.HasSource());
  EXPECT_THAT(input.LastError(), HasSubstr("97"));
  const Level level = Push();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  Result<FrameStatus> stepped = input.Step(sim);
  ASSERT_TRUE(stepped.ok());
  EXPECT_EQ(stepped.value(), FrameStatus::kLost);
  EXPECT_EQ(sim.Frame(), 0);
  const MaybeError again = input.Reconnect();
  ASSERT_TRUE(again);
  EXPECT_THAT(again->Format(), HasSubstr("97"));
}

}  // namespace
}  // namespace pg
