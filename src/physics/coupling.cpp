// Coupling of object slices across layers (mass splitting after Tonge, Benevolenski and
// Voroshilov, SIGGRAPH 2012), top friction from particles resting on objects, and Coulomb table
// friction with the full mass. See docs/physics.md for the derivation.
#include "world_impl.h"

#include <Eigen/Dense>

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
  int object;
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

void LayeredWorld::Impl::Couple() {
  const double g = params.gravity;
  const double fd = params.particleDownForce;
  const double kineticFactor = params.topKineticFactor;

  // particles resting on each object's top
  std::vector<std::vector<int>> onTop(objects.size());
  for (int i = 0; i < static_cast<int>(particles.size()); ++i) {
    if (particles[i].restingOn >= 0) onTop[particles[i].restingOn].push_back(i);
  }

  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    ObjectData& o = objects[oi];
    const double M = o.props.mass, I = o.props.inertia;
    const double w = 1.0 / o.splitCount;  // each slice carries M/n of the mass

    // momentum-weighted sum of the slices' velocity changes; position corrections from the
    // layers with contacts (displacement beyond what their velocity integrated)
    Vec2 dv = Vec2::Zero(), corr = Vec2::Zero();
    double dw = 0.0, corrA = 0.0;
    for (Slice& s : o.slices) {
      const b2Body* b = s.body;
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

    // top friction: each resting particle drags the surface point under it (Coulomb, static
    // then kinetic), Gauss-Seidel over the particles in creation order
    const double mu = particleFriction[oi];
    for (int pi : onTop[oi]) {
      ParticleData& p = particles[pi];
      b2Body* base = p.bodies.front();
      const Vec2 x = FromB2(base->GetPosition());
      const Vec2 r = x - centerAfterStep;
      const Vec2 surface = vel + omega * Vec2(-r.y(), r.x());
      const Vec2 rel = FromB2(base->GetLinearVelocity()) - surface;
      // inverse effective mass of the object at the point: K = 1/M + r_perp r_perp^T / I
      Eigen::Matrix2d K;
      K << 1.0 / M + r.y() * r.y() / I, -r.x() * r.y() / I, -r.x() * r.y() / I,
          1.0 / M + r.x() * r.x() / I;
      Vec2 J = K.inverse() * rel;
      const double jn = fd * dt;
      if (J.norm() > mu * jn) J *= mu * kineticFactor * jn / J.norm();
      vel += J / M;
      omega += Cross(r, J) / I;
      base->ApplyLinearImpulseToCenter(ToB2(-J), true);
      o.topFriction += J;
    }
    const double topForce = fd * static_cast<double>(onTop[oi].size());
    o.topNormal += topForce * dt;
    o.particlesOnTop = static_cast<int>(onTop[oi].size());

    // this substep's displacement follows the velocity the contacts and top friction left
    Vec2 move = vel * dt + corr;
    double turn = omega * dt + corrA;

    // table friction with the full mass: static holds when the impulse that stops the object
    // fits under mu_s N dt, and then the substep's displacement is undone; otherwise kinetic
    // friction takes mu_k N dt off the momentum for the next substep (taking it off this
    // substep's displacement too would make a carried object slip out of a steady grip)
    const double N = M * g + topForce;
    const double speed = vel.norm();
    if (M * speed <= o.spec.tableStatic * N * dt) {
      vel.setZero();
      move = corr;
    } else {
      vel *= std::max(0.0, speed - o.spec.tableKinetic * N * dt / M) / speed;
    }
    if (o.rEff > 0) {
      const double spin = std::abs(omega);
      if (I * spin <= o.spec.tableStatic * N * o.rEff * dt) {
        omega = 0.0;
        turn = corrA;
      } else {
        omega *= std::max(0.0, spin - o.spec.tableKinetic * N * o.rEff * dt / I) / spin;
      }
    }

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
