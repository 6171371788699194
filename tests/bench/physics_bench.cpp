// LayeredWorld::Step on a two-hand scene: K = 8 layers, 10 (or 2) objects, 600 particles (two hand
// outlines of 300 points sweeping over the objects), serial versus threaded layer stepping.
//   build/release/bench_physics [--benchmark_filter=...]
#include "proxygrasp/core/units.h"
#include "proxygrasp/physics/layered_world.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pg {
namespace {

constexpr int kPointsPerHand = 300;

// a hand-like closed outline: a disc with five finger lobes, centred at c
Vec2 HandPoint(const Vec2& c, int i, double t) {
  const double a = 2.0 * kPi * i / kPointsPerHand;
  const double r = 5.0 * (1.0 + 0.35 * std::max(0.0, std::sin(5.0 * a + 0.5 * t)));
  return c + r * Vec2(std::cos(a), std::sin(a));
}

std::vector<ObjectSpec> Objects() {
  std::vector<ObjectSpec> objects;
  for (int i = 0; i < 10; ++i) {
    ObjectSpec s;
    s.name = "obj" + std::to_string(i);
    s.pose.pos = Vec2(8.0 + 5.0 * i, i % 2 == 0 ? 18.0 : 28.0);
    s.pose.angle = 0.3 * i;
    switch (i % 4) {
      case 0:
        s.shape = ObjectShape::kBox;
        s.sizeX = 3;
        s.sizeY = 4;
        s.height = 3;
        break;
      case 1:
        s.shape = ObjectShape::kCylinder;
        s.radius = 1.8;
        s.height = 5;
        break;
      case 2:
        s.shape = ObjectShape::kSphere;
        s.radius = 1.5;
        break;
      default:
        s.shape = ObjectShape::kConcavePrism;
        s.points = {Vec2(-2, -2), Vec2(2, -2), Vec2(2, 0), Vec2(0, 0), Vec2(0, 2), Vec2(-2, 2)};
        s.height = 2;
        break;
    }
    objects.push_back(s);
  }
  return objects;
}

Vec2 HandCentre(int hand, double t) {
  const Vec2 c0 = hand == 0 ? Vec2(18, 23) : Vec2(42, 23);
  return c0 + Vec2(8.0 * std::sin(0.7 * t + hand), 6.0 * std::cos(0.5 * t));
}

void BM_StepFrameTwoHands(benchmark::State& state) {
  PhysicsParams p;
  p.layers = 8;
  p.threads = static_cast<int>(state.range(0));
  p.stackSize = static_cast<int>(state.range(1));
  LayeredWorld world;
  // the first `objects` of the ten: with 2, most of each hand is far from every object
  std::vector<ObjectSpec> objects = Objects();
  objects.resize(static_cast<size_t>(state.range(2)));
  if (world.Build(p, TableParams{}, objects)) {
    state.SkipWithError("build failed");
    return;
  }
  // create both hands, then let the scene get going
  ParticlePlan plan;
  for (int hand = 0; hand < 2; ++hand) {
    for (int i = 0; i < kPointsPerHand; ++i) {
      PlannedParticle pp;
      pp.id = 1 + hand * kPointsPerHand + i;
      pp.action = ParticleAction::kCreated;
      pp.start = pp.target = HandPoint(HandCentre(hand, 0.0), i, 0.0);
      plan.particles.push_back(pp);
    }
  }
  world.ApplyPlan(plan);
  int64_t frame = 0;
  auto step = [&] {
    ++frame;
    const double t = frame / 60.0;
    for (PlannedParticle& pp : plan.particles) {
      const int hand = (pp.id - 1) / kPointsPerHand, i = (pp.id - 1) % kPointsPerHand;
      pp.action = ParticleAction::kReused;
      pp.target = HandPoint(HandCentre(hand, t), i, t);
    }
    world.Step(plan);
  };
  for (int i = 0; i < 60; ++i) step();
  double substeps = 0.0;  // taken per frame, on average (more than 4 where a grip needs them)
  for (auto _ : state) {
    step();
    substeps += world.FrameSubsteps();
  }
  state.counters["substeps"] = substeps / std::max<double>(1.0, state.iterations());
  state.counters["bodies"] = world.BodyCount();
  state.counters["particles"] = world.ParticleCount();
  state.counters["active"] = world.ActiveParticleCount();
  state.counters["solved"] = world.SolvedBodyCount();
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StepFrameTwoHands)
    ->ArgNames({"threads", "stack", "objects"})
    ->Args({1, 1, 10})
    ->Args({2, 1, 10})
    ->Args({1, 3, 10})
    ->Args({2, 3, 10})
    ->Args({1, 3, 2})
    ->Args({2, 3, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace pg

BENCHMARK_MAIN();
