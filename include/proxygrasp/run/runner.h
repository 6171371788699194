// The headless runner: plays a level's script (or its recording) through the whole pipeline, once
// per run its expectations need (variants and proxy modes), checks the expectations and streams
// the traces to disk. `proxygrasp run`, the level tests and `run --video` (app/video.h) use it.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/run/expectations.h"
#include "proxygrasp/run/plan.h"
#include "proxygrasp/run/simulation.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pg {

/// Options of `proxygrasp run` beyond the level itself.
struct RunOptions {
  std::optional<ProxyMode> mode;  ///< force every run into this proxy mode
  int64_t frames = -1;            ///< frames per run; < 0 runs the script's duration
  /// Write objects.csv and frames.csv here ("" = no trace); a level of several runs gets a
  /// sub-folder per run ("base-persistent", ...).
  std::string traceDir;
  /// Record the first run's camera frames to this video (FFV1 .mkv) and its trace into
  /// RecordingTraceDir(record); "" records nothing.
  std::string record;
  /// Where every run's frames come from instead of the level's script (FrameInput::Open: a frame
  /// source, or tuio:PORT / tuio:ADDRESS:PORT); "" takes the level's own input. A live TUIO stream
  /// paces the run: each frame waits up to a frame's time for the sender's.
  std::string input;
};

/// Milliseconds per frame of one stage, as a histogram of constant size: its percentiles are
/// within 1% of the exact ones, however many frames it holds.
class StageTimes {
 public:
  void Add(double ms);
  /// The q-quantile (0..1) in ms; 0 when empty.
  double Percentile(double q) const;
  int64_t Count() const { return m_count; }

 private:
  static constexpr int kBins = 1200;  // 2% wide from 1e-4 ms up
  std::array<int64_t, kBins> m_bins{};
  int64_t m_count = 0;
};

/// The stage timings of frames, for `--profile`.
struct Profile {
  StageTimes sense, track, proxies, physics, total;
  void Add(const FrameStats& frame);
};

/// One run of a level: its expectations' results and how many frames it ran. The traces went to
/// disk as it ran; nothing per frame is kept.
struct RunResult {
  LevelRun run;
  std::string name;  ///< "base", or the variant, plus the mode: "base/persistent"
  std::vector<ExpectationResult> results;
  int64_t frames = 0;    ///< frames stepped
  std::string traceDir;  ///< where its objects.csv and frames.csv are ("" = none written)
  bool Passed() const;
};

/// Every run of one level.
struct LevelResult {
  std::vector<RunResult> runs;
  Profile profile;  ///< every frame of every run
  bool Passed() const;
};

/// Called after every frame of every run (`run --video` draws frames with it).
using FrameObserver = std::function<void(const RunResult& run, const Simulation& sim)>;

/// Runs every run of the level and evaluates its expectations. Errors (a frame the sensor rejects,
/// an object spec the physics rejects, a trace that cannot be written) name where they are;
/// expectations failing is not an error.
Result<LevelResult> RunLevel(const Level& level, const RunOptions& options,
                             const FrameObserver& observer = {});

/// The per-level report: one line per expectation with the measured value and PASS or FAIL.
std::string FormatReport(const Level& level, const LevelResult& result);

/// Median and 99th percentile milliseconds per stage per frame over every run, as a table.
std::string FormatProfile(const LevelResult& result);

}  // namespace pg
