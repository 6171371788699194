#include "proxygrasp/sensing/preview.h"

#include "proxygrasp/sensing/synthetic_camera.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

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

// --- the depth chain's view ---

// The height tile's colours from the band's edges (defaults: touch_low 0.5, touch_high 2.0,
// hover_ceiling 30 cm, so 5, 20 and 300 mm, on a pixel whose lower edge is touch_low): grey below
// 5 mm, green from kBandDarkest at 5 mm to 255 at 20 mm, blue (255, 200 t, 0) with t from 0 just
// above 20 mm to 1 at 300 mm, white above. The greys run from kBelowDarkest at -5 mm to
// kBelowBrightest at 5 mm, so 0 mm is their mean 90. The mid-band green: 140 + (12.5 - 5) / 15 x
// 115 = 197.5, truncated to 197.
TEST(DepthPreview, HeightColoursMarkTheBandsEdges) {
  namespace dc = depth_colors;
  const DepthParams p;
  const float low = 5.0f;
  EXPECT_EQ(HeightColour(0.0f, low, p), cv::Vec3b(90, 90, 90));
  EXPECT_EQ(HeightColour(-50.0f, low, p),
            cv::Vec3b(dc::kBelowDarkest, dc::kBelowDarkest, dc::kBelowDarkest));
  EXPECT_EQ(HeightColour(4.99f, low, p)[1], HeightColour(4.99f, low, p)[0]);  // grey just below
  EXPECT_EQ(HeightColour(5.0f, low, p), cv::Vec3b(0, dc::kBandDarkest, 0));
  EXPECT_EQ(HeightColour(12.5f, low, p), cv::Vec3b(0, 197, 0));
  EXPECT_EQ(HeightColour(20.0f, low, p), cv::Vec3b(0, 255, 0));
  EXPECT_EQ(HeightColour(20.01f, low, p), cv::Vec3b(255, 0, 0));  // blue just above the band
  EXPECT_EQ(HeightColour(300.0f, low, p), cv::Vec3b(255, 200, 0));
  EXPECT_EQ(HeightColour(300.5f, low, p), dc::kAboveCeiling);
  // a band moved live moves the colours with it: 12.5 mm is above a band ending at 1 cm
  DepthParams lower = p;
  lower.touchHigh = 1.0;
  EXPECT_EQ(HeightColour(12.5f, low, lower)[0], 255);
  EXPECT_EQ(HeightColour(12.5f, low, lower)[2], 0);
  // a noisy pixel's band starts higher: at 10 mm, 12.5 mm is 140 + 2.5 / 10 x 115 = 168.75 (168)
  EXPECT_EQ(HeightColour(12.5f, 10.0f, p), cv::Vec3b(0, 168, 0));
  EXPECT_EQ(HeightColour(8.0f, 10.0f, p)[1], HeightColour(8.0f, 10.0f, p)[0]);
  // and above touch_high it has no band: grey up to its edge (25 mm), hover above it (as the
  // sensor's hover starts at the higher of the two), never green; an edge under touch_low is
  // touch_low
  EXPECT_EQ(HeightColour(22.0f, 25.0f, p)[1], HeightColour(22.0f, 25.0f, p)[0]);
  EXPECT_EQ(HeightColour(26.0f, 25.0f, p), cv::Vec3b(255, 0, 0));
  EXPECT_EQ(HeightColour(4.0f, 1.0f, p)[1], HeightColour(4.0f, 1.0f, p)[0]);
}

TEST(DepthPreview, EmptyBeforeTheFirstFrame) {
  DepthSensor sensor;
  EXPECT_TRUE(DepthPreview(sensor, {}, {}).empty());
  ASSERT_FALSE(sensor.Configure(DepthParams{}, SensingParams{}, TableParams{}, {640, 480}));
  EXPECT_TRUE(DepthPreview(sensor, {}, {}).empty());
}

// The expected false colour of a depth: level 255 (far - d) / (far - near), saturated, through
// OpenCV's turbo map (DepthPreview's header gives the scale: near and far from the surface).
cv::Vec3b Turbo(double level) {
  cv::Mat grey(1, 1, CV_8UC1, cv::Scalar(std::clamp(std::round(level), 0.0, 255.0)));
  cv::Mat bgr;
  cv::applyColorMap(grey, bgr, cv::COLORMAP_TURBO);
  return bgr.at<cv::Vec3b>(0, 0);
}

int Channel(const cv::Vec3b& a, const cv::Vec3b& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

// A flat surface 1000 mm away (noise 0.5 mm), then one frame with a fingertip-sized disk (radius
// 30 px) 12 mm up at (200, 240), a palm (radius 50 px) 50 mm up at (450, 240) and a hole (no
// reading) over x 100-139, y 50-79. The band's lower edge is max(touch_low 5 mm, noise_factor 4 x
// max(0.5, the floor 1.5 mm at 1 m)) = 6 mm, its upper edge 20 mm: the disk touches, the palm
// hovers (20 to 300 mm), the hole is in neither (it stands the surface's 1000 mm up). Five tiles of
// 640x480 in 3 columns: depth, surface, height; touch, hover.
TEST(DepthPreview, ShowsDepthSurfaceHeightTouchAndHover) {
  namespace dc = depth_colors;
  DepthSensor sensor;
  ASSERT_FALSE(sensor.Configure(DepthParams{}, SensingParams{}, TableParams{}, {640, 480}));
  ASSERT_FALSE(sensor.SetSurface(cv::Mat(480, 640, CV_32F, cv::Scalar(1000.0f)), 0.5));
  cv::Mat mm(480, 640, CV_16UC1, cv::Scalar(1000));
  cv::circle(mm, {200, 240}, 30, cv::Scalar(988), cv::FILLED);
  cv::circle(mm, {450, 240}, 50, cv::Scalar(950), cv::FILLED);
  mm(cv::Rect(100, 50, 40, 30)).setTo(0);
  Result<ContourFrame> r = sensor.Step(mm, 0, 0.0);
  ASSERT_TRUE(r) << r.error().Format();
  ASSERT_EQ(r.value().blobs.size(), 1u);
  ASSERT_EQ(r.value().hover.size(), 1u);

  const cv::Mat view = DepthPreview(sensor, {{&r.value().blobs[0], 7}}, r.value().hover);
  ASSERT_EQ(view.size(), cv::Size(3 * 640, 2 * 480));
  ASSERT_EQ(view.type(), CV_8UC3);
  const auto at = [&](int tile, int x, int y) {
    return view.at<cv::Vec3b>((tile / 3) * 480 + y, (tile % 3) * 640 + x);
  };
  enum { kDepthTile, kSurfaceTile, kHeightTile, kTouchTile, kHoverTile };
  const cv::Point table(320, 400), touch(190, 245), palm(430, 245), hole(120, 65);

  // the hole: magenta in depth and height, dark magenta on the masks
  EXPECT_EQ(at(kDepthTile, hole.x, hole.y), dc::kNoReading);
  EXPECT_EQ(at(kHeightTile, hole.x, hole.y), dc::kNoReading);
  EXPECT_EQ(at(kTouchTile, hole.x, hole.y), dc::kNoReadingMask);
  EXPECT_EQ(at(kHoverTile, hole.x, hole.y), dc::kNoReadingMask);

  // depth and surface on one scale: near 1000 - 2 x 20 = 960 mm, far 1000 + 20 = 1020 mm. The
  // table (1000 mm) is level 255 x 20 / 60 = 85, the fingertip (988) 255 x 32 / 60 = 136, the palm
  // (950) saturates at 255; all three levels are whole numbers, so the colours are exact. The
  // surface is 1000 mm everywhere (the first frame has no time step: nothing is learned).
  EXPECT_EQ(at(kDepthTile, table.x, table.y), Turbo(85.0));
  EXPECT_EQ(at(kDepthTile, touch.x, touch.y), Turbo(136.0));
  EXPECT_EQ(at(kDepthTile, palm.x, palm.y), Turbo(255.0));
  EXPECT_EQ(at(kSurfaceTile, touch.x, touch.y), Turbo(85.0));
  // and the touch stands out of the table: a channel differs by more than a third of its range
  EXPECT_GT(Channel(at(kDepthTile, touch.x, touch.y), at(kDepthTile, table.x, table.y)), 85);

  // height, with each pixel's band from 6 mm: the table grey 90 (0 mm: half way from -6 to 6),
  // the fingertip green 140 + (12 - 6) / 14 x 115 = 189.3 (189), the palm blue (255, 200 x 30 /
  // 280 = 21.4 (21), 0)
  EXPECT_EQ(at(kHeightTile, table.x, table.y), cv::Vec3b(90, 90, 90));
  EXPECT_EQ(at(kHeightTile, touch.x, touch.y), cv::Vec3b(0, 189, 0));
  EXPECT_EQ(at(kHeightTile, palm.x, palm.y), cv::Vec3b(255, 21, 0));

  // touch and hover masks: white where each is, black elsewhere
  EXPECT_EQ(at(kTouchTile, touch.x, touch.y), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(at(kTouchTile, palm.x, palm.y), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(at(kTouchTile, table.x, table.y), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(at(kHoverTile, palm.x, palm.y), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(at(kHoverTile, touch.x, touch.y), cv::Vec3b(0, 0, 0));

  // the contact's outline (green) on the depth and touch tiles, at the disk's edge (30 px right
  // of its centre, within 2 px)
  for (int tile : {kDepthTile, kTouchTile}) {
    int green = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const cv::Vec3b p = at(tile, 230 + dx, 240 + dy);
        green += p[1] > 200 && p[0] < 100 && p[2] < 100;
      }
    EXPECT_GT(green, 0) << "tile " << tile;
  }
  // the palm's mean height (5.0 cm) written beside its centre on the hover tile, in orange
  // (0, 200, 255) over the black and white mask: some pixels of that hue right of the centre
  int orange = 0;
  for (int y = 220; y < 260; ++y)
    for (int x = 450; x < 540; ++x) {
      const cv::Vec3b p = at(kHoverTile, x, y);
      orange += p[2] > 150 && p[0] < 100 && p[1] > 80 && p[1] < p[2];
    }
  EXPECT_GT(orange, 5);

  // the legend strip at the height tile's foot (rows 446-455 at this size; the label below it):
  // grey, then the band's greens, then the hover's blues, then white above the ceiling, in that
  // order from x 320 to 632 (its edges ticked at 372, 476 and 606)
  EXPECT_EQ(at(kHeightTile, 340, 451)[0], at(kHeightTile, 340, 451)[1]);
  EXPECT_EQ(at(kHeightTile, 420, 451)[0], 0);
  EXPECT_GE(at(kHeightTile, 420, 451)[1], dc::kBandDarkest);
  EXPECT_EQ(at(kHeightTile, 540, 451)[0], 255);
  EXPECT_EQ(at(kHeightTile, 540, 451)[2], 0);
  EXPECT_EQ(at(kHeightTile, 620, 451), dc::kAboveCeiling);

  // at half scale (what a window shows): tiles of 320x240, the same colours where they are even
  const cv::Mat half = DepthPreview(sensor, {{&r.value().blobs[0], 7}}, r.value().hover, 3, 0.5);
  ASSERT_EQ(half.size(), cv::Size(3 * 320, 2 * 240));
  EXPECT_EQ(half.at<cv::Vec3b>(hole.y / 2, hole.x / 2), dc::kNoReading);
  EXPECT_EQ(half.at<cv::Vec3b>(touch.y / 2, 2 * 320 + touch.x / 2), cv::Vec3b(0, 189, 0));
  EXPECT_TRUE(DepthPreview(sensor, {}, {}, 3, 0.0).empty());
  EXPECT_TRUE(DepthPreview(sensor, {}, {}, 0).empty());
}

// Before the surface is learned (15 frames by default) the depth tile shows the frame on its own
// range and the other four tiles are black
TEST(DepthPreview, WhileTheSurfaceIsLearnedOnlyTheDepthShows) {
  DepthSensor sensor;
  ASSERT_FALSE(sensor.Configure(DepthParams{}, SensingParams{}, TableParams{}, {640, 480}));
  cv::Mat mm(480, 640, CV_16UC1, cv::Scalar(1000));
  mm(cv::Rect(0, 0, 320, 480)).setTo(900);
  ASSERT_TRUE(sensor.Step(mm, 0, 0.0));
  ASSERT_FALSE(sensor.HasSurface());
  const cv::Mat view = DepthPreview(sensor, {}, {});
  ASSERT_EQ(view.size(), cv::Size(3 * 640, 2 * 480));
  // the frame's range 900-1000 mm: its near half red (255), its far half the far end (0)
  EXPECT_EQ(view.at<cv::Vec3b>(240, 100), Turbo(255.0));
  EXPECT_EQ(view.at<cv::Vec3b>(240, 500), Turbo(0.0));
  for (int tile = 1; tile < 5; ++tile)
    EXPECT_EQ(view.at<cv::Vec3b>((tile / 3) * 480 + 240, (tile % 3) * 640 + 320),
              cv::Vec3b(0, 0, 0))
        << "tile " << tile;
}

}  // namespace
}  // namespace pg
