// `proxygrasp run`: runs levels headless through the whole pipeline and checks their expectations.
#include "commands.h"

#include "proxygrasp/app/level_search.h"
#include "proxygrasp/app/video.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/runner.h"

#include <iostream>

namespace pg {

namespace {

struct RunArgs {
  std::vector<std::string> levels;
  std::vector<std::string> sets;
  std::string mode;
  std::string traceDir;
  std::string record;
  std::string input;  // frames from here instead of each level's script
  int64_t frames = -1;
  bool profile = false;
  std::string video;  // draw the first run into this video (one level only)
  std::string png;    // and one frame of it into this PNG
  std::string show;   // overlays of the drawing
};

int RunLevels(const RunArgs& args) {
  RunOptions options;
  options.frames = args.frames;
  options.traceDir = args.traceDir;
  options.record = args.record;
  options.input = args.input;
  if (!args.record.empty() && args.levels.size() != 1) {
    std::cerr << "proxygrasp run: --record " << args.record << ": record one level at a time\n";
    return kExitBadInput;
  }
  if (!args.mode.empty()) {
    options.mode = args.mode == "instant" ? ProxyMode::kInstant : ProxyMode::kPersistent;
  }

  if ((!args.video.empty() || !args.png.empty()) && args.levels.size() != 1) {
    std::cerr << "proxygrasp run: --video and --png take exactly one level\n";
    return kExitBadInput;
  }

  // load and override every level first, so a bad file or --set stops before anything runs
  std::vector<Level> levels;
  for (const std::string& given : args.levels) {
    // a file, or a level name in ./levels, the installed levels or the source tree's
    const Result<std::string> path = ResolveLevel(given);
    if (!path.ok()) {
      std::cerr << "proxygrasp run: " << path.error().Format() << "\n";
      return kExitBadInput;
    }
    Result<Level> level = LoadLevel(path.value());
    if (!level.ok()) {
      std::cerr << level.error().Format() << "\n";
      return kExitBadInput;
    }
    if (MaybeError s = ApplyOverrides(level.value(), args.sets)) {
      std::cerr << "proxygrasp run: " << s->Format() << "\n";
      return kExitBadInput;
    }
    levels.push_back(std::move(level.value()));
  }

  bool allPassed = true;
  for (const Level& level : levels) {
    RunOptions levelOptions = options;
    if (!options.traceDir.empty() && levels.size() > 1) {
      levelOptions.traceDir += "/" + level.name;
    }
    VideoOptions video;
    video.videoPath = args.video;
    video.pngPath = args.png;
    if (MaybeError s = ParseViewOptions(args.show, video.view)) {
      std::cerr << "proxygrasp run: --show: " << s->Format() << "\n";
      return kExitBadInput;
    }
    Result<LevelResult> result = (args.video.empty() && args.png.empty())
                                     ? RunLevel(level, levelOptions)
                                     : RunLevelToVideo(level, levelOptions, video);
    if (!result.ok()) {
      std::cerr << result.error().Format() << "\n";
      return kExitBadInput;
    }
    std::cout << FormatReport(level, result.value());
    if (!args.video.empty()) std::cout << "video: " << args.video << "\n";
    if (!args.png.empty()) std::cout << "picture: " << args.png << "\n";
    if (args.profile) std::cout << FormatProfile(result.value());
    allPassed = allPassed && result.value().Passed();
  }
  return allPassed ? kExitOk : kExitFailed;
}

}  // namespace

void AddRunCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "run", "Run levels headless through the whole pipeline and check their expectations");
  // CLI11 binds options by reference, so they live as long as the program
  static RunArgs args;
  cmd->add_option("levels", args.levels,
                  "Level files (TOML), or level names (demo_sort) found in ./levels, then the "
                  "installed share/proxygrasp/levels, then the source tree of a build folder")
      ->required();
  cmd->add_option("--set", args.sets, "Override a parameter: section.key=value (repeatable)");
  cmd->add_option("--mode", args.mode, "Force the proxy mode of every run")
      ->check(CLI::IsMember({"persistent", "instant"}));
  cmd->add_option("--trace", args.traceDir,
                  "Write objects.csv, frames.csv and contacts.csv into this folder");
  cmd->add_option("--frames", args.frames, "Frames per run (default: the script's duration)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--video", args.video,
                  "Draw the first run, as play draws it, into this video (.mp4: mp4v)");
  cmd->add_option("--png", args.png, "Save the frame at 60% of the first run as this PNG");
  cmd->add_option("--show", args.show,
                  "Overlays of --video and --png: forces,successors,camera,sensing,nohud,layer=N");
  cmd->add_flag("--profile", args.profile, "Print median and p99 milliseconds per stage");
  cmd->add_option(
      "--input", args.input,
      "Take every run's frames from here instead of the level's script: tuio:PORT or "
      "tuio:ADDRESS:PORT (TUIO over UDP), or a frame source (video:FILE, camera:N, or a "
      "depth source: kinect[:N], openni[:URI], oni:FILE, depth:DIR, fakenect:DIR)");
  cmd->add_option("--record", args.record,
                  "Record the first run's camera frames to FILE (lossless .mkv) and its trace "
                  "into FILE's name without extension + _trace/");
  cmd->callback([&exitCode] { exitCode = RunLevels(args); });
}

}  // namespace pg
