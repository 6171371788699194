#include "proxygrasp/sensing/preview.h"

#include "proxygrasp/sensing/synthetic_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace pg {
namespace {

TEST(SensingPreview, EmptyBeforeTheFirstFrame) {
  Sensor sensor;
  EXPECT_TRUE(SensingPreview(sensor, {}).empty());
}

TEST(SensingPreview, ShowsEveryStageAndTheContactOutlines) {
  TableParams table;
  SyntheticCamera camera(SyntheticCameraParams{}, table);
  Sensor sensor;
  ASSERT_FALSE(sensor.Configure(SensingParams{}, table, CalibrationFromModel(camera.model())));
  ASSERT_FALSE(sensor.SetBackground(camera.Background()));
  ContactShape tip;
  tip.pose.pos = {30.0, 20.0};
  const ContactShape shapes[] = {tip};
  Result<ContourFrame> r = sensor.Step(camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);

  // 7 tiles (camera and 6 stages) in 4 columns: 2 rows of 640x480
  const cv::Mat view = SensingPreview(sensor, {{&r.value().blobs[0], 3}});
  ASSERT_EQ(view.size(), cv::Size(4 * 640, 2 * 480));
  EXPECT_EQ(view.type(), CV_8UC3);
  // the outline is drawn in green on the camera tile, on the fingertip's edge (0.8 cm radius)
  const Vec2 edge = camera.model().TableToCamera(Vec2(30.8, 20.0));
  int green = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const cv::Vec3b p =
          view.at<cv::Vec3b>(static_cast<int>(edge.y()) + dy, static_cast<int>(edge.x()) + dx);
      green += p[1] > 200 && p[0] < 100 && p[2] < 100;
    }
  EXPECT_GT(green, 0);
  // the binary tile (the 7th: row 1, column 2) is white at the fingertip's centre
  const Vec2 c = camera.model().TableToCamera(Vec2(30.0, 20.0));
  const cv::Vec3b b =
      view.at<cv::Vec3b>(480 + static_cast<int>(c.y()), 2 * 640 + static_cast<int>(c.x()));
  EXPECT_EQ(b, cv::Vec3b(255, 255, 255));

  // at half scale (what a window shows): tiles of 320x240, the outline drawn at that size
  const cv::Mat half = SensingPreview(sensor, {{&r.value().blobs[0], 3}}, 4, 0.5);
  ASSERT_EQ(half.size(), cv::Size(4 * 320, 2 * 240));
  int halfGreen = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const cv::Vec3b p = half.at<cv::Vec3b>(static_cast<int>(0.5 * edge.y()) + dy,
                                             static_cast<int>(0.5 * edge.x()) + dx);
      halfGreen += p[1] > 200 && p[0] < 100 && p[2] < 100;
    }
  EXPECT_GT(halfGreen, 0);
  EXPECT_EQ(half.at<cv::Vec3b>(240 + static_cast<int>(0.5 * c.y()),
                               2 * 320 + static_cast<int>(0.5 * c.x())),
            cv::Vec3b(255, 255, 255));
  // a scale that is not positive gives nothing
  EXPECT_TRUE(SensingPreview(sensor, {}, 4, 0.0).empty());
}

// The difference stages are brightened so that the threshold shows as grey 128: by 128 / 30 at
// the threshold of 30 (gain 1); by 64 at most (a threshold of 1 would ask 128); never darkened
// (a threshold of 200 would ask 0.64). The subtracted tile (the 3rd: row 0, column 2) must be the
// stage image times that factor, saturated at 255, pixel for pixel (above the label's rows); the
// factor 128 / 30 leaves the fingertip's rim (levels under 60) unsaturated, so the factor itself
// is checked there. The binary tile stays 0/255.
TEST(SensingPreview, BrightensTheDifferenceStagesSoThatTheThresholdIsMidGrey) {
  TableParams table;
  SyntheticCamera camera(SyntheticCameraParams{}, table);
  ContactShape tip;
  tip.pose.pos = {30.0, 20.0};
  const ContactShape shapes[] = {tip};
  const cv::Mat frame = camera.Render(shapes);
  for (double threshold : {30.0, 1.0, 200.0}) {
    SensingParams sp;
    sp.thresholdMode = ThresholdMode::kFixed;
    sp.threshold = threshold;
    Sensor sensor;
    ASSERT_FALSE(sensor.Configure(sp, table, CalibrationFromModel(camera.model())));
    ASSERT_FALSE(sensor.SetBackground(camera.Background()));
    ASSERT_TRUE(sensor.Step(frame, 0, 0.0));
    const double stretch = std::clamp(128.0 / threshold, 1.0, 64.0);
    const cv::Mat view = SensingPreview(sensor, {});
    const cv::Rect above(0, 0, 640, 440);  // the label is in the tile's bottom rows
    cv::Mat shown;
    cv::extractChannel(view(cv::Rect(2 * 640, 0, 640, 480)), shown, 0);
    cv::Mat expected;
    sensor.StageImage(SensingStage::kSubtracted).convertTo(expected, CV_8UC1, stretch);
    EXPECT_EQ(cv::norm(shown(above), expected(above), cv::NORM_INF), 0.0)
        << "threshold " << threshold;
    if (threshold == 30.0) {
      // some rim pixels of the fingertip lie between 10 and 255 / stretch: shown unsaturated
      const cv::Mat& sub = sensor.StageImage(SensingStage::kSubtracted);
      int unsaturated = 0;
      for (int y = 0; y < 440; ++y)
        for (int x = 0; x < 640; ++x)
          unsaturated += sub.at<uint8_t>(y, x) >= 10 && sub.at<uint8_t>(y, x) * stretch < 254.0;
      EXPECT_GT(unsaturated, 10);
    }
    const cv::Mat& binary = sensor.StageImage(SensingStage::kBinary);
    cv::Mat shownBinary;
    cv::extractChannel(view(cv::Rect(2 * 640, 480, 640, 480)), shownBinary, 0);
    EXPECT_EQ(cv::norm(shownBinary(above), binary(above), cv::NORM_INF), 0.0);
  }
}

}  // namespace
}  // namespace pg
