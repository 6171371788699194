// Small builders shared by the physics tests: object specs and particle plans.
#pragma once

#include "proxygrasp/physics/layered_world.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace pg::test {

/// A box of the given size, centred at (x, y).
inline ObjectSpec Box(const std::string& name, double x, double y, double sx = 4.0, double sy = 4.0,
                      double height = 2.0) {
  ObjectSpec s;
  s.name = name;
  s.shape = ObjectShape::kBox;
  s.sizeX = sx;
  s.sizeY = sy;
  s.height = height;
  s.pose.pos = Vec2(x, y);
  return s;
}

/// A cylinder of radius r centred at (x, y).
inline ObjectSpec Cylinder(const std::string& name, double x, double y, double r, double height) {
  ObjectSpec s;
  s.name = name;
  s.shape = ObjectShape::kCylinder;
  s.radius = r;
  s.height = height;
  s.pose.pos = Vec2(x, y);
  return s;
}

/// Builds a world and fails the test on error.
inline void MustBuild(LayeredWorld& world, const PhysicsParams& p,
                      const std::vector<ObjectSpec>& objects, const TableParams& table = {}) {
  const MaybeError s = world.Build(p, table, objects);
  ASSERT_FALSE(s.has_value()) << s->Format();
}

/// A plan entry creating particle id at start with a target.
inline PlannedParticle Create(ParticleId id, const Vec2& start, const Vec2& target,
                              double baseHeight = 0.0) {
  PlannedParticle pp;
  pp.id = id;
  pp.contact = 1;
  pp.action = ParticleAction::kCreated;
  pp.start = start;
  pp.target = target;
  pp.baseHeight = baseHeight;
  return pp;
}

/// A plan entry moving particle id to target.
inline PlannedParticle Reuse(ParticleId id, const Vec2& target) {
  PlannedParticle pp;
  pp.id = id;
  pp.contact = 1;
  pp.action = ParticleAction::kReused;
  pp.target = target;
  return pp;
}

/// A plan entry deleting particle id.
inline PlannedParticle Delete(ParticleId id) {
  PlannedParticle pp;
  pp.id = id;
  pp.action = ParticleAction::kDeleted;
  return pp;
}

/// A plan that only holds the listed entries.
inline ParticlePlan Plan(std::vector<PlannedParticle> entries) {
  ParticlePlan plan;
  plan.particles = std::move(entries);
  return plan;
}

}  // namespace pg::test
