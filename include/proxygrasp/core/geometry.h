// Small 2D geometry on Eigen types, in table centimetres unless stated.
// A Contour is a closed polyline stored as a 2xN matrix of distinct points; the edge from the last
// column back to the first is implied, so index arithmetic on it is cyclic.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace pg {

/// A point or vector in the table plane, cm.
using Vec2 = Eigen::Vector2d;

/// A closed polyline, 2xN, implicitly closed (last point connects to the first).
using Contour = Eigen::Matrix2Xd;

/// A rigid transform in the plane: rotate by angle (radians, CCW), then translate by pos (cm).
struct Pose2 {
  Vec2 pos = Vec2::Zero();
  double angle = 0.0;

  /// Maps a point from this pose's local frame to the parent frame.
  Vec2 Apply(const Vec2& local) const;
  /// Maps a point from the parent frame to this pose's local frame.
  Vec2 Inverse(const Vec2& world) const;
};

/// Rotates v by angle radians counter-clockwise.
Vec2 Rotate(const Vec2& v, double angle);

/// Wraps an angle to (-pi, pi].
double WrapAngle(double angle);

/// 2D cross product a.x*b.y - a.y*b.x.
inline double Cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Index i wrapped into [0, n); n must be > 0.
inline int WrapIndex(int i, int n) {
  int r = i % n;
  return r < 0 ? r + n : r;
}

/// Signed area of a closed polygon, cm^2: positive when counter-clockwise.
double SignedArea(const Contour& c);

/// Area centroid of a closed polygon; the vertex mean when the area is (near) zero.
Vec2 PolygonCentroid(const Contour& c);

/// Total length of the closed polyline, cm.
double Perimeter(const Contour& c);

/// The same polygon wound counter-clockwise (reversed when it was clockwise).
Contour MakeCounterClockwise(const Contour& c);

/// Resamples a closed polyline to points evenly spaced by arc length. The count is
/// max(minPoints, round(perimeter / spacing)), so the actual spacing is perimeter / count.
/// The first output point is the first input point.
Contour ResampleClosed(const Contour& c, double spacing, int minPoints = 3);

/// True when p lies inside the closed polygon (even-odd rule).
bool PointInPolygon(const Contour& poly, const Vec2& p);

/// The point of segment ab nearest to p (a when the segment has no length).
Vec2 ClosestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b);

/// Distance from p to the segment ab.
double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b);

/// Distance from p to the boundary of the closed polygon.
double DistanceToBoundary(const Contour& poly, const Vec2& p);

/// Signed distance to the polygon boundary: positive inside, negative outside.
double SignedDistance(const Contour& poly, const Vec2& p);

/// A closed polygon's edges listed by horizontal bands of its height, for asking the same two
/// questions about many points: Inside(p) is PointInPolygon(poly, p) and Within(p, margin) is
/// DistanceToBoundary(poly, p) <= margin, with the same answers, edge for edge, but each reads
/// only the edges of the bands that can matter (the ray's crossings lie in the point's band; an
/// edge within the margin lies in the bands within it, and the first one found answers). Holds a
/// reference to `poly`, which must outlive it and not change.
class PolygonBands {
 public:
  explicit PolygonBands(const Contour& poly);
  bool Inside(const Vec2& p) const;
  bool Within(const Vec2& p, double margin) const;

 private:
  int Band(double y) const;

  const Contour& m_poly;
  double m_y0 = 0.0, m_height = 1.0;
  int m_bands = 1;
  std::vector<int> m_start;  // band b's edges are m_edges[m_start[b], m_start[b + 1])
  std::vector<int> m_edges;  // edge e joins points e and e + 1 (cyclically)
};

/// Symmetric Hausdorff distance between two closed polylines, measured from every vertex of each to
/// the boundary (edges) of the other.
double HausdorffDistance(const Contour& a, const Contour& b);

/// What makes a closed polygon unusable as an outline, or nullopt when nothing does: fewer than 3
/// points, coincident neighbours, edges that touch or cross (not a simple polygon), no area, or,
/// when convex is asked, a turn the other way. Points are numbered from 1 in the text ("is not
/// convex: it turns the other way at point 3").
std::optional<std::string> PolygonProblem(const std::vector<Vec2>& points, bool convex);

/// Builds a Contour from a list of points.
Contour ToContour(const std::vector<Vec2>& points);

/// Linear interpolation a + (b - a) t.
inline double Lerp(double a, double b, double t) {
  return a + (b - a) * t;
}

/// Hermite smoothstep of t clamped to [0, 1]: 3t^2 - 2t^3.
inline double SmoothStep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace pg
