// Particle stacks: creation in consecutive layers, kinematic control (Wilson, ITS 2009,
// "KINEMATIC CONTROL") and support: a stack keeps its base layer while something holds it there
// and otherwise falls to the highest surface below; it never climbs.
#include "world_impl.h"

#include <algorithm>
#include <cmath>

namespace pg {

int LayeredWorld::Impl::LayerOf(double z) const {
  const int k = static_cast<int>(std::lround(z / params.layerHeight));
  return std::clamp(k, 0, LayerCount() - 1);
}

int LayeredWorld::Impl::SupportLayer(int o, double h) const {
  // the first layer above the object's slices, even for slabs thinner than half a layer
  const int above = static_cast<int>(objects[o].slices.size());
  return std::min(std::max(LayerOf(h), above), LayerCount() - 1);
}

void LayeredWorld::Impl::FindSupport(const Vec2& p, int maxLayer, int* layer, double* height,
                                     ObjectId* object) const {
  *layer = 0;
  *height = 0.0;
  *object = kNoObject;
  // with one layer nothing can rest on an object's top
  if (LayerCount() < 2) return;
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    const ObjectData& o = objects[oi];
    if (!o.MayHold(p)) continue;
    const double h = SurfaceHeightAt(o.spec, o.ToLocal(p));
    if (h < 0) continue;
    const int k = SupportLayer(oi, h);
    if (k > maxLayer) continue;
    if (k > *layer || (k == *layer && h > *height)) {
      *layer = k;
      *height = h;
      *object = oi;
    }
  }
}

int LayeredWorld::Impl::CreationLayer(const Vec2& p, double baseHeight) const {
  int k = LayerOf(baseHeight);
  if (baseHeight <= 0 || LayerCount() < 2) return k;
  // resting on an object's surface at that height: use the layer above its slices
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    if (!objects[oi].MayHold(p)) continue;
    const double h = SurfaceHeightAt(objects[oi].spec, objects[oi].ToLocal(p));
    if (h >= 0 && LayerOf(h) == LayerOf(baseHeight)) k = std::max(k, SupportLayer(oi, h));
  }
  return k;
}

double LayeredWorld::Impl::ParticleMass() const {
  return params.gripStiffness * dt * dt + params.gripDamping * dt;
}

double LayeredWorld::Impl::GripPush(double depth, double goalSpeed) const {
  return params.gripStiffness * std::min(depth, params.gripMaxDepth) +
         params.gripDamping * goalSpeed;
}

b2MassData LayeredWorld::Impl::ParticleMassData() const {
  b2MassData md;
  md.mass = static_cast<float>(ParticleMass());
  md.center.SetZero();
  md.I = 0.0f;  // rotation is fixed
  return md;
}

// Bodies pressing an object each act on where its face was when the substep began. Pushed
// towards one side, the object carries that side's bodies with it in the contact solve (their
// mass adds to its own) while the other side's push is still the one from the substep's start:
// with n bodies of mass m pressing, a mass-spring chain of stiffness n k and mass M + n m / 2
// stepped with dt, stable while n k dt^2 < 4/3 (M + n m / 2), which with m = k dt^2 is n m < 4 M.
// levels/deep_squeeze.toml's 20 g box, pressed by 20 to 27 bodies, chattered at 2 substeps
// (n m = 80 to 108 g) and held still at 3 (36 to 48 g); with 2 substeps it held for a box of
// 30 g and more (n m / M up to 3.6) and chattered for 25 g (4.3). Frames keep n m at half the
// limit, 2 M: at 2.9 M a pusher arriving within one frame still let that box give 17% more
// than at 2 M (Substeps test).
constexpr double kStableMassRatio = 2.0;

std::vector<double> LayeredWorld::Impl::PressingBodies() const {
  // a layer's contacts times the share of their normal force that opposing contacts cancel: all
  // of it for a balanced squeeze, none for a push from one side
  std::vector<double> pressed(objects.size(), 0.0);
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    for (const LayerForces& f : objects[oi].forces) {
      if (f.contacts == 0 || !(f.normalMagnitude > 0.0)) continue;
      pressed[oi] += f.contacts * (1.0 - std::min(1.0, f.normal.norm() / f.normalMagnitude));
    }
  }
  return pressed;
}

int LayeredWorld::Impl::StableSubsteps(const std::vector<double>& pressed) const {
  const int least = params.substeps;
  const int most = std::max(params.maxSubsteps, least);
  int needed = least;
  if (most == least) return needed;
  // bodies whose targets lie on or within a body's radius of a footprint will press it this
  // frame, inwards where their target is nearest its edge; as above, count those that opposing
  // ones cancel
  std::vector<double> coming(objects.size(), 0.0);
  std::vector<Vec2> pushes(objects.size(), Vec2::Zero());
  const double r = params.particleRadius;
  for (const ParticleData& p : particles) {
    if (!p.active || p.bodies.empty() || p.restingOn != kNoObject) continue;
    for (size_t oi = 0; oi < objects.size(); ++oi) {
      const ObjectData& o = objects[oi];
      const double reach = o.boundRadius + r;
      if ((p.target - o.pose.pos).squaredNorm() > reach * reach) continue;
      const Vec2 local = o.ToLocal(p.target);
      const double depth = FootprintSignedDistance(o.spec, o.footprint, local);
      if (depth <= -r) continue;
      // its bodies in the layers the object's slices occupy
      const int top = p.baseLayer + static_cast<int>(p.bodies.size());
      const int n = std::min(top, static_cast<int>(o.slices.size())) - p.baseLayer;
      if (n <= 0) continue;
      Vec2 inward = NearestFootprintPoint(o.footprint, local) - local;
      if (depth > 0.0) inward = -inward;
      const double length = inward.norm();
      if (!(length > 1e-9)) inward = o.props.centroid - local;
      coming[oi] += n;
      pushes[oi] += n * inward.normalized();
    }
  }
  const double k = params.gripStiffness, c = params.gripDamping;
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    const double n = std::max(pressed[oi], coming[oi] - pushes[oi].norm());
    if (!(n > 0.5)) continue;
    // the longest substep with n (k dt^2 + c dt) <= kStableMassRatio M
    const double budget = kStableMassRatio * objects[oi].props.mass / n;
    const double dtMax = (std::sqrt(c * c + 4.0 * k * budget) - c) / (2.0 * k);
    const double steps = std::ceil(1.0 / (params.frameRate * dtMax) - 1e-9);
    if (steps > needed) needed = steps >= most ? most : static_cast<int>(steps);
  }
  return needed;
}

void LayeredWorld::Impl::UseSubsteps(int n) {
  frameSubsteps = n;
  dt = 1.0 / (params.frameRate * n);
  const b2MassData md = ParticleMassData();
  for (ParticleData& p : particles) {
    for (b2Body* b : p.bodies) b->SetMassData(&md);
  }
}

void LayeredWorld::Impl::CreateBodies(ParticleData& p, const Vec2& pos, const Vec2& vel) {
  assert(p.bodies.empty() && "stack already has bodies");
  const int top = p.baseLayer + StackLayers(p);
  b2CircleShape circle;
  circle.m_radius = static_cast<float>(params.particleRadius);
  b2FixtureDef fd;
  fd.shape = &circle;
  fd.density = 1.0f;
  fd.friction = 0.0f;  // set per contact from the object (LayerListener::PreSolve)
  fd.restitution = 0.0f;
  fd.filter.categoryBits = kParticleBit;
  fd.filter.maskBits = kObjectBit;
  fd.userData.pointer = MakeTag(BodyKind::kParticle, 0);
  const b2MassData md = ParticleMassData();
  for (int k = p.baseLayer; k < top; ++k) {
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position = ToB2(pos);
    bd.linearVelocity = ToB2(vel);
    bd.fixedRotation = true;
    bd.allowSleep = false;
    b2Body* body = layers[k]->world->CreateBody(&bd);
    body->CreateFixture(&fd);
    body->SetMassData(&md);
    p.bodies.push_back(body);
  }
  p.freeVel.assign(p.bodies.size(), vel);
  p.freeAim.assign(p.bodies.size(), pos);
  p.freeNow.assign(p.bodies.size(), 0);
}

void LayeredWorld::Impl::DestroyBodies(ParticleData& p) {
  for (int j = 0; j < static_cast<int>(p.bodies.size()); ++j) {
    layers[p.baseLayer + j]->world->DestroyBody(p.bodies[j]);
  }
  p.bodies.clear();
  p.freeVel.clear();
  p.freeAim.clear();
  p.freeNow.clear();
}

int LayeredWorld::Impl::StackLayers(const ParticleData& p) const {
  const int K = LayerCount();
  return (params.capsule ? K : std::min(K, p.baseLayer + params.stackSize)) - p.baseLayer;
}

Vec2 LayeredWorld::Impl::BasePosition(const ParticleData& p) {
  return p.bodies.empty() ? p.pos : FromB2(p.bodies.front()->GetPosition());
}

Vec2 LayeredWorld::Impl::BaseVelocity(const ParticleData& p) {
  return p.bodies.empty() ? p.vel : BodyVelocity(p, 0);
}

Vec2 LayeredWorld::Impl::BodyVelocity(const ParticleData& p, int j) {
  const b2Body* b = p.bodies[j];
  return b->IsAwake() ? FromB2(b->GetLinearVelocity()) : p.freeVel[j];
}

void LayeredWorld::Impl::ApplyParticleImpulse(ParticleData& p, int j, const Vec2& impulse) const {
  if (p.bodies.empty()) {
    p.vel += impulse / ParticleMass();
    return;
  }
  b2Body* b = p.bodies[j];
  if (b->IsAwake()) {
    b->ApplyLinearImpulseToCenter(ToB2(impulse), true);
  } else {
    p.freeVel[j] += impulse / ParticleMass();
  }
}

void LayeredWorld::Impl::PlaceFreeBodies() {
  for (ParticleData& p : particles) {
    if (!p.active) continue;
    for (int j = 0; j < static_cast<int>(p.bodies.size()); ++j) {
      if (!p.freeNow[j]) continue;
      b2Body* b = p.bodies[j];
      // a contact that stopped touching at the step's start wakes its bodies (b2Contact::Update);
      // such a body took part in the step alone, without velocity or force, so it did not move
      b->SetAwake(false);
      b->SetTransform(ToB2(p.freeAim[j]), 0.0f);
    }
  }
}

b2Fixture* LayeredWorld::Impl::StopAtSurface(b2Body* body, const Vec2& x, Vec2* aim,
                                             const std::vector<b2Fixture*>& unpaired) const {
  // The plain control would move the body to its aim in one substep, up to 0.5 cm into an object
  // at full grip (d_max); a contact that is not in the solver yet cannot stop it. Cast the circle
  // along its path against the objects it has contacts with (its fat bounding box overlaps
  // theirs), and those it will have at the step's start (unpaired), and stop it where it first
  // meets one: the next substep finds the contact and presses.
  const Vec2 path = *aim - x;
  if (path.squaredNorm() == 0.0) return nullptr;
  double lambda = 1.0;
  b2Fixture* hit = nullptr;
  const b2Fixture* particle = body->GetFixtureList();
  // the box the body sweeps: a fixture whose (fattened) box it misses cannot stop it
  const double r = params.particleRadius;
  b2AABB swept;
  swept.lowerBound = ToB2(Vec2(x.cwiseMin(*aim).array() - r));
  swept.upperBound = ToB2(Vec2(x.cwiseMax(*aim).array() + r));
  auto cast = [&](b2Fixture* other, int child) {
    if (!b2TestOverlap(other->GetAABB(child), swept)) return;
    b2ShapeCastInput input;
    input.proxyA.Set(other->GetShape(), child);
    input.proxyB.Set(particle->GetShape(), 0);
    input.transformA = other->GetBody()->GetTransform();
    input.transformB = body->GetTransform();
    input.translationB = ToB2(path);
    b2ShapeCastOutput output;
    if (b2ShapeCast(&output, &input) && output.lambda < lambda) {
      lambda = output.lambda;
      hit = other;
    }
  };
  for (b2ContactEdge* e = body->GetContactList(); e != nullptr; e = e->next) {
    b2Contact* contact = e->contact;
    const bool particleIsA = contact->GetFixtureA() == particle;
    cast(particleIsA ? contact->GetFixtureB() : contact->GetFixtureA(),
         particleIsA ? contact->GetChildIndexB() : contact->GetChildIndexA());
  }
  for (b2Fixture* other : unpaired) cast(other, 0);
  *aim = x + lambda * path;
  return hit;
}

void LayeredWorld::Impl::FindUnpaired(int layer, const b2Body* body, const Vec2& x, const Vec2& aim,
                                      std::vector<b2Fixture*>* unpaired) const {
  // A body put on its aim by SetTransform gets a bounding box without Box2D's allowance for its
  // motion, and its new pairs are found only at the next step's start, after the control has
  // looked at its contacts. List the object fixtures in its layer that its path comes near
  // (bounding boxes within Box2D's fattening) and that it has no contact with yet.
  unpaired->clear();
  const double reach = params.particleRadius + b2_aabbExtension;
  b2AABB swept;
  swept.lowerBound = ToB2(Vec2(x.cwiseMin(aim).array() - reach));
  swept.upperBound = ToB2(Vec2(x.cwiseMax(aim).array() + reach));
  for (const ObjectData& o : objects) {
    if (layer >= static_cast<int>(o.slices.size())) continue;
    for (b2Fixture* f = o.slices[layer].body->GetFixtureList(); f != nullptr; f = f->GetNext()) {
      if (!b2TestOverlap(f->GetAABB(0), swept)) continue;
      bool paired = false;
      for (const b2ContactEdge* e = body->GetContactList(); e != nullptr && !paired; e = e->next) {
        paired = e->contact->GetFixtureA() == f || e->contact->GetFixtureB() == f;
      }
      if (!paired) unpaired->push_back(f);
    }
  }
}

bool LayeredWorld::Impl::NearSlices(int layer, const Vec2& x, const Vec2& aim, double extra) const {
  // the path lies within half its length of its midpoint; every slice lies within the footprint
  const Vec2 mid = 0.5 * (x + aim);
  const double half = 0.5 * (aim - x).norm();
  const double reach = params.particleRadius + b2_aabbExtension + extra + half;
  for (const ObjectData& o : objects) {
    if (layer >= static_cast<int>(o.slices.size())) continue;
    const double within = reach + o.FastestPointSpeed() * dt;
    const double far = o.boundRadius + within;
    if ((mid - o.pose.pos).squaredNorm() > far * far) continue;
    if (-FootprintSignedDistance(o.spec, o.footprint, o.ToLocal(mid)) <= within) return true;
  }
  return false;
}

void LayeredWorld::Impl::PressOnArrival(int layer, b2Fixture* surface, const Vec2& stop,
                                        const Vec2& goal, const ParticleData& p) {
  // Without this, every body that comes off a surface by more than Box2D's skin (a grip
  // rattling, a turn sliding the bodies along a face) pressed with nothing for a substep while
  // the other side of the grip pushed in full, and a light object shot towards it.
  const uintptr_t tag = surface->GetUserData().pointer;
  if (TagKind(tag) != BodyKind::kObject) return;
  b2Body* slice = surface->GetBody();
  // the distance from the face's core to the body's centre gives the normal where it arrives
  b2CircleShape centre;
  centre.m_radius = 0.0f;
  b2DistanceInput input;
  input.proxyA.Set(surface->GetShape(), 0);
  input.proxyB.Set(&centre, 0);
  input.transformA = slice->GetTransform();
  input.transformB = b2Transform(ToB2(stop), b2Rot(0.0f));
  input.useRadii = false;
  b2SimplexCache cache;
  cache.count = 0;
  b2DistanceOutput output;
  b2Distance(&output, &cache, &input);
  if (output.distance <= 0.0f) return;  // the centre inside the core: no normal to press along
  const Vec2 point = FromB2(output.pointA);
  const Vec2 in = (point - FromB2(output.pointB)) / static_cast<double>(output.distance);
  const double d = (goal - stop).dot(in);
  if (d <= 0.0) return;
  const double push = GripPush(d, p.goalVel.dot(in));
  if (push <= 0.0) return;
  slice->ApplyForce(ToB2(push * in), ToB2(point), true);
  ContactRecord r;
  r.object = TagIndex(tag);
  r.normalIn = in;
  r.tangentIn = Vec2(-in.y(), in.x());
  r.normalImpulse = push * dt;
  r.friction = particleFriction[r.object];
  r.points = 1;
  r.point = point;
  r.padVel = p.padVel;
  layers[layer]->records.push_back(r);
}

// How far a pressing body overlaps the face it presses on, cm. Box2D's contact stops a body's
// approach at the velocity level and pushes overlaps beyond its slop apart, so nothing closes a
// gap within the skin: over the substeps of a turn a pressing body drifted out by the
// second-order difference between its straight path and the face's arc, until the contact was
// gone. In that substep the body was stopped at the face without its friction while the face
// moved on, so it fell behind by the face's travel in one substep, and its spring then dragged
// the object forward: a box turned by two rings at 110 degrees/s ran ahead of them by 3.6% at 2
// substeps (about omega^2 dt^2). A pressing body that has drifted out to less than half this
// overlap is seated this far into the face (half of Box2D's slop, inside the range its position
// solver leaves alone), so it keeps its contact and its friction. (Seating every pressing body
// every substep cost 3% more physics time for the same result.)
constexpr double kPressedOverlap = 0.5 * b2_linearSlop;

void LayeredWorld::Impl::ApplyKinematicControl(double alpha) {
  // The controller F = m ((aim - x)/dt - v)/dt lands a free body on its aim. A body pressing on
  // an object is held at its surface by the contact, so along the contact normal the object feels
  // m (aim - x)/dt^2 - (m/dt) v_surface. With m = k dt^2 + c dt and the aim's normal part set to
  // (k min(d, d_max) + c v_goal) dt^2 / m, where d is how far the goal lies inside the surface,
  // that is the implicit spring-damper k min(d_end, d_max) + c (v_goal - v_surface): the same
  // force law at any substep count (docs/physics.md, "Grip").
  const double m = ParticleMass();
  const double aimScale = dt * dt / m;
  std::vector<b2Fixture*> unpaired;
  // the layers' contact records of this substep start here: PressOnArrival adds to them
  for (auto& layer : layers) layer->records.clear();
  for (ParticleData& p : particles) {
    const Vec2 goal = p.prevTarget + alpha * (p.target - p.prevTarget);
    if (!p.active) {
      // nothing within reach: the control would put the body on its goal with the velocity
      // that got it there (x' = x + dt v', v' = (x* - x)/dt); do it directly, without bodies
      p.vel = (goal - p.pos) / dt;
      p.pos = goal;
      continue;
    }
    // a particle created this frame goes from where it was placed to its target; its goal moves
    // as its finger's surface does (a goal placed beside a face and aimed inside it is a pad
    // pressed in, not a pad arriving at 1/T times the distance)
    const Vec2 goalVel = p.born ? p.padVel : Vec2((p.target - p.prevTarget) * params.frameRate);
    p.goalVel = goalVel;
    for (int j = 0; j < static_cast<int>(p.bodies.size()); ++j) {
      b2Body* b = p.bodies[j];
      // the contact records read the goal's velocity through it (LayerListener::PostSolve)
      b->GetUserData().pointer = reinterpret_cast<uintptr_t>(&p);
      const Vec2 x = FromB2(b->GetPosition());
      const Vec2 v = BodyVelocity(p, j);
      Vec2 aim = goal;
      // a body the step leaves alone goes to its aim after it (PlaceFreeBodies), moving as the
      // step would have moved it
      auto leaveOnAim = [&] {
        p.freeVel[j] = (aim - x) / dt;
        p.freeAim[j] = aim;
        p.freeNow[j] = 1;
      };
      if (!b->IsEnabled()) {
        // out of its world (see below): it goes to its aim until an object comes within reach
        if (!NearSlices(p.baseLayer + j, x, aim, 0.0)) {
          leaveOnAim();
          continue;
        }
        b->SetEnabled(true);  // in again where it is; Box2D pairs it at the step's start
      }
      // contacts as they are now (Box2D's flags date from the last step's start): a body that
      // overlaps an object presses on it; the others may only reach its surface this substep
      bool pressing = false;
      Vec2 seat = Vec2::Zero();
      for (b2ContactEdge* e = b->GetContactList(); e != nullptr; e = e->next) {
        b2Contact* contact = e->contact;
        b2Fixture* fa = contact->GetFixtureA();
        b2Fixture* fb = contact->GetFixtureB();
        const b2Transform& xfA = fa->GetBody()->GetTransform();
        const b2Transform& xfB = fb->GetBody()->GetTransform();
        b2Manifold manifold;
        contact->Evaluate(&manifold, xfA, xfB);
        if (manifold.pointCount == 0) continue;
        pressing = true;
        b2WorldManifold wm;
        wm.Initialize(&manifold, xfA, fa->GetShape()->m_radius, xfB, fb->GetShape()->m_radius);
        // Box2D's normal points from fixture A to fixture B; particles touch objects only
        const Vec2 in = (fa->GetBody() == b ? 1.0 : -1.0) * FromB2(wm.normal);
        const double d = (aim - x).dot(in);
        if (d <= 0.0) continue;  // moving off the surface: the plain control lets go
        aim += (GripPush(d, goalVel.dot(in)) * aimScale - d) * in;
        // a pressing body stays within the contact's skin (see kPressedOverlap)
        float gap = wm.separations[0];
        for (int i = 1; i < manifold.pointCount; ++i) gap = std::max(gap, wm.separations[i]);
        if (gap > -0.5 * kPressedOverlap) seat += (gap + kPressedOverlap) * in;
      }
      if (seat.squaredNorm() > 0.0) {
        // seated along its normals; its aim moves with it, so it presses as hard as before
        b->SetTransform(ToB2(x + seat), b->GetAngle());
        aim += seat;
      }
      // a body that was asleep was put on its aim outside Box2D: pairs it will have may be
      // missing from its contact list
      unpaired.clear();
      if (!b->IsAwake()) FindUnpaired(p.baseLayer + j, b, x, aim, &unpaired);
      if (!pressing) {
        b2Fixture* surface = StopAtSurface(b, x, &aim, unpaired);
        if (surface != nullptr) PressOnArrival(p.baseLayer + j, surface, aim, goal, p);
      }
      // continuous collision only when a step could carry the body past a surface: a body moving
      // less than its radius per step, or already pressing on a surface, is held by the ordinary
      // contact; time-of-impact sub-steps would only disturb the contact forces and cost time
      const bool fast = (aim - x).norm() > params.particleRadius;
      if (!pressing && !fast && unpaired.empty()) {
        // Touching nothing, Box2D would only integrate it onto its aim, alone in an island of
        // its own (a third of a microsecond each, most of the stepping when many fingers are
        // near objects). It stays asleep there and goes to its aim after the step. A body near
        // an object it has no pair with yet stays awake for a substep, so that Box2D's step
        // finds the pair.
        b->SetAwake(false);
        leaveOnAim();
        b->SetBullet(false);
        // Asleep, it still has a proxy in the layer's broad-phase, and SetTransform moves it out
        // of its fattened box every substep or two: the tree re-inserts it and the next step
        // pairs it again with every particle of its contact (filtered out one by one). A body
        // that no object can reach leaves its world instead, until one can.
        if (!keepFreeBodies && !NearSlices(p.baseLayer + j, x, aim, kOutOfWorldHysteresis)) {
          b->SetEnabled(false);
        }
        continue;
      }
      p.freeNow[j] = 0;
      if (!b->IsAwake()) {
        b->SetAwake(true);
        b->SetLinearVelocity(ToB2(v));
      }
      b->SetAngularVelocity(static_cast<float>(p.spin));
      const Vec2 force = m * ((aim - x) / dt - v) / dt;
      b->ApplyForceToCenter(ToB2(force), true);
      b->SetBullet(fast && !pressing);
    }
  }
}

void LayeredWorld::Impl::PlaceMeasured(ParticleData& p, const Vec2& pos) {
  const double m = p.measured;
  const double margin = params.restMargin;
  const int K = LayerCount();
  int layer = 0;
  double height = 0.0;
  ObjectId object = kNoObject;
  bool aloft = false;
  // still over the object it rests on and not lifted off it: it stays, pressing its top
  bool kept = false;
  if (p.restingOn != kNoObject && p.restingOn < static_cast<int>(objects.size())) {
    const ObjectData& o = objects[p.restingOn];
    const double h = o.MayHold(pos) ? SurfaceHeightAt(o.spec, o.ToLocal(pos)) : -1.0;
    if (h >= 0.0 && m <= h + margin) {
      layer = SupportLayer(p.restingOn, h);
      height = h;
      object = p.restingOn;
      kept = true;
    }
  }
  if (!kept) {
    // the highest surface under its base, whatever its height: the base body cannot have entered
    // an object's footprint through its side (it collides with it there), so a base over a
    // footprint came down onto it from above, and a reading below that top (the finger pressing
    // into a virtual object) rests on it rather than hovering inside its slices
    int belowLayer;
    double belowHeight;
    ObjectId below;
    FindSupport(pos, K - 1, &belowLayer, &belowHeight, &below);
    if (m <= belowHeight + margin) {
      layer = belowLayer;
      height = belowHeight;
      object = below;
    } else {
      // hovering: its underside is in layer floor(m / h) (the slab [k h, (k + 1) h)), and never
      // in the slices of the surface it is above
      const double k = std::floor(m / params.layerHeight);
      aloft = k >= K;
      layer = aloft ? K - 1 : std::max(static_cast<int>(k), belowLayer);
      height = m;
    }
  }
  p.restingOn = object;
  p.baseHeight = height;
  if (layer == p.baseLayer && aloft == p.aloft) return;
  if (p.bodies.empty()) {
    p.baseLayer = layer;
    p.aloft = aloft;
    if (aloft) p.active = false;
    return;
  }
  const Vec2 vel = BodyVelocity(p, 0);
  DestroyBodies(p);
  p.baseLayer = layer;
  p.aloft = aloft;
  if (aloft) {
    // out of every world until it comes down
    p.active = false;
    p.pos = pos;
    p.vel = vel;
    return;
  }
  CreateBodies(p, pos, vel);
}

void LayeredWorld::Impl::UpdateSupport() {
  for (ParticleData& p : particles) {
    if (!std::isnan(p.measured)) {
      PlaceMeasured(p, BasePosition(p));
      continue;
    }
    // A stack out of the worlds this frame stays beyond every object's bounding circle
    // (UpdateActivity), so no object can support it: on the table already, it stays there.
    if (!p.active && p.baseLayer == 0 && p.restingOn == kNoObject && p.baseHeight == 0.0) continue;
    const Vec2 pos = BasePosition(p);
    int layer, object;
    double height;
    FindSupport(pos, p.baseLayer, &layer, &height, &object);
    p.restingOn = object;
    p.baseHeight = height;
    if (layer == p.baseLayer) continue;
    // the support went away: fall to the highest surface below, keeping the motion
    if (p.bodies.empty()) {
      p.baseLayer = layer;
      continue;
    }
    const Vec2 vel = BodyVelocity(p, 0);
    DestroyBodies(p);
    p.baseLayer = layer;
    CreateBodies(p, pos, vel);
  }
}

void LayeredWorld::Impl::UpdateSpin() {
  // A particle is a piece of a finger's surface. When the finger turns, that surface moves with
  // it: a body that only translated would roll along a face it grips (its contact point moving
  // at the face's speed, its centre r further out lagging behind by r omega), and its spring,
  // pulled back to its target, would push the face on in the turn's direction (a box turned by
  // two fingertips turned 10% further than they did). The turn of a contact is the rotation that
  // best carries its particles' previous targets to their targets (least squares about their
  // means); the bodies carry it as angular velocity. They never turn by themselves: their
  // rotation is fixed, so no contact changes it. The same fit gives the velocity of the finger's
  // surface at each particle (padVel: the contact's mean velocity plus its turn), which, unlike
  // the goal's own velocity, leaves out the particles' slide along the contour. The fit runs over
  // the particles of one finger: those created for one contact (ParticleData::finger). When
  // outlines merge, the merged contact holds the particles of several fingers, and one fit over
  // them all would move the pads of a finger that holds still with the one that pushes.
  struct Sums {
    Vec2 from = Vec2::Zero();
    Vec2 to = Vec2::Zero();
    int count = 0;
    double cross = 0.0;
    double dot = 0.0;
    double spin = 0.0;             // the fitted turn rate, rad/s
    Vec2 velocity = Vec2::Zero();  // the fitted mean velocity, cm/s
  };
  std::unordered_map<ContactId, Sums> sums;
  // a contact's particles mostly follow each other in creation order: look its sums up once per
  // run of them (the same sums, added in the same order)
  ContactId last = kNoId;
  Sums* run = nullptr;
  auto sumsOf = [&](ContactId contact) -> Sums& {
    if (run == nullptr || contact != last) {
      run = &sums[contact];
      last = contact;
    }
    return *run;
  };
  // A particle created this frame moves from where it was placed to its target: that is no
  // motion of the finger (placed beside a face, its target inside), and it is left out of the fit
  for (const ParticleData& p : particles) {
    if (p.born) continue;
    Sums& s = sumsOf(p.finger);
    s.from += p.prevTarget;
    s.to += p.target;
    ++s.count;
  }
  for (const ParticleData& p : particles) {
    if (p.born) continue;
    Sums& s = sumsOf(p.finger);
    const Vec2 a = p.prevTarget - s.from / s.count;
    const Vec2 b = p.target - s.to / s.count;
    s.cross += a.x() * b.y() - a.y() * b.x();
    s.dot += a.dot(b);
  }
  for (auto& [contact, s] : sums) {
    // fewer than three points, or a contour turned by more than a right angle in one frame,
    // shows no turn that a surface could have
    s.spin = s.count >= 3 && s.dot > 0.0 ? std::atan2(s.cross, s.dot) * params.frameRate : 0.0;
    s.velocity = (s.to - s.from) / s.count * params.frameRate;
  }
  for (ParticleData& p : particles) {
    const Sums& s = sumsOf(p.finger);
    if (s.count == 0) {
      // a finger all of whose particles are new shows no motion yet
      p.spin = 0.0;
      p.padVel.setZero();
      continue;
    }
    p.spin = s.spin;
    const Vec2 arm = p.target - s.to / s.count;
    p.padVel = s.velocity + p.spin * Vec2(-arm.y(), arm.x());
  }
}

void LayeredWorld::Impl::UpdateActivity() {
  // An object moves at most (|v| + |omega| r) T in a frame of T seconds (plus what a push adds
  // within the frame: kActivityMargin). A particle whose straight path from where it is to its
  // target stays farther than that, plus both radii, from every object's bounding circle cannot
  // touch it this frame.
  const double frameTime = 1.0 / params.frameRate;
  // each object's origin and squared reach, once per frame
  reaches.resize(objects.size());
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    const ObjectData& o = objects[oi];
    const double travel = o.FastestPointSpeed() * frameTime;
    const double reach = o.boundRadius + params.particleRadius + travel + kActivityMargin;
    reaches[oi] = {o.pose.pos, reach * reach};
  }
  for (ParticleData& p : particles) {
    bool active = p.restingOn != kNoObject;
    const Vec2 from = BasePosition(p);
    if (p.aloft) {
      // above every layer: nothing to touch (UpdateSupport brings it down)
      assert(p.bodies.empty() && "an aloft stack has no bodies");
      p.active = false;
      continue;
    }
    const Vec2 path = p.target - from;
    const double length2 = path.squaredNorm();
    for (size_t oi = 0; oi < reaches.size() && !active; ++oi) {
      const Vec2& origin = reaches[oi].first;
      // nearest point of the path to the object's origin
      const double t =
          length2 > 0.0 ? std::clamp((origin - from).dot(path) / length2, 0.0, 1.0) : 0.0;
      active = (from + t * path - origin).squaredNorm() <= reaches[oi].second;
    }
    if (active == p.active) continue;
    p.active = active;
    // a stack gets its bodies where it is, moving as it was; leaving, it keeps its base's motion
    if (active) {
      CreateBodies(p, p.pos, p.vel);
    } else {
      p.pos = from;
      p.vel = BaseVelocity(p);
      DestroyBodies(p);
    }
  }
}

}  // namespace pg
