// `proxygrasp play`: plays a level in a window on the table (or full screen on the projector).
// Without a display it runs the level headless and writes a video and a PNG instead.
#include "commands.h"

#include "proxygrasp/app/app.h"
#include "proxygrasp/app/level_search.h"
#include "proxygrasp/app/video.h"
#include "proxygrasp/bench/bench.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/runner.h"
#include "proxygrasp/run/tuio_output.h"

#include <SDL.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

namespace pg {

namespace {

struct PlayArgs {
  std::string level;
  std::string input;
  std::vector<std::string> sets;
  bool fullscreen = false;
  int display = 0;
  int64_t frames = -1;
  std::string screenshot;
  std::string size = "1280x960";
  std::string outDir = "out";
  std::string show;
  std::string tuioOut;  // HOST:PORT or file:PATH
  bool tuioCursors = false;
  bool timing = false;
};

// what each frame carried, for `play --timing`
struct FrameLoad {
  std::vector<int> contacts;
  std::vector<int> particles;
};

// the mean of values[skip..]
double MeanAfter(const std::vector<int>& values, size_t skip) {
  if (values.size() <= skip) return 0.0;
  double sum = 0.0;
  for (size_t i = skip; i < values.size(); ++i) sum += values[i];
  return sum / static_cast<double>(values.size() - skip);
}

// `play --timing`: the work per frame against the frame period, from the frames after the first
// second (the window opening and the first uploads are not the loop), and what the frames
// carried (a driven mouse hand shows as one contact and its particles)
void PrintTiming(std::vector<double> ms, const FrameLoad& load, double frameRate) {
  const size_t skip = static_cast<size_t>(std::max(0.0, frameRate));
  if (ms.size() <= skip) {
    std::cout << "timing: " << ms.size() << " frames, too few to time (the first " << skip
              << " are skipped)\n";
    return;
  }
  ms.erase(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(skip));
  const double period = 1000.0 / frameRate;
  const auto over = static_cast<size_t>(
      std::count_if(ms.begin(), ms.end(), [period](double m) { return m > period; }));
  std::printf(
      "timing: %zu frames after the first %zu, work per frame median %.2f ms, p99 %.2f ms, "
      "max %.2f ms; %zu over the %.1f ms of a frame at %.0f Hz; per frame %.2f contacts, %.0f "
      "particles\n",
      ms.size(), skip, Percentile(ms, 0.5), Percentile(ms, 0.99),
      *std::max_element(ms.begin(), ms.end()), over, period, frameRate,
      MeanAfter(load.contacts, skip), MeanAfter(load.particles, skip));
}

// true when SDL can open its video subsystem: a display is there
bool HaveDisplay() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  const char* driver = std::getenv("SDL_VIDEODRIVER");
  const bool any = (x11 && *x11) || (wayland && *wayland) || (driver && *driver);
  if (!any) return false;
  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    std::cerr << "proxygrasp play: no display (" << SDL_GetError() << ")\n";
    return false;
  }
  SDL_Quit();
  return true;
}

// no display: the level's script, drawn into out/<level>.mp4 and out/<level>.png
int PlayHeadless(const PlayArgs& args, Level level) {
  const std::string stem = std::filesystem::path(level.path).stem().string();
  VideoOptions video;
  video.videoPath = args.outDir + "/" + stem + ".mp4";
  video.pngPath = args.outDir + "/" + stem + ".png";
  if (MaybeError s = ParseViewOptions(args.show, video.view)) {
    std::cerr << "proxygrasp play: --show: " << s->Format() << "\n";
    return kExitBadInput;
  }
  // the first run's frames go out as TUIO too, as the window would send them
  std::unique_ptr<TuioOutput> output;
  if (!args.tuioOut.empty()) {
    TuioEncoderParams encoding;
    encoding.cursors11 = args.tuioCursors;
    Result<std::unique_ptr<TuioOutput>> opened = TuioOutput::Open(args.tuioOut, encoding);
    if (!opened.ok()) {
      std::cerr << "proxygrasp play: --tuio-out " << args.tuioOut << ": " << opened.error().Format()
                << "\n";
      return kExitBadInput;
    }
    output = std::move(opened.value());
  }
  FrameObserver send;
  if (output) {
    send = [&output](const RunResult&, const Simulation& sim) {
      const bool firstFailure = output->sendErrors() == 0;
      if (MaybeError s = output->Send(sim); s && firstFailure)
        std::cerr << "proxygrasp play: --tuio-out: " << s->Format()
                  << " (further failures are counted)\n";
    };
  }
  RunOptions options;
  options.frames = args.frames;
  std::cout << "proxygrasp play: no display; running " << level.path << " headless\n";
  Result<LevelResult> result = RunLevelToVideo(level, options, video, send);
  MaybeError closed = output ? output->Close() : std::nullopt;
  if (!result.ok()) {
    std::cerr << result.error().Format() << "\n";
    return kExitBadInput;
  }
  std::cout << FormatReport(level, result.value());
  std::cout << "video: " << video.videoPath << "\npicture: " << video.pngPath << "\n";
  if (output) std::cout << output->Status() << "\n";
  if (closed) {
    std::cerr << "proxygrasp play: --tuio-out: " << closed->Format() << "\n";
    return kExitFailed;
  }
  return kExitOk;
}

int Play(const PlayArgs& args) {
  PlayArgs a = args;
  // a file, or a level name in ./levels, the installed levels or the source tree's
  if (a.level.empty()) a.level = kDefaultLevel;
  const Result<std::string> path = ResolveLevel(a.level);
  if (!path.ok()) {
    std::cerr << "proxygrasp play: " << path.error().Format() << "\n";
    return kExitBadInput;
  }
  a.level = path.value();

  // the level is checked first, so a bad file is reported the same with or without a display
  Result<Level> level = LoadLevel(a.level);
  if (!level.ok()) {
    std::cerr << level.error().Format() << "\n";
    return kExitBadInput;
  }
  if (MaybeError s = ApplyOverrides(level.value(), a.sets)) {
    std::cerr << "proxygrasp play: " << s->Format() << "\n";
    return kExitBadInput;
  }
  if (!HaveDisplay()) return PlayHeadless(a, std::move(level.value()));

  AppOptions options;
  options.level = a.level;
  options.sets = a.sets;
  options.input = a.input;
  options.fullscreen = a.fullscreen;
  options.display = a.display;
  options.outDir = a.outDir;
  options.tuioOut = a.tuioOut;
  options.tuioCursors = a.tuioCursors;
  if (MaybeError s = ParseViewOptions(a.show, options.view)) {
    std::cerr << "proxygrasp play: --show: " << s->Format() << "\n";
    return kExitBadInput;
  }
  // a fixed number of frames runs as fast as it can (tests, screenshots), unless it is timed: the
  // loop being timed is the one a user plays, paced at the level's frame rate
  options.realtime = a.frames < 0 || a.timing;
  int w = 0;
  int h = 0;
  if (std::sscanf(a.size.c_str(), "%dx%d", &w, &h) != 2 || w < 64 || h < 64) {
    std::cerr << "proxygrasp play: --size " << a.size << ": expected WxH, each at least 64\n";
    return kExitBadInput;
  }
  options.windowSize = {w, h};
  options.timing = a.timing;

  App app;
  FrameLoad load;  // with --timing
  if (MaybeError s = app.Open(options)) {
    std::cerr << "proxygrasp play: " << s->Format() << "\n";
    return kExitBadInput;
  }
  for (int64_t i = 0; a.frames < 0 || i < a.frames; ++i) {
    if (!a.screenshot.empty() && i == a.frames - 1) app.RequestScreenshot(a.screenshot);
    if (!app.Tick()) break;
    if (a.timing) {
      load.contacts.push_back(app.simulation().stats().contacts);
      load.particles.push_back(app.simulation().stats().particles);
    }
  }
  if (a.timing) PrintTiming(app.tickWorkMs(), load, app.level().params.physics.frameRate);
  if (!a.screenshot.empty()) {
    const Result<std::string>& shot = app.screenshotStatus();
    if (!shot.ok()) {
      std::cerr << "proxygrasp play: " << shot.error().Format() << "\n";
      return kExitFailed;
    }
    std::cout << "screenshot: " << shot.value() << "\n";
  }
  return kExitOk;
}

}  // namespace

void AddPlayCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "play", "Play a level in a window on the table (headless video and PNG without a display)");
  // CLI11 binds options by reference, so they live as long as the program
  static PlayArgs args;
  cmd->add_option(
      "level", args.level,
      std::string("Level file (TOML) or level name, found as run's are; default ") + kDefaultLevel);
  cmd->add_option("--input", args.input,
                  "camera:N, video:FILE, script, mouse, touch, or tuio:PORT / tuio:ADDRESS:PORT "
                  "(TUIO over UDP) (default: camera 0 when it opens, else the mouse)");
  cmd->add_option("--set", args.sets, "Override a parameter: section.key=value (repeatable)");
  cmd->add_flag("--fullscreen", args.fullscreen, "Full screen on --display (the projector)");
  cmd->add_option("--display", args.display, "Display index for the window")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--frames", args.frames,
                  "Stop after this many frames (default: run until closed)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--screenshot", args.screenshot, "Save the window as a PNG after the last frame")
      ->needs("--frames");
  cmd->add_option("--size", args.size, "Window size WxH in pixels (default 1280x960)");
  cmd->add_option("--show", args.show,
                  "Overlays at start: forces,successors,camera,sensing,help,nohud,layer=N");
  cmd->add_option("--out", args.outDir, "Folder for screenshots, recordings and headless output");
  cmd->add_option("--tuio-out", args.tuioOut,
                  "Also send each frame's contacts as TUIO 2.0 to HOST:PORT over UDP, or record "
                  "them to file:PATH (touchlib XML; time tags are the frames' times)");
  cmd->add_flag("--timing", args.timing,
                "At the end, print the work per frame (median, p99, max) against the level's "
                "frame period; the loop is paced at the level's frame rate even with --frames");
  cmd->add_flag("--tuio-cursors", args.tuioCursors,
                "With --tuio-out, also send TUIO 1.1 /tuio/2Dcur cursors for older clients")
      ->needs("--tuio-out");
  cmd->callback([&exitCode] { exitCode = Play(args); });
}

}  // namespace pg
