#include "proxygrasp/sensing/preview.h"

#include "proxygrasp/sensing/synthetic_camera.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pg
