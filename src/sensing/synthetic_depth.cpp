// The synthetic depth camera: SyntheticCamera with kind = depth. A Kinect v1-like camera looks
// straight down at the table's centre from cameraHeight(); its image maps linearly onto the table
// (image edges = table edges, top = the far edge). The contacts are bodies with thickness on a
// height field; each pixel's ray is marched through it (perspective: raised points appear farther
// from the image centre), what the IR projector beside the camera cannot light reads 0, pixels at
// depth edges may read 0, and the depth gets per-pixel noise and 11-bit disparity steps.
// docs/sensing.md, "The synthetic depth camera".
#include "prefault.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/depth_source.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pg {

namespace {

// Kinect v1's depth camera: field of view, deg, and nearest reading in its default range, cm
constexpr double kKinectFovX = 57.0;
constexpr double kKinectFovY = 43.0;
constexpr double kKinectNearest = 80.0;

// an IR camera's view of a contact above the diffuser fades over this height, cm
constexpr double kIrHoverFade = 0.5;

// Hands, in their unscaled local frame (synthetic_camera.cpp: the palm is a rounded box 8 x 10 cm
// about the origin, fingers along +y from about y = 4): below kPalmEnd a hand is palm thick, above
// kFingersStart finger thick, smoothly between. The forearm leaves the palm at kWristY, kArmRadius
// wide on either side, rising at arm_rise along -y for kArmLength along the table.
constexpr double kPalmEnd = 2.0;
constexpr double kFingersStart = 5.0;
constexpr double kWristY = -4.0;
constexpr double kArmRadius = 3.0;
constexpr double kArmLength = 40.0;
// the palm's half width, and the distance beside it over which the hand thins to a thumb's
// thickness, unscaled cm
constexpr double kPalmHalfWidth = 4.0;
constexpr double kThumbBlend = 1.5;
// a cupped hand's edge (a band 1.5 cm wide) stands this tall at its middle, unscaled cm
constexpr double kCupHeight = 6.0;
constexpr double kCupHalfWidth = 0.75;

// tiles of the height field's maximum, px
constexpr int kTile = 8;
// a surface point is in the projector's shadow when the height field rises this much above its
// ray to the projector, cm (bilinear sampling of a sloped surface must not shadow itself)
constexpr double kShadowMargin = 0.02;
// a camera ray marches down at most this far a step, cm: less than the thinnest body (a pad,
// finger_thickness 1.2 cm at the defaults) and its rounded rim's outer tenth
constexpr double kMarchStep = 0.1;
// a camera ray's crossing with the height field is found to within this, cm
constexpr double kCrossingTolerance = 0.002;

// A rounded body's top above its underside at `inside` cm within its outline, for a body `t` cm
// thick: its edge is a quarter round of radius t/2 over a vertical side t/2 tall (seen from above,
// the outline is at half the thickness), flat from t/2 inside on.
double RoundedTop(double inside, double t) {
  const double r = 0.5 * t;
  if (inside >= r) return t;
  const double k = r - inside;
  return r + std::sqrt(std::max(r * r - k * k, 0.0));
}

// a hand's signed distance (sampled where SampledHandDistance can; off its grid the point lies
// more than 2.5 cm, unscaled, beyond the hand's bounds: outside)
double HandDistance(const ContactShape& s, const Vec2& tablePoint) {
  double d, error;
  if (SampledHandDistance(s, tablePoint, d, error)) return d;
  return 1.0;
}

// a depth in mm as the camera reports it without noise: on a disparity step or rounded to mm
uint16_t Report(double mm, bool steps) {
  if (!(mm > 0.0)) return 0;
  if (steps) {
    const long raw = std::lround(KinectDisparity(mm));
    return raw >= 0 && raw < kKinectNoReading ? KinectRawToMmTable()[raw] : 0;
  }
  return static_cast<uint16_t>(std::clamp<long>(std::lround(mm), 0, 65535));
}

// the height field: the bodies' tops and undersides (a body is solid between them, air below
// it), bilinear reads, and the tops' maximum over rectangles (through kTile tiles)
struct HeightField {
  cv::Mat top;      // CV_32F, cm above the table, 0 = the table
  cv::Mat bottom;   // CV_32F, the bodies' undersides, cm above the table, 0 = the table
  cv::Mat tileMax;  // CV_32F, the maximum of each kTile x kTile tile
  int w = 0, h = 0;

  // bilinear at pixel coordinates (pixel centres at integers); 0 off the image
  static double Bilinear(const cv::Mat& m, int w, int h, double x, double y) {
    if (!(x > -1.0 && y > -1.0 && x < w && y < h)) return 0.0;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto px = [&](int u, int v) {
      return u >= 0 && v >= 0 && u < w && v < h ? static_cast<double>(m.at<float>(v, u)) : 0.0;
    };
    return (1.0 - fy) * ((1.0 - fx) * px(x0, y0) + fx * px(x0 + 1, y0)) +
           fy * ((1.0 - fx) * px(x0, y0 + 1) + fx * px(x0 + 1, y0 + 1));
  }
  double At(double x, double y) const { return Bilinear(top, w, h, x, y); }
  // whether height z at pixel coordinates (x, y) is inside a body or the table (z <= 0)
  bool Solid(double x, double y, double z) const {
    return z <= 0.0 || (At(x, y) >= z && Bilinear(bottom, w, h, x, y) <= z);
  }

  // the highest point within [x0, x1] x [y0, y1] px (and a pixel around, for bilinear reads)
  double Max(double x0, double y0, double x1, double y1) const {
    const int t0 = std::max(0, static_cast<int>(std::floor((x0 - 1.0) / kTile)));
    const int t1 = std::min(tileMax.cols - 1, static_cast<int>(std::floor((x1 + 1.0) / kTile)));
    const int s0 = std::max(0, static_cast<int>(std::floor((y0 - 1.0) / kTile)));
    const int s1 = std::min(tileMax.rows - 1, static_cast<int>(std::floor((y1 + 1.0) / kTile)));
    double m = 0.0;
    for (int s = s0; s <= s1; ++s)
      for (int t = t0; t <= t1; ++t) m = std::max(m, static_cast<double>(tileMax.at<float>(s, t)));
    return m;
  }
};

// the table-cm rectangle a body can occupy, from its local rectangle
void GrowBounds(const Pose2& pose, const Vec2& lo, const Vec2& hi, Vec2& outLo, Vec2& outHi) {
  for (const Vec2& c : {lo, hi, Vec2(lo.x(), hi.y()), Vec2(hi.x(), lo.y())}) {
    const Vec2 p = pose.Apply(c);
    outLo = outLo.cwiseMin(p);
    outHi = outHi.cwiseMax(p);
  }
}

}  // namespace

double DepthCameraHeight(const SyntheticCameraParams& params, const TableParams& table) {
  if (params.cameraHeight > 0.0) return params.cameraHeight;
  // the whole table in the field of view, and the tallest body no nearer than the nearest reading
  const double acrossX = table.width / (2.0 * std::tan(DegToRad(0.5 * kKinectFovX)));
  const double acrossY = table.height / (2.0 * std::tan(DegToRad(0.5 * kKinectFovY)));
  return std::max({acrossX, acrossY, kKinectNearest + kDepthTallestBody});
}

double IrHoverDimming(double height) {
  return height > 0.0 ? std::exp(-height / kIrHoverFade) : 1.0;
}

namespace {

// A body's top above the table at a table point, cm (negative where the body is not), and its
// underside there (`underside`, cm; set only where the body is): a body is solid from its
// underside to its top, with air below it when it hovers or rises.
double BodyAt(const ContactShape& s, const SyntheticCameraParams& p, const Vec2& tablePoint,
              double& underside) {
  const Vec2 local = s.pose.Inverse(tablePoint);
  const double base = std::max(s.height, 0.0);
  underside = base;
  switch (s.kind) {
    case ShapeKind::kCircle: {
      // a fingertip: its pad, and its finger rising from the pad's centre toward local -y
      const double along = std::clamp(-local.y(), 0.0, p.fingerLength);
      const double d = (local - Vec2(0.0, -along)).norm() - s.radius;
      if (d >= 0.0) return -1.0;
      underside = base + along * std::tan(DegToRad(p.fingerRise));
      return underside + RoundedTop(-d, p.fingerThickness);
    }
    case ShapeKind::kHandFive:
    case ShapeKind::kHandFlat: {
      const double scale = std::max(s.scale, 1e-6);
      const Vec2 unscaled = local / scale;
      double top = -1.0;
      const double d = HandDistance(s, tablePoint);
      underside = std::numeric_limits<double>::infinity();
      if (d < 0.0) {
        underside = base;
        const double f = SmoothStep(
            std::clamp((unscaled.y() - kPalmEnd) / (kFingersStart - kPalmEnd), 0.0, 1.0));
        // beside the palm (the thumb) the hand thins to a thumb's thickness, halfway between a
        // palm's and a finger's (an adult thumb's tip on its side: 1.7 to 2 cm)
        const double g = SmoothStep(
            std::clamp((std::abs(unscaled.x()) - kPalmHalfWidth) / kThumbBlend, 0.0, 1.0));
        const double thumb = 0.5 * (p.palmThickness + p.fingerThickness);
        const double thickness = scale * std::min(Lerp(p.palmThickness, p.fingerThickness, f),
                                                  Lerp(p.palmThickness, thumb, g));
        top = base + RoundedTop(-d, thickness);
      }
      // the forearm: palm thick, rising from the wrist
      const double along = std::clamp(kWristY - unscaled.y(), 0.0, kArmLength);
      const double da = scale * ((unscaled - Vec2(0.0, kWristY - along)).norm() - kArmRadius);
      if (da < 0.0) {
        const double arm = base + scale * along * std::tan(DegToRad(p.armRise));
        underside = std::min(underside, arm);
        top = std::max(top, arm + RoundedTop(-da, scale * p.palmThickness));
      }
      if (top < 0.0) underside = base;
      return top;
    }
    case ShapeKind::kHandCupped: {
      // the edge of a cupped hand stands on the table: a rounded wall
      const double scale = std::max(s.scale, 1e-6);
      const double d = HandDistance(s, tablePoint);
      if (d >= 0.0) return -1.0;
      const double profile = RoundedTop(-d / scale, 2.0 * kCupHalfWidth) / (2.0 * kCupHalfWidth);
      return base + scale * kCupHeight * profile;
    }
    case ShapeKind::kEllipse:
    case ShapeKind::kCapsule:
    case ShapeKind::kConvexPolygon:
    case ShapeKind::kConcavePolygon: {
      // a finger (or anything) lying flat
      const double d = ShapeDistance(s, tablePoint);
      if (d >= 0.0) return -1.0;
      return base + RoundedTop(-d, p.fingerThickness);
    }
  }
  return -1.0;
}

}  // namespace

double BodyTopHeight(const ContactShape& s, const SyntheticCameraParams& p,
                     const Vec2& tablePoint) {
  double underside = 0.0;
  return BodyAt(s, p, tablePoint, underside);
}

double BodyUnderside(const ContactShape& s, const SyntheticCameraParams& p,
                     const Vec2& tablePoint) {
  double underside = 0.0;
  return BodyAt(s, p, tablePoint, underside) < 0.0 ? -1.0 : underside;
}

cv::Mat SyntheticCamera::DepthBackground() const {
  const double tableMm = 10.0 * m_cameraHeight;
  return cv::Mat(m_params.height, m_params.width, CV_16UC1,
                 cv::Scalar(Report(tableMm, m_params.disparitySteps)));
}

cv::Mat SyntheticCamera::RenderDepth(std::span<const ContactShape> shapes) {
  const int w = m_params.width, h = m_params.height;
  const double z0 = m_cameraHeight;  // cm
  // the linear map: pixel (u, v) sees table point ((u + 0.5) sx, H - (v + 0.5) sy)
  const double sx = m_table.width / w, sy = m_table.height / h;  // cm per px
  auto tableAt = [&](double u, double v) {
    return Vec2((u + 0.5) * sx, m_table.height - (v + 0.5) * sy);
  };

  // the bodies' tops on the pixel grid of the table (the view from straight above)
  DepthScratch& scratch = m_depthScratch;
  HeightField field;
  field.w = w;
  field.h = h;
  scratch.top.create(h, w, CV_32F);
  scratch.top.setTo(0.0f);
  field.top = scratch.top;
  // the lowest underside of the bodies at a pixel (none yet: infinity), 0 on the table after
  constexpr float kNoBody = std::numeric_limits<float>::infinity();
  scratch.bottom.create(h, w, CV_32F);
  scratch.bottom.setTo(kNoBody);
  field.bottom = scratch.bottom;
  double tallest = 0.0;
  for (const ContactShape& s : shapes) {
    auto [lo, hi] = ShapeBounds(s);
    if (s.kind == ShapeKind::kCircle) {
      GrowBounds(s.pose, Vec2(-s.radius, -m_params.fingerLength - s.radius),
                 Vec2(s.radius, s.radius), lo, hi);
    } else if (s.kind == ShapeKind::kHandFive || s.kind == ShapeKind::kHandFlat) {
      const double scale = std::max(s.scale, 1e-6);
      GrowBounds(s.pose, scale * Vec2(-kArmRadius, kWristY - kArmLength - kArmRadius),
                 scale * Vec2(kArmRadius, kWristY + kArmRadius), lo, hi);
    }
    const int u0 = std::max(0, static_cast<int>(std::floor(lo.x() / sx - 0.5)));
    const int u1 = std::min(w - 1, static_cast<int>(std::ceil(hi.x() / sx - 0.5)));
    const int v0 = std::max(0, static_cast<int>(std::floor((m_table.height - hi.y()) / sy - 0.5)));
    const int v1 =
        std::min(h - 1, static_cast<int>(std::ceil((m_table.height - lo.y()) / sy - 0.5)));
    for (int v = v0; v <= v1; ++v) {
      float* row = field.top.ptr<float>(v);
      float* under = field.bottom.ptr<float>(v);
      for (int u = u0; u <= u1; ++u) {
        double underside = 0.0;
        const double z = BodyAt(s, m_params, tableAt(u, v), underside);
        if (z < 0.0) continue;
        under[u] = std::min(under[u], static_cast<float>(underside));
        if (z > row[u]) {
          row[u] = static_cast<float>(z);
          tallest = std::max(tallest, z);
        }
      }
    }
  }
  for (int v = 0; v < h; ++v) {
    float* under = field.bottom.ptr<float>(v);
    for (int u = 0; u < w; ++u)
      if (under[u] == kNoBody) under[u] = 0.0f;
  }
  // never at or above the camera
  tallest = std::min(tallest, 0.95 * z0);
  const bool clear = tallest <= 0.0;  // nothing above the table
  if (!clear) cv::min(field.top, tallest, field.top);
  const int tilesX = (w + kTile - 1) / kTile, tilesY = (h + kTile - 1) / kTile;
  scratch.tileMax.create(tilesY, tilesX, CV_32F);
  scratch.tileMax.setTo(0.0f);
  field.tileMax = scratch.tileMax;
  for (int v = 0; v < h && !clear; ++v) {
    const float* row = field.top.ptr<float>(v);
    float* tiles = field.tileMax.ptr<float>(v / kTile);
    for (int u = 0; u < w; ++u) tiles[u / kTile] = std::max(tiles[u / kTile], row[u]);
  }

  // each pixel's ray from the camera above the table's centre (pixel c) meets the height field:
  // at height z it passes over pixel q - (q - c) z / z0
  const Vec2 c(0.5 * (w - 1), 0.5 * (h - 1));
  const double baselinePx = m_params.projectorBaseline / sx;
  const Vec2 projector = c + Vec2(baselinePx, 0.0);  // px, at height z0
  const bool shadows = m_params.projectorBaseline != 0.0;
  cv::Mat& seen = scratch.seen;  // the visible surface's height, cm
  cv::Mat& lit = scratch.lit;    // 0 in the projector's shadow
  seen.create(h, w, CV_32F);
  lit.create(h, w, CV_8UC1);
  if (!clear) {
    seen.setTo(0.0f);
    lit.setTo(1);
    for (int tv = 0; tv < tilesY; ++tv) {
      for (int tu = 0; tu < tilesX; ++tu) {
        const int ua = tu * kTile, ub = std::min(w, ua + kTile) - 1;
        const int va = tv * kTile, vb = std::min(h, va + kTile) - 1;
        const Vec2 corners[4] = {Vec2(ua, va), Vec2(ub, va), Vec2(ua, vb), Vec2(ub, vb)};
        // the highest a ray of this tile can meet: the field's maximum where the rays run below
        // that height (twice, as a lower height narrows the region)
        double rayTop = tallest;
        for (int pass = 0; pass < 2 && rayTop > 0.0; ++pass) {
          Vec2 lo = corners[0], hi = corners[0];
          for (const Vec2& q : corners) {
            const Vec2 end = q - (q - c) * (rayTop / z0);
            lo = lo.cwiseMin(q).cwiseMin(end);
            hi = hi.cwiseMax(q).cwiseMax(end);
          }
          rayTop = std::min(rayTop, field.Max(lo.x(), lo.y(), hi.x(), hi.y()));
        }
        // the highest a ray from a point seen in this tile toward the projector can meet
        double shadowTop = 0.0;
        if (shadows) {
          Vec2 lo = corners[0], hi = corners[0];
          for (const Vec2& q : corners) {
            const Vec2 high = q - (q - c) * (rayTop / z0);
            for (const Vec2& from : {q, high}) {
              const Vec2 end = from + (projector - from) * (tallest / z0);
              lo = lo.cwiseMin(from).cwiseMin(end);
              hi = hi.cwiseMax(from).cwiseMax(end);
            }
          }
          shadowTop = field.Max(lo.x(), lo.y(), hi.x(), hi.y());
        }
        if (rayTop <= 0.0 && shadowTop <= kShadowMargin) continue;

        for (int v = va; v <= vb; ++v) {
          for (int u = ua; u <= ub; ++u) {
            const Vec2 q(u, v);
            const Vec2 drift = (q - c) / z0;  // px the ray moves per cm of height
            auto solid = [&](double z) {
              const Vec2 p = q - drift * z;
              return field.Solid(p.x(), p.y(), z);
            };
            // march down from rayTop in steps of at most half a pixel across, then bisect the
            // step where the ray first reaches the surface
            double z = 0.0;
            if (rayTop > 0.0) {
              const double across = drift.norm();
              // and at most kMarchStep down: a ray may pass under a raised body, so the first
              // solid height below a step is only the surface seen when no body lies between
              const double dz =
                  std::min({rayTop, across > 0.0 ? 0.5 / across : rayTop, kMarchStep});
              double above = rayTop;
              if (solid(above)) {
                z = above;
              } else {
                while (true) {
                  const double below = std::max(above - dz, 0.0);
                  if (solid(below)) {
                    // the table itself (nothing raised under the ray's last step) needs no search
                    const Vec2 p = q - drift * below;
                    if (below == 0.0 && field.At(p.x(), p.y()) <= 0.0) break;
                    double hitLo = below, hitHi = above;
                    while (hitHi - hitLo > kCrossingTolerance) {
                      const double mid = 0.5 * (hitLo + hitHi);
                      (solid(mid) ? hitLo : hitHi) = mid;
                    }
                    z = hitLo;
                    break;
                  }
                  above = below;
                }
              }
            }
            seen.at<float>(v, u) = static_cast<float>(z);
            // the projector's ray to the surface point: blocked when the field rises above it
            if (shadows && shadowTop > z + kShadowMargin) {
              const Vec2 from = q - drift * z;
              const Vec2 toward = projector - from;
              const double length = toward.norm();
              const double reach = (shadowTop - z) / (z0 - z);  // fraction of the way up
              const double step = length > 0.0 ? 0.5 / length : reach;
              for (double t = step; t <= reach; t += step) {
                const Vec2 p = from + toward * t;
                const double ray = z + t * (z0 - z);
                if (field.At(p.x(), p.y()) > ray + kShadowMargin &&
                    HeightField::Bilinear(field.bottom, w, h, p.x(), p.y()) < ray - kShadowMargin) {
                  lit.at<uint8_t>(v, u) = 0;
                  break;
                }
              }
            }
          }
        }
      }
    }
  }

  // depth along the optical axis, mm, before noise
  cv::Mat& depth = scratch.depth;
  if (!clear) seen.convertTo(depth, CV_32F, -10.0, 10.0 * z0);

  // holes at depth edges: a pixel whose neighbour's depth differs by more than edge_jump
  cv::Mat& hole = scratch.hole;
  hole.create(h, w, CV_8UC1);
  if (!clear) hole.setTo(0);
  if (m_params.edgeHoles > 0.0 && !clear) {
    const float jump = static_cast<float>(m_params.edgeJump);
    for (int v = 0; v < h; ++v) {
      const float* row = depth.ptr<float>(v);
      const float* up = depth.ptr<float>(std::max(v - 1, 0));
      const float* down = depth.ptr<float>(std::min(v + 1, h - 1));
      uint8_t* out = hole.ptr<uint8_t>(v);
      for (int u = 0; u < w; ++u) {
        const float d = row[u];
        const float step = std::max({std::abs(d - row[std::max(u - 1, 0)]),
                                     std::abs(d - row[std::min(u + 1, w - 1)]), std::abs(d - up[u]),
                                     std::abs(d - down[u])});
        if (step > jump && m_rng.Uniform() < m_params.edgeHoles) out[u] = 1;
      }
    }
  }

  // noise in disparity (so its depth deviation grows with the distance squared), then the
  // 11-bit steps, then mm as the depth sources report them
  cv::Mat out(h, w, CV_16UC1);
  PrefaultPages(out);
  const double sigma = m_params.disparityNoise;
  const bool steps = m_params.disparitySteps;
  const double tableMm = 10.0 * z0;
  const double tableDisparity = KinectDisparity(tableMm);
  const std::array<uint16_t, 2048>& rawToMm = KinectRawToMmTable();
  const uint16_t tableReport = Report(tableMm, steps);
  for (int v = 0; v < h; ++v) {
    uint16_t* o = out.ptr<uint16_t>(v);
    const float* noise = sigma > 0.0 && !m_noiseBank.empty()
                             ? m_noiseBank.data() + m_rng.NextU64() % (m_noiseBank.size() - w)
                             : nullptr;
    if (clear && !noise) {
      std::fill(o, o + w, tableReport);
      continue;
    }
    const float* row = clear ? nullptr : depth.ptr<float>(v);
    const float* height = clear ? nullptr : seen.ptr<float>(v);
    const uint8_t* holes = clear ? nullptr : hole.ptr<uint8_t>(v);
    const uint8_t* light = clear ? nullptr : lit.ptr<uint8_t>(v);
    for (int u = 0; u < w; ++u) {
      const bool table = clear || height[u] == 0.0f;
      if (!clear && (holes[u] || !light[u])) {
        o[u] = 0;
        continue;
      }
      if (!noise) {
        o[u] = table ? tableReport : Report(row[u], steps);
        continue;
      }
      const double disparity =
          (table ? tableDisparity : KinectDisparity(row[u])) + sigma * noise[u];
      if (steps) {
        // floor(x + 0.5): lround's rounding for the positive values that matter, without the call
        const double rounded = std::floor(disparity + 0.5);
        const int raw = rounded >= 0.0 && rounded < kKinectNoReading ? static_cast<int>(rounded)
                                                                     : kKinectNoReading;
        o[u] = raw < kKinectNoReading ? rawToMm[raw] : 0;
      } else {
        const double mm = kKinectFitScale * std::tan(disparity / kKinectFitSpan + kKinectFitOffset);
        o[u] = mm > 0.0 && mm < 65535.0 ? static_cast<uint16_t>(std::lround(mm)) : 0;
      }
    }
  }
  return out;
}

}  // namespace pg
