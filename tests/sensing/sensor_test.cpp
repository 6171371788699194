#include "proxygrasp/sensing/sensor.h"

#include "test_paths.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "sensing/real_footage.h"

namespace pg {
namespace {

using ::testing::HasSubstr;

// a camera with every nuisance on: noise, vignetting, gradient, barrel distortion and keystone
SyntheticCameraParams HardCamera(int seed = 7) {
  SyntheticCameraParams p;
  p.noise = 3.0;
  p.gradient = 12.0;
  p.vignetting = 0.25;
  p.distortion = -0.08;
  p.perspective = 0.06;
  p.seed = seed;
  return p;
}

// Hausdorff distance between two table contours measured in camera pixels of the true model
double HausdorffPixels(const CameraModel& model, const Contour& a, const Contour& b) {
  auto toPixels = [&](const Contour& c) {
    Contour out(2, c.cols());
    for (int i = 0; i < c.cols(); ++i) out.col(i) = model.TableToCamera(c.col(i));
    return out;
  };
  return HausdorffDistance(toPixels(a), toPixels(b));
}

struct AccuracyCase {
  std::string name;
  ContactShape shape;
};

ContactShape Make(ShapeKind kind, Vec2 pos, double angleDeg) {
  ContactShape s;
  s.kind = kind;
  s.pose.pos = pos;
  s.pose.angle = DegToRad(angleDeg);
  return s;
}

std::vector<AccuracyCase> AccuracyCases() {
  std::vector<AccuracyCase> cases;
  ContactShape circle = Make(ShapeKind::kCircle, {3.0, 43.0}, 0);
  circle.radius = 0.8;
  cases.push_back({"circle_corner", circle});
  circle.pose.pos = {12.0, 35.0};
  cases.push_back({"circle_off_centre", circle});
  circle.pose.pos = {30.5, 23.0};
  circle.radius = 1.1;
  cases.push_back({"circle_centre", circle});
  ContactShape ellipse = Make(ShapeKind::kEllipse, {45.0, 12.0}, 30);
  ellipse.radiusX = 1.6;
  ellipse.radiusY = 0.9;
  cases.push_back({"ellipse", ellipse});
  cases.push_back({"hand_five", Make(ShapeKind::kHandFive, {20.0, 18.0}, 20)});
  cases.push_back({"hand_flat", Make(ShapeKind::kHandFlat, {40.0, 17.0}, -25)});
  cases.push_back({"hand_cupped", Make(ShapeKind::kHandCupped, {32.0, 24.0}, 70)});
  ContactShape smallHand = Make(ShapeKind::kHandFive, {44.0, 20.0}, -10);
  smallHand.scale = 0.8;
  cases.push_back({"hand_five_small", smallHand});
  return cases;
}

void PrintTo(const AccuracyCase& c, std::ostream* os) {
  *os << c.name;
}

class ContourAccuracy : public ::testing::TestWithParam<AccuracyCase> {};

TEST_P(ContourAccuracy, WithinOnePixelOfTruth) {
  const AccuracyCase& c = GetParam();
  const TableParams table;
  SyntheticCamera camera(HardCamera(), table);
  Sensor sensor;
  SensingParams params;
  ASSERT_FALSE(sensor.Configure(params, table, CalibrationFromModel(camera.model())));
  ASSERT_FALSE(sensor.SetBackground(camera.Background()));

  const ContactShape shapes[] = {c.shape};
  const Contour truth = camera.TrueOutlines(shapes)[0];
  // a few frames, so several noise draws are checked
  for (int frame = 0; frame < 3; ++frame) {
    Result<ContourFrame> r = sensor.Step(camera.Render(shapes), frame, frame / 60.0);
    ASSERT_TRUE(r) << r.error().Format();
    ASSERT_EQ(r.value().blobs.size(), 1u) << c.name;
    const Blob& blob = r.value().blobs[0];
    // the acceptance bound of the issue: the contour within 1 camera pixel (Hausdorff)
    const double h = HausdorffPixels(camera.model(), truth, blob.contour);
    EXPECT_LE(h, 1.0) << c.name << " frame " << frame;
    // area and centroid follow from the outline: a 1 px band around the perimeter bounds them
    const double cmpp =
        camera.model().CmPerPixel(camera.model().TableToCamera(PolygonCentroid(truth)));
    const double truthArea = SignedArea(truth);
    EXPECT_NEAR(blob.area, truthArea, Perimeter(truth) * cmpp) << c.name;
    EXPECT_LT((blob.centroid - PolygonCentroid(truth)).norm(), cmpp) << c.name;
    if (frame == 0) std::printf("%-16s Hausdorff %.3f px\n", c.name.c_str(), h);
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ContourAccuracy, ::testing::ValuesIn(AccuracyCases()),
                         [](const auto& info) { return info.param.name; });

// a sensor looking through a camera, with the true calibration and the noiseless background
struct Rig {
  explicit Rig(SyntheticCameraParams p = HardCamera(), SensingParams sp = SensingParams())
      : camera(p, table) {
    EXPECT_FALSE(sensor.Configure(sp, table, CalibrationFromModel(camera.model())));
  }
  TableParams table;
  SyntheticCamera camera;
  Sensor sensor;
};

ContactShape Circle(Vec2 pos, double radius) {
  ContactShape s;
  s.pose.pos = pos;
  s.radius = radius;
  return s;
}

// The sensor's own opening of radius 1 against OpenCV's, bit for bit: binary images (what the
// sensor opens) and grey ones, at sizes that exercise the 16-pixel blocks, their remainders and
// the image's edges (one row, one column, narrower than a block).
TEST(OpenCross3, GivesWhatMorphologyExGives) {
  cv::RNG rng(20261127);
  const cv::Size sizes[] = {{640, 480}, {17, 5}, {33, 2},  {1, 9},
                            {9, 1},     {1, 1},  {16, 16}, {50, 31}};
  for (const cv::Size& size : sizes) {
    for (int kind = 0; kind < 3; ++kind) {
      cv::Mat src(size, CV_8UC1);
      rng.fill(src, cv::RNG::UNIFORM, 0, 256);
      // kind 0: grey; 1: sparse binary (specks to remove); 2: dense binary (holes to keep)
      if (kind == 1) cv::threshold(src, src, 200, 255, cv::THRESH_BINARY);
      if (kind == 2) cv::threshold(src, src, 40, 255, cv::THRESH_BINARY);
      cv::Mat expected, scratch;
      cv::morphologyEx(src, expected, cv::MORPH_OPEN, OpeningKernel(1));
      cv::Mat got = src.clone();
      OpenCross3(got, scratch);
      EXPECT_EQ(cv::countNonZero(got != expected), 0) << size << " kind " << kind;

      // the image 0 outside a few areas (overlapping, at the edges, one beyond the image), as
      // the sensor's tiled high-pass leaves it, opened in those areas only; scratch left dirty
      const std::vector<cv::Rect> areas = {
          cv::Rect(size.width / 4, size.height / 4, size.width / 2 + 1, size.height / 2 + 1),
          cv::Rect(0, 0, size.width / 3 + 1, size.height / 3 + 1),
          cv::Rect(size.width / 3, size.height / 5, size.width, size.height / 2 + 1)};
      cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
      for (const cv::Rect& a : areas) mask(a & cv::Rect(cv::Point(), size)).setTo(255);
      cv::Mat sparse = cv::Mat::zeros(size, CV_8UC1);
      src.copyTo(sparse, mask);
      cv::morphologyEx(sparse, expected, cv::MORPH_OPEN, OpeningKernel(1));
      scratch.setTo(255);
      OpenCross3(sparse, scratch, &areas);
      EXPECT_EQ(cv::countNonZero(sparse != expected), 0) << size << " kind " << kind << " areas";
    }
  }
}

TEST(Sensor, EmptyTableHasNoPhantoms) {
  // noise, vignetting, gradient and distortion on, for every background strategy and every
  // threshold mode: 20 frames each (the adaptive mode 180, 3 s, so that its level has come down
  // from the threshold to the noise floor: with no touch seen it is held at the threshold for a
  // second from the first frame, then falls by a factor e a second from 30 to 5 sigma = 16 grey,
  // by 1.6 s) must hold no contact at all. At 16 grey, 5 deviations of the 3-grey noise, a pixel
  // passes with probability 3e-7 and a contact needs a cross of 5 such pixels to survive the
  // opening.
  for (int strategy = 0; strategy < 3; ++strategy) {
    for (ThresholdMode mode :
         {ThresholdMode::kFixed, ThresholdMode::kAuto, ThresholdMode::kAdaptive}) {
      SensingParams sp;
      sp.thresholdMode = mode;
      sp.backgroundFrames = strategy == 1 ? 4 : 0;
      Rig rig(HardCamera(11 + strategy), sp);
      if (strategy == 2) {
        ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
      }
      const int frames = mode == ThresholdMode::kAdaptive ? 180 : 20;
      for (int i = 0; i < frames; ++i) {
        Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render({}), i, i / 60.0);
        ASSERT_TRUE(r) << r.error().Format();
        EXPECT_TRUE(r.value().blobs.empty())
            << "strategy " << strategy << " mode " << static_cast<int>(mode) << " frame " << i;
      }
    }
  }
}

TEST(Sensor, StrongNoiseAndGradientStillNoPhantoms) {
  // twice the default noise and gradient, estimated background: 5 sigma below the threshold of 30
  // (the fixed mode; and the adaptive mode once adapted, whose noise floor is then 5 sigma =
  // 30 grey too), over 3 s of frames
  for (ThresholdMode mode : {ThresholdMode::kFixed, ThresholdMode::kAdaptive}) {
    SyntheticCameraParams p = HardCamera(5);
    p.noise = 6.0;
    p.gradient = 24.0;
    SensingParams sp;
    sp.thresholdMode = mode;
    Rig rig(p, sp);
    for (int i = 0; i < 180; ++i) {
      Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render({}), i, i / 60.0);
      ASSERT_TRUE(r);
      EXPECT_TRUE(r.value().blobs.empty()) << "mode " << static_cast<int>(mode) << " frame " << i;
    }
  }
}

// The adaptive level on a dim table like t2.avi's: touches 10 grey above a table whose camera
// noise is 0.7 grey (the fixed threshold of 30 sees none of them).
//  - Noise floor: frame and background are whole grey levels, so the noise the sensor sees is
//    sqrt(0.7^2 + 1/12 + 1/12) = 0.81 grey (each rounding is uniform, variance 1/12; the
//    calibrated background is noiseless). The median of |frame - background| over a clear table
//    (the touches cover under 1% of the frame) is 0.6745 of that; read on whole-grey differences,
//    interpolating linearly within the bin [0.5, 1.5) where the density in fact falls, it comes
//    out at 0.5 + (0.5 - 0.463) / 0.473 = 0.578, so sigma reads 0.86: 5 sigma = 4.3 +- 0.5 grey
//    (the sample, the touches).
//  - Brightest touch: a 10-grey disc less the high-pass's mean over its 4 cm blur (a 1.6 cm disc
//    is (0.8 / 2)^2 = 16% of it) is 8.4 grey, its 3x3 mean within a grey of that (noise, 8-bit
//    truncation); 0.3 x 8.4 = 2.5 grey, under the noise floor.
//  - So from the first touched frame (the warm-up needs none with a calibrated background; the
//    noise is averaged over the first second, the mean so far standing meanwhile; issue 45: the
//    level starts from the frame's brightest fingertip-like touch, not from the threshold)
//    the level is 4.3 +- 0.5 grey, at least 3.6 grey (4 sigma) below the touches' 8.4, and every
//    touch is found within the synthetic camera's 1 px (0.1 cm); the clear frames between hold
//    no contact. The first frame, clear, shows no touch: the level is the threshold there.
// The same table's touches at full contrast (180 grey) hold the level at the threshold from the
// first frame: 0.3 x 180 = 54 > 30.
TEST(Sensor, AdaptiveLevelFindsADimTablesTouchesAndKeepsTheThresholdOnABrightOne) {
  const ContactShape touches[] = {Circle({15.0, 15.0}, 0.8), Circle({30.0, 25.0}, 0.8),
                                  Circle({45.0, 15.0}, 0.8)};
  for (int seed : {3, 11}) {
    SyntheticCameraParams dim;
    dim.noise = 0.7;
    dim.contactLevel = dim.background + 10.0;
    dim.haloLevel = 0.0;
    dim.seed = seed;
    Rig rig(dim);
    ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
    int phantoms = 0;
    for (int i = 0; i < 480; ++i) {
      const bool touched = i % 2 == 1;
      const cv::Mat frame = touched ? rig.camera.Render(touches) : rig.camera.Render({});
      Result<ContourFrame> r = rig.sensor.Step(frame, i, i / 60.0);
      ASSERT_TRUE(r);
      const double level = rig.sensor.LastThreshold();
      if (i == 0) {
        EXPECT_EQ(level, 30.0) << "seed " << seed;
        continue;
      }
      EXPECT_NEAR(level, 4.3, 0.5) << "seed " << seed << " frame " << i;
      if (!touched) {
        phantoms += static_cast<int>(r.value().blobs.size());
        continue;
      }
      ASSERT_EQ(r.value().blobs.size(), std::size(touches)) << "seed " << seed << " frame " << i;
      for (const ContactShape& t : touches) {
        double nearest = 1e9;
        for (const Blob& b : r.value().blobs)
          nearest = std::min(nearest, (b.centroid - t.pose.pos).norm());
        EXPECT_LT(nearest, 0.1) << "seed " << seed << " frame " << i;
      }
    }
    EXPECT_EQ(phantoms, 0) << "seed " << seed;

    SyntheticCameraParams bright = dim;
    bright.contactLevel = 220.0;
    Rig brightRig(bright);
    ASSERT_FALSE(brightRig.sensor.SetBackground(brightRig.camera.Background()));
    for (int i = 0; i < 240; ++i) {
      ASSERT_TRUE(brightRig.sensor.Step(brightRig.camera.Render(touches), i, i / 60.0));
      EXPECT_EQ(brightRig.sensor.LastThreshold(), 30.0) << "seed " << seed << " frame " << i;
    }
  }
}

TEST(Sensor, HaloIsNotAContact) {
  // a hand's halo is dimmer than the threshold: one blob whose area matches the hand, not the halo
  Rig rig;
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  ContactShape hand = Make(ShapeKind::kHandFlat, {30.0, 20.0}, 0);
  const ContactShape shapes[] = {hand};
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  const double truthArea = SignedArea(ShapeOutline(hand));
  // tolerance: a 0.1 cm (about one pixel) band around the outline
  EXPECT_NEAR(r.value().blobs[0].area, truthArea, 0.1 * Perimeter(ShapeOutline(hand)));
}

TEST(Sensor, EstimatedBackgroundWithHandsOnTheTable) {
  // no clear-table frame at all: the first frame shows two hands and ten fingertips; the estimate
  // must still find every contact and no more
  Rig rig;
  std::vector<ContactShape> shapes;
  ASSERT_TRUE(DemoScene("fingers", 30, rig.table, shapes));
  ContactShape hand = Make(ShapeKind::kHandFlat, {30.0, 10.0}, 0);
  hand.scale = 0.8;
  shapes.push_back(hand);
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r.value().blobs.size(), shapes.size());
}

TEST(Sensor, ContourConventions) {
  Rig rig;
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Make(ShapeKind::kHandFive, {30.0, 18.0}, 10)};
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 3, 0.05);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  const Blob& b = r.value().blobs[0];
  EXPECT_EQ(r.value().index, 3);
  EXPECT_DOUBLE_EQ(r.value().time, 0.05);
  // counter-clockwise, implicitly closed (no repeated first point), evenly spaced near 0.3 cm
  EXPECT_GT(SignedArea(b.contour), 0.0);
  EXPECT_GT((b.contour.col(0) - b.contour.col(b.contour.cols() - 1)).norm(), 1e-6);
  const double spacing = Perimeter(b.contour) / b.contour.cols();
  EXPECT_NEAR(spacing, 0.3, 0.03);  // count = round(perimeter / 0.3): within 10%
  for (int i = 0; i < b.contour.cols(); ++i) {
    const double step = (b.contour.col((i + 1) % b.contour.cols()) - b.contour.col(i)).norm();
    // a chord is never longer than its arc, which is 0.3 cm up to the rounding of the count
    EXPECT_LE(step, 0.3 * 1.05) << "point " << i;
  }
  // the summary agrees with the contour
  EXPECT_TRUE(PointInPolygon(b.contour, b.centroid));
  EXPECT_LE(b.boundsMin.x(), b.contour.row(0).minCoeff() + 1e-9);
  EXPECT_GE(b.boundsMax.y(), b.contour.row(1).maxCoeff() - 1e-9);
}

TEST(Sensor, SmallContactsAreRemoved) {
  SensingParams sp;
  sp.minArea = 0.5;
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  // areas 0.28 cm^2 (removed) and 0.79 cm^2 (kept)
  const ContactShape shapes[] = {Circle({20.0, 20.0}, 0.3), Circle({40.0, 20.0}, 0.5)};
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  EXPECT_NEAR(r.value().blobs[0].centroid.x(), 40.0, 0.1);
}

TEST(Sensor, SetParamsChangesAConfiguredSensorAndKeepsItsBackground) {
  SensingParams sp;
  sp.minArea = 0.5;
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat background = rig.sensor.Background().clone();
  const ContactShape shapes[] = {Circle({20.0, 20.0}, 0.3), Circle({40.0, 20.0}, 0.5)};
  const cv::Mat frame = rig.camera.Render(shapes);
  Result<ContourFrame> before = rig.sensor.Step(frame, 0, 0.0, true);
  ASSERT_TRUE(before);
  ASSERT_EQ(before.value().blobs.size(), 1u);

  // the 0.28 cm^2 contact is kept, contours are sampled twice as far apart, the table image
  // has pixels twice as large
  sp.minArea = 0.1;
  sp.spacing = 0.6;
  sp.tableCmPerPixel = 0.2;
  sp.morphology = 0;
  ASSERT_FALSE(rig.sensor.SetParams(sp));
  EXPECT_EQ(rig.sensor.params().minArea, 0.1);
  Result<ContourFrame> after = rig.sensor.Step(frame, 1, 0.0, true);
  ASSERT_TRUE(after);
  ASSERT_EQ(after.value().blobs.size(), 2u);
  const Blob& big = before.value().blobs[0];
  const Blob& same = after.value().blobs[0];
  EXPECT_NEAR(same.centroid.x(), 40.0, 0.1);
  // a 3.1 cm circumference: about 10 points at 0.3 cm, 5 at 0.6 cm
  EXPECT_LT(same.contour.cols(), big.contour.cols());
  EXPECT_EQ(after.value().tableImage.image.cols, 305);  // 61 cm / 0.2 cm
  EXPECT_EQ(cv::norm(rig.sensor.Background(), background, cv::NORM_INF), 0.0);
}

TEST(Sensor, SetParamsRejectsWhatOnlyConfigureCanChange) {
  Sensor unconfigured;
  const MaybeError none = unconfigured.SetParams(SensingParams{});
  ASSERT_TRUE(none);
  EXPECT_THAT(none->Format(), HasSubstr("not configured"));

  Rig rig;
  SensingParams sp = rig.sensor.params();
  sp.threshold = 90.0;
  sp.calibration = "other.yaml";
  sp.backgroundFrames = 3;
  EXPECT_EQ(rig.sensor.FixedKeysChanged(sp),
            (std::vector<std::string>{"calibration", "background_frames"}));
  const MaybeError fixed = rig.sensor.SetParams(sp);
  ASSERT_TRUE(fixed);
  EXPECT_EQ(fixed->Format(),
            "sensing.calibration: cannot change on a configured sensor (Configure it again)");
  sp = rig.sensor.params();
  sp.threshold = 90.0;
  sp.spacing = 0.0;
  const MaybeError bad = rig.sensor.SetParams(sp);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->Format(), "sensing.spacing must be in [0.05, 5] cm (got 0)");
  // nothing changed
  EXPECT_EQ(rig.sensor.params().threshold, SensingParams().threshold);
  EXPECT_TRUE(rig.sensor.FixedKeysChanged(rig.sensor.params()).empty());
}

TEST(Sensor, BlobsAreLargestFirstAndTouchingShapesMerge) {
  Rig rig;
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  // two overlapping fingertips are one component; a larger one elsewhere comes first
  const ContactShape shapes[] = {Circle({10.0, 10.0}, 0.8), Circle({11.2, 10.0}, 0.8),
                                 Circle({40.0, 30.0}, 2.0)};
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 2u);
  EXPECT_NEAR(r.value().blobs[0].centroid.x(), 40.0, 0.1);
  EXPECT_NEAR(r.value().blobs[1].centroid.x(), 10.6, 0.1);
}

TEST(Sensor, HolesAreIgnored) {
  // a square frame of four bars (6 cm outside, 4 cm inside) is one component with a hole: the
  // outer contour alone describes it
  Rig rig;
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  std::vector<ContactShape> bars;
  for (int i = 0; i < 4; ++i) {
    ContactShape bar;
    bar.kind = ShapeKind::kConvexPolygon;
    bar.points = {{-3, -3}, {3, -3}, {3, -2}, {-3, -2}};
    bar.pose.pos = {30, 23};
    bar.pose.angle = i * kPi / 2;
    bars.push_back(bar);
  }
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(bars), 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  // the outer square's area, not the frame's: 36 cm^2 (tolerance: a 0.1 cm band round 24 cm)
  EXPECT_NEAR(r.value().blobs[0].area, 36.0, 2.4);
}

TEST(Sensor, BackgroundCapturedFromFirstFrames) {
  SensingParams sp;
  sp.backgroundFrames = 3;
  Rig rig(HardCamera(), sp);
  const ContactShape shapes[] = {Circle({30.0, 20.0}, 1.0)};
  // the first three frames (clear table) go into the background and report nothing
  for (int i = 0; i < 3; ++i) {
    Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render({}), i, 0.0);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r.value().blobs.empty());
  }
  EXPECT_TRUE(rig.sensor.HasBackground());
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 3, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  EXPECT_NEAR(r.value().blobs[0].area, kPi, 0.1 * 2.0 * kPi);
}

TEST(Sensor, AutomaticThresholdFindsContacts) {
  SensingParams sp;
  sp.thresholdMode = ThresholdMode::kAuto;
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Circle({20.0, 20.0}, 1.0),
                                 Make(ShapeKind::kHandFlat, {40, 20}, 0)};
  Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r.value().blobs.size(), 2u);
  // Otsu splits contact (~150 above background) from the rest, far above the floor
  EXPECT_GT(rig.sensor.LastThreshold(), SensingParams().autoFloor);
}

TEST(Sensor, TableImageOnRequest) {
  SyntheticCameraParams p = HardCamera();
  Rig rig(p);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Circle({20.0, 30.0}, 1.5)};
  const cv::Mat frame = rig.camera.Render(shapes);
  Result<ContourFrame> without = rig.sensor.Step(frame, 0, 0.0);
  ASSERT_TRUE(without);
  EXPECT_TRUE(without.value().tableImage.image.empty());
  Result<ContourFrame> with = rig.sensor.Step(frame, 1, 0.0, true);
  ASSERT_TRUE(with);
  const TableImage& t = with.value().tableImage;
  ASSERT_EQ(t.image.type(), CV_8UC1);
  EXPECT_EQ(t.image.cols, 610);  // 61 cm / 0.1 cm
  EXPECT_EQ(t.image.rows, 460);
  // pixel (u, v) covers (u + 0.5, v + 0.5) * 0.1 cm: the circle's centre is bright, far is dark
  EXPECT_GT(t.image.at<uint8_t>(300, 200), 100);
  EXPECT_LT(t.image.at<uint8_t>(300, 260), 30);
  EXPECT_LT(t.image.at<uint8_t>(160, 200), 30);
}

TEST(Sensor, BadFramesGiveErrorsNamingTheFrame) {
  Rig rig;
  Result<ContourFrame> empty = rig.sensor.Step(cv::Mat(), 7, 0.0);
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().Format(), "frame 7: empty frame (expected 640x480 8-bit grey, CV_8UC1)");

  Result<ContourFrame> small = rig.sensor.Step(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)), 8, 0.0);
  ASSERT_FALSE(small);
  EXPECT_EQ(small.error().Format(), "frame 8: frame is 320x240, expected 640x480");

  Result<ContourFrame> deep = rig.sensor.Step(cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)), 9, 0.0);
  ASSERT_FALSE(deep);
  EXPECT_THAT(
      deep.error().Format(),
      HasSubstr("frame 9: frame type is CV_16UC1, expected 8-bit grey (CV_8UC1) or colour"));

  Result<ContourFrame> floats = rig.sensor.Step(cv::Mat(480, 640, CV_32F, cv::Scalar(0)), 10, 0.0);
  ASSERT_FALSE(floats);
  EXPECT_THAT(floats.error().Format(), HasSubstr("frame 10: frame type is CV_32FC1"));

  // the sensor keeps working after bad frames
  Result<ContourFrame> good = rig.sensor.Step(rig.camera.Render({}), 11, 0.0);
  EXPECT_TRUE(good);
}

TEST(Sensor, UnconfiguredSensorSaysSo) {
  Sensor sensor;
  Result<ContourFrame> r = sensor.Step(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), 0, 0.0);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("not configured"));
}

TEST(Sensor, ConfigureErrorsNameTheFileAndField) {
  Sensor sensor;
  SensingParams sp;
  sp.calibration = "/nonexistent/calib.yaml";
  MaybeError s = sensor.Configure(sp, TableParams{}, cv::Size(640, 480));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->Format(), "/nonexistent/calib.yaml: calibration file not found");

  // a calibration for another image size
  const std::string path = ::testing::TempDir() + "/calib_320.yaml";
  ASSERT_FALSE(SaveCalibration(path, LinearCalibration({320, 240}, TableParams{})));
  sp.calibration = path;
  s = sensor.Configure(sp, TableParams{}, cv::Size(640, 480));
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr(path + ": field 'image_width'/'image_height' is 320x240"));

  sp.calibration = "";
  sp.spacing = 0.0;
  s = sensor.Configure(sp, TableParams{}, cv::Size(640, 480));
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr("sensing.spacing"));

  MaybeError bg = sensor.SetBackground(cv::Mat(10, 10, CV_8UC1));
  ASSERT_TRUE(bg);
  EXPECT_THAT(bg->Format(), HasSubstr("background"));
}

TEST(Sensor, CalibrationFileRoundTripGivesTheSameContours) {
  // the same calibration in memory and through a YAML file (with its background) sense alike
  Rig rig;
  const std::string path = ::testing::TempDir() + "/calib_true.yaml";
  ASSERT_FALSE(
      SaveCalibration(path, CalibrationFromModel(rig.camera.model(), rig.camera.Background())));
  Sensor fromFile;
  SensingParams sp;
  sp.calibration = path;
  ASSERT_FALSE(fromFile.Configure(sp, rig.table, cv::Size(640, 480)));
  ASSERT_TRUE(fromFile.HasBackground());
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Make(ShapeKind::kHandCupped, {30, 20}, 40)};
  const cv::Mat frame = rig.camera.Render(shapes);
  Result<ContourFrame> a = rig.sensor.Step(frame, 0, 0.0);
  Result<ContourFrame> b = fromFile.Step(frame, 0, 0.0);
  ASSERT_TRUE(a);
  ASSERT_TRUE(b);
  ASSERT_EQ(a.value().blobs.size(), 1u);
  ASSERT_EQ(b.value().blobs.size(), 1u);
  // YAML stores doubles with 16 significant digits: the contours agree to well under a micron
  EXPECT_LT(HausdorffDistance(a.value().blobs[0].contour, b.value().blobs[0].contour), 1e-4);
}

TEST(EstimateBackground, MatchesTheClearTableUnderContacts) {
  SyntheticCamera camera(HardCamera(), TableParams{});
  std::vector<ContactShape> shapes;
  shapes.push_back(Make(ShapeKind::kHandFlat, {20, 20}, 0));
  shapes.push_back(Make(ShapeKind::kHandFive, {42, 20}, 0));
  const cv::Mat estimate =
      EstimateBackground(camera.Render(shapes), 1.0 / camera.model().CmPerPixel(Vec2(320, 240)));
  const cv::Mat clear = camera.Background();
  // away from the hands (beyond their halo and 3 cm, two of the estimate's 1.5 cm blocks) the
  // estimate is the clear table within 8 grey (the opening's lower envelope of the vignetting and
  // gradient, interpolation); near them it may absorb part of the halo (brighter), but it is never
  // more than 12 grey darker than the clear table, so it cannot lift the background noise over the
  // 30 grey threshold anywhere
  double worstFar = 0.0, worstDarker = 0.0;
  for (int v = 0; v < clear.rows; ++v) {
    for (int u = 0; u < clear.cols; ++u) {
      const double diff = static_cast<double>(estimate.at<uint8_t>(v, u)) - clear.at<uint8_t>(v, u);
      worstDarker = std::max(worstDarker, -diff);
      const Vec2 t = camera.model().CameraToTable(Vec2(u, v));
      double nearest = 1e9;
      for (const ContactShape& s : shapes) nearest = std::min(nearest, ShapeDistance(s, t));
      if (nearest > camera.params().haloWidth + 3.0) worstFar = std::max(worstFar, std::abs(diff));
    }
  }
  EXPECT_LT(worstFar, 8.0);
  EXPECT_LT(worstDarker, 12.0);
}

TEST(Sensor, ColourFramesAreConvertedToGrey) {
  Rig rig;
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Circle({30.0, 20.0}, 0.8)};
  const cv::Mat grey = rig.camera.Render(shapes);
  cv::Mat bgr, bgra;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  for (const cv::Mat& frame : {bgr, bgra}) {
    Result<ContourFrame> r = rig.sensor.Step(frame, 0, 0.0);
    ASSERT_TRUE(r) << r.error().Format();
    ASSERT_EQ(r.value().blobs.size(), 1u);
    // grey in, grey out: the same contact as from the grey frame, well inside the 1 px accuracy
    EXPECT_NEAR(r.value().blobs[0].centroid.x(), 30.0, 0.1);
    EXPECT_EQ(cv::norm(rig.sensor.StageImage(SensingStage::kCamera), grey, cv::NORM_INF), 0.0);
  }
}

TEST(Sensor, EveryStageImageIsKept) {
  Rig rig;
  const ContactShape shapes[] = {Circle({30.0, 20.0}, 0.8)};
  ASSERT_TRUE(rig.sensor.Step(rig.camera.Render(shapes), 0, 0.0));
  for (int k = 0; k < kSensingStageCount; ++k) {
    const cv::Mat& m = rig.sensor.StageImage(static_cast<SensingStage>(k));
    EXPECT_EQ(m.size(), cv::Size(640, 480)) << kSensingStageNames[k];
    EXPECT_EQ(m.type(), CV_8UC1) << kSensingStageNames[k];
  }
  // the binary image holds the fingertip (pixel of its centre) and nothing far from it
  const Vec2 centre = rig.camera.model().TableToCamera(Vec2(30.0, 20.0));
  const cv::Mat& binary = rig.sensor.StageImage(SensingStage::kBinary);
  EXPECT_EQ(binary.at<uint8_t>(static_cast<int>(centre.y()), static_cast<int>(centre.x())), 255);
  EXPECT_EQ(binary.at<uint8_t>(10, 10), 0);
}

TEST(Sensor, StagesSwitchedOnAndOffLiveKeepEveryStageImageTrue) {
  // A stage that changes nothing shows its input without a copy. Switching smoothing, the
  // high-pass and the gain on and off between frames, in every combination and order, must never
  // make one stage write over another's image: each stage image is checked against its
  // definition from the one before, computed here with plain OpenCV calls.
  SensingParams sp;
  sp.backgroundLearning = 0.0;  // s: the background stays the one given
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Circle({30.0, 20.0}, 0.8), Circle({12.0, 30.0}, 1.0)};
  const cv::Mat frame = rig.camera.Render(shapes);
  // the sensor's sizes: pixels per cm at the image centre
  const double pxPerCm = 1.0 / rig.camera.model().CmPerPixel(Vec2(320.0, 240.0));
  for (int combo = 0; combo < 24; ++combo) {
    const int bits = combo % 8 ^ (combo / 8);   // every combination, in three orders
    sp.smooth = (bits & 1) ? 0.1 : 0.0;         // cm
    sp.highpassWidth = (bits & 2) ? 4.0 : 0.0;  // cm
    sp.gain = (bits & 4) ? 2.0 : 1.0;
    ASSERT_FALSE(rig.sensor.SetParams(sp));
    ASSERT_TRUE(rig.sensor.Step(frame, combo, combo / 60.0));
    auto stage = [&](SensingStage s) { return rig.sensor.StageImage(s).clone(); };
    cv::Mat expect;
    cv::subtract(frame, rig.camera.Background(), expect);
    EXPECT_EQ(cv::norm(stage(SensingStage::kSubtracted), expect, cv::NORM_INF), 0.0) << bits;
    const cv::Mat subtracted = expect.clone();
    const double sigma = sp.smooth * pxPerCm;
    if (sigma >= 0.3)
      cv::GaussianBlur(subtracted, expect, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
    EXPECT_EQ(cv::norm(stage(SensingStage::kSmoothed), expect, cv::NORM_INF), 0.0) << bits;
    const cv::Mat smoothed = expect.clone();
    if (sp.highpassWidth > 0.0) {
      const int w = static_cast<int>(std::lround(sp.highpassWidth * pxPerCm)) | 1;
      cv::Mat wide;
      cv::blur(smoothed, wide, cv::Size(w, w), cv::Point(-1, -1), cv::BORDER_REPLICATE);
      cv::min(wide, sp.highpassCap, wide);
      cv::subtract(smoothed, wide, expect);
    }
    EXPECT_EQ(cv::norm(stage(SensingStage::kHighpass), expect, cv::NORM_INF), 0.0) << bits;
    expect.convertTo(expect, CV_8UC1, sp.gain);
    EXPECT_EQ(cv::norm(stage(SensingStage::kGained), expect, cv::NORM_INF), 0.0) << bits;
  }
}

// a clear table frame with a wide, faint glow (a palm or arm hovering above an FTIR surface):
// a Gaussian of `sigmaCm` and `level` grey above the synthetic background
cv::Mat WithGlow(const Rig& rig, cv::Mat frame, Vec2 at, double sigmaCm, double level) {
  for (int v = 0; v < frame.rows; ++v) {
    for (int u = 0; u < frame.cols; ++u) {
      const Vec2 t = rig.camera.model().CameraToTable(Vec2(u, v));
      const double g = level * std::exp(-(t - at).squaredNorm() / (2.0 * sigmaCm * sigmaCm));
      uint8_t& p = frame.at<uint8_t>(v, u);
      p = cv::saturate_cast<uint8_t>(p + g);
    }
  }
  return frame;
}

TEST(Sensor, HighpassFadesAWideGlowAndKeepsAFingertip) {
  // a 4 cm (deviation) glow 45 grey bright, with a fingertip on it: the glow alone is over the
  // threshold of 30; the high-pass (4 cm wide, removing up to 40 grey) leaves the glow at most
  // 45 - 40 = 5 grey where its own blur is at its peak, so only the fingertip is a contact
  SensingParams sp;  // the defaults
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const ContactShape shapes[] = {Circle({30.0, 22.0}, 0.8)};
  const cv::Mat frame = WithGlow(rig, rig.camera.Render(shapes), Vec2(30.0, 18.0), 4.0, 45.0);
  Result<ContourFrame> r = rig.sensor.Step(frame, 0, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  EXPECT_NEAR(r.value().blobs[0].centroid.x(), 30.0, 0.1);
  EXPECT_NEAR(r.value().blobs[0].centroid.y(), 22.0, 0.1);

  // without the high-pass the glow is a contact (with the fingertip in it)
  sp.highpassWidth = 0.0;
  ASSERT_FALSE(rig.sensor.SetParams(sp));
  r = rig.sensor.Step(frame, 1, 0.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  EXPECT_GT(r.value().blobs[0].area, 10.0);  // cm^2: far more than a 2 cm^2 fingertip
}

TEST(Sensor, BackgroundFollowsTheFramesWhereNothingTouches) {
  SensingParams sp;
  sp.backgroundLearning = 1.0;  // s
  sp.touchLearning = 0.0;       // never under a contact (see the test below)
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat before = rig.sensor.Background().clone();
  // the room light goes up by 20 grey while a finger rests at (30, 20)
  const ContactShape shapes[] = {Circle({30.0, 20.0}, 0.8)};
  cv::Mat frame = rig.camera.Render(shapes);
  frame += cv::Scalar(20);
  // 5 s at 30 frames/s = 5 time constants: 1 - e^-5 = 99.3% of the change is learned
  for (int i = 0; i <= 150; ++i) {
    Result<ContourFrame> r = rig.sensor.Step(frame, i, i / 30.0);
    ASSERT_TRUE(r);
    ASSERT_EQ(r.value().blobs.size(), 1u) << "frame " << i;
  }
  const cv::Mat& after = rig.sensor.Background();
  // far from the finger: within 1 grey (0.7% of 20 plus rounding) of the brighter frame
  EXPECT_NEAR(after.at<uint8_t>(100, 100), frame.at<uint8_t>(100, 100), 1.0);
  // under the finger: unchanged
  const Vec2 c = rig.camera.model().TableToCamera(Vec2(30.0, 20.0));
  const cv::Point at(static_cast<int>(c.x()), static_cast<int>(c.y()));
  EXPECT_EQ(after.at<uint8_t>(at), before.at<uint8_t>(at));

  // frames at the same time as the last one change nothing
  const cv::Mat kept = after.clone();
  ASSERT_TRUE(rig.sensor.Step(rig.camera.Render(shapes), 151, 150 / 30.0));
  EXPECT_EQ(cv::norm(rig.sensor.Background(), kept, cv::NORM_INF), 0.0);
}

// How much the background's mean over the 9 x 9 px round a table point changed, grey.
double PatchChange(const Rig& rig, const cv::Mat& before, const cv::Mat& after, Vec2 at) {
  const Vec2 c = rig.camera.model().TableToCamera(at);
  const cv::Rect patch(static_cast<int>(c.x()) - 4, static_cast<int>(c.y()) - 4, 9, 9);
  return cv::mean(after(patch))[0] - cv::mean(before(patch))[0];
}

// A hand hovering over the table glows there: brighter than the table by less than a touch, so
// no contact, but not the table either. Learned at background_learning (10 s) as the table is,
// 20 s of it raised the background by 1 - e^-2 = 86% of the glow, and a fingertip landing there
// lost that much of its contrast (t2.avi's frame 1500: a ring fingertip 8 grey above the table,
// 4 above a background its hovering hand had raised). A pixel brighter than the background by the
// bright margin (3 noise deviations: 9 grey on this camera) is learned as a contact is, at
// touch_learning (300 s). The glow here: 25 grey at its centre, 4 cm wide (deviation), which the
// high-pass fades below the level; held for 20 s at 15 frames/s (four noise draws in turn).
// The background's rise, the mean over 9 x 9 px (the four draws' noise, 1.5 grey a pixel, and the
// rounding to whole grey levels average out to under 0.3 grey):
// - at the glow's centre at most 25 (1 - e^(-20/300)) = 1.6 grey, plus 1 for what averages out
//   only in part: 2.6 (before, 25 (1 - e^-2) = 21.6);
// - 4 cm out, where the glow is 15.2 grey, a pixel's noise (3 grey) takes it under the margin in
//   1.9% of draws (6.2 grey, 2.07 deviations): those are learned at the full rate, the others at
//   touch_learning's, 15.2 (0.019 (1 - e^-2) + 1 - e^(-20/300)) = 1.2 grey, plus 1: 2.2;
// - away from the glow the table is learned as before: within 1 grey of where it was.
TEST(Sensor, AHoveringHandsGlowIsNotLearnedIntoTheBackground) {
  SensingParams sp;  // the defaults: background_learning 10 s, touch_learning 300 s
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat before = rig.sensor.Background().clone();
  const Vec2 at(30.0, 22.0);
  const cv::Mat glow = WithGlow(rig, cv::Mat::zeros(before.size(), CV_8UC1), at, 4.0, 25.0);
  std::vector<cv::Mat> frames;
  for (int k = 0; k < 4; ++k) frames.push_back(rig.camera.Render({}) + glow);
  for (int i = 0; i <= 300; ++i) {
    Result<ContourFrame> r = rig.sensor.Step(frames[i % 4], i, i / 15.0);
    ASSERT_TRUE(r) << r.error().Format();
    ASSERT_TRUE(r.value().blobs.empty()) << "frame " << i;
  }
  const cv::Mat& after = rig.sensor.Background();
  auto rise = [&](Vec2 p) { return PatchChange(rig, before, after, p); };
  EXPECT_LE(rise(at), 2.6);
  EXPECT_LE(rise(at + Vec2(4.0, 0.0)), 2.2);
  EXPECT_LE(rise(at + Vec2(0.0, 4.0)), 2.2);
  EXPECT_LE(std::abs(rise(Vec2(8.0, 8.0))), 1.0);
  EXPECT_LE(std::abs(rise(Vec2(52.0, 38.0))), 1.0);
  std::printf("rise: centre %.2f, 4 cm out %.2f and %.2f, away %.2f and %.2f grey\n", rise(at),
              rise(at + Vec2(4.0, 0.0)), rise(at + Vec2(0.0, 4.0)), rise(Vec2(8.0, 8.0)),
              rise(Vec2(52.0, 38.0)));
}

// Something dark that lies long on the table (a finger's shadow in strong ambient light) is learned
// at background_learning, and when it goes the table there reads brighter than the background:
// not a glow, which the rule above would learn only at touch_learning, keeping the background
// low for minutes. The background's long-term level (learned everywhere at touch_learning) tells
// them apart: where the background lies below it by more than the margin, the brighter table is
// learned back at background_learning. A spot 30 grey deep, 2 cm across (0.5 cm deviation),
// lies 10 s on the table: the background there comes down 30 (1 - e^-1) = 19 grey, the long-term
// level 30 (1 - e^(-10/300)) = 1 grey. When it goes, the background comes back at the full rate
// until it lies within the margin m (3 measured noise deviations, 9 to 10.5 grey here) of the
// long-term level: T ln(19 / m) = 6.4 to 7.5 s. From there it comes back at the share of the
// camera's draws that read within the margin of it, at least half (the draws are symmetric about
// the table, which lies above it), so at d <= m e^(-(t - 7.5 s) / 2T). 40 s after it went that is
// 10.5 e^-1.6 = 2.0 grey, plus 1 for the 8-bit background the comparisons read and what the
// 9 x 9 px mean of 16 noise draws leaves: within 3 grey of the clear table (with bright pixels
// learned at touch_learning alone it was still 10.5 grey below). No contact comes from it.
TEST(Sensor, ADarkSpotThatGoesIsLearnedBack) {
  SensingParams sp;  // the defaults
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat before = rig.sensor.Background().clone();
  const Vec2 at(30.0, 22.0);
  const cv::Mat spot = WithGlow(rig, cv::Mat::zeros(before.size(), CV_8UC1), at, 0.5, 30.0);
  // 16 noise draws in turn: the last grey levels come back through the draws that read within
  // the margin, which a pixel with only a few draws might never have
  std::vector<cv::Mat> clear, dark;
  for (int k = 0; k < 16; ++k) {
    clear.push_back(rig.camera.Render({}));
    dark.push_back(clear.back() - spot);
  }
  for (int i = 0; i <= 750; ++i) {
    const double t = i / 15.0;
    Result<ContourFrame> r = rig.sensor.Step(t < 10.0 ? dark[i % 16] : clear[i % 16], i, t);
    ASSERT_TRUE(r) << r.error().Format();
    ASSERT_TRUE(r.value().blobs.empty()) << "frame " << i;
  }
  const double left = PatchChange(rig, before, rig.sensor.Background(), at);
  std::printf("background at the spot 40 s after it went: %.2f grey from the clear table\n", left);
  EXPECT_NEAR(left, 0.0, 3.0);
}

// A noiseless camera: every |frame - background| is 0, so the measured noise is 0, and the level
// would come down to 0 (any grey level above the table a contact). It stops at the rounding of
// frame and background to whole grey levels, which every 8-bit camera has: 5 x sqrt(2 / 12) =
// 2.04 grey. After 3 s (warm-up, a second of measuring, the fall from 30 to 2 takes ln 15 =
// 2.7 s more: 4 s in all) the level is that, and the empty table shows nothing.
TEST(Sensor, AdaptiveLevelOnANoiselessCameraStopsAtTheRounding) {
  SyntheticCameraParams p = HardCamera(4);
  p.noise = 0.0;
  Rig rig(p);
  for (int i = 0; i < 300; ++i) {
    Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render({}), i, i / 60.0);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r.value().blobs.empty()) << "frame " << i;
  }
  EXPECT_NEAR(rig.sensor.LastThreshold(), 5.0 * std::sqrt(2.0 / 12.0), 1e-9);
}

// Under a contact the background learns with touch_learning. A bright disc that never changes
// (180 grey above the table at its centre; the fixed threshold 30) fades out of the contacts once
// the background under it has learned all but 30 of its 180 grey: 1 - e^(-t / T) = 5/6, so at
// t = T ln 6 = 3.6 s for T = 2 s. Each band of rows learns under contacts when its turn comes
// (every 8 frames, 0.13 s) once T / 100 has passed, at the rate for the time since it last did,
// so that moment comes up to 0.13 s late; the disc's rim falls below the threshold before its
// centre, and the rim then learns at background_learning, so it may go sooner but not before its
// centre is half learned (t = T ln 2 = 1.4 s). So: present at 0.3 s, gone by 4.8 s. With
// touch_learning = 0 it stays.
TEST(Sensor, AContactThatNeverChangesFadesIntoTheBackground) {
  const ContactShape spot[] = {Circle({30.0, 20.0}, 1.0)};
  for (double touchLearning : {2.0, 0.0}) {
    SensingParams sp;
    sp.thresholdMode = ThresholdMode::kFixed;
    sp.touchLearning = touchLearning;
    sp.backgroundLearning = 1.0;
    Rig rig(HardCamera(), sp);
    ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
    for (int i = 0; i <= 360; ++i) {
      Result<ContourFrame> r = rig.sensor.Step(rig.camera.Render(spot), i, i / 60.0);
      ASSERT_TRUE(r);
      const size_t n = r.value().blobs.size();
      if (i <= 18 || touchLearning == 0.0) {
        EXPECT_EQ(n, 1u) << "touch_learning " << touchLearning << " frame " << i;
      }
      if (i >= 288 && touchLearning > 0.0) {
        EXPECT_EQ(n, 0u) << "frame " << i;
      }
    }
  }
}

TEST(Sensor, EveryBandOfRowsLearnsWithTheSameTimeConstant) {
  // The learning updates one of 8 bands of rows a frame, in turn, each with the rate for the
  // time since it was last learned. The same frame, with the room light up by 20 grey, comes
  // again and again: a pixel learned last at time s holds d (1 - e^(-s / T)) of its change d
  // (the frame's pixel less the background's). At t = 1 s with T = 1 s and 30 frames/s, every
  // band was learned within the last 8 frames, so s is in (1 - 7/30, 1] s: between
  // d (1 - e^-0.767) = 0.54 d and d (1 - e^-1) = 0.63 d, plus 1 grey of rounding either way.
  SensingParams sp;
  sp.backgroundLearning = 1.0;  // s
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat before = rig.sensor.Background().clone();
  cv::Mat frame = rig.camera.Render({});
  frame += cv::Scalar(20);
  for (int i = 0; i <= 30; ++i) ASSERT_TRUE(rig.sensor.Step(frame, i, i / 30.0));
  const cv::Mat& after = rig.sensor.Background();
  const double early = 1.0 - std::exp(-(1.0 - 7.0 / 30.0));
  const double late = 1.0 - std::exp(-1.0);
  // one row in every band of 60 rows
  for (int row = 30; row < after.rows; row += 60) {
    for (int col : {100, 320, 540}) {
      const double d = frame.at<uint8_t>(row, col) - before.at<uint8_t>(row, col);
      const double learned = after.at<uint8_t>(row, col) - before.at<uint8_t>(row, col);
      EXPECT_GE(learned, early * d - 1.0) << "row " << row << " col " << col << " d " << d;
      EXPECT_LE(learned, late * d + 1.0) << "row " << row << " col " << col << " d " << d;
    }
  }
}

TEST(Sensor, TimeWithLearningOffIsNotLearnedWhenItComesBackOn) {
  // Learning (T = 1 s) runs for a second, is switched off for 10 s while the room light goes up
  // by 20 grey, then comes back on for 8 frames at 30 frames/s (every band once). Only those
  // 8 frames are learned: at most d (1 - e^(-8/30)) = 0.23 d of a pixel's change d, plus 1 grey
  // of rounding. Had the bands kept their times from before, each would take the 10 s at once
  // (1 - e^-10, all of it).
  SensingParams sp;
  sp.backgroundLearning = 1.0;  // s
  Rig rig(HardCamera(), sp);
  ASSERT_FALSE(rig.sensor.SetBackground(rig.camera.Background()));
  const cv::Mat clear = rig.camera.Render({});
  cv::Mat brighter = clear.clone();
  brighter += cv::Scalar(20);
  int index = 0;
  for (int i = 0; i <= 30; ++i, ++index) ASSERT_TRUE(rig.sensor.Step(clear, index, i / 30.0));
  const cv::Mat learnedClear = rig.sensor.Background().clone();
  sp.backgroundLearning = 0.0;
  ASSERT_FALSE(rig.sensor.SetParams(sp));
  for (int i = 31; i <= 330; ++i, ++index) ASSERT_TRUE(rig.sensor.Step(brighter, index, i / 30.0));
  EXPECT_EQ(cv::norm(rig.sensor.Background(), learnedClear, cv::NORM_INF), 0.0);
  sp.backgroundLearning = 1.0;
  ASSERT_FALSE(rig.sensor.SetParams(sp));
  for (int i = 331; i <= 338; ++i, ++index) ASSERT_TRUE(rig.sensor.Step(brighter, index, i / 30.0));
  const cv::Mat& after = rig.sensor.Background();
  const double most = 1.0 - std::exp(-8.0 / 30.0);
  for (int row = 30; row < after.rows; row += 60) {
    for (int col : {100, 320, 540}) {
      const double d = brighter.at<uint8_t>(row, col) - learnedClear.at<uint8_t>(row, col);
      const double learned = after.at<uint8_t>(row, col) - learnedClear.at<uint8_t>(row, col);
      EXPECT_LE(learned, most * d + 1.0) << "row " << row << " col " << col << " d " << d;
      EXPECT_GE(learned, 0.0) << "row " << row << " col " << col;
    }
  }
}

TEST(Sensor, WarmupMakesAStaticHotSpotBackground) {
  // no background given: estimated from the first frame, which shows an illuminator's hot spot
  // (a 3 cm deviation glow 150 grey bright, wider than the 32 px blocks of the estimate); after
  // the warm-up (0.3 s) it is background, and a fingertip that comes later is the only contact
  SensingParams sp;  // the defaults
  Rig rig(HardCamera(), sp);
  const cv::Mat empty = WithGlow(rig, rig.camera.Render({}), Vec2(15.0, 30.0), 3.0, 150.0);
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(rig.sensor.Step(empty, i, i / 30.0));
  Result<ContourFrame> r = rig.sensor.Step(empty, 30, 1.0);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r.value().blobs.empty());
  const ContactShape shapes[] = {Circle({40.0, 20.0}, 0.8)};
  const cv::Mat touched = WithGlow(rig, rig.camera.Render(shapes), Vec2(15.0, 30.0), 3.0, 150.0);
  r = rig.sensor.Step(touched, 31, 31 / 30.0);
  ASSERT_TRUE(r);
  ASSERT_EQ(r.value().blobs.size(), 1u);
  EXPECT_NEAR(r.value().blobs[0].centroid.x(), 40.0, 0.1);
}

// The pipeline's sensor works the high-pass out only in the tiles where a pixel is bright enough
// to pass the threshold (SetWholeStages(false)). The high-pass never brightens a pixel, so the
// thresholded image must be the same bits as the whole frame's, and so must every contour. Checked
// on frames with fingertips, hands at several pressures (faint ones near the threshold), wide
// glows and one touching the image's edge, at several thresholds and gains.
// The adaptive level with the partial high-pass: the level each frame and the thresholded image
// are those of the whole frame's, bit for bit, on a dim table (touches 12 grey, noise 1: the
// level comes down to the noise floor, about 6.1 grey (below): the estimated background's warm-up
// of 0.3 s and a second of noise measuring, then the fall from 30 by a factor e a second, by
// 1.3 + ln(30 / 6.1) = 2.9 s) through the level's fall, and when a full-contrast touch lands at
// 3.5 s (the brightest touch rises at once, the level with it) and lifts at 4.5 s (the level
// stays: the touch is remembered for contrast_memory).
TEST(Sensor, AdaptiveLevelWithTheHighpassOnlyWhereContactsCanBeIsTheWholeFramesLevel) {
  SyntheticCameraParams dim = HardCamera(9);
  dim.noise = 1.0;
  dim.contactLevel = dim.background + 12.0;
  dim.haloLevel = 0.0;
  Rig whole(dim), parts(dim);
  parts.sensor.SetWholeStages(false);
  int samples = 0, onContacts = 0;
  SyntheticCameraParams brightParams = dim;
  brightParams.contactLevel = 220.0;
  SyntheticCamera bright(brightParams, whole.table);
  double lowest = 255.0;
  for (int i = 0; i < 330; ++i) {
    std::vector<ContactShape> shapes = {Circle({10.0 + 0.05 * i, 12.0}, 0.8),
                                        Make(ShapeKind::kHandFive, {35.0, 22.0}, 0.5 * i)};
    cv::Mat frame = whole.camera.Render(shapes);
    if (i >= 210 && i < 270) {
      // a firm touch beside them: the bright camera's frame there, the dim one's elsewhere
      const ContactShape firm[] = {Circle({50.0, 35.0}, 0.9)};
      const cv::Mat lit = bright.Render(firm);
      const cv::Point c(static_cast<int>(whole.camera.model().TableToCamera({50.0, 35.0}).x()),
                        static_cast<int>(whole.camera.model().TableToCamera({50.0, 35.0}).y()));
      const cv::Rect r = cv::Rect(c.x - 20, c.y - 20, 41, 41) & cv::Rect(cv::Point(), frame.size());
      lit(r).copyTo(frame(r));
    }
    ASSERT_TRUE(whole.sensor.Step(frame, i, i / 60.0));
    ASSERT_TRUE(parts.sensor.Step(frame, i, i / 60.0));
    ASSERT_EQ(whole.sensor.LastThreshold(), parts.sensor.LastThreshold()) << "frame " << i;
    ASSERT_EQ(cv::norm(whole.sensor.StageImage(SensingStage::kBinary),
                       parts.sensor.StageImage(SensingStage::kBinary), cv::NORM_INF),
              0.0)
        << "frame " << i;
    if (i < 210) lowest = std::min(lowest, whole.sensor.LastThreshold());
    if (i >= 150 && i < 210) {
      // the share of the noise samples (every 8th column of every 8th row) on the contacts
      const cv::Mat clear = whole.camera.Background();
      for (int y = 4; y < frame.rows; y += 8) {
        for (int x = 4; x < frame.cols; x += 8) {
          ++samples;
          onContacts += std::abs(frame.at<uint8_t>(y, x) - clear.at<uint8_t>(y, x)) > 6;
        }
      }
    }
    // the firm touch (about 180 grey): 0.3 x 180 > 30 holds the level at the threshold
    if (i >= 210) {
      EXPECT_EQ(whole.sensor.LastThreshold(), 30.0) << "frame " << i;
    }
  }
  // Before it: down to the noise floor. The noise the sensor sees: the camera's 1 grey, the
  // rounding of frame and background (1/12 each) and what the estimated background kept of the
  // noise during its warm-up (an average with weight a = 1 - e^(-1/6) a frame keeps a / (2 - a) =
  // 0.083 of the variance): sqrt(1 + 2/12 + 0.083) = 1.12 grey. For that deviation a whole grey
  // level d reads 0 with chance 0.345 and 1 with chance 0.475. The hand and the touch are a share
  // f of the samples, all above the median: the median is the noise's 0.5 / (1 - f) quantile,
  // interpolated linearly in the bin [0.5, 1.5): 0.5 + (0.5 / (1 - f) - 0.345) / 0.475 (0.826
  // for f = 0), over 0.6745 is sigma, and the level 5 sigma (6.1 for f = 0) +- 0.4 (the sample
  // is finite). The hand lies on the table from the first frame: the warm-up takes in what of
  // it has not moved by 0.2 s, until it moves (TrackStillRegions), and the noise is read with the
  // whole of it.
  ASSERT_GT(samples, 0);
  const double f = static_cast<double>(onContacts) / samples;
  const double median = 0.5 + (0.5 / (1.0 - f) - 0.345) / 0.475;
  std::printf("contacts' share of the noise samples %.3f: the level %.2f, derived %.2f\n", f,
              lowest, 5.0 * median / 0.6745);
  EXPECT_NEAR(lowest, 5.0 * median / 0.6745, 0.4);
}

TEST(Sensor, HighpassOnlyWhereContactsCanBeGivesTheSameContours) {
  struct Setting {
    double threshold, gain, cap;
  };
  const Setting settings[] = {{30.0, 1.0, 40.0},
                              {60.0, 1.0, 40.0},
                              {10.0, 1.0, 255.0},
                              {40.0, 2.7, 40.0},
                              {30.0, 0.6, 40.0}};
  int frames = 0;
  for (const Setting& setting : settings) {
    SensingParams sp;
    sp.threshold = setting.threshold;
    sp.gain = setting.gain;
    sp.highpassCap = setting.cap;
    Rig whole(HardCamera(5), sp), parts(HardCamera(5), sp);
    ASSERT_TRUE(whole.sensor.WholeStages());  // the default: a sensor shows every stage
    parts.sensor.SetWholeStages(false);
    ASSERT_FALSE(whole.sensor.SetBackground(whole.camera.Background()));
    ASSERT_FALSE(parts.sensor.SetBackground(parts.camera.Background()));
    for (int i = 0; i < 8; ++i) {
      std::vector<ContactShape> shapes;
      const double drift = 1.0 * i;
      shapes.push_back(Circle({8.0 + drift, 10.0}, 0.8));
      shapes.push_back(Circle({0.4, 20.0 + drift}, 0.9));  // across the image's left edge
      ContactShape five = Make(ShapeKind::kHandFive, {22.0 + drift, 20.0}, 15.0 * i);
      five.pressure = 0.15 + 0.1 * i;  // from faint (near the threshold) to firm
      shapes.push_back(five);
      shapes.push_back(Make(ShapeKind::kHandFlat, {45.0, 30.0 - drift}, -20.0));
      cv::Mat frame = whole.camera.Render(shapes);
      frame = WithGlow(whole, frame, Vec2(50.0, 8.0 + drift), 3.0, 25.0 + 7.0 * i);
      Result<ContourFrame> a = whole.sensor.Step(frame, i, i / 60.0);
      Result<ContourFrame> b = parts.sensor.Step(frame, i, i / 60.0);
      ASSERT_TRUE(a && b);
      ++frames;
      const std::string where = "threshold " + std::to_string(setting.threshold) + " gain " +
                                std::to_string(setting.gain) + " frame " + std::to_string(i);
      EXPECT_EQ(cv::norm(whole.sensor.StageImage(SensingStage::kBinary),
                         parts.sensor.StageImage(SensingStage::kBinary), cv::NORM_INF),
                0.0)
          << where;
      // where the two high-pass images differ, the partial one was not worked out (0) and the
      // whole one's gained level does not pass the threshold
      const cv::Mat& hpWhole = whole.sensor.StageImage(SensingStage::kHighpass);
      const cv::Mat& hpParts = parts.sensor.StageImage(SensingStage::kHighpass);
      const cv::Mat& gainedWhole = whole.sensor.StageImage(SensingStage::kGained);
      int differing = 0, wrong = 0;
      for (int v = 0; v < hpWhole.rows; ++v) {
        for (int u = 0; u < hpWhole.cols; ++u) {
          if (hpWhole.at<uint8_t>(v, u) == hpParts.at<uint8_t>(v, u)) continue;
          ++differing;
          if (hpParts.at<uint8_t>(v, u) != 0 || gainedWhole.at<uint8_t>(v, u) > setting.threshold)
            ++wrong;
        }
      }
      EXPECT_EQ(wrong, 0) << where;
      // at threshold 10 the camera's noise (3 grey deviation) reaches the level somewhere in
      // every tile, and the whole frame is worked out
      if (i == 0 && setting.threshold >= 30.0) {
        EXPECT_GT(differing, 0) << where << ": the partial chain skipped nothing";
      }
      const std::vector<Blob>& ba = a.value().blobs;
      const std::vector<Blob>& bb = b.value().blobs;
      ASSERT_EQ(ba.size(), bb.size()) << where;
      EXPECT_GE(ba.size(), 2u) << where;
      for (size_t k = 0; k < ba.size(); ++k) {
        ASSERT_EQ(ba[k].contour.cols(), bb[k].contour.cols()) << where;
        EXPECT_EQ((ba[k].contour - bb[k].contour).cwiseAbs().maxCoeff(), 0.0) << where;
      }
    }
  }
  EXPECT_EQ(frames, 40);
}

// ---- real table footage (../shared/real) ----

// the labelled clips, or a skip message
struct RealData {
  std::string dir;
  std::vector<real::LabelledClip> clips;
};
RealData LoadReal() {
  RealData d;
  d.dir = real::RealDataDir();
  if (!d.dir.empty())
    d.clips = real::ReadLabels(std::string(pg::test::TestDataDir()) + "/real_labels.txt");
  return d;
}
constexpr const char* kNoRealData =
    "../shared/real is absent (a clone of the project alone): no real footage to test on; set "
    "PROXYGRASP_REAL_DATA to its folder";

// scores the labelled frames of the clips whose path contains one of `names`
real::Score ScoreClips(const RealData& d, const std::vector<std::string>& names) {
  real::Score total;
  for (const real::LabelledClip& clip : d.clips) {
    bool wanted = false;
    for (const std::string& n : names) wanted = wanted || clip.path.find(n) != std::string::npos;
    if (!wanted) continue;
    real::ClipScorer scorer(clip);
    const bool read = real::RunClip(
        d.dir, clip, SensingParams(), clip.LastFrame(),
        [&](int i, const ContourFrame& f, const Sensor& sensor) { scorer(i, f, sensor); });
    EXPECT_TRUE(read) << "cannot read " << d.dir << "/" << clip.path;
    const real::Score& s = scorer.score;
    std::printf(
        "%-50s %2d frames: %3d of %3d fingertips found, %2d of %3d contacts unmatched (%2d "
        "without the hand circles)\n",
        clip.path.c_str(), s.frames, s.found, s.tips, s.unmatched, s.contacts, s.offTips);
    total.frames += s.frames;
    total.tips += s.tips;
    total.found += s.found;
    total.contacts += s.contacts;
    total.unmatched += s.unmatched;
    total.offTips += s.offTips;
    total.misses += s.misses;
  }
  return total;
}

// every labelled clip
const std::vector<std::string> kAllClips = {"hard-5point", "seth_tests", "t2.avi", "realhands"};

TEST(RealFootage, DefaultsFindAtLeast95PercentOfTheLabelledFingertips) {
  const RealData d = LoadReal();
  if (d.dir.empty()) GTEST_SKIP() << kNoRealData;
  const real::Score s = ScoreClips(d, kAllClips);
  ASSERT_GT(s.tips, 200);
  // issue 14 acceptance: a contact's contour holds (within the 3 px label precision) the label
  EXPECT_GE(s.found, 0.95 * s.tips) << s.misses;
}

// t2.avi alone: its hands are a few grey levels above the table (the fixed threshold of 30 finds
// none of them); the adaptive level comes down to them (docs/sensing.md).
TEST(RealFootage, DefaultsFindTheLowContrastHandsOfT2) {
  const RealData d = LoadReal();
  if (d.dir.empty()) GTEST_SKIP() << kNoRealData;
  const real::Score s = ScoreClips(d, {"t2.avi"});
  ASSERT_EQ(s.tips, 60);
  EXPECT_GE(s.found, 0.95 * s.tips) << s.misses;
}

// "No contact at a static hot spot of t2.avi after the first second". A contact "at" a hot spot:
// its centroid within half the spot's radius of the centre. The hands pass over the lower hot
// spots (frame 300's left palm lies on one), and a hand there is a contact at the spot that is no
// phantom; so two checks:
//  - on the frames where the table is clear (the labels' `clear` ranges, seen by eye: from frame
//    1900 the hands are gone), none at all;
//  - at no time after the first second does a contact stay at a hot spot for 2 s (117 frames): a
//    phantom of a static spot stays as long as the spot does, while a hand moves on (the longest
//    a hand lingered at one was 0.75 s, frames 1471 to 1514).
TEST(RealFootage, DefaultsFindNoContactAtTheHotSpotsOfT2AfterTheFirstSecond) {
  const RealData d = LoadReal();
  if (d.dir.empty()) GTEST_SKIP() << kNoRealData;
  for (const real::LabelledClip& clip : d.clips) {
    if (clip.hotspots.empty()) continue;
    ASSERT_FALSE(clip.clear.empty()) << clip.path;
    int clearHits = 0, frames = 0, clearFrames = 0;
    std::vector<int> run(clip.hotspots.size(), 0), longest(clip.hotspots.size(), 0);
    ASSERT_TRUE(real::RunClip(d.dir, clip, SensingParams(), 1 << 30,
                              [&](int i, const ContourFrame& f, const Sensor& sensor) {
                                ++frames;
                                if (f.time <= 1.0) return;
                                clearFrames += clip.IsClear(i) ? 1 : 0;
                                for (size_t k = 0; k < clip.hotspots.size(); ++k) {
                                  const real::Spot& h = clip.hotspots[k];
                                  bool at = false;
                                  for (const Blob& b : f.blobs) {
                                    const Vec2 c = real::CentroidPixel(b, sensor);
                                    at = at || std::hypot(c.x() - h.x, c.y() - h.y) < 0.5 * h.r;
                                  }
                                  run[k] = at ? run[k] + 1 : 0;
                                  longest[k] = std::max(longest[k], run[k]);
                                  if (at && clip.IsClear(i)) ++clearHits;
                                }
                              }));
    EXPECT_GT(frames, 2000) << clip.path;
    EXPECT_GT(clearFrames, 400) << clip.path;
    EXPECT_EQ(clearHits, 0) << clip.path;
    for (size_t k = 0; k < clip.hotspots.size(); ++k) {
      std::printf("%s hot spot (%.0f, %.0f): longest stay of a contact %d frames\n",
                  clip.path.c_str(), clip.hotspots[k].x, clip.hotspots[k].y, longest[k]);
      EXPECT_LT(longest[k], 117) << clip.path << " hot spot " << k;
    }
  }
}

// The pipeline's partial high-pass (Sensor::SetWholeStages(false)) on real footage: the same
// thresholded image, bit for bit, as the whole frame's on every frame of the FTIR clips (a
// textured background, glowing arms) and of t2.avi (hot spots), up to the 300th frame of each
// video clip, from their first frame (background estimated, warm-up) on.
TEST(RealFootage, HighpassOnlyWhereContactsCanBeGivesTheSameThresholdedImage) {
  const RealData d = LoadReal();
  if (d.dir.empty()) GTEST_SKIP() << kNoRealData;
  int compared = 0;
  for (const real::LabelledClip& clip : d.clips) {
    if (clip.IsStill()) continue;
    cv::VideoCapture video(d.dir + "/" + clip.path);
    ASSERT_TRUE(video.isOpened()) << clip.path;
    Sensor whole, parts;
    parts.SetWholeStages(false);
    cv::Mat frame;
    for (int i = 0; i < 300 && video.read(frame); ++i) {
      if (i == 0) {
        const TableParams table = real::ClipTable(clip, frame.size());
        const Calibration calibration = LinearCalibration(frame.size(), table);
        ASSERT_FALSE(whole.Configure(SensingParams(), table, calibration, clip.path));
        ASSERT_FALSE(parts.Configure(SensingParams(), table, calibration, clip.path));
      }
      ASSERT_TRUE(whole.Step(frame, i, i / 30.0));
      ASSERT_TRUE(parts.Step(frame, i, i / 30.0));
      ASSERT_EQ(cv::norm(whole.StageImage(SensingStage::kBinary),
                         parts.StageImage(SensingStage::kBinary), cv::NORM_INF),
                0.0)
          << clip.path << " frame " << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 800);
}

// Issue 14: at most 1 contact per 20 labelled frames that holds no fingertip label and lies in no
// "maybe" or "hand" circle (within the labels' 3 px reading precision, as for the fingertips).
// Two in 43 frames are expected, and both are false contacts by the labels: hard-5point.avi's
// first frame shows a static bright streak of the table (no background is known yet, and its
// block estimate cannot tell a streak from a touch on one frame), and seth_tests.avi's frame 500
// a glowing finger segment that no circle covers. Three more lie on t2.avi's fingers, 0.7 to
// 2.5 px outside the hand circles drawn there (docs/sensing.md shows them). Without the hand
// circles, 12.
TEST(RealFootage, DefaultsFindAtMostOneUnlabelledContactPer20Frames) {
  const RealData d = LoadReal();
  if (d.dir.empty()) GTEST_SKIP() << kNoRealData;
  const real::Score s = ScoreClips(d, kAllClips);
  std::printf("all clips: %d unmatched in %d frames (%d without the hand circles)\n", s.unmatched,
              s.frames, s.offTips);
  EXPECT_LE(s.unmatched * 20, s.frames) << s.misses;
}

}  // namespace
}  // namespace pg
