// Latency of TUIO input (issue 18): from the moment a frame's bundles are sent on the loopback to
// the moment the physics has applied them. A level's contacts are first sensed from its script
// and encoded; each iteration then sends one frame's bundles to tuio:127.0.0.1:PORT and steps a
// second simulation of the level from that input: receive, decode, resample, proxies, physics.
// The figure is the iteration's wall time; the counters split off the simulation's own stages.
//
//   build/release/bench_tuio                 every level below
//   build/release/bench_tuio --benchmark_filter=demo_sort
#include "proxygrasp/level/level.h"
#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/run/tuio_output.h"
#include "proxygrasp/tuio/encoder.h"
#include "proxygrasp/tuio/transport.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace pg {
namespace {

// the TUIO bundles of every frame of the level's script, as our own sender makes them
std::vector<std::vector<OscBundle>> EncodeLevel(const Level& level) {
  Simulation sensed;
  std::vector<std::vector<OscBundle>> frames;
  if (sensed.Start(level, level.params, {RunStages::kThroughTracking})) return frames;
  TuioEncoderParams ep;
  ep.table = level.params.table;
  TuioEncoder encoder(ep);
  FrameInput script = FrameInput::Script();
  const int64_t count =
      static_cast<int64_t>(level.script.duration * level.params.physics.frameRate);
  for (int64_t i = 0; i < count; ++i) {
    if (!script.Step(sensed).ok()) break;
    frames.push_back(encoder.Encode(i, OscTimeTag::FromSeconds(sensed.Time()),
                                    ToTuioOutContacts(sensed.contacts())));
  }
  return frames;
}

void BM_TuioLatency(benchmark::State& state, const std::string& name) {
  const Result<Level> loaded =
      LoadLevel(std::string(PROXYGRASP_SOURCE_DIR) + "/levels/" + name + ".toml");
  if (!loaded.ok()) {
    state.SkipWithError(loaded.error().Format().c_str());
    return;
  }
  const Level& level = loaded.value();
  const std::vector<std::vector<OscBundle>> frames = EncodeLevel(level);
  Result<FrameInput> opened = FrameInput::Open("tuio:127.0.0.1:0");
  if (!opened.ok() || frames.empty()) {
    state.SkipWithError("cannot listen on the loopback, or the level has no frames");
    return;
  }
  FrameInput& input = opened.value();
  input.tuio()->SetWait(1.0);
  TuioEncoderParams ep;
  ep.table = level.params.table;
  Result<std::unique_ptr<TuioSender>> sender =
      TuioSender::Open("127.0.0.1:" + std::to_string(input.tuio()->port()), ep);
  if (!sender.ok()) {
    state.SkipWithError(sender.error().Format().c_str());
    return;
  }

  Simulation sim;
  std::vector<double> latency;  // ms, each frame's
  double simMs = 0.0;
  size_t frame = 0;
  int64_t contacts = 0;
  for (auto _ : state) {
    if (frame == frames.size()) {
      // the level's end: start it again, untimed
      state.PauseTiming();
      frame = 0;
      state.ResumeTiming();
    }
    if (frame == 0) {
      state.PauseTiming();
      (void)sim.Start(level, level.params);
      state.ResumeTiming();
    }
    const auto start = std::chrono::steady_clock::now();
    for (const OscBundle& b : frames[frame]) (void)sender.value()->SendBundle(b);
    (void)input.Step(sim);
    const auto end = std::chrono::steady_clock::now();
    latency.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    simMs += sim.stats().totalMs;
    contacts += sim.stats().contacts;
    ++frame;
  }
  std::sort(latency.begin(), latency.end());
  const auto at = [&](double q) {
    return latency[std::min(latency.size() - 1, static_cast<size_t>(q * latency.size()))];
  };
  state.counters["p50_ms"] = at(0.5);
  state.counters["p99_ms"] = at(0.99);
  state.counters["max_ms"] = latency.back();
  state.counters["stages_ms"] = simMs / static_cast<double>(latency.size());
  state.counters["contacts"] = static_cast<double>(contacts) / static_cast<double>(latency.size());
}

BENCHMARK_CAPTURE(BM_TuioLatency, side_push, std::string("side_push"))
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(600);
BENCHMARK_CAPTURE(BM_TuioLatency, grasp_turn, std::string("grasp_turn"))
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(600);
BENCHMARK_CAPTURE(BM_TuioLatency, demo_sort, std::string("demo_sort"))
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(600);

}  // namespace
}  // namespace pg

BENCHMARK_MAIN();
