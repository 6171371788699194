// LayeredWorld (src/physics/layered_world.cpp): building and its errors, the scene queries,
// plans, diagnostics for drawing, and determinism serial versus threaded.
#include "physics_test_util.h"

#include "proxygrasp/core/rng.h"
#include "proxygrasp/core/units.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace pg {
namespace {

using test::Box;
using test::Create;
using test::MustBuild;
using test::Plan;
using test::Reuse;

TEST(Build, BadObjectGivesErrorAtItsPlaceAndLeavesWorldEmpty) {
  PhysicsParams p;
  LayeredWorld w;
  MustBuild(w, p, {Box("ok", 10, 10)});
  ObjectSpec bad = Box("cup", 20, 20);
  bad.shape = ObjectShape::kCylinder;
  bad.radius = 0;
  bad.loc = SourceLoc{"levels/cups.toml", 12, 5};
  const MaybeError s = w.Build(p, TableParams{}, std::vector<ObjectSpec>{Box("ok", 10, 10), bad});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->Format(), "levels/cups.toml:12:5: object 'cup': radius must be > 0 (got 0)");
  EXPECT_EQ(w.ObjectCount(), 0);
  EXPECT_EQ(w.BodyCount(), 0);
  // stepping an empty world is harmless
  w.StepFrame();
}

TEST(Build, Box2DStepsAreTimedOnlyWhenAsked) {
  PhysicsParams p;
  LayeredWorld w;
  MustBuild(w, p, {Box("box", 10, 10)});
  w.StepFrame();
  EXPECT_EQ(w.Box2DMs(), 0.0);
  // with a clock the time is a reading of it, whatever its size; without one again, 0
  w.SetBox2DClock(TimerClock::kThreadCpu);
  w.StepFrame();
  EXPECT_TRUE(std::isfinite(w.Box2DMs()));
  EXPECT_GE(w.Box2DMs(), 0.0);
  w.SetBox2DClock(std::nullopt);
  w.StepFrame();
  EXPECT_EQ(w.Box2DMs(), 0.0);
}

TEST(Build, OffTableObjectAndBadParamsAreErrors) {
  PhysicsParams p;
  LayeredWorld w;
  ObjectSpec far = Box("lost", 70, 10);
  far.loc = SourceLoc{"levels/a.toml", 4, 1};
  MaybeError s = w.Build(p, TableParams{}, std::vector<ObjectSpec>{far});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->Format(),
            "levels/a.toml:4:1: object 'lost': pose puts its centre at (70, 10) cm, outside the "
            "61 x 46 cm table");
  p.layers = 20;
  s = w.Build(p, TableParams{}, std::vector<ObjectSpec>{});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->message, "physics.layers must be in [1, 16] (got 20)");
}

TEST(Build, SlicesPerLayerAndOutlinesForDrawing) {
  PhysicsParams p;
  ObjectSpec ball;
  ball.name = "ball";
  ball.shape = ObjectShape::kSphere;
  ball.radius = 2.0;
  ball.pose.pos = Vec2(30, 23);
  ObjectSpec l;
  l.name = "ell";
  l.shape = ObjectShape::kConcavePrism;
  l.points = {Vec2(0, 0), Vec2(4, 0), Vec2(4, 2), Vec2(2, 2), Vec2(2, 4), Vec2(0, 4)};
  l.height = 1.0;
  l.pose.pos = Vec2(10, 10);
  LayeredWorld w;
  MustBuild(w, p, {ball, l});
  EXPECT_EQ(w.BodyCount(), 4 + 1);
  const std::vector<SliceOutline> s = w.Slices(0);
  ASSERT_EQ(s.size(), 4u);
  for (const SliceOutline& so : s) {
    const double r = std::sqrt(4.0 - (so.z - 2.0) * (so.z - 2.0));
    EXPECT_NEAR(so.outline.col(0).norm(), r, 1e-12);
  }
  const std::vector<SliceOutline> ls = w.Slices(1);
  ASSERT_EQ(ls.size(), 1u);
  EXPECT_EQ(ls[0].pieces.size(), 2u);
  // the prism's pose is its local origin; the centre of mass is the L's centroid
  const ObjectState st = w.Object(1);
  EXPECT_NEAR((st.pose.pos - Vec2(10, 10)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((st.centerOfMass - Vec2(10 + 5.0 / 3.0, 10 + 5.0 / 3.0)).norm(), 0.0, 1e-12);
  // at rest it stays exactly where it is
  for (int i = 0; i < 10; ++i) w.StepFrame();
  EXPECT_NEAR((w.Object(1).pose.pos - Vec2(10, 10)).norm(), 0.0, 1e-5);
  EXPECT_EQ(w.Frame(), 10);
}

TEST(Queries, HeightsDepthsAndNearestOutside) {
  PhysicsParams p;
  ObjectSpec box = Box("box", 20, 20, 4, 2, 3.0);
  box.pose.angle = kPi / 2;  // 2 wide along x, 4 along y once turned
  ObjectSpec ball;
  ball.name = "ball";
  ball.shape = ObjectShape::kSphere;
  ball.radius = 2.0;
  ball.pose.pos = Vec2(40, 20);
  LayeredWorld w;
  MustBuild(w, p, {box, ball});
  EXPECT_DOUBLE_EQ(w.TopHeightAt(Vec2(20.5, 21.5)), 3.0);
  EXPECT_DOUBLE_EQ(w.TopHeightAt(Vec2(21.5, 20)), 0.0);  // beside the turned box
  EXPECT_NEAR(w.TopHeightAt(Vec2(41, 20)), 2.0 + std::sqrt(3.0), 1e-12);

  double top = -1;
  EXPECT_NEAR(w.FootprintDepth(Vec2(20.2, 20), &top), 0.8, 1e-9);
  EXPECT_DOUBLE_EQ(top, 3.0);
  EXPECT_NEAR(w.FootprintDepth(Vec2(40, 20.5), &top), 1.5, 1e-9);
  EXPECT_DOUBLE_EQ(top, 4.0);
  EXPECT_LT(w.FootprintDepth(Vec2(30, 30), &top), 0.0);
  EXPECT_DOUBLE_EQ(top, 0.0);

  // out through the nearest side of the turned box (x = 21), and radially out of the ball
  const Vec2 out = w.NearestOutside(Vec2(20.7, 20.5));
  EXPECT_NEAR((out - Vec2(21, 20.5)).norm(), 0.0, 1e-5);
  const Vec2 outBall = w.NearestOutside(Vec2(41, 20));
  EXPECT_NEAR((outBall - Vec2(42, 20)).norm(), 0.0, 1e-5);
  EXPECT_EQ(w.NearestOutside(Vec2(5, 5)), Vec2(5, 5));
}

TEST(Queries, NearestOutsideLeavesOverlappingFootprints) {
  PhysicsParams p;
  ObjectSpec a = Box("a", 20, 20, 4, 4, 1.0);
  ObjectSpec b = Box("b", 23.5, 20, 4, 4, 1.0);  // overlaps a on x in [21.5, 22]
  a.mass = b.mass = 1e6;
  LayeredWorld w;
  MustBuild(w, p, {a, b});
  const Vec2 q = w.NearestOutside(Vec2(21.8, 20));
  double top;
  EXPECT_LE(w.FootprintDepth(q, &top), 0.0);
  // the union spans x in [18, 25.5] and y in [18, 22]: the nearest way out is 2 cm along y
  EXPECT_NEAR((q - Vec2(21.8, 20)).norm(), 2.0, 1e-5);
  EXPECT_NEAR(std::abs(q.y() - 20.0), 2.0, 1e-5);
}

TEST(Plan, UnknownAndDuplicateEntriesAreCountedAndSkipped) {
  PhysicsParams p;
  LayeredWorld w;
  MustBuild(w, p, {});
  w.ApplyPlan(Plan({Create(1, Vec2(5, 5), Vec2(5, 5)), Create(1, Vec2(6, 6), Vec2(6, 6)),
                    Reuse(7, Vec2(1, 1)), test::Delete(9)}));
  EXPECT_EQ(w.PlanErrors(), 3);
  EXPECT_EQ(w.ParticleCount(), 1);
  const std::vector<ParticleFeedback> fb = w.Feedback();
  ASSERT_EQ(fb.size(), 1u);
  EXPECT_EQ(fb[0].id, 1);
  EXPECT_EQ(fb[0].pos, Vec2(5, 5));
  // bad pushes are counted and dropped too
  w.ApplyForce(3, Vec2(1, 0), Vec2(0, 0), 0);
  EXPECT_EQ(w.PlanErrors(), 4);
  // a particle created high above the empty table falls to it at once
  w.ApplyPlan(Plan({Create(2, Vec2(8, 8), Vec2(8, 8), 3.0)}));
  EXPECT_EQ(w.Particles()[1].baseLayer, 0);
  EXPECT_EQ(w.Particles()[1].baseHeight, 0.0);
}

TEST(Plan, RandomCreateReuseDeleteKeepsBookkeepingConsistent) {
  PhysicsParams p;
  p.stackSize = 2;
  LayeredWorld w;
  MustBuild(w, p, {Box("a", 20, 20, 4, 4, 3.0), test::Cylinder("b", 35, 25, 2.0, 5.0)});
  const int slices = w.BodyCount();
  Rng rng(11);
  std::vector<ParticleId> alive;
  int nextId = 1;
  for (int f = 0; f < 120; ++f) {
    ParticlePlan plan;
    std::vector<ParticleId> keep;
    for (ParticleId id : alive) {
      const Vec2 at(rng.Uniform(10, 50), rng.Uniform(10, 36));
      if (rng.Uniform() < 0.1) {
        plan.particles.push_back(test::Delete(id));
      } else {
        // small steps, sometimes into the objects
        const ParticleState s =
            w.Particles()[std::distance(alive.begin(), std::find(alive.begin(), alive.end(), id))];
        plan.particles.push_back(Reuse(id, s.target + 0.3 * (at - s.target).normalized()));
        keep.push_back(id);
      }
    }
    for (int i = 0; i < 8; ++i) {
      const Vec2 at(rng.Uniform(10, 50), rng.Uniform(10, 36));
      plan.particles.push_back(Create(nextId, at, at, w.TopHeightAt(at)));
      keep.push_back(nextId++);
    }
    w.ApplyPlan(plan);
    if (f % 7 == 0)
      w.ApplyForce(f % 2, Vec2(rng.Uniform(-5e4, 5e4), rng.Uniform(-5e4, 5e4)),
                   w.Object(f % 2).centerOfMass, f % 3);
    w.StepFrame();
    alive = keep;
    // every stack is listed once in creation order, with the bodies of the active ones counted
    const std::vector<ParticleState> ps = w.Particles();
    ASSERT_EQ(ps.size(), alive.size());
    int bodies = slices, active = 0;
    for (size_t i = 0; i < ps.size(); ++i) {
      ASSERT_EQ(ps[i].id, alive[i]);
      ASSERT_TRUE(ps[i].pos.allFinite());
      ASSERT_EQ(ps[i].layerCount, std::min(p.stackSize, p.layers - ps[i].baseLayer));
      bodies += ps[i].active ? ps[i].layerCount : 0;
      active += ps[i].active ? 1 : 0;
    }
    ASSERT_EQ(w.BodyCount(), bodies);
    ASSERT_EQ(w.ActiveParticleCount(), active);
    ASSERT_TRUE(w.SlicesAgree());
    for (int i = 0; i < w.ObjectCount(); ++i) ASSERT_TRUE(w.Object(i).pose.pos.allFinite());
  }
  EXPECT_EQ(w.PlanErrors(), 0);
}

// a busy scene: objects of every shape, two rings of stacked particles sweeping through them
struct Busy {
  LayeredWorld world;
  int nextId = 1;
  std::vector<ParticleId> ids;

  explicit Busy(int threads, const PhysicsParams& base = PhysicsParams()) {
    PhysicsParams p = base;
    p.threads = threads;
    p.stackSize = 3;
    std::vector<ObjectSpec> objects = {Box("a", 20, 20, 4, 4, 2.0), Box("b", 30, 25, 3, 6, 5.0),
                                       test::Cylinder("c", 40, 20, 2.0, 3.0)};
    ObjectSpec ball;
    ball.name = "ball";
    ball.shape = ObjectShape::kSphere;
    ball.radius = 1.5;
    ball.pose.pos = Vec2(25, 32);
    objects.push_back(ball);
    ObjectSpec cone;
    cone.name = "cone";
    cone.shape = ObjectShape::kFrustum;
    cone.radius = 2;
    cone.topRadius = 0.5;
    cone.height = 4;
    cone.pose.pos = Vec2(35, 33);
    objects.push_back(cone);
    MustBuild(world, p, objects);
  }

  void Frame(int f) {
    ParticlePlan plan;
    // two rings of 60 particles orbiting and shrinking into the objects
    Rng rng(static_cast<uint64_t>(f));
    for (int ring = 0; ring < 2; ++ring) {
      const Vec2 c = ring == 0 ? Vec2(25, 23) : Vec2(36, 27);
      const double r = 12.0 - 0.08 * f;
      for (int i = 0; i < 60; ++i) {
        const double a = 2 * kPi * i / 60 + 0.02 * f;
        const Vec2 at =
            c + r * Vec2(std::cos(a), std::sin(a)) + 0.05 * Vec2(rng.Uniform(), rng.Uniform());
        const int slot = ring * 60 + i;
        if (f == 0) {
          ids.push_back(nextId);
          plan.particles.push_back(Create(nextId++, at, at, ring == 0 ? 0.0 : 2.0));
        } else {
          plan.particles.push_back(Reuse(ids[slot], at));
        }
      }
    }
    world.ApplyPlan(plan);
    world.StepFrame();
  }
};

TEST(Determinism, ThreadedSteppingIsBitIdenticalToSerial) {
  Busy serial(1), threaded(4);
  bool moved = false;
  for (int f = 0; f < 90; ++f) {
    serial.Frame(f);
    threaded.Frame(f);
    ASSERT_EQ(serial.world.StateHash(), threaded.world.StateHash()) << "frame " << f;
    for (int i = 0; i < serial.world.ObjectCount(); ++i) {
      moved |= serial.world.Object(i).velocity.norm() > 1.0;
    }
  }
  EXPECT_TRUE(moved) << "the scene was not busy: no object moved";
  // and the same run twice gives the same state
  Busy again(2);
  for (int f = 0; f < 90; ++f) again.Frame(f);
  EXPECT_EQ(again.world.StateHash(), serial.world.StateHash());
}

// every parameter SetParams may change (the live ones), away from its default
PhysicsParams Tuned() {
  PhysicsParams p;
  p.substeps = 5;
  p.velocityIterations = 6;
  p.positionIterations = 4;
  p.gravity = 700;
  p.gripStiffness = 40000;
  p.gripDamping = 120;
  p.gripMaxDepth = 0.3;
  p.particleDownForce = 3500;
  p.particleFriction = 0.5;
  p.topKineticFactor = 0.6;
  p.heldOpposingDot = -0.7;
  p.heldFrictionMargin = 0.9;
  return p;
}

TEST(SetParams, RetunedWorldRunsLikeOneBuiltWithTheNewParameters) {
  PhysicsParams tuned = Tuned();
  tuned.stackSize = 3;  // as Busy builds
  Busy built(1, tuned), retuned(1);
  tuned.threads = 2;  // threads change the pool, never the results
  ASSERT_EQ(retuned.world.SetParams(tuned), std::nullopt);
  EXPECT_EQ(retuned.world.params().substeps, 5);
  for (int f = 0; f < 60; ++f) {
    built.Frame(f);
    retuned.Frame(f);
    ASSERT_EQ(built.world.StateHash(), retuned.world.StateHash()) << "frame " << f;
  }
}

TEST(SetParams, KeepsTheStateAndChangesTheRunFromTheNextFrame) {
  Busy a(1), b(1);
  for (int f = 0; f < 30; ++f) {
    a.Frame(f);
    b.Frame(f);
  }
  const uint64_t before = b.world.StateHash();
  PhysicsParams tuned = Tuned();
  tuned.stackSize = 3;
  ASSERT_EQ(b.world.SetParams(tuned), std::nullopt);
  // nothing moved: objects and particles are where they were
  EXPECT_EQ(b.world.StateHash(), before);
  EXPECT_EQ(b.world.ParticleCount(), a.world.ParticleCount());
  a.Frame(30);
  b.Frame(30);
  EXPECT_NE(a.world.StateHash(), b.world.StateHash());
}

TEST(SetParams, RebuildKeysAndBadValuesAreErrorsThatChangeNothing) {
  Busy b(1);
  b.Frame(0);
  const PhysicsParams before = b.world.params();
  PhysicsParams p = before;
  p.layers = 6;
  p.particleRadius = 0.3;
  EXPECT_EQ(b.world.FixedKeysChanged(p), (std::vector<std::string>{"layers", "particle_radius"}));
  p.substeps = 7;
  MaybeError s = b.world.SetParams(p);
  ASSERT_NE(s, std::nullopt);
  EXPECT_THAT(s->Format(), ::testing::HasSubstr("layers"));
  EXPECT_EQ(b.world.params().substeps, before.substeps);
  p = before;
  p.substeps = 0;
  s = b.world.SetParams(p);
  ASSERT_NE(s, std::nullopt);
  EXPECT_THAT(s->Format(), ::testing::HasSubstr("substeps"));
  EXPECT_EQ(b.world.params().substeps, before.substeps);
  EXPECT_TRUE(b.world.FixedKeysChanged(before).empty());
  LayeredWorld empty;
  EXPECT_NE(empty.SetParams(before), std::nullopt);
}

}  // namespace
}  // namespace pg
