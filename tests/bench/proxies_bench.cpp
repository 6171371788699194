// Contour matching speed on a two-hand frame: two hand outlines of 500 points each, moved between
// frames. Run pinned to one core:
//   taskset -c 0 build/release/bench_proxies
// Figures and the machine are recorded in docs/performance.md ("Contour matching").
#include "proxygrasp/core/rng.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/proxies/matching.h"
#include "proxygrasp/proxies/proxy_stage.h"

#include <benchmark/benchmark.h>

#include <vector>

#include "proxies/test_shapes.h"

namespace pg {
namespace {

using testing::HandOutline;
using testing::Moved;
using testing::Sensed;

// points per hand contour
constexpr int kHandPoints = 500;
// frame pairs in the prepared sequence (each iteration matches one pair for both hands)
constexpr int kFrames = 32;
constexpr int kWindow = 8;
constexpr int kRadius = 12;

// One frame: the two hand contours.
struct Frame {
  Contour hands[2];
};

// A sequence of frames in which each hand moves by up to `move` cm and turns by up to `turn`
// degrees per frame, in random directions.
std::vector<Frame> MakeSequence(double move, double turn) {
  const Contour outline = HandOutline();
  const double spacing = Perimeter(outline) / kHandPoints;
  Rng rng(17);
  Pose2 poses[2] = {{Vec2(18, 22), 0.35}, {Vec2(43, 22), -0.35}};
  std::vector<Frame> frames;
  for (int f = 0; f <= kFrames; ++f) {
    Frame frame;
    for (int h = 0; h < 2; ++h) {
      frame.hands[h] = Sensed(Moved(outline, poses[h]), spacing);
      const double dir = rng.Uniform(-kPi, kPi);
      poses[h].pos += move * rng.Uniform(0.5, 1.0) * Vec2(std::cos(dir), std::sin(dir));
      poses[h].angle += DegToRad(rng.Uniform(-turn, turn));
    }
    frames.push_back(frame);
  }
  return frames;
}

// everyday motion: 0.5 cm and 2 degrees per 60 Hz frame (30 cm/s, 120 deg/s)
const std::vector<Frame>& Everyday() {
  static const std::vector<Frame> frames = MakeSequence(0.5, 2.0);
  return frames;
}

// the extreme of the acceptance range: 3 cm and 15 degrees per frame
const std::vector<Frame>& Extreme() {
  static const std::vector<Frame> frames = MakeSequence(3.0, 15.0);
  return frames;
}

template <typename MatchFn>
void RunPairs(benchmark::State& state, const std::vector<Frame>& frames, MatchFn match) {
  int f = 0;
  int fallbacks = 0;
  int points = 0;
  for (auto _ : state) {
    for (int h = 0; h < 2; ++h) {
      const MatchResult r = match(frames[f].hands[h], frames[f + 1].hands[h]);
      benchmark::DoNotOptimize(r.successor.data());
      fallbacks += r.fallbacks;
      points += static_cast<int>(r.successor.size());
    }
    f = (f + 1) % kFrames;
  }
  state.counters["points"] =
      static_cast<double>(frames[0].hands[0].cols() + frames[0].hands[1].cols());
  state.counters["fallback_fraction"] = points > 0 ? static_cast<double>(fallbacks) / points : 0;
}

void BM_MatchReference(benchmark::State& state) {
  RunPairs(state, Everyday(),
           [](const Contour& a, const Contour& b) { return MatchReference(a, b, kWindow); });
}

void BM_MatchFast(benchmark::State& state) {
  RunPairs(state, Everyday(),
           [](const Contour& a, const Contour& b) { return MatchFast(a, b, kWindow); });
}

// the prediction is part of the windowed search's cost
void BM_MatchWindowed(benchmark::State& state) {
  RunPairs(state, Everyday(), [](const Contour& a, const Contour& b) {
    return MatchWindowed(a, b, kWindow, PredictSuccessors(a, b), kRadius,
                         ProxyParams{}.fallbackScore);
  });
}

void BM_MatchReferenceExtreme(benchmark::State& state) {
  RunPairs(state, Extreme(),
           [](const Contour& a, const Contour& b) { return MatchReference(a, b, kWindow); });
}

void BM_MatchFastExtreme(benchmark::State& state) {
  RunPairs(state, Extreme(),
           [](const Contour& a, const Contour& b) { return MatchFast(a, b, kWindow); });
}

void BM_MatchWindowedExtreme(benchmark::State& state) {
  RunPairs(state, Extreme(), [](const Contour& a, const Contour& b) {
    return MatchWindowed(a, b, kWindow, PredictSuccessors(a, b), kRadius,
                         ProxyParams{}.fallbackScore);
  });
}

// A scene with nothing on the table.
class EmptyScene : public SceneQuery {
 public:
  double TopHeightAt(const Vec2&) const override { return 0.0; }
  double FootprintDepth(const Vec2&, double* top) const override {
    if (top) *top = 0.0;
    return 0.0;
  }
  Vec2 NearestOutside(const Vec2& p) const override { return p; }
  ObjectId ObjectAt(const Vec2&) const override { return kNoObject; }
};

// the whole persistent stage on the two-hand sequence: matching plus the particle lifecycle
void StageRun(benchmark::State& state, MatchAlgorithm algorithm) {
  const std::vector<Frame>& frames = Everyday();
  ProxyParams params;
  params.algorithm = algorithm;
  EmptyScene scene;
  ProxyStage stage(params);
  int f = 0;
  for (auto _ : state) {
    ContactSet set;
    set.frame = f;
    for (int h = 0; h < 2; ++h) {
      Contact c;
      c.id = h + 1;
      c.state = f == 0 ? ContactState::kNew : ContactState::kContinuing;
      c.blob.contour = frames[f].hands[h];
      set.contacts.push_back(c);
    }
    const ParticlePlan plan = stage.Step(set, scene, {}, nullptr);
    benchmark::DoNotOptimize(plan.particles.data());
    f = (f + 1) % (kFrames + 1);
    // start over rather than jump from the last frame back to the first
    if (f == 0) stage.Reset();
  }
}

void BM_StageFast(benchmark::State& state) {
  StageRun(state, MatchAlgorithm::kFast);
}

void BM_StageWindowed(benchmark::State& state) {
  StageRun(state, MatchAlgorithm::kWindowed);
}

BENCHMARK(BM_MatchReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchFast)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchWindowed)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchReferenceExtreme)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchFastExtreme)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchWindowedExtreme)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StageFast)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StageWindowed)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace pg

BENCHMARK_MAIN();
