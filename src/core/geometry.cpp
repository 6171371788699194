#include "proxygrasp/core/geometry.h"

#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace pg {

Vec2 Pose2::Apply(const Vec2& local) const {
  return Rotate(local, angle) + pos;
}

Vec2 Pose2::Inverse(const Vec2& world) const {
  return Rotate(world - pos, -angle);
}

Vec2 Rotate(const Vec2& v, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

double WrapAngle(double angle) {
  double a = std::fmod(angle + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

double SignedArea(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  double twice = 0.0;
  for (int i = 0; i < n; ++i) {
    twice += Cross(c.col(i), c.col((i + 1) % n));
  }
  return 0.5 * twice;
}

Vec2 PolygonCentroid(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  assert(n > 0 && "centroid needs at least one point");
  double twiceArea = 0.0;
  Vec2 sum = Vec2::Zero();
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(i);
    const Vec2 b = c.col((i + 1) % n);
    const double w = Cross(a, b);
    twiceArea += w;
    sum += (a + b) * w;
  }
  // degenerate polygons fall back to the vertex mean
  if (std::abs(twiceArea) < 1e-12) return c.rowwise().mean();
  return sum / (3.0 * twiceArea);
}

double Perimeter(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  double length = 0.0;
  for (int i = 0; i < n; ++i) length += (c.col((i + 1) % n) - c.col(i)).norm();
  return length;
}

Contour MakeCounterClockwise(const Contour& c) {
  if (SignedArea(c) >= 0.0) return c;
  return c.rowwise().reverse();
}

Contour ResampleClosed(const Contour& c, double spacing, int minPoints) {
  assert(spacing > 0.0 && "resample spacing must be positive");
  const int n = static_cast<int>(c.cols());
  if (n == 0) return c;
  const double total = Perimeter(c);
  if (total <= 0.0) return c.leftCols(1);
  const int count = std::max(minPoints, static_cast<int>(std::lround(total / spacing)));
  const double step = total / count;

  Contour out(2, count);
  // walk the edges once, emitting a point every `step` of arc length
  int edge = 0;
  double edgeStart = 0.0;  // arc length at the start of the current edge
  double edgeLength = (c.col(1 % n) - c.col(0)).norm();
  for (int k = 0; k < count; ++k) {
    const double s = k * step;
    while (s > edgeStart + edgeLength && edge < n - 1) {
      edgeStart += edgeLength;
      ++edge;
      edgeLength = (c.col((edge + 1) % n) - c.col(edge)).norm();
    }
    const double t = edgeLength > 0.0 ? std::clamp((s - edgeStart) / edgeLength, 0.0, 1.0) : 0.0;
    out.col(k) = c.col(edge) + t * (c.col((edge + 1) % n) - c.col(edge));
  }
  return out;
}

bool PointInPolygon(const Contour& poly, const Vec2& p) {
  const int n = static_cast<int>(poly.cols());
  bool inside = false;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = poly.col(i);
    const Vec2 b = poly.col(j);
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

Vec2 ClosestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return (p - ClosestPointOnSegment(p, a, b)).norm();
}

double DistanceToBoundary(const Contour& poly, const Vec2& p) {
  const int n = static_cast<int>(poly.cols());
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    best = std::min(best, DistanceToSegment(p, poly.col(i), poly.col((i + 1) % n)));
  }
  return best;
}

double SignedDistance(const Contour& poly, const Vec2& p) {
  const double d = DistanceToBoundary(poly, p);
  return PointInPolygon(poly, p) ? d : -d;
}

PolygonBands::PolygonBands(const Contour& poly) : m_poly(poly) {
  const int n = static_cast<int>(poly.cols());
  if (n == 0) {
    m_start.assign(2, 0);
    return;
  }
  m_y0 = poly.row(1).minCoeff();
  const double height = poly.row(1).maxCoeff() - m_y0;
  // about four edges a band: a hand's outline of 200 points reads a few of them a question
  m_bands = std::clamp(n / 4, 1, 64);
  m_height = height > 0.0 ? height / m_bands : 1.0;
  // each edge in every band its height range meets: counted, then placed
  m_start.assign(static_cast<size_t>(m_bands) + 1, 0);
  const auto range = [&](int e, int* lo, int* hi) {
    const double ya = poly(1, e), yb = poly(1, e + 1 < n ? e + 1 : 0);
    *lo = Band(std::min(ya, yb));
    *hi = Band(std::max(ya, yb));
  };
  for (int e = 0; e < n; ++e) {
    int lo, hi;
    range(e, &lo, &hi);
    for (int b = lo; b <= hi; ++b) ++m_start[static_cast<size_t>(b) + 1];
  }
  for (int b = 0; b < m_bands; ++b) m_start[b + 1] += m_start[b];
  m_edges.resize(static_cast<size_t>(m_start[m_bands]));
  std::vector<int> fill(m_start.begin(), m_start.end() - 1);
  for (int e = 0; e < n; ++e) {
    int lo, hi;
    range(e, &lo, &hi);
    for (int b = lo; b <= hi; ++b) m_edges[static_cast<size_t>(fill[b]++)] = e;
  }
}

int PolygonBands::Band(double y) const {
  const double b = std::floor((y - m_y0) / m_height);
  return static_cast<int>(std::clamp(b, 0.0, static_cast<double>(m_bands - 1)));
}

bool PolygonBands::Inside(const Vec2& p) const {
  // PointInPolygon's crossings (its pairs i, j = i - 1: edge e read from e + 1 to e), over the
  // edges of the point's band: an edge that the ray meets spans the point's height
  const int n = static_cast<int>(m_poly.cols());
  const int band = Band(p.y());
  bool inside = false;
  for (int k = m_start[band]; k < m_start[band + 1]; ++k) {
    const int e = m_edges[static_cast<size_t>(k)];
    const Vec2 a = m_poly.col(e + 1 < n ? e + 1 : 0);
    const Vec2 b = m_poly.col(e);
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

bool PolygonBands::Within(const Vec2& p, double margin) const {
  // DistanceToBoundary's segments (e, e + 1) in the bands within the margin; an edge whose box
  // lies farther than the margin (by more than rounding could move a distance) is not measured
  const int n = static_cast<int>(m_poly.cols());
  if (n == 0 || !(margin >= 0.0)) return false;
  const double reach = margin * (1.0 + 1e-12) + 1e-12;
  const int first = Band(p.y() - reach), last = Band(p.y() + reach);
  for (int band = first; band <= last; ++band) {
    for (int k = m_start[band]; k < m_start[band + 1]; ++k) {
      const int e = m_edges[static_cast<size_t>(k)];
      const Vec2 a = m_poly.col(e);
      const Vec2 b = m_poly.col(e + 1 < n ? e + 1 : 0);
      if (p.x() < std::min(a.x(), b.x()) - reach || p.x() > std::max(a.x(), b.x()) + reach ||
          p.y() < std::min(a.y(), b.y()) - reach || p.y() > std::max(a.y(), b.y()) + reach) {
        continue;
      }
      if (DistanceToSegment(p, a, b) <= margin) return true;
    }
  }
  return false;
}

double HausdorffDistance(const Contour& a, const Contour& b) {
  double worst = 0.0;
  for (int i = 0; i < a.cols(); ++i) worst = std::max(worst, DistanceToBoundary(b, a.col(i)));
  for (int i = 0; i < b.cols(); ++i) worst = std::max(worst, DistanceToBoundary(a, b.col(i)));
  return worst;
}

Contour ToContour(const std::vector<Vec2>& points) {
  Contour c(2, static_cast<Eigen::Index>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) c.col(static_cast<Eigen::Index>(i)) = points[i];
  return c;
}

std::optional<std::string> PolygonProblem(const std::vector<Vec2>& p, bool convex) {
  const size_t n = p.size();
  if (n < 3) return "needs at least 3 points, got " + std::to_string(n);
  for (size_t i = 0; i < n; ++i) {
    if ((p[i] - p[(i + 1) % n]).norm() < 1e-9) {
      return "has coincident points " + std::to_string(i + 1) + " and " +
             std::to_string((i + 1) % n + 1);
    }
  }
  // any two edges that are not neighbours must not touch
  auto segmentsMeet = [](const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double d1 = Cross(b - a, c - a);
    const double d2 = Cross(b - a, d - a);
    const double d3 = Cross(d - c, a - c);
    const double d4 = Cross(d - c, b - c);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
      return true;
    }
    // touching or collinear overlap
    auto onSegment = [](const Vec2& s, const Vec2& e, const Vec2& q, double cross) {
      return cross == 0 && q.x() >= std::min(s.x(), e.x()) && q.x() <= std::max(s.x(), e.x()) &&
             q.y() >= std::min(s.y(), e.y()) && q.y() <= std::max(s.y(), e.y());
    };
    return onSegment(a, b, c, d1) || onSegment(a, b, d, d2) || onSegment(c, d, a, d3) ||
           onSegment(c, d, b, d4);
  };
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      if (segmentsMeet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) {
        return "is not a simple polygon: edge " + std::to_string(i + 1) + "-" +
               std::to_string((i + 1) % n + 1) + " meets edge " + std::to_string(j + 1) + "-" +
               std::to_string((j + 1) % n + 1);
      }
    }
  }
  if (std::abs(SignedArea(ToContour(p))) < 1e-6) return "encloses no area";
  if (convex) {
    const double sign = SignedArea(ToContour(p)) > 0 ? 1.0 : -1.0;
    for (size_t i = 0; i < n; ++i) {
      const Vec2& a = p[(i + n - 1) % n];
      const Vec2& b = p[i];
      const Vec2& c = p[(i + 1) % n];
      if (sign * Cross(b - a, c - b) < 0) {
        return "is not convex: it turns the other way at point " + std::to_string(i + 1);
      }
    }
  }
  return std::nullopt;
}

}  // namespace pg
