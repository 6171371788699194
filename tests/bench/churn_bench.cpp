// Particle churn against speed and turn rate (issue 16), through the whole pipeline: synthetic
// camera with its noise, sensing, tracking, proxies and physics, one second of contact on an
// empty table. Each benchmark runs one scene once and reports, as counters, the particles created
// and deleted per frame after the contact's first frame and the largest drift of a kept particle
// in the contact's own frame. Time per iteration is the pipeline's whole cost for the second of
// contact and is not the figure of interest here.
//
//   build/release/bench_churn                      fast search (the default)
//   build/release/bench_churn --algorithm=reference the paper's literal search, for comparison
//   build/release/bench_churn --seed=N             another camera noise seed
#include "proxygrasp/bench/churn.h"
#include "proxygrasp/core/units.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace pg {
namespace {

MatchAlgorithm g_algorithm = MatchAlgorithm::kFast;
int g_seed = 0;  // 0: the default camera seed

ChurnScene SceneOf(int shape) {
  switch (shape) {
    case 0:
      return FingertipScene();
    case 1:
      return OvalScene();
    default:
      return FlatHandScene();
  }
}

// args: shape (0 fingertip, 1 oval, 2 flat hand), speed in cm/s, turn rate in degrees/s
void BM_Churn(benchmark::State& state) {
  ChurnScene scene = SceneOf(static_cast<int>(state.range(0)));
  scene.speed = static_cast<double>(state.range(1));
  scene.turnRate = DegToRad(static_cast<double>(state.range(2)));
  LevelParams params;
  params.proxies.algorithm = g_algorithm;
  if (g_seed != 0) params.camera.seed = g_seed;
  ChurnResult result;
  for (auto _ : state) {
    const Result<ChurnResult> r = MeasureChurn(scene, params);
    if (!r.ok()) {
      state.SkipWithError(r.error().Format().c_str());
      return;
    }
    result = r.value();
  }
  const double frames = result.frames > 0 ? result.frames : 1;
  state.SetLabel(scene.name);
  state.counters["particles"] = result.firstParticles;
  state.counters["created/frame"] = result.created / frames;
  state.counters["deleted/frame"] = result.deleted / frames;
  state.counters["kept"] = result.kept;
  state.counters["drift_cm"] = result.maxDrift;
}

void ChurnArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"shape", "cm_per_s", "deg_per_s"});
  for (int shape = 0; shape < 3; ++shape) {
    for (int speed : {2, 5, 10, 20, 40, 60}) b->Args({shape, speed, 0});
    for (int turn : {30, 60, 120, 180}) b->Args({shape, 0, turn});
  }
}

BENCHMARK(BM_Churn)->Apply(ChurnArgs)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pg

int main(int argc, char** argv) {
  // our own flag first, then Google Benchmark's
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--seed=", 7) == 0) {
      pg::g_seed = std::atoi(argv[i] + 7);
      continue;
    }
    const char* prefix = "--algorithm=";
    if (std::strncmp(argv[i], prefix, std::strlen(prefix)) == 0) {
      const std::string name = argv[i] + std::strlen(prefix);
      bool found = false;
      for (int a = 0; a < 3; ++a) {
        if (name == pg::kMatchAlgorithmNames[a]) {
          pg::g_algorithm = static_cast<pg::MatchAlgorithm>(a);
          found = true;
        }
      }
      if (!found) {
        std::fprintf(stderr, "bench_churn: --algorithm=%s: expected fast, windowed or reference\n",
                     name.c_str());
        return 2;
      }
      continue;
    }
    argv[kept++] = argv[i];
  }
  argc = kept;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
