// `proxygrasp tune SOURCE`: proposes sensing values for a real table from a capture (its first
// seconds a clear table, then touches) and writes them, with the clear-table background, to the
// calibration YAML. The rule is in docs/sensing.md ("Tuning a table").
#include "commands.h"

#include "proxygrasp/run/overrides.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/tune.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace pg {

namespace {

struct TuneArgs {
  std::string source;
  std::string calibration;
  std::string output;
  double clear = 1.0;
  double seconds = 10.0;
  int64_t frames = 0;
  double fps = 0.0;
  std::vector<std::string> sets;
};

int Tune(const TuneArgs& a) {
  const char* const me = "proxygrasp tune: ";
  LevelParams params;
  if (!a.calibration.empty()) params.sensing.calibration = a.calibration;
  if (MaybeError s = ApplyOverrides(params, a.sets)) {
    std::cerr << me << s->Format() << "\n";
    return kExitBadInput;
  }
  Result<std::unique_ptr<FrameSource>> opened = OpenFrameSource(a.source);
  if (!opened) {
    std::cerr << me << opened.error().Format() << "\n";
    return kExitBadInput;
  }
  FrameSource& source = *opened.value();
  double fps = a.fps > 0.0 ? a.fps : source.FrameRate();
  if (!(fps > 0.0)) {
    fps = 60.0;
    std::cerr << me << source.Describe() << " gives no frame rate: taking 60 Hz (--fps sets it)\n";
  }

  SensingTuner tuner;
  Calibration calibration;
  TuneOptions options;
  options.clearSeconds = a.clear;
  int64_t index = 0;
  int bad = 0;
  cv::Mat frame;
  // a live camera never ends: --seconds (of the capture's own time) ends it
  const int64_t last = a.seconds > 0.0 ? static_cast<int64_t>(std::ceil(a.seconds * fps)) : 0;
  while ((a.frames <= 0 || index < a.frames) && (last <= 0 || index < last)) {
    const FrameStatus status = source.Read(frame);
    if (status == FrameStatus::kEnd) break;
    if (status == FrameStatus::kLost) {
      std::cerr << me << source.Describe() << ": lost after " << index
                << " frames; tuning on what came (" << source.LastError() << ")\n";
      break;
    }
    if (status == FrameStatus::kError) {
      std::cerr << me << source.Describe() << ": frame " << index
                << " skipped: " << source.LastError() << "\n";
      ++bad;
      ++index;
      continue;
    }
    if (index - bad == 0) {
      // the first good frame fixes the image size the calibration must have
      if (!params.sensing.calibration.empty()) {
        Result<Calibration> loaded = LoadCalibration(params.sensing.calibration, frame.size());
        if (!loaded) {
          std::cerr << me << loaded.error().Format() << "\n";
          return kExitBadInput;
        }
        calibration = loaded.value();
      } else {
        calibration = LinearCalibration(frame.size(), params.table);
      }
      if (MaybeError s = tuner.Configure(params.sensing, params.table, calibration, options)) {
        std::cerr << me << s->Format() << "\n";
        return kExitBadInput;
      }
    }
    if (MaybeError s = tuner.AddFrame(frame, index, static_cast<double>(index) / fps)) {
      std::cerr << me << source.Describe() << ": " << s->Format() << "\n";
      ++bad;
    }
    ++index;
  }
  if (index - bad <= 0) {
    std::cerr << me << source.Describe() << " gave no frame\n";
    return kExitBadInput;
  }
  Result<TuneProposal> r = tuner.Propose();
  if (!r) {
    std::cerr << me << source.Describe() << ": " << r.error().Format() << "\n";
    return kExitFailed;
  }
  const TuneProposal& p = r.value();
  std::printf("%s: %d clear-table frames, %d frames of touches (%.1f Hz)\n",
              source.Describe().c_str(), p.clearFrames, p.touchFrames, fps);
  std::printf("clear table: no contact above high-pass level N = %d grey\n", p.noiseLevel);
  std::printf("touches: %zu seen above N; the weakest %.0f%% peak at or below W = %.0f grey\n",
              p.touchPeaks.size(), 100.0 * options.weakQuantile, p.weakTouch);
  std::printf("contact level T = max(N, floor(W / 2)) = %d grey: gain %g, threshold %g (fixed)\n",
              p.level, p.params.gain, p.params.threshold);

  // the proposal replaces those keys and keeps the calibration's other tuned values
  calibration.background = p.background;
  for (const auto& [key, text] : p.values) {
    bool replaced = false;
    for (auto& entry : calibration.sensing) {
      if (entry.first == key) {
        entry.second = text;
        replaced = true;
      }
    }
    if (!replaced) calibration.sensing.emplace_back(key, text);
  }
  const std::string output = !a.output.empty()                     ? a.output
                             : !params.sensing.calibration.empty() ? params.sensing.calibration
                                                                   : "calibration.yaml";
  if (MaybeError s = SaveCalibration(output, calibration)) {
    std::cerr << me << s->Format() << "\n";
    return kExitBadInput;
  }
  std::printf(
      "wrote %s (background and sensing values); sensing reads them with "
      "--calibration %s or sensing.calibration = \"%s\"\n",
      output.c_str(), output.c_str(), output.c_str());
  return kExitOk;
}

}  // namespace

void AddTuneCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "tune",
      "Propose sensing values for a real table from a capture (a clear table first, then "
      "touches) and write them to the calibration file");
  static TuneArgs args;
  cmd->add_option("source", args.source,
                  "Frames: a video file, camera:N, /dev/videoN, folder:DIR (its first seconds a "
                  "clear table, then touches)")
      ->required();
  cmd->add_option("--clear", args.clear, "The first seconds of the capture show the clear table, s")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 600.0));
  cmd->add_option("--seconds", args.seconds,
                  "Read at most this many seconds of the capture, the clear part included (0 = "
                  "to its end; a camera needs a limit)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  cmd->add_option("--frames", args.frames, "Read at most this many frames (0 = no limit)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--fps", args.fps, "Frame rate when the source gives none, Hz")
      ->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--calibration", args.calibration,
                  "Calibration file to see the capture through and to update (its lens and "
                  "homography are kept); without it the image maps linearly onto the table");
  cmd->add_option("--output", args.output,
                  "Calibration file to write (default: the --calibration file, else "
                  "calibration.yaml)");
  cmd->add_option("--set", args.sets,
                  "Override a parameter: section.key=value, e.g. table.width=115 (repeatable)");
  cmd->callback([&exitCode] { exitCode = Tune(args); });
}

}  // namespace pg
