// Sensing plus tracking of one 640x480 frame: Sensor::Process + Tracker::Update on frames rendered
// beforehand by the synthetic table camera. Targets (issue #3): <= 1 ms with ten fingertips, <= 1.5
// ms with two flat hands, on one core. Run pinned: taskset -c 0 build/release/bench_sensing
#include "proxygrasp/bench/bench.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"
#include "proxygrasp/tracking/tracker.h"

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include <string>
#include <vector>

namespace pg {
namespace {

constexpr int kFrames = 60;  // one second of the demo scene, cycled

struct Recording {
  std::vector<cv::Mat> frames;
  Calibration calibration;
  cv::Mat background;
};

Recording Record(const std::string& scene, double distortion) {
  const TableParams table;
  SyntheticCameraParams p;
  p.distortion = distortion;
  SyntheticCamera camera(p, table);
  Recording r;
  std::vector<ContactShape> shapes;
  // skip the demo's clear-table start
  for (int i = 0; i < kFrames; ++i) {
    DemoScene(scene, 10 + i, table, shapes);
    r.frames.push_back(camera.Render(shapes));
  }
  r.calibration = CalibrationFromModel(camera.model());
  r.background = camera.Background();
  return r;
}

void SenseAndTrack(benchmark::State& state, const std::string& scene, double distortion) {
  // one core: OpenCV runs every function sequentially, no worker threads
  cv::setNumThreads(0);
  const Recording rec = Record(scene, distortion);
  Sensor sensor;
  if (sensor.Configure(SensingParams{}, TableParams{}, rec.calibration) ||
      sensor.SetBackground(rec.background)) {
    state.SkipWithError("sensor configuration failed");
    return;
  }
  sensor.SetWholeStages(false);  // as the pipeline runs it: the high-pass only where it matters
  Tracker tracker;
  int64_t index = 0;
  size_t contacts = 0, points = 0;
  for (auto _ : state) {
    Result<ContourFrame> frame = sensor.Step(rec.frames[index % kFrames], index, index / 60.0);
    const ContactSet set = tracker.Step(frame.value());
    contacts = set.contacts.size();
    points = 0;
    for (const Contact& c : set.contacts) points += static_cast<size_t>(c.blob.contour.cols());
    benchmark::DoNotOptimize(set.contacts.data());
    ++index;
  }
  state.counters["contacts"] = static_cast<double>(contacts);
  state.counters["points"] = static_cast<double>(points);
}

void BM_TenFingertips(benchmark::State& state) {
  SenseAndTrack(state, "fingers", 0.0);
}
void BM_TwoFlatHands(benchmark::State& state) {
  SenseAndTrack(state, "hands", 0.0);
}
void BM_TenFingertipsDistorted(benchmark::State& state) {
  SenseAndTrack(state, "fingers", -0.08);
}
void BM_TwoFlatHandsDistorted(benchmark::State& state) {
  SenseAndTrack(state, "hands", -0.08);
}

// The synthetic camera's own cost: rendering one frame of the scene (not in the pipeline's stage
// times, but every script, mouse and touch frame pays it). Issue 17's target: two hands in at most
// 1 ms.
void Render(benchmark::State& state, const std::string& scene, CameraKind kind = CameraKind::kIr) {
  cv::setNumThreads(0);
  const TableParams table;
  SyntheticCameraParams params;
  params.kind = kind;
  SyntheticCamera camera(params, table);
  std::vector<std::vector<ContactShape>> scenes(kFrames);
  for (int i = 0; i < kFrames; ++i) DemoScene(scene, 10 + i, table, scenes[i]);
  int64_t index = 0;
  for (auto _ : state) {
    const cv::Mat frame = camera.Render(scenes[index % kFrames]);
    benchmark::DoNotOptimize(frame.data);
    ++index;
  }
}
void BM_RenderTenFingertips(benchmark::State& state) {
  Render(state, "fingers");
}
void BM_RenderTwoFlatHands(benchmark::State& state) {
  Render(state, "hands");
}
// no shapes at all (DemoScene knows no "clear" scene and leaves the list empty)
void BM_RenderClearTable(benchmark::State& state) {
  Render(state, "clear");
}
// the same scenes through the synthetic depth camera (fingers with their shafts, hands with their
// forearms, the projector's shadow, edge holes, noise and disparity steps)
void BM_RenderDepthTenFingertips(benchmark::State& state) {
  Render(state, "fingers", CameraKind::kDepth);
}
void BM_RenderDepthTwoFlatHands(benchmark::State& state) {
  Render(state, "hands", CameraKind::kDepth);
}
void BM_RenderDepthClearTable(benchmark::State& state) {
  Render(state, "clear", CameraKind::kDepth);
}

BENCHMARK(BM_TenFingertips)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_TwoFlatHands)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_TenFingertipsDistorted)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_TwoFlatHandsDistorted)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderTenFingertips)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderTwoFlatHands)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderClearTable)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderDepthTenFingertips)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderDepthTwoFlatHands)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_RenderDepthClearTable)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();

// The filter chain of issue 14 side by side: the whole sensing stage (Sensor::Step with the
// default chain: background subtraction, smoothing, high-pass, gain, threshold, opening, contours,
// sub-pixel edges, table mapping, resampling, background learning) against the same filters as
// bare OpenCV calls ending at findContours (BareSensingChain, bench/bench.h). Target: the sensing
// stage within 1.5x of the bare chain. Both run the default parameters.

void BM_ChainSensingStage(benchmark::State& state) {
  cv::setNumThreads(0);
  const Recording rec = Record("fingers", 0.0);
  Sensor sensor;
  if (sensor.Configure(SensingParams(), TableParams{}, rec.calibration) ||
      sensor.SetBackground(rec.background)) {
    state.SkipWithError("sensor configuration failed");
    return;
  }
  sensor.SetWholeStages(false);  // as the pipeline runs it: the high-pass only where it matters
  int64_t index = 0;
  size_t blobs = 0;
  for (auto _ : state) {
    Result<ContourFrame> frame = sensor.Step(rec.frames[index % kFrames], index, index / 60.0);
    blobs = frame.value().blobs.size();
    benchmark::DoNotOptimize(frame.value().blobs.data());
    ++index;
  }
  state.counters["contacts"] = static_cast<double>(blobs);
}

void BM_ChainBareOpenCV(benchmark::State& state) {
  cv::setNumThreads(0);
  const Recording rec = Record("fingers", 0.0);
  // the same chain `proxygrasp bench` compares the sensing stage with
  BareSensingChain chain(SensingParams(), TableParams{}, rec.background);
  int64_t index = 0;
  size_t contours = 0;
  for (auto _ : state) {
    contours = chain.Step(rec.frames[index % kFrames]);
    benchmark::DoNotOptimize(contours);
    ++index;
  }
  state.counters["contacts"] = static_cast<double>(contours);
}

BENCHMARK(BM_ChainSensingStage)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();
BENCHMARK(BM_ChainBareOpenCV)->Unit(benchmark::kMicrosecond)->MeasureProcessCPUTime();

}  // namespace
}  // namespace pg

BENCHMARK_MAIN();
