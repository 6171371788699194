// Coupling of object slices across layers (mass splitting after Tonge, Benevolenski and
// Voroshilov, SIGGRAPH 2012), top friction from particles resting on objects, and Coulomb table
// friction with the full mass. See docs/physics.md for the derivation.
#include "world_impl.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace pg {

namespace {

// true when the slice's body has a touching, enabled contact with anything
bool HasTouchingContact(b2Body* body) {
  for (b2ContactEdge* e = body->GetContactList(); e != nullptr; e = e->next) {
    if (e->contact->IsTouching() && e->contact->IsEnabled()) return true;
  }
  return false;
}

}  // namespace

void LayerListener::PreSolve(b2Contact* contact, const b2Manifold* oldManifold) {
  (void)oldManifold;
  const uintptr_t a = contact->GetFixtureA()->GetUserData().pointer;
  const uintptr_t b = contact->GetFixtureB()->GetUserData().pointer;
  const BodyKind ka = TagKind(a), kb = TagKind(b);
  // friction of an object against particles or walls is the object's own coefficient;
  // object against object keeps Box2D's geometric mean of the two objectFriction values
  // particle contacts are inelastic: the controller, not a bounce, sets how hard they push
  if (ka == BodyKind::kObject && kb == BodyKind::kParticle) {
    contact->SetFriction(static_cast<float>((*particleFriction)[TagIndex(a)]));
    contact->SetRestitution(0.0f);
  } else if (kb == BodyKind::kObject && ka == BodyKind::kParticle) {
    contact->SetFriction(static_cast<float>((*particleFriction)[TagIndex(b)]));
    contact->SetRestitution(0.0f);
  } else if (ka == BodyKind::kObject && kb == BodyKind::kWall) {
    contact->SetFriction(static_cast<float>((*objectFriction)[TagIndex(a)]));
  } else if (kb == BodyKind::kObject && ka == BodyKind::kWall) {
    contact->SetFriction(static_cast<float>((*objectFriction)[TagIndex(b)]));
  }
}

void LayerListener::PostSolve(b2Contact* contact, const b2ContactImpulse* impulse) {
  const uintptr_t a = contact->GetFixtureA()->GetUserData().pointer;
  const uintptr_t b = contact->GetFixtureB()->GetUserData().pointer;
  const BodyKind ka = TagKind(a), kb = TagKind(b);
  double sign;
  ObjectId object;
  if (ka == BodyKind::kObject && kb == BodyKind::kParticle) {
    object = TagIndex(a);
    sign = -1.0;  // the normal points from A (the object) to B
  } else if (kb == BodyKind::kObject && ka == BodyKind::kParticle) {
    object = TagIndex(b);
    sign = 1.0;
  } else {
    return;
  }
  b2WorldManifold wm;
  contact->GetWorldManifold(&wm);
  const Vec2 n = FromB2(wm.normal);
  ContactRecord r;
  r.object = object;
  r.normalIn = sign * n;
  r.tangentIn = sign * Vec2(n.y(), -n.x());  // Box2D's tangent is b2Cross(normal, 1)
  r.friction = contact->GetFriction();
  r.points = impulse->count;
  for (int i = 0; i < impulse->count; ++i) {
    r.normalImpulse += impulse->normalImpulses[i];
    r.tangentImpulse += impulse->tangentImpulses[i];
  }
  records->push_back(r);
}

void LayeredWorld::Impl::PrepareMassSplitting() {
  for (ObjectData& o : objects) {
    // n = layers that touched something in the last substep; none: all slices share the mass
    int n = 0;
    for (const Slice& s : o.slices) n += s.touching ? 1 : 0;
    if (n == 0) n = static_cast<int>(o.slices.size());
    if (n == o.splitCount) continue;
    o.splitCount = n;
    b2MassData md;
    md.mass = static_cast<float>(o.props.mass / n);
    const Vec2 c = o.props.centroid;
    md.center = ToB2(c);
    // Box2D takes the inertia about the body origin
    md.I = static_cast<float>(o.props.inertia / n + o.props.mass / n * c.squaredNorm());
    for (Slice& s : o.slices) s.body->SetMassData(&md);
  }
}

double LayeredWorld::Impl::TableNormal(int oi) const {
  return objects[oi].props.mass * params.gravity +
         params.particleDownForce * static_cast<double>(onTop[oi].size());
}

void LayeredWorld::Impl::PrepareTableFriction() {
  onTop.assign(objects.size(), {});
  for (int i = 0; i < static_cast<int>(particles.size()); ++i) {
    if (particles[i].restingOn != kNoObject) onTop[particles[i].restingOn].push_back(i);
  }
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    ObjectData& o = objects[oi];
    const double N = TableNormal(oi);
    const double mu = o.sliding ? o.spec.tableKinetic : o.spec.tableStatic;
    const double muTurn = o.spinning ? o.spec.tableKinetic : o.spec.tableStatic;
    // split like the mass: each of the n slices that carry the object's mass in this substep
    // resists with 1/n of the limit, so a grip solved in its layers meets the whole table
    // friction and no more; Couple() then brings the sum within the Coulomb limit (a push that
    // one layer cannot hold alone is still held when the whole limit can)
    const int n = o.splitCount;
    const bool all = n == static_cast<int>(o.slices.size());
    for (Slice& s : o.slices) {
      const double share = all || s.touching ? 1.0 / n : 0.0;
      s.table->SetMaxForce(static_cast<float>(share * mu * N));
      s.table->SetMaxTorque(static_cast<float>(share * muTurn * N * o.rEff));
    }
  }
}

void LayeredWorld::Impl::ApplyPushes() {
  for (ObjectData& o : objects) {
    for (const Push& p : o.pushes) {
      o.slices[p.layer].body->ApplyForce(ToB2(p.force), ToB2(p.point), true);
    }
  }
}

void LayeredWorld::Impl::StepLayers() {
  const float h = static_cast<float>(dt);
  pool->Run(LayerCount(), [&](int k) {
    Layer& layer = *layers[k];
    layer.records.clear();
    layer.world->Step(h, params.velocityIterations, params.positionIterations);
  });
}

namespace {

// projected Gauss-Seidel sweeps over one object's friction impulses in one substep; the impulses
// of a few dozen particles and the table settle to 1e-6 of their size well within this
constexpr int kFrictionIterations = 16;

// a limit counts as reached within this fraction, so a converged static solve is not taken as
// sliding through rounding
constexpr double kLimitReached = 1.0 - 1e-9;

Vec2 ClampNorm(const Vec2& v, double limit) {
  const double n = v.norm();
  return n > limit && n > 0.0 ? Vec2(v * (limit / n)) : v;
}

}  // namespace

LayeredWorld::Impl::FrictionSolve LayeredWorld::Impl::SolveFriction(
    int oi, const std::vector<int>& onTop, const Vec2& center, const Vec2& vel0, double omega0,
    const TableImpulse& applied, double normal, bool kinetic,
    const FrictionSolve* staticPass) const {
  const ObjectData& o = objects[oi];
  const double M = o.props.mass, I = o.props.inertia;
  const double mu = particleFriction[oi];
  const double fdt = params.particleDownForce * dt;
  const size_t n = onTop.size();
  FrictionSolve r;
  r.vel = vel0;
  r.omega = omega0;
  r.top.assign(n, Vec2::Zero());
  r.topSliding.assign(n, false);
  // the impulses the slices' friction joints applied are the starting guess; the first sweep
  // brings their sum within the limit
  r.table = applied.linear;
  r.spin = o.rEff > 0 ? applied.angular : 0.0;

  // impulse limits: static, or kinetic for the contacts that slid in the static pass
  std::vector<double> topLimit(n, mu * fdt);
  double tableLimit = o.spec.tableStatic * normal * dt;
  double spinLimit = o.spec.tableStatic * normal * o.rEff * dt;
  if (kinetic) {
    for (size_t k = 0; k < n; ++k) {
      if (staticPass->topSliding[k]) topLimit[k] *= params.topKineticFactor;
    }
    if (staticPass->tableSliding) tableLimit = o.spec.tableKinetic * normal * dt;
    if (staticPass->spinSliding) spinLimit = o.spec.tableKinetic * normal * o.rEff * dt;
  }

  // each resting particle: its lever arm, its velocity, and the object's point mass there
  std::vector<Vec2> arm(n), particleVel(n);
  std::vector<Eigen::Matrix2d> pointMass(n);
  for (size_t k = 0; k < n; ++k) {
    const b2Body* base = particles[onTop[k]].bodies.front();
    const Vec2 a = FromB2(base->GetPosition()) - center;
    arm[k] = a;
    particleVel[k] = FromB2(base->GetLinearVelocity());
    // inverse effective mass of the object at the point: K = 1/M + r_perp r_perp^T / I
    Eigen::Matrix2d K;
    K << 1.0 / M + a.y() * a.y() / I, -a.x() * a.y() / I, -a.x() * a.y() / I,
        1.0 / M + a.x() * a.x() / I;
    pointMass[k] = K.inverse();
  }

  for (int it = 0; it < kFrictionIterations; ++it) {
    // top friction: each particle drags the surface point under it towards its own velocity
    for (size_t k = 0; k < n; ++k) {
      const Vec2& a = arm[k];
      const Vec2 surface = r.vel + r.omega * Vec2(-a.y(), a.x());
      const Vec2 total =
          ClampNorm(r.top[k] + pointMass[k] * (particleVel[k] - surface), topLimit[k]);
      const Vec2 change = total - r.top[k];
      r.top[k] = total;
      r.vel += change / M;
      r.omega += Cross(a, change) / I;
    }
    // table friction: resists the object's sliding with the full mass
    const Vec2 table = ClampNorm(r.table - M * r.vel, tableLimit);
    r.vel += (table - r.table) / M;
    r.table = table;
    if (o.rEff > 0) {
      const double spin = std::clamp(r.spin - I * r.omega, -spinLimit, spinLimit);
      r.omega += (spin - r.spin) / I;
      r.spin = spin;
    }
  }

  // which limits were reached
  for (size_t k = 0; k < n; ++k) {
    r.topSliding[k] = r.top[k].norm() >= kLimitReached * topLimit[k];
    r.anyTopSliding = r.anyTopSliding || r.topSliding[k];
  }
  r.tableSliding = r.table.norm() >= kLimitReached * tableLimit && r.vel.norm() > 0.0;
  r.spinSliding = o.rEff > 0 && std::abs(r.spin) >= kLimitReached * spinLimit && r.omega != 0.0;
  return r;
}

void LayeredWorld::Impl::Couple() {
  const double fd = params.particleDownForce;
  // onTop, the particles resting on each object, is this substep's (PrepareTableFriction)
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    ObjectData& o = objects[oi];
    const double w = 1.0 / o.splitCount;  // each slice carries M/n of the mass

    // momentum-weighted sum of the slices' velocity changes; position corrections from the
    // layers with contacts (displacement beyond what their velocity integrated)
    Vec2 dv = Vec2::Zero(), corr = Vec2::Zero();
    double dw = 0.0, corrA = 0.0;
    TableImpulse table;
    for (Slice& s : o.slices) {
      const b2Body* b = s.body;
      // what the slice's table friction joint applied (GetReaction* with inverse step 1)
      table.linear += FromB2(s.table->GetReactionForce(1.0f));
      table.angular += s.table->GetReactionTorque(1.0f);
      const Vec2 v = FromB2(b->GetLinearVelocity());
      const double om = b->GetAngularVelocity();
      dv += w * (v - o.velF);
      dw += w * (om - o.omegaF);
      s.touching = HasTouchingContact(s.body);
      if (s.touching) {
        corr += w * ((FromB2(b->GetWorldCenter()) - o.centerF) - v * dt);
        corrA += w * ((b->GetAngle() - o.angleF) - om * dt);
      }
    }
    Vec2 vel = o.vel + dv;
    double omega = o.omega + dw;
    const Vec2 centerAfterStep = o.center + vel * dt + corr;

    // Table friction was solved inside the layer worlds, together with the side contacts (each
    // slice's joint may hold the whole limit). Here its sum over the slices is brought within the
    // Coulomb limit, and top friction is solved together with it: a finger on top can only drag
    // the object when its friction beats the table's, which a sequential pass gets wrong (top
    // friction would only supply what matches the finger's speed in one substep, and the table's
    // static check would then cancel it every substep).
    const double N = TableNormal(oi);
    FrictionSolve solve =
        SolveFriction(oi, onTop[oi], centerAfterStep, vel, omega, table, N, false);
    // Coulomb: where a static limit is reached the contact slides, and slides at kinetic friction
    if (solve.tableSliding || solve.spinSliding || solve.anyTopSliding) {
      solve = SolveFriction(oi, onTop[oi], centerAfterStep, vel, omega, table, N, true, &solve);
    }
    for (size_t k = 0; k < onTop[oi].size(); ++k) {
      particles[onTop[oi][k]].bodies.front()->ApplyLinearImpulseToCenter(ToB2(-solve.top[k]), true);
      o.topFriction += solve.top[k];
    }
    o.topNormal += fd * static_cast<double>(onTop[oi].size()) * dt;
    o.particlesOnTop = static_cast<int>(onTop[oi].size());

    // the substep's displacement follows the velocity after friction (symplectic Euler, as Box2D
    // integrates); static table friction holds the object exactly still (a push below mu_s M g
    // leaves only the contacts' position corrections)
    Vec2 move = solve.vel * dt + corr;
    double turn = solve.omega * dt + corrA;
    if (!solve.tableSliding) {
      solve.vel.setZero();
      move = corr;
    }
    if (o.rEff > 0 && !solve.spinSliding) {
      solve.omega = 0.0;
      turn = corrA;
    }
    vel = solve.vel;
    omega = solve.omega;
    o.sliding = solve.tableSliding;
    o.spinning = solve.spinSliding;

    o.center += move;
    o.angle += turn;
    o.vel = vel;
    o.omega = omega;
    WriteBack(o);
  }
}

void LayeredWorld::Impl::WriteBack(ObjectData& o) {
  o.CachePose();
  const b2Vec2 origin = ToB2(o.pose.pos);
  const float angle = static_cast<float>(o.angle);
  const b2Vec2 v = ToB2(o.vel);
  const float om = static_cast<float>(o.omega);
  for (Slice& s : o.slices) {
    s.body->SetTransform(origin, angle);
    s.body->SetLinearVelocity(v);
    s.body->SetAngularVelocity(om);
  }
  const b2Body* b = o.slices.front().body;
  o.centerF = FromB2(b->GetWorldCenter());
  o.angleF = b->GetAngle();
  o.velF = FromB2(b->GetLinearVelocity());
  o.omegaF = b->GetAngularVelocity();
}

void LayeredWorld::Impl::CollectRecords(bool lastSubstep) {
  const double cosLimit = params.heldOpposingDot;
  const double margin = params.heldFrictionMargin;
  std::vector<std::vector<Vec2>> gripping(objects.size());
  for (int k = 0; k < LayerCount(); ++k) {
    for (const ContactRecord& r : layers[k]->records) {
      ObjectData& o = objects[r.object];
      LayerForces& f = o.forces[k];
      f.normal += r.normalImpulse * r.normalIn;
      f.friction += r.tangentImpulse * r.tangentIn;
      f.normalMagnitude += std::abs(r.normalImpulse);
      f.frictionMagnitude += std::abs(r.tangentImpulse);
      if (!lastSubstep) continue;
      f.contacts += r.points;
      // a contact that pushes and does not slip takes part in a grip
      if (r.normalImpulse > 0 &&
          std::abs(r.tangentImpulse) < margin * r.friction * r.normalImpulse) {
        gripping[r.object].push_back(r.normalIn);
      }
    }
  }
  if (!lastSubstep) return;
  // held: two gripping contacts push from opposing sides
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    const std::vector<Vec2>& normals = gripping[oi];
    bool held = false;
    for (size_t i = 0; i < normals.size() && !held; ++i) {
      for (size_t j = i + 1; j < normals.size() && !held; ++j) {
        held = normals[i].dot(normals[j]) < cosLimit;
      }
    }
    objects[oi].held = held;
  }
}

}  // namespace pg
