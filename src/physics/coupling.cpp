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
    r.point += FromB2(wm.points[i]) / impulse->count;
  }
  b2Body* particle = (sign > 0 ? contact->GetFixtureA() : contact->GetFixtureB())->GetBody();
  if (const auto* p = reinterpret_cast<const ParticleData*>(particle->GetUserData().pointer)) {
    r.padVel = p->padVel;
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
    // A joint in each layer resists sliding and turning, solved with the layer's contacts, so
    // that a grip meets the table's friction where it acts. Its two limits are separate, but the
    // table's friction is one, spread over the base (Couple() solves it over the base points):
    // at rest the joint may hold up to the static limits mu_s N and mu_s N r_eff; while the
    // object slides it resists with the force and torque the base points gave in the last
    // substep, which share the kinetic friction between sliding and turning.
    double force = o.spec.tableStatic * N;
    double torque = o.spec.tableStatic * N * o.rEff;
    if (o.sliding) {
      force = o.slideForce.norm();
      torque = std::abs(o.slideTorque);
    }
    // split like the mass: each of the n slices that carry the object's mass in this substep
    // resists with 1/n of the limit, so a grip solved in its layers meets the whole table
    // friction and no more; Couple() then brings the sum within the Coulomb limit (a push that
    // one layer cannot hold alone is still held when the whole limit can)
    const int n = o.splitCount;
    const bool all = n == static_cast<int>(o.slices.size());
    for (Slice& s : o.slices) {
      const double share = all || s.touching ? 1.0 / n : 0.0;
      s.table->SetMaxForce(static_cast<float>(share * force));
      s.table->SetMaxTorque(static_cast<float>(share * torque));
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
    layer.world->Step(h, params.velocityIterations, params.positionIterations);
  });
}

namespace {

// projected Gauss-Seidel sweeps over one object's friction impulses in one substep, at most; the
// sweeps stop when one changes the impulses by less than kSettled of their limits
constexpr int kFrictionIterations = 48;
constexpr double kSettled = 1e-9;

// a limit counts as reached within this fraction, so a converged static solve is not taken as
// sliding through rounding
constexpr double kLimitReached = 1.0 - 1e-9;

// Newton iterations for a sliding object's table friction, and the slip speed below which a
// point's slip direction is smoothed, cm/s (a micrometre a second)
constexpr int kSlideNewtonIterations = 20;
constexpr double kSlipFloor = 1e-4;
// the slip below which a sliding object counts as come to rest, cm/s
constexpr double kRestingSlip = 20 * kSlipFloor;

// motion the table friction leaves, as a fraction of what it had to stop, below which the object
// counts as held still
constexpr double kStillFraction = 1e-2;

Vec2 ClampNorm(const Vec2& v, double limit) {
  const double n = v.norm();
  return n > limit && n > 0.0 ? Vec2(v * (limit / n)) : v;
}

// Kinetic table friction of a sliding object, implicit in its motion: finds the twist t = (v, w)
// with t = t_free + M^-1 W(t), where W is the wrench of the points' friction, each of magnitude
// limit[k] against its own slip v + w x arm[k]. Newton's method on the 3 x 3 system; a slip is
// regularised below kSlipFloor so that its direction has a derivative.
void SolveSlidingTable(size_t P, const std::vector<Vec2>& arm, const std::vector<double>& limit,
                       Vec2* vel, double* omega, std::vector<Vec2>* impulses, double M, double I) {
  // the motion without the table's current impulses
  Vec2 force = Vec2::Zero();
  double torque = 0.0;
  for (size_t k = 0; k < P; ++k) {
    force += (*impulses)[k];
    torque += Cross(arm[k], (*impulses)[k]);
  }
  const Eigen::Vector3d free(vel->x() - force.x() / M, vel->y() - force.y() / M,
                             *omega - torque / I);
  const Eigen::Vector3d invMass(1.0 / M, 1.0 / M, 1.0 / I);
  // the residual t - free - M^-1 W(t) and, when asked, its Jacobian
  auto residual = [&](const Eigen::Vector3d& t, Eigen::Matrix3d* jacobian) {
    Eigen::Vector3d wrench = Eigen::Vector3d::Zero();
    if (jacobian != nullptr) jacobian->setZero();
    for (size_t k = 0; k < P; ++k) {
      // slip = J t with J = [1 0 -a.y; 0 1 a.x]
      Eigen::Matrix<double, 2, 3> J;
      J << 1.0, 0.0, -arm[k].y(), 0.0, 1.0, arm[k].x();
      const Eigen::Vector2d slip = J * t;
      const double speed = std::sqrt(slip.squaredNorm() + kSlipFloor * kSlipFloor);
      const Eigen::Vector2d dir = slip / speed;
      wrench -= limit[k] * J.transpose() * dir;
      if (jacobian != nullptr) {
        // d(-L s/|s|)/ds = -(L/|s|)(1 - s s^T/|s|^2)
        const Eigen::Matrix2d ds =
            -(limit[k] / speed) *
            (Eigen::Matrix2d::Identity() - slip * slip.transpose() / (speed * speed));
        *jacobian += J.transpose() * ds * J;
      }
    }
    return Eigen::Vector3d(t - free - invMass.asDiagonal() * wrench);
  };
  // Newton's method, each step shortened until it lowers the residual: friction of constant
  // magnitude has no slope along the slip, so a full step can carry the motion through zero
  Eigen::Vector3d t = free;
  Eigen::Matrix3d jacobian;
  Eigen::Vector3d res = residual(t, &jacobian);
  const double tolerance = 1e-9 * (1.0 + free.norm());
  for (int iter = 0; iter < kSlideNewtonIterations && res.norm() > tolerance; ++iter) {
    const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - invMass.asDiagonal() * jacobian;
    const Eigen::Vector3d step = A.partialPivLu().solve(-res);
    double scale = 1.0;
    Eigen::Vector3d next = t + step;
    Eigen::Vector3d nextRes = residual(next, nullptr);
    for (int halving = 0; halving < 30 && nextRes.norm() >= res.norm(); ++halving) {
      scale *= 0.5;
      next = t + scale * step;
      nextRes = residual(next, nullptr);
    }
    if (nextRes.norm() >= res.norm()) break;
    t = next;
    res = residual(t, &jacobian);
  }
  for (size_t k = 0; k < P; ++k) {
    const Vec2 slip(t.x() - t.z() * arm[k].y(), t.y() + t.z() * arm[k].x());
    const double speed = std::sqrt(slip.squaredNorm() + kSlipFloor * kSlipFloor);
    (*impulses)[k] = -limit[k] / speed * slip;
  }
  *vel = Vec2(t.x(), t.y());
  *omega = t.z();
}

}  // namespace

LayeredWorld::Impl::FrictionSolve LayeredWorld::Impl::SolveFriction(
    int oi, const std::vector<int>& onTop, const Vec2& center, const Vec2& vel0, double omega0,
    const TableImpulse& applied, double normal, bool kinetic, const FrictionSolve* staticPass,
    bool breakingLoose) const {
  const ObjectData& o = objects[oi];
  const double M = o.props.mass, I = o.props.inertia;
  const double mu = particleFriction[oi];
  const double fdt = params.particleDownForce * dt;
  const size_t n = onTop.size();
  const size_t P = o.tablePoints.size();
  FrictionSolve r;
  // the table friction the slices' joints applied is taken out and solved again over the base
  // points, which couple sliding and turning
  r.vel = vel0 - applied.linear / M;
  r.omega = omega0 - applied.angular / I;
  r.top.assign(n, Vec2::Zero());
  r.topSliding.assign(n, false);
  r.table.assign(P, Vec2::Zero());

  // impulse limits: static, or kinetic for the contacts that slid in the static pass; the table's
  // points all slide when the object moves (only its centre of rotation is at rest)
  std::vector<double> topLimit(n, mu * fdt);
  const double tableMu = kinetic && staticPass->tableSliding && !breakingLoose ? o.spec.tableKinetic
                                                                               : o.spec.tableStatic;
  if (kinetic) {
    for (size_t k = 0; k < n; ++k) {
      if (staticPass->topSliding[k]) topLimit[k] *= params.topKineticFactor;
    }
  }

  // With nobody on top the impulse that would stop the object decides at once in most cases: it
  // is held for certain inside the double cone spanned by the pure slide limit mu_s N dt (any
  // direction) and the pure turn limit mu_s N r_eff dt, which the points' convex limit surface
  // contains, and it slides for certain beyond either limit, which bound the surface. (A sphere
  // without a contact patch turns freely: its turn never counts.)
  if (!kinetic && n == 0) {
    const double slide = M * r.vel.norm() / (o.spec.tableStatic * normal * dt);
    const double turn =
        o.rEff > 0 ? I * std::abs(r.omega) / (o.spec.tableStatic * normal * o.rEff * dt) : 0.0;
    if (slide + turn <= 1.0) {
      r.vel.setZero();
      if (o.rEff > 0) r.omega = 0.0;
      return r;
    }
    if (slide > 1.0 || turn > 1.0) {
      r.tableSliding = true;
      return r;
    }
  }

  // each point (resting particle or base point): its lever arm and the object's point mass there
  auto pointMass = [&](const Vec2& a) {
    // inverse effective mass of the object at the point: K = 1/M + r_perp r_perp^T / I
    Eigen::Matrix2d K;
    K << 1.0 / M + a.y() * a.y() / I, -a.x() * a.y() / I, -a.x() * a.y() / I,
        1.0 / M + a.x() * a.x() / I;
    return Eigen::Matrix2d(K.inverse());
  };
  std::vector<Vec2> arm(n), particleVel(n);
  std::vector<Eigen::Matrix2d> mass(n);
  for (size_t k = 0; k < n; ++k) {
    arm[k] = BasePosition(particles[onTop[k]]) - center;
    particleVel[k] = particles[onTop[k]].padVel;
    mass[k] = pointMass(arm[k]);
  }
  // a sliding table is solved for all its points at once (SolveSlidingTable), without their
  // point masses
  const bool tableSlides = kinetic && staticPass->tableSliding;
  std::vector<Vec2> tableArm(P);
  std::vector<Eigen::Matrix2d> tableMass(tableSlides ? 0 : P);
  std::vector<double> tableLimit(P);
  for (size_t k = 0; k < P; ++k) {
    tableArm[k] = o.ToTableDirection(o.tablePoints[k].arm);
    if (!tableSlides) tableMass[k] = pointMass(tableArm[k]);
    tableLimit[k] = tableMu * o.tablePoints[k].weight * normal * dt;
  }
  // a point friction impulse towards stopping the surface point at arm a (relative to `target`),
  // within `limit`. Static: the impulse that stops it, clamped to the limit (projected
  // Gauss-Seidel). Sliding: where even the limit cannot stop the point, kinetic friction opposes
  // its slip velocity; the stopping impulse of a point off the centre is not parallel to its slip
  // (it also undoes the turn), and clamping it would rob a slide of part of mu_k N.
  double changed = 0.0;  // impulse changed in the current sweep
  auto applyChange = [&](const Vec2& a, const Vec2& change) {
    changed += change.norm();
    r.vel += change / M;
    r.omega += Cross(a, change) / I;
  };
  auto solvePoint = [&](Vec2& impulse, const Vec2& a, const Eigen::Matrix2d& m, const Vec2& target,
                        double limit, bool sliding) {
    const Vec2 slip = r.vel + r.omega * Vec2(-a.y(), a.x()) - target;
    Vec2 total = impulse - m * slip;
    if (total.squaredNorm() > limit * limit) {
      const double slipSpeed = slip.norm();
      total =
          sliding && slipSpeed > 0.0 ? Vec2(-limit / slipSpeed * slip) : ClampNorm(total, limit);
    }
    applyChange(a, total - impulse);
    impulse = total;
  };

  double limits = 0.0;
  for (double l : topLimit) limits += l;
  for (double l : tableLimit) limits += l;
  for (int it = 0; it < kFrictionIterations; ++it) {
    changed = 0.0;
    // top friction: each particle drags the surface point under it towards its own velocity
    for (size_t k = 0; k < n; ++k) {
      solvePoint(r.top[k], arm[k], mass[k], particleVel[k], topLimit[k],
                 kinetic && staticPass->topSliding[k]);
    }
    // table friction: each base point resists its own sliding with its share of the normal force
    if (!tableSlides) {
      for (size_t k = 0; k < P; ++k) {
        solvePoint(r.table[k], tableArm[k], tableMass[k], Vec2::Zero(), tableLimit[k], false);
      }
      if (changed <= kSettled * limits) break;
      continue;
    }
    // Sliding: the table could not hold the object, so every base point slides (all but its
    // centre of rotation) and kinetic friction opposes each point's slip, at the motion after the
    // substep: W(t) = -sum L_k s_k / |s_k| with s_k the slip of point k under the twist t, and
    // t = t_free + M^-1 W(t). Solved for t by Newton's method: one point at a time (Gauss-Seidel)
    // or with the slip directions of the motion before would overshoot where the slips are slower
    // than what the friction takes off in a substep (a spinning ball's small patch, or the point
    // about which a pushed bar turns), and turn the directions at random.
    SolveSlidingTable(P, tableArm, tableLimit, &r.vel, &r.omega, &r.table, M, I);
    // without fingers on top one solve is the answer; with them, until their impulses settle
    if (n == 0 || changed <= kSettled * limits) break;
  }

  // which limits were reached
  for (size_t k = 0; k < n; ++k) {
    r.topSliding[k] = r.top[k].norm() >= kLimitReached * topLimit[k];
    r.anyTopSliding = r.anyTopSliding || r.topSliding[k];
  }
  // the object slides when the table could not stop it: points at their limits and motion left
  // (more than kStillFraction of what the table had to stop; projected Gauss-Seidel leaves a
  // little of a motion it can stop)
  const double reach = o.boundRadius;
  const double left = r.vel.norm() + std::abs(r.omega) * reach;
  // what the table had to stop: the motion the layers left it, and what the fingers on top gave
  double free = (vel0 - applied.linear / M).norm() + std::abs(omega0 - applied.angular / I) * reach;
  for (size_t k = 0; k < n; ++k) {
    free += r.top[k].norm() / M + std::abs(Cross(arm[k], r.top[k])) / I * reach;
  }
  bool limited = false;
  for (size_t k = 0; k < P && !limited; ++k) {
    limited = r.table[k].norm() >= kLimitReached * tableLimit[k];
  }
  r.tableSliding = tableSlides || (limited && left > kStillFraction * free);
  if (tableSlides) {
    // kinetic friction that stops the object within the substep leaves only the slip that
    // smooths its direction (a few kSlipFloor): it came to rest
    double fastest = 0.0;
    for (size_t k = 0; k < P; ++k) {
      const Vec2& a = tableArm[k];
      fastest = std::max(fastest, (r.vel + r.omega * Vec2(-a.y(), a.x())).norm());
    }
    r.tableSliding = fastest > kRestingSlip;
  }
  return r;
}

void LayeredWorld::Impl::LimitRelease(int oi, const std::vector<ContactRecord*>& pushes, Vec2* vel,
                                      double* omega) const {
  // A particle is the proxy of a soft finger, whose pad springs back at a bounded speed: it
  // pushes a face only while the face recedes from the finger's surface slower than u =
  // grip_release_speed. The contact solver gave each pressing body's impulse lambda_i with no
  // such bound, so a squeezed object let go took the grip's whole stored energy at once. Here
  // each lambda_i is lowered (never below 0) until the face at its point recedes at most u
  // faster than the finger's surface there advances: (v + w x r_i) . n_i <= max(g_i, 0) + u,
  // g_i = padVel . n_i, projected Gauss-Seidel over the object's pushes, and the contact's
  // friction impulse is brought within mu lambda_i. A surface that withdraws (g_i < 0) throws
  // nothing: the face it leaves behind is slower than it, so the bound is the pad's u alone;
  // measured from the withdrawing surface, a grip that starts a carry at once let go with its
  // leading pads while the object still lagged inside them, and a pinched round object spun out
  // on the trailing pads' friction alone. The advance is the finger's surface's (padVel, fitted
  // over the finger's particles), not the particle's goal's own: a goal also slides along the
  // contour, and where outlines merge or split its target is laid onto the new outline, up to a
  // few millimetres in one frame. Measured from the goal, such a jump into the face let it
  // recede at the jump's speed: a cylinder pinched 1.2 cm deep left at 16.5 cm/s behind a pusher
  // at 6 the frame its outline merged with the pinch's (grasp sweep 225 #564).
  // A face that also slides across the pad faster than u (speed s along t_i, relative to the
  // finger's surface there) is left behind by it: it may recede at most u (u / s). Without this,
  // two pads pinching a round slice formed a wedge that squeezed it out sideways at u / sin(phi),
  // phi the tilt of their normals from the pinch's axis. docs/physics.md, "Grip".
  const ObjectData& o = objects[oi];
  const double u = params.gripReleaseSpeed;
  const double invM = 1.0 / o.props.mass, invI = 1.0 / o.props.inertia;
  for (int iteration = 0; iteration < kReleaseIterations; ++iteration) {
    bool changed = false;
    for (ContactRecord* r : pushes) {
      if (r->normalImpulse <= 0.0) continue;
      const Vec2 arm = r->point - o.center;
      const double armN = Cross(arm, r->normalIn);
      const Vec2 v = *vel + Vec2(-arm.y(), arm.x()) * *omega;
      const double slide = (v - r->padVel).dot(r->tangentIn);
      const double recede = std::abs(slide) > u ? u * u / std::abs(slide) : u;
      const double excess = v.dot(r->normalIn) - std::max(r->padVel.dot(r->normalIn), 0.0) - recede;
      if (excess <= 0.0) continue;
      const double take = std::min(r->normalImpulse, excess / (invM + armN * armN * invI));
      r->normalImpulse -= take;
      *vel -= take * invM * r->normalIn;
      *omega -= take * armN * invI;
      // the contact's friction stays within mu times what is left of its push
      const double limit = r->friction * r->normalImpulse;
      const double kept = std::clamp(r->tangentImpulse, -limit, limit);
      const double back = r->tangentImpulse - kept;
      r->tangentImpulse = kept;
      *vel -= back * invM * r->tangentIn;
      *omega -= back * Cross(arm, r->tangentIn) * invI;
      changed = true;
    }
    if (!changed) break;
  }
}

void LayeredWorld::Impl::Couple() {
  const double fd = params.particleDownForce;
  // the particles' pushes on each object in this substep, for LimitRelease
  std::vector<std::vector<ContactRecord*>>& pushes = releasePushes;
  pushes.resize(objects.size());
  for (std::vector<ContactRecord*>& list : pushes) list.clear();
  if (params.gripReleaseSpeed > 0.0) {
    for (auto& layer : layers) {
      for (ContactRecord& r : layer->records) pushes[r.object].push_back(&r);
    }
  }
  // onTop, the particles resting on each object, is this substep's (PrepareTableFriction)
  for (int oi = 0; oi < static_cast<int>(objects.size()); ++oi) {
    ObjectData& o = objects[oi];
    const double w = 1.0 / o.splitCount;  // each slice carries M/n of the mass

    // momentum-weighted sum of the slices' velocity changes; position corrections from the
    // layers with contacts (displacement beyond what their velocity integrated)
    Vec2 dv = Vec2::Zero(), corr = Vec2::Zero();
    double dw = 0.0, corrA = 0.0;
    TableImpulse table;
    bool still = true;     // no slice moved or turned in the step
    bool touched = false;  // a slice has a touching contact
    for (Slice& s : o.slices) {
      const b2Body* b = s.body;
      // what the slice's table friction joint applied (GetReaction* with inverse step 1)
      table.linear += FromB2(s.table->GetReactionForce(1.0f));
      table.angular += s.table->GetReactionTorque(1.0f);
      const Vec2 v = FromB2(b->GetLinearVelocity());
      const double om = b->GetAngularVelocity();
      still = still && v == Vec2::Zero() && om == 0.0;
      dv += w * (v - o.velF);
      dw += w * (om - o.omegaF);
      s.touching = HasTouchingContact(s.body);
      touched = touched || s.touching;
      if (s.touching) {
        corr += w * ((FromB2(b->GetWorldCenter()) - o.centerF) - v * dt);
        corrA += w * ((b->GetAngle() - o.angleF) - om * dt);
      }
    }
    // An object at rest that nothing touched, pushed, held or rested on in this substep stays
    // as it is: the friction solve and the write-back below would give it back the same pose and
    // no motion, bit for bit. Its slices sleep in their worlds until something touches or
    // pushes one (Box2D wakes a body that a contact starts touching or a force is applied to;
    // WriteBack wakes the others): a slice at rest has nothing to solve, and its friction joint
    // holds no impulse.
    if (still && !touched && !o.sliding && onTop[oi].empty() && pushes[oi].empty() &&
        o.omega == 0.0 && o.vel == Vec2::Zero() && table.angular == 0.0 &&
        table.linear == Vec2::Zero()) {
      for (Slice& s : o.slices) s.body->SetAwake(false);
      o.slideForce.setZero();
      o.slideTorque = 0.0;
      o.particlesOnTop = 0;
      continue;
    }
    Vec2 vel = o.vel + dv;
    double omega = o.omega + dw;
    if (!pushes[oi].empty()) LimitRelease(oi, pushes[oi], &vel, &omega);
    const Vec2 centerAfterStep = o.center + vel * dt + corr;

    // Table friction was solved inside the layer worlds, together with the side contacts (each
    // slice's joint may hold the whole limit). Here its sum over the slices is brought within the
    // Coulomb limit, and top friction is solved together with it: a finger on top can only drag
    // the object when its friction beats the table's, which a sequential pass gets wrong (top
    // friction would only supply what matches the finger's speed in one substep, and the table's
    // static check would then cancel it every substep).
    //
    // Coulomb on the table: an object that moves at the substep's start (it slid in the last
    // one, or was set moving) slides, at kinetic friction, until that friction stops it; only an
    // object at rest meets static friction. (Asking first whether mu_s could stop a sliding
    // object stopped slow ones that mu_k would not, every other substep.) In the substep in
    // which an object at rest breaks loose, the layers solved its contacts against the joints'
    // static limits: a grip that sticks to it gave it only what moves it at the grip's speed
    // against mu_s. Where it has contacts, friction stays at mu_s through that substep;
    // re-solved at mu_k, the object would get (mu_s - mu_k) N dt of momentum that no contact
    // supplied and run ahead of the grip (a light object turned at 2 substeps by up to 40% more
    // than the grip). Without contacts (a force applied to it) nothing was solved against the
    // limit and mu_k is exact.
    const double N = TableNormal(oi);
    const bool moving = o.sliding || o.vel.squaredNorm() > 0.0 || (o.rEff > 0.0 && o.omega != 0.0);
    FrictionSolve solve =
        SolveFriction(oi, onTop[oi], centerAfterStep, vel, omega, table, N, false);
    const bool breakingLoose = !moving && solve.tableSliding && touched;
    if (moving) solve.tableSliding = true;
    if (solve.tableSliding || solve.anyTopSliding) {
      solve = SolveFriction(oi, onTop[oi], centerAfterStep, vel, omega, table, N, true, &solve,
                            breakingLoose);
    }
    for (size_t k = 0; k < onTop[oi].size(); ++k) {
      ApplyParticleImpulse(particles[onTop[oi][k]], 0, -solve.top[k]);
      o.topFriction += solve.top[k];
    }
    o.topNormal += fd * static_cast<double>(onTop[oi].size()) * dt;
    o.particlesOnTop = static_cast<int>(onTop[oi].size());

    // the substep's displacement follows the velocity after friction (symplectic Euler, as Box2D
    // integrates); static table friction holds the object exactly still (a push within the
    // static limits leaves only the contacts' position corrections)
    Vec2 move = solve.vel * dt + corr;
    double turn = solve.omega * dt + corrA;
    if (!solve.tableSliding) {
      solve.vel.setZero();
      move = corr;
      // a sphere without a contact patch has nothing that resists its turning
      if (o.rEff > 0) {
        solve.omega = 0.0;
        turn = corrA;
      }
    }
    vel = solve.vel;
    omega = solve.omega;
    o.sliding = solve.tableSliding;
    o.slideForce.setZero();
    o.slideTorque = 0.0;
    if (solve.tableSliding) {
      // the next substep's joints resist with kinetic friction, also after one at mu_s
      const double toKinetic = breakingLoose && o.spec.tableStatic > 0.0
                                   ? o.spec.tableKinetic / o.spec.tableStatic
                                   : 1.0;
      for (size_t k = 0; k < o.tablePoints.size(); ++k) {
        const Vec2 arm = o.ToTableDirection(o.tablePoints[k].arm);
        o.slideForce += toKinetic * solve.table[k] / dt;
        o.slideTorque += toKinetic * Cross(arm, solve.table[k]) / dt;
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
    if (!s.body->IsAwake()) s.body->SetAwake(true);
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
