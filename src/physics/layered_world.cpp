#include "proxygrasp/physics/layered_world.h"

#include "world_impl.h"

#include "proxygrasp/core/params.h"
#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace pg {

namespace {

Error ParamError(const std::string& key, const std::string& what) {
  return MakeError(SourceLoc{}, "physics." + key + " " + what);
}

MaybeError ValidateParams(const PhysicsParams& p, const TableParams& t) {
  // every range comes from the parameters' description
  if (MaybeError s = CheckDescribed("physics", p)) return s;
  if (!(t.width > 0 && t.height > 0 && t.wallThickness > 0)) {
    return MakeError(SourceLoc{}, "table width, height and wall_thickness must be > 0");
  }
  return std::nullopt;
}

// an object's friction against particles: its own, or the default when it sets none
double ParticleFriction(const ObjectSpec& spec, const PhysicsParams& physics) {
  return spec.particleFriction >= 0 ? spec.particleFriction : physics.particleFriction;
}

b2Body* CreateWalls(b2World& world, const TableParams& t) {
  b2BodyDef bd;
  b2Body* walls = world.CreateBody(&bd);
  const float W = static_cast<float>(t.width), H = static_cast<float>(t.height);
  const float th = static_cast<float>(t.wallThickness);
  b2PolygonShape box;
  b2FixtureDef fd;
  fd.shape = &box;
  fd.friction = 0.0f;  // set per contact from the object (LayerListener::PreSolve)
  fd.filter.categoryBits = kWallBit;
  fd.filter.maskBits = kObjectBit;
  fd.userData.pointer = MakeTag(BodyKind::kWall, 0);
  // left, right, bottom, top; the long ones overlap at the corners
  box.SetAsBox(th / 2, H / 2 + th, b2Vec2(-th / 2, H / 2), 0.0f);
  walls->CreateFixture(&fd);
  box.SetAsBox(th / 2, H / 2 + th, b2Vec2(W + th / 2, H / 2), 0.0f);
  walls->CreateFixture(&fd);
  box.SetAsBox(W / 2 + th, th / 2, b2Vec2(W / 2, -th / 2), 0.0f);
  walls->CreateFixture(&fd);
  box.SetAsBox(W / 2 + th, th / 2, b2Vec2(W / 2, H + th / 2), 0.0f);
  walls->CreateFixture(&fd);
  return walls;
}

void HashBytes(uint64_t& h, const void* data, size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
}

template <typename T>
void HashValue(uint64_t& h, T v) {
  HashBytes(h, &v, sizeof(v));
}

}  // namespace

Pose2 ObjectData::Pose() const {
  Pose2 p;
  p.angle = angle;
  p.pos = center - Rotate(props.centroid, angle);
  return p;
}

void ObjectData::CachePose() {
  pose = Pose();
  cosA = std::cos(angle);
  sinA = std::sin(angle);
}

LayeredWorld::LayeredWorld() : m_impl(std::make_unique<Impl>()) {
  m_impl->pool = std::make_unique<ThreadPool>(1);
}
LayeredWorld::~LayeredWorld() = default;
LayeredWorld::LayeredWorld(LayeredWorld&&) noexcept = default;
LayeredWorld& LayeredWorld::operator=(LayeredWorld&&) noexcept = default;

MaybeError LayeredWorld::Build(const PhysicsParams& physics, const TableParams& table,
                               std::span<const ObjectSpec> objects) {
  // nothing is half-built: start from an empty world, fill it only when everything validated
  m_impl = std::make_unique<Impl>();
  Impl& w = *m_impl;
  w.pool = std::make_unique<ThreadPool>(1);
  if (MaybeError s = ValidateParams(physics, table)) return s;
  for (const ObjectSpec& spec : objects) {
    if (MaybeError s = ValidateObject(spec, physics)) return s;
    const MassProps props = ComputeMassProps(spec);
    const Vec2 c = spec.pose.Apply(props.centroid);
    if (c.x() < 0 || c.x() > table.width || c.y() < 0 || c.y() > table.height) {
      return MakeError(spec.loc, "object '" + spec.name + "': pose puts its centre at (" +
                                     FormatDouble(c.x()) + ", " + FormatDouble(c.y()) +
                                     ") cm, outside the " + FormatDouble(table.width) + " x " +
                                     FormatDouble(table.height) + " cm table");
    }
  }

  w.params = physics;
  w.table = table;
  w.frameSubsteps = physics.substeps;
  w.dt = 1.0 / (physics.frameRate * physics.substeps);
  w.pool = std::make_unique<ThreadPool>(physics.threads);

  // per-object friction tables the layer listeners read
  for (const ObjectSpec& spec : objects) {
    w.particleFriction.push_back(ParticleFriction(spec, physics));
    w.objectFriction.push_back(spec.objectFriction);
  }

  // one world per layer, no gravity (the table is the plane), walls at the table's edges
  for (int k = 0; k < physics.layers; ++k) {
    auto layer = std::make_unique<Layer>();
    layer->world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
    layer->world->SetAllowSleeping(false);
    layer->world->SetContinuousPhysics(true);
    layer->listener.particleFriction = &w.particleFriction;
    layer->listener.objectFriction = &w.objectFriction;
    layer->listener.records = &layer->records;
    layer->world->SetContactListener(&layer->listener);
    layer->walls = CreateWalls(*layer->world, table);
    w.layers.push_back(std::move(layer));
  }

  // objects: one slice per occupied layer, all sharing the object's pose and velocity
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    ObjectData o;
    o.spec = objects[oi];
    if (o.spec.name.empty()) o.spec.name = "object " + std::to_string(oi + 1);
    o.props = ComputeMassProps(o.spec);
    o.top = ObjectHeight(o.spec);
    o.rEff = EffectiveFrictionRadius(o.spec, o.props.centroid);
    o.tablePoints = TableFrictionPoints(o.spec, o.props.centroid);
    o.footprint = Footprint(o.spec);
    for (int i = 0; i < o.footprint.outline.cols(); ++i) {
      o.boundRadius = std::max(o.boundRadius, o.footprint.outline.col(i).norm());
    }
    o.boundRadius += 1e-6;
    o.center = o.spec.pose.Apply(o.props.centroid);
    o.angle = o.spec.pose.angle;
    o.vel = o.spec.velocity;
    o.omega = o.spec.angularVelocity;
    o.forces.assign(physics.layers, LayerForces{});
    const int n = SliceLayerCount(o.spec, physics.layerHeight, physics.layers);
    for (int k = 0; k < n; ++k) {
      Slice s;
      s.layer = k;
      s.z = SliceHeight(o.spec, k, physics.layerHeight);
      s.section = SectionAt(o.spec, s.z);
      b2BodyDef bd;
      bd.type = b2_dynamicBody;
      bd.allowSleep = false;
      s.body = w.layers[k]->world->CreateBody(&bd);
      b2FixtureDef fd;
      fd.density = 0.0f;  // the mass data is set by mass splitting
      fd.friction = static_cast<float>(o.spec.objectFriction);
      fd.restitution = static_cast<float>(o.spec.restitution);
      fd.filter.categoryBits = kObjectBit;
      fd.filter.maskBits = kObjectBit | kParticleBit | kWallBit;
      fd.userData.pointer = MakeTag(BodyKind::kObject, oi);
      if (s.section.circle) {
        b2CircleShape circle;
        circle.m_radius = static_cast<float>(s.section.radius);
        fd.shape = &circle;
        s.body->CreateFixture(&fd);
      } else {
        for (const Contour& piece : s.section.pieces) {
          b2Vec2 pts[b2_maxPolygonVertices];
          const int count = static_cast<int>(piece.cols());
          assert(count >= 3 && count <= b2_maxPolygonVertices && "convex piece out of range");
          for (int i = 0; i < count; ++i) pts[i] = ToB2(piece.col(i));
          b2PolygonShape poly;
          poly.Set(pts, count);
          fd.shape = &poly;
          s.body->CreateFixture(&fd);
        }
      }
      // table friction acts at the centre of mass; its limits are set every substep
      b2FrictionJointDef jd;
      jd.Initialize(w.layers[k]->walls, s.body, ToB2(o.center));
      jd.localAnchorB = ToB2(o.props.centroid);
      jd.collideConnected = true;  // the walls are the ground body, and they must stay walls
      s.table = static_cast<b2FrictionJoint*>(w.layers[k]->world->CreateJoint(&jd));
      o.slices.push_back(std::move(s));
    }
    w.objects.push_back(std::move(o));
  }
  // mass data first: it sets the slices' centre of mass, which the written pose refers to
  w.PrepareMassSplitting();
  for (ObjectData& o : w.objects) w.WriteBack(o);
  return std::nullopt;
}

void LayeredWorld::ApplyPlan(const ParticlePlan& plan) {
  Impl& w = *m_impl;
  if (w.layers.empty()) return;
  std::vector<uint8_t> gone;  // per particle entry: deleted by this plan (empty: none was)
  for (const PlannedParticle& pp : plan.particles) {
    auto it = w.particleIndex.find(pp.id);
    switch (pp.action) {
      case ParticleAction::kCreated: {
        if (it != w.particleIndex.end() || !pp.start.allFinite() || !pp.target.allFinite()) {
          ++w.planErrors;
          break;
        }
        ParticleData p;
        p.id = pp.id;
        p.contact = pp.contact;
        p.finger = pp.contact;
        p.prevTarget = pp.start;
        p.target = pp.target;
        p.born = true;
        p.baseHeight = std::max(0.0, pp.baseHeight);
        p.baseLayer = w.CreationLayer(pp.start, p.baseHeight);
        int layer;
        w.FindSupport(pp.start, p.baseLayer, &layer, &p.baseHeight, &p.restingOn);
        if (layer < p.baseLayer) p.baseLayer = layer;  // nothing there to rest on
        if (!std::isnan(pp.measured)) {
          // measured: resting where it was placed while the measurement agrees, hovering at it
          // otherwise; UpdateActivity gives it bodies in that layer
          p.measured = std::max(0.0, pp.measured);
          w.PlaceMeasured(p, pp.start);
        }
        // no bodies yet: the frame's UpdateActivity gives them to a stack within reach of an
        // object
        p.pos = pp.start;
        w.particleIndex[p.id] = static_cast<int>(w.particles.size());
        w.particles.push_back(std::move(p));
        break;
      }
      case ParticleAction::kReused:
        if (it == w.particleIndex.end() || !pp.target.allFinite()) {
          ++w.planErrors;
          break;
        }
        w.particles[it->second].target = pp.target;
        w.particles[it->second].contact = pp.contact;
        w.particles[it->second].measured =
            std::isnan(pp.measured) ? pp.measured : std::max(0.0, pp.measured);
        break;
      case ParticleAction::kDeleted: {
        if (it == w.particleIndex.end()) {
          ++w.planErrors;
          break;
        }
        // the bodies go now, in plan order; the entry is marked and removed below
        const int index = it->second;
        w.DestroyBodies(w.particles[index]);
        w.particleIndex.erase(it);
        gone.resize(w.particles.size(), 0);
        gone[index] = 1;
        break;
      }
    }
  }
  if (gone.empty()) return;
  // one pass removes the deleted entries keeping creation order (deterministic, and what
  // Particles() promises) and renumbers the index once: erasing and renumbering per deletion cost
  // O(particles) each, milliseconds in a frame where hands' contours shed hundreds of particles
  gone.resize(w.particles.size(), 0);
  int kept = 0;
  for (int i = 0; i < static_cast<int>(w.particles.size()); ++i) {
    if (gone[i]) continue;
    if (kept != i) w.particles[kept] = std::move(w.particles[i]);
    w.particleIndex[w.particles[kept].id] = kept;
    ++kept;
  }
  w.particles.resize(kept);
}

void LayeredWorld::StepFrame() {
  Impl& w = *m_impl;
  if (w.layers.empty()) return;
  const std::vector<double> pressed = w.PressingBodies();  // before the forces are cleared
  for (ObjectData& o : w.objects) {
    o.forces.assign(w.layers.size(), LayerForces{});
    o.topFriction.setZero();
    o.topNormal = 0.0;
  }
  // particles far from every object stay out of the Box2D worlds this frame
  w.UpdateActivity();
  w.UpdateSpin();
  // enough substeps for the bodies about to press each object (docs/physics.md, "Substeps that
  // keep a grip stable")
  if (const int n = w.StableSubsteps(pressed); n != w.frameSubsteps) w.UseSubsteps(n);

  // substeps: control, step the layers, couple, support
  const int S = w.frameSubsteps;
  w.box2dMs = 0.0;
  for (int s = 0; s < S; ++s) {
    w.ApplyKinematicControl(static_cast<double>(s + 1) / S);
    w.PrepareMassSplitting();
    w.PrepareTableFriction();
    w.ApplyPushes();
    if (w.box2dClock) {
      const Stopwatch watch(*w.box2dClock);
      w.StepLayers();
      w.box2dMs += watch.Ms();
    } else {
      w.StepLayers();
    }
    w.PlaceFreeBodies();
    w.Couple();
    w.CollectRecords(s == S - 1);
    w.UpdateSupport();
    if (w.observer) w.observer(s);
  }

  // impulses summed over the frame become the frame's mean forces
  const double frameTime = 1.0 / w.params.frameRate;
  for (ObjectData& o : w.objects) {
    for (LayerForces& f : o.forces) {
      f.normal /= frameTime;
      f.friction /= frameTime;
      f.normalMagnitude /= frameTime;
      f.frictionMagnitude /= frameTime;
    }
    o.topFriction /= frameTime;
    o.topNormal /= frameTime;
    o.pushes.clear();
  }
  for (ParticleData& p : w.particles) {
    p.prevTarget = p.target;
    p.born = false;
  }
  ++w.frame;
}

void LayeredWorld::ApplyForce(ObjectId object, const Vec2& force, const Vec2& worldPoint,
                              int layer) {
  Impl& w = *m_impl;
  // bad pushes are counted and dropped, never simulated
  if (object < 0 || object >= ObjectCount() || !force.allFinite() || !worldPoint.allFinite()) {
    ++w.planErrors;
    return;
  }
  ObjectData& o = w.objects[object];
  Push p;
  p.force = force;
  p.point = worldPoint;
  p.layer = std::clamp(layer, 0, static_cast<int>(o.slices.size()) - 1);
  o.pushes.push_back(p);
}

double LayeredWorld::TopHeightAt(const Vec2& p) const {
  double best = 0.0;
  for (const ObjectData& o : m_impl->objects) {
    if (!o.MayHold(p)) continue;
    best = std::max(best, SurfaceHeightAt(o.spec, o.ToLocal(p)));
  }
  return best;
}

double LayeredWorld::FootprintDepth(const Vec2& p, double* topHeight) const {
  double depth = -1e300, top = 0.0, bestTop = -1.0;
  for (const ObjectData& o : m_impl->objects) {
    const double d = FootprintSignedDistance(o.spec, o.footprint, o.ToLocal(p));
    if (d > 0) {
      // inside: the highest object wins
      if (o.top > bestTop) {
        bestTop = o.top;
        depth = d;
        top = o.top;
      }
    } else if (bestTop < 0) {
      depth = std::max(depth, d);
    }
  }
  if (topHeight != nullptr) *topHeight = top;
  return m_impl->objects.empty() ? -1e300 : depth;
}

ObjectId LayeredWorld::ObjectAt(const Vec2& p) const {
  ObjectId best = kNoObject;
  double bestTop = -1.0;
  for (ObjectId i = 0; i < ObjectCount(); ++i) {
    const ObjectData& o = m_impl->objects[i];
    if (o.top > bestTop && o.MayHold(p) &&
        FootprintSignedDistance(o.spec, o.footprint, o.ToLocal(p)) > 0) {
      best = i;
      bestTop = o.top;
    }
  }
  return best;
}

Vec2 LayeredWorld::NearestOutside(const Vec2& p) const {
  const auto& objects = m_impl->objects;
  constexpr double kEps = 1e-6;  // how far outside the boundary the answer lies, cm
  auto inside = [&](const Vec2& q) {
    for (const ObjectData& o : objects) {
      // the bound radius holds the footprint and 1e-6 cm more, so MayHold passes every point
      // this accepts
      if (o.MayHold(q) && FootprintSignedDistance(o.spec, o.footprint, o.ToLocal(q)) > -kEps / 2) {
        return true;
      }
    }
    return false;
  };
  if (!inside(p)) return p;
  Vec2 best = p;
  double bestD = 1e300;
  auto consider = [&](const Vec2& q) {
    const double d = (q - p).norm();
    if (d < bestD && !inside(q)) {
      bestD = d;
      best = q;
    }
  };
  // p projected out through each footprint's nearest edge; any free point lies at least as far
  // as the deepest footprint holding p is deep, so a free candidate that close is the answer
  double lowerBound = 0.0;
  for (const ObjectData& o : objects) {
    const Pose2& pose = o.pose;
    const Vec2 local = o.ToLocal(p);
    lowerBound = std::max(lowerBound, FootprintSignedDistance(o.spec, o.footprint, local));
    const Vec2 edge = NearestFootprintPoint(o.footprint, local);
    const Vec2 out = FootprintSignedDistance(o.spec, o.footprint, local) > 0 ? Vec2(edge - local)
                                                                             : Vec2(local - edge);
    consider(pose.Apply(edge + kEps * (out.norm() > 1e-12 ? Vec2(out.normalized()) : Vec2(1, 0))));
  }
  if (bestD <= lowerBound + 2 * kEps) return best;
  // overlapping footprints need a search: march out along 64 rays and bisect the first free
  // point on each
  constexpr int kRays = 64;
  constexpr double kStep = 0.05, kReach = 200.0;  // cm
  for (int i = 0; i < kRays; ++i) {
    const double a = 2.0 * kPi * i / kRays;
    const Vec2 dir(std::cos(a), std::sin(a));
    double lo = 0.0, hi = -1.0;
    for (double t = kStep; t < std::min(kReach, bestD + kStep); t += kStep) {
      if (!inside(p + t * dir)) {
        hi = t;
        break;
      }
      lo = t;
    }
    if (hi < 0) continue;
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (inside(p + mid * dir) ? lo : hi) = mid;
    }
    consider(p + hi * dir);
  }
  return best;
}

std::vector<ParticleFeedback> LayeredWorld::Feedback() const {
  std::vector<ParticleFeedback> out;
  out.reserve(m_impl->particles.size());
  for (const ParticleData& p : m_impl->particles) {
    ParticleFeedback f;
    f.id = p.id;
    f.pos = Impl::BasePosition(p);
    f.baseHeight = p.baseHeight;
    out.push_back(f);
  }
  return out;
}

int LayeredWorld::ObjectCount() const {
  return static_cast<int>(m_impl->objects.size());
}

ObjectState LayeredWorld::Object(ObjectId i) const {
  assert(i >= 0 && i < ObjectCount() && "object index out of range");
  const ObjectData& o = m_impl->objects[i];
  ObjectState s;
  s.name = o.spec.name;
  s.pose = o.pose;
  s.velocity = o.vel;
  s.angularVelocity = o.omega;
  s.centerOfMass = o.center;
  s.held = o.held;
  s.topHeight = o.top;
  s.mass = o.props.mass;
  s.inertia = o.props.inertia;
  s.layerCount = static_cast<int>(o.slices.size());
  s.particlesOnTop = o.particlesOnTop;
  return s;
}

ObjectForces LayeredWorld::Forces(ObjectId i) const {
  assert(i >= 0 && i < ObjectCount() && "object index out of range");
  const ObjectData& o = m_impl->objects[i];
  ObjectForces f;
  f.layers = o.forces;
  for (const LayerForces& l : o.forces) {
    f.total.normal += l.normal;
    f.total.friction += l.friction;
    f.total.normalMagnitude += l.normalMagnitude;
    f.total.frictionMagnitude += l.frictionMagnitude;
    f.total.contacts += l.contacts;
  }
  f.topFriction = o.topFriction;
  f.topNormal = o.topNormal;
  return f;
}

std::vector<SliceOutline> LayeredWorld::Slices(ObjectId i) const {
  assert(i >= 0 && i < ObjectCount() && "object index out of range");
  std::vector<SliceOutline> out;
  for (const Slice& s : m_impl->objects[i].slices) {
    SliceOutline so;
    so.layer = s.layer;
    so.z = s.z;
    so.outline = s.section.outline;
    so.pieces = s.section.circle ? std::vector<Contour>{s.section.outline} : s.section.pieces;
    out.push_back(std::move(so));
  }
  return out;
}

std::vector<ParticleState> LayeredWorld::Particles() const {
  std::vector<ParticleState> out;
  out.reserve(m_impl->particles.size());
  for (const ParticleData& p : m_impl->particles) {
    ParticleState s;
    s.id = p.id;
    s.contact = p.contact;
    s.pos = Impl::BasePosition(p);
    s.target = p.target;
    s.baseHeight = p.baseHeight;
    s.baseLayer = p.baseLayer;
    s.layerCount = m_impl->StackLayers(p);
    s.restingOn = p.restingOn;
    s.measured = p.measured;
    s.aloft = p.aloft;
    s.active = p.active;
    out.push_back(s);
  }
  return out;
}

int LayeredWorld::ParticleCount() const {
  return static_cast<int>(m_impl->particles.size());
}

int LayeredWorld::ActiveParticleCount() const {
  int n = 0;
  for (const ParticleData& p : m_impl->particles) n += p.active ? 1 : 0;
  return n;
}

int LayeredWorld::SolvedBodyCount() const {
  int n = 0;
  for (const ParticleData& p : m_impl->particles) {
    for (const b2Body* b : p.bodies) n += b->IsAwake() ? 1 : 0;
  }
  return n;
}

int LayeredWorld::InWorldBodyCount() const {
  int n = 0;
  for (const ParticleData& p : m_impl->particles) {
    for (const b2Body* b : p.bodies) n += b->IsEnabled() ? 1 : 0;
  }
  return n;
}

int LayeredWorld::BodyCount() const {
  int n = 0;
  for (const auto& layer : m_impl->layers) n += layer->world->GetBodyCount() - 1;  // walls
  return n;
}

int64_t LayeredWorld::Frame() const {
  return m_impl->frame;
}

int LayeredWorld::FrameSubsteps() const {
  return m_impl->frameSubsteps;
}

int LayeredWorld::PlanErrors() const {
  return m_impl->planErrors;
}

std::vector<std::string> LayeredWorld::FixedKeysChanged(const PhysicsParams& physics) const {
  // the keys described as needing a restart (Apply::kRestart)
  return RestartKeysChanged("physics", m_impl->params, physics);
}

MaybeError LayeredWorld::SetParams(const PhysicsParams& physics) {
  Impl& w = *m_impl;
  if (w.layers.empty()) return MakeError(SourceLoc{}, "physics: SetParams before Build");
  if (MaybeError s = ValidateParams(physics, w.table)) return s;
  const std::vector<std::string> fixed = FixedKeysChanged(physics);
  if (!fixed.empty()) {
    return ParamError(fixed.front(), "cannot change while the world runs; rebuild it");
  }
  const PhysicsParams old = w.params;
  w.params = physics;
  if (physics.threads != old.threads) w.pool = std::make_unique<ThreadPool>(physics.threads);
  for (size_t oi = 0; oi < w.objects.size(); ++oi) {
    w.particleFriction[oi] = ParticleFriction(w.objects[oi].spec, physics);
  }
  if (physics.gripStiffness != old.gripStiffness || physics.gripDamping != old.gripDamping ||
      physics.substeps != w.frameSubsteps) {
    w.UseSubsteps(physics.substeps);
  }
  return std::nullopt;
}

void LayeredWorld::Step(const ParticlePlan& plan) {
  ApplyPlan(plan);
  StepFrame();
}

const PhysicsParams& LayeredWorld::params() const {
  return m_impl->params;
}

uint64_t LayeredWorld::StateHash() const {
  uint64_t h = 14695981039346656037ull;
  for (const ObjectData& o : m_impl->objects) {
    HashValue(h, o.center.x());
    HashValue(h, o.center.y());
    HashValue(h, o.angle);
    HashValue(h, o.vel.x());
    HashValue(h, o.vel.y());
    HashValue(h, o.omega);
  }
  for (const ParticleData& p : m_impl->particles) {
    HashValue(h, p.id);
    HashValue(h, p.baseLayer);
    for (int j = 0; j < static_cast<int>(p.bodies.size()); ++j) {
      const b2Vec2 x = p.bodies[j]->GetPosition();
      const b2Vec2 v = ToB2(Impl::BodyVelocity(p, j));
      HashValue(h, x.x);
      HashValue(h, x.y);
      HashValue(h, v.x);
      HashValue(h, v.y);
    }
    if (p.bodies.empty()) {
      HashValue(h, p.pos.x());
      HashValue(h, p.pos.y());
      HashValue(h, p.vel.x());
      HashValue(h, p.vel.y());
    }
  }
  return h;
}

bool LayeredWorld::SlicesAgree() const {
  for (const ObjectData& o : m_impl->objects) {
    const b2Body* first = o.slices.front().body;
    const b2Transform xf = first->GetTransform();
    for (const Slice& s : o.slices) {
      const b2Transform t = s.body->GetTransform();
      if (std::memcmp(&t, &xf, sizeof(xf)) != 0) return false;
      if (s.body->GetAngle() != first->GetAngle()) return false;
      const b2Vec2 v = s.body->GetLinearVelocity(), v0 = first->GetLinearVelocity();
      if (v.x != v0.x || v.y != v0.y) return false;
      if (s.body->GetAngularVelocity() != first->GetAngularVelocity()) return false;
    }
  }
  return true;
}

void LayeredWorld::SetBox2DClock(std::optional<TimerClock> clock) {
  m_impl->box2dClock = clock;
}

double LayeredWorld::Box2DMs() const {
  return m_impl->box2dMs;
}

void LayeredWorld::SetSubstepObserver(std::function<void(int)> observer) {
  m_impl->observer = std::move(observer);
}

void LayeredWorld::KeepFreeBodiesInWorlds(bool keep) {
  m_impl->keepFreeBodies = keep;
}

}  // namespace pg
