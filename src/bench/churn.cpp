#include "proxygrasp/bench/churn.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/run/simulation.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pg {
namespace {

// the contact travels back and forth along a segment this long through its start (a fast
// contact would otherwise leave the table), cm; a hand's segment is shorter so it stays on
constexpr double kPathLength = 30.0;
constexpr double kHandPathLength = 16.0;

// position along a back-and-forth path of length len after travelling distance s, in
// [-len/2, len/2] (a triangle wave starting at 0 and going up)
double BackAndForth(double s, double len) {
  const double u = std::fmod(s + 0.25 * 2.0 * len, 2.0 * len);  // 0 at the path's start
  return (u < len ? u : 2.0 * len - u) - 0.5 * len;
}

ContactShape ShapeAt(const ChurnScene& scene, double t) {
  ContactShape s = scene.shape;
  const bool hand = s.kind == ShapeKind::kHandFive || s.kind == ShapeKind::kHandFlat ||
                    s.kind == ShapeKind::kHandCupped;
  const double len = hand ? kHandPathLength : kPathLength;
  const double along = BackAndForth(scene.speed * t, len);
  s.pose.pos += along * Vec2(std::cos(scene.heading), std::sin(scene.heading));
  s.pose.angle += scene.turnRate * t;
  const double grow = 1.0 + scene.growth * t;
  s.radius *= grow;
  s.radiusX *= grow;
  s.radiusY *= grow;
  s.scale *= grow;
  return s;
}

ChurnScene AtCentre(std::string name, ContactShape shape) {
  ChurnScene scene;
  scene.name = std::move(name);
  shape.pose.pos = Vec2(30.5, 23.0);
  scene.shape = std::move(shape);
  return scene;
}

}  // namespace

ChurnScene FingertipScene() {
  ContactShape s;
  s.kind = ShapeKind::kCircle;
  s.radius = 0.8;
  return AtCentre("fingertip", s);
}

ChurnScene OvalScene() {
  ContactShape s;
  s.kind = ShapeKind::kEllipse;
  s.radiusX = 1.0;
  s.radiusY = 0.7;
  return AtCentre("oval", s);
}

ChurnScene FlatHandScene() {
  ContactShape s;
  s.kind = ShapeKind::kHandFlat;
  s.scale = 1.0;
  return AtCentre("flat hand", s);
}

double ChurnResult::CreatedPerSecond(double frameRate) const {
  return frames > 0 ? created * frameRate / frames : 0.0;
}

double ChurnResult::DeletedPerSecond(double frameRate) const {
  return frames > 0 ? deleted * frameRate / frames : 0.0;
}

Result<ChurnResult> MeasureChurn(const ChurnScene& scene, const LevelParams& params) {
  Level level;
  level.name = "churn: " + scene.name;
  level.params = params;
  Simulation sim;
  if (MaybeError e = sim.Start(level, params)) return *e;
  const double dt = sim.FrameDuration();
  const int frames = std::max(1, static_cast<int>(std::lround(scene.duration / dt)));
  ChurnResult r;
  std::unordered_map<ParticleId, Vec2> firstLocal;  // first frame's targets, contact frame
  std::unordered_map<ParticleId, Vec2> lastLocal;
  bool started = false;  // the contact has been on the table (a lost and found contact's new
                         // particles count as churn)
  for (int f = 0; f < frames; ++f) {
    const ContactShape shape = ShapeAt(scene, f * dt);
    if (MaybeError e = sim.StepShapes({&shape, 1})) return *e;
    const FrameStats& stats = sim.stats();
    r.contactsSeen = std::max(r.contactsSeen, stats.contacts);
    if (!started) {
      if (stats.contacts == 0) continue;
      r.firstParticles = stats.particles;
      started = true;
    } else {
      ++r.frames;
      r.created += stats.created;
      r.deleted += stats.deleted;
    }
    r.lastParticles = stats.particles;
    lastLocal.clear();
    for (const ParticleState& p : sim.world().Particles()) {
      const Vec2 local = shape.pose.Inverse(p.target);
      lastLocal[p.id] = local;
      if (r.frames == 0) firstLocal[p.id] = local;
    }
  }
  for (const auto& [id, local] : firstLocal) {
    const auto it = lastLocal.find(id);
    if (it == lastLocal.end()) continue;
    ++r.kept;
    r.maxDrift = std::max(r.maxDrift, (it->second - local).norm());
  }
  return r;
}

}  // namespace pg
