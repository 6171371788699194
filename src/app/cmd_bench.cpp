// `proxygrasp bench`: the standard scenes through the pipeline on pre-rendered frames, stage CPU
// times and the baselines (issue 17; run/bench.h).
#include "commands.h"

#include "proxygrasp/run/bench.h"

#include <fstream>
#include <iostream>
#include <sstream>

namespace pg {

namespace {

struct BenchArgs {
  std::string json;    // write the report here as JSON
  std::string scenes;  // comma-separated scene names, "" for all
  int frames = 120;
  int repeat = 1;
};

int RunBenchCommand(const BenchArgs& args) {
  BenchOptions options;
  options.frames = args.frames;
  options.repeat = args.repeat;
  std::istringstream names(args.scenes);
  for (std::string name; std::getline(names, name, ',');) {
    if (!name.empty()) options.scenes.push_back(name);
  }

  // the JSON file must be writable before minutes of measuring
  std::ofstream json;
  if (!args.json.empty()) {
    json.open(args.json);
    if (!json) {
      std::cerr << "proxygrasp bench: --json " << args.json << ": cannot write the file\n";
      return kExitBadInput;
    }
  }
  Result<BenchReport> report = RunBench(options);
  if (!report.ok()) {
    std::cerr << "proxygrasp bench: " << report.error().Format() << "\n";
    return kExitBadInput;
  }
  std::cout << FormatBench(report.value());
  if (json.is_open()) {
    json << BenchJson(report.value());
    json.close();
    if (!json) {
      std::cerr << "proxygrasp bench: --json " << args.json << ": writing failed\n";
      return kExitFailed;
    }
    std::cout << "json: " << args.json << "\n";
  }
  return kExitOk;
}

}  // namespace

void AddBenchCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Time the pipeline's stages on the standard scenes (pre-rendered frames, CPU time) beside "
      "bare OpenCV sensing, Box2D stepping and exhaustive matching");
  // CLI11 binds options by reference, so they live as long as the program
  static BenchArgs args;
  cmd->add_option("--json", args.json, "Write the figures to this JSON file");
  cmd->add_option("--frames", args.frames, "Timed frames per scene (default 120)");
  cmd->add_option("--repeat", args.repeat, "Runs of each scene, pooled (default 1)");
  cmd->add_option("--scenes", args.scenes,
                  "Comma-separated scenes (default all: fingertips10_s3, flat_hands2_s3_k8, "
                  "five_hands4_s3, flat_hands8)");
  cmd->callback([&exitCode] { exitCode = RunBenchCommand(args); });
}

}  // namespace pg
