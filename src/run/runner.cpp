#include "proxygrasp/run/runner.h"

#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/trace.h"
#include "proxygrasp/sensing/depth_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace pg {

namespace {

constexpr double kHistogramMinMs = 1e-4;
const double kHistogramStep = std::log(1.02);

// the trace folder of one run: the folder itself, or a sub-folder per run when there are several
std::string RunTraceDir(const RunOptions& options, const std::string& runName, size_t runs) {
  if (options.traceDir.empty()) return "";
  if (runs == 1) return options.traceDir;
  std::string sub = runName;
  std::replace(sub.begin(), sub.end(), '/', '-');
  return options.traceDir + "/" + sub;
}

Result<RunResult> RunOne(const Level& level, const LevelRun& run, const RunOptions& options,
                         size_t runCount, Profile& profile, const FrameObserver& observer) {
  Simulation sim;
  // frames from a depth source (--input depth:DIR, fakenect:DIR, a device) are not the synthetic
  // camera's: the depth chain learns its surface from their first frames, as it would on a table
  SimulationOptions setup;
  setup.cameraBackground = options.input.empty() || !IsDepthSourceSpec(options.input);
  if (MaybeError s = sim.Start(level, RunParams(level, run), setup)) return *s;
  RunResult out;
  out.run = run;
  out.name = RunName(run);
  out.traceDir = RunTraceDir(options, out.name, runCount);

  const double frameDuration = sim.FrameDuration();
  const int64_t frames =
      options.frames >= 0
          ? options.frames
          : static_cast<int64_t>(std::ceil(level.script.duration / frameDuration - 1e-9));
  Result<FrameInput> opened =
      options.input.empty() ? FrameInput::ForLevel(level) : FrameInput::Open(options.input);
  if (!opened.ok() && !options.input.empty())
    return MakeError({}, "--input " + options.input + ": " + opened.error().Format());
  if (!opened.ok()) return opened.error();
  FrameInput& input = opened.value();
  if (TuioStream* tuio = input.tuio(); tuio && tuio->live()) tuio->SetWait(frameDuration);

  // traces stream to disk as the run goes: the trace folder, and the recording with its own
  TraceWriter trace;
  if (!out.traceDir.empty()) {
    if (MaybeError s = trace.Open(out.traceDir)) return *s;
  }
  TraceWriter recording;
  if (!options.record.empty()) {
    if (MaybeError s = recording.Open(RecordingTraceDir(options.record), options.record,
                                      sim.CameraSize(), sim.params().physics.frameRate)) {
      return *s;
    }
  }

  Evaluator evaluator(level, run, sim);
  auto fail = [&](const std::string& message) {
    return MakeError({}, level.path + ": run " + out.name + ": " + message);
  };
  for (int64_t i = 0; i < frames; ++i) {
    Result<FrameStatus> stepped = input.Step(sim);
    if (!stepped.ok()) return fail(stepped.error().Format());
    if (stepped.value() == FrameStatus::kEnd) break;
    if (stepped.value() != FrameStatus::kOk) {
      const Error e = MakeError({level.script.recording},
                                "frame " + std::to_string(sim.Frame()) + ": " + input.LastError());
      return fail(e.Format());
    }
    out.frames = i + 1;
    for (TraceWriter* writer : {&trace, &recording}) {
      if (!writer->IsOpen()) continue;
      if (MaybeError s = writer->Write(sim)) return *s;
    }
    profile.Add(sim.stats());
    evaluator.AfterFrame(sim, sim.Time(), out.results);
    if (observer) observer(out, sim);
  }
  for (TraceWriter* writer : {&trace, &recording}) {
    if (MaybeError s = writer->Close()) return *s;
  }
  evaluator.Finish(sim, static_cast<double>(out.frames) * frameDuration, out.results);
  return out;
}

}  // namespace

void StageTimes::Add(double ms) {
  const double bin = ms > kHistogramMinMs ? std::log(ms / kHistogramMinMs) / kHistogramStep : 0.0;
  const int index = std::clamp(static_cast<int>(bin), 0, kBins - 1);
  ++m_bins[static_cast<size_t>(index)];
  ++m_count;
}

double StageTimes::Percentile(double q) const {
  if (m_count == 0) return 0.0;
  // the bin holding the sample of rank q (n - 1), reported at its geometric centre
  const auto rank =
      static_cast<int64_t>(std::floor(std::clamp(q, 0.0, 1.0) * static_cast<double>(m_count - 1)));
  int64_t seen = 0;
  for (int i = 0; i < kBins; ++i) {
    seen += m_bins[static_cast<size_t>(i)];
    if (seen > rank) return kHistogramMinMs * std::exp((i + 0.5) * kHistogramStep);
  }
  return kHistogramMinMs * std::exp((kBins - 0.5) * kHistogramStep);
}

void Profile::Add(const FrameStats& frame) {
  sense.Add(frame.senseMs);
  track.Add(frame.trackMs);
  proxies.Add(frame.proxyMs);
  physics.Add(frame.physicsMs);
  total.Add(frame.totalMs);
}

bool RunResult::Passed() const {
  return std::all_of(results.begin(), results.end(),
                     [](const ExpectationResult& r) { return r.passed; });
}

bool LevelResult::Passed() const {
  return std::all_of(runs.begin(), runs.end(), [](const RunResult& r) { return r.Passed(); });
}

Result<LevelResult> RunLevel(const Level& level, const RunOptions& options,
                             const FrameObserver& observer) {
  LevelResult result;
  const std::vector<LevelRun> runs = LevelRuns(level, options.mode);
  for (const LevelRun& run : runs) {
    // only the first run is recorded, with its trace beside the video
    RunOptions runOptions = options;
    if (&run != &runs.front()) runOptions.record.clear();
    Result<RunResult> one = RunOne(level, run, runOptions, runs.size(), result.profile, observer);
    if (!one.ok()) return one.error();
    result.runs.push_back(std::move(one.value()));
  }
  return result;
}

std::string FormatReport(const Level& level, const LevelResult& result) {
  std::string out = "level " + level.name + " (" + level.path + ")\n";
  for (const RunResult& run : result.runs) {
    out += "  run " + run.name + ": " + std::to_string(run.frames) + " frames\n";
    if (run.results.empty()) out += "    (no expectations in this run)\n";
    for (const ExpectationResult& r : run.results) {
      char line[512];
      std::snprintf(line, sizeof(line), "    %-4s  %-48s  measured %s\n",
                    r.passed ? "PASS" : "FAIL", r.text.c_str(), r.measured.c_str());
      out += line;
      if (r.expectation && !r.expectation->label.empty()) {
        out += "          (" + r.expectation->label + ")\n";
      }
      if (!r.passed && r.expectation) {
        out += "          at " + r.expectation->loc.Format() + "\n";
      }
    }
  }
  out += result.Passed() ? "  => PASS\n" : "  => FAIL\n";
  return out;
}

std::string FormatProfile(const LevelResult& result) {
  const Profile& p = result.profile;
  std::string out =
      "  stage      median ms    p99 ms   (" + std::to_string(p.total.Count()) + " frames)\n";
  for (const auto& [name, times] : {std::pair<const char*, const StageTimes*>{"sense", &p.sense},
                                    {"track", &p.track},
                                    {"proxies", &p.proxies},
                                    {"physics", &p.physics},
                                    {"total", &p.total}}) {
    char line[128];
    std::snprintf(line, sizeof(line), "  %-9s %10.3f %9.3f\n", name, times->Percentile(0.5),
                  times->Percentile(0.99));
    out += line;
  }
  return out;
}

}  // namespace pg
