#include "proxygrasp/sensing/synthetic_camera.h"

#include "prefault.h"

#include "proxygrasp/core/params.h"
#include "proxygrasp/core/units.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pg {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- signed distance primitives (local frame, cm, negative inside) ----

double CapsuleDistance(const Vec2& p, const Vec2& a, const Vec2& b, double r) {
  return DistanceToSegment(p, a, b) - r;
}

double RoundedBoxDistance(const Vec2& p, const Vec2& half, double r) {
  const Vec2 q = p.cwiseAbs() - half + Vec2(r, r);
  return q.cwiseMax(0.0).norm() + std::min(std::max(q.x(), q.y()), 0.0) - r;
}

// a band of half-thickness t around an arc of radius R centred on direction `mid`, +-half radians
double ArcDistance(const Vec2& p, double R, double mid, double half, double t) {
  const Vec2 q = Rotate(p, -mid);
  const double phi = std::atan2(q.y(), q.x());
  if (std::abs(phi) <= half) return std::abs(q.norm() - R) - t;
  const Vec2 e1(R * std::cos(half), R * std::sin(half));
  const Vec2 e2(R * std::cos(half), -R * std::sin(half));
  return std::min((q - e1).norm(), (q - e2).norm()) - t;
}

double EllipseDistance(const Vec2& p, double a, double b) {
  // first-order distance (f / |grad f| form): its zero level is the exact ellipse
  const double k0 = Vec2(p.x() / a, p.y() / b).norm();
  const double k1 = Vec2(p.x() / (a * a), p.y() / (b * b)).norm();
  if (k1 < 1e-12) return -std::min(a, b);
  return k0 * (k0 - 1.0) / k1;
}

// union of two shapes whose concave joints are filleted with circular arcs of radius r (for
// straight boundaries the fillet is exact; the zero level stays continuous everywhere)
double RoundUnion(double a, double b, double r) {
  if (r <= 0.0) return std::min(a, b);
  const double u = std::max(r - a, 0.0), v = std::max(r - b, 0.0);
  return std::max(r, std::min(a, b)) - std::sqrt(u * u + v * v);
}

// ---- hands: a palm (rounded box) and finger capsules, in the hand's unscaled local frame ----

struct Finger {
  Vec2 base;
  double angle;  // from +y, positive towards -x, degrees
  double length;
  double radius;
};

struct HandModel {
  Vec2 palmHalf{4.0, 5.0};
  double palmCorner = 1.8;
  std::vector<Finger> fingers;    // thumb first
  std::vector<Vec2> tips;         // fingertip cap centres, from the fingers
  std::vector<Vec2> mids;         // finger axis midpoints, from the fingers
  std::vector<Vec2> axes;         // tip - base, from the fingers
  std::vector<double> axisLen2s;  // squared axis lengths (> 0), from the fingers
  std::vector<double> reaches;    // half axis length plus radius: no finger point is farther from
                                  // its midpoint
  double blend = 0.5;  // radius of the fillets where fingers meet the palm and each other, cm
  bool cupped = false;
};

Vec2 FingerTip(const Finger& f) {
  const double a = DegToRad(f.angle);
  return f.base + f.length * Vec2(-std::sin(a), std::cos(a));
}

HandModel WithTips(HandModel h) {
  for (const Finger& f : h.fingers) {
    h.tips.push_back(FingerTip(f));
    h.mids.push_back(0.5 * (f.base + h.tips.back()));
    h.axes.push_back(h.tips.back() - f.base);
    h.axisLen2s.push_back(h.axes.back().squaredNorm());
    h.reaches.push_back(0.5 * (h.tips.back() - f.base).norm() + f.radius);
  }
  return h;
}

const HandModel& HandFor(ShapeKind kind) {
  static const HandModel kFive = [] {
    HandModel h;
    h.fingers = {{{-3.0, -1.8}, 55, 6.0, 1.0},
                 {{-3.15, 3.8}, 16, 7.6, 0.85},
                 {{-1.0, 4.2}, 4, 8.8, 0.9},
                 {{1.15, 4.0}, -9, 8.1, 0.85},
                 {{3.15, 3.3}, -24, 6.4, 0.75}};
    h.blend = 0.45;
    return WithTips(h);
  }();
  static const HandModel kFlat = [] {
    HandModel h;
    // fingers side by side, overlapping a little, as wide together as the palm; the thumb lies
    // along the palm's side
    h.fingers = {{{-3.4, -2.5}, 10, 5.2, 1.0},
                 {{-2.6, 4.0}, 0, 7.4, 0.95},
                 {{-0.87, 4.2}, 0, 8.6, 0.95},
                 {{0.87, 4.1}, 0, 8.0, 0.95},
                 {{2.6, 3.6}, 0, 6.4, 0.85}};
    h.blend = 0.6;
    return WithTips(h);
  }();
  static const HandModel kCupped = [] {
    HandModel h;
    h.cupped = true;
    return h;
  }();
  switch (kind) {
    case ShapeKind::kHandFive:
      return kFive;
    case ShapeKind::kHandFlat:
      return kFlat;
    default:
      return kCupped;
  }
}

// the cupped hand's edge: a C-shaped band 1.5 cm thick on an arc of radius 5.4 cm spanning 200
// degrees, opening towards +x; its centreline is about 19 cm long
constexpr double kCupRadius = 5.4;
constexpr double kCupHalfSpan = 100.0;  // degrees
constexpr double kCupHalfThickness = 0.75;

// DistanceToSegment(p, a, a + ab) - r with ab's squared length (> 0) given: the same operations in
// the same order, so the same bits, without the call (a hand pixel evaluates up to five of these)
inline double FingerDistance(const Vec2& p, const Vec2& a, const Vec2& ab, double len2, double r) {
  const double ax = p.x() - a.x(), ay = p.y() - a.y();
  const double t = std::clamp((ax * ab.x() + ay * ab.y()) / len2, 0.0, 1.0);
  const double dx = p.x() - (a.x() + t * ab.x()), dy = p.y() - (a.y() + t * ab.y());
  return std::sqrt(dx * dx + dy * dy) - r;
}

double HandDistanceUnscaled(const HandModel& h, const Vec2& p) {
  if (h.cupped) return ArcDistance(p, kCupRadius, kPi, DegToRad(kCupHalfSpan), kCupHalfThickness);
  double d = RoundedBoxDistance(p, h.palmHalf, h.palmCorner);
  for (size_t i = 0; i < h.fingers.size(); ++i) {
    // A finger's distance is at least |p - mid| - reach. Where that is at least m = max(blend, d)
    // the union takes nothing from the finger: RoundUnion(d, b, blend) is the same number for
    // every b >= m (v = 0 and min(d, b) = d), so it is computed with b = m, bit for bit what the
    // finger's own distance gives, without the finger. Most pixels of a hand are far from most
    // of its fingers. (1e-6 cm keeps rounding in the bound on the safe side.)
    const double m = std::max(h.blend, d);
    const double far = m + h.reaches[i] + 1e-6;
    if (far > 0.0 && (p - h.mids[i]).squaredNorm() >= far * far) {
      // RoundUnion(d, m, blend) is max(blend, d) - sqrt(u * u) with u = max(blend - d, 0), and
      // in binary floating point sqrt(u * u) is u exactly (when u * u underflows, u is far below
      // blend's last bit and both give blend): this is that number without the root
      if (d < h.blend) d = h.blend - (h.blend - d);
      continue;
    }
    const Finger& f = h.fingers[i];
    d = RoundUnion(d, FingerDistance(p, f.base, h.axes[i], h.axisLen2s[i], f.radius), h.blend);
  }
  return d;
}

bool IsHand(ShapeKind kind) {
  return kind == ShapeKind::kHandFive || kind == ShapeKind::kHandFlat ||
         kind == ShapeKind::kHandCupped;
}

// signed distance in the shape's local frame
double LocalDistance(const ContactShape& s, const Contour* polygon, const Vec2& p) {
  switch (s.kind) {
    case ShapeKind::kCircle:
      return p.norm() - s.radius;
    case ShapeKind::kEllipse:
      return EllipseDistance(p, s.radiusX, s.radiusY);
    case ShapeKind::kCapsule:
      return CapsuleDistance(p, Vec2(-0.5 * s.length, 0.0), Vec2(0.5 * s.length, 0.0), s.radius);
    case ShapeKind::kConvexPolygon:
    case ShapeKind::kConcavePolygon:
      if (!polygon || polygon->cols() < 3) return kInf;
      return -SignedDistance(*polygon, p);
    case ShapeKind::kHandFive:
    case ShapeKind::kHandFlat:
    case ShapeKind::kHandCupped: {
      const double scale = std::max(s.scale, 1e-6);
      return scale * HandDistanceUnscaled(HandFor(s.kind), p / scale);
    }
  }
  return kInf;
}

Contour LocalPolygon(const ContactShape& s) {
  return MakeCounterClockwise(ToContour(s.points));
}

// a hand's unscaled local bounds, from its primitives
std::pair<Vec2, Vec2> HandBounds(const HandModel& h) {
  if (h.cupped) {
    const double r = kCupRadius + kCupHalfThickness;
    return {Vec2(-r, -r), Vec2(r, r)};
  }
  Vec2 lo = -h.palmHalf, hi = h.palmHalf;
  for (const Finger& f : h.fingers) {
    const Vec2 tip = FingerTip(f);
    lo = lo.cwiseMin(f.base - Vec2::Constant(f.radius)).cwiseMin(tip - Vec2::Constant(f.radius));
    hi = hi.cwiseMax(f.base + Vec2::Constant(f.radius)).cwiseMax(tip + Vec2::Constant(f.radius));
  }
  return {lo, hi};
}

// ---- a hand's distance sampled on a grid: rendering reads it where the exact value is not needed

// A hand's unscaled distance at the nodes of a square grid (exact there, stored as float), read
// between them by bilinear interpolation. The distance is sqrt(2)-Lipschitz (a round union's
// gradient is (u grad a + v grad b) / sqrt(u^2 + v^2), at most sqrt(2) long; every other part is a
// true distance), and the bilinear weights w_i of a cell's corners c_i give
// sum w_i |p - c_i| <= sqrt(sum w_i |p - c_i|^2) = spacing sqrt(s (1 - s) + t (1 - t))
// <= spacing / sqrt(2). So an interpolated value is within sqrt(2) spacing / sqrt(2) = spacing of
// the exact one, plus the float rounding of the nodes (|d| < 30 cm: under 2e-6 cm).
struct HandField {
  static constexpr double kSpacing = 0.05;  // cm, unscaled
  static constexpr double kMargin = 2.5;    // cm beyond the hand's bounds, unscaled
  Vec2 origin = Vec2::Zero();               // node (0, 0), unscaled local cm
  int cols = 0, rows = 0;
  std::vector<float> values;       // row-major, rows along y
  double error = kSpacing + 1e-5;  // bound on |sampled - exact|, unscaled cm

  // the interpolated distance at grid coordinates (x, y) (node (c, r) at (c, r)); false off the
  // grid
  bool Sample(double x, double y, double& d) const {
    if (!(x >= 0.0 && y >= 0.0 && x < cols - 1 && y < rows - 1)) return false;
    const int c = static_cast<int>(x), r = static_cast<int>(y);
    const double fx = x - c, fy = y - r;
    const float* a = values.data() + static_cast<size_t>(r) * cols + c;
    const float* b = a + cols;
    d = (1.0 - fy) * ((1.0 - fx) * a[0] + fx * a[1]) + fy * ((1.0 - fx) * b[0] + fx * b[1]);
    return true;
  }
};

HandField BuildHandField(const HandModel& h) {
  HandField f;
  const auto [lo, hi] = HandBounds(h);
  f.origin = lo - Vec2::Constant(HandField::kMargin);
  const Vec2 size = hi - lo + Vec2::Constant(2.0 * HandField::kMargin);
  f.cols = static_cast<int>(std::ceil(size.x() / HandField::kSpacing)) + 1;
  f.rows = static_cast<int>(std::ceil(size.y() / HandField::kSpacing)) + 1;
  f.values.resize(static_cast<size_t>(f.cols) * f.rows);
  for (int r = 0; r < f.rows; ++r) {
    for (int c = 0; c < f.cols; ++c) {
      const Vec2 p = f.origin + HandField::kSpacing * Vec2(c, r);
      f.values[static_cast<size_t>(r) * f.cols + c] =
          static_cast<float>(HandDistanceUnscaled(h, p));
    }
  }
  return f;
}

// built on first use, once per process (0.14 to 0.21 million nodes, 0.5 to 0.8 MB, per hand kind)
const HandField& HandFieldFor(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kHandFive: {
      static const HandField five = BuildHandField(HandFor(kind));
      return five;
    }
    case ShapeKind::kHandFlat: {
      static const HandField flat = BuildHandField(HandFor(kind));
      return flat;
    }
    default: {
      static const HandField cupped = BuildHandField(HandFor(ShapeKind::kHandCupped));
      return cupped;
    }
  }
}

// ---- hand outlines: rasterize the distance sign finely, trace, then snap to the zero level ----

Contour TraceHandOutline(ShapeKind kind, double scale) {
  ContactShape s;
  s.kind = kind;
  s.scale = scale;
  const auto eval = [&](const Vec2& p) { return LocalDistance(s, nullptr, p); };

  auto [lo, hi] = HandBounds(HandFor(kind));
  lo = lo * scale - Vec2::Constant(0.2);
  hi = hi * scale + Vec2::Constant(0.2);

  // inside mask on a fine grid
  constexpr double kGrid = 0.04;  // cm
  const double step = kGrid * std::min(1.0, std::max(scale, 0.25));
  const int cols = static_cast<int>(std::ceil((hi.x() - lo.x()) / step)) + 1;
  const int rows = static_cast<int>(std::ceil((hi.y() - lo.y()) / step)) + 1;
  cv::Mat mask(rows, cols, CV_8UC1);
  for (int r = 0; r < rows; ++r) {
    uint8_t* row = mask.ptr<uint8_t>(r);
    for (int c = 0; c < cols; ++c) row[c] = eval(lo + Vec2(c * step, r * step)) <= 0.0 ? 255 : 0;
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  if (contours.empty()) return Contour(2, 0);
  const auto largest = std::max_element(contours.begin(), contours.end(), [](auto& a, auto& b) {
    return std::abs(cv::contourArea(a)) < std::abs(cv::contourArea(b));
  });

  // move each boundary cell centre outwards along the gradient onto the zero level (bisection)
  std::vector<Vec2> points;
  points.reserve(largest->size());
  for (const cv::Point& cell : *largest) {
    const Vec2 p = lo + Vec2(cell.x * step, cell.y * step);
    constexpr double kDiff = 1e-4;
    Vec2 g((eval(p + Vec2(kDiff, 0)) - eval(p - Vec2(kDiff, 0))),
           (eval(p + Vec2(0, kDiff)) - eval(p - Vec2(0, kDiff))));
    if (g.norm() < 1e-12) continue;
    g.normalize();
    double t0 = 0.0, t1 = 3.0 * step;
    if (eval(p) > 0.0 || eval(p + t1 * g) <= 0.0) {
      points.push_back(p);
      continue;
    }
    for (int i = 0; i < 30; ++i) {
      const double tm = 0.5 * (t0 + t1);
      (eval(p + tm * g) <= 0.0 ? t0 : t1) = tm;
    }
    points.push_back(p + 0.5 * (t0 + t1) * g);
  }
  return MakeCounterClockwise(ToContour(points));
}

const Contour& CachedHandOutline(ShapeKind kind, double scale) {
  static std::mutex mutex;
  static std::map<std::pair<int, double>, Contour> cache;
  std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(static_cast<int>(kind), scale);
  auto it = cache.find(key);
  if (it == cache.end()) {
    // a handful of hand sizes are used at a time; keep the cache from growing without bound
    if (cache.size() > 64) cache.clear();
    it = cache.emplace(key, TraceHandOutline(kind, scale)).first;
  }
  return it->second;
}

Contour SampleEllipse(double a, double b) {
  const double perimeter = kPi * (3.0 * (a + b) - std::sqrt((3.0 * a + b) * (a + 3.0 * b)));
  const int n = std::max(64, static_cast<int>(std::ceil(perimeter / 0.03)));
  Contour c(2, n);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * i / n;
    c.col(i) = Vec2(a * std::cos(t), b * std::sin(t));
  }
  return c;
}

Contour SampleCapsule(double length, double r) {
  const int half = std::max(32, static_cast<int>(std::ceil(kPi * r / 0.03)));
  Contour c(2, 2 * (half + 1));
  int k = 0;
  // right cap from -90 to +90 degrees, then the left cap from +90 to 270
  for (int i = 0; i <= half; ++i) {
    const double t = -0.5 * kPi + kPi * i / half;
    c.col(k++) = Vec2(0.5 * length + r * std::cos(t), r * std::sin(t));
  }
  for (int i = 0; i <= half; ++i) {
    const double t = 0.5 * kPi + kPi * i / half;
    c.col(k++) = Vec2(-0.5 * length + r * std::cos(t), r * std::sin(t));
  }
  return c;
}

Contour LocalOutline(const ContactShape& s) {
  switch (s.kind) {
    case ShapeKind::kCircle:
      return SampleEllipse(s.radius, s.radius);
    case ShapeKind::kEllipse:
      return SampleEllipse(s.radiusX, s.radiusY);
    case ShapeKind::kCapsule:
      return SampleCapsule(s.length, s.radius);
    case ShapeKind::kConvexPolygon:
    case ShapeKind::kConcavePolygon:
      return LocalPolygon(s);
    case ShapeKind::kHandFive:
    case ShapeKind::kHandFlat:
    case ShapeKind::kHandCupped:
      return CachedHandOutline(s.kind, s.scale);
  }
  return Contour(2, 0);
}

// ---- composing a frame: the illumination model on spans of a row ----

// A new frame's memory is usually fresh from the kernel: touching it faults once per 4 KB page, and
// on a virtual machine those traps took a third of a two-hand frame. One call maps them all. Where
// the call is missing or fails the pages fault as before; the contents never change.
}  // namespace

void PrefaultPages(const cv::Mat& image) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  static const uintptr_t kPage = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const uintptr_t data = reinterpret_cast<uintptr_t>(image.data);
  // whole pages inside the image only: madvise takes page-aligned ranges
  const uintptr_t begin = (data + kPage - 1) / kPage * kPage;
  const uintptr_t end = (data + image.total() * image.elemSize()) / kPage * kPage;
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
  (void)image;
#endif
}

namespace {

// one row of Compose's inputs and output
struct ComposeRow {
  const float* gain;           // vignetting, 0..1
  const float* background;     // grey
  const float* litBackground;  // gain * background, grey
  const float* contact;        // coverage, 0..1
  const float* halo;           // 0..1
  const float* noise;          // standard normal samples, nullptr for none
  double sigma;                // noise deviation, grey
  float tie;                   // how near a half the level in float may be (ComposeSpan), grey
  float contactLevel, haloLevel;
  uint8_t* out;
};

// pixels [begin, end) of a row: background, contact and halo, all dimmed by vignetting, then sensor
// noise. Without shapes (no contact and no halo there) the level is the background exactly, so the
// precomputed gain * background gives the same bits. Sixteen pixels at a time where the CPU has
// 128-bit vectors with doubles: the same float and double operations in the same order, and the
// same rounding (to nearest even, as cvRound) and saturation as the one-pixel loop.
template <bool kShapes>
void ComposeSpan(const ComposeRow& r, int begin, int end) {
  int u = begin;
#if CV_SIMD128_64F
  const cv::v_float32x4 contactLevel = cv::v_setall_f32(r.contactLevel);
  const cv::v_float32x4 haloLevel = cv::v_setall_f32(r.haloLevel);
  const cv::v_float32x4 one = cv::v_setall_f32(1.0f);
  const cv::v_float64x2 sigma = cv::v_setall_f64(r.sigma);
  const cv::v_float32x4 sigmaF = cv::v_setall_f32(static_cast<float>(r.sigma));
  // The level with noise is lit + sigma n in double. The same sum in float is within r.tie of
  // it (Compose), so it rounds to the same integer unless it lies within r.tie of a half: a group
  // of 16 pixels with such a level is done again in double.
  const cv::v_float32x4 nearHalf = cv::v_setall_f32(0.5f - r.tie);
  auto lit = [&](int i) {
    if constexpr (kShapes) {
      const cv::v_float32x4 b = cv::v_load(r.background + i);
      const cv::v_float32x4 c = cv::v_load(r.contact + i);
      const cv::v_float32x4 level =
          b + (contactLevel - b) * c + haloLevel * cv::v_load(r.halo + i) * (one - c);
      return cv::v_load(r.gain + i) * level;
    } else {
      return cv::v_load(r.litBackground + i);
    }
  };
  for (; u + 16 <= end; u += 16) {
    cv::v_int32x4 rounded[4];
    if (!r.noise) {
      // without noise the level is the float itself, which double holds exactly
      for (int k = 0; k < 4; ++k) rounded[k] = cv::v_round(lit(u + 4 * k));
    } else {
      cv::v_float32x4 tie = cv::v_setzero_f32();
      for (int k = 0; k < 4; ++k) {
        const int i = u + 4 * k;
        const cv::v_float32x4 level = lit(i) + sigmaF * cv::v_load(r.noise + i);
        rounded[k] = cv::v_round(level);
        tie = tie | (cv::v_abs(level - cv::v_cvt_f32(rounded[k])) > nearHalf);
      }
      if (cv::v_check_any(tie)) {
        for (int k = 0; k < 4; ++k) {
          const int i = u + 4 * k;
          const cv::v_float32x4 l = lit(i), n = cv::v_load(r.noise + i);
          const cv::v_float64x2 low = cv::v_cvt_f64(l) + sigma * cv::v_cvt_f64(n);
          const cv::v_float64x2 high = cv::v_cvt_f64_high(l) + sigma * cv::v_cvt_f64_high(n);
          rounded[k] = cv::v_round(low, high);
        }
      }
    }
    cv::v_store(r.out + u, cv::v_pack_u(cv::v_pack(rounded[0], rounded[1]),
                                        cv::v_pack(rounded[2], rounded[3])));
  }
#endif
  for (; u < end; ++u) {
    float lit;
    if constexpr (kShapes) {
      const float b = r.background[u], c = r.contact[u];
      const float level = b + (r.contactLevel - b) * c + r.haloLevel * r.halo[u] * (1.0f - c);
      lit = r.gain[u] * level;
    } else {
      lit = r.litBackground[u];
    }
    double value = lit;
    if (r.noise) value += r.sigma * r.noise[u];
    r.out[u] = cv::saturate_cast<uint8_t>(value);
  }
}

}  // namespace

double ShapeDistance(const ContactShape& shape, const Vec2& tablePoint) {
  const Vec2 local = shape.pose.Inverse(tablePoint);
  if (shape.kind == ShapeKind::kConvexPolygon || shape.kind == ShapeKind::kConcavePolygon) {
    const Contour poly = LocalPolygon(shape);
    return LocalDistance(shape, &poly, local);
  }
  return LocalDistance(shape, nullptr, local);
}

bool SampledHandDistance(const ContactShape& shape, const Vec2& tablePoint, double& distance,
                         double& error) {
  if (!IsHand(shape.kind)) return false;
  const HandField& field = HandFieldFor(shape.kind);
  const double scale = std::max(shape.scale, 1e-6);
  const Vec2 grid = (shape.pose.Inverse(tablePoint) / scale - field.origin) / HandField::kSpacing;
  double d;
  if (!field.Sample(grid.x(), grid.y(), d)) return false;
  distance = scale * d;
  error = scale * field.error;
  return true;
}

std::vector<Circle> HandFingertips(const ContactShape& shape) {
  std::vector<Circle> tips;
  if (shape.kind != ShapeKind::kHandFive && shape.kind != ShapeKind::kHandFlat) return tips;
  const HandModel& hand = HandFor(shape.kind);
  const double scale = std::max(shape.scale, 1e-6);
  for (size_t i = 0; i < hand.fingers.size(); ++i)
    tips.push_back({shape.pose.Apply(scale * hand.tips[i]), scale * hand.fingers[i].radius});
  return tips;
}

Contour ShapeOutline(const ContactShape& shape) {
  const Contour local = LocalOutline(shape);
  Contour out(2, local.cols());
  // Pose2::Apply with its cosine and sine computed once, not per point (a hand's outline has
  // thousands, and Render bounds every shape with this each frame)
  const double c = std::cos(shape.pose.angle), s = std::sin(shape.pose.angle);
  for (int i = 0; i < local.cols(); ++i) {
    const double x = local(0, i), y = local(1, i);
    out.col(i) = Vec2(c * x - s * y, s * x + c * y) + shape.pose.pos;
  }
  return out;
}

std::pair<Vec2, Vec2> ShapeBounds(const ContactShape& shape) {
  const Contour c = ShapeOutline(shape);
  if (c.cols() == 0) return {shape.pose.pos, shape.pose.pos};
  return {c.rowwise().minCoeff(), c.rowwise().maxCoeff()};
}

CameraModel SyntheticCameraModel(const SyntheticCameraParams& params, const TableParams& table) {
  CameraModel m;
  const int w = params.width, h = params.height;
  m.imageSize = cv::Size(w, h);
  // a moderately wide lens: focal length 0.9 of the image width
  const double f = 0.9 * w;
  m.cameraMatrix = cv::Matx33d(f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1);
  // the depth camera looks straight down: the table maps linearly onto its image
  const bool depth = params.kind == CameraKind::kDepth;
  m.distCoeffs = cv::Vec<double, 5>(depth ? 0.0 : params.distortion, 0, 0, 0, 0);
  // the table's near edge fills the bottom of the image; its far edge appears narrower by
  // `perspective` of the width (keystone)
  const double inset = depth ? 0.0 : 0.5 * params.perspective * w;
  const cv::Point2f image[4] = {{static_cast<float>(-0.5 + inset), -0.5f},
                                {static_cast<float>(w - 0.5 - inset), -0.5f},
                                {static_cast<float>(w - 0.5), static_cast<float>(h - 0.5)},
                                {-0.5f, static_cast<float>(h - 0.5)}};
  const cv::Point2f tablePts[4] = {
      {0.0f, static_cast<float>(table.height)},
      {static_cast<float>(table.width), static_cast<float>(table.height)},
      {static_cast<float>(table.width), 0.0f},
      {0.0f, 0.0f}};
  cv::Mat hm = cv::getPerspectiveTransform(image, tablePts);
  m.cameraToTable = cv::Matx33d(hm.ptr<double>());
  return m;
}

SyntheticCamera::SyntheticCamera(const SyntheticCameraParams& params, const TableParams& table)
    : m_params(params),
      m_table(table),
      m_model(SyntheticCameraModel(params, table)),
      m_rng(static_cast<uint64_t>(params.seed)),
      m_cameraHeight(DepthCameraHeight(params, table)) {
  const int w = params.width, h = params.height;
  m_tableX.create(h, w, CV_32F);
  m_tableY.create(h, w, CV_32F);
  // where each pixel looks on the table, and the illumination it sees
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Vec2 t = m_model.CameraToTable(Vec2(u, v));
      m_tableX.at<float>(v, u) = static_cast<float>(t.x());
      m_tableY.at<float>(v, u) = static_cast<float>(t.y());
    }
  }
  BuildIllumination();
  if (WantsNoiseBank()) DrawNoiseBank();
  // local pixel size from the map's finite differences
  m_cmPerPixel.create(h, w, CV_32F);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const int u0 = std::max(u - 1, 0), u1 = std::min(u + 1, w - 1);
      const int v0 = std::max(v - 1, 0), v1 = std::min(v + 1, h - 1);
      const double du = std::max(u1 - u0, 1), dv = std::max(v1 - v0, 1);
      const double jxx = (m_tableX.at<float>(v, u1) - m_tableX.at<float>(v, u0)) / du;
      const double jxy = (m_tableY.at<float>(v, u1) - m_tableY.at<float>(v, u0)) / du;
      const double jyx = (m_tableX.at<float>(v1, u) - m_tableX.at<float>(v0, u)) / dv;
      const double jyy = (m_tableY.at<float>(v1, u) - m_tableY.at<float>(v0, u)) / dv;
      m_cmPerPixel.at<float>(v, u) = static_cast<float>(std::sqrt(std::abs(jxx * jyy - jxy * jyx)));
    }
  }
}

void SyntheticCamera::BuildIllumination() {
  const int w = m_params.width, h = m_params.height;
  // fresh buffers: a copied camera shares its maps with the original until they are rebuilt
  m_gain = cv::Mat(h, w, CV_32F);
  m_background = cv::Mat(h, w, CV_32F);
  m_litBackground = cv::Mat(h, w, CV_32F);
  const double cx = (w - 1) / 2.0, cy = (h - 1) / 2.0;
  const double rMax2 = cx * cx + cy * cy;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / rMax2;
      m_gain.at<float>(v, u) = static_cast<float>(1.0 - m_params.vignetting * r2);
      m_background.at<float>(v, u) = static_cast<float>(
          m_params.background + m_params.gradient * (u / std::max(w - 1.0, 1.0) - 0.5));
      // what Compose's illumination gives where there is neither contact nor halo, bit for bit
      m_litBackground.at<float>(v, u) = m_gain.at<float>(v, u) * m_background.at<float>(v, u);
    }
  }
}

void SyntheticCamera::DrawNoiseBank() {
  // a bank of standard normal samples; frames draw their noise rows from random places in it
  constexpr size_t kBankSize = size_t{1} << 18;
  m_noiseBank.resize(std::max(kBankSize, static_cast<size_t>(4 * m_params.width)));
  m_noiseMax = 0.0f;
  for (float& n : m_noiseBank) {
    n = static_cast<float>(m_rng.Normal());
    m_noiseMax = std::max(m_noiseMax, std::abs(n));
  }
}

MaybeError SyntheticCamera::SetParams(const SyntheticCameraParams& params) {
  const std::vector<std::string> fixed = FixedKeysChanged(params);
  if (!fixed.empty()) {
    return MakeError({"camera." + fixed.front()},
                     "cannot change on a built camera (it fixes the image and the noise stream)");
  }
  const bool lighting = params.background != m_params.background ||
                        params.gradient != m_params.gradient ||
                        params.vignetting != m_params.vignetting;
  m_params = params;
  if (lighting) BuildIllumination();
  // the bank is drawn the first time noise is asked for
  if (WantsNoiseBank() && m_noiseBank.empty()) DrawNoiseBank();
  return std::nullopt;
}

bool SyntheticCamera::WantsNoiseBank() const {
  return m_params.kind == CameraKind::kDepth ? m_params.disparityNoise > 0.0 : m_params.noise > 0.0;
}

std::vector<std::string> SyntheticCamera::FixedKeysChanged(
    const SyntheticCameraParams& params) const {
  // the keys described as needing a restart (Apply::kRestart)
  return RestartKeysChanged("camera", m_params, params);
}

cv::Mat SyntheticCamera::Compose(const cv::Mat& contact, const cv::Mat& halo,
                                 std::span<const cv::Rect> drawn) {
  const int w = m_params.width, h = m_params.height;
  cv::Mat out(h, w, CV_8UC1);
  PrefaultPages(out);
  ComposeRow row;
  row.contactLevel = static_cast<float>(m_params.contactLevel);
  row.haloLevel = static_cast<float>(m_params.haloLevel);
  row.sigma = m_params.noise;
  // Float rounds sigma, the product sigma n and the sum lit + sigma n each within a relative
  // 2^-24; with |lit| < 1024 grey (a level of at most background + contact + halo, dimmed) the
  // float sum is within 2^-24 (1024 + 3 sigma max|n|) of the double one. Four times that, and
  // at least 1e-3 grey.
  row.tie = static_cast<float>(
      std::max(1e-3, 4.0 * std::ldexp(1024.0 + 3.0 * m_params.noise * m_noiseMax, -24)));
  std::vector<std::pair<int, int>> spans;
  for (int v = 0; v < h; ++v) {
    row.gain = m_gain.ptr<float>(v);
    row.background = m_background.ptr<float>(v);
    row.litBackground = m_litBackground.ptr<float>(v);
    row.contact = contact.ptr<float>(v);
    row.halo = halo.ptr<float>(v);
    row.out = out.ptr<uint8_t>(v);
    // each row takes its noise from a random place in the bank
    row.noise =
        row.sigma > 0.0 ? m_noiseBank.data() + m_rng.NextU64() % (m_noiseBank.size() - w) : nullptr;
    // the columns shapes drew into on this row, in order; the rest shows the clear table
    spans.clear();
    for (const cv::Rect& r : drawn) {
      if (v >= r.y && v < r.y + r.height) spans.emplace_back(r.x, r.x + r.width);
    }
    std::sort(spans.begin(), spans.end());
    int u = 0;
    for (const auto& [begin, end] : spans) {
      if (end <= u) continue;
      ComposeSpan<false>(row, u, std::max(begin, u));
      ComposeSpan<true>(row, std::max(begin, u), end);
      u = end;
    }
    ComposeSpan<false>(row, u, w);
  }
  return out;
}

cv::Mat SyntheticCamera::Render(std::span<const ContactShape> shapes) {
  if (m_params.kind == CameraKind::kDepth) return RenderDepth(shapes);
  const int w = m_params.width, h = m_params.height;
  // reused buffers: a fresh pair of 1.2 MB images a frame cost more than drawing the shapes
  // (page faults and clearing); only what the last frame drew is cleared
  Scratch& scratch = m_scratch;
  if (scratch.contact.rows != h || scratch.contact.cols != w) {
    scratch.contact = cv::Mat::zeros(h, w, CV_32F);
    scratch.halo = cv::Mat::zeros(h, w, CV_32F);
    scratch.drawn.clear();
  }
  for (const cv::Rect& r : scratch.drawn) {
    scratch.contact(r).setTo(0.0f);
    scratch.halo(r).setTo(0.0f);
  }
  scratch.drawn.clear();
  cv::Mat& contact = scratch.contact;
  cv::Mat& halo = scratch.halo;
  const double haloWidth = m_params.haloWidth;

  for (const ContactShape& s : shapes) {
    const bool hand = IsHand(s.kind);
    const Contour polygon = LocalPolygon(s);
    // camera pixels that can see the shape (and its halo)
    auto [lo, hi] = ShapeBounds(s);
    const double margin = (hand ? haloWidth : 0.0) + 0.5;
    lo -= Vec2::Constant(margin);
    hi += Vec2::Constant(margin);
    double u0 = kInf, v0 = kInf, u1 = -kInf, v1 = -kInf;
    constexpr int kEdgeSamples = 8;
    for (int i = 0; i <= kEdgeSamples; ++i) {
      const double t = static_cast<double>(i) / kEdgeSamples;
      for (const Vec2& p :
           {Vec2(Lerp(lo.x(), hi.x(), t), lo.y()), Vec2(Lerp(lo.x(), hi.x(), t), hi.y()),
            Vec2(lo.x(), Lerp(lo.y(), hi.y(), t)), Vec2(hi.x(), Lerp(lo.y(), hi.y(), t))}) {
        const Vec2 px = m_model.TableToCamera(p);
        u0 = std::min(u0, px.x());
        u1 = std::max(u1, px.x());
        v0 = std::min(v0, px.y());
        v1 = std::max(v1, px.y());
      }
    }
    const int uBegin = std::max(0, static_cast<int>(std::floor(u0)) - 3);
    const int uEnd = std::min(w - 1, static_cast<int>(std::ceil(u1)) + 3);
    const int vBegin = std::max(0, static_cast<int>(std::floor(v0)) - 3);
    const int vEnd = std::min(h - 1, static_cast<int>(std::ceil(v1)) + 3);
    if (uBegin > uEnd || vBegin > vEnd) continue;  // entirely off the image
    scratch.drawn.emplace_back(uBegin, vBegin, uEnd - uBegin + 1, vEnd - vBegin + 1);

    // area coverage from the signed distance in pixels (a one-pixel linear ramp), and the halo;
    // blocks whose centre is far outside (beyond the halo) or deep inside are done at once
    // a contact above the surface is dimmed (1 when touching, so touching contacts are unchanged)
    const double pressure = std::clamp(s.pressure, 0.0, 1.0) * IrHoverDimming(s.height);
    const double haloReach = hand && haloWidth > 0.0 ? haloWidth : 0.0;
    // the pose's inverse with its rotation computed once
    const double cosA = std::cos(s.pose.angle), sinA = std::sin(s.pose.angle);
    // a hand's model, sampled field and scale looked up once
    const HandModel* handModel = hand ? &HandFor(s.kind) : nullptr;
    const HandField* field = hand ? &HandFieldFor(s.kind) : nullptr;
    const double handScale = std::max(s.scale, 1e-6);
    const double fieldError = hand ? handScale * field->error : 0.0;  // cm
    auto localAt = [&](int v, int u) {
      const double x = m_tableX.at<float>(v, u) - s.pose.pos.x();
      const double y = m_tableY.at<float>(v, u) - s.pose.pos.y();
      return Vec2(cosA * x + sinA * y, -sinA * x + cosA * y);
    };
    auto exactAt = [&](const Vec2& local) {
      if (handModel) return handScale * HandDistanceUnscaled(*handModel, local / handScale);
      return LocalDistance(s, &polygon, local);
    };
    // a table point's place on a hand field's grid: g = G (t - pos) + g0, G the inverse rotation
    // over scale times spacing (one affine map a pixel, no division)
    const double toGrid = hand ? 1.0 / (handScale * HandField::kSpacing) : 0.0;
    const double gxx = toGrid * cosA, gxy = toGrid * sinA;
    const Vec2 g0 = hand ? Vec2(-field->origin / HandField::kSpacing) : Vec2::Zero();
    // a hand's distance from its sampled field, within `error` cm of the exact one; the exact
    // distance (error 0) where the pixel is off the field's grid, and for other shapes
    auto distanceAt = [&](int v, int u, double& error) {
      if (field) {
        const double x = m_tableX.at<float>(v, u) - s.pose.pos.x();
        const double y = m_tableY.at<float>(v, u) - s.pose.pos.y();
        double d;
        if (field->Sample(gxx * x + gxy * y + g0.x(), gxx * y - gxy * x + g0.y(), d)) {
          error = fieldError;
          return handScale * d;
        }
      }
      error = 0.0;
      return exactAt(localAt(v, u));
    };
    const double haloInverse = haloReach > 0.0 ? 1.0 / haloReach : 0.0;
    auto shadeAt = [&](int v, int u, double d) {
      const double coverage =
          std::clamp(0.5 - d / m_cmPerPixel.at<float>(v, u), 0.0, 1.0) * pressure;
      float& c = contact.at<float>(v, u);
      c = std::max(c, static_cast<float>(coverage));
      if (haloReach > 0.0) {
        const double glow = d <= 0.0 ? 1.0 : 1.0 - SmoothStep(d * haloInverse);
        float& hl = halo.at<float>(v, u);
        hl = std::max(hl, static_cast<float>(glow));
      }
    };
    // full coverage and halo: a pixel inside the outline by more than half a pixel
    auto fillAt = [&](int v, int u) {
      float& c = contact.at<float>(v, u);
      c = std::max(c, static_cast<float>(pressure));
      if (haloReach > 0.0) halo.at<float>(v, u) = 1.0f;
    };
    // the halo alone at d > 0 cm outside the outline
    auto glowAt = [&](int v, int u, double d) {
      float& hl = halo.at<float>(v, u);
      hl = std::max(hl, static_cast<float>(1.0 - SmoothStep(d * haloInverse)));
    };
    // Coverage is exact. A distance more than half a pixel (plus the sampled distance's error)
    // outside the outline gives coverage 0, and a halo only nearer than halo_width (smoothstep is 1
    // from 1 on). More than half a pixel inside it gives full coverage and a halo of 1, whatever
    // the exact distance. Only the halo outside comes from the sampled distance; nearer the outline
    // than half a pixel plus the error the exact distance is taken.
    auto shade = [&](int v, int u) {
      double error;
      const double d = distanceAt(v, u, error);
      const double half = 0.5 * m_cmPerPixel.at<float>(v, u);
      if (d - error > half) {
        if (d < haloReach) glowAt(v, u, d);
        return;
      }
      if (d + error < -half) {
        fillAt(v, u);
        return;
      }
      shadeAt(v, u, error == 0.0 ? d : exactAt(localAt(v, u)));
    };
    // Four pixels u .. u + 3 of row v of a hand, in float, four at a time: the same decisions
    // as shade, with the float arithmetic's own error (under 1e-4 cm) added to the field's.
    auto shade4 = [&](int v, int u) {
#if CV_SIMD128
      const cv::v_float32x4 x = cv::v_load(m_tableX.ptr<float>(v) + u) -
                                cv::v_setall_f32(static_cast<float>(s.pose.pos.x()));
      const cv::v_float32x4 y = cv::v_load(m_tableY.ptr<float>(v) + u) -
                                cv::v_setall_f32(static_cast<float>(s.pose.pos.y()));
      const cv::v_float32x4 cxx = cv::v_setall_f32(static_cast<float>(gxx));
      const cv::v_float32x4 cxy = cv::v_setall_f32(static_cast<float>(gxy));
      const cv::v_float32x4 gx = cxx * x + cxy * y + cv::v_setall_f32(static_cast<float>(g0.x()));
      const cv::v_float32x4 gy = cxx * y - cxy * x + cv::v_setall_f32(static_cast<float>(g0.y()));
      const cv::v_float32x4 zero = cv::v_setzero_f32();
      const cv::v_float32x4 onGrid = (gx >= zero) & (gy >= zero) &
                                     (gx < cv::v_setall_f32(static_cast<float>(field->cols - 1))) &
                                     (gy < cv::v_setall_f32(static_cast<float>(field->rows - 1)));
      // off the grid: sample node (0, 0) instead, and leave the pixel to shade
      const cv::v_float32x4 sx = cv::v_select(onGrid, gx, zero);
      const cv::v_float32x4 sy = cv::v_select(onGrid, gy, zero);
      const cv::v_int32x4 ci = cv::v_floor(sx), ri = cv::v_floor(sy);
      const cv::v_float32x4 fx = sx - cv::v_cvt_f32(ci), fy = sy - cv::v_cvt_f32(ri);
      alignas(16) int cs[4], rs[4], index[4];
      cv::v_store_aligned(cs, ci);
      cv::v_store_aligned(rs, ri);
      for (int k = 0; k < 4; ++k) index[k] = rs[k] * field->cols + cs[k];
      const float* values = field->values.data();
      const cv::v_float32x4 a0 = cv::v_lut(values, index), a1 = cv::v_lut(values + 1, index);
      const cv::v_float32x4 b0 = cv::v_lut(values + field->cols, index);
      const cv::v_float32x4 b1 = cv::v_lut(values + field->cols + 1, index);
      const cv::v_float32x4 one = cv::v_setall_f32(1.0f);
      const cv::v_float32x4 d =
          cv::v_setall_f32(static_cast<float>(handScale)) *
          ((one - fy) * ((one - fx) * a0 + fx * a1) + fy * ((one - fx) * b0 + fx * b1));
      const cv::v_float32x4 error = cv::v_setall_f32(static_cast<float>(fieldError + 1e-4));
      const cv::v_float32x4 half =
          cv::v_setall_f32(0.5f) * cv::v_load(m_cmPerPixel.ptr<float>(v) + u);
      const cv::v_float32x4 outside = onGrid & (d - error > half);
      const cv::v_float32x4 inside = onGrid & (d + error < zero - half);
      float* c = contact.ptr<float>(v) + u;
      cv::v_store(
          c, cv::v_max(cv::v_load(c),
                       cv::v_select(inside, cv::v_setall_f32(static_cast<float>(pressure)), zero)));
      if (haloReach > 0.0) {
        const cv::v_float32x4 t =
            cv::v_min(d * cv::v_setall_f32(static_cast<float>(haloInverse)), one);
        const cv::v_float32x4 glow = one - t * t * (cv::v_setall_f32(3.0f) - t - t);
        float* hl = halo.ptr<float>(v) + u;
        cv::v_store(hl, cv::v_max(cv::v_load(hl),
                                  cv::v_select(inside, one, cv::v_select(outside, glow, zero))));
      }
      // the rest (off the grid or near the outline) from the exact distance
      const int decided = cv::v_signmask(outside | inside);
      for (int k = 0; k < 4; ++k)
        if (!(decided & (1 << k))) shadeAt(v, u + k, exactAt(localAt(v, u + k)));
#else
      for (int k = 0; k < 4; ++k) shade(v, u + k);
#endif
    };
    // Within a block of n x n px the distance changes by at most L * 0.71 n px from its centre;
    // 1.5 n px allows L up to 2.1 (round unions have L <= sqrt(2)) and the local scale changing
    // across the block. A block far outside (nothing to draw) or deep inside (filled), with the
    // sampled distance's error on the safe side, is decided at once; an 8 px block left undecided
    // is tried again as four 4 px blocks, which narrows the bands along the outline where every
    // pixel is shaded.
    enum BlockCode : uint8_t { kSkip, kFill, kShade };
    auto classify = [&](int bu, int bv, int buEnd, int bvEnd, int n) {
      const int cv = (bv + bvEnd) / 2, cu = (bu + buEnd) / 2;
      const double cmpp = m_cmPerPixel.at<float>(cv, cu);
      double error;
      const double dc = distanceAt(cv, cu, error);
      const double reach = 1.5 * n * cmpp;
      if (dc - error > reach + haloReach + cmpp) return kSkip;
      if (dc + error < -reach - cmpp) return kFill;
      return kShade;
    };
    constexpr int kBlock = 8, kSubBlock = 4;  // px
    const int blockCols = (uEnd - uBegin) / kSubBlock + 1;
    const int blockRows = (vEnd - vBegin) / kSubBlock + 1;
    std::vector<uint8_t>& codes = scratch.blockCodes;
    codes.assign(static_cast<size_t>(blockCols) * blockRows, kSkip);
    for (int bv = vBegin; bv <= vEnd; bv += kBlock) {
      const int bvEnd = std::min(bv + kBlock - 1, vEnd);
      for (int bu = uBegin; bu <= uEnd; bu += kBlock) {
        const int buEnd = std::min(bu + kBlock - 1, uEnd);
        const BlockCode code = classify(bu, bv, buEnd, bvEnd, kBlock);
        for (int sv = bv; sv <= bvEnd; sv += kSubBlock) {
          const int svEnd = std::min(sv + kSubBlock - 1, bvEnd);
          for (int su = bu; su <= buEnd; su += kSubBlock) {
            const int suEnd = std::min(su + kSubBlock - 1, buEnd);
            codes[static_cast<size_t>((sv - vBegin) / kSubBlock) * blockCols +
                  (su - uBegin) / kSubBlock] =
                code == kShade ? classify(su, sv, suEnd, svEnd, kSubBlock) : code;
          }
        }
      }
    }
    // then the pixels, row by row in memory order, of the blocks filled or left undecided
    for (int v = vBegin; v <= vEnd; ++v) {
      const uint8_t* rowCodes =
          codes.data() + static_cast<size_t>((v - vBegin) / kSubBlock) * blockCols;
      for (int k = 0; k < blockCols; ++k) {
        if (rowCodes[k] == kSkip) continue;
        const int su = uBegin + k * kSubBlock, suEnd = std::min(su + kSubBlock - 1, uEnd);
        if (rowCodes[k] == kFill) {
          for (int u = su; u <= suEnd; ++u) fillAt(v, u);
        } else if (field && suEnd == su + kSubBlock - 1) {
          shade4(v, su);
        } else {
          for (int u = su; u <= suEnd; ++u) shade(v, u);
        }
      }
    }
  }
  return Compose(contact, halo, scratch.drawn);
}

std::vector<Contour> SyntheticCamera::TrueOutlines(std::span<const ContactShape> shapes) const {
  std::vector<Contour> out;
  out.reserve(shapes.size());
  for (const ContactShape& s : shapes) out.push_back(ShapeOutline(s));
  return out;
}

cv::Mat SyntheticCamera::RenderTableImage(const cv::Mat& tableImage) {
  const int w = m_params.width, h = m_params.height;
  cv::Mat contact = cv::Mat::zeros(h, w, CV_32F);
  if (!tableImage.empty()) {
    // any depth and 1, 3 or 4 channels: grey reflectance in 0..1
    cv::Mat grey;
    if (tableImage.channels() == 3)
      cv::cvtColor(tableImage, grey, cv::COLOR_BGR2GRAY);
    else if (tableImage.channels() == 4)
      cv::cvtColor(tableImage, grey, cv::COLOR_BGRA2GRAY);
    else
      grey = tableImage.channels() == 1 ? tableImage : cv::Mat::zeros(tableImage.size(), CV_8UC1);
    const double full = grey.depth() == CV_8U                              ? 255.0
                        : grey.depth() == CV_16U                           ? 65535.0
                        : grey.depth() == CV_32F || grey.depth() == CV_64F ? 1.0
                                                                           : 255.0;
    cv::Mat reflectance;
    grey.convertTo(reflectance, CV_32F, 1.0 / full);
    // each camera pixel samples the table image where it looks
    cv::Mat mapX(h, w, CV_32F), mapY(h, w, CV_32F);
    const double sx = reflectance.cols / m_table.width;
    const double sy = reflectance.rows / m_table.height;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        mapX.at<float>(v, u) = static_cast<float>(m_tableX.at<float>(v, u) * sx - 0.5);
        mapY.at<float>(v, u) =
            static_cast<float>((m_table.height - m_tableY.at<float>(v, u)) * sy - 0.5);
      }
    }
    cv::remap(reflectance, contact, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar(0));
  }
  const cv::Rect all(0, 0, w, h);
  return Compose(contact, cv::Mat::zeros(h, w, CV_32F), {&all, 1});
}

cv::Mat SyntheticCamera::Background() const {
  if (m_params.kind == CameraKind::kDepth) return DepthBackground();
  cv::Mat level;
  cv::multiply(m_gain, m_background, level);
  cv::Mat out;
  level.convertTo(out, CV_8UC1);
  return out;
}

bool DemoScene(const std::string& name, int64_t frame, const TableParams& table,
               std::vector<ContactShape>& shapes) {
  shapes.clear();
  // both scenes start with a clear table for a few frames, as a person walking up to it would
  constexpr int64_t kClearFrames = 5;
  constexpr double kFrameRate = 60.0;  // Hz
  const double t = static_cast<double>(frame - kClearFrames) / kFrameRate;
  if (name == "fingers") {
    if (frame < kClearFrames) return true;
    // ten fingertips, five per hand, each tracing its own small ellipse
    for (int i = 0; i < 10; ++i) {
      const int hand = i / 5, k = i % 5;
      const Vec2 home(table.width * (hand == 0 ? 0.3 : 0.7) + (k - 2) * 3.5,
                      table.height * 0.5 + (k == 0 || k == 4 ? -2.0 : 1.0) + (k == 2 ? 1.0 : 0.0));
      const double phase = 0.7 * i;
      ContactShape s;
      s.kind = ShapeKind::kCircle;
      s.radius = 0.75 + 0.05 * k;
      s.pose.pos = home + Vec2(1.2 * std::cos(2.0 * t + phase), 0.8 * std::sin(1.5 * t + phase));
      shapes.push_back(s);
    }
    return true;
  }
  if (name == "hands") {
    if (frame < kClearFrames) return true;
    // two flat hands sliding towards each other and back, turning a little
    for (int i = 0; i < 2; ++i) {
      const double side = i == 0 ? -1.0 : 1.0;
      ContactShape s;
      s.kind = ShapeKind::kHandFlat;
      s.scale = 0.95;
      s.pose.pos = Vec2(table.width * 0.5 + side * (14.0 - 4.0 * std::sin(1.2 * t)),
                        table.height * 0.42 + 2.0 * std::sin(0.8 * t + i));
      s.pose.angle = -side * DegToRad(15.0 + 8.0 * std::sin(0.9 * t));
      shapes.push_back(s);
    }
    return true;
  }
  return false;
}

}  // namespace pg
