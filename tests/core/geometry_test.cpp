#include "proxygrasp/core/geometry.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace pg {
namespace {

// exact arithmetic on small integers and halves: only rounding in the last bit is allowed
constexpr double kExact = 1e-12;

Contour Square(double side) {
  return ToContour({{0, 0}, {side, 0}, {side, side}, {0, side}});
}

Contour Circle(double r, int n) {
  Contour c(2, n);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    c.col(i) = Vec2(r * std::cos(a), r * std::sin(a));
  }
  return c;
}

TEST(Geometry, RotateQuarterTurn) {
  const Vec2 r = Rotate(Vec2(1, 0), kPi / 2);
  EXPECT_NEAR(r.x(), 0.0, kExact);
  EXPECT_NEAR(r.y(), 1.0, kExact);
}

TEST(Geometry, PoseApplyAndInverseRoundTrip) {
  const Pose2 pose{Vec2(3, -2), DegToRad(30)};
  const Vec2 local(1.5, 0.25);
  const Vec2 world = pose.Apply(local);
  EXPECT_NEAR((pose.Inverse(world) - local).norm(), 0.0, kExact);
  // (1, 0) rotated by 30 degrees then moved
  const Vec2 x = pose.Apply(Vec2(1, 0));
  EXPECT_NEAR(x.x(), 3 + std::cos(DegToRad(30)), kExact);
  EXPECT_NEAR(x.y(), -2 + std::sin(DegToRad(30)), kExact);
}

TEST(Geometry, WrapAngleRange) {
  EXPECT_NEAR(WrapAngle(3 * kPi), kPi, kExact);
  EXPECT_NEAR(WrapAngle(-kPi / 2 - 2 * kPi), -kPi / 2, kExact);
  EXPECT_NEAR(WrapAngle(0.1), 0.1, kExact);
  EXPECT_GT(WrapAngle(-kPi), 0.0);  // -pi maps to +pi: the interval is (-pi, pi]
}

TEST(Geometry, WrapIndexIsCyclic) {
  EXPECT_EQ(WrapIndex(-1, 10), 9);
  EXPECT_EQ(WrapIndex(10, 10), 0);
  EXPECT_EQ(WrapIndex(-21, 10), 9);
  EXPECT_EQ(WrapIndex(3, 10), 3);
}

TEST(Geometry, SquareAreaCentroidPerimeter) {
  const Contour s = Square(2.0);
  EXPECT_NEAR(SignedArea(s), 4.0, kExact);
  EXPECT_NEAR(SignedArea(s.rowwise().reverse()), -4.0, kExact);
  const Vec2 c = PolygonCentroid(s);
  EXPECT_NEAR(c.x(), 1.0, kExact);
  EXPECT_NEAR(c.y(), 1.0, kExact);
  EXPECT_NEAR(Perimeter(s), 8.0, kExact);
}

TEST(Geometry, CentroidOfLShape) {
  // two unit squares side by side and one on top of the left: centroid (5/6, 5/6)
  const Contour l = ToContour({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  EXPECT_NEAR(SignedArea(l), 3.0, kExact);
  const Vec2 c = PolygonCentroid(l);
  EXPECT_NEAR(c.x(), 5.0 / 6.0, kExact);
  EXPECT_NEAR(c.y(), 5.0 / 6.0, kExact);
}

TEST(Geometry, MakeCounterClockwiseReversesClockwise) {
  const Contour cw = Square(1.0).rowwise().reverse();
  EXPECT_LT(SignedArea(cw), 0.0);
  EXPECT_GT(SignedArea(MakeCounterClockwise(cw)), 0.0);
  EXPECT_GT(SignedArea(MakeCounterClockwise(Square(1.0))), 0.0);
}

TEST(Geometry, ResampleSquareEvenly) {
  // perimeter 8, spacing 0.5 -> 16 points, each 0.5 from the next along the boundary
  const Contour r = ResampleClosed(Square(2.0), 0.5);
  ASSERT_EQ(r.cols(), 16);
  for (int i = 0; i < r.cols(); ++i) {
    const double d = (r.col((i + 1) % r.cols()) - r.col(i)).norm();
    EXPECT_NEAR(d, 0.5, kExact) << "at " << i;
  }
  EXPECT_NEAR((r.col(0) - Vec2(0, 0)).norm(), 0.0, kExact);
  EXPECT_NEAR((r.col(4) - Vec2(2, 0)).norm(), 0.0, kExact);
}

TEST(Geometry, ResampleRoundsCountAndKeepsMinimum) {
  // perimeter 8 with spacing 3 -> round(2.67) = 3 points; spacing 100 -> the minimum of 3
  EXPECT_EQ(ResampleClosed(Square(2.0), 3.0).cols(), 3);
  EXPECT_EQ(ResampleClosed(Square(2.0), 100.0).cols(), 3);
  EXPECT_EQ(ResampleClosed(Square(2.0), 100.0, 5).cols(), 5);
}

TEST(Geometry, ResampleCircleStaysOnCircle) {
  // a 720-gon of radius 5: resampled points lie on it within the chord sagitta r(1-cos(pi/720))
  const Contour r = ResampleClosed(Circle(5.0, 720), 0.3);
  const double sagitta = 5.0 * (1.0 - std::cos(kPi / 720));
  EXPECT_EQ(r.cols(), std::lround(Perimeter(Circle(5.0, 720)) / 0.3));
  for (int i = 0; i < r.cols(); ++i) EXPECT_NEAR(r.col(i).norm(), 5.0, sagitta + kExact);
}

TEST(Geometry, PointInPolygonAndSignedDistance) {
  const Contour s = Square(2.0);
  EXPECT_TRUE(PointInPolygon(s, Vec2(1, 1)));
  EXPECT_FALSE(PointInPolygon(s, Vec2(3, 1)));
  EXPECT_NEAR(SignedDistance(s, Vec2(1, 0.5)), 0.5, kExact);
  EXPECT_NEAR(SignedDistance(s, Vec2(3, 1)), -1.0, kExact);
  EXPECT_NEAR(SignedDistance(s, Vec2(3, 3)), -std::sqrt(2.0), kExact);
}

// PolygonBands answers as PointInPolygon and DistanceToBoundary <= margin do, point for point:
// on a square (edges along the bands, points on its edges and corners), a flat segment's worth of
// outline (no height), a jagged star and random wiggly outlines (a hand's size and spacing),
// with points inside, outside, on the outline and exactly at a margin's distance from a vertex.
TEST(Geometry, PolygonBandsAnswersAsTheWholeOutlineDoes) {
  std::vector<Contour> polys = {Square(2.0), ToContour({{0, 1}, {3, 1}, {1, 1}}), Circle(1.5, 7)};
  Contour star(2, 40);
  for (int i = 0; i < 40; ++i) {
    const double a = 2.0 * kPi * i / 40, r = i % 2 == 0 ? 3.0 : 1.2;
    star.col(i) = Vec2(r * std::cos(a), r * std::sin(a));
  }
  polys.push_back(star);
  uint64_t state = 12345;
  auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53);
  };
  for (int k = 0; k < 3; ++k) {
    // about 0.3 cm apart, as the sensor resamples, round a radius that wanders
    Contour wiggly(2, 200);
    for (int i = 0; i < 200; ++i) {
      const double a = 2.0 * kPi * i / 200;
      const double r = 8.0 + 2.5 * std::sin(5 * a + k) + uniform(-0.2, 0.2);
      wiggly.col(i) = Vec2(20.0 + r * std::cos(a), 15.0 + r * std::sin(a));
    }
    polys.push_back(wiggly);
  }
  int inside = 0, within = 0, asked = 0;
  for (const Contour& poly : polys) {
    const PolygonBands bands(poly);
    const Vec2 lo = poly.rowwise().minCoeff(), hi = poly.rowwise().maxCoeff();
    std::vector<Vec2> points;
    for (int i = 0; i < 400; ++i)
      points.emplace_back(uniform(lo.x() - 1.0, hi.x() + 1.0), uniform(lo.y() - 1.0, hi.y() + 1.0));
    for (int i = 0; i < poly.cols(); ++i) {
      const Vec2 a = poly.col(i), b = poly.col((i + 1) % poly.cols());
      points.push_back(a);
      points.push_back(0.5 * (a + b));
      points.push_back(a + Vec2(0.25, 0.0));  // exactly 0.25 from the vertex, for margin 0.25
    }
    for (const Vec2& p : points) {
      ++asked;
      const bool in = PointInPolygon(poly, p);
      ASSERT_EQ(bands.Inside(p), in) << "at " << p.transpose();
      inside += in ? 1 : 0;
      for (double margin : {0.0, 0.05, 0.25, 1.0}) {
        const bool near = DistanceToBoundary(poly, p) <= margin;
        ASSERT_EQ(bands.Within(p, margin), near) << "at " << p.transpose() << " margin " << margin;
        within += near ? 1 : 0;
      }
    }
  }
  // both answers came out both ways
  EXPECT_GT(inside, 100);
  EXPECT_LT(inside, asked - 100);
  EXPECT_GT(within, 100);
}

TEST(Geometry, DistanceToSegmentEndsAndMiddle) {
  EXPECT_NEAR(DistanceToSegment(Vec2(0, 1), Vec2(-1, 0), Vec2(1, 0)), 1.0, kExact);
  EXPECT_NEAR(DistanceToSegment(Vec2(3, 0), Vec2(-1, 0), Vec2(1, 0)), 2.0, kExact);
  EXPECT_NEAR(DistanceToSegment(Vec2(0, 2), Vec2(0, 0), Vec2(0, 0)), 2.0, kExact);
}

TEST(Geometry, ClosestPointOnSegmentClampsToEnds) {
  EXPECT_NEAR((ClosestPointOnSegment(Vec2(0.5, 2), Vec2(0, 0), Vec2(1, 0)) - Vec2(0.5, 0)).norm(),
              0.0, kExact);
  EXPECT_NEAR((ClosestPointOnSegment(Vec2(-3, 1), Vec2(0, 0), Vec2(1, 0)) - Vec2(0, 0)).norm(), 0.0,
              kExact);
  EXPECT_NEAR((ClosestPointOnSegment(Vec2(4, -1), Vec2(0, 0), Vec2(1, 0)) - Vec2(1, 0)).norm(), 0.0,
              kExact);
  EXPECT_EQ(ClosestPointOnSegment(Vec2(4, 4), Vec2(2, 2), Vec2(2, 2)), Vec2(2, 2));
}

TEST(Geometry, HausdorffOfShiftedSquares) {
  // shifting a square by 0.3 along x: the farthest vertex is 0.3 from the other boundary
  Contour a = Square(2.0);
  Contour b = a;
  b.row(0).array() += 0.3;
  EXPECT_NEAR(HausdorffDistance(a, b), 0.3, kExact);
  EXPECT_NEAR(HausdorffDistance(a, a), 0.0, kExact);
}

TEST(Geometry, SmoothStepEndsAndMiddle) {
  EXPECT_EQ(SmoothStep(-1.0), 0.0);
  EXPECT_EQ(SmoothStep(2.0), 1.0);
  EXPECT_NEAR(SmoothStep(0.5), 0.5, kExact);
  EXPECT_NEAR(SmoothStep(0.25), 0.15625, kExact);
}

TEST(Geometry, PolygonProblemNamesWhatIsWrong) {
  const std::vector<Vec2> square = {Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)};
  EXPECT_EQ(PolygonProblem(square, true), std::nullopt);
  const std::vector<Vec2> bow = {Vec2(0, 0), Vec2(2, 2), Vec2(2, 0), Vec2(0, 2)};
  EXPECT_EQ(PolygonProblem(bow, false), "is not a simple polygon: edge 1-2 meets edge 3-4");
  const std::vector<Vec2> dart = {Vec2(0, 0), Vec2(4, 0), Vec2(1, 1), Vec2(0, 4)};
  EXPECT_EQ(PolygonProblem(dart, false), std::nullopt) << "simple, only not convex";
  EXPECT_EQ(PolygonProblem(dart, true), "is not convex: it turns the other way at point 3");
  EXPECT_EQ(PolygonProblem({Vec2(0, 0), Vec2(1, 0)}, false), "needs at least 3 points, got 2");
  EXPECT_EQ(PolygonProblem({Vec2(0, 0), Vec2(0, 0), Vec2(1, 1)}, false),
            "has coincident points 1 and 2");
  EXPECT_EQ(PolygonProblem({Vec2(0, 0), Vec2(1, 0), Vec2(2, 0)}, false), "encloses no area");
}

}  // namespace
}  // namespace pg
