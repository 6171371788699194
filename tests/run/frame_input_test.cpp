#include "proxygrasp/run/frame_input.h"

#include "proxygrasp/run/simulation.h"
#include "proxygrasp/run/trace.h"
#include "proxygrasp/sensing/depth_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <memory>

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

// a depth folder of `n` frames at the level's camera size, frame k a flat 1000 + k mm
std::string DepthFrames(const std::string& name, int n) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (int k = 0; k < n; ++k)
    cv::imwrite(dir + "/f_" + std::to_string(k) + ".png",
                cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000 + k)));
  return dir;
}

// a Kinect on a cable the test pulls, playing a depth folder through the real folder reader:
// unplugged, it neither opens nor delivers. `delivered` is the depth of the last frame it gave.
struct Plug {
  bool in = true;
  int delivered = -1;
};

class FolderKinect : public KinectDevice {
 public:
  FolderKinect(std::unique_ptr<FrameSource> folder, std::shared_ptr<Plug> plug)
      : m_folder(std::move(folder)), m_plug(std::move(plug)) {}
  std::string Open(int index) override {
    if (!m_plug->in) return "no Kinect " + std::to_string(index) + " (0 found)";
    m_open = true;
    return "";
  }
  bool NextFrame(double, cv::Mat& depthMm) override {
    if (!m_open || !m_plug->in || m_folder->Read(depthMm) != FrameStatus::kOk) return false;
    m_plug->delivered = depthMm.at<uint16_t>(0, 0);
    return true;
  }
  void Close() override { m_open = false; }

 private:
  std::unique_ptr<FrameSource> m_folder;
  std::shared_ptr<Plug> m_plug;
  bool m_open = false;
};

TEST(FrameInput, ADepthDeviceLostMidRunResumesWithItsNextFrameWhenItReturns) {
  const std::string dir = DepthFrames("frame_input_unplug", 5);
  Result<std::unique_ptr<FrameSource>> folder = OpenFrameSource("depth:" + dir);
  ASSERT_TRUE(folder) << folder.error().Format();
  auto plug = std::make_shared<Plug>();
  // the Kinect source (OpenKinect) on the stand-in device; Reconnect opens the spec anew when the
  // source cannot reopen: kinect:9, no more there than the real one while unplugged
  Result<std::unique_ptr<FrameSource>> kinect =
      OpenKinect(std::make_unique<FolderKinect>(std::move(folder.value()), plug), 9, "kinect:9");
  ASSERT_TRUE(kinect) << kinect.error().Format();
  FrameInput input = FrameInput::FromSource(std::move(kinect.value()), "kinect:9");
  const Level level = Push();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  // what the pipeline makes of a depth frame is not this test's business: only that it was read
  auto stepped = [&] {
    Result<FrameStatus> r = input.Step(sim);
    return r.ok() ? r.value() : FrameStatus::kOk;
  };
  EXPECT_EQ(stepped(), FrameStatus::kOk);
  EXPECT_EQ(stepped(), FrameStatus::kOk);
  EXPECT_EQ(plug->delivered, 1001);
  const int64_t skipped = input.skippedFrames();

  plug->in = false;
  for (int retry = 0; retry < 3; ++retry) {
    EXPECT_EQ(stepped(), FrameStatus::kLost);
    EXPECT_THAT(input.LastError(), HasSubstr("Kinect 9: "));
    const MaybeError again = input.Reconnect();
    ASSERT_TRUE(again);
    EXPECT_THAT(again->Format(), HasSubstr("kinect:9"));
  }
  EXPECT_EQ(plug->delivered, 1001) << "nothing is read while the device is away";
  EXPECT_EQ(input.skippedFrames(), skipped) << "a lost device is no bad frame";

  plug->in = true;
  EXPECT_FALSE(input.Reconnect());
  EXPECT_EQ(input.LastError(), "");
  EXPECT_EQ(stepped(), FrameStatus::kOk);
  EXPECT_EQ(plug->delivered, 1002) << "the run resumes with the device's next frame";
  fs::remove_all(dir);
}

TEST(FrameInput, CorruptDepthFramesAreCountedAndSkipped) {
  const Level level = Push();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  // a depth folder: an unreadable PNG and a frame of the wrong size between good ones
  const std::string dir = DepthFrames("frame_input_corrupt", 4);
  std::ofstream(dir + "/f_1.png", std::ios::trunc) << "not a png";
  cv::imwrite(dir + "/f_2.png", cv::Mat(240, 320, CV_16UC1, cv::Scalar(900)));
  Result<FrameInput> opened = FrameInput::Open("depth:" + dir);
  ASSERT_TRUE(opened) << opened.error().Format();
  FrameInput& input = opened.value();
  const int64_t afterFirst = [&] {
    (void)input.Step(sim);  // f_0: the pipeline's business
    return input.skippedFrames();
  }();
  Result<FrameStatus> corrupt = input.Step(sim);
  ASSERT_TRUE(corrupt.ok());
  EXPECT_EQ(corrupt.value(), FrameStatus::kError);
  EXPECT_THAT(input.LastError(), HasSubstr("f_1.png: cannot read the image"));
  EXPECT_EQ(input.skippedFrames(), afterFirst + 1);
  Result<FrameStatus> small = input.Step(sim);
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(small.value(), FrameStatus::kError);
  EXPECT_THAT(input.LastError(), HasSubstr("frame 2: frame is 320x240, expected 640x480"));
  EXPECT_EQ(input.skippedFrames(), afterFirst + 2);
  (void)input.Step(sim);  // f_3, read
  Result<FrameStatus> end = input.Step(sim);
  ASSERT_TRUE(end.ok());
  EXPECT_EQ(end.value(), FrameStatus::kEnd);

  // a fakenect recording whose second frame is truncated
  const std::string rec = ::testing::TempDir() + "/frame_input_fakenect";
  fs::remove_all(rec);
  Result<DepthRecordingWriter> w =
      DepthRecordingWriter::Create(rec, DepthRecordingWriter::Format::kFakenect);
  ASSERT_TRUE(w) << w.error().Format();
  for (int k = 0; k < 3; ++k)
    ASSERT_FALSE(w.value().Write(cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000)), k / 30.0));
  std::string second;
  {
    std::ifstream index(rec + "/INDEX.txt");
    std::getline(index, second);
    std::getline(index, second);
  }
  fs::resize_file(rec + "/" + second, 5000);
  Result<FrameInput> kinect = FrameInput::Open("fakenect:" + rec);
  ASSERT_TRUE(kinect) << kinect.error().Format();
  (void)kinect.value().Step(sim);
  const int64_t before = kinect.value().skippedFrames();
  Result<FrameStatus> truncated = kinect.value().Step(sim);
  ASSERT_TRUE(truncated.ok());
  EXPECT_EQ(truncated.value(), FrameStatus::kError);
  EXPECT_THAT(kinect.value().LastError(), HasSubstr(second + ": truncated"));
  EXPECT_EQ(kinect.value().skippedFrames(), before + 1);
  (void)kinect.value().Step(sim);
  EXPECT_EQ(kinect.value().Step(sim).value(), FrameStatus::kEnd);
  fs::remove_all(dir);
  fs::remove_all(rec);
}

}  // namespace
}  // namespace pg
