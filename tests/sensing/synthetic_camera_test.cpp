#include "proxygrasp/sensing/synthetic_camera.h"

#include "proxygrasp/core/rng.h"
#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace pg {
namespace {

ContactShape Shape(ShapeKind kind, Vec2 pos = {30, 23}, double angle = 0.0) {
  ContactShape s;
  s.kind = kind;
  s.pose.pos = pos;
  s.pose.angle = angle;
  return s;
}

double Len(const Contour& c) {
  return Perimeter(c);
}

TEST(ShapeOutline, AnalyticAreas) {
  // dense outlines (<= 0.05 cm steps) differ from the analytic areas by the chord loss only,
  // well under 0.5%
  ContactShape circle = Shape(ShapeKind::kCircle);
  circle.radius = 1.3;
  EXPECT_NEAR(SignedArea(ShapeOutline(circle)), kPi * 1.3 * 1.3, 0.005 * kPi * 1.69);
  ContactShape ellipse = Shape(ShapeKind::kEllipse, {10, 10}, 0.4);
  ellipse.radiusX = 2.0;
  ellipse.radiusY = 0.7;
  EXPECT_NEAR(SignedArea(ShapeOutline(ellipse)), kPi * 2.0 * 0.7, 0.005 * kPi * 1.4);
  ContactShape capsule = Shape(ShapeKind::kCapsule);
  capsule.radius = 0.8;
  capsule.length = 4.0;
  EXPECT_NEAR(SignedArea(ShapeOutline(capsule)), kPi * 0.64 + 2 * 0.8 * 4.0, 0.005 * 8.4);
  ContactShape poly = Shape(ShapeKind::kConcavePolygon, {5, 5});
  poly.points = {{0, 0}, {0, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 0}};  // an L, clockwise
  EXPECT_DOUBLE_EQ(SignedArea(ShapeOutline(poly)), 3.0);
}

TEST(ShapeOutline, OutlineIsTheZeroLevelOfTheDistance) {
  // every outline point lies on the boundary the renderer draws (|distance| < 0.005 cm)
  for (ShapeKind kind : {ShapeKind::kCircle, ShapeKind::kEllipse, ShapeKind::kCapsule,
                         ShapeKind::kHandFive, ShapeKind::kHandFlat, ShapeKind::kHandCupped}) {
    const ContactShape s = Shape(kind, {25, 20}, 0.7);
    const Contour c = ShapeOutline(s);
    ASSERT_GT(c.cols(), 50);
    double worst = 0.0;
    for (int i = 0; i < c.cols(); ++i)
      worst = std::max(worst, std::abs(ShapeDistance(s, c.col(i))));
    EXPECT_LT(worst, 0.005) << kShapeKindNames[static_cast<int>(kind)];
    EXPECT_GT(SignedArea(c), 0.0) << "counter-clockwise";
  }
}

TEST(ShapeOutline, HandSizes) {
  // scale 1 is an adult hand about 19 cm long (heel of the palm to the middle fingertip)
  for (ShapeKind kind : {ShapeKind::kHandFive, ShapeKind::kHandFlat}) {
    const Contour c = ShapeOutline(Shape(kind, {0, 0}));
    const double length = c.row(1).maxCoeff() - c.row(1).minCoeff();
    EXPECT_NEAR(length, 19.0, 0.5) << kShapeKindNames[static_cast<int>(kind)];
    ContactShape half = Shape(kind, {0, 0});
    half.scale = 0.5;
    const Contour h = ShapeOutline(half);
    EXPECT_NEAR(h.row(1).maxCoeff() - h.row(1).minCoeff(), 0.5 * length, 0.05);
  }
  // the cupped hand's edge is a band about 1.5 cm thick: area / centreline length
  const Contour cup = ShapeOutline(Shape(ShapeKind::kHandCupped, {0, 0}));
  const double centreline = 5.4 * DegToRad(200.0);
  const double capArea = kPi * 0.75 * 0.75;  // the two rounded ends
  EXPECT_NEAR((SignedArea(cup) - capArea) / centreline, 1.5, 0.02);
  EXPECT_NEAR(centreline + 1.5, 20.4, 1.5) << "about one hand long";
  // the five fingers are spread: the outline has five tips, i.e. a long perimeter
  EXPECT_GT(Len(ShapeOutline(Shape(ShapeKind::kHandFive))),
            Len(ShapeOutline(Shape(ShapeKind::kHandFlat))) + 10.0);
}

TEST(ShapeOutline, PoseMovesTheOutline) {
  const Contour a = ShapeOutline(Shape(ShapeKind::kHandFive, {0, 0}, 0.0));
  const Contour b = ShapeOutline(Shape(ShapeKind::kHandFive, {10, 5}, kPi / 2));
  ASSERT_EQ(a.cols(), b.cols());
  for (int i = 0; i < a.cols(); i += 97)
    EXPECT_LT((b.col(i) - (Rotate(a.col(i), kPi / 2) + Vec2(10, 5))).norm(), 1e-9);
}

TEST(SampledHandDistance, StaysWithinItsBoundOfTheExactDistance) {
  // bilinear between exact nodes 0.05 cm apart (unscaled) of a sqrt(2)-Lipschitz distance: within
  // sqrt(2) * 0.05 / sqrt(2) = 0.05 cm times the scale (synthetic_camera.cpp derives it); the
  // worst seen must also be above zero, or the test would pass on the exact distance alone
  Rng rng(17);
  for (ShapeKind kind : {ShapeKind::kHandFive, ShapeKind::kHandFlat, ShapeKind::kHandCupped}) {
    for (double scale : {0.6, 1.0, 1.3}) {
      // unturned, so that the grid (the hand's bounds and 2.5 cm unscaled beyond) holds the
      // outline's bounds and 2.4 cm unscaled beyond
      ContactShape hand = Shape(kind, {30, 23});
      hand.scale = scale;
      const auto [lo, hi] = ShapeBounds(hand);
      const double margin = 2.4 * scale;
      double worst = 0.0, bound = 0.0;
      int sampled = 0;
      for (int i = 0; i < 20000; ++i) {
        const Vec2 p(rng.Uniform(lo.x() - margin, hi.x() + margin),
                     rng.Uniform(lo.y() - margin, hi.y() + margin));
        double d, error;
        if (!SampledHandDistance(hand, p, d, error)) continue;
        ++sampled;
        bound = error;
        worst = std::max(worst, std::abs(d - ShapeDistance(hand, p)));
      }
      SCOPED_TRACE(testing::Message() << "kind " << static_cast<int>(kind) << " scale " << scale);
      EXPECT_EQ(sampled, 20000);
      RecordProperty("worst_cm", std::to_string(worst));
      EXPECT_NEAR(bound, scale * 0.05, scale * 1e-4);
      EXPECT_LE(worst, bound);
      EXPECT_GT(worst, 1e-4) << "interpolated, not exact";
    }
  }
  double d, error;
  EXPECT_FALSE(SampledHandDistance(Shape(ShapeKind::kCircle), {30, 23}, d, error));
  EXPECT_FALSE(SampledHandDistance(Shape(ShapeKind::kHandFlat), {300, 23}, d, error))
      << "off the grid";
}

TEST(SyntheticCamera, FrameFormatAndLevels) {
  SyntheticCameraParams p;
  p.noise = 0.0;
  const TableParams table;
  SyntheticCamera camera(p, table);
  ContactShape disc = Shape(ShapeKind::kCircle, {30.5, 23.0});
  disc.radius = 2.0;
  const ContactShape shapes[] = {disc};
  const cv::Mat frame = camera.Render(shapes);
  ASSERT_EQ(frame.type(), CV_8UC1);
  ASSERT_EQ(frame.size(), cv::Size(640, 480));
  // the table centre is the image centre without perspective: full contact level there
  EXPECT_NEAR(frame.at<uint8_t>(240, 320), p.contactLevel, 1.0);
  // background: vignetting darkens the corners by 25%, the gradient brightens the right side
  const double left = frame.at<uint8_t>(240, 5), right = frame.at<uint8_t>(240, 634);
  EXPECT_NEAR(right - left, p.gradient * (1 - 0.25 * 0.64), 2.0);
  EXPECT_NEAR(frame.at<uint8_t>(2, 2), (p.background - p.gradient / 2) * (1 - p.vignetting), 1.5);
}

TEST(SyntheticCamera, HaloIsDimmerThanContactAndBelowThreshold) {
  SyntheticCameraParams p;
  p.noise = 0.0;
  const TableParams table;
  SyntheticCamera camera(p, table);
  const ContactShape hand = Shape(ShapeKind::kHandFlat, {30.5, 15.0});
  const ContactShape shapes[] = {hand};
  const cv::Mat frame = camera.Render(shapes);
  const cv::Mat bg = camera.Background();
  // a point 0.5 cm outside the hand: brighter than the background, below the 60 grey threshold
  const Contour outline = ShapeOutline(hand);
  const Vec2 out = outline.col(0) + 0.5 * (outline.col(0) - hand.pose.pos).normalized();
  ASSERT_GT(ShapeDistance(hand, out), 0.3);
  const Vec2 px = camera.model().TableToCamera(out);
  const int above = frame.at<uint8_t>(std::lround(px.y()), std::lround(px.x())) -
                    bg.at<uint8_t>(std::lround(px.y()), std::lround(px.x()));
  EXPECT_GT(above, 10);
  EXPECT_LT(above, 60);
  // circles (fingertips hovering no hand) have no halo
  ContactShape finger = Shape(ShapeKind::kCircle, {10, 10});
  const ContactShape fingers[] = {finger};
  const cv::Mat f = camera.Render(fingers);
  const Vec2 near = camera.model().TableToCamera(Vec2(10 + finger.radius + 0.4, 10));
  EXPECT_LE(std::abs(f.at<uint8_t>(std::lround(near.y()), std::lround(near.x())) -
                     bg.at<uint8_t>(std::lround(near.y()), std::lround(near.x()))),
            1);
}

TEST(SyntheticCamera, DeterministicForASeed) {
  const TableParams table;
  SyntheticCameraParams p;
  const ContactShape shapes[] = {Shape(ShapeKind::kHandFive)};
  SyntheticCamera a(p, table), b(p, table);
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(cv::norm(a.Render(shapes), b.Render(shapes), cv::NORM_INF), 0.0);
  p.seed = 2;
  SyntheticCamera c(p, table);
  SyntheticCamera d(SyntheticCameraParams{}, table);
  EXPECT_GT(cv::norm(c.Render(shapes), d.Render(shapes), cv::NORM_INF), 0.0);
  // consecutive frames differ by their noise only
  SyntheticCamera e(SyntheticCameraParams{}, table);
  const cv::Mat f0 = e.Render(shapes), f1 = e.Render(shapes);
  EXPECT_GT(cv::norm(f0, f1, cv::NORM_INF), 0.0);
  EXPECT_LT(cv::norm(f0, f1, cv::NORM_L2) / std::sqrt(640.0 * 480.0), 3.0 * std::sqrt(2.0) * 1.1);
}

TEST(SyntheticCamera, SetParamsChangesLightingAndNoiseBetweenFrames) {
  const TableParams table;
  SyntheticCameraParams p;
  p.noise = 0.0;
  SyntheticCamera camera(p, table);
  ContactShape disc = Shape(ShapeKind::kCircle, {30.5, 23.0});
  disc.radius = 2.0;
  const ContactShape shapes[] = {disc};
  const cv::Mat quiet = camera.Render(shapes);

  // a brighter, flatter table and a dimmer contact, the same as a camera built with them
  p.background = 70.0;
  p.gradient = 0.0;
  p.vignetting = 0.0;
  p.contactLevel = 180.0;
  ASSERT_FALSE(camera.SetParams(p));
  EXPECT_EQ(camera.params().background, 70.0);
  const SyntheticCamera built(p, table);
  EXPECT_EQ(cv::norm(camera.Background(), built.Background(), cv::NORM_INF), 0.0);
  const cv::Mat lit = camera.Render(shapes);
  EXPECT_NEAR(lit.at<uint8_t>(2, 2), 70.0, 1.0);
  EXPECT_NEAR(lit.at<uint8_t>(240, 320), 180.0, 1.0);
  EXPECT_GT(cv::norm(lit, quiet, cv::NORM_INF), 20.0);

  // noise asked for after the start: consecutive frames now differ
  p.noise = 3.0;
  ASSERT_FALSE(camera.SetParams(p));
  const cv::Mat f0 = camera.Render(shapes), f1 = camera.Render(shapes);
  EXPECT_GT(cv::norm(f0, f1, cv::NORM_INF), 0.0);
}

TEST(SyntheticCamera, SetParamsRejectsWhatFixesTheImageAndChangesNothing) {
  const TableParams table;
  SyntheticCameraParams p;
  SyntheticCamera camera(p, table);
  SyntheticCameraParams next = p;
  next.noise = 1.0;
  next.width = 320;
  next.seed = 9;
  EXPECT_EQ(camera.FixedKeysChanged(next), (std::vector<std::string>{"width", "seed"}));
  const MaybeError s = camera.SetParams(next);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->Format(),
            "camera.width: cannot change on a built camera (it fixes the image and the noise "
            "stream)");
  EXPECT_EQ(camera.params().noise, p.noise);
  EXPECT_EQ(camera.Render({}).cols, 640);
}

TEST(SyntheticCamera, DistortionAndPerspectiveMoveTheImage) {
  const TableParams table;
  SyntheticCameraParams p;
  p.distortion = -0.1;
  p.perspective = 0.1;
  SyntheticCamera camera(p, table);
  const CameraModel& m = camera.model();
  EXPECT_DOUBLE_EQ(m.distCoeffs[0], -0.1);
  // the table's far corners appear inset by the keystone; the near ones at the image corners
  const Vec2 farLeft = m.Distort(Vec2(-0.5 + 0.05 * 640, -0.5));
  EXPECT_LT((m.TableToCamera(Vec2(0, 46)) - farLeft).norm(), 1e-6);
  // a contact drawn at a table point appears at TableToCamera of it
  ContactShape disc = Shape(ShapeKind::kCircle, {8.0, 40.0});
  disc.radius = 1.0;
  p.noise = 0.0;
  SyntheticCamera quiet(p, table);
  const ContactShape shapes[] = {disc};
  const cv::Mat frame = quiet.Render(shapes);
  const Vec2 px = quiet.model().TableToCamera(disc.pose.pos);
  const cv::Point at(std::lround(px.x()), std::lround(px.y()));
  // vignetting dims the contact too, but it stays far above the background there
  EXPECT_GT(frame.at<uint8_t>(at) - quiet.Background().at<uint8_t>(at), 120);
}

TEST(SyntheticCamera, RenderTableImageUsesTheSameModel) {
  const TableParams table;
  SyntheticCameraParams p;
  p.noise = 0.0;
  p.distortion = 0.05;
  SyntheticCamera camera(p, table);
  // a 610x460 table image (0.1 cm pixels) with one white square at table (40..44, 10..14) cm
  cv::Mat tableImage(460, 610, CV_8UC1, cv::Scalar(0));
  tableImage(cv::Rect(400, 460 - 140, 40, 40)).setTo(255);
  const cv::Mat frame = camera.RenderTableImage(tableImage);
  const Vec2 inside = camera.model().TableToCamera(Vec2(42, 12));
  const Vec2 outside = camera.model().TableToCamera(Vec2(47, 12));
  EXPECT_GT(frame.at<uint8_t>(std::lround(inside.y()), std::lround(inside.x())), 200);
  EXPECT_LT(frame.at<uint8_t>(std::lround(outside.y()), std::lround(outside.x())), 60);
  // colour, 4-channel and float images of the same picture render the same
  cv::Mat bgr, bgra, floats;
  cv::cvtColor(tableImage, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(tableImage, bgra, cv::COLOR_GRAY2BGRA);
  tableImage.convertTo(floats, CV_32F, 1.0 / 255.0);
  EXPECT_EQ(cv::norm(camera.RenderTableImage(bgr), frame, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(camera.RenderTableImage(bgra), frame, cv::NORM_INF), 0.0);
  EXPECT_LE(cv::norm(camera.RenderTableImage(floats), frame, cv::NORM_INF), 1.0);
  // an empty table image is the clear table
  EXPECT_LE(cv::norm(camera.RenderTableImage(cv::Mat(460, 610, CV_8UC1, cv::Scalar(0))),
                     camera.Background(), cv::NORM_INF),
            1.0);
}

TEST(SyntheticCamera, EveryPixelFollowsTheImageModel) {
  // the renderer skips blocks far from a shape, reads a hand's halo from its sampled distance, and
  // composes the clear table from a precomputed image; a pixel-by-pixel evaluation of the
  // documented model with the exact distance must give the same image: g (B + (contact - B) c +
  // halo h (1 - c)), with the coverage c = clamp(0.5 - d / s), the halo h = 1 - smoothstep(d /
  // halo_width) outside hands, the vignetting gain g = 1 - vignetting r^2 (r from the centre, 1
  // at the corners) and the background B = background + gradient (u / (width - 1) - 0.5)
  SyntheticCameraParams p;
  p.noise = 0.0;
  p.perspective = 0.05;
  SyntheticCamera camera(p, TableParams{});
  // the flat hand runs off the far edge of the table, past the circle
  const ContactShape shapes[] = {
      Shape(ShapeKind::kHandFive, {20, 20}, 0.3), Shape(ShapeKind::kCircle, {45, 30}),
      Shape(ShapeKind::kHandCupped, {45, 12}, 1.0), Shape(ShapeKind::kHandFlat, {38, 36}, -0.4)};
  const cv::Mat frame = camera.Render(shapes);
  const double cx = (frame.cols - 1) / 2.0, cy = (frame.rows - 1) / 2.0;
  // Pixels with only a halo (outside every outline by more than half a pixel) take it from the
  // sampled distance, within 0.05 cm (scale 1) of the exact one: the halo's slope is at most
  // 1.5 / halo_width per cm (smoothstep's), so they may differ by up to 45 grey x 1.5 / 1.5 cm x
  // 0.05 cm = 2.25 grey more. Every other pixel's coverage and halo are exact.
  const double haloError = p.haloLevel * 1.5 / p.haloWidth * 0.05;
  int worst = 0;
  double worstHalo = 0.0;
  for (int v = 0; v < frame.rows; ++v) {
    for (int u = 0; u < frame.cols; ++u) {
      const Vec2 t = camera.model().CameraToTable(Vec2(u, v));
      const double s = camera.model().CmPerPixel(Vec2(u, v));
      double c = 0.0, h = 0.0;
      bool haloOnly = true;
      for (const ContactShape& shape : shapes) {
        const double d = ShapeDistance(shape, t);
        c = std::max(c, std::clamp(0.5 - d / s, 0.0, 1.0));
        if (shape.kind != ShapeKind::kCircle)
          h = std::max(h, d <= 0.0 ? 1.0 : 1.0 - SmoothStep(d / p.haloWidth));
        if (d <= 0.5 * s + 0.05) haloOnly = false;
      }
      const double gain =
          1.0 - p.vignetting * ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / (cx * cx + cy * cy);
      const double background = p.background + p.gradient * (u / (frame.cols - 1.0) - 0.5);
      const double expected =
          gain * (background + (p.contactLevel - background) * c + p.haloLevel * h * (1.0 - c));
      const double difference = std::abs(frame.at<uint8_t>(v, u) - expected);
      if (haloOnly && h > 0.0)
        worstHalo = std::max(worstHalo, difference);
      else
        worst = std::max(worst, static_cast<int>(difference + 0.5));
    }
  }
  // rounding to 8 bits, and the local pixel size differing slightly between finite differences
  EXPECT_LE(worst, 2);
  EXPECT_LE(worstHalo, 2.5 + haloError);
  RecordProperty("worst_halo_grey", std::to_string(worstHalo));
}

TEST(SyntheticCamera, ReusedBuffersLeaveNothingOfTheLastFrame) {
  // Render keeps its coverage and halo images between frames and clears only what the last
  // frame drew: a frame after other shapes (and after an empty frame) is the frame a fresh camera
  // renders, pixel for pixel; a copied camera draws into its own buffers
  SyntheticCameraParams p;
  p.noise = 0.0;
  const ContactShape first[] = {Shape(ShapeKind::kHandFlat, {20, 20}, 0.3),
                                Shape(ShapeKind::kCircle, {45, 30})};
  const ContactShape second[] = {Shape(ShapeKind::kHandFive, {25, 22}, -0.4)};
  SyntheticCamera fresh(p, TableParams{});
  const cv::Mat expected = fresh.Render(second);
  SyntheticCamera used(p, TableParams{});
  used.Render(first);
  SyntheticCamera copy = used;
  EXPECT_EQ(cv::norm(used.Render(second), expected, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(used.Render({}), fresh.Render({}), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(used.Render(second), expected, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(copy.Render(second), expected, cv::NORM_INF), 0.0);
}

TEST(SyntheticCamera, PressureDimsAContact) {
  SyntheticCameraParams p;
  p.noise = 0.0;
  SyntheticCamera camera(p, TableParams{});
  ContactShape light = Shape(ShapeKind::kCircle, {30.5, 23.0});
  light.radius = 1.5;
  light.pressure = 0.5;
  const ContactShape shapes[] = {light};
  const cv::Mat frame = camera.Render(shapes);
  EXPECT_NEAR(frame.at<uint8_t>(240, 320), 0.5 * (p.contactLevel + p.background), 1.5);
}

TEST(SyntheticCamera, HeightDimsAContact) {
  // a contact 1 cm above the surface shows exp(-1 / 0.5) = 0.135 of its contrast; touching, all
  SyntheticCameraParams p;
  p.noise = 0.0;
  SyntheticCamera camera(p, TableParams{});
  ContactShape raised = Shape(ShapeKind::kCircle, {30.5, 23.0});
  raised.radius = 1.5;
  for (double height : {0.0, 1.0, 3.0}) {
    raised.height = height;
    const ContactShape shapes[] = {raised};
    const cv::Mat frame = camera.Render(shapes);
    const double expected =
        p.background + (p.contactLevel - p.background) * std::exp(-height / 0.5);
    EXPECT_NEAR(IrHoverDimming(height), std::exp(-height / 0.5), 1e-15);
    // 1.5 grey: the vignetting at the centre and the rounding to a grey level
    EXPECT_NEAR(frame.at<uint8_t>(240, 320), expected, 1.5) << height << " cm";
  }
}

TEST(SyntheticCamera, TheKindFixesTheCamera) {
  const TableParams table;
  SyntheticCameraParams p;
  SyntheticCamera camera(p, table);
  EXPECT_EQ(camera.kind(), CameraKind::kIr);
  SyntheticCameraParams depth = p;
  depth.kind = CameraKind::kDepth;
  depth.cameraHeight = 120.0;
  depth.disparityNoise = 1.0;  // live
  EXPECT_EQ(camera.FixedKeysChanged(depth), (std::vector<std::string>{"kind", "camera_height"}));
  // the depth camera maps its image linearly onto the table whatever distortion and perspective
  // say (they are the IR camera's)
  depth.distortion = 0.2;
  depth.perspective = 0.1;
  const CameraModel model = SyntheticCameraModel(depth, table);
  const Vec2 corner = model.CameraToTable(Vec2(-0.5, -0.5));
  EXPECT_NEAR(corner.x(), 0.0, 1e-6);
  EXPECT_NEAR(corner.y(), table.height, 1e-6);
  const Vec2 centre = model.CameraToTable(Vec2(319.5, 239.5));
  EXPECT_NEAR((centre - Vec2(30.5, 23.0)).norm(), 0.0, 1e-6);
  EXPECT_EQ(SyntheticCamera(depth, table).Render({}).type(), CV_16UC1);
}

TEST(DemoScene, KnownScenes) {
  const TableParams table;
  std::vector<ContactShape> shapes;
  ASSERT_TRUE(DemoScene("fingers", 0, table, shapes));
  EXPECT_TRUE(shapes.empty()) << "the demo scenes start with a clear table";
  ASSERT_TRUE(DemoScene("fingers", 100, table, shapes));
  EXPECT_EQ(shapes.size(), 10u);
  ASSERT_TRUE(DemoScene("hands", 100, table, shapes));
  ASSERT_EQ(shapes.size(), 2u);
  EXPECT_EQ(shapes[0].kind, ShapeKind::kHandFlat);
  EXPECT_FALSE(DemoScene("nope", 0, table, shapes));
}

}  // namespace
}  // namespace pg
