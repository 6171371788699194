// The headless runner: plays a level's script through the whole pipeline, once per run its
// expectations need (variants and proxy modes), checks the expectations, and writes traces.
// `proxygrasp run`, the level tests and the app's script input all use it.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/level/simulation.h"

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
  std::string traceDir;           ///< write objects.csv and frames.csv here ("" = no trace)
  /// Record the first run's camera frames to this video (FFV1 .mkv) and its trace into
  /// RecordingTraceDir(record); "" records nothing.
  std::string record;
};

/// Where a recording's trace goes: the file's path without its extension plus "_trace"
/// ("runs/push.mkv" -> "runs/push_trace").
std::string RecordingTraceDir(const std::string& recordingPath);

/// The outcome of one expectation in one run.
struct ExpectationResult {
  const Expectation* expectation = nullptr;
  std::string text;      ///< what it checks, for the report
  std::string measured;  ///< the value measured, with its unit
  bool passed = false;
};

/// One run of a level: its results, per-frame stats and the traces as CSV text.
struct RunResult {
  LevelRun run;
  std::string name;  ///< "base", or the variant, plus the mode: "base/persistent"
  std::vector<ExpectationResult> results;
  std::vector<FrameStats> frames;
  std::string objectsCsv;  ///< frame,t,object,x,y,angle_deg,vx,vy,omega_deg_s,held
  std::string framesCsv;   ///< frame,t,contacts,particles,created,deleted,bodies,*_ms
  bool Passed() const;
};

/// Every run of one level.
struct LevelResult {
  std::vector<RunResult> runs;
  bool Passed() const;
};

/// Called after every frame of every run (the app's script input and video writer use it).
using FrameObserver = std::function<void(const RunResult& run, const Simulation& sim)>;

/// Runs every run of the level and evaluates its expectations. Errors (a frame the sensor rejects,
/// an object spec the physics rejects) name where they are; expectations failing is not an error.
Result<LevelResult> RunLevel(const Level& level, const RunOptions& options,
                             const FrameObserver& observer = {});

/// Writes a run's objects.csv and frames.csv into dir (created if missing).
Status WriteTrace(const RunResult& run, const std::string& dir);

/// The per-level report: one line per expectation with the measured value and PASS or FAIL.
std::string FormatReport(const Level& level, const LevelResult& result);

/// Median and 99th percentile milliseconds per stage per frame over every run, as a table.
std::string FormatProfile(const LevelResult& result);

/// The objects.csv header line (without newline).
inline constexpr const char* kObjectsCsvHeader =
    "frame,t,object,x,y,angle_deg,vx,vy,omega_deg_s,held";
/// The frames.csv header line (without newline).
inline constexpr const char* kFramesCsvHeader =
    "frame,t,contacts,particles,created,deleted,bodies,sense_ms,track_ms,proxy_ms,physics_ms,"
    "total_ms";

}  // namespace pg
