// Analytic contact contours for the proxies tests and benchmark, shaped as sensing delivers them:
// counter-clockwise, resampled to ~0.3 cm spacing, starting at the lowest point (the first pixel a
// raster scan of the table image meets), so the start index moves as the shape moves.
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/units.h"

#include <cmath>
#include <vector>

namespace pg::testing {

/// The spacing sensing resamples contours to, cm.
inline constexpr double kSpacing = 0.3;

/// An outline as sensing would deliver it: CCW, start at the lowest (then leftmost) point of a
/// dense sampling, moved startShift cm along the outline (the raster's first pixel jumps about
/// when a contour moves by less than a pixel), resampled to `spacing`.
inline Contour Sensed(const Contour& outline, double spacing = kSpacing, double startShift = 0.0) {
  constexpr double kDense = 0.02;  // cm
  const Contour dense = ResampleClosed(MakeCounterClockwise(outline), kDense);
  const int n = static_cast<int>(dense.cols());
  int start = 0;
  for (int i = 1; i < n; ++i) {
    const double dy = dense(1, i) - dense(1, start);
    if (dy < -1e-9 || (std::abs(dy) <= 1e-9 && dense(0, i) < dense(0, start))) start = i;
  }
  start += static_cast<int>(std::lround(startShift / kDense));
  Contour rotated(2, n);
  for (int i = 0; i < n; ++i) rotated.col(i) = dense.col(WrapIndex(start + i, n));
  return ResampleClosed(rotated, spacing);
}

/// An outline moved by a pose.
inline Contour Moved(const Contour& c, const Pose2& pose) {
  Contour out(2, c.cols());
  for (int i = 0; i < c.cols(); ++i) out.col(i) = pose.Apply(c.col(i));
  return out;
}

/// An arc of `count` points around centre from angle a0 to a1 (radians), end points included.
inline void AppendArc(std::vector<Vec2>& pts, const Vec2& centre, double radius, double a0,
                      double a1, int count) {
  for (int i = 0; i < count; ++i) {
    const double a = a0 + (a1 - a0) * i / (count - 1);
    pts.push_back(centre + radius * Vec2(std::cos(a), std::sin(a)));
  }
}

/// A circle outline (local frame centred on the origin).
inline Contour CircleOutline(double radius) {
  std::vector<Vec2> pts;
  AppendArc(pts, Vec2::Zero(), radius, 0.0, 2 * kPi * (1.0 - 1.0 / 256), 256);
  return ToContour(pts);
}

/// An ellipse outline with semi-axes rx (local x) and ry.
inline Contour EllipseOutline(double rx, double ry) {
  Contour c(2, 256);
  for (int i = 0; i < 256; ++i) {
    const double a = 2 * kPi * i / 256;
    c.col(i) = Vec2(rx * std::cos(a), ry * std::sin(a));
  }
  return c;
}

/// A capsule outline: the segment from (-length/2, 0) to (length/2, 0) swept by radius.
inline Contour CapsuleOutline(double length, double radius) {
  std::vector<Vec2> pts;
  AppendArc(pts, Vec2(length / 2, 0), radius, -kPi / 2, kPi / 2, 64);
  AppendArc(pts, Vec2(-length / 2, 0), radius, kPi / 2, 3 * kPi / 2, 64);
  return ToContour(pts);
}

/// The outline of two overlapping discs of one radius whose centres lie `distance` apart on the
/// local x axis (0 < distance < 2 radius): two fingertips pressed together.
inline Contour TwoDiscsOutline(double distance, double radius) {
  const double alpha = std::acos(distance / (2.0 * radius));  // where the circles cross
  std::vector<Vec2> pts;
  AppendArc(pts, Vec2(distance / 2, 0), radius, -kPi + alpha, kPi - alpha, 128);
  AppendArc(pts, Vec2(-distance / 2, 0), radius, alpha, 2 * kPi - alpha, 128);
  return ToContour(pts);
}

/// The outer outline of a union of discs (centres and radii) that form one connected region with
/// no holes: each circle sampled at 1024 points, walked counter-clockwise and, where the walk
/// enters another disc, continued on that disc's circle from its sample nearest the crossing.
inline Contour DiscsOutline(const std::vector<Vec2>& centres, const std::vector<double>& radii) {
  constexpr int kSamples = 1024;
  const int discs = static_cast<int>(centres.size());
  auto at = [&](int d, int i) {
    const double a = 2 * kPi * i / kSamples;
    return Vec2(centres[d] + radii[d] * Vec2(std::cos(a), std::sin(a)));
  };
  auto covered = [&](const Vec2& p, int except) {
    for (int d = 0; d < discs; ++d) {
      if (d != except && (p - centres[d]).norm() < radii[d]) return true;
    }
    return false;
  };
  // start at the lowest point of all the circles, which no other disc covers
  int disc = 0, index = 3 * kSamples / 4;
  for (int d = 1; d < discs; ++d) {
    if (centres[d].y() - radii[d] < centres[disc].y() - radii[disc]) disc = d;
  }
  const int startDisc = disc, startIndex = index;
  std::vector<Vec2> pts;
  for (int guard = 0; guard < discs * kSamples; ++guard) {
    pts.push_back(at(disc, index));
    const int next = (index + 1) % kSamples;
    const Vec2 p = at(disc, next);
    if (covered(p, disc)) {
      // the nearest uncovered sample of the disc entered, ahead of the crossing
      int entered = -1;
      for (int d = 0; d < discs; ++d) {
        if (d != disc && (p - centres[d]).norm() < radii[d]) entered = d;
      }
      int best = 0;
      double nearest = 1e300;
      for (int i = 0; i < kSamples; ++i) {
        const Vec2 q = at(entered, i);
        const double dist = (q - p).norm();
        if (dist < nearest && !covered(q, entered)) {
          nearest = dist;
          best = i;
        }
      }
      disc = entered;
      index = best;
    } else {
      index = next;
    }
    if (disc == startDisc && index == startIndex) break;
  }
  return ToContour(pts);
}

/// One finger of a hand outline, walked counter-clockwise: out along its right side, round the
/// tip, back along its left side. base is the centre of its root, angle its direction.
inline void AppendFinger(std::vector<Vec2>& pts, const Vec2& base, double angle, double length,
                         double radius) {
  const Vec2 u(std::cos(angle), std::sin(angle));
  const Vec2 right(u.y(), -u.x());
  pts.push_back(base + radius * right);
  AppendArc(pts, base + length * u, radius, angle - kPi / 2, angle + kPi / 2, 24);
  pts.push_back(base - radius * right);
}

/// A hand with five spread fingers, fingers along local +y, palm centred on the origin; about
/// 19 cm long at scale 1 and 2 x 500 points for two hands at 0.3 cm spacing.
inline Contour HandOutline(double scale = 1.0) {
  std::vector<Vec2> pts;
  const double s = scale;
  // palm: rounded bottom, right side up to the little finger
  AppendArc(pts, Vec2(0, -3.0 * s), 4.0 * s, kPi, 2 * kPi, 24);
  pts.push_back(Vec2(4.0 * s, 2.8 * s));
  // four fingers from the little finger (right) to the index finger, fanned outward
  const double bases[4] = {3.05, 1.0, -1.0, -3.05};
  const double angles[4] = {-12, -4, 4, 12};
  const double lengths[4] = {5.5, 7.0, 7.5, 6.5};
  for (int f = 0; f < 4; ++f) {
    AppendFinger(pts, Vec2(bases[f] * s, 3.2 * s), DegToRad(90 + angles[f]), lengths[f] * s,
                 0.85 * s);
  }
  // left side of the palm and the thumb, pointing up and out to the left
  pts.push_back(Vec2(-4.0 * s, 2.8 * s));
  AppendFinger(pts, Vec2(-4.2 * s, -1.0 * s), DegToRad(150), 4.5 * s, 1.0 * s);
  return ToContour(pts);
}

/// True when no two non-adjacent edges of the closed polygon cross.
inline bool IsSimple(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  auto cross = [](const Vec2& a, const Vec2& b, const Vec2& p) { return Cross(b - a, p - a); };
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(i), b = c.col((i + 1) % n);
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      const Vec2 p = c.col(j), q = c.col((j + 1) % n);
      const double d1 = cross(a, b, p), d2 = cross(a, b, q);
      const double d3 = cross(p, q, a), d4 = cross(p, q, b);
      if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0))) return false;
    }
  }
  return true;
}

}  // namespace pg::testing
