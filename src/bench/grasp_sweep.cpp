// The grasp sweep: scene generation, the analytic hold rule, running and scoring
// (bench/grasp_sweep.h; the rule's derivation is in docs/physics.md, "Grasp sweep").
#include "proxygrasp/bench/grasp_sweep.h"

#include "proxygrasp/core/rng.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/physics/shapes.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/simulation.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <unordered_map>

namespace pg {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// the scene's timeline, s
constexpr double kApproachTime = 0.5;        // fingers move in from outside the object
constexpr double kMoveStart = 0.9;           // the grip has settled
constexpr double kSettleTime = 0.7;          // after the motion, before the end pose is taken
constexpr double kKeyInterval = 1.0 / 30.0;  // keyframes during motion, s
constexpr double kClearance = 0.6;  // gap kept between contours, and before the approach, cm
constexpr double kPushSpeed = 6.0;  // the pusher's peak speed, cm/s

// scoring (issue 15)
constexpr double kFollowDistance = 1.0;         // cm
constexpr double kFollowAngle = DegToRad(5.0);  // rad
constexpr double kBoundaryBand = 0.2;           // margins within 20% of 1 are not scored
constexpr double kBreakLooseSlip = 0.5;         // cm a grip may slide across before it counts
constexpr double kSpeedFactor = 1.5;            // peak object speed against the contacts
constexpr double kSpeedAllowance = 5.0;         // cm/s

// the centre of the default 61 x 46 cm table
const Vec2 kTableCentre(30.5, 23.0);

// a contact's path: its table-frame centre at time t
struct FingerPath {
  double radius = 0.8;
  double start = 0.0;  // appears, s
  std::vector<std::pair<double, Vec2>> keys;
};

// bang-bang: constant acceleration over the first half, constant deceleration over the second
double BangBang(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  return tau < 0.5 ? 2.0 * tau * tau : 1.0 - 2.0 * (1.0 - tau) * (1.0 - tau);
}

double SmoothStep01(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  return tau * tau * (3.0 - 2.0 * tau);
}

// the layer-0 slice of the object, in which fingertips on the table press
CrossSection Slice0(const ObjectSpec& object, const PhysicsParams& physics) {
  return SectionAt(object, SliceHeight(object, 0, physics.layerHeight));
}

// how far along its motion the grip is at tau (0 .. 1 of the motion's time): bang-bang, or a
// velocity step (constant speed from the first frame to the last)
double Progress(const GraspScene& s, double tau) {
  return s.profile == GraspProfile::kStep ? std::clamp(tau, 0.0, 1.0) : BangBang(tau);
}

// the rigid motion of the grip at time t: the pose that carries the object frame at the start
Pose2 GripMotionAt(const GraspScene& s, double t) {
  const double tau = (t - s.moveStart) / std::max(s.moveEnd - s.moveStart, 1e-9);
  Pose2 m;
  if (s.motion == GraspMotion::kCarry) {
    m.pos = s.direction * (s.distance * Progress(s, tau));
  } else if (s.motion == GraspMotion::kTurn) {
    // about the object's starting position: p -> c + R (p - c)
    const double a = s.turn * Progress(s, tau);
    const Vec2 c = s.object.pose.pos;
    m.angle = a;
    m.pos = c - Rotate(c, a);
  }
  return m;
}

Vec2 ApplyMotion(const Pose2& m, const Vec2& p) {
  return m.pos + Rotate(p, m.angle);
}

// a regular polygon of n sides with circumradius R, one face normal along +x
std::vector<Vec2> RegularPolygon(int n, double circumradius) {
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    const double a = kPi / n + 2.0 * kPi * i / n;
    pts.emplace_back(circumradius * std::cos(a), circumradius * std::sin(a));
  }
  return pts;
}

// distance from the slice's centre to its boundary along the unit direction u (convex slices)
double ReachAlong(const CrossSection& slice, const Vec2& u) {
  if (slice.circle) return slice.radius;
  double best = kInfinity;
  const Contour& c = slice.outline;
  const int n = static_cast<int>(c.cols());
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(i), b = c.col((i + 1) % n);
    const Vec2 e = b - a;
    const Vec2 normal = Vec2(e.y(), -e.x()).normalized();  // outward for counter-clockwise
    const double along = normal.dot(u);
    if (along > 1e-9) best = std::min(best, normal.dot(a) / along);
  }
  return best;
}

// An edge of a counter-clockwise polygon: its start, unit direction, length and outward normal.
struct Edge {
  Vec2 start = Vec2::Zero();
  Vec2 dir = Vec2::Zero();
  double length = 0.0;
  Vec2 normal = Vec2::Zero();
};

// the edge of a polygon slice whose outward normal points most along the unit direction u: the
// face a fingertip pressing along -u meets
Edge FacingEdge(const CrossSection& slice, const Vec2& u) {
  Edge best;
  double bestAlong = -kInfinity;
  const Contour& c = slice.outline;
  const int n = static_cast<int>(c.cols());
  for (int i = 0; i < n; ++i) {
    const Vec2 a = c.col(i), e = Vec2(c.col((i + 1) % n)) - a;
    const Vec2 normal = Vec2(e.y(), -e.x()).normalized();
    if (normal.dot(u) > bestAlong) {
      bestAlong = normal.dot(u);
      best = {a, e.normalized(), e.norm(), normal};
    }
  }
  return best;
}

// half the length of the face the direction u meets (infinity for a circle)
double FaceHalfLength(const CrossSection& slice, const Vec2& u) {
  return slice.circle ? kInfinity : 0.5 * FacingEdge(slice, u).length;
}

// how far the footprint (a sphere's equator) reaches beyond the layer-0 slice the fingers grip,
// along -inward
double Overhang(const ObjectSpec& object, const Vec2& inward) {
  const PhysicsParams physics;
  const CrossSection slice = Slice0(object, physics), footprint = Footprint(object);
  return ReachAlong(footprint, -inward) - ReachAlong(slice, -inward);
}

// where finger i grips at time t (object frame at the start): where it started, or on its slide
// (at constant speed) to where it ends
Vec2 FingerGripAt(const GraspScene& s, size_t i, double t) {
  if (s.fingersAfter.empty()) return s.fingers[i].pos;
  const double span = std::max(s.eventEnd - s.eventStart, 1e-9);
  const double f = std::clamp((t - s.eventStart) / span, 0.0, 1.0);
  return s.fingers[i].pos + (s.fingersAfter[i].pos - s.fingers[i].pos) * f;
}

std::vector<FingerPath> Paths(const GraspScene& s) {
  std::vector<FingerPath> paths;
  const Pose2& pose = s.object.pose;
  for (size_t i = 0; i < s.fingers.size(); ++i) {
    const GraspFinger& f = s.fingers[i];
    FingerPath path;
    path.radius = f.radius;
    const Vec2 grip = pose.Apply(f.pos);
    const Vec2 in = Rotate(f.inward, pose.angle);
    // from outside the footprint: a contact that appears over the object is placed on its top
    const Vec2 from = grip - in * (s.depth + kClearance + Overhang(s.object, f.inward));
    for (double t = 0.0; t < kApproachTime - 1e-9; t += kKeyInterval) {
      path.keys.emplace_back(t, from + (grip - from) * SmoothStep01(t / kApproachTime));
    }
    // after the approach: the grip's rigid motion of where the finger grips (which changes
    // while it slides), at the motion's and the slide's keyframes
    std::vector<double> times = {kApproachTime};
    if (s.motion != GraspMotion::kPush) {
      for (double t = s.moveStart; t < s.moveEnd - 1e-9; t += kKeyInterval) times.push_back(t);
      times.push_back(s.moveEnd);
    }
    if (!s.fingersAfter.empty()) {
      for (double t = s.eventStart; t < s.eventEnd - 1e-9; t += kKeyInterval) times.push_back(t);
      times.push_back(s.eventEnd);
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end(),
                            [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                times.end());
    times.push_back(s.duration);
    for (double t : times) {
      path.keys.emplace_back(t, ApplyMotion(GripMotionAt(s, t), pose.Apply(FingerGripAt(s, i, t))));
    }
    paths.push_back(std::move(path));
  }
  if (s.motion == GraspMotion::kPush) {
    FingerPath path;
    path.radius = s.pusher.radius;
    path.start = s.moveStart;
    const Vec2 at = pose.Apply(s.pusher.pos);
    const Vec2 in = Rotate(s.pusher.inward, pose.angle);
    const Vec2 from = at - in * (s.pushDepth + kClearance + Overhang(s.object, s.pusher.inward));
    for (double t = s.moveStart; t < s.moveEnd - 1e-9; t += kKeyInterval) {
      const double tau = (t - s.moveStart) / (s.moveEnd - s.moveStart);
      const double along = s.profile == GraspProfile::kStep ? tau : SmoothStep01(tau);
      path.keys.emplace_back(t, from + (at - from) * along);
    }
    path.keys.emplace_back(s.moveEnd, at);
    path.keys.emplace_back(s.duration, at);
    paths.push_back(std::move(path));
  }
  return paths;
}

// A fingertip's contour of `radius` has about 2 pi R / spacing samples; where they fall along it
// varies, so the rule averages over kSamplePhases phases of the sampling: each(offset) is called
// with every sample's offset from the fingertip's centre, and sums are divided by kSamplePhases.
constexpr int kSamplePhases = 16;
// A point inside a `hidden` disc (another fingertip whose outline merged with this one) is not
// on the merged outline and is skipped.
template <typename Each>
void ForEachContourSample(double radius, double spacing, std::span<const HiddenDisc> hidden,
                          Each&& each) {
  const int points = std::max(3, static_cast<int>(std::lround(2.0 * kPi * radius / spacing)));
  for (int phase = 0; phase < kSamplePhases; ++phase) {
    for (int i = 0; i < points; ++i) {
      const double a = 2.0 * kPi * (i + static_cast<double>(phase) / kSamplePhases) / points;
      const Vec2 along = radius * Vec2(std::cos(a), std::sin(a));
      bool gone = false;
      for (const HiddenDisc& h : hidden) gone = gone || (along - h.offset).norm() < h.radius;
      if (!gone) each(along);
    }
  }
}

// how far a body's target q lies beyond its centre on a polygon's face (r minus q's height above
// the face), or nothing when q lies beyond the face's ends (a body there meets no face)
std::optional<double> FaceDepth(const Edge& face, const Vec2& q, double r) {
  const double at = (q - face.start).dot(face.dir);
  if (at < 0.0 || at > face.length) return std::nullopt;
  return r - (q - face.start).dot(face.normal);
}

// Where a body on its way in stops on a round slice of radius R: it comes in along `inward` on
// the line through its target at rest, and its centre stops on the circle of radius R + r where
// the line enters it. Nothing when the line misses the slice or the target lies short of it.
std::optional<Vec2> MeetCircle(double sliceRadius, const Vec2& rest, const Vec2& inward, double r) {
  const double reach = sliceRadius + r;
  const double ae = rest.dot(inward);
  const double disc = ae * ae - rest.squaredNorm() + reach * reach;
  if (disc < 0.0) return std::nullopt;  // its path misses the slice
  const double t = ae + std::sqrt(disc);
  if (t < 0.0) return std::nullopt;  // its target lies short of the slice
  return Vec2(rest - t * inward);
}

// What a body on its way in meets on a convex polygon: it comes in along `inward` on the line
// through its target at rest and meets a face, or rounds a corner (within its radius r of a
// vertex). It then presses that face along its inward normal, or that corner along the line from
// where it stopped to the vertex.
struct Meeting {
  bool corner = false;
  Edge face;                   // the face it met
  Vec2 vertex = Vec2::Zero();  // the corner it met
  Vec2 stop = Vec2::Zero();    // its centre where it met the corner
  Vec2 push = Vec2::Zero();    // unit, into the polygon, at the corner
};

std::optional<Meeting> MeetPolygon(const Contour& polygon, const Vec2& rest, const Vec2& inward,
                                   double r) {
  const int n = static_cast<int>(polygon.cols());
  // from far out on the line: origin o, moving along +inward
  double far = 0.0;
  for (int i = 0; i < n; ++i) far = std::max(far, polygon.col(i).norm());
  far = rest.norm() + far + r + 1.0;
  const Vec2 o = rest - far * inward;
  double first = kInfinity;
  Meeting met;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = polygon.col(i), e = Vec2(polygon.col((i + 1) % n)) - a;
    const Edge face{a, e.normalized(), e.norm(), Vec2(e.y(), -e.x()).normalized()};
    const double towards = inward.dot(face.normal);
    if (towards > -1e-12) continue;  // it moves along or away from this face
    const double t = (r - (o - a).dot(face.normal)) / towards;
    const double at = (o + t * inward - a).dot(face.dir);
    if (at < 0.0 || at > face.length || t >= first) continue;
    first = t;
    met = Meeting{};
    met.face = face;
  }
  for (int i = 0; i < n; ++i) {
    const Vec2 v = polygon.col(i), w = o - v;
    const double b = w.dot(inward), disc = b * b - (w.squaredNorm() - r * r);
    if (disc < 0.0) continue;
    const double t = -b - std::sqrt(disc);
    if (t >= first) continue;
    first = t;
    met = Meeting{};
    met.corner = true;
    met.vertex = v;
    met.stop = o + t * inward;
    met.push = (v - met.stop) / r;
  }
  if (first == kInfinity) return std::nullopt;
  return met;
}

// how far a body whose target is now q presses what it met (see FaceDepth), and where on the
// polygon it presses; nothing when it has slid off its face's ends
std::optional<double> MeetingDepth(const Meeting& met, const Vec2& q, double r, Vec2* push,
                                   Vec2* at) {
  if (met.corner) {
    *push = met.push;
    *at = met.vertex;
    return (q - met.stop).dot(met.push);
  }
  const std::optional<double> d = FaceDepth(met.face, q, r);
  *push = -met.face.normal;
  *at = q - (q - met.face.start).dot(met.face.normal) * met.face.normal;
  return d;
}

// A body of a fingertip's contour that came in along `inward` with its target at rest: where it
// stopped (its centre), the normal it presses along, the point of the object it presses, its
// target's depth, and on a polygon what it met.
struct BodyAtRest {
  Vec2 stop = Vec2::Zero(), push = Vec2::Zero(), at = Vec2::Zero();
  double depth = 0.0;
  std::optional<Meeting> met;
};

// nothing when the body meets nothing of the slice
std::optional<BodyAtRest> MeetBody(const CrossSection& slice, const Vec2& rest, const Vec2& inward,
                                   double r) {
  BodyAtRest b;
  if (slice.circle) {
    const double reach = slice.radius + r;
    const std::optional<Vec2> stop = MeetCircle(slice.radius, rest, inward, r);
    if (!stop) return std::nullopt;
    b.stop = *stop;
    b.push = -b.stop / reach;
    b.at = b.stop * (slice.radius / reach);
    b.depth = (rest - b.stop).dot(b.push);
    return b;
  }
  b.met = MeetPolygon(slice.outline, rest, inward, r);
  if (!b.met) return std::nullopt;
  const std::optional<double> d = MeetingDepth(*b.met, rest, r, &b.push, &b.at);
  if (!d) return std::nullopt;
  b.depth = *d;
  b.stop = b.met->corner ? b.met->stop : Vec2(b.at - r * b.push);
  return b;
}

// its target's depth once the target is at q: on a round slice along the normal where it
// stopped, on a polygon as MeetingDepth (`atNow`: where it presses then); nothing when it has
// slid off its face's ends
std::optional<double> DepthNow(const CrossSection& slice, const BodyAtRest& b, const Vec2& q,
                               double r, Vec2* atNow) {
  if (slice.circle) {
    *atNow = b.at;
    return (q - b.stop).dot(b.push);
  }
  Vec2 pushNow;
  return MeetingDepth(*b.met, q, r, &pushNow, atNow);
}

// the most can-hold scenes the sweep keeps (GraspSweepOptions::holdShare of the count)
int HoldQuota(const GraspSweepOptions& options) {
  return static_cast<int>(std::floor(options.holdShare * options.scenes + 1e-9));
}

}  // namespace

Vec2 FingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                    const Vec2& center, double radius, const Vec2& inward,
                    std::span<const HiddenDisc> hidden) {
  return FingertipForce(object, physics, spacing, center, center, radius, inward, nullptr, hidden);
}

Vec2 FingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                    const Vec2& restCenter, const Vec2& center, double radius, const Vec2& inward,
                    double* pressing, std::span<const HiddenDisc> hidden, double slideFriction) {
  const CrossSection slice = Slice0(object, physics);
  const double k = physics.gripStiffness, dMax = physics.gripMaxDepth;
  const double r = physics.particleRadius;
  Vec2 total = Vec2::Zero();
  int bodies = 0;
  ForEachContourSample(radius, spacing, hidden, [&](const Vec2& along) {
    const Vec2 q = center + along;
    double d;  // how far the target lies beyond the body's centre, along the push
    Vec2 push;
    if (slice.circle) {
      // The body came in along `inward` with its target (at rest) and stopped where its circle
      // met the slice's: its centre on the circle of radius R + r, at the line's entry. It
      // presses along the normal there, by its target's depth along that normal.
      const std::optional<Vec2> stop = MeetCircle(slice.radius, restCenter + along, inward, r);
      if (!stop) return;
      push = -*stop / (slice.radius + r);
      d = (q - *stop).dot(push);
    } else {
      // the face it met on its way in (the one `inward` faces, or beyond that face's ends the
      // next face or the corner between them), followed with its target
      const std::optional<Meeting> met = MeetPolygon(slice.outline, restCenter + along, inward, r);
      if (!met) return;
      Vec2 at;
      const std::optional<double> depth = MeetingDepth(*met, q, r, &push, &at);
      if (!depth) return;
      d = *depth;
    }
    if (d > 0.0) {
      const double normal = k * std::min(d, dMax);
      total += push * normal;
      // a body whose target still advances along `inward` slides over the surface by the part
      // of `inward` along it, and its friction drags the object that way
      if (slideFriction > 0.0) {
        const Vec2 slide = inward - inward.dot(push) * push;
        const double length = slide.norm();
        if (length > 1e-9) total += slide * (slideFriction * normal / length);
      }
      ++bodies;
    }
  });
  if (pressing) *pressing = static_cast<double>(bodies) / kSamplePhases;
  return total / kSamplePhases;
}

namespace {

// Where a body pressing a round slice comes to rest when its target moves to `target` (object
// frame, the slice's axis at the origin), from the angle `phi` of its centre on the circle of
// radius rho = R + r. With the target at polar (rho_q, psi) and delta = psi - phi, its spring
// pulls it along the surface by k rho_q sin(delta) and presses it by k min(rho - rho_q
// cos(delta), d_max). It stays while the pull is within mu times the press; beyond, it slides
// towards the target's radial projection (delta -> 0) and stops at the first angle where they
// are equal again.
double SettleOnCircle(double phi, const Vec2& target, double rho, double dMax, double friction) {
  const double rq = target.norm();
  if (!(rq > 1e-12)) return phi;
  double delta = std::remainder(std::atan2(target.y(), target.x()) - phi, 2.0 * kPi);
  auto excess = [&](double a) {  // pull beyond what friction holds at |delta| = a
    const double press = std::min(rho - rq * std::cos(a), dMax);
    if (press <= 0.0) return -1.0;  // not pressing there: nothing pulls it on
    return rq * std::sin(a) - friction * press;
  };
  const double from = std::abs(delta);
  if (excess(from) <= 0.0) return phi;
  // march from |delta| towards 0 to the first angle it holds at, then bisect that interval
  constexpr int kMarch = 64;
  double hi = from, lo = from;
  for (int j = 1; j <= kMarch; ++j) {
    lo = from * (1.0 - static_cast<double>(j) / kMarch);
    if (excess(lo) <= 0.0) break;
    hi = lo;
  }
  for (int j = 0; j < 40; ++j) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) <= 0.0 ? lo : hi) = mid;
  }
  return phi + std::copysign(from - lo, delta);
}

}  // namespace

Vec2 RoundFingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                         const Vec2& restCenter, const Vec2& center, double radius,
                         const Vec2& inward, double friction, std::span<const HiddenDisc> hidden) {
  const CrossSection slice = Slice0(object, physics);
  if (!slice.circle) {
    return FingertipForce(object, physics, spacing, restCenter, center, radius, inward, nullptr,
                          hidden);
  }
  const double k = physics.gripStiffness, dMax = physics.gripMaxDepth;
  const double rho = slice.radius + physics.particleRadius;
  Vec2 total = Vec2::Zero();
  ForEachContourSample(radius, spacing, hidden, [&](const Vec2& along) {
    const Vec2 rest = restCenter + along;
    const std::optional<Vec2> stop = MeetCircle(slice.radius, rest, inward, physics.particleRadius);
    if (!stop) return;
    // where the squeeze left it, then where the move takes it
    double phi = SettleOnCircle(std::atan2(stop->y(), stop->x()), rest, rho, dMax, friction);
    const Vec2 q = center + along;
    phi = SettleOnCircle(phi, q, rho, dMax, friction);
    const Vec2 out(std::cos(phi), std::sin(phi));
    const Vec2 tangent(-out.y(), out.x());
    const Vec2 offset = q - rho * out;
    const double depth = -offset.dot(out);
    if (depth <= 0.0) return;
    const double normal = k * std::min(depth, dMax);
    const double pull = std::clamp(k * offset.dot(tangent), -friction * normal, friction * normal);
    total += -out * normal + tangent * pull;
  });
  return total / kSamplePhases;
}

double GripTurnTorque(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                      const Vec2& center, double radius, const Vec2& inward, double turn,
                      double friction, std::span<const HiddenDisc> hidden,
                      std::optional<double> peak) {
  const CrossSection slice = Slice0(object, physics);
  const double k = physics.gripStiffness, dMax = physics.gripMaxDepth;
  const double r = physics.particleRadius;
  const double c = std::cos(turn), s = std::sin(turn);
  const double top = peak.value_or(turn);
  const double cp = std::cos(top), sp = std::sin(top);
  double torque = 0.0;
  ForEachContourSample(radius, spacing, hidden, [&](const Vec2& along) {
    const Vec2 rest = center + along;
    const Vec2 q(c * rest.x() - s * rest.y(), s * rest.x() + c * rest.y());
    const Vec2 qPeak(cp * rest.x() - sp * rest.y(), sp * rest.x() + cp * rest.y());
    // where the body stopped as it came in (its centre), the normal it presses along, the point
    // of the object it presses and its depth, all with the grip at rest
    const std::optional<BodyAtRest> body = MeetBody(slice, rest, inward, r);
    if (!body || body->depth <= 0.0) return;
    const Vec2& stop = body->stop;
    const Vec2& push = body->push;
    Vec2 at = body->at;
    const double normal = k * std::min(body->depth, dMax);
    // along the surface the body is a spring k towards its target until its friction slides;
    // at rest it has slid until its pull is within the limit (on a round slice the targets lie
    // off the bodies' normals and pull them sideways), and the turn adds to that pull
    const Vec2 tangent(-push.y(), push.x());
    const double limit = friction * normal;
    const double held = std::clamp(k * (rest - stop).dot(tangent), -limit, limit);
    // the turn out to its peak adds to that pull, and the way back from the peak takes from it
    // (a body that slid on the way out holds the pull at its limit there, and springs back
    // elastically from it)
    const double pullPeak = held + k * (qPeak - rest).dot(tangent);
    const double pull = std::clamp(pullPeak, -limit, limit) + k * (q - qPeak).dot(tangent);
    const bool slides = std::abs(pullPeak) > limit || std::abs(pull) > limit;
    torque += Cross(at, tangent) * std::clamp(pull, -limit, limit);
    // its normal force, by its target's depth now: a body that slides follows its target along
    // its face (or stays on its corner); one that sticks presses where it met the object
    Vec2 atNow;
    const std::optional<double> d = DepthNow(slice, *body, q, r, &atNow);
    if (!d) return;
    if (slides) at = atNow;
    if (*d > 0.0) torque += Cross(at, push * (k * std::min(*d, dMax)));
  });
  return torque / kSamplePhases;
}

namespace {

// Where a walk along a curve (a torque by angle, or a force by distance), f(from + direction t)
// for t = 0, h, 2h, ... up to `steps` steps of h = `step`, first reaches `threshold` (sign (f -
// threshold) >= 0), and then where sign (f - kinetic), integrated on from there, reaches
// `energy`: distances t along the walk, infinity for none (the curve linear between its points,
// each crossing solved on its segment).
struct CurveWalk {
  double cross = kInfinity;
  double end = kInfinity;
};
CurveWalk WalkCurve(const std::function<double(double)>& f, double from, double direction,
                    double kStep, int steps, double sign, double threshold, double kinetic,
                    double energy) {
  // where an integral of g over [a, b] (g linear between ga and gb) reaches `need`, as a
  // distance from a (the area is a quadratic in it)
  auto reach = [](double ga, double gb, double need, double width) {
    const double slope = (gb - ga) / width;
    if (std::abs(slope) * width < 1e-12 * (std::abs(ga) + std::abs(gb)) || slope == 0.0)
      return ga > 0.0 ? need / ga : width;
    const double disc = ga * ga + 2.0 * slope * need;
    return disc <= 0.0 ? width : (std::sqrt(disc) - ga) / slope;
  };
  CurveWalk walk;
  double t = 0.0, g = sign * (f(from) - kinetic);
  const double over = sign * (threshold - kinetic);  // g where the curve meets the threshold
  if (g >= over) walk.cross = 0.0;
  double taken = 0.0;
  for (int j = 1; j <= steps; ++j) {
    const double tNext = j * kStep, gNext = sign * (f(from + direction * tNext) - kinetic);
    if (walk.cross == kInfinity) {
      if (gNext < over) {
        t = tNext;
        g = gNext;
        continue;
      }
      walk.cross = tNext - kStep * (gNext - over) / (gNext - g);
      t = walk.cross;
      g = over;
    }
    const double width = tNext - t;
    const double area = 0.5 * (g + gNext) * width;
    if (width > 0.0 && taken + area >= energy) {
      walk.end = t + reach(g, gNext, energy - taken, width);
      return walk;
    }
    taken += area;
    t = tNext;
    g = gNext;
  }
  return walk;
}

}  // namespace

TurnStepLags TurnStepLag(const std::function<double(double)>& loading,
                         const std::function<double(double, double)>& unloading,
                         double staticTorque, double kineticTorque, double inertia, double rate,
                         double maxLag) {
  constexpr double kTurnStep = DegToRad(0.25);
  const int steps = static_cast<int>(std::ceil(maxLag / kTurnStep));
  const double energy = 0.5 * inertia * rate * rate;
  TurnStepLags lags;
  // at rest until the grip's torque reaches static friction; then it catches up, the grip's
  // excess over kinetic friction taking the energy it has relative to the grip
  const CurveWalk out =
      WalkCurve(loading, 0.0, 1.0, kTurnStep, steps, 1.0, staticTorque, kineticTorque, energy);
  lags.breakLoose = out.cross;
  lags.peak = out.end;
  lags.sliding = lags.rest = kInfinity;
  if (lags.peak == kInfinity) return lags;
  // back from the peak to where it slides on with the grip (the torque down to kinetic
  // friction), then on through the stop until the table's kinetic friction less the grip's
  // torque has taken the same energy again
  const double peak = lags.peak;
  const CurveWalk back =
      WalkCurve([&](double lag) { return unloading(peak, lag); }, peak, -1.0, kTurnStep, 4 * steps,
                -1.0, kineticTorque, kineticTorque, energy);
  if (back.cross != kInfinity) lags.sliding = peak - back.cross;
  // past the scan, it runs on past the grip as far as it looks
  lags.rest = back.end == kInfinity ? -kInfinity : peak - back.end;
  return lags;
}

CarryStepLags CarryStepLag(const std::function<double(double)>& loose, double looseReach,
                           const std::function<double(double)>& loading,
                           const std::function<double(double, double)>& unloading,
                           double staticForce, double kineticForce, double mass, double speed,
                           double across, double maxLag) {
  constexpr double kStep = 0.01;  // cm between the curves' points
  const int steps = static_cast<int>(std::ceil(maxLag / kStep));
  CarryStepLags lags;
  lags.breakLoose = lags.peak = lags.sliding = lags.rest = kInfinity;
  const double vs = speed * across;
  const double va = speed * std::sqrt(std::max(0.0, 1.0 - across * across));
  const double energy = 0.5 * mass * vs * vs;
  // at rest until the grip's force reaches static friction, the grip moving on along the motion
  const CurveWalk rest =
      WalkCurve(loose, 0.0, 1.0, kStep, static_cast<int>(std::floor(looseReach / kStep)), 1.0,
                staticForce, 0.0, 0.0);
  if (rest.cross == kInfinity) return lags;
  lags.breakLoose = rest.cross;
  // It catches up across: relative to the grip it comes in at vs - w (w its own speed across,
  // from the energy e = 1/2 M (vs - w)^2 left), the grip's force taking that energy and the
  // table's kinetic friction along the object's velocity (va, w) giving some back (midpoint
  // steps on the curve's points, the first from where it broke loose, the peak solved on its
  // step).
  auto table = [&](double e) {
    const double w = std::max(0.0, vs - std::sqrt(2.0 * std::max(e, 0.0) / mass));
    const double v = std::hypot(va, w);
    return v > 0.0 ? kineticForce * w / v : 0.0;
  };
  const double x0 = lags.breakLoose * across;
  const int first = static_cast<int>(std::floor(x0 / kStep));
  double x = x0, e = energy;
  double h = loading(first * kStep) +
             (x0 / kStep - first) * (loading((first + 1) * kStep) - loading(first * kStep));
  if (e <= 0.0) lags.peak = x;
  for (int j = first + 1; j <= first + steps && lags.peak == kInfinity; ++j) {
    const double xNext = j * kStep, width = xNext - x, hNext = loading(xNext);
    const double eMid = e - 0.5 * width * (h - table(e));
    const double eNext = e - width * (0.5 * (h + hNext) - table(eMid));
    if (eNext <= 0.0) lags.peak = x + width * e / (e - eNext);
    x = xNext;
    h = hNext;
    e = eNext;
  }
  if (lags.peak == kInfinity) return lags;
  // Back from the peak to where it slides on with the grip (at the grip's velocity, the table's
  // friction along the motion: its part across is mu_k W sin), then on through the stop, where
  // the axis stops first and the table's whole kinetic friction less the grip's force takes the
  // energy across again.
  const double peak = lags.peak;
  const CurveWalk back =
      WalkCurve([&](double lag) { return unloading(peak, lag); }, peak, -1.0, kStep, 2 * steps,
                -1.0, kineticForce * across, kineticForce, energy);
  if (back.cross == kInfinity) return lags;  // the grip pulls it on faster than friction
  lags.sliding = peak - back.cross;
  // past the walk, it runs on past the grip as far as it looks
  lags.rest = back.end == kInfinity ? -kInfinity : peak - back.end;
  return lags;
}

Vec2 GripSlideFriction(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                       const Vec2& restCenter, const Vec2& center, double radius,
                       const Vec2& inward, const Vec2& slide, double friction,
                       std::span<const HiddenDisc> hidden, std::optional<Vec2> peakSlide) {
  const CrossSection slice = Slice0(object, physics);
  const Vec2 top = peakSlide.value_or(slide);
  const double k = physics.gripStiffness, dMax = physics.gripMaxDepth;
  const double r = physics.particleRadius;
  Vec2 total = Vec2::Zero();
  ForEachContourSample(radius, spacing, hidden, [&](const Vec2& along) {
    const Vec2 rest = restCenter + along;
    const Vec2 q = center + along;
    // where the body stopped as it came in, and the normal it presses along (as GripTurnTorque)
    const std::optional<BodyAtRest> body = MeetBody(slice, rest, inward, r);
    if (!body || body->depth <= 0.0) return;
    // its friction limit, by its target's depth now
    Vec2 atNow;
    const std::optional<double> d = DepthNow(slice, *body, q, r, &atNow);
    if (!d || *d <= 0.0) return;
    const double limit = friction * k * std::min(*d, dMax);
    // at rest the body has slid until its pull along the surface is within its limit (targets
    // that lie off its normal pull it sideways); the move adds to that pull until it slides
    const Vec2 tangent(-body->push.y(), body->push.x());
    const double atRest = friction * k * std::min(body->depth, dMax);
    const double held = std::clamp(k * (rest - body->stop).dot(tangent), -atRest, atRest);
    // out to the peak, and back from the limit the body slid at there
    const double pullPeak = std::clamp(held + k * (q - rest + top).dot(tangent), -limit, limit);
    total += tangent * std::clamp(pullPeak + k * (slide - top).dot(tangent), -limit, limit);
  });
  return total / kSamplePhases;
}

namespace {
GraspShape DrawShape(Rng& rng);
void DrawObject(Rng& rng, GraspScene& s, double sizeLo, double sizeHi);
}  // namespace

GraspScene GenerateGraspScene(uint64_t seed, int index) {
  // each scene its own stream, so that a scene does not depend on the ones before it
  Rng rng(seed * 1000003ULL + static_cast<uint64_t>(index) * 7919ULL + 17ULL);
  GraspScene s;
  s.index = index;
  s.seed = seed;
  const PhysicsParams physics;
  ObjectSpec& o = s.object;
  o.name = "object";

  s.shape = DrawShape(rng);
  // size 2 to 12 cm: the width of a box, the diameter of a round one
  DrawObject(rng, s, 2.0, 12.0);
  o.mass = rng.Uniform(20.0, 300.0);
  o.tableStatic = rng.Uniform(0.2, 0.8);
  o.tableKinetic = o.tableStatic * rng.Uniform(0.6, 0.9);
  // from slippery (the paper's soap) to rubbery, evenly on a log scale
  o.particleFriction = std::exp(rng.Uniform(std::log(0.05), std::log(1.2)));
  o.pose.angle = rng.Uniform(0.0, 2.0 * kPi);

  const CrossSection slice = Slice0(o, physics);
  const double fingerRadius = rng.Uniform(0.6, 1.0);
  s.depth = rng.Uniform(0.1, 1.5);

  // the grip: opposed on two parallel faces, or three fingertips at 120 degrees
  const bool parallelFaces = s.shape == GraspShape::kBox || s.shape == GraspShape::kHexagon;
  const bool round = s.shape == GraspShape::kCylinder || s.shape == GraspShape::kSphere;
  s.grip = s.shape == GraspShape::kTriangle || (round && rng.Uniform() < 0.4) ? GraspGrip::kCaged
                                                                              : GraspGrip::kOpposed;
  Vec2 axis = Vec2::UnitX();  // local: the far finger (thumb) presses along +axis
  if (s.shape == GraspShape::kBox && rng.Uniform() < 0.5) axis = Vec2::UnitY();
  if (s.shape == GraspShape::kHexagon) {
    // a face normal of the hexagon (faces at 0, 60, 120 degrees)
    const double a = kPi / 3.0 * std::floor(rng.Uniform(0.0, 3.0));
    axis = Vec2(std::cos(a), std::sin(a));
  }
  if (s.grip == GraspGrip::kCaged) {
    const double a0 = s.shape == GraspShape::kTriangle ? 0.0 : rng.Uniform(0.0, 2.0 * kPi);
    const double maxDepth = 0.5 * std::sqrt(3.0) * ReachAlong(slice, Vec2::UnitX()) - kClearance;
    s.depth = std::min(s.depth, std::max(0.1, maxDepth));
    for (int i = 0; i < 3; ++i) {
      const double a = a0 + 2.0 * kPi * i / 3.0;
      const Vec2 out(std::cos(a), std::sin(a));
      GraspFinger f;
      f.radius = fingerRadius;
      f.inward = -out;
      f.pos = out * (ReachAlong(slice, out) + fingerRadius - s.depth);
      s.fingers.push_back(f);
    }
  } else {
    const double half = ReachAlong(slice, axis);
    // the two sides' contours keep kClearance apart
    s.depth = std::min(s.depth, std::max(0.1, half - 0.5 * kClearance));
    // a thumb on the far side; one, two or three fingers side by side on the near one (a hand)
    int nearCount = 1;
    const double u = rng.Uniform();
    if (parallelFaces) nearCount = u < 0.6 ? 1 : u < 0.85 ? 2 : 3;
    const double pitch = 2.0 * fingerRadius + kClearance;
    const double faceHalf = FaceHalfLength(slice, -axis);
    while (nearCount > 1 && nearCount * pitch > 2.0 * faceHalf) --nearCount;
    const Vec2 side(-axis.y(), axis.x());
    GraspFinger thumb;
    thumb.radius = fingerRadius;
    thumb.inward = axis;
    thumb.pos = -axis * (half + fingerRadius - s.depth);
    s.fingers.push_back(thumb);
    for (int i = 0; i < nearCount; ++i) {
      GraspFinger f;
      f.radius = fingerRadius;
      f.inward = -axis;
      f.pos = axis * (half + fingerRadius - s.depth) + side * ((i - 0.5 * (nearCount - 1)) * pitch);
      s.fingers.push_back(f);
    }
  }

  // the motion
  const double m = rng.Uniform();
  s.motion = m < 0.45 ? GraspMotion::kCarry : m < 0.8 ? GraspMotion::kTurn : GraspMotion::kPush;
  if (s.motion == GraspMotion::kPush) {
    // only across a grip of one finger on each side, from the middle of a face across the axis
    bool fits = s.grip == GraspGrip::kOpposed && s.fingers.size() == 2;
    if (fits) {
      const Vec2 across(-axis.y(), axis.x());
      const double reach = ReachAlong(slice, -across);
      GraspFinger& p = s.pusher;
      p.radius = rng.Uniform(0.6, 1.0);
      p.inward = across;
      s.pushDepth = rng.Uniform(1.5, 2.5);
      // its contour stays kClearance from the gripping ones, and within its face
      const double faceHalf = FaceHalfLength(slice, -across);
      fits = p.radius + physics.particleRadius < faceHalf;
      for (; fits && s.pushDepth >= 1.5; s.pushDepth -= 0.05) {
        p.pos = -across * (reach + p.radius - s.pushDepth);
        bool clear = true;
        for (const GraspFinger& f : s.fingers) {
          clear = clear && (p.pos - f.pos).norm() >= p.radius + f.radius + kClearance;
        }
        if (clear) break;
      }
      fits = fits && s.pushDepth >= 1.5;
    }
    if (!fits) s.motion = GraspMotion::kCarry;
  }
  s.moveStart = kMoveStart;
  if (s.motion == GraspMotion::kCarry) {
    const double a = rng.Uniform(0.0, 2.0 * kPi);
    s.direction = Vec2(std::cos(a), std::sin(a));
    s.distance = rng.Uniform(8.0, 14.0);
    s.speed = rng.Uniform(5.0, 30.0);
    s.moveEnd = s.moveStart + 2.0 * s.distance / s.speed;  // bang-bang: peak speed 2 D / T
    o.pose.pos = kTableCentre - s.direction * (0.5 * s.distance);
  } else if (s.motion == GraspMotion::kTurn) {
    s.turn = DegToRad(rng.Uniform(60.0, 180.0)) * (rng.Uniform() < 0.5 ? -1.0 : 1.0);
    s.turnRate = DegToRad(rng.Uniform(30.0, 120.0));
    s.moveEnd = s.moveStart + 2.0 * std::abs(s.turn) / s.turnRate;
    o.pose.pos = kTableCentre;
  } else {
    s.moveEnd = s.moveStart + 1.5 * (s.pushDepth + kClearance) / kPushSpeed;
    o.pose.pos = kTableCentre;
  }
  s.duration = s.moveEnd + kSettleTime;
  return s;
}

GraspClasses GraspClasses::Legacy() {
  GraspClasses c;
  for (int i = 1; i < kGraspTopologyCount; ++i) c.topology[i] = false;
  c.step = false;
  return c;
}

bool GraspClasses::IsLegacy() const {
  for (int i = 1; i < kGraspTopologyCount; ++i) {
    if (topology[i]) return false;
  }
  return topology[0] && bangBang && !step;
}

Result<GraspClasses> ParseGraspClasses(const std::string& list) {
  if (list.empty() || list == "all") return GraspClasses{};
  if (list == "legacy") return GraspClasses::Legacy();
  GraspClasses c;
  for (bool& t : c.topology) t = false;
  c.bangBang = c.step = false;
  bool anyTopology = false, anyProfile = false;
  std::istringstream names(list);
  for (std::string name; std::getline(names, name, ',');) {
    bool known = false;
    for (int i = 0; i < kGraspTopologyCount; ++i) {
      if (name == kGraspTopologyNames[i]) known = anyTopology = c.topology[i] = true;
    }
    if (name == "bang-bang") known = anyProfile = c.bangBang = true;
    if (name == "step") known = anyProfile = c.step = true;
    if (!known) {
      return MakeError({}, "--classes: unknown class '" + name +
                               "' (all, legacy, or a list of none, merged, merge, split, "
                               "bang-bang, step)");
    }
  }
  if (!anyTopology) {
    for (bool& t : c.topology) t = true;
  }
  if (!anyProfile) c.bangBang = c.step = true;
  return c;
}

const char* GraspEventPhase(const GraspScene& s) {
  if (s.fingersAfter.empty()) return "";
  if (s.eventEnd <= s.moveStart + 1e-9) return "before";
  if (s.eventStart >= s.moveEnd - 1e-9) return "after";
  return "during";
}

namespace {

// the share of each topology among the classes drawn, and of steps among the profiles
constexpr double kTopologyWeights[kGraspTopologyCount] = {0.4, 0.2, 0.2, 0.2};
constexpr double kStepShare = 0.4;
constexpr double kStepMaxSpeed = 15.0;  // cm/s, a carry's step
constexpr double kEventTimeMin = 0.15;  // s a slide together or apart lasts, at least
constexpr double kEventTimeMax = 0.3;   // s, at most

// times the motion for its profile: a bang-bang motion's peak speed is twice its mean, a step's
// speed is its mean
void TimeMotion(GraspScene& s) {
  const double factor = s.profile == GraspProfile::kStep ? 1.0 : 2.0;
  if (s.motion == GraspMotion::kCarry) {
    s.moveEnd = s.moveStart + factor * s.distance / s.speed;
  } else if (s.motion == GraspMotion::kTurn) {
    s.moveEnd = s.moveStart + factor * std::abs(s.turn) / s.turnRate;
  } else if (s.profile == GraspProfile::kStep) {
    // the pusher comes in at its speed from outside the footprint
    const double way = s.pushDepth + kClearance + Overhang(s.object, s.pusher.inward);
    s.moveEnd = s.moveStart + way / kPushSpeed;
  } else {
    s.moveEnd = s.moveStart + 1.5 * (s.pushDepth + kClearance) / kPushSpeed;
  }
  s.duration = s.moveEnd + kSettleTime;
}

// the shape of a scene's object: box 35%, cylinder 20%, sphere 15%, triangle 10%, hexagon 20%
GraspShape DrawShape(Rng& rng) {
  const double pick = rng.Uniform();
  return pick < 0.35   ? GraspShape::kBox
         : pick < 0.55 ? GraspShape::kCylinder
         : pick < 0.70 ? GraspShape::kSphere
         : pick < 0.80 ? GraspShape::kTriangle
                       : GraspShape::kHexagon;
}

// the object of a scene: shape and size drawn as the sweep before issue 42 draws them
void DrawObject(Rng& rng, GraspScene& s, double sizeLo, double sizeHi) {
  ObjectSpec& o = s.object;
  o.points.clear();
  const double size = rng.Uniform(sizeLo, sizeHi);
  const double height = rng.Uniform(1.0, 4.0);
  switch (s.shape) {
    case GraspShape::kBox:
      o.shape = ObjectShape::kBox;
      o.sizeX = size;
      o.sizeY = std::clamp(size * rng.Uniform(0.5, 1.5), 2.0, 12.0);
      o.height = height;
      break;
    case GraspShape::kCylinder:
      o.shape = ObjectShape::kCylinder;
      o.radius = 0.5 * size;
      o.height = height;
      break;
    case GraspShape::kSphere:
      o.shape = ObjectShape::kSphere;
      o.radius = 0.5 * (2.0 + 0.5 * (size - 2.0));
      break;
    case GraspShape::kTriangle:
    case GraspShape::kHexagon:
      o.shape = ObjectShape::kConvexPrism;
      o.height = height;
      for (const Vec2& p : RegularPolygon(s.shape == GraspShape::kTriangle ? 3 : 6, 0.5 * size)) {
        o.points.push_back(p);
      }
      break;
  }
}

// whether every two fingertips of `fingers` (and `more`) that are not both in `group` (the first
// `group` fingers) keep kClearance between their contours
bool KeepClear(const std::vector<GraspFinger>& fingers, size_t group) {
  for (size_t i = 0; i < fingers.size(); ++i) {
    for (size_t j = i + 1; j < fingers.size(); ++j) {
      if (i < group && j < group) continue;
      const double apart = (fingers[i].pos - fingers[j].pos).norm();
      if (apart < fingers[i].radius + fingers[j].radius + kClearance - 1e-9) return false;
    }
  }
  return true;
}

// A scene of a topology other than none (issue 42): two or three fingertips side by side on one
// face against a thumb (or, on a triangle, against a fingertip on each other face) that touch from
// the start, slide together or slide apart; or a pinch whose third finger pushes until its outline
// merges with the pinch's.
// Nothing when no object of the shape drawn takes the fingers (the caller draws a scene of
// topology none instead).
std::optional<GraspScene> GenerateTopologyScene(Rng& rng, uint64_t seed, int index,
                                                GraspTopology topology, GraspProfile profile,
                                                bool mayPush = true) {
  GraspScene s;
  s.index = index;
  s.seed = seed;
  s.topology = topology;
  s.profile = profile;
  const PhysicsParams physics;
  ObjectSpec& o = s.object;
  o.name = "object";
  s.shape = DrawShape(rng);
  o.mass = rng.Uniform(20.0, 300.0);
  o.tableStatic = rng.Uniform(0.2, 0.8);
  o.tableKinetic = o.tableStatic * rng.Uniform(0.6, 0.9);
  o.particleFriction = std::exp(rng.Uniform(std::log(0.05), std::log(1.2)));
  o.pose.angle = rng.Uniform(0.0, 2.0 * kPi);
  const double fingerRadius = rng.Uniform(0.6, 1.0);
  const double drawnDepth = rng.Uniform(0.1, 1.5);
  // touching contours reach `overlap` into each other; contours apart keep `gap` between them
  const double overlap = rng.Uniform(0.1, 0.5) * fingerRadius;
  const double gap = rng.Uniform(kClearance, kClearance + 0.6);
  const double touchPitch = 2.0 * fingerRadius - overlap;
  const double apartPitch = 2.0 * fingerRadius + gap;
  const double m = rng.Uniform();
  // a merging third finger pushes across a pinch: not on a triangle, which is caged
  if (topology == GraspTopology::kMerge && mayPush && s.shape != GraspShape::kTriangle) {
    s.motion = m < 0.2 ? GraspMotion::kPush : m < 0.65 ? GraspMotion::kCarry : GraspMotion::kTurn;
  } else if (topology == GraspTopology::kMerge) {
    s.motion = m < 0.65 ? GraspMotion::kCarry : GraspMotion::kTurn;
  } else {
    s.motion = m < 0.56 ? GraspMotion::kCarry : GraspMotion::kTurn;
  }
  const bool parallelFaces = s.shape == GraspShape::kBox || s.shape == GraspShape::kHexagon;
  int nearCount = s.motion == GraspMotion::kPush ? 1 : 2;
  if (topology == GraspTopology::kMerged && parallelFaces && rng.Uniform() < 0.25) nearCount = 3;
  const double pushRadius = rng.Uniform(0.6, 1.0);
  const double pushOverlap = rng.Uniform(0.1, 0.4), pushDepthDrawn = rng.Uniform(1.5, 2.5);
  const double axisPick = rng.Uniform();

  // the pitches of the side-by-side fingertips before and after their slide
  const double pitchStart = topology == GraspTopology::kMerge ? apartPitch : touchPitch;
  const double pitchEnd = topology == GraspTopology::kSplit ? apartPitch : touchPitch;
  const double widest = std::max(pitchStart, pitchEnd);
  bool placed = false;
  for (int attempt = 0; attempt < 100 && !placed; ++attempt) {
    // small objects for a merging pusher: it reaches the pinch's contours only there
    const bool pushing = s.motion == GraspMotion::kPush;
    DrawObject(rng, s, attempt >= 80 && !pushing ? 12.0 : 2.0, pushing ? 4.0 : 12.0);
    const double depthDrawn = pushing ? rng.Uniform(0.1, 1.5) : drawnDepth;
    const CrossSection slice = Slice0(o, physics);
    s.fingers.clear();
    s.fingersAfter.clear();
    auto makeFinger = [&](const Vec2& pos, const Vec2& inward) {
      GraspFinger f;
      f.radius = fingerRadius;
      f.pos = pos;
      f.inward = inward;
      return f;
    };
    if (s.shape == GraspShape::kTriangle) {
      // caged: two fingertips side by side on the face whose normal is +x, one on each other face
      s.grip = GraspGrip::kCaged;
      const double reach = ReachAlong(slice, Vec2::UnitX());
      if (widest + 2.0 * fingerRadius + kClearance > 2.0 * FaceHalfLength(slice, Vec2::UnitX())) {
        continue;
      }
      auto place = [&](double depth, double pitch) {
        std::vector<GraspFinger> f;
        for (int i = 0; i < 3; ++i) {
          const double a = 2.0 * kPi * i / 3.0;
          const Vec2 out(std::cos(a), std::sin(a));
          const Vec2 at = out * (reach + fingerRadius - depth);
          if (i == 0) {
            for (double side : {-0.5, 0.5}) {
              f.push_back(makeFinger(at + Vec2(-out.y(), out.x()) * (side * pitch), -out));
            }
          } else {
            f.push_back(makeFinger(at, -out));
          }
        }
        return f;
      };
      s.depth = std::min(depthDrawn, std::max(0.1, 0.5 * std::sqrt(3.0) * reach - kClearance));
      for (; s.depth >= 0.1; s.depth -= 0.05) {
        if (KeepClear(place(s.depth, pitchStart), 2) && KeepClear(place(s.depth, pitchEnd), 2)) {
          break;
        }
      }
      if (s.depth < 0.1) continue;
      s.fingers = place(s.depth, pitchStart);
      if (topology == GraspTopology::kMerge || topology == GraspTopology::kSplit) {
        s.fingersAfter = place(s.depth, pitchEnd);
      }
      placed = true;
      continue;
    }
    // opposed: a thumb on one face, the fingertips side by side on the opposite one
    s.grip = GraspGrip::kOpposed;
    Vec2 axis = Vec2::UnitX();
    if (s.shape == GraspShape::kBox && axisPick < 0.5) axis = Vec2::UnitY();
    if (s.shape == GraspShape::kHexagon) {
      const double a = kPi / 3.0 * std::floor(axisPick * 3.0);
      axis = Vec2(std::cos(a), std::sin(a));
    }
    const Vec2 side(-axis.y(), axis.x());
    const double half = ReachAlong(slice, axis);
    const double groupPitch = nearCount > 1 ? widest : 0.0;
    if (slice.circle) {
      // the outer fingertips still press the round slice's near side
      if (0.5 * (nearCount - 1) * groupPitch > 0.9 * slice.radius) continue;
    } else if ((nearCount - 1) * groupPitch + 2.0 * fingerRadius + kClearance >
               2.0 * FaceHalfLength(slice, -axis)) {
      continue;
    }
    s.depth = std::min(depthDrawn, std::max(0.1, half - 0.5 * kClearance));
    auto place = [&](double pitch) {
      std::vector<GraspFinger> f;
      f.push_back(makeFinger(-axis * (half + fingerRadius - s.depth), axis));
      for (int i = 0; i < nearCount; ++i) {
        f.push_back(makeFinger(
            axis * (half + fingerRadius - s.depth) + side * ((i - 0.5 * (nearCount - 1)) * pitch),
            -axis));
      }
      return f;
    };
    s.fingers = place(pitchStart);
    if (!pushing) {
      if (topology == GraspTopology::kMerge || topology == GraspTopology::kSplit) {
        s.fingersAfter = place(pitchEnd);
      }
      placed = true;
      continue;
    }
    // a pinch whose third finger comes in across it from the middle of a face until its contour
    // overlaps the pinch's contours by pushOverlap cm (deeper than the drawn 1.5 to 2.5 cm where
    // that is needed, up to 3 cm, its centre short of the object's)
    GraspFinger& p = s.pusher;
    p.radius = pushRadius;
    p.inward = side;
    const double reach = ReachAlong(slice, -side);
    if (!slice.circle && p.radius + physics.particleRadius >= FaceHalfLength(slice, -side)) {
      continue;
    }
    const double a = half + fingerRadius - s.depth;
    const double meet = p.radius + fingerRadius - pushOverlap;
    if (a >= meet) continue;
    const double merged = reach + p.radius - std::sqrt(meet * meet - a * a);
    s.pushDepth = std::max(pushDepthDrawn, merged);
    if (s.pushDepth > std::min(3.0, reach + p.radius)) continue;
    p.pos = -side * (reach + p.radius - s.pushDepth);
    placed = true;
  }
  if (!placed && s.motion == GraspMotion::kPush) {
    // no small object of this shape let the pusher reach the pinch: the fingers slide instead
    s.motion = GraspMotion::kCarry;
    return GenerateTopologyScene(rng, seed, index, topology, profile, false);
  }
  if (!placed) return std::nullopt;

  s.moveStart = kMoveStart;
  if (s.motion == GraspMotion::kCarry) {
    const double a = rng.Uniform(0.0, 2.0 * kPi);
    s.direction = Vec2(std::cos(a), std::sin(a));
    s.distance = rng.Uniform(8.0, 14.0);
    s.speed =
        profile == GraspProfile::kStep ? rng.Uniform(5.0, kStepMaxSpeed) : rng.Uniform(5.0, 30.0);
    o.pose.pos = kTableCentre - s.direction * (0.5 * s.distance);
  } else if (s.motion == GraspMotion::kTurn) {
    s.turn = DegToRad(rng.Uniform(60.0, 180.0)) * (rng.Uniform() < 0.5 ? -1.0 : 1.0);
    s.turnRate = DegToRad(rng.Uniform(30.0, 120.0));
    o.pose.pos = kTableCentre;
  } else {
    o.pose.pos = kTableCentre;
  }
  TimeMotion(s);
  if (!s.fingersAfter.empty()) {
    // the slide, before, during or after the motion
    const double span = rng.Uniform(kEventTimeMin, kEventTimeMax);
    const double when = rng.Uniform();
    if (when < 1.0 / 3.0) {
      const double lo = kApproachTime + 0.05, hi = std::max(lo, kMoveStart - 0.05 - span);
      s.eventStart = rng.Uniform(lo, hi);
    } else if (when < 2.0 / 3.0) {
      s.eventStart = rng.Uniform(s.moveStart, std::max(s.moveStart, s.moveEnd - span));
    } else {
      s.eventStart = rng.Uniform(s.moveEnd + 0.05, s.moveEnd + 0.3);
    }
    s.eventEnd = s.eventStart + span;
    s.duration = std::max(s.duration, s.eventEnd + 0.5);
  }
  return s;
}

}  // namespace

GraspScene GenerateGraspScene(uint64_t seed, int index, const GraspClasses& classes) {
  if (classes.IsLegacy()) return GenerateGraspScene(seed, index);
  // the scene's class, from a stream of its own
  Rng rng(seed * 2654435761ULL + static_cast<uint64_t>(index) * 40503ULL + 0x5151ULL);
  double total = 0.0;
  for (int i = 0; i < kGraspTopologyCount; ++i)
    total += classes.topology[i] ? kTopologyWeights[i] : 0;
  double pick = rng.Uniform() * total;
  GraspTopology topology = GraspTopology::kNone;
  for (int i = 0; i < kGraspTopologyCount; ++i) {
    if (!classes.topology[i]) continue;
    topology = static_cast<GraspTopology>(i);
    pick -= kTopologyWeights[i];
    if (pick < 0.0) break;
  }
  const double stepPick = rng.Uniform();
  const GraspProfile profile = !classes.step           ? GraspProfile::kBangBang
                               : !classes.bangBang     ? GraspProfile::kStep
                               : stepPick < kStepShare ? GraspProfile::kStep
                                                       : GraspProfile::kBangBang;
  if (topology != GraspTopology::kNone) {
    if (std::optional<GraspScene> s = GenerateTopologyScene(rng, seed, index, topology, profile)) {
      return *s;
    }
  }
  // none: the scene of the sweep before issue 42, its motion made a step if that is drawn
  GraspScene s = GenerateGraspScene(seed, index);
  s.profile = profile;
  if (profile == GraspProfile::kStep) {
    if (s.motion == GraspMotion::kCarry) s.speed = rng.Uniform(5.0, kStepMaxSpeed);
    if (s.motion == GraspMotion::kTurn) s.turnRate = DegToRad(rng.Uniform(30.0, 120.0));
    TimeMotion(s);
  }
  return s;
}

namespace {

// The margin of a velocity step followed through its phases (seventeenth revision): how much
// heavier (or, when it runs on past the grip, lighter) the object could be and still come to rest
// within `tolerance` of the grip, its mass and with it the table's friction scaled together
// against the same grip (as the other margins: capacity over a requirement that scales with the
// mass). `restsAt(factor)` is where it rests behind the grip (negative: ahead) at that factor;
// `rest` receives it at 1. Factors from 1/4 to 4, each edge halved 10 times.
double StepMassMargin(const std::function<double(double)>& restsAt, double tolerance,
                      double* rest) {
  constexpr double kMostFactor = 4.0;
  constexpr int kHalvings = 10;
  auto follows = [&](double factor) { return std::abs(restsAt(factor)) <= tolerance; };
  // the factor where following turns to not, between one that follows and one that does not
  // (halving the ratio between them)
  auto edge = [&](double good, double bad) {
    for (int i = 0; i < kHalvings; ++i) {
      const double middle = std::sqrt(good * bad);
      (follows(middle) ? good : bad) = middle;
    }
    return good;
  };
  const double lag = restsAt(1.0);
  *rest = lag;
  if (std::abs(lag) <= tolerance) {
    const double heavier = follows(kMostFactor) ? kMostFactor : edge(1.0, kMostFactor);
    const double lighter =
        follows(1.0 / kMostFactor) ? 1.0 / kMostFactor : edge(1.0, 1.0 / kMostFactor);
    return std::min(heavier, 1.0 / lighter);
  }
  // it stays behind (or runs on past the grip): the nearest lighter (heavier) factor that
  // follows, in quarter octaves out to 1/4 (4), then halved to the edge; 0 for none
  const double side = lag > 0.0 ? -1.0 : 1.0;
  double bad = 1.0, nearest = 0.0;
  for (int k = 1; k <= 8 && nearest == 0.0; ++k) {
    const double factor = std::pow(kMostFactor, side * k / 8.0);
    if (follows(factor)) nearest = edge(factor, bad);
    bad = factor;
  }
  return nearest == 0.0 ? 0.0 : (lag > 0.0 ? nearest : 1.0 / nearest);
}

// The rule for the fingers where they are (docs/physics.md, "Grasp sweep"): PredictGrasp takes
// it over the configurations a slide passes through.
GraspPrediction PredictConfig(const GraspScene& s, const PhysicsParams& physics, double spacing) {
  GraspPrediction p;
  const ObjectSpec& o = s.object;
  const MassProps mass = ComputeMassProps(o);
  const double g = physics.gravity;
  const double weight = mass.mass * g;
  const double muP = o.particleFriction >= 0 ? o.particleFriction : physics.particleFriction;
  const bool step = s.profile == GraspProfile::kStep;
  // Fingertips whose outlines overlap press as the outline of their union: each loses its
  // contour points inside the others (a merging pusher counts at its deepest). They move
  // together, so the offsets hold whatever the object does.
  std::vector<GraspFinger> all = s.fingers;
  if (s.motion == GraspMotion::kPush) all.push_back(s.pusher);
  std::vector<std::vector<HiddenDisc>> hidden(all.size());
  for (size_t i = 0; i < all.size(); ++i) {
    for (size_t j = 0; j < all.size(); ++j) {
      const Vec2 offset = all[j].pos - all[i].pos;
      if (j != i && offset.norm() < all[i].radius + all[j].radius) {
        hidden[i].push_back({offset, all[j].radius});
      }
    }
  }
  const size_t fingers = s.fingers.size();
  auto force = [&](size_t i, const Vec2& shift) {
    // the object moved by `shift`: in its frame the finger moved by -shift
    const GraspFinger& f = s.fingers[i];
    return FingertipForce(o, physics, spacing, f.pos - shift, f.radius, f.inward, hidden[i]);
  };
  // the same with the object lagging from its rest shift: the bodies stay where they met it
  // (`pressing`: how many of them press)
  auto laggedForce = [&](size_t i, const Vec2& rest, const Vec2& shift,
                         double* pressing = nullptr) {
    const GraspFinger& f = s.fingers[i];
    return FingertipForce(o, physics, spacing, f.pos - rest, f.pos - shift, f.radius, f.inward,
                          pressing, hidden[i]);
  };

  // The grip at rest: where the sides press unequally (more fingertips against a thumb, or two on
  // one face of a cage) the object settles where they balance. The grip is symmetric about the
  // first fingertip's line of push, so the object moves along it.
  Vec2 shift = Vec2::Zero();
  // Tenth revision: the imbalance B the table's static friction holds while the object has not
  // moved, dyn along the first fingertip's push (see breaking loose, below)
  double restImbalance = 0.0;
  if ((s.grip == GraspGrip::kOpposed && fingers > 2) ||
      (s.grip == GraspGrip::kCaged && fingers > 3)) {
    const Vec2 axis = s.fingers.front().inward;
    auto imbalance = [&](double d) {
      Vec2 sum = Vec2::Zero();
      for (size_t i = 0; i < fingers; ++i) sum += force(i, axis * d);
      return sum.dot(axis);  // falls as the object moves along the first fingertip's push
    };
    double lo = -(s.depth + 2.0), hi = s.depth + 2.0;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (imbalance(mid) > 0.0 ? lo : hi) = mid;
    }
    shift = axis * (0.5 * (lo + hi));
    // The fingers come in slowly and B grows with their depth. While |B| <= mu_s W the table's
    // static friction keeps the object where it was and B stays on it; beyond, it slides towards
    // the weaker side during the squeeze and comes to rest with mu_k W of B left.
    const double b = imbalance(0.0);
    restImbalance =
        std::abs(b) <= o.tableStatic * weight ? b : std::copysign(o.tableKinetic * weight, b);
  }
  p.restImbalance = restImbalance;
  // the normal force at rest, and how many bodies press
  double bodiesAtRest = 0.0;
  for (size_t i = 0; i < fingers; ++i) {
    double pressing = 0.0;
    p.normalForce += laggedForce(i, shift, shift, &pressing).norm();
    bodiesAtRest += pressing;
  }

  // what every fingertip, together, pushes along u with the object lagging `lag` behind the grip
  // along u. Nineteenth revision: on a round slice each body slides over it once its spring pulls
  // along the surface by more than mu_p times its press, and its pull adds to the push
  // (RoundFingertipForce); a body kept where it met the slice pushed on along its first normal
  // however far its target went, which a slippery grip's bodies do not.
  auto pushAt = [&](const Vec2& u, double lag) {
    Vec2 sum = Vec2::Zero();
    for (size_t i = 0; i < fingers; ++i) {
      const GraspFinger& f = s.fingers[i];
      sum += RoundFingertipForce(o, physics, spacing, f.pos - shift, f.pos - shift + u * lag,
                                 f.radius, f.inward, muP, hidden[i]);
    }
    return sum.dot(u);
  };
  // what they can push along u while the object lags behind the grip by up to d_max (a lag the
  // springs take back when the grip stops): the leading fingertips press deeper and the trailing
  // ones let go. Fingertips larger than a round slice press less when pushed past its centre, so
  // every lag up to d_max is tried.
  auto pushCapacity = [&](const Vec2& u) {
    double best = 0.0;
    constexpr int kLags = 16;
    for (int j = 1; j <= kLags; ++j)
      best = std::max(best, pushAt(u, physics.gripMaxDepth * j / kLags));
    return best;
  };
  // A velocity step (issue 42): the grip starts at speed v within a frame while the object rests.
  // It stays put until the grip's force reaches static friction (at lag L0), then slides against
  // kinetic friction while the springs push it on; it catches up once the springs have taken its
  // kinetic energy relative to the grip, 1/2 M v^2 (in the grip's frame the object comes in at v
  // and the springs stop it): E(L) = integral from L0 to L of (F(x) - mu_k W) dx must reach it
  // within the lag the grip gives back, L <= `limit`. The fastest step it catches is
  // sqrt(2 max E / M). Stopping, the object runs on at v and the springs and the table's
  // friction together stop it: integral from 0 of (F(x) + mu_k W) dx. `forceAt(L)` is the
  // grip's force along the motion at lag L (its magnitude for breaking loose in `looseAt`).
  constexpr int kStepLags = 64;
  // the most energy a force gives over a lag from `from` to `limit` against `resist`
  auto energyFrom = [&](auto&& forceAt, double from, double limit, double resist) {
    if (from >= limit) return 0.0;
    double energy = 0.0, best = 0.0, previous = forceAt(from) - resist;
    for (int j = 1; j <= kStepLags; ++j) {
      const double l = from + (limit - from) * j / kStepLags;
      const double f = forceAt(l) - resist;
      energy += 0.5 * (previous + f) * (limit - from) / kStepLags;
      best = std::max(best, energy);
      previous = f;
    }
    return best;
  };
  auto catchUp = [&](auto&& forceAt, auto&& looseAt, double limit, double staticLimit,
                     double kinetic, double inertia, bool stopping) {
    double energy = 0.0, best = 0.0;
    bool loose = stopping;
    double previous = 0.0;
    for (int j = 0; j <= kStepLags; ++j) {
      const double l = limit * j / kStepLags;
      const double f = forceAt(l) + (stopping ? kinetic : -kinetic);
      if (!loose && looseAt(l) >= staticLimit) {
        loose = true;
        previous = f;
        continue;
      }
      if (loose && j > 0) {
        energy += 0.5 * (previous + f) * (limit / kStepLags);
        best = std::max(best, energy);
      }
      previous = f;
    }
    return std::sqrt(2.0 * best / inertia);
  };

  if (s.motion == GraspMotion::kCarry) {
    const double a = step ? 0.0 : s.speed * s.speed / s.distance;  // bang-bang: v^2 / D
    // to break loose from the table, then to accelerate while sliding (a step: to slide on at
    // its speed, and to catch up, below)
    const double breakLoose = o.tableStatic * weight;
    const double sliding = o.tableKinetic * weight + mass.mass * a;
    p.requirement = std::max(breakLoose, sliding);
    const Vec2 u = Rotate(s.direction, -o.pose.angle);  // object frame
    if (s.grip == GraspGrip::kOpposed) {
      const Vec2 axis = s.fingers.front().inward;
      const double cosE = std::abs(u.dot(axis));
      const double sinE = std::abs(u.x() * axis.y() - u.y() * axis.x());
      const Vec2 lead = u.dot(axis) >= 0 ? axis : Vec2(-axis);
      const double push = pushCapacity(lead);
      // Sliding (kinetic friction and the acceleration, along u): along the axis the leading
      // side pushes; across it friction holds, on the normal force of both sides, which the push
      // shifts from one side to the other without reducing it until the trailing side lets go.
      const double along = sliding * cosE, across = sliding * sinE;
      // On a round slice (seventh revision) the normals tilt as the object moves across the
      // axis, by its move over the reach rho (slice radius plus r): the normal force N pushes it
      // on across by N / rho per cm, while friction holds it through the springs of the n
      // pressing bodies, k n per cm. Friction F stretches them F / (k n), so the tilt takes
      // F dbar / rho of it back (dbar = N / (k n), their mean depth): across, the grip holds
      // F (1 - dbar / rho). (Two fingertips pinching a ball deep slid it out sideways and spun
      // it: seeds 38 to 43 had 17 such carries the rule said could hold.)
      const CrossSection grip0 = Slice0(o, physics);
      const double tilt = grip0.circle && bodiesAtRest > 0.0
                              ? p.normalForce / (physics.gripStiffness * bodiesAtRest) /
                                    (grip0.radius + physics.particleRadius)
                              : 0.0;
      const double keep = std::max(0.0, 1.0 - tilt);
      // along the axis the leading side's push; across, the grip's friction (and a round
      // slice's bounds, below)
      const double alongMargin = along > 0 ? push / along : kInfinity;
      const double frictionMargin =
          across > 0 ? muP * std::max(p.normalForce, along) * keep / across : kInfinity;
      double roundMargin = kInfinity;
      // The two sides of the grip (those pressing along the lead, and the rest) once the object
      // lags far enough behind the grip along the lead, in `steps` steps of d_max, for their
      // forces to push `along` (the last step when they never do), and by x across it (along w):
      // what they push across, and each side's normal force. `forceOf(i, moved)` is fingertip
      // i's force with the object moved from its rest shift to `moved`.
      struct SideForces {
        double across = 0.0;
        double lead = 0.0, trail = 0.0;
      };
      auto sidesAtBalance = [&](auto&& forceOf, int steps, const Vec2& w, double x) {
        SideForces r;
        for (int j = 0; j <= steps; ++j) {
          const double l = physics.gripMaxDepth * j / steps;
          double pushed = 0.0;
          r = SideForces{};
          for (size_t i = 0; i < fingers; ++i) {
            const Vec2 f = forceOf(i, Vec2(shift - lead * l - w * x));
            pushed += f.dot(lead);
            r.across += f.dot(w);
            (s.fingers[i].inward.dot(lead) > 0.0 ? r.lead : r.trail) += f.norm();
          }
          if (pushed >= along) break;
        }
        return r;
      };
      // Twelfth revision (docs/physics.md, "A round slice carried across a pinch"): the normals
      // on a round slice pass through its centre, so only friction turns it, and a slice sliding
      // on the table is turned back by almost nothing. In a pinch of two fingertips, one a side,
      // friction across the axis must then come from the two sides in equal shares, as their
      // torques about the centre cancel, and the side that presses less (the trailing side, once
      // the leading side pushes `along`) bounds it: across <= 2 mu_p min(N_lead, N_trail) (with
      // the tilt's `keep`), each side's normal forces taken where the object lags far enough
      // behind the grip for their sum along the lead to push `along` (the bodies staying where
      // they met the slice). Two or more fingertips against a thumb also cradle the slice with
      // their normals: the thirteenth revision, below.
      if (grip0.circle && fingers == 2 && across > 0.0) {
        const SideForces sides = sidesAtBalance(
            [&](size_t i, const Vec2& moved) { return laggedForce(i, shift, moved); }, 64,
            Vec2::Zero(), 0.0);
        roundMargin = 2.0 * muP * std::min(sides.lead, sides.trail) * keep / across;
      }
      // Thirteenth revision (docs/physics.md, "A round slice cradled against a thumb"): with two
      // or more fingertips against a thumb the pair's normals also push across once the object
      // lags across by x, the nearer fingertip pressing deeper (a cradle), and they turn nothing.
      // Each body is taken where it meets the slice as its target comes in with the object
      // displaced (`force`: a body that slides round the slice, its normal tilted), so that the
      // normals' push across holds both the cradle and the tilt that pushes a pinched slice
      // out. To that the springs add friction k n x, up to what the sides give in equal shares,
      // 2 mu_p min(N_lead, N_trail), the sides' forces taken where they also push `along`.
      // Across the grip holds the most of that over x up to the springs' stretch at friction
      // plus the slip that still counts as holding.
      if (grip0.circle && fingers > 2 && across > 0.0) {
        const Vec2 w = (u - u.dot(axis) * axis).normalized();
        const double stiffness = physics.gripStiffness;
        const double elastic =
            bodiesAtRest > 0.0 ? muP * p.normalForce / (stiffness * bodiesAtRest) : 0.0;
        const double reach = elastic + kBreakLooseSlip;
        constexpr int kAcrossLags = 16;
        double best = 0.0;
        for (int jx = 0; jx <= kAcrossLags; ++jx) {
          const double x = reach * jx / kAcrossLags;
          const SideForces sides = sidesAtBalance(force, 32, w, x);
          const double f =
              std::min(stiffness * bodiesAtRest * x, 2.0 * muP * std::min(sides.lead, sides.trail));
          best = std::max(best, sides.across + f);
        }
        roundMargin = best / across;
      }
      // the cradle's bound replaces the friction's (it holds the friction the sides give)
      const double slideMargin = std::min(
          {alongMargin, grip0.circle && fingers > 2 && across > 0.0 ? kInfinity : frictionMargin,
           roundMargin});
      // Breaking loose: the table's static friction gives way to a force of mu_s W in any
      // direction. While the object is stuck the grip moves on along u; it lags l along the axis
      // (the leading side presses deeper) and l tan(angle) across it, where each pressing body
      // is a spring k until friction slides it. Slid further across than kBreakLooseSlip, the
      // grip would leave the object that far behind for good.
      const double k = physics.gripStiffness;
      // the force with the object lagging l along the axis and `acrossLag` across it: along
      // the axis, across it, and how far across the springs stretch before friction slides
      struct Lagged {
        double axial = 0.0, held = 0.0, elastic = 0.0;
        double friction = 0.0;  // across, the bodies' friction without the round slice's tilt
      };
      // the unit direction across the axis in which the grip moves on from the object
      const Vec2 acrossDir = sinE > 1e-9 ? Vec2((u - axis * u.dot(axis)).normalized()) : axis;
      // Sixteenth revision: the friction across body by body (GripSlideFriction). At rest the
      // bodies on a round slice (and on faces met obliquely) have slid until their pull along
      // the surface is at its limit, symmetric about the fingertip's push: half of them pull
      // against any move across and must first give that back. The grip reaches its full friction
      // across only at about twice the stretch the bodies take from a pull-free start (seed 225
      // scene 62: a 149 g sphere pinched 1.14 cm deep, mu_p 0.14, gave 70,000 dyn across at a
      // lag of 0.13 cm, where k n x from a pull-free start is its whole 120,000; it lagged on,
      // its normals tilted, and it squirted out).
      auto laggedGrip = [&](const Vec2& dir, double l, double acrossLag,
                            const Vec2& across = Vec2::Zero()) {
        const Vec2 side = across.squaredNorm() > 0.0 ? across : acrossDir;
        Vec2 sum = Vec2::Zero(), friction = Vec2::Zero();
        double normalSum = 0.0, bodies = 0.0;
        for (size_t i = 0; i < fingers; ++i) {
          double pressing = 0.0;
          const Vec2 force = laggedForce(i, shift, shift - dir * l, &pressing);
          sum += force;
          normalSum += force.norm();
          bodies += pressing;
        }
        Lagged r;
        r.elastic = bodies > 0.0 ? muP * normalSum / (k * bodies) : 0.0;
        // slid further than the slip that still counts as holding, the grip has let go
        const double x = std::min(acrossLag, r.elastic + kBreakLooseSlip);
        if (x > 0.0) {
          for (size_t i = 0; i < fingers; ++i) {
            const GraspFinger& f = s.fingers[i];
            friction +=
                GripSlideFriction(o, physics, spacing, f.pos - shift, f.pos - shift + dir * l,
                                  f.radius, f.inward, side * x, muP, hidden[i]);
          }
        }
        r.friction = std::max(0.0, friction.dot(side));
        r.held = r.friction * keep;
        r.axial = std::max(sum.dot(dir), 0.0);
        return r;
      };
      // Tenth revision: while the object rests, the table's static friction already holds the
      // imbalance B the sides leave (unequal sides; 0 for a symmetric grip), along the axis. The
      // object breaks loose when the whole force on it, B plus what the lag adds, reaches mu_s W
      // in any direction: B counts with its sign along the lead (against the motion it takes
      // some of the across force's share of the circle; along it, it adds to the push).
      const double preload = restImbalance * axis.dot(lead);
      auto looseMagnitude = [&](const Lagged& r) { return std::hypot(r.axial + preload, r.held); };
      auto breakingForce = [&](double l, double acrossLag, double& elastic) {
        const Lagged r = laggedGrip(lead, l, acrossLag);
        elastic = r.elastic;
        return looseMagnitude(r);
      };
      // the most force the grip reaches before it has slid kBreakLooseSlip across, over mu_s W
      // (a step follows breaking loose as one of its phases instead, below)
      auto looseMargin = [&] {
        constexpr int kLags = 32;
        double looseForce = 0.0;
        for (int j = 0; j <= kLags; ++j) {
          const double l = physics.gripMaxDepth * j / kLags;
          const double acrossLag = cosE > 0.0 ? l * sinE / cosE : kInfinity;
          double elastic = 0.0;
          const double force = breakingForce(l, acrossLag, elastic);
          if (acrossLag <= elastic + kBreakLooseSlip) {
            looseForce = std::max(looseForce, force);
            continue;
          }
          // the grip reaches the slip it may take at a smaller axial lag: the last one tried
          const double cap = elastic + kBreakLooseSlip;
          const double last = cosE > 0.0 ? cap * cosE / sinE : 0.0;
          looseForce = std::max(looseForce, breakingForce(last, cap, elastic));
          break;
        }
        return breakLoose > 0.0 ? looseForce / breakLoose : kInfinity;
      };
      if (!step) {
        p.margin = std::min(slideMargin, looseMargin());
      } else {
        // The step, opposed. Along the axis the leading side's normal forces catch the object
        // up, and stop it, within d_max: each must take the kinetic energy along the axis,
        // 1/2 M (v cos)^2, the table's kinetic friction against the catch-up in full (while the
        // object's speed across is still about 0) and helping the stop by its share cos.
        // Eighteenth revision: across, where the object comes to rest after the stop (below).
        const double elastic = laggedGrip(lead, 0.0, 0.0).elastic;
        const double kinetic = o.tableKinetic * weight;
        constexpr double kMostAcross = 3.0;  // cm, as far across as the object is followed
        double looseReach = cosE > 1e-9 ? physics.gripMaxDepth / cosE : kInfinity;
        if (sinE > 1e-9) looseReach = std::min(looseReach, kMostAcross / sinE);
        // The grip's force across with the object lagging x, once its bodies have slid `slid`
        // across it, from a lag of `peak` (x itself on the way out). Up to the springs'
        // stretch e the bodies stick to the object and move with it. Beyond it they slide over
        // its surface and stay where the grip holds them, and the object has moved x - e past
        // them: each fingertip presses it there as it would a fresh one (`force`), and each
        // body's friction limit is set by its depth there (a fingertip slid past a face's end
        // holds nothing). On a flat face the normals do not turn; two fingertips pinching a
        // round slice press through its centre, which has moved off their line, and push it on
        // (the seventh revision's tilt); a thumb against two fingertips cradles it. On the way
        // back from a peak each body springs back from the pull it had there, and the bodies
        // slide back only once the object has come back twice the stretch: they lie between
        // x - e and x + e of its lag.
        auto acrossForce = [&](double slid, double x, double peak) {
          Vec2 normals = Vec2::Zero();
          double friction = 0.0;
          for (size_t i = 0; i < fingers; ++i) {
            const GraspFinger& f = s.fingers[i];
            const Vec2 at = f.pos - shift + acrossDir * slid;
            normals += force(i, shift - acrossDir * slid);
            friction += GripSlideFriction(o, physics, spacing, f.pos - shift, at, f.radius,
                                          f.inward, acrossDir * (x - slid), muP, hidden[i],
                                          Vec2(acrossDir * (peak - slid)))
                            .dot(acrossDir);
          }
          return friction + normals.dot(acrossDir);
        };
        std::unordered_map<double, double> loosened, loaded;
        auto loose = [&](double l) {
          auto [it, fresh] = loosened.try_emplace(l, 0.0);
          if (fresh) it->second = looseMagnitude(laggedGrip(lead, l * cosE, l * sinE));
          return it->second;
        };
        auto loading = [&](double x) {
          auto [it, fresh] = loaded.try_emplace(x, 0.0);
          if (fresh) it->second = acrossForce(std::max(0.0, x - elastic), x, x);
          return it->second;
        };
        auto unloading = [&](double peak, double x) {
          return acrossForce(std::min(std::max(0.0, peak - elastic), x + elastic), x, peak);
        };
        auto lagsAt = [&](double factor) {
          return CarryStepLag(loose, looseReach, loading, unloading, factor * breakLoose,
                              factor * kinetic, factor * mass.mass, s.speed, sinE, kMostAcross);
        };
        // the axis: from where the object breaks loose (catching up) and from rest (stopping)
        auto axialSpeed = [&](const Vec2& dir, double from, double resist) {
          if (cosE <= 1e-9) return kInfinity;
          const double axial = energyFrom([&](double l) { return laggedGrip(dir, l, 0.0).axial; },
                                          from * cosE, physics.gripMaxDepth, resist);
          return std::sqrt(2.0 * axial / mass.mass) / cosE;
        };
        const double looseLag = lagsAt(1.0).breakLoose;
        p.catchUpSpeed = axialSpeed(lead, std::isfinite(looseLag) ? looseLag : 0.0, kinetic);
        p.stopSpeed = axialSpeed(-lead, 0.0, -kinetic * cosE);
        // Eighteenth revision (docs/physics.md, "A carry step, followed through its phases"):
        // across the axis the object is followed through its phases (CarryStepLag) to where it
        // rests after the stop. It follows when that is within 1 cm of the grip; the margin is
        // the factor on its mass (weight, and with it the table's friction) at which it stops
        // following, as for a turn step. Breaking loose is one of its phases: the static margin
        // (the grip reaching mu_s W within 0.5 cm of slip) is the bang-bang carry's. The slide
        // margin stays: the grip's friction must carry the object across at full speed.
        const double acrossMargin = StepMassMargin(
            [&](double factor) { return lagsAt(factor).rest; }, kFollowDistance, &p.stepRest);
        p.margin =
            std::min({slideMargin, p.catchUpSpeed / s.speed, p.stopSpeed / s.speed, acrossMargin});
      }
      p.capacity = p.margin * p.requirement;
    } else {
      // caged: the fingertips push it in any direction
      p.margin = pushCapacity(u) / p.requirement;
      if (step) {
        const double limit = physics.gripMaxDepth;
        auto along = [&](const Vec2& dir) {
          return [&, dir](double lag) { return pushAt(dir, lag); };
        };
        p.catchUpSpeed = catchUp(along(u), along(u), limit, breakLoose, o.tableKinetic * weight,
                                 mass.mass, false);
        p.stopSpeed = catchUp(along(-u), along(-u), limit, breakLoose, o.tableKinetic * weight,
                              mass.mass, true);
        p.margin = std::min({p.margin, p.catchUpSpeed / s.speed, p.stopSpeed / s.speed});
      }
      p.capacity = p.margin * p.requirement;
    }
  } else if (s.motion == GraspMotion::kTurn) {
    const double alpha = step ? 0.0 : s.turnRate * s.turnRate / std::abs(s.turn);  // w^2 / theta
    const double rEff = EffectiveFrictionRadius(o, mass.centroid);
    p.requirement = std::max(o.tableStatic * weight * rEff,
                             o.tableKinetic * weight * rEff + mass.inertia * alpha);
    const double turnSign = s.turn >= 0.0 ? 1.0 : -1.0;
    // What the grip gives once the object lags the turn by `lag` (sixth revision: at the angle
    // that still counts as following): in the object's frame each fingertip has turned on by
    // that angle about its centre. Each body pulls along the surface as a spring until its
    // friction slides, from the pull it already had at rest, and presses by its target's new
    // depth (a body that slides follows its target along its face).
    std::vector<double> atRest(fingers);
    for (size_t i = 0; i < fingers; ++i) {
      const GraspFinger& f = s.fingers[i];
      atRest[i] = GripTurnTorque(o, physics, spacing, f.pos - shift, f.radius, f.inward, 0.0, muP,
                                 hidden[i]);
    }
    auto gripTorque = [&](double sign, double lag, std::optional<double> peak = std::nullopt) {
      double torque = 0.0;
      const std::optional<double> turnedTo =
          peak ? std::optional<double>(sign * *peak) : std::nullopt;
      for (size_t i = 0; i < fingers; ++i) {
        const GraspFinger& f = s.fingers[i];
        torque += sign * (GripTurnTorque(o, physics, spacing, f.pos - shift, f.radius, f.inward,
                                         sign * lag, muP, hidden[i], turnedTo) -
                          atRest[i]);
      }
      return torque;
    };
    p.capacity = gripTorque(turnSign, kFollowAngle);
    p.margin = p.requirement > 0 ? p.capacity / p.requirement : kInfinity;
    if (step) {
      // Seventeenth revision: a step of the turn rate, followed through its phases (TurnStepLag,
      // docs/physics.md "A turn step"): at rest until the grip's torque reaches static
      // friction, the catch-up to the peak lag, sliding on with the grip where the torque on the
      // way back from the peak is kinetic friction, and the run-on at the stop. It follows when
      // it comes to rest within 5 degrees of the grip. The margin is how much heavier (or, when
      // it runs on past the grip, lighter) the object could be and still follow: its weight and
      // inertia, and with them the table's friction, scaled together against the same grip (as
      // the margins above, capacity over a requirement that scales with the mass).
      constexpr double kMaxLag = DegToRad(30.0);
      const double staticTorque = o.tableStatic * weight * rEff;
      const double kineticTorque = o.tableKinetic * weight * rEff;
      std::unordered_map<double, double> loaded;  // the grip's torque out from rest, by lag
      auto loading = [&](double lag) {
        auto [it, fresh] = loaded.try_emplace(lag, 0.0);
        if (fresh) it->second = gripTorque(turnSign, lag);
        return it->second;
      };
      auto unloading = [&](double peak, double lag) { return gripTorque(turnSign, lag, peak); };
      auto restsAt = [&](double factor) {
        return TurnStepLag(loading, unloading, factor * staticTorque, factor * kineticTorque,
                           factor * mass.inertia, s.turnRate, kMaxLag)
            .rest;
      };
      p.margin = StepMassMargin(restsAt, kFollowAngle, &p.stepRest);
      p.capacity = p.margin * p.requirement;
    }
  } else {
    // The pusher is a finger held at its depth, not a force: an object it pushes away presses
    // it less. A pusher whose outline merged with the grip's presses with what is left of its
    // contour, and takes from the grip's contours what lies inside it.
    // Fifteenth revision: with the object moved d along the push u, every fingertip's normal
    // force drives it, D(d) = sum_i F_i(d).u, and the grip's friction and the table's static
    // friction resist, C(d) = mu_p sum_grip |F_i(d)| + mu_s W. Before, D was the pusher's force
    // alone: right for a box, whose gripped faces lie along the push, but a round slice's
    // fingertips press along lines through its centre, which tilt as it moves: with whole
    // contours towards the push (the slice squirts out), and, where a merged pusher's disc hides
    // the backs of their contours, against it (their fronts wedge the slice back). The pusher
    // comes in slowly and D grows with its depth at every d, so the object moves on from each
    // place it stopped and ends at the first d where D(d) <= C(d): it follows (stays within
    // kFollowDistance) when some d up to that distance has D(d) <= C(d). The margin is the best
    // C / D over d.
    // Sixteenth revision: the pusher's own friction. While the pusher comes in and the object
    // has stopped, each of its pressing bodies slides over the surface by the part of u that
    // lies along it (a body holds its aim along a surface as hard as its friction lets it:
    // `ApplyKinematicControl` springs only the normal part), and its friction drags the object
    // that way: along u by mu_p N sin(alpha), alpha the angle between u and its normal. Before,
    // D counted the pusher's normal forces alone, N cos(alpha) along u: on a face met obliquely
    // short by mu_p N sin(alpha) (218 #446: a hexagon face 21 degrees off the push took 278,000
    // dyn along u from a pusher pressing 260,000 normal to it).
    const Vec2 u = s.pusher.inward;
    p.margin = 0.0;
    constexpr int kPushLags = 16;
    for (int j = 0; j <= kPushLags; ++j) {
      const Vec2 moved = shift + u * (kFollowDistance * j / kPushLags);
      const Vec2 at = s.pusher.pos - moved;
      Vec2 drive = FingertipForce(o, physics, spacing, at, at, s.pusher.radius, s.pusher.inward,
                                  nullptr, hidden.back(), muP);
      double gripNormal = 0.0;
      for (size_t i = 0; i < fingers; ++i) {
        const Vec2 f = force(i, moved);
        drive += f;
        gripNormal += f.norm();
      }
      const double requirement = std::max(drive.dot(u), 0.0);
      const double capacity = muP * gripNormal + o.tableStatic * weight;
      const double margin = requirement > 0 ? capacity / requirement : kInfinity;
      if (j == 0 || margin > p.margin) {
        p.margin = margin;
        p.requirement = requirement;
        p.capacity = capacity;
      }
    }
  }
  p.canHold = p.margin >= 1.0;
  p.nearBoundary = p.margin >= 1.0 - kBoundaryBand && p.margin <= 1.0 + kBoundaryBand;
  p.marginMax = p.margin;
  return p;
}

// The farthest a fingertip that slides over the round layer-0 slice goes round it (rad): the
// change of its centre's bearing from the slice's axis. 0 when the slice is not round or nothing
// slides.
double SlideTurn(const GraspScene& s, const PhysicsParams& physics) {
  if (s.fingersAfter.empty() || !Slice0(s.object, physics).circle) return 0.0;
  double most = 0.0;
  for (size_t i = 0; i < s.fingers.size() && i < s.fingersAfter.size(); ++i) {
    const Vec2& a = s.fingers[i].pos;
    const Vec2& b = s.fingersAfter[i].pos;
    most = std::max(most, std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b))));
  }
  return most;
}

}  // namespace

GraspPrediction PredictGrasp(const GraspScene& s, const PhysicsParams& physics, double spacing) {
  if (s.fingersAfter.empty()) return PredictConfig(s, physics, spacing);
  // Fingers that slide together or apart: the rule is taken for the configurations present
  // while the grip moves. A slide before the motion leaves the configuration after it, one after
  // the motion the one before it; a slide during the motion passes through every one between
  // (taken at fifths of the slide). The scene can hold when the least margin can; it cannot when
  // the greatest cannot; otherwise which configuration meets the motion's demand decides, and
  // the rule does not say: it is reported with the boundary (not scored).
  std::vector<double> fractions;
  const std::string phase = GraspEventPhase(s);
  if (phase == "before") {
    fractions = {1.0};
  } else if (phase == "after") {
    fractions = {0.0};
  } else {
    fractions = {0.0, 0.2, 0.4, 0.6, 0.8, 1.0};
  }
  GraspPrediction least;
  double most = -kInfinity;
  bool first = true;
  for (double f : fractions) {
    GraspScene config = s;
    config.fingersAfter.clear();
    for (size_t i = 0; i < s.fingers.size(); ++i) {
      config.fingers[i].pos = s.fingers[i].pos + (s.fingersAfter[i].pos - s.fingers[i].pos) * f;
    }
    const GraspPrediction p = PredictConfig(config, physics, spacing);
    most = std::max(most, p.margin);
    if (first || p.margin < least.margin) least = p;
    first = false;
  }
  least.marginMax = most;
  least.canHold = least.margin >= 1.0;
  least.nearBoundary =
      (least.margin >= 1.0 - kBoundaryBand && least.margin <= 1.0 + kBoundaryBand) ||
      (least.margin < 1.0 - kBoundaryBand && most >= 1.0 - kBoundaryBand);
  // Eighth revision (docs/physics.md, "A slide over a round slice"): fingertips that slide over a
  // round slice press it through its centre, so their normal forces give it no torque, and their
  // friction turns it by mu_p (N_a - N_b) rho, the difference of the sliding pieces' pushes. The
  // piece that presses harder holds the surface and the slice turns with it, at most as far as
  // that piece goes round it. How much harder one piece presses depends on where the object sits
  // in the grip when the slide begins, which the rule does not model: where a piece goes round
  // the slice by the angle that still counts as following or more, the rule does not say that
  // the grip holds (a grip that cannot hold still cannot).
  least.slideTurn = SlideTurn(s, physics);
  if (least.canHold && least.slideTurn >= kFollowAngle) least.nearBoundary = true;
  return least;
}

std::string GraspSceneToml(const GraspScene& s, const GraspPrediction& prediction) {
  const ObjectSpec& o = s.object;
  std::ostringstream t;
  t << std::setprecision(10);
  t << "name = \"grasp sweep " << s.seed << "/" << s.index << "\"\n"
    << "description = \"\"\"\nGenerated by the grasp sweep (seed " << s.seed << ", scene "
    << s.index << "): a " << kGraspShapeNames[static_cast<int>(s.shape)] << " gripped by "
    << s.fingers.size() << " fingertips ("
    << (s.grip == GraspGrip::kCaged ? "at 120 degrees" : "on opposite faces") << "), contours "
    << s.depth << " cm inside, then a " << kGraspMotionNames[static_cast<int>(s.motion)] << " ("
    << kGraspProfileNames[static_cast<int>(s.profile)]
    << "); outlines: " << kGraspTopologyNames[static_cast<int>(s.topology)];
  if (!s.fingersAfter.empty()) {
    t << " (the fingers slide from " << s.eventStart << " to " << s.eventEnd << " s, "
      << GraspEventPhase(s) << " the motion)";
  }
  t << ".\"\"\"\n\n";
  t << "# The hold rule (docs/physics.md, \"Grasp sweep\"): grip normal force "
    << prediction.normalForce << " dyn, capacity " << prediction.capacity << ", requirement "
    << prediction.requirement << (s.motion == GraspMotion::kTurn ? " dyn cm" : " dyn")
    << ", margin " << prediction.margin;
  if (prediction.marginMax > prediction.margin)
    t << " (to " << prediction.marginMax << " while the fingers slide)";
  if (prediction.slideTurn > 0.0) {
    t << ", a fingertip slides " << RadToDeg(prediction.slideTurn) << " deg round the slice";
  }
  if (s.profile == GraspProfile::kStep && s.motion == GraspMotion::kTurn) {
    t << ", step: rests " << RadToDeg(prediction.stepRest) << " deg behind the grip";
  } else if (s.profile == GraspProfile::kStep && s.motion == GraspMotion::kCarry) {
    t << ", step: " << (s.grip == GraspGrip::kOpposed ? "the axis " : "") << "catches up to "
      << prediction.catchUpSpeed << ", stops from " << prediction.stopSpeed << " cm/s";
    if (s.grip == GraspGrip::kOpposed)
      t << ", rests " << prediction.stepRest << " cm across behind the grip";
  }
  t << ": "
    << (prediction.nearBoundary ? "near the boundary (not scored)"
        : prediction.canHold    ? "can hold"
                                : "cannot hold")
    << "\n\n";
  t << "[physics]\nframe_rate = 60\n\n";
  t << "[[objects]]\nname = \"object\"\nshape = \"" << kObjectShapeNames[static_cast<int>(o.shape)]
    << "\"\n";
  switch (o.shape) {
    case ObjectShape::kBox:
      t << "size_x = " << o.sizeX << "\nsize_y = " << o.sizeY << "\nheight = " << o.height << "\n";
      break;
    case ObjectShape::kCylinder:
      t << "radius = " << o.radius << "\nheight = " << o.height << "\n";
      break;
    case ObjectShape::kSphere:
      t << "radius = " << o.radius << "\n";
      break;
    default:
      t << "height = " << o.height << "\npoints = [";
      for (size_t i = 0; i < o.points.size(); ++i) {
        t << (i ? ", " : "") << "[" << o.points[i].x() << ", " << o.points[i].y() << "]";
      }
      t << "]\n";
      break;
  }
  t << "mass = " << o.mass << "\ntable_static = " << o.tableStatic
    << "\ntable_kinetic = " << o.tableKinetic << "\nparticle_friction = " << o.particleFriction
    << "\npos = [" << o.pose.pos.x() << ", " << o.pose.pos.y()
    << "]\nangle = " << RadToDeg(o.pose.angle) << "\n\n";
  t << "[script]\ninterpolation = \"linear\"\nduration = " << s.duration << "\n";
  const std::vector<FingerPath> paths = Paths(s);
  for (size_t i = 0; i < paths.size(); ++i) {
    t << "\n[[script.contacts]]\nname = \"finger" << i
      << "\"\nshape = \"circle\"\nradius = " << paths[i].radius << "\nkeys = [\n";
    for (const auto& [time, pos] : paths[i].keys) {
      t << "  {t = " << time << ", pos = [" << pos.x() << ", " << pos.y() << "]},\n";
    }
    t << "]\n";
  }
  if (prediction.canHold && !prediction.nearBoundary) {
    const Pose2 m = GripMotionAt(s, s.duration);
    const Vec2 end = ApplyMotion(m, o.pose.pos);
    t << "\n# it can hold: the object follows the grip's rigid motion within 1 cm and 5 degrees\n"
      << "[[expect]]\nkind = \"position\"\nobject = \"object\"\ncenter = [" << end.x() << ", "
      << end.y() << "]\nradius = " << kFollowDistance << "\nlabel = \"follows the grip\"\n\n"
      << "[[expect]]\nkind = \"rotation\"\nobject = \"object\"\nabove = "
      << RadToDeg(m.angle - kFollowAngle) << "\nbelow = " << RadToDeg(m.angle + kFollowAngle)
      << "\n"
      << "label = \"turns with the grip\"\n";
  }
  return t.str();
}

Result<GraspOutcome> RunGraspScene(const GraspScene& s, int substeps,
                                   const std::vector<std::string>& sets) {
  const GraspPrediction none;
  Result<Level> level =
      ParseLevel(GraspSceneToml(s, none), "grasp-sweep/scene_" + std::to_string(s.index) + ".toml");
  if (!level.ok()) return level.error();
  LevelParams params = level.value().params;
  if (MaybeError e = ApplyOverrides(params, sets)) return *e;
  params.physics.substeps = substeps;
  Simulation sim;
  if (MaybeError e = sim.Start(level.value(), params)) return *e;

  GraspOutcome out;
  const double dt = sim.FrameDuration();
  const int64_t frames = static_cast<int64_t>(std::ceil(s.duration / dt - 1e-9));
  Pose2 atStart = s.object.pose;
  bool started = false;
  for (int64_t f = 0; f < frames; ++f) {
    if (!started && sim.Time() >= s.moveStart - 1e-9) {
      atStart = sim.world().Object(0).pose;
      started = true;
    }
    if (MaybeError e = sim.StepScript()) return *e;
    const ObjectState st = sim.world().Object(0);
    out.peakSpeed = std::max(out.peakSpeed, st.velocity.norm());
  }
  const ObjectState end = sim.world().Object(0);
  const Pose2 m = GripMotionAt(s, s.duration);
  out.endError = (end.pose.pos - ApplyMotion(m, atStart.pos)).norm();
  out.endAngleError = std::abs(WrapAngle(end.pose.angle - (atStart.angle + m.angle)));
  for (const FingerPath& path : Paths(s)) {
    for (size_t i = 1; i < path.keys.size(); ++i) {
      const double span = path.keys[i].first - path.keys[i - 1].first;
      if (span > 1e-9) {
        out.contactSpeed = std::max(out.contactSpeed,
                                    (path.keys[i].second - path.keys[i - 1].second).norm() / span);
      }
    }
  }
  out.followed = out.endError <= kFollowDistance && out.endAngleError <= kFollowAngle;
  out.ejected = out.peakSpeed > kSpeedFactor * out.contactSpeed + kSpeedAllowance;
  return out;
}

namespace {

// the rates at each substep count of the scenes `in` takes
template <typename In>
std::vector<GraspRates> ScoreRates(const GraspSweepReport& report, In&& in) {
  std::vector<GraspRates> all;
  for (size_t k = 0; k < report.options.substeps.size(); ++k) {
    GraspRates rates;
    rates.substeps = report.options.substeps[k];
    for (const GraspSceneResult& r : report.scenes) {
      if (!in(r)) continue;
      const GraspOutcome& o = r.outcomes[k];
      rates.ejections += o.ejected ? 1 : 0;
      rates.worstSpeedRatio = std::max(
          rates.worstSpeedRatio, o.peakSpeed / (kSpeedFactor * o.contactSpeed + kSpeedAllowance));
      if (r.prediction.nearBoundary) {
        ++rates.boundaryScenes;
      } else if (r.prediction.canHold) {
        ++rates.holdScenes;
        rates.holdFollowed += o.followed ? 1 : 0;
        rates.worstHoldError = std::max(rates.worstHoldError, o.endError);
      } else {
        ++rates.slipScenes;
        rates.slipSlipped += o.followed ? 0 : 1;
      }
    }
    all.push_back(rates);
  }
  return all;
}

}  // namespace

Result<GraspSweepReport> RunGraspSweep(const GraspSweepOptions& options) {
  if (options.scenes < 1) {
    return MakeError({}, "--count must be at least 1 (got " + std::to_string(options.scenes) + ")");
  }
  if (options.substeps.empty() && !options.ruleOnly)
    return MakeError({}, "--substeps names no substep count");
  for (int n : options.substeps) {
    if (n < 1 || n > 64) {
      return MakeError({}, "--substeps must be in [1, 64] (got " + std::to_string(n) + ")");
    }
  }
  if (options.threads < 1) {
    return MakeError({},
                     "--threads must be at least 1 (got " + std::to_string(options.threads) + ")");
  }
  if (!(options.holdShare >= 0.5 && options.holdShare <= 1.0)) {
    std::ostringstream got;
    got << options.holdShare;
    return MakeError({}, "--hold-share must be in [0.5, 1] (got " + got.str() + ")");
  }
  const GraspClasses& c = options.classes;
  if (!(c.bangBang || c.step) ||
      std::none_of(std::begin(c.topology), std::end(c.topology), [](bool on) { return on; })) {
    return MakeError({}, "--classes names no topology or no profile");
  }
  GraspSweepReport report;
  report.options = options;
  LevelParams defaults;
  if (MaybeError e = ApplyOverrides(defaults, options.sets)) return *e;
  // Draws in order; a can-hold draw is skipped once the kept ones reach the share. Parameters
  // under which nearly every draw can hold would draw for ever: after kMaxDrawsPerScene draws a
  // scene, every draw is kept.
  constexpr int kMaxDrawsPerScene = 20;
  const int holdQuota = HoldQuota(options);
  int kept = 0, keptHold = 0;
  for (int i = 0; kept < options.scenes; ++i) {
    GraspSceneResult r;
    r.scene = GenerateGraspScene(options.seed, i, options.classes);
    r.prediction = PredictGrasp(r.scene, defaults.physics, defaults.sensing.spacing);
    report.draws = i + 1;
    const bool hold = r.prediction.canHold && !r.prediction.nearBoundary;
    if (hold && keptHold >= holdQuota &&
        i < static_cast<int64_t>(kMaxDrawsPerScene) * options.scenes) {
      continue;
    }
    keptHold += hold ? 1 : 0;
    ++kept;
    r.outcomes.resize(options.ruleOnly ? 0 : options.substeps.size());
    report.scenes.push_back(std::move(r));
  }
  if (options.ruleOnly) return report;

  // every (scene, substep count) is independent
  const size_t jobs = report.scenes.size() * options.substeps.size();
  std::atomic<size_t> next{0};
  size_t done = 0;
  std::mutex errorMutex, progressMutex;
  std::optional<Error> firstError;
  auto work = [&] {
    for (size_t j = next++; j < jobs; j = next++) {
      GraspSceneResult& r = report.scenes[j / options.substeps.size()];
      const size_t k = j % options.substeps.size();
      Result<GraspOutcome> o = RunGraspScene(r.scene, options.substeps[k], options.sets);
      if (o.ok()) {
        r.outcomes[k] = o.value();
      } else {
        std::lock_guard<std::mutex> lock(errorMutex);
        if (!firstError) firstError = o.error();
      }
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progressMutex);
        options.progress(++done, jobs);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < options.threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (firstError) return *firstError;

  report.rates = ScoreRates(report, [](const GraspSceneResult&) { return true; });
  // per shape, motion and profile, topology and when the fingers slide
  auto addClass = [&](const std::string& group, const std::string& name, auto&& in) {
    GraspClassRates c;
    c.group = group;
    c.name = name;
    for (const GraspSceneResult& r : report.scenes) c.scenes += in(r) ? 1 : 0;
    if (c.scenes == 0) return;
    c.rates = ScoreRates(report, in);
    report.classRates.push_back(std::move(c));
  };
  for (int i = 0; i < 5; ++i) {
    addClass("shape", kGraspShapeNames[i],
             [i](const GraspSceneResult& r) { return static_cast<int>(r.scene.shape) == i; });
  }
  for (int m = 0; m < 3; ++m) {
    for (int f = 0; f < 2; ++f) {
      addClass("motion", std::string(kGraspMotionNames[m]) + " " + kGraspProfileNames[f],
               [m, f](const GraspSceneResult& r) {
                 return static_cast<int>(r.scene.motion) == m &&
                        static_cast<int>(r.scene.profile) == f;
               });
    }
  }
  for (int i = 0; i < kGraspTopologyCount; ++i) {
    addClass("topology", kGraspTopologyNames[i],
             [i](const GraspSceneResult& r) { return static_cast<int>(r.scene.topology) == i; });
  }
  for (const char* phase : {"before", "during", "after"}) {
    addClass("slide", phase, [phase](const GraspSceneResult& r) {
      return std::string(GraspEventPhase(r.scene)) == phase;
    });
  }

  if (!options.failuresDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.failuresDir, ec);
    if (ec)
      return MakeError({}, options.failuresDir + ": cannot create the folder: " + ec.message());
    for (const GraspSceneResult& r : report.scenes) {
      bool failed = false;
      for (const GraspOutcome& o : r.outcomes) {
        const bool wrong = !r.prediction.nearBoundary && o.followed != r.prediction.canHold;
        failed = failed || wrong || o.ejected;
      }
      if (!failed) continue;
      std::ostringstream name;
      name << options.failuresDir << "/grasp_" << options.seed << "_" << std::setw(3)
           << std::setfill('0') << r.scene.index << ".toml";
      std::ofstream file(name.str());
      file << "# Failed in the grasp sweep:";
      for (size_t k = 0; k < options.substeps.size(); ++k) {
        const GraspOutcome& o = r.outcomes[k];
        file << (k ? ";" : "") << " " << options.substeps[k] << " substeps: end "
             << std::setprecision(3) << o.endError << " cm, " << RadToDeg(o.endAngleError)
             << " deg, peak " << o.peakSpeed << " cm/s (contacts " << o.contactSpeed << ")";
      }
      file << "\n" << GraspSceneToml(r.scene, r.prediction);
      if (!file) return MakeError({}, name.str() + ": cannot write the scene");
    }
  }
  return report;
}

namespace {

std::string SceneLabel(const GraspScene& s) {
  std::ostringstream t;
  t << kGraspShapeNames[static_cast<int>(s.shape)] << " " << std::fixed << std::setprecision(0)
    << s.object.mass << " g, " << s.fingers.size()
    << (s.grip == GraspGrip::kCaged ? " caged" : " opposed") << ", depth " << std::setprecision(2)
    << s.depth << ", " << kGraspMotionNames[static_cast<int>(s.motion)];
  if (s.motion == GraspMotion::kCarry) {
    t << " " << std::setprecision(1) << s.distance << " cm at " << s.speed << " cm/s";
  } else if (s.motion == GraspMotion::kTurn) {
    t << " " << std::setprecision(0) << RadToDeg(s.turn) << " deg at " << RadToDeg(s.turnRate)
      << " deg/s";
  } else {
    t << " " << std::setprecision(2) << s.pushDepth << " cm deep";
  }
  t << " (" << kGraspProfileNames[static_cast<int>(s.profile)] << "), outlines "
    << kGraspTopologyNames[static_cast<int>(s.topology)];
  if (!s.fingersAfter.empty()) t << " " << GraspEventPhase(s) << " the motion";
  return t.str();
}

}  // namespace

std::string FormatGraspSweep(const GraspSweepReport& report) {
  std::ostringstream t;
  int hold = 0, slip = 0, boundary = 0;
  for (const GraspSceneResult& r : report.scenes) {
    (r.prediction.nearBoundary ? boundary : r.prediction.canHold ? hold : slip) += 1;
  }
  t << "grasp sweep: seed " << report.options.seed << ", " << report.scenes.size()
    << " scenes: the rule says " << hold << " can hold, " << slip << " cannot, " << boundary
    << " near the boundary (not scored)\n";
  if (report.draws > static_cast<int>(report.scenes.size())) {
    t << "  (" << report.draws << " drawn; can-hold draws beyond " << HoldQuota(report.options)
      << " skipped: --hold-share " << report.options.holdShare << ")\n";
  }
  for (int m = 0; m < 3; ++m) {
    int counts[3] = {0, 0, 0};
    for (const GraspSceneResult& r : report.scenes) {
      if (static_cast<int>(r.scene.motion) != m) continue;
      ++counts[r.prediction.nearBoundary ? 2 : r.prediction.canHold ? 0 : 1];
    }
    t << "  " << std::setw(5) << kGraspMotionNames[m] << ": " << counts[0] << " can hold, "
      << counts[1] << " cannot, " << counts[2] << " near the boundary\n";
  }
  t << "\n";
  t << "substeps  held&followed   slipping&slipped  ejections  worst hold error  worst speed\n";
  for (const GraspRates& r : report.rates) {
    t << std::setw(8) << r.substeps << "  " << std::setw(4) << r.holdFollowed << "/" << std::setw(4)
      << std::left << r.holdScenes << std::right << std::fixed << std::setprecision(1)
      << std::setw(6) << 100.0 * r.HoldRate() << "%  " << std::setw(4) << r.slipSlipped << "/"
      << std::setw(4) << std::left << r.slipScenes << std::right << std::setw(6)
      << 100.0 * r.SlipRate() << "%  " << std::setw(9) << r.ejections << "  " << std::setw(13)
      << std::setprecision(2) << r.worstHoldError << " cm  " << std::setw(10) << r.worstSpeedRatio
      << "\n";
  }
  t << "\n(worst speed: peak object speed / (1.5 x fastest contact + 5 cm/s); above 1 is an "
       "ejection)\n";
  if (!report.classRates.empty()) {
    t << "\nby class: held&followed, slipping&slipped, ejections at each substep count\n";
    std::string group;
    for (const GraspClassRates& c : report.classRates) {
      if (c.group != group) {
        group = c.group;
        t << "  " << group << "\n";
      }
      const GraspRates& first = c.rates.front();
      t << "    " << std::left << std::setw(16) << c.name << std::right << std::setw(4) << c.scenes
        << " (" << first.holdScenes << "/" << first.slipScenes << "/" << first.boundaryScenes
        << ")";
      for (const GraspRates& r : c.rates) {
        t << " | " << r.substeps << ": " << r.holdFollowed << "/" << r.holdScenes << " "
          << std::setprecision(1) << 100.0 * r.HoldRate() << "%, " << r.slipSlipped << "/"
          << r.slipScenes << " " << 100.0 * r.SlipRate() << "%, " << r.ejections;
      }
      t << "\n";
    }
    t << "  (scenes: can hold / cannot / near the boundary)\n";
  }
  t << "\nscenes the rule got wrong, or ejections:\n";
  int listed = 0;
  for (const GraspSceneResult& r : report.scenes) {
    bool wrong = false;
    for (const GraspOutcome& o : r.outcomes) {
      wrong =
          wrong || o.ejected || (!r.prediction.nearBoundary && o.followed != r.prediction.canHold);
    }
    if (!wrong) continue;
    ++listed;
    t << "  #" << std::setw(3) << r.scene.index << "  " << SceneLabel(r.scene) << "; margin "
      << std::setprecision(2) << r.prediction.margin << " ("
      << (r.prediction.canHold ? "hold" : "slip") << ")\n";
    for (size_t k = 0; k < r.outcomes.size(); ++k) {
      const GraspOutcome& o = r.outcomes[k];
      t << "        " << report.options.substeps[k] << " substeps: end " << o.endError << " cm, "
        << std::setprecision(1) << RadToDeg(o.endAngleError) << " deg, peak " << o.peakSpeed
        << " cm/s (contacts " << o.contactSpeed << ")" << (o.ejected ? " EJECTED" : "") << "\n"
        << std::setprecision(2);
    }
  }
  if (listed == 0) t << "  none\n";
  return t.str();
}

std::string GraspSweepJson(const GraspSweepReport& report) {
  std::ostringstream t;
  t << std::setprecision(6);
  t << "{\n  \"seed\": " << report.options.seed << ",\n  \"scenes\": " << report.scenes.size()
    << ",\n  \"draws\": " << report.draws << ",\n  \"hold_share\": " << report.options.holdShare
    << ",\n  \"classes_drawn\": \"" << (report.options.classes.IsLegacy() ? "legacy" : "issue 42")
    << "\""
    << ",\n  \"rates\": [";
  for (size_t k = 0; k < report.rates.size(); ++k) {
    const GraspRates& r = report.rates[k];
    t << (k ? "," : "") << "\n    {\"substeps\": " << r.substeps
      << ", \"hold_scenes\": " << r.holdScenes << ", \"hold_followed\": " << r.holdFollowed
      << ", \"hold_rate\": " << r.HoldRate() << ", \"slip_scenes\": " << r.slipScenes
      << ", \"slip_slipped\": " << r.slipSlipped << ", \"slip_rate\": " << r.SlipRate()
      << ", \"boundary_scenes\": " << r.boundaryScenes << ", \"ejections\": " << r.ejections
      << ", \"worst_hold_error_cm\": " << r.worstHoldError
      << ", \"worst_speed_ratio\": " << r.worstSpeedRatio << "}";
  }
  t << "\n  ],\n  \"classes\": [";
  for (size_t i = 0; i < report.classRates.size(); ++i) {
    const GraspClassRates& c = report.classRates[i];
    t << (i ? "," : "") << "\n    {\"group\": \"" << c.group << "\", \"class\": \"" << c.name
      << "\", \"scenes\": " << c.scenes << ", \"rates\": [";
    for (size_t k = 0; k < c.rates.size(); ++k) {
      const GraspRates& r = c.rates[k];
      t << (k ? ", " : "") << "{\"substeps\": " << r.substeps
        << ", \"hold_scenes\": " << r.holdScenes << ", \"hold_followed\": " << r.holdFollowed
        << ", \"hold_rate\": " << r.HoldRate() << ", \"slip_scenes\": " << r.slipScenes
        << ", \"slip_slipped\": " << r.slipSlipped << ", \"slip_rate\": " << r.SlipRate()
        << ", \"boundary_scenes\": " << r.boundaryScenes << ", \"ejections\": " << r.ejections
        << ", \"worst_speed_ratio\": " << r.worstSpeedRatio << "}";
    }
    t << "]}";
  }
  t << "\n  ],\n  \"results\": [";
  for (size_t i = 0; i < report.scenes.size(); ++i) {
    const GraspSceneResult& r = report.scenes[i];
    t << (i ? "," : "") << "\n    {\"index\": " << r.scene.index << ", \"shape\": \""
      << kGraspShapeNames[static_cast<int>(r.scene.shape)] << "\", \"motion\": \""
      << kGraspMotionNames[static_cast<int>(r.scene.motion)] << "\", \"profile\": \""
      << kGraspProfileNames[static_cast<int>(r.scene.profile)] << "\", \"topology\": \""
      << kGraspTopologyNames[static_cast<int>(r.scene.topology)] << "\", \"slide\": \""
      << GraspEventPhase(r.scene)
      << "\", \"margin\": " << (std::isfinite(r.prediction.margin) ? r.prediction.margin : 1e9)
      << ", \"margin_max\": "
      << (std::isfinite(r.prediction.marginMax) ? r.prediction.marginMax : 1e9)
      << ", \"slide_turn_deg\": " << RadToDeg(r.prediction.slideTurn)
      << ", \"fingers\": " << r.scene.fingers.size() << ", \"depth\": " << r.scene.depth
      << ", \"can_hold\": " << (r.prediction.canHold ? "true" : "false")
      << ", \"near_boundary\": " << (r.prediction.nearBoundary ? "true" : "false")
      << ", \"outcomes\": [";
    for (size_t k = 0; k < r.outcomes.size(); ++k) {
      const GraspOutcome& o = r.outcomes[k];
      t << (k ? ", " : "") << "{\"substeps\": " << report.options.substeps[k]
        << ", \"end_error_cm\": " << o.endError
        << ", \"end_angle_error_deg\": " << RadToDeg(o.endAngleError)
        << ", \"peak_speed\": " << o.peakSpeed << ", \"contact_speed\": " << o.contactSpeed
        << ", \"followed\": " << (o.followed ? "true" : "false") << "}";
    }
    t << "]}";
  }
  t << "\n  ]\n}\n";
  return t.str();
}

}  // namespace pg
