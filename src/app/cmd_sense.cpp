// `proxygrasp sense INPUT`: what the table sees. Reads frames from a camera, a video, a folder of
// images or a synthetic scene, runs sensing and tracking, and prints one JSON object per frame with
// the tracked contacts in table cm.
#include "commands.h"

#include "proxygrasp/level/level.h"
#include "proxygrasp/level/params.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/tracking/tracker.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace pg {

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The input of `sense`: a level file (*.toml) is its script rendered through the synthetic camera
// for the script's duration, with the level's parameters (params receives them); every other spec
// goes to OpenFrameSource.
Result<std::unique_ptr<FrameSource>> OpenSenseInput(const std::string& spec, LevelParams& params) {
  if (!EndsWith(spec, ".toml")) return OpenFrameSource(spec);
  Result<Level> loaded = LoadLevel(spec);
  if (!loaded.ok()) return loaded.error();
  auto level = std::make_shared<const Level>(std::move(loaded.value()));
  params = level->params;
  const double fps = params.physics.frameRate;
  const auto frames = static_cast<int64_t>(std::ceil(level->script.duration * fps - 1e-9));
  ShapeScript script = [level, fps](int64_t frame, std::vector<ContactShape>& shapes) {
    shapes = ShapesAt(level->script, static_cast<double>(frame) / fps);
    return true;
  };
  std::unique_ptr<FrameSource> source = std::make_unique<SyntheticSource>(
      spec, params.camera, params.table, std::move(script), frames, fps);
  return source;
}

void AppendNumber(std::string& out, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  out += buf;
}

// one frame as a single line of JSON, table cm
std::string FrameJson(int64_t index, const ContactSet& set) {
  std::string out = "{\"frame\": " + std::to_string(index) + ", \"contacts\": [";
  for (size_t i = 0; i < set.contacts.size(); ++i) {
    const Contact& c = set.contacts[i];
    if (i) out += ", ";
    out += "{\"id\": " + std::to_string(c.id) + ", \"state\": \"" +
           kContactStateNames[static_cast<int>(c.state)] + "\", \"centroid\": [";
    AppendNumber(out, c.blob.centroid.x());
    out += ", ";
    AppendNumber(out, c.blob.centroid.y());
    out += "], \"area\": ";
    AppendNumber(out, c.blob.area);
    out += ", \"contour\": [";
    for (Eigen::Index k = 0; k < c.blob.contour.cols(); ++k) {
      if (k) out += ", ";
      out += "[";
      AppendNumber(out, c.blob.contour(0, k));
      out += ", ";
      AppendNumber(out, c.blob.contour(1, k));
      out += "]";
    }
    out += "]}";
  }
  out += "]}";
  return out;
}

struct SenseOptions {
  std::string input;
  std::string calibration;
  int64_t frames = 0;
  std::vector<std::string> sets;
};

int RunSense(const SenseOptions& o) {
  const char* const me = "proxygrasp sense: ";
  // parameters: defaults or the level's, then --set, then --calibration
  LevelParams params;
  Result<std::unique_ptr<FrameSource>> opened = OpenSenseInput(o.input, params);
  if (!opened) {
    std::cerr << me << opened.error().Format() << "\n";
    return kExitBadInput;
  }
  for (const std::string& s : o.sets) {
    if (Status st = SetParam(params, s.substr(0, s.find('=')),
                             s.find('=') == std::string::npos ? "" : s.substr(s.find('=') + 1))) {
      std::cerr << me << "--set " << s << ": " << st->Format() << "\n";
      return kExitBadInput;
    }
  }
  if (!o.calibration.empty()) params.sensing.calibration = o.calibration;
  FrameSource& source = *opened.value();
  const double fps = source.FrameRate() > 0.0 ? source.FrameRate() : 60.0;

  Sensor sensor;
  Tracker tracker;
  cv::Mat frame;
  int64_t index = 0;
  int badFrames = 0;
  int failuresInARow = 0;
  constexpr int kMaxFailuresInARow = 10;
  constexpr int kReopenAttempts = 5;
  while (o.frames <= 0 || index < o.frames) {
    const FrameStatus status = source.Read(frame);
    if (status == FrameStatus::kEnd) break;
    if (status == FrameStatus::kLost) {
      // a camera that disappears: say so, and try to get it back for a few seconds
      std::cerr << me << source.LastError() << "; no input, retrying\n";
      bool back = false;
      for (int attempt = 0; attempt < kReopenAttempts && !back; ++attempt) {
        std::this_thread::sleep_for(std::chrono::seconds(1));
        back = !source.Reopen();
      }
      if (!back) {
        std::cerr << me << source.Describe() << ": gave up after " << kReopenAttempts
                  << " attempts\n";
        return kExitFailed;
      }
      continue;
    }
    if (status == FrameStatus::kError) {
      std::cerr << me << source.LastError() << "\n";
      ++badFrames;
      if (++failuresInARow >= kMaxFailuresInARow) {
        std::cerr << me << source.Describe() << ": " << kMaxFailuresInARow
                  << " bad frames in a row, stopping\n";
        return kExitFailed;
      }
      ++index;
      continue;
    }
    // the first frame fixes the image size the calibration must match
    if (!sensor.configured()) {
      if (Status s = sensor.Configure(params.sensing, params.table, frame.size())) {
        std::cerr << me << s->Format() << "\n";
        return kExitBadInput;
      }
    }
    Result<ContourFrame> sensed = sensor.Process(frame, index, index / fps);
    if (!sensed) {
      std::cerr << me << source.Describe() << ": " << sensed.error().Format() << "\n";
      ++badFrames;
      if (++failuresInARow >= kMaxFailuresInARow) return kExitFailed;
      ++index;
      continue;
    }
    failuresInARow = 0;
    const ContactSet contacts = tracker.Update(params.tracking, sensed.value());
    std::cout << FrameJson(index, contacts) << "\n";
    ++index;
  }
  std::cout.flush();
  if (badFrames > 0) {
    std::cerr << me << badFrames << " bad frame(s) skipped\n";
    return kExitFailed;
  }
  return kExitOk;
}

}  // namespace

void AddSenseCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "sense", "Print what the table sees: tracked contacts per frame as JSON lines, in table cm");
  // CLI11 binds options by reference, so they live as long as the program
  static SenseOptions options;
  cmd->add_option("INPUT", options.input,
                  "camera:N, /dev/videoN, video:FILE or a video file, folder:DIR or a directory, "
                  "synthetic:fingers or synthetic:hands")
      ->required();
  cmd->add_option("--calibration", options.calibration,
                  "calibration YAML (proxygrasp calibrate); without it the image maps linearly "
                  "onto the table");
  cmd->add_option("--frames", options.frames, "stop after N frames (0: until the input ends)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--set", options.sets,
                  "set a parameter, e.g. --set sensing.threshold=50 (repeatable)");
  cmd->callback([&exitCode] { exitCode = RunSense(options); });
}

}  // namespace pg
