#include "proxygrasp/physics/shapes.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace pg {

namespace {

constexpr int kCirclePoints = 32;
// Box2D welds vertices closer than half its linear slop (0.005 cm); keep edges well above that
constexpr double kMinEdge = 0.02;
// a slice circle never shrinks below Box2D's polygon skin, cm
constexpr double kMinSliceRadius = 0.01;

std::string Label(const ObjectSpec& spec) {
  return spec.name.empty() ? std::string("object (unnamed)") : "object '" + spec.name + "'";
}

Error FieldError(const ObjectSpec& spec, const std::string& field, const std::string& what) {
  return MakeError(spec.loc, Label(spec) + ": " + field + " " + what);
}

std::string Num(double v) {
  return FormatDouble(v);
}

Contour CirclePolygon(double r) {
  Contour c(2, kCirclePoints);
  for (int i = 0; i < kCirclePoints; ++i) {
    const double a = 2.0 * kPi * i / kCirclePoints;
    c.col(i) = Vec2(r * std::cos(a), r * std::sin(a));
  }
  return c;
}

Contour BoxPolygon(double sx, double sy) {
  Contour c(2, 4);
  c.col(0) = Vec2(-sx / 2, -sy / 2);
  c.col(1) = Vec2(sx / 2, -sy / 2);
  c.col(2) = Vec2(sx / 2, sy / 2);
  c.col(3) = Vec2(-sx / 2, sy / 2);
  return c;
}

// drops vertices on a straight line between their neighbours
Contour DropCollinear(const Contour& c) {
  std::vector<Vec2> kept;
  const int n = static_cast<int>(c.cols());
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(WrapIndex(i - 1, n));
    const Vec2 b = c.col(i);
    const Vec2 d = c.col(WrapIndex(i + 1, n));
    const double scale = (b - a).norm() * (d - b).norm();
    if (std::abs(Cross(b - a, d - b)) > 1e-9 * std::max(scale, 1e-12)) kept.push_back(b);
  }
  return ToContour(kept);
}

bool IsConvexCcw(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(i), b = c.col((i + 1) % n), d = c.col((i + 2) % n);
    if (Cross(b - a, d - b) < -1e-9) return false;
  }
  return true;
}

bool PointInTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  return Cross(b - a, p - a) >= 0 && Cross(c - b, p - b) >= 0 && Cross(a - c, p - c) >= 0;
}

// the vertex list of a piece as a contour
Contour PieceContour(const Contour& poly, const std::vector<int>& idx) {
  Contour c(2, static_cast<Eigen::Index>(idx.size()));
  for (size_t i = 0; i < idx.size(); ++i) c.col(static_cast<Eigen::Index>(i)) = poly.col(idx[i]);
  return c;
}

// merged index cycle of two pieces sharing the edge a->b in p and b->a in q, or empty
std::vector<int> MergeAcross(const std::vector<int>& p, const std::vector<int>& q) {
  const int np = static_cast<int>(p.size()), nq = static_cast<int>(q.size());
  for (int i = 0; i < np; ++i) {
    const int a = p[i], b = p[(i + 1) % np];
    for (int j = 0; j < nq; ++j) {
      if (q[j] != b || q[(j + 1) % nq] != a) continue;
      // walk p from b around to a, then q from a (exclusive) around to b (exclusive)
      std::vector<int> merged;
      for (int k = 0; k < np; ++k) merged.push_back(p[(i + 1 + k) % np]);
      for (int k = 2; k < nq; ++k) merged.push_back(q[(j + k) % nq]);
      return merged;
    }
  }
  return {};
}

}  // namespace

double ObjectHeight(const ObjectSpec& spec) {
  return spec.shape == ObjectShape::kSphere ? 2.0 * spec.radius : spec.height;
}

MaybeError ValidateObject(const ObjectSpec& spec, const PhysicsParams& params, std::string* field) {
  // every problem names the field it is in
  auto fail = [&](const std::string& key, const std::string& what) {
    if (field) *field = key;
    return FieldError(spec, key, what);
  };
  auto positive = [&](const char* key, double v) -> MaybeError {
    if (!(v > 0) || !std::isfinite(v)) return fail(key, "must be > 0 (got " + Num(v) + ")");
    return std::nullopt;
  };
  auto nonNegative = [&](const char* key, double v) -> MaybeError {
    if (!(v >= 0) || !std::isfinite(v)) {
      return fail(key, "must be >= 0 (got " + Num(v) + ")");
    }
    return std::nullopt;
  };

  // shape dimensions
  MaybeError s;
  switch (spec.shape) {
    case ObjectShape::kBox:
      if ((s = positive("size_x", spec.sizeX)) || (s = positive("size_y", spec.sizeY))) return s;
      break;
    case ObjectShape::kCylinder:
      if ((s = positive("radius", spec.radius))) return s;
      break;
    case ObjectShape::kSphere:
      if ((s = positive("radius", spec.radius)) ||
          (s = nonNegative("patch_radius", spec.patchRadius))) {
        return s;
      }
      if (spec.patchRadius > spec.radius) {
        return fail("patch_radius", "must be at most the radius " + Num(spec.radius) + " (got " +
                                        Num(spec.patchRadius) + ")");
      }
      break;
    case ObjectShape::kFrustum:
      if ((s = positive("radius", spec.radius)) ||
          (s = nonNegative("top_radius", spec.topRadius))) {
        return s;
      }
      break;
    case ObjectShape::kConvexPrism:
    case ObjectShape::kConcavePrism: {
      for (size_t i = 0; i < spec.points.size(); ++i) {
        if (!spec.points[i].allFinite()) {
          return fail("points", "point " + std::to_string(i + 1) + " is not finite");
        }
      }
      // a simple polygon, convex for a convex prism (core/geometry.h)
      if (auto problem = PolygonProblem(spec.points, spec.shape == ObjectShape::kConvexPrism)) {
        return fail("points", *problem);
      }
      // then what Box2D needs: edges well above its vertex welding, some area, no slivers
      const Contour c = ToContour(spec.points);
      const int n = static_cast<int>(c.cols());
      for (int i = 0; i < n; ++i) {
        if ((c.col((i + 1) % n) - c.col(i)).norm() < kMinEdge) {
          return fail("points", "has points " + std::to_string(i + 1) + " and " +
                                    std::to_string((i + 1) % n + 1) + " closer than " +
                                    Num(kMinEdge) + " cm");
        }
      }
      if (std::abs(SignedArea(c)) < 0.01) {
        return fail("points", "outline has no area (" + Num(SignedArea(c)) + " cm^2)");
      }
      const Contour ccw = DropCollinear(MakeCounterClockwise(c));
      for (const Contour& piece : ConvexDecompose(ccw)) {
        if (SignedArea(piece) < 1e-4) {
          return fail("points", "outline has a sliver Box2D cannot simulate");
        }
      }
      break;
    }
  }
  if (spec.shape != ObjectShape::kSphere && (s = positive("height", spec.height))) return s;

  // mass and surface properties
  if (!(spec.mass >= 0) || !std::isfinite(spec.mass)) {
    return fail("mass", "must be >= 0 (got " + Num(spec.mass) + ")");
  }
  if (spec.mass == 0 && (s = positive("density", spec.density))) return s;
  if (spec.particleFriction >= 0 && !std::isfinite(spec.particleFriction)) {
    return fail("particle_friction", "must be finite");
  }
  if ((s = nonNegative("table_static", spec.tableStatic)) ||
      (s = nonNegative("table_kinetic", spec.tableKinetic)) ||
      (s = nonNegative("object_friction", spec.objectFriction)) ||
      (s = nonNegative("restitution", spec.restitution))) {
    return s;
  }
  if (spec.tableKinetic > spec.tableStatic) {
    return fail("table_kinetic", "must be <= table_static (" + Num(spec.tableKinetic) + " > " +
                                     Num(spec.tableStatic) + ")");
  }
  if (spec.restitution > 1) {
    return fail("restitution", "must be <= 1 (got " + Num(spec.restitution) + ")");
  }
  if (!spec.pose.pos.allFinite() || !std::isfinite(spec.pose.angle)) {
    return fail("pose", "must be finite");
  }
  if (!spec.velocity.allFinite() || !std::isfinite(spec.angularVelocity)) {
    return fail("velocity", "must be finite");
  }

  // particles resting on the top need a layer above the object's slices
  const double h = params.layerHeight;
  const double maxHeight = (params.layers - 0.5) * h;
  if (params.layers > 1 && ObjectHeight(spec) > maxHeight) {
    return fail(spec.shape == ObjectShape::kSphere ? "radius" : "height",
                "makes the object " + Num(ObjectHeight(spec)) +
                    " cm tall, too tall for the layer stack: at most " + Num(maxHeight) +
                    " cm with layers = " + std::to_string(params.layers) +
                    " and layer_height = " + Num(h) + " cm, so that particles can rest on its top");
  }
  return std::nullopt;
}

MassProps ComputeMassProps(const ObjectSpec& spec) {
  MassProps m;
  const double H = spec.height;
  double inertiaPerDensity = 0.0;
  switch (spec.shape) {
    case ObjectShape::kBox:
      m.volume = spec.sizeX * spec.sizeY * H;
      inertiaPerDensity = m.volume * (spec.sizeX * spec.sizeX + spec.sizeY * spec.sizeY) / 12.0;
      break;
    case ObjectShape::kCylinder: {
      const double r = spec.radius;
      m.volume = kPi * r * r * H;
      inertiaPerDensity = m.volume * r * r / 2.0;
      break;
    }
    case ObjectShape::kSphere: {
      const double r = spec.radius;
      m.volume = 4.0 / 3.0 * kPi * r * r * r;
      inertiaPerDensity = 0.4 * m.volume * r * r;
      break;
    }
    case ObjectShape::kFrustum: {
      // integral over z of the disc volume and of the disc inertia pi r^4 / 2
      const double R = spec.radius, t = spec.topRadius;
      m.volume = kPi * H / 3.0 * (R * R + R * t + t * t);
      inertiaPerDensity =
          kPi * H / 10.0 *
          (R * R * R * R + R * R * R * t + R * R * t * t + R * t * t * t + t * t * t * t);
      break;
    }
    case ObjectShape::kConvexPrism:
    case ObjectShape::kConcavePrism: {
      const Contour c = MakeCounterClockwise(ToContour(spec.points));
      m.centroid = PolygonCentroid(c);
      m.volume = SignedArea(c) * H;
      inertiaPerDensity = PolygonPolarMoment(c, m.centroid) * H;
      break;
    }
  }
  const double densityMass = spec.density * m.volume;
  m.mass = spec.mass > 0 ? spec.mass : densityMass;
  m.inertia = inertiaPerDensity * (m.mass / m.volume);
  return m;
}

int SliceLayerCount(const ObjectSpec& spec, double layerHeight, int layers) {
  const double H = ObjectHeight(spec);
  int n = 0;
  while (n < layers && (n + 0.5) * layerHeight < H) ++n;
  return std::max(1, n);
}

double SliceHeight(const ObjectSpec& spec, int layer, double layerHeight) {
  const double mid = (layer + 0.5) * layerHeight;
  const double H = ObjectHeight(spec);
  return mid < H ? mid : 0.5 * H;
}

CrossSection SectionAt(const ObjectSpec& spec, double z) {
  CrossSection s;
  auto circle = [&](double r) {
    s.circle = true;
    s.radius = std::max(r, kMinSliceRadius);
    s.outline = CirclePolygon(s.radius);
  };
  switch (spec.shape) {
    case ObjectShape::kBox:
      s.outline = BoxPolygon(spec.sizeX, spec.sizeY);
      s.pieces = {s.outline};
      break;
    case ObjectShape::kCylinder:
      circle(spec.radius);
      break;
    case ObjectShape::kSphere: {
      const double r = spec.radius, dz = z - r;
      circle(std::sqrt(std::max(0.0, r * r - dz * dz)));
      break;
    }
    case ObjectShape::kFrustum: {
      const double t = std::clamp(z / spec.height, 0.0, 1.0);
      circle(Lerp(spec.radius, spec.topRadius, t));
      break;
    }
    case ObjectShape::kConvexPrism:
    case ObjectShape::kConcavePrism:
      s.outline = DropCollinear(MakeCounterClockwise(ToContour(spec.points)));
      s.pieces = ConvexDecompose(s.outline);
      break;
  }
  return s;
}

CrossSection Footprint(const ObjectSpec& spec) {
  switch (spec.shape) {
    case ObjectShape::kSphere:
      return SectionAt(spec, spec.radius);
    case ObjectShape::kFrustum:
      return SectionAt(spec, spec.topRadius > spec.radius ? spec.height : 0.0);
    default:
      return SectionAt(spec, 0.0);
  }
}

std::pair<Vec2, Vec2> FootprintBounds(const ObjectSpec& spec) {
  const CrossSection footprint = Footprint(spec);
  if (footprint.circle) {
    const Vec2 r = Vec2::Constant(footprint.radius);
    return {spec.pose.pos - r, spec.pose.pos + r};
  }
  Vec2 low = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 high = -low;
  for (Eigen::Index i = 0; i < footprint.outline.cols(); ++i) {
    const Vec2 w = spec.pose.Apply(footprint.outline.col(i));
    low = low.cwiseMin(w);
    high = high.cwiseMax(w);
  }
  return {low, high};
}

double SurfaceHeightAt(const ObjectSpec& spec, const Vec2& p) {
  const double d = p.norm();
  switch (spec.shape) {
    case ObjectShape::kBox:
      return std::abs(p.x()) <= spec.sizeX / 2 && std::abs(p.y()) <= spec.sizeY / 2 ? spec.height
                                                                                    : -1.0;
    case ObjectShape::kCylinder:
      return d <= spec.radius ? spec.height : -1.0;
    case ObjectShape::kSphere:
      return d <= spec.radius ? spec.radius + std::sqrt(spec.radius * spec.radius - d * d) : -1.0;
    case ObjectShape::kFrustum: {
      const double R = spec.radius, t = spec.topRadius;
      if (d <= t) return spec.height;
      if (d <= R) return spec.height * (R - d) / (R - t);  // on the slanted side
      return -1.0;
    }
    case ObjectShape::kConvexPrism:
    case ObjectShape::kConcavePrism:
      return PointInPolygon(ToContour(spec.points), p) ? spec.height : -1.0;
  }
  return -1.0;
}

double FootprintSignedDistance(const ObjectSpec& spec, const CrossSection& footprint,
                               const Vec2& p) {
  (void)spec;
  if (footprint.circle) return footprint.radius - p.norm();
  return SignedDistance(footprint.outline, p);
}

Vec2 NearestFootprintPoint(const CrossSection& footprint, const Vec2& p) {
  if (footprint.circle) {
    const double d = p.norm();
    return d > 1e-12 ? Vec2(p * (footprint.radius / d)) : Vec2(footprint.radius, 0.0);
  }
  const Contour& c = footprint.outline;
  const int n = static_cast<int>(c.cols());
  Vec2 best = c.col(0);
  double bestD = 1e300;
  for (int i = 0; i < n; ++i) {
    const Vec2 q = ClosestPointOnSegment(p, c.col(i), c.col((i + 1) % n));
    const double d = (q - p).squaredNorm();
    if (d < bestD) {
      bestD = d;
      best = q;
    }
  }
  return best;
}

double EffectiveFrictionRadius(const ObjectSpec& spec, const Vec2& centroid) {
  switch (spec.shape) {
    case ObjectShape::kSphere:
      // its contact patch, a small disc of uniform pressure like a cylinder's base
      return 2.0 * spec.patchRadius / 3.0;
    case ObjectShape::kCylinder:
    case ObjectShape::kFrustum:
      return 2.0 * spec.radius / 3.0;  // the base disc
    default:
      break;
  }
  // polygonal base: midpoint rule over a fine grid of the bounding box
  const CrossSection base = SectionAt(spec, 0.0);
  const Contour& c = base.outline;
  const Vec2 lo = c.rowwise().minCoeff(), hi = c.rowwise().maxCoeff();
  constexpr int kGrid = 160;
  const Vec2 cell = (hi - lo) / kGrid;
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Vec2 p = lo + Vec2((i + 0.5) * cell.x(), (j + 0.5) * cell.y());
      if (!PointInPolygon(c, p)) continue;
      sum += (p - centroid).norm();
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

std::vector<FrictionPoint> TableFrictionPoints(const ObjectSpec& spec, const Vec2& centroid) {
  std::vector<FrictionPoint> points;
  const double rEff = EffectiveFrictionRadius(spec, centroid);
  const bool round = spec.shape == ObjectShape::kSphere || spec.shape == ObjectShape::kCylinder ||
                     spec.shape == ObjectShape::kFrustum;
  if (round) {
    const double R = spec.shape == ObjectShape::kSphere ? spec.patchRadius : spec.radius;
    if (R <= 0.0) return {FrictionPoint{Vec2::Zero(), 1.0}};
    // rings r1, r2 with (r1 + r2)/2 = 2R/3 and (r1^2 + r2^2)/2 = R^2/2
    const double radii[2] = {(4.0 - std::sqrt(2.0)) / 6.0 * R, (4.0 + std::sqrt(2.0)) / 6.0 * R};
    constexpr int kPerRing = 8;
    for (int ring = 0; ring < 2; ++ring) {
      for (int i = 0; i < kPerRing; ++i) {
        const double a = 2.0 * kPi * (i + 0.5 * ring) / kPerRing;
        points.push_back({radii[ring] * Vec2(std::cos(a), std::sin(a)), 1.0 / (2 * kPerRing)});
      }
    }
    return points;
  }
  // polygonal base: a fine grid of samples gathered into about 16 cells shaped like the base's
  // bounding box
  const Contour& c = SectionAt(spec, 0.0).outline;
  const Vec2 lo = c.rowwise().minCoeff(), hi = c.rowwise().maxCoeff();
  const Vec2 size = hi - lo;
  constexpr int kCells = 16;
  const int nx =
      std::clamp(static_cast<int>(std::lround(std::sqrt(kCells * size.x() / size.y()))), 1, kCells);
  const int ny = std::max(1, static_cast<int>(std::lround(static_cast<double>(kCells) / nx)));
  constexpr int kGrid = 160;
  std::vector<Vec2> sum(static_cast<size_t>(nx * ny), Vec2::Zero());
  std::vector<int> count(static_cast<size_t>(nx * ny), 0);
  int total = 0;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Vec2 p = lo + Vec2((i + 0.5) * size.x() / kGrid, (j + 0.5) * size.y() / kGrid);
      if (!PointInPolygon(c, p)) continue;
      const int cell = (i * nx / kGrid) * ny + j * ny / kGrid;
      sum[cell] += p;
      ++count[cell];
      ++total;
    }
  }
  Vec2 mean = Vec2::Zero();
  for (size_t k = 0; k < sum.size(); ++k) {
    if (count[k] == 0) continue;
    const double w = static_cast<double>(count[k]) / total;
    points.push_back({sum[k] / count[k] - centroid, w});
    mean += w * points.back().arm;
  }
  // exactly balanced about the centroid, and spread so that a pure turn meets mu N r_eff (the
  // cells' centroids lie nearer the centre than their area does)
  double spread = 0.0;
  for (FrictionPoint& p : points) {
    p.arm -= mean;
    spread += p.weight * p.arm.norm();
  }
  if (spread > 0.0) {
    for (FrictionPoint& p : points) p.arm *= rEff / spread;
  }
  return points;
}

std::vector<Contour> ConvexDecompose(const Contour& polygon, int maxVertices) {
  assert(maxVertices >= 3 && "pieces need at least 3 vertices");
  const int n = static_cast<int>(polygon.cols());
  assert(n >= 3 && "a polygon needs at least 3 vertices");
  if (n <= maxVertices && IsConvexCcw(polygon)) return {polygon};

  // ear clipping into triangles (index triples into polygon)
  std::vector<std::vector<int>> pieces;
  std::vector<int> remaining(n);
  for (int i = 0; i < n; ++i) remaining[i] = i;
  while (remaining.size() > 3) {
    const int m = static_cast<int>(remaining.size());
    int ear = -1;
    double bestTurn = -1e300;
    int fallback = 0;
    for (int i = 0; i < m && ear < 0; ++i) {
      const Vec2 a = polygon.col(remaining[WrapIndex(i - 1, m)]);
      const Vec2 b = polygon.col(remaining[i]);
      const Vec2 c = polygon.col(remaining[(i + 1) % m]);
      const double turn = Cross(b - a, c - b);
      if (turn > bestTurn) {
        bestTurn = turn;
        fallback = i;
      }
      if (turn <= 1e-12) continue;
      bool empty = true;
      for (int j = 0; j < m && empty; ++j) {
        if (j == i || j == WrapIndex(i - 1, m) || j == (i + 1) % m) continue;
        const Vec2 p = polygon.col(remaining[j]);
        if (p == a || p == b || p == c) continue;
        empty = !PointInTriangle(p, a, b, c);
      }
      if (empty) ear = i;
    }
    // numerically stuck: clip the most convex corner
    if (ear < 0) ear = fallback;
    pieces.push_back({remaining[WrapIndex(ear - 1, m)], remaining[ear], remaining[(ear + 1) % m]});
    remaining.erase(remaining.begin() + ear);
  }
  pieces.push_back(remaining);

  // merge neighbouring pieces while the union stays convex and small enough
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t i = 0; i < pieces.size() && !merged; ++i) {
      for (size_t j = i + 1; j < pieces.size() && !merged; ++j) {
        std::vector<int> u = MergeAcross(pieces[i], pieces[j]);
        if (u.empty()) continue;
        const Contour uc = DropCollinear(PieceContour(polygon, u));
        if (uc.cols() > maxVertices || !IsConvexCcw(uc)) continue;
        pieces[i] = std::move(u);
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
  std::vector<Contour> out;
  for (const auto& p : pieces) out.push_back(DropCollinear(PieceContour(polygon, p)));
  return out;
}

double PolygonPolarMoment(const Contour& polygon, const Vec2& c) {
  const int n = static_cast<int>(polygon.cols());
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = polygon.col(i) - c, b = polygon.col((i + 1) % n) - c;
    sum += Cross(a, b) * (a.squaredNorm() + a.dot(b) + b.squaredNorm());
  }
  return std::abs(sum) / 12.0;
}

}  // namespace pg
