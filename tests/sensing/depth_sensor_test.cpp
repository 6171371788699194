#include "proxygrasp/sensing/depth_sensor.h"

#include "real_data.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/depth_plane.h"
#include "proxygrasp/sensing/depth_source.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace pg {
namespace {

using ::testing::HasSubstr;

// The scenes: a depth camera looking down at a table about 1 m away, the image mapped linearly
// onto the default 61 x 46 cm table (no calibration: image edges = table edges, top of the image
// = the far edge, y up), so that pixel (u, v) sees table point ((u + 0.5) W / cols,
// H - (v + 0.5) H / rows). Shapes stand on the table with flat tops at a known height above it.
// Noise: Gaussian of 1.5 mm, a Kinect v1's at 1 m (Khoshelham and Elberink 2012), the readings
// rounded to whole mm as a depth camera delivers them.
constexpr double kFps = 30.0;
constexpr double kNoiseMm = 1.5;

struct Shape {
  Vec2 a, b;            // a capsule's axis, table cm (a == b: a disk)
  double radius = 0.8;  // cm
  double topMm = 14.0;  // height of its flat top above the table, mm
};

double DistanceToAxis(const Shape& s, const Vec2& p) {
  const Vec2 ab = s.b - s.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - s.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (s.a + t * ab)).norm();
}

class Scene {
 public:
  explicit Scene(cv::Size size = {640, 480}, uint64_t seed = 7) : m_size(size), m_rng(seed) {}

  Vec2 TableOf(int u, int v) const {
    return Vec2((u + 0.5) * m_table.width / m_size.width,
                m_table.height - (v + 0.5) * m_table.height / m_size.height);
  }
  // the table's distance from the camera at pixel (u, v), mm: 1 m, tilted by 6 mm across the
  // image and 3 mm down it, plus `rise` (negative: nearer the camera)
  double TableMm(int u, int v) const { return 1000.0 + 0.01 * u + 0.00625 * v + m_offsetMm; }

  void SetOffset(double mm) { m_offsetMm = mm; }
  // a rectangle of pixels without a reading (0)
  void SetHole(cv::Rect hole) { m_hole = hole; }

  cv::Mat Render(const std::vector<Shape>& shapes, double noiseMm = kNoiseMm) {
    cv::Mat mm(m_size, CV_64F);
    for (int v = 0; v < m_size.height; ++v) {
      double* row = mm.ptr<double>(v);
      for (int u = 0; u < m_size.width; ++u) {
        double top = 0.0;
        const Vec2 p = TableOf(u, v);
        for (const Shape& s : shapes)
          if (DistanceToAxis(s, p) <= s.radius) top = std::max(top, s.topMm);
        row[u] = TableMm(u, v) - top;
      }
    }
    cv::Mat noise(m_size, CV_64F);
    m_rng.fill(noise, cv::RNG::NORMAL, 0.0, noiseMm);
    mm += noise;
    cv::Mat out;
    mm.convertTo(out, CV_16UC1);  // rounds to whole mm
    if (m_hole.area() > 0) out(m_hole).setTo(0);
    return out;
  }

  cv::Size size() const { return m_size; }
  const TableParams& table() const { return m_table; }

 private:
  cv::Size m_size;
  TableParams m_table;
  cv::RNG m_rng;
  double m_offsetMm = 0.0;
  cv::Rect m_hole;
};

DepthSensor Configured(cv::Size size, const DepthParams& depth = {}) {
  DepthSensor sensor;
  const MaybeError s = sensor.Configure(depth, SensingParams(), TableParams(), size);
  EXPECT_FALSE(s) << s->Format();
  return sensor;
}

// steps the sensor over frames index .. index + n - 1 of a scene; returns the last frame's output
ContourFrame StepFrames(DepthSensor& sensor, Scene& scene, const std::vector<Shape>& shapes,
                        int64_t& index, int n,
                        const std::function<void(const ContourFrame&)>& each = {}) {
  ContourFrame last;
  for (int i = 0; i < n; ++i, ++index) {
    Result<ContourFrame> out =
        sensor.Step(scene.Render(shapes), index, static_cast<double>(index) / kFps);
    EXPECT_TRUE(out.ok()) << out.error().Format();
    if (!out.ok()) return last;
    last = std::move(out.value());
    if (each) each(last);
  }
  return last;
}

double MeanHeight(const Blob& b) {
  return b.MeanHeight().value_or(0.0);
}

TEST(DepthSensor, ReportsNothingWhileTheSurfaceIsLearned) {
  Scene scene;
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  // even a fingertip on the table: the first surface_frames frames are the surface
  const std::vector<Shape> finger = {{Vec2(20, 15), Vec2(20, 15)}};
  for (int i = 0; i < DepthParams().surfaceFrames; ++i) {
    EXPECT_FALSE(sensor.HasSurface());
    const ContourFrame f = StepFrames(sensor, scene, finger, index, 1);
    EXPECT_TRUE(f.blobs.empty());
    EXPECT_TRUE(f.hover.empty());
  }
  EXPECT_TRUE(sensor.HasSurface());
}

TEST(DepthSensor, FingertipTouchingIsFoundWithItsContourAndHeight) {
  Scene scene;
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
  ASSERT_TRUE(sensor.HasSurface());

  // a fingertip touching: a disk of radius 0.8 cm whose top is 14 mm above the table (a finger's
  // thickness), and a finger lying flat (a capsule 4 cm long, radius 0.7 cm, top 12 mm)
  const Shape tip{Vec2(20, 15), Vec2(20, 15), 0.8, 14.0};
  const Shape flat{Vec2(35, 30), Vec2(39, 32), 0.7, 12.0};
  double tipSq = 0.0, flatSq = 0.0;
  int points = 0, flatPoints = 0, frames = 0;
  StepFrames(sensor, scene, {tip, flat}, index, 20, [&](const ContourFrame& f) {
    ++frames;
    ASSERT_EQ(f.blobs.size(), 2u);
    EXPECT_TRUE(f.hover.empty());
    // largest first: the capsule (8.0 cm^2), then the disk (2.0 cm^2)
    const Blob& finger = f.blobs[0];
    const Blob& b = f.blobs[1];
    // Contour tolerance: the region is the pixels whose centres lie on the shape, so its
    // pixel-centre border runs up to 1 px inside the true outline, and moved out by half a pixel
    // it lies within half a pixel either side of it (rms about 0.3 px); the resampling's chords
    // cut 0.3 cm arcs of a 0.7 cm circle by 0.016 cm. The noise adds notches: a border pixel
    // whose reading falls below the band's lower edge (1% of them for a top 12 mm up: 6 mm down
    // is 4 deviations, and a pixel's deviation, measured over 15 frames, can be 1.5 times too
    // high) leaves the region, and the opening (a 3x3 cross) takes the pixels beside it: up to
    // 2 px deep. Bounds: rms 0.5 px (0.05 cm) and every point within 2.5 px (0.24 cm).
    double sq = 0.0;
    for (Eigen::Index k = 0; k < b.contour.cols(); ++k) {
      const double e = (b.contour.col(k) - tip.a).norm() - tip.radius;
      EXPECT_LT(std::abs(e), 0.24) << k;
      sq += e * e;
    }
    for (Eigen::Index k = 0; k < finger.contour.cols(); ++k) {
      const double e = DistanceToAxis(flat, finger.contour.col(k)) - flat.radius;
      EXPECT_LT(std::abs(e), 0.24) << k;
      sq += e * e;
    }
    EXPECT_LT(std::sqrt(sq / static_cast<double>(b.contour.cols() + finger.contour.cols())), 0.05);
    // the centroid of a symmetric region: within half a pixel of the centre
    EXPECT_NEAR((b.centroid - tip.a).norm(), 0.0, 0.05);
    // its area within 0.5 px of the radius: 2 pi r 0.05 cm = 0.25 cm^2
    EXPECT_NEAR(b.area, M_PI * 0.8 * 0.8, 0.25);
    // one height per contour point, cm
    ASSERT_EQ(b.heights.size(), static_cast<size_t>(b.contour.cols()));
    ASSERT_EQ(finger.heights.size(), static_cast<size_t>(finger.contour.cols()));
    for (double h : b.heights) tipSq += (h - 1.4) * (h - 1.4);
    for (double h : finger.heights) flatSq += (h - 1.2) * (h - 1.2);
    points += static_cast<int>(b.heights.size());
    flatPoints += static_cast<int>(finger.heights.size());
  });
  EXPECT_EQ(frames, 20);
  // Heights: the issue asks 5 mm rms. Expected far less: each point's height is the median of
  // the 30 to 80 region pixels within 0.5 cm of it, each read with 1.5 mm of noise against a
  // surface averaged over 15 frames (0.4 mm): 1.25 x 1.55 / sqrt(30) = 0.35 mm at most; bound
  // 1 mm, about three times that.
  EXPECT_LT(std::sqrt(tipSq / points), 0.1);
  EXPECT_LT(std::sqrt(flatSq / flatPoints), 0.1);
}

TEST(DepthSensor, WithTheTablesPlaneHeightsAreAlongItsNormal) {
  // A calibration that holds the table's plane (calibrate with a depth source) makes heights
  // along the plane's normal: an axial step dz at pixel (u, v) is dz x PlaneHeightScale there.
  // The plane here is tilted 20 degrees about x (normal (0, sin 20, -cos 20)); the frames are the
  // scene's (the sensor uses the plane for the scale only; its surface is learned from them). The
  // same frames (the scene's noise is seeded) through a sensor without the plane and one with
  // it: a disk under the image's centre, its top 14 mm nearer on the axis, reads the same
  // regions, and every height with the plane is the one without it times the scale, cos 20 =
  // 0.940 at the centre. Tolerance: the scale changes by n_y / f_y = 0.06% a pixel along v, so by
  // 0.5% over the disk's 16 px: the ratio of the means within 0.005.
  const double tilt = 20.0 * kPi / 180.0;
  Calibration calibration = LinearCalibration({640, 480}, TableParams());
  const DepthIntrinsics k = DepthIntrinsics::KinectV1({640, 480});
  calibration.cameraMatrix =
      (cv::Mat_<double>(3, 3) << k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0);
  calibration.depthPlane = (cv::Mat_<double>(1, 4) << 0.0, std::sin(tilt), -std::cos(tilt), 1000.0);
  const std::string path =
      (std::filesystem::temp_directory_path() / "pg_depth_plane_heights.yaml").string();
  ASSERT_FALSE(SaveCalibration(path, calibration));
  // under the image's centre: table point (30.5, 23)
  const Shape tip{Vec2(30.5, 23.0), Vec2(30.5, 23.0), 0.8, 14.0};
  const auto meanHeights = [&](const std::string& calibrationPath) {
    Scene scene;
    SensingParams sensing;
    sensing.calibration = calibrationPath;
    DepthSensor sensor;
    const MaybeError s = sensor.Configure(DepthParams(), sensing, scene.table(), scene.size());
    EXPECT_FALSE(s) << s->Format();
    int64_t index = 0;
    StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
    std::vector<double> means;
    StepFrames(sensor, scene, {tip}, index, 10, [&](const ContourFrame& f) {
      ASSERT_EQ(f.blobs.size(), 1u);
      double sum = 0.0;
      for (const double h : f.blobs[0].heights) sum += h;
      means.push_back(sum / static_cast<double>(f.blobs[0].heights.size()));
    });
    return means;
  };
  const std::vector<double> along = meanHeights("");
  const std::vector<double> normal = meanHeights(path);
  ASSERT_EQ(along.size(), 10u);
  ASSERT_EQ(normal.size(), 10u);
  for (size_t i = 0; i < along.size(); ++i) {
    EXPECT_NEAR(along[i], 1.4, 0.1) << i;  // the top, less the rim's lower medians
    EXPECT_NEAR(normal[i] / along[i], std::cos(tilt), 0.005) << i;
  }
  std::filesystem::remove(path);
}

TEST(DepthSensor, FingertipHoveringThreeCentimetresOrMoreIsHoverNotTouch) {
  for (const double underside : {30.0, 50.0, 100.0}) {
    Scene scene;
    DepthSensor sensor = Configured(scene.size());
    int64_t index = 0;
    StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
    // the same fingertip 14 mm thick, its underside `underside` mm above the table
    const Shape tip{Vec2(30, 20), Vec2(30, 20), 0.8, underside + 14.0};
    StepFrames(sensor, scene, {tip}, index, 20, [&](const ContourFrame& f) {
      EXPECT_TRUE(f.blobs.empty()) << underside << " mm";
      ASSERT_EQ(f.hover.size(), 1u) << underside << " mm";
      // its mean height: the top, within the same 1 mm as a touching fingertip's
      EXPECT_NEAR(MeanHeight(f.hover[0]), 0.1 * tip.topMm, 0.1);
      EXPECT_NEAR((f.hover[0].centroid - tip.a).norm(), 0.0, 0.05);
    });
  }
}

TEST(DepthSensor, AboveTheCeilingIsNeitherTouchNorHover) {
  Scene scene;
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
  // a head leaning 40 cm above the table (hover_ceiling 30 cm)
  const ContourFrame f =
      StepFrames(sensor, scene, {{Vec2(30, 20), Vec2(35, 20), 6.0, 400.0}}, index, 3);
  EXPECT_TRUE(f.blobs.empty());
  EXPECT_TRUE(f.hover.empty());
}

// The side of a body above the band (a forearm 4 cm up) seen as a strip within the band, 0.4 cm
// wide (the widest such strip the synthetic hands gave was 0.48 cm) and lying along the body
// (its hover), is dropped by min_width (0.6 cm); a fingertip (1.6 cm across), a finger lying
// flat 1 cm wide, and a strip as thin as the side's but lying alone on the table (nothing above
// the band beside it: a thin finger far from the camera) are kept. min_width = 0 keeps the side
// too. The pixels are 0.095 cm: the 0.4 cm strips are 4 px wide, and survive the opening (3 px);
// the finger is 10 px, its inscribed width measured to within a pixel.
TEST(DepthSensor, StripsNarrowerThanMinWidthAreNotTouches) {
  const std::vector<Shape> shapes = {
      {Vec2(30, 10), Vec2(30, 30), 3.0, 40.0},      // the forearm, hover
      {Vec2(33.2, 12), Vec2(33.2, 28), 0.2, 15.0},  // a strip along its side, in the band
      {Vec2(10, 20), Vec2(10, 20), 0.8, 14.0},      // a fingertip
      {Vec2(50, 15), Vec2(50, 25), 0.5, 12.0},      // a finger lying flat
      {Vec2(42, 35), Vec2(52, 35), 0.2, 12.0},      // a thin strip alone
  };
  for (const double minWidth : {DepthParams().minWidth, 0.0}) {
    Scene scene;
    DepthParams depth;
    depth.minWidth = minWidth;
    DepthSensor sensor = Configured(scene.size(), depth);
    int64_t index = 0;
    StepFrames(sensor, scene, {}, index, depth.surfaceFrames);
    const ContourFrame f = StepFrames(sensor, scene, shapes, index, 1);
    bool strip = false, tip = false, finger = false, alone = false;
    for (const Blob& b : f.blobs) {
      strip = strip || std::abs(b.centroid.x() - 33.2) < 0.3;
      tip = tip || (b.centroid - Vec2(10, 20)).norm() < 0.3;
      finger = finger || (b.centroid - Vec2(50, 20)).norm() < 0.3;
      alone = alone || (b.centroid - Vec2(47, 35)).norm() < 0.3;
    }
    EXPECT_TRUE(tip) << minWidth;
    EXPECT_TRUE(finger) << minWidth;
    EXPECT_TRUE(alone) << minWidth;
    EXPECT_EQ(strip, minWidth == 0.0);
    EXPECT_EQ(f.blobs.size(), minWidth == 0.0 ? 4u : 3u);
    ASSERT_EQ(f.hover.size(), 1u);
  }
}

// 40 s of a table that rises towards the camera by 0.2 mm/s, with learning on or off
int ContactsWhileTheTableRises(double learning, double* lagMm) {
  Scene scene(cv::Size(160, 120));
  DepthParams depth;
  depth.surfaceLearning = learning;
  DepthSensor sensor = Configured(scene.size(), depth);
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, depth.surfaceFrames);
  int contacts = 0;
  for (int i = 0; i < 40 * static_cast<int>(kFps); ++i) {
    scene.SetOffset(-0.2 * (static_cast<double>(index) / kFps));
    const ContourFrame f = StepFrames(sensor, scene, {}, index, 1);
    contacts += static_cast<int>(f.blobs.size());
  }
  // the surface's lag behind the table, mean over the image, mm
  double sum = 0.0;
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u) sum += sensor.Surface().at<float>(v, u) - scene.TableMm(u, v);
  *lagMm = sum / (160.0 * 120.0);
  return contacts;
}

// The one pass that classifies, and the opening and contours of only the rows that can hold a
// region (docs/sensing.md, "Speed"), give bit for bit what the rule computed over the whole image
// by plain OpenCV calls gives: height = surface - frame; touch = inRange(height, the noise edge,
// min(touch_high, surface - 0.5 mm)); hover = inRange(height, max(touch_high, edge) + 0.001 mm,
// min(hover_ceiling, surface - 0.5 mm)); each opened by cv::morphologyEx with the 3x3 cross. No
// tolerance: the same float operations must give the same bits. The image is 630 px wide (39
// blocks of 16 and 6 more, so the pass's tail runs too); fingertips touch, a palm hovers 5 cm up
// on rows shared with them, a hole has no reading, and the 1.5 mm noise against a 6 mm edge
// (4 deviations) leaves specks that the opening removes (checked to be there).
TEST(DepthSensor, StageImagesAreWhatTheWholeImageOpenCVCallsGive) {
  Scene scene(cv::Size(630, 470), 11);
  scene.SetHole(cv::Rect(40, 200, 25, 12));
  const DepthParams p;
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, p.surfaceFrames);
  const cv::Mat kernel = OpeningKernel(1);
  int specks = 0;
  for (int i = 0; i < 20; ++i, ++index) {
    const double x = 10.0 + 0.5 * i;
    const std::vector<Shape> shapes = {{Vec2(x, 23), Vec2(x, 23)},
                                       {Vec2(x + 12, 10), Vec2(x + 12, 10)},
                                       {Vec2(x + 25, 23), Vec2(x + 25, 23), 4.0, 60.0}};
    const cv::Mat frame = scene.Render(shapes);
    const cv::Mat surface = sensor.Surface().clone(), noise = sensor.SurfaceNoise().clone();
    ASSERT_TRUE(sensor.Step(frame, index, static_cast<double>(index) / kFps).ok());

    cv::Mat asFloat, height;
    frame.convertTo(asFloat, CV_32F);
    cv::subtract(surface, asFloat, height);
    cv::Mat touchLow(scene.size(), CV_32F), touchHigh(scene.size(), CV_32F);
    cv::Mat hoverLow(scene.size(), CV_32F), hoverHigh(scene.size(), CV_32F);
    const float low = static_cast<float>(10.0 * p.touchLow), k = static_cast<float>(p.noiseFactor);
    const float floor = static_cast<float>(p.noiseFloor * 1e-6);
    const float high = static_cast<float>(10.0 * p.touchHigh);
    const float ceiling = static_cast<float>(10.0 * p.hoverCeiling);
    for (int v = 0; v < surface.rows; ++v) {
      for (int u = 0; u < surface.cols; ++u) {
        const float s = surface.at<float>(v, u);
        const float edge = std::max(low, k * std::max(noise.at<float>(v, u), floor * s * s));
        touchLow.at<float>(v, u) = edge;
        touchHigh.at<float>(v, u) = std::min(high, s - 0.5f);
        hoverLow.at<float>(v, u) = std::max(high, edge) + 1e-3f;
        hoverHigh.at<float>(v, u) = std::min(ceiling, s - 0.5f);
      }
    }
    cv::Mat touch, hover, opened;
    cv::inRange(height, touchLow, touchHigh, touch);
    cv::inRange(height, hoverLow, hoverHigh, hover);
    cv::morphologyEx(touch, opened, cv::MORPH_OPEN, kernel);
    specks += cv::countNonZero(touch) - cv::countNonZero(opened);
    touch = opened;
    cv::morphologyEx(hover, hover, cv::MORPH_OPEN, kernel);

    EXPECT_EQ(cv::norm(height, sensor.StageImage(DepthStage::kHeight), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::countNonZero(touch != sensor.StageImage(DepthStage::kTouch)), 0) << i;
    EXPECT_EQ(cv::countNonZero(hover != sensor.StageImage(DepthStage::kHover)), 0) << i;
    EXPECT_GT(cv::countNonZero(touch), 0);
    EXPECT_GT(cv::countNonZero(hover), 0);
  }
  EXPECT_GT(specks, 0) << "no specks: the test would not see them cleared";
}

TEST(DepthSensor, SurfaceFollowsATableThatChangesSlowly) {
  double lag = 0.0;
  // A surface learned with a time constant of 10 s follows a ramp of 0.2 mm/s 0.2 x 10 = 2 mm
  // behind it (the steady lag of a first-order filter), below the band's lower edge (5 mm): no
  // contact. The mean over 19,200 pixels of the noise is nothing against it; the bound is
  // 2 +- 0.5 mm, what the learning's one band of rows in four per frame (each learning at the
  // rate for the time since it last did) may add or take.
  EXPECT_EQ(ContactsWhileTheTableRises(10.0, &lag), 0);
  EXPECT_NEAR(lag, 2.0, 0.5);
  // the same with the surface fixed: 8 mm up at the end, the whole table is in the band
  double fixedLag = 0.0;
  EXPECT_GT(ContactsWhileTheTableRises(0.0, &fixedLag), 0);
  EXPECT_NEAR(fixedLag, 8.0, 0.5);
}

TEST(DepthSensor, SurfaceDoesNotLearnAHandHeldStill) {
  Scene scene(cv::Size(320, 240));
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
  const cv::Mat before = sensor.Surface().clone();
  // a palm hovering 2 cm above the table (top 4 cm) and a fingertip touching, held still for
  // 60 s: six of the surface's time constants (10 s), which would learn them both to within
  // e^-6 = 0.25% if it learned where something is near
  const Shape palm{Vec2(15, 20), Vec2(15, 26), 4.0, 40.0};
  const Shape tip{Vec2(40, 20), Vec2(40, 20), 0.8, 14.0};
  const ContourFrame held = StepFrames(sensor, scene, {palm, tip}, index, 60 * 30);
  ASSERT_EQ(held.blobs.size(), 1u);
  ASSERT_EQ(held.hover.size(), 1u);
  EXPECT_NEAR(MeanHeight(held.blobs[0]), 1.4, 0.1);
  EXPECT_NEAR(MeanHeight(held.hover[0]), 4.0, 0.1);
  // the surface under them (more than 0.3 cm inside their outlines) has not moved: where
  // something is near it does not learn at all, and learned it would have come up by tens of mm
  double worst = 0.0;
  int under = 0;
  for (int v = 0; v < scene.size().height; ++v)
    for (int u = 0; u < scene.size().width; ++u) {
      const Vec2 p = scene.TableOf(u, v);
      if (DistanceToAxis(palm, p) > palm.radius - 0.3 && DistanceToAxis(tip, p) > tip.radius - 0.3)
        continue;
      ++under;
      worst = std::max<double>(worst,
                               std::abs(sensor.Surface().at<float>(v, u) - before.at<float>(v, u)));
    }
  EXPECT_GT(under, 2000);
  EXPECT_LT(worst, 0.5);
  // gone: nothing is left behind
  const ContourFrame after = StepFrames(sensor, scene, {}, index, 1);
  EXPECT_TRUE(after.blobs.empty());
  EXPECT_TRUE(after.hover.empty());
}

TEST(DepthSensor, SomethingThatLeavesTheTableIsForgottenQuickly) {
  Scene scene(cv::Size(320, 240));
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  // a book 3 cm thick on the table while the surface is learned, then taken away: where it was,
  // the table reads 3 cm farther than the surface, which follows with surface_recovery (1 s):
  // 3 cm x e^-(t / 1 s) is below 1 mm after 3.4 s
  const Shape book{Vec2(30, 20), Vec2(36, 20), 5.0, 30.0};
  StepFrames(sensor, scene, {book}, index, DepthParams().surfaceFrames);
  int contacts = 0;
  StepFrames(sensor, scene, {}, index, 20 * 30, [&](const ContourFrame& f) {
    contacts += static_cast<int>(f.blobs.size() + f.hover.size());
  });
  EXPECT_EQ(contacts, 0);  // a table farther than the surface is never above it
  // Where the book was, the surface follows at surface_recovery while the table reads more than
  // the band's lower edge (noise_factor x 1.5 mm = 6 mm) farther than it, from 30 mm to 6 mm in
  // ln 5 = 1.6 s; the last 6 mm at surface_learning (10 s): 6 e^-1.84 = 1.0 mm left after 20 s.
  // (A surface nearer the camera than the table gives no false touch meanwhile.) Bound: the
  // surface between 1 mm below the table and 3 mm above it.
  const int u = 320 * 33 / 61, v = 240 - 240 * 20 / 46;  // the book's centre
  const double above = scene.TableMm(u, v) - sensor.Surface().at<float>(v, u);
  EXPECT_GT(above, -1.0);
  EXPECT_LT(above, 3.0);
  // a fingertip touching there is found: it reads 11 mm or more above the surface, and the
  // deviation there, inflated while the surface lagged, is back below 2.5 mm (band edge 10 mm)
  const ContourFrame f =
      StepFrames(sensor, scene, {{Vec2(33, 20), Vec2(33, 20), 0.8, 14.0}}, index, 1);
  ASSERT_EQ(f.blobs.size(), 1u);
  EXPECT_NEAR((f.blobs[0].centroid - Vec2(33, 20)).norm(), 0.0, 0.05);
}

TEST(FillHoles, FillsFromTheNeighboursOfATiltedPlane) {
  // a plane of 0.2 mm per pixel across and 0.1 down, with a 40 x 30 px hole and every 7th pixel
  // of another row missing
  cv::Mat plane(120, 160, CV_32F), valid(120, 160, CV_8UC1, cv::Scalar(255));
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) plane.at<float>(y, x) = 1000.0f + 0.2f * x + 0.1f * y;
  cv::Mat image = plane.clone();
  image(cv::Rect(60, 40, 40, 30)).setTo(0.0f);
  valid(cv::Rect(60, 40, 40, 30)).setTo(0);
  for (int x = 3; x < 160; x += 7) {
    image.at<float>(100, x) = 0.0f;
    valid.at<uint8_t>(100, x) = 0;
  }
  FillHoles(image, valid);
  // Valid pixels are kept as they were. A hole is filled by the mean of the valid pixels in the
  // smallest box that holds enough of them: on a plane that mean is the plane at their
  // centroid, which lies at most half the box (31 px wide for the 40 x 30 hole's middle) from
  // the pixel: 15 px x 0.22 mm/px = 3.4 mm at worst; the isolated pixels (3x3 box, symmetric
  // but for the missing one) are within 0.03 mm.
  double worst = 0.0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const double e = std::abs(image.at<float>(y, x) - plane.at<float>(y, x));
      if (valid.at<uint8_t>(y, x)) {
        ASSERT_EQ(e, 0.0);
      }
      worst = std::max(worst, e);
      if (y == 100 && !valid.at<uint8_t>(y, x)) {
        EXPECT_LT(e, 0.03) << x;
      }
    }
  EXPECT_LT(worst, 3.4);
  EXPECT_GT(cv::countNonZero(image), 120 * 160 - 1);
}

TEST(DepthSensor, HolesInTheSurfaceAreFilledAndTouchesFoundThere) {
  Scene scene;
  // the table reads nothing in a 30 x 30 px patch while the surface is learned
  const cv::Rect hole(300, 200, 30, 30);
  scene.SetHole(hole);
  DepthSensor sensor = Configured(scene.size());
  int64_t index = 0;
  StepFrames(sensor, scene, {}, index, DepthParams().surfaceFrames);
  // filled from its neighbours: the table tilts 0.012 mm/px, so the fill is within 0.2 mm of it
  // (15 px x 0.012), plus the 0.4 mm of the surface's noise; bound 1 mm
  for (int v = hole.y; v < hole.br().y; ++v)
    for (int u = hole.x; u < hole.br().x; ++u)
      ASSERT_NEAR(sensor.Surface().at<float>(v, u), scene.TableMm(u, v), 1.0) << u << "," << v;
  // the patch reads again, with a fingertip touching in it: found with its height
  scene.SetHole(cv::Rect());
  const Vec2 at = scene.TableOf(315, 215);
  const ContourFrame f = StepFrames(sensor, scene, {{at, at, 0.8, 14.0}}, index, 1);
  ASSERT_EQ(f.blobs.size(), 1u);
  EXPECT_NEAR((f.blobs[0].centroid - at).norm(), 0.0, 0.05);
  EXPECT_NEAR(MeanHeight(f.blobs[0]), 1.4, 0.1);
  // and a hole in a frame is neither touch nor hover
  scene.SetHole(cv::Rect(100, 100, 50, 50));
  const ContourFrame holed = StepFrames(sensor, scene, {}, index, 1);
  EXPECT_TRUE(holed.blobs.empty());
  EXPECT_TRUE(holed.hover.empty());
}

TEST(DepthSensor, WrongFrameTypeOrSizeIsAnErrorNamingTheFrame) {
  DepthSensor sensor = Configured(cv::Size(64, 48));
  const Result<ContourFrame> grey = sensor.Step(cv::Mat(48, 64, CV_8UC1, cv::Scalar(9)), 7, 0.2);
  ASSERT_FALSE(grey.ok());
  EXPECT_THAT(grey.error().Format(), HasSubstr("frame 7"));
  EXPECT_THAT(grey.error().Format(), HasSubstr("CV_8UC1"));
  EXPECT_THAT(grey.error().Format(), HasSubstr("CV_16UC1"));
  const Result<ContourFrame> small =
      sensor.Step(cv::Mat(24, 32, CV_16UC1, cv::Scalar(1000)), 8, 0.3);
  ASSERT_FALSE(small.ok());
  EXPECT_THAT(small.error().Format(), HasSubstr("frame 8"));
  EXPECT_THAT(small.error().Format(), HasSubstr("32x24, expected 64x48"));
  const Result<ContourFrame> empty = sensor.Step(cv::Mat(), 9, 0.4);
  ASSERT_FALSE(empty.ok());
  EXPECT_THAT(empty.error().Format(), HasSubstr("frame 9"));
  DepthSensor unconfigured;
  EXPECT_FALSE(unconfigured.Step(cv::Mat(48, 64, CV_16UC1), 0, 0.0).ok());
}

TEST(DepthSensor, BadParametersAreErrorsNamingTheKey) {
  DepthSensor sensor;
  DepthParams depth;
  depth.touchHigh = 0.0;  // below its range (0.1 to 20 cm)
  const MaybeError s = sensor.Configure(depth, SensingParams(), TableParams(), cv::Size(64, 48));
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr("touch_high"));
  // surface_frames needs a new Configure
  DepthSensor ok = Configured(cv::Size(64, 48));
  DepthParams more;
  more.surfaceFrames = 30;
  const MaybeError restart = ok.SetParams(more, SensingParams());
  ASSERT_TRUE(restart);
  EXPECT_THAT(restart->Format(), HasSubstr("surface_frames"));
}

// the real recordings (../shared/real/depth/README.md): static scenes, nobody touching
std::string RealDepthDir() {
  const std::string root = test::RealDataDir("depth");
  return root.empty() ? "" : root + "/depth";
}

std::vector<cv::Mat> ReadAll(const std::string& spec) {
  std::vector<cv::Mat> frames;
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource(spec);
  EXPECT_TRUE(src) << src.error().Format();
  if (!src) return frames;
  cv::Mat frame;
  while (src.value()->Read(frame) == FrameStatus::kOk) frames.push_back(frame.clone());
  return frames;
}

// contacts and hover regions in the frames after the first `learn`, the surface learned from those
int ContactsAfterLearning(const std::vector<cv::Mat>& frames, int learn, int* hover) {
  DepthParams depth;
  depth.surfaceFrames = learn;
  DepthSensor sensor = Configured(frames.at(0).size(), depth);
  int contacts = 0;
  *hover = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    Result<ContourFrame> f =
        sensor.Step(frames[i], static_cast<int64_t>(i), static_cast<double>(i) / kFps);
    EXPECT_TRUE(f.ok()) << f.error().Format();
    if (!f.ok()) continue;
    contacts += static_cast<int>(f.value().blobs.size());
    *hover += static_cast<int>(f.value().hover.size());
  }
  return contacts;
}

TEST(RealDepth, StaticScenesGiveNoContactOnceTheirSurfaceIsLearned) {
  const std::string dir = RealDepthDir();
  if (dir.empty())
    GTEST_SKIP() << "../shared/real/depth is absent (a clone of the project alone): no real "
                    "depth recordings; set PROXYGRASP_REAL_DATA to the folder that holds depth/";
  // kinectcap: a room with a whiteboard and a wall about 1 m away, 4 frames of real Kinect v1
  // noise and quantisation (2.9 mm a step at 1 m, more farther), 8% of pixels without a reading;
  // learned from the first two, the other two have no contact and no hover
  const std::vector<cv::Mat> room = ReadAll("fakenect:" + dir + "/kinectcap");
  ASSERT_EQ(room.size(), 4u);
  int hover = 0;
  EXPECT_EQ(ContactsAfterLearning(room, 2, &hover), 0);
  EXPECT_EQ(hover, 0);
  // test.oni (through OpenNI2's file driver): a room, a person at the image's edge; learned from
  // the first 6 of its 12 frames
  if (!HaveOpenNi2()) GTEST_SKIP() << "not built with OpenNI2: test.oni not read";
  const std::vector<cv::Mat> oni = ReadAll("oni:" + dir + "/test.oni");
  ASSERT_EQ(oni.size(), 12u);
  EXPECT_EQ(ContactsAfterLearning(oni, 6, &hover), 0);
  EXPECT_EQ(hover, 0);
}

// ---- issue 43's acceptance: the synthetic depth camera, scripted hands touching and hovering ----

// Camera seeds 1 to 6; under the sanitizers (five to ten times slower) seed 1 alone: the code it
// runs is the same for every seed.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kAcceptLastSeed = 1;
#else
constexpr int kAcceptLastSeed = 6;
#endif

// the depth camera's frame rate (a Kinect v1's), Hz
constexpr double kKinectFps = 30.0;
// frames of the clear table the surface is learned from (DepthParams::surfaceFrames), then the
// frames scored
constexpr int kClearFrames = 15;
constexpr int kScoredFrames = 45;

// One scripted contact: a shape and its keyframes (time s, position cm, angle deg, height of its
// underside above the table cm), linear between them; present from the first keyframe to the last.
struct Key {
  double t, x, y, angle, height;
};
struct Scripted {
  ContactShape shape;
  std::vector<Key> keys;
};

ContactShape Tip(double radius) {
  ContactShape s;
  s.kind = ShapeKind::kCircle;
  s.radius = radius;
  return s;
}
ContactShape Hand(ShapeKind kind) {
  ContactShape s;
  s.kind = kind;
  return s;
}

// The script (scored from t0 = 0.5 s, after the clear table, for 1.5 s): fingertips and two hands
// that touch, hover at 1, 2, 3 and 5 cm, and are lowered and lifted at 10 to 30 cm/s (a finger
// tapping moves at 10 to 50 cm/s), moving across the table at up to 10 cm/s. A fingertip's finger
// rises toward local -y (the arm): their angles keep them pointing away from the near edge. No
// forearm passes over another contact (from above it would hide it).
std::vector<Scripted> AcceptanceScript() {
  return {
      // touching throughout, sliding 10 cm/s
      {Tip(0.8), {{0.5, 18, 9, 10, 0}, {2.0, 30, 14, 10, 0}}},
      // hovering 3 cm, sliding
      {Tip(0.75), {{0.5, 22, 28, -25, 3}, {2.0, 31, 33, -25, 3}}},
      // hovering 5 cm
      {Tip(0.8), {{0.5, 56, 8, 20, 5}, {2.0, 51, 13, 20, 5}}},
      // touching, lifted to 5 cm at 20 cm/s, held, lowered at 20 cm/s, touching
      {Tip(0.8),
       {{0.5, 30, 20, 0, 0},
        {0.8, 31, 20.5, 0, 0},
        {1.05, 32, 21, 0, 5},
        {1.3, 33, 21.5, 0, 5},
        {1.55, 34, 22, 0, 0},
        {2.0, 36, 22, 0, 0}}},
      // at 1 cm, 2 cm, touching, 3 cm: each step at 10 to 30 cm/s
      {Tip(0.7),
       {{0.5, 24, 38, -10, 1},
        {0.8, 25, 38, -10, 1},
        {0.9, 25.5, 38, -10, 2},
        {1.1, 26, 38, -10, 2},
        {1.3, 27, 38, -10, 0},
        {1.6, 28, 38, -10, 0},
        {1.7, 28.5, 38, -10, 3},
        {2.0, 29, 38, -10, 3}}},
      // a spread hand touching, sliding and turning
      {Hand(ShapeKind::kHandFive), {{0.5, 45, 27, -20, 0}, {2.0, 49, 29, 0, 0}}},
      // a flat hand lowered from 3 cm at 10 cm/s, touching, lifted to 2 cm
      {Hand(ShapeKind::kHandFlat),
       {{0.5, 10, 31, 0, 3},
        {0.8, 10, 31, 0, 0},
        {1.6, 11, 32, 5, 0},
        {1.8, 11, 32, 5, 2},
        {2.0, 11, 32, 5, 2}}},
  };
}

// the shapes of the script at time t, each at its pose and height
std::vector<ContactShape> ScriptShapes(const std::vector<Scripted>& script, double t) {
  std::vector<ContactShape> shapes;
  for (const Scripted& c : script) {
    if (t < c.keys.front().t - 1e-9 || t > c.keys.back().t + 1e-9) continue;
    size_t k = 0;
    while (k + 2 < c.keys.size() && t > c.keys[k + 1].t) ++k;
    const Key& a = c.keys[k];
    const Key& b = c.keys[std::min(k + 1, c.keys.size() - 1)];
    const double f = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
    ContactShape s = c.shape;
    s.pose.pos = Vec2(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
    s.pose.angle = DegToRad(a.angle + f * (b.angle - a.angle));
    s.height = a.height + f * (b.height - a.height);
    shapes.push_back(s);
  }
  return shapes;
}

// A fingertip of the truth: a scripted circle, or a hand's finger end (HandFingertips), with the
// height of its body's underside and the true top of its pad (BodyTopHeight at its centre).
struct TrueTip {
  Circle pad;
  double height = 0.0;  // cm, underside above the table
  double top = 0.0;     // cm, the pad's top above the table
  size_t shape = 0;     // index of its shape
};

std::vector<TrueTip> TrueTips(const std::vector<ContactShape>& shapes,
                              const SyntheticCameraParams& camera) {
  std::vector<TrueTip> tips;
  for (size_t i = 0; i < shapes.size(); ++i) {
    const ContactShape& s = shapes[i];
    std::vector<Circle> pads = HandFingertips(s);
    if (s.kind == ShapeKind::kCircle) pads.push_back({s.pose.pos, s.radius});
    for (const Circle& c : pads)
      tips.push_back({c, s.height, BodyTopHeight(s, camera, c.centre), i});
  }
  return tips;
}

// A body touches when its underside is on the table, hovers (and must give no contact) from 3 cm
// up; between, a contact is neither required nor false (the band sees the lower part of a
// fingertip 1 cm up, and a fingertip passing through while lowered or lifted).
constexpr double kTouching = 1e-9;
constexpr double kHovering = 3.0;

// the signed distance from a table point to a contact's outline, cm (positive inside)
double Inside(const Blob& b, const Vec2& p) {
  std::vector<cv::Point2f> outline;
  outline.reserve(static_cast<size_t>(b.contour.cols()));
  for (Eigen::Index k = 0; k < b.contour.cols(); ++k)
    outline.emplace_back(static_cast<float>(b.contour(0, k)), static_cast<float>(b.contour(1, k)));
  return cv::pointPolygonTest(
      outline, cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), true);
}

struct DepthScore {
  int frames = 0;
  int tips = 0;         // touching fingertips
  int found = 0;        // of them, held by a contact (within one pad radius)
  int contacts = 0;     // contacts
  int unmatched = 0;    // contacts holding no touching fingertip, not on a touching hand, and not
                        // on a body between 0 and 3 cm
  int fromHover = 0;    // contacts on a body hovering 3 cm or more and on nothing touching
  double heightSq = 0;  // sum of (measured - true)^2 over found fingertips, cm^2
  int heights = 0;
  std::string misses;  // where, for messages

  double HeightRms() const { return heights > 0 ? std::sqrt(heightSq / heights) : 0.0; }
};

// Scores one frame's contacts against the shapes drawn in it.
void ScoreDepthFrame(const std::vector<ContactShape>& shapes, const SyntheticCameraParams& camera,
                     const ContourFrame& frame, DepthScore& score) {
  ++score.frames;
  const std::vector<TrueTip> tips = TrueTips(shapes, camera);
  const std::string at = " @" + std::to_string(frame.index);
  // a contact holds a fingertip when its outline passes within one pad radius of the pad's
  // centre (the chain maps the image linearly: the pad's top, 1.2 cm up, appears up to 0.46 cm
  // outward from the table's centre; docs/sensing.md, "Parallax")
  auto holds = [](const Blob& b, const TrueTip& t) {
    return Inside(b, t.pad.centre) >= -t.pad.radius;
  };
  for (const TrueTip& t : tips) {
    if (t.height > kTouching) continue;
    ++score.tips;
    const Blob* best = nullptr;
    for (const Blob& b : frame.blobs)
      if (holds(b, t) && (!best || Inside(b, t.pad.centre) > Inside(*best, t.pad.centre)))
        best = &b;
    if (!best) {
      score.misses += " missed" + at + "(" + std::to_string(t.pad.centre.x()) + "," +
                      std::to_string(t.pad.centre.y()) + ")";
      continue;
    }
    ++score.found;
    // Its height: the mean of the heights of the contact's points within two pad radii of the
    // pad's centre (the contact of a touching fingertip is its pad and the finger rising from it,
    // of a hand all of its fingers: the pad's own points are the ones that measure it), against
    // the pad's top (TrueTip::top: finger_thickness, 1.2 cm, for a touching fingertip). What a
    // camera above sees of a touching fingertip is its top, and the chain's height at a contour
    // point is the median of the region's heights within height_radius (0.5 cm) of it: at the
    // rim the region's pixels run from the band's lower edge (6.7 mm) over the quarter round
    // (0.93, 1.05, 1.12, 1.17 cm at 0.1 to 0.4 cm in) onto the flat 1.2 cm top, whose median is
    // 1 to 1.5 mm under the top; the finger rising behind the pad (4.7 mm per cm) lifts the
    // points toward the arm as much; the noise of a 20 to 80 pixel median is 0.3 to 0.4 mm.
    // The acceptance's bound is 5 mm rms (a measured 2.2 to 2.3 mm; 3.4 to 3.5 mm while the
    // camera drew a thumb palm-thick, its top above the band).
    double sum = 0.0;
    int n = 0;
    for (Eigen::Index k = 0; k < best->contour.cols(); ++k) {
      if ((Vec2(best->contour.col(k)) - t.pad.centre).norm() > 2.0 * t.pad.radius) continue;
      sum += best->heights[static_cast<size_t>(k)];
      ++n;
    }
    if (n == 0) continue;
    const double e = sum / n - t.top;
    score.heightSq += e * e;
    ++score.heights;
  }
  for (const Blob& b : frame.blobs) {
    ++score.contacts;
    bool touching = false, between = false, hovering = false;
    for (const TrueTip& t : tips) {
      if (!holds(b, t)) continue;
      (t.height <= kTouching ? touching : t.height < kHovering ? between : hovering) = true;
    }
    // on a touching body: the centroid within its outline (what touches: a fingertip's pad, a
    // hand) grown by a pad radius (0.8 cm); on a raised one: anywhere the depth camera draws it
    // (BodyTopHeight: its finger or forearm too)
    for (const ContactShape& s : shapes) {
      if (s.height <= kTouching) {
        touching = touching || ShapeDistance(s, b.centroid) <= 0.8;
      } else if (ShapeDistance(s, b.centroid) <= 0.8 ||
                 BodyTopHeight(s, camera, b.centroid) >= 0.0) {
        (s.height < kHovering ? between : hovering) = true;
      }
    }
    if (touching || between) continue;
    ++score.unmatched;
    if (hovering) ++score.fromHover;
    score.misses += std::string(hovering ? " hover" : " extra") + at + "(" +
                    std::to_string(b.centroid.x()) + "," + std::to_string(b.centroid.y()) + ")";
  }
}

// the frame at index i of the acceptance run: the clear table, then the script
double AcceptTime(int64_t i) {
  return static_cast<double>(i) / kKinectFps;
}

// One seed's run: the synthetic camera's frames through a depth sensor, scored, and written out
// as `depth:` and `fakenect:` recordings under `dir`.
DepthScore ScoreSynthetic(int seed, const std::string& dir) {
  const TableParams table;
  SyntheticCameraParams params;
  params.kind = CameraKind::kDepth;
  params.seed = static_cast<uint64_t>(seed);
  SyntheticCamera camera(params, table);
  DepthSensor sensor;
  EXPECT_FALSE(sensor.Configure(DepthParams(), SensingParams(), table,
                                cv::Size(params.width, params.height)));
  Result<DepthRecordingWriter> png =
      DepthRecordingWriter::Create(dir + "/depth", DepthRecordingWriter::Format::kDepthPng);
  Result<DepthRecordingWriter> fakenect =
      DepthRecordingWriter::Create(dir + "/fakenect", DepthRecordingWriter::Format::kFakenect);
  EXPECT_TRUE(png.ok() && fakenect.ok());
  const std::vector<Scripted> script = AcceptanceScript();
  DepthScore score;
  for (int64_t i = 0; i < kClearFrames + kScoredFrames; ++i) {
    const std::vector<ContactShape> shapes = ScriptShapes(script, AcceptTime(i));
    const cv::Mat frame = camera.Render(shapes);
    if (png.ok()) {
      EXPECT_FALSE(png.value().Write(frame, AcceptTime(i)));
    }
    if (fakenect.ok()) {
      EXPECT_FALSE(fakenect.value().Write(frame, AcceptTime(i)));
    }
    Result<ContourFrame> out = sensor.Step(frame, i, AcceptTime(i));
    EXPECT_TRUE(out.ok()) << out.error().Format();
    if (out.ok() && i >= kClearFrames) ScoreDepthFrame(shapes, params, out.value(), score);
  }
  return score;
}

// The same frames read back through a depth source (`depth:DIR`, `fakenect:DIR`), scored.
DepthScore ScoreRecording(int seed, const std::string& spec) {
  const TableParams table;
  SyntheticCameraParams params;
  params.kind = CameraKind::kDepth;
  params.seed = static_cast<uint64_t>(seed);
  Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(spec);
  EXPECT_TRUE(source.ok()) << source.error().Format();
  DepthScore score;
  if (!source.ok()) return score;
  DepthSensor sensor;
  EXPECT_FALSE(sensor.Configure(DepthParams(), SensingParams(), table,
                                cv::Size(params.width, params.height)));
  const std::vector<Scripted> script = AcceptanceScript();
  cv::Mat frame;
  int64_t i = 0;
  for (; source.value()->Read(frame) == FrameStatus::kOk; ++i) {
    Result<ContourFrame> out = sensor.Step(frame, i, AcceptTime(i));
    EXPECT_TRUE(out.ok()) << out.error().Format();
    if (out.ok() && i >= kClearFrames)
      ScoreDepthFrame(ScriptShapes(script, AcceptTime(i)), params, out.value(), score);
  }
  EXPECT_EQ(i, kClearFrames + kScoredFrames) << spec;
  return score;
}

// Issue 43's acceptance on the synthetic depth camera (default noise): at least 97% of touching
// fingertips found, at most 1 unmatched contact per 20 frames, no contact
// from a fingertip hovering 3 cm or more, fingertip height within 5 mm rms; the same read back
// through depth:DIR and fakenect:DIR. One test per camera seed; each prints its figures per source
// (docs/sensing.md, "Depth cameras").
class DepthAcceptance : public ::testing::TestWithParam<int> {};

TEST_P(DepthAcceptance, ScriptedHandsTouchingAndHovering) {
  const int seed = GetParam();
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("pg_depth_acceptance_seed" + std::to_string(seed));
  std::filesystem::remove_all(root);
  const char* kSources[] = {"synthetic", "depth", "fakenect"};
  const std::string dir = root.string();
  const DepthScore scores[3] = {ScoreSynthetic(seed, dir),
                                ScoreRecording(seed, "depth:" + dir + "/depth"),
                                ScoreRecording(seed, "fakenect:" + dir + "/fakenect")};
  for (int k = 0; k < 3; ++k) {
    const DepthScore& s = scores[k];
    std::printf(
        "seed %d %-9s %2d frames: %3d of %3d touching fingertips found, %2d of %3d contacts "
        "unmatched, %d from hovering >= 3 cm, height rms %.2f mm over %d\n",
        seed, kSources[k], s.frames, s.found, s.tips, s.unmatched, s.contacts, s.fromHover,
        10.0 * s.HeightRms(), s.heights);
    EXPECT_EQ(s.frames, kScoredFrames) << kSources[k];
    EXPECT_GE(s.found * 100, 97 * s.tips) << kSources[k] << s.misses;
    // at most 1 unmatched contact per 20 frames. Without depth.min_width there were 3 to 11 in
    // 45 frames, nearly all strips along the side of a forearm 2 to 4 cm from a touching hand's
    // wrist, whose wall passes through the touch band there (docs/sensing.md, "Touch from depth")
    EXPECT_LE(s.unmatched * 20, s.frames) << kSources[k] << s.misses;
    EXPECT_EQ(s.fromHover, 0) << kSources[k] << s.misses;
    EXPECT_LT(s.HeightRms(), 0.5) << kSources[k];
  }
  // the recordings give the sensor the very frames the camera gave it (PNGs keep the mm, and
  // every reading lies on a disparity step, which fakenect keeps): the same figures
  for (int k = 1; k < 3; ++k) {
    EXPECT_EQ(scores[k].found, scores[0].found) << kSources[k];
    EXPECT_EQ(scores[k].unmatched, scores[0].unmatched) << kSources[k];
    EXPECT_EQ(scores[k].contacts, scores[0].contacts) << kSources[k];
    EXPECT_NEAR(scores[k].HeightRms(), scores[0].HeightRms(), 1e-9) << kSources[k];
  }
  std::filesystem::remove_all(root);
}

INSTANTIATE_TEST_SUITE_P(Seeds, DepthAcceptance, ::testing::Range(1, kAcceptLastSeed + 1));

}  // namespace
}  // namespace pg
