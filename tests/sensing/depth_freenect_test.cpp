// The live Kinect source on a stand-in device (KinectDevice): what it does when the device stops
// delivering and when it comes back. The libfreenect layer itself needs a Kinect: without one its
// open is an error naming it (depth_source_test.cpp, DepthDevices).
#include "proxygrasp/sensing/depth_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>

namespace pg {
namespace {

using ::testing::HasSubstr;

// a Kinect on a cable the test pulls: unplugged, it neither opens nor delivers; its frames are a
// flat 1000 + n mm, n counting the frames it delivered
struct Cable {
  bool plugged = true;
  int delivered = 0;
  int opens = 0;
};

class StandInKinect : public KinectDevice {
 public:
  explicit StandInKinect(std::shared_ptr<Cable> cable) : m_cable(std::move(cable)) {}
  std::string Open(int index) override {
    if (!m_cable->plugged) return "no Kinect " + std::to_string(index) + " (0 found)";
    ++m_cable->opens;
    m_open = true;
    return "";
  }
  bool NextFrame(double, cv::Mat& depthMm) override {
    if (!m_open || !m_cable->plugged) return false;
    depthMm = cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000 + m_cable->delivered++));
    return true;
  }
  void Close() override { m_open = false; }

 private:
  std::shared_ptr<Cable> m_cable;
  bool m_open = false;
};

TEST(KinectSource, ALostKinectReadsLostUntilItIsBackThenGoesOn) {
  auto cable = std::make_shared<Cable>();
  Result<std::unique_ptr<FrameSource>> opened =
      OpenKinect(std::make_unique<StandInKinect>(cable), 0, "kinect:0");
  ASSERT_TRUE(opened) << opened.error().Format();
  FrameSource& kinect = *opened.value();
  EXPECT_EQ(kinect.Describe(), "Kinect 0");
  cv::Mat frame;
  ASSERT_EQ(kinect.Read(frame), FrameStatus::kOk);
  ASSERT_EQ(kinect.Read(frame), FrameStatus::kOk);
  EXPECT_EQ(frame.at<uint16_t>(0, 0), 1001);

  cable->plugged = false;
  EXPECT_EQ(kinect.Read(frame), FrameStatus::kLost);
  EXPECT_EQ(kinect.LastError(), "Kinect 0: the Kinect stopped delivering frames");
  const MaybeError away = kinect.Reopen();
  ASSERT_TRUE(away);
  EXPECT_THAT(away->Format(), HasSubstr("kinect:0: no Kinect 0 (0 found)"));
  EXPECT_EQ(kinect.Read(frame), FrameStatus::kLost) << "a device that did not reopen stays lost";
  EXPECT_EQ(kinect.LastError(), "Kinect 0: not open");

  cable->plugged = true;
  EXPECT_FALSE(kinect.Reopen());
  EXPECT_EQ(cable->opens, 2);
  ASSERT_EQ(kinect.Read(frame), FrameStatus::kOk);
  EXPECT_EQ(frame.at<uint16_t>(0, 0), 1002) << "the device's next frame";
  EXPECT_EQ(kinect.LastError(), "");
}

TEST(KinectSource, AKinectThatIsNotThereIsAnErrorNamingTheSpec) {
  auto cable = std::make_shared<Cable>();
  cable->plugged = false;
  Result<std::unique_ptr<FrameSource>> opened =
      OpenKinect(std::make_unique<StandInKinect>(cable), 3, "kinect:3");
  ASSERT_FALSE(opened);
  EXPECT_EQ(opened.error().Format(), "kinect:3: no Kinect 3 (0 found)");
}

}  // namespace
}  // namespace pg
