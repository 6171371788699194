// `proxygrasp bench`: the standard scenes through the pipeline on pre-rendered frames, stage CPU
// times and the baselines (issue 17; bench/bench.h).
#include "commands.h"

#include "proxygrasp/bench/bench.h"
#include "proxygrasp/bench/grasp_sweep.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace pg {

namespace {

struct BenchArgs {
  std::string suite = "pipeline";  // "pipeline" or "grasp"
  std::string json;                // write the report here as JSON
  std::string scenes;              // comma-separated scene names, "" for all
  int frames = 120;
  int repeat = 1;
  // grasp
  int count = 300;
  uint64_t seed = 1;
  std::string substeps = "2,4,8";
  std::string failures;
  int threads = 2;
  bool ruleOnly = false;
  double holdShare = 0.6;
  std::string classes = "all";
  bool quiet = false;
  std::vector<std::string> sets;
  std::string clock = "cpu";
};

// Runs a suite and reports it: the JSON file is opened first (it must be writable before minutes
// of measuring), then the report is printed as text and written as JSON. `name` prefixes messages.
template <typename Report>
int RunAndReport(const std::string& name, const std::string& jsonPath,
                 const std::function<Result<Report>()>& run, std::string (*format)(const Report&),
                 std::string (*toJson)(const Report&)) {
  std::ofstream json;
  if (!jsonPath.empty()) {
    json.open(jsonPath);
    if (!json) {
      std::cerr << name << ": --json " << jsonPath << ": cannot write the file\n";
      return kExitBadInput;
    }
  }
  Result<Report> report = run();
  if (!report.ok()) {
    std::cerr << name << ": " << report.error().Format() << "\n";
    return kExitBadInput;
  }
  std::cout << format(report.value());
  if (json.is_open()) {
    json << toJson(report.value());
    json.close();
    if (!json) {
      std::cerr << name << ": --json " << jsonPath << ": writing failed\n";
      return kExitFailed;
    }
    std::cout << "json: " << jsonPath << "\n";
  }
  return kExitOk;
}

int RunGraspCommand(const BenchArgs& args) {
  GraspSweepOptions options;
  options.scenes = args.count;
  options.seed = args.seed;
  options.failuresDir = args.failures;
  options.threads = args.threads;
  options.ruleOnly = args.ruleOnly;
  options.holdShare = args.holdShare;
  options.sets = args.sets;
  Result<GraspClasses> classes = ParseGraspClasses(args.classes);
  if (!classes.ok()) {
    std::cerr << "proxygrasp bench grasp: " << classes.error().message << "\n";
    return kExitBadInput;
  }
  options.classes = classes.value();
  // progress on stderr: one line rewritten in place on a terminal, a line every 30 s otherwise
  const bool terminal = isatty(STDERR_FILENO) != 0;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  Clock::time_point last = start;
  if (!args.quiet) {
    options.progress = [terminal, start, last](size_t done, size_t total) mutable {
      const Clock::time_point now = Clock::now();
      const double interval = terminal ? 0.5 : 30.0;
      if (done < total && std::chrono::duration<double>(now - last).count() < interval) return;
      last = now;
      const double elapsed = std::chrono::duration<double>(now - start).count();
      const double left = done > 0 ? elapsed * static_cast<double>(total - done) / done : 0.0;
      char line[160];
      std::snprintf(line, sizeof line, "grasp sweep: %zu / %zu runs, %.0f s, about %.0f s left",
                    done, total, elapsed, left);
      if (terminal) {
        std::cerr << "\r" << line << "\x1b[K" << (done == total ? "\n" : "") << std::flush;
      } else {
        std::cerr << line << "\n" << std::flush;
      }
    };
  }
  options.substeps.clear();
  std::istringstream counts(args.substeps);
  for (std::string n; std::getline(counts, n, ',');) {
    char* end = nullptr;
    const long v = std::strtol(n.c_str(), &end, 10);
    if (n.empty() || *end != '\0') {
      std::cerr << "proxygrasp bench grasp: --substeps " << args.substeps
                << ": not a comma-separated list of counts\n";
      return kExitBadInput;
    }
    options.substeps.push_back(static_cast<int>(v));
  }
  return RunAndReport<GraspSweepReport>(
      "proxygrasp bench grasp", args.json, [&options] { return RunGraspSweep(options); },
      FormatGraspSweep, GraspSweepJson);
}

int RunBenchCommand(const BenchArgs& args) {
  if (args.suite == "grasp") return RunGraspCommand(args);
  if (args.suite != "pipeline") {
    std::cerr << "proxygrasp bench: unknown suite '" << args.suite << "' (pipeline or grasp)\n";
    return kExitBadInput;
  }
  BenchOptions options;
  options.frames = args.frames;
  options.repeat = args.repeat;
  options.sets = args.sets;
  if (args.clock != "cpu" && args.clock != "wall") {
    std::cerr << "proxygrasp bench: --clock " << args.clock << ": must be cpu or wall\n";
    return kExitBadInput;
  }
  options.clock = args.clock == "wall" ? TimerClock::kWall : TimerClock::kThreadCpu;
  std::istringstream names(args.scenes);
  for (std::string name; std::getline(names, name, ',');) {
    if (!name.empty()) options.scenes.push_back(name);
  }

  return RunAndReport<BenchReport>(
      "proxygrasp bench", args.json, [&options] { return RunBench(options); }, FormatBench,
      BenchJson);
}

}  // namespace

void AddBenchCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Time the pipeline's stages on the standard scenes (pre-rendered frames, CPU time) beside "
      "bare OpenCV sensing, Box2D stepping and exhaustive matching");
  // CLI11 binds options by reference, so they live as long as the program
  static BenchArgs args;
  cmd->add_option("suite", args.suite,
                  "pipeline (default): the standard scenes; grasp: the grasp sweep (random grasp "
                  "scenes scored against the analytic hold rule, docs/physics.md)");
  cmd->add_option("--json", args.json, "Write the figures to this JSON file");
  cmd->add_option("--frames", args.frames, "Timed frames per scene (default 120)");
  cmd->add_option("--repeat", args.repeat, "Runs of each scene, pooled (default 1)");
  cmd->add_option("--scenes", args.scenes,
                  "Comma-separated scenes (default all: fingertips10_s3, flat_hands2_s3_k8, "
                  "five_hands4_s3, flat_hands8)");
  cmd->add_option("--count", args.count, "grasp: scenes to generate (default 300)");
  cmd->add_option("--seed", args.seed, "grasp: seed of the scenes (default 1)");
  cmd->add_option("--substeps", args.substeps,
                  "grasp: comma-separated substep counts to run each scene at (default 2,4,8)");
  cmd->add_option("--failures", args.failures,
                  "grasp: write each scene the rule got wrong to this folder as a level file");
  cmd->add_option("--threads", args.threads, "grasp: scenes run concurrently (default 2)");
  cmd->add_option("--set", args.sets,
                  "Override a parameter in every scene (grasp: for the rule and the runs): "
                  "section.key=value (repeatable)");
  cmd->add_option("--clock", args.clock,
                  "cpu (default): the stepping thread's CPU time; wall: wall time, for "
                  "physics.threads > 1");
  cmd->add_option("--hold-share", args.holdShare,
                  "grasp: the most of the scenes the rule may call can-hold (0.5 .. 1, default "
                  "0.6): later can-hold draws are skipped; 1 keeps every draw");
  cmd->add_option("--classes", args.classes,
                  "grasp: the classes of scene drawn (docs/physics.md, \"Grasp sweep\"): all "
                  "(default), legacy (the scenes before issue 42, scene for scene), or a list of "
                  "topologies (none, merged, merge, split) and profiles (bang-bang, step)");
  cmd->add_flag("--quiet", args.quiet, "grasp: no progress line on stderr");
  cmd->add_flag("--rule-only", args.ruleOnly,
                "grasp: classify the scenes by the hold rule without running them");
  cmd->callback([&exitCode] { exitCode = RunBenchCommand(args); });
}

}  // namespace pg
