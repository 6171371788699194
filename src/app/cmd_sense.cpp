// `proxygrasp sense INPUT`: what the table sees. Steps a simulation of sensing and tracking alone
// (run/simulation.h) with frames from a camera, a video, a folder of images, a synthetic scene or
// a level's script, and prints one JSON object per frame with the tracked contacts in table cm.
// With --tuio-out the contacts also go out as TUIO (run/tuio_output.h).
#include "commands.h"

#include "proxygrasp/level/level.h"
#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/run/tuio_output.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/preview.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace pg {

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The input of `sense` and the level it runs: a level file (*.toml) is its input (the script drawn
// by the synthetic camera, its recording or its TUIO stream) for the script's duration, with the
// level's parameters; every other spec is a frame source (OpenFrameSource) or a TUIO port
// (tuio:PORT, tuio:ADDRESS:PORT) on an empty table with the default parameters.
struct SenseInput {
  Level level;
  FrameInput frames = FrameInput::Script();
  int64_t frameCount = 0;  // frames the input lasts; 0 until it ends
};

Result<SenseInput> OpenSenseInput(const std::string& spec) {
  SenseInput input;
  if (EndsWith(spec, ".toml")) {
    Result<Level> loaded = LoadLevel(spec);
    if (!loaded.ok()) return loaded.error();
    input.level = std::move(loaded.value());
    Result<FrameInput> frames = FrameInput::ForLevel(input.level);
    if (!frames.ok()) return frames.error();
    input.frames = std::move(frames.value());
    input.frameCount = static_cast<int64_t>(
        std::ceil(input.level.script.duration * input.level.params.physics.frameRate - 1e-9));
    return input;
  }
  Result<FrameInput> frames = FrameInput::Open(spec);
  if (!frames.ok()) return frames.error();
  input.level.path = spec;
  input.level.name = spec;
  input.frames = std::move(frames.value());
  return input;
}

void AppendNumber(std::string& out, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  out += buf;
}

// a depth camera's heights of a blob: the mean and one per contour point, cm
void AppendHeights(std::string& out, const Blob& b) {
  const std::optional<double> mean = b.MeanHeight();
  if (!mean) return;
  out += ", \"height\": ";
  AppendNumber(out, *mean);
  out += ", \"heights\": [";
  for (size_t k = 0; k < b.heights.size(); ++k) {
    if (k) out += ", ";
    AppendNumber(out, b.heights[k]);
  }
  out += "]";
}

void AppendContour(std::string& out, const Contour& contour) {
  out += "[";
  for (Eigen::Index k = 0; k < contour.cols(); ++k) {
    if (k) out += ", ";
    out += "[";
    AppendNumber(out, contour(0, k));
    out += ", ";
    AppendNumber(out, contour(1, k));
    out += "]";
  }
  out += "]";
}

// one frame as a single line of JSON, table cm; a depth camera's frames add heights and hover
std::string FrameJson(int64_t index, const ContactSet& set, const std::vector<Blob>& hover) {
  std::string out = "{\"frame\": " + std::to_string(index) + ", \"contacts\": [";
  for (size_t i = 0; i < set.contacts.size(); ++i) {
    const Contact& c = set.contacts[i];
    if (i) out += ", ";
    out += "{\"id\": " + std::to_string(c.id) + ", \"state\": \"" +
           kContactStateNames[static_cast<int>(c.state)] + "\", \"parents\": [";
    for (size_t k = 0; k < c.parents.size(); ++k) {
      if (k) out += ", ";
      out += std::to_string(c.parents[k]);
    }
    out += "]";
    if (c.mergedInto != kNoId) out += ", \"merged_into\": " + std::to_string(c.mergedInto);
    out += ", \"centroid\": [";
    AppendNumber(out, c.blob.centroid.x());
    out += ", ";
    AppendNumber(out, c.blob.centroid.y());
    out += "], \"area\": ";
    AppendNumber(out, c.blob.area);
    AppendHeights(out, c.blob);
    out += ", \"contour\": ";
    AppendContour(out, c.blob.contour);
    out += "}";
  }
  out += "]";
  if (!hover.empty()) {
    out += ", \"hover\": [";
    for (size_t i = 0; i < hover.size(); ++i) {
      if (i) out += ", ";
      out += "{\"centroid\": [";
      AppendNumber(out, hover[i].centroid.x());
      out += ", ";
      AppendNumber(out, hover[i].centroid.y());
      out += "], \"area\": ";
      AppendNumber(out, hover[i].area);
      AppendHeights(out, hover[i]);
      out += ", \"contour\": ";
      AppendContour(out, hover[i].contour);
      out += "}";
    }
    out += "]";
  }
  out += ", \"merges\": " + std::to_string(set.merges) +
         ", \"splits\": " + std::to_string(set.splits) + "}";
  return out;
}

struct SenseOptions {
  std::string input;
  std::string calibration;
  int64_t frames = 0;
  std::vector<std::string> sets;
  std::string preview;  // PNG of the last frame's filter stages and contacts
  std::string tuioOut;  // HOST:PORT or file:PATH
  bool tuioCursors = false;
  bool stills = false;  // each image on its own
};

// the sensing view of the last frame: each filter stage side by side, contacts and ids drawn; a
// depth frame's: depth, surface, height, touch and hover
bool WritePreview(const Simulation& sim, const std::string& path) {
  std::vector<PreviewContact> shown;
  for (const Contact& c : sim.contacts().contacts)
    if (c.state != ContactState::kLifted) shown.push_back({&c.blob, static_cast<int>(c.id)});
  const cv::Mat view = sim.cameraImage().type() == CV_16UC1
                           ? DepthPreview(sim.depthSensor(), shown, sim.contours().hover)
                           : SensingPreview(sim.sensor(), shown);
  return !view.empty() && cv::imwrite(path, view);
}

int RunSense(const SenseOptions& o) {
  const char* const me = "proxygrasp sense: ";
  // parameters: defaults or the level's, --calibration, its tuned sensing values, then --set
  Result<SenseInput> opened = OpenSenseInput(o.input);
  if (!opened) {
    std::cerr << me << opened.error().Format() << "\n";
    return kExitBadInput;
  }
  SenseInput& in = opened.value();
  LevelParams params = in.level.params;
  if (!o.calibration.empty()) params.sensing.calibration = o.calibration;
  if (MaybeError s = ApplyOverrides(params, o.sets)) {
    std::cerr << me << s->Format() << "\n";
    return kExitBadInput;
  }
  // Stills: each image is sensed on its own, by a simulation started afresh for it (its
  // background is its own spatial estimate, its level set from its own evidence: sensing.stills).
  // A single image file is one (and said); a folder's images are taken as one camera's frames
  // (one of another size is a bad frame) unless --stills says otherwise.
  bool stills = o.stills || params.sensing.stills;
  if (!stills && !EndsWith(o.input, ".toml") && IsImageFile(o.input)) {
    std::cerr << me << o.input << " is a single image: sensed on its own (--stills)\n";
    stills = true;
  }
  params.sensing.stills = stills;

  // the TUIO output, before any frame: a bad spec stops the run before it starts
  std::unique_ptr<TuioOutput> output;
  if (!o.tuioOut.empty()) {
    TuioEncoderParams encoding;
    encoding.cursors11 = o.tuioCursors;
    Result<std::unique_ptr<TuioOutput>> out = TuioOutput::Open(o.tuioOut, encoding);
    if (!out) {
      std::cerr << me << "--tuio-out " << o.tuioOut << ": " << out.error().Format() << "\n";
      return kExitBadInput;
    }
    output = std::move(out.value());
  }

  // sensing and tracking only; a source's first frame fixes the image size the sensor takes, and
  // real frames get no synthetic background; a script or TUIO takes the level's camera size
  const bool script = in.frames.kind() == FrameInput::Kind::kScript;
  const bool imageless = script || in.frames.Imageless();
  SimulationOptions setup;
  setup.stages = RunStages::kThroughTracking;
  setup.cameraBackground = script;
  setup.wholeStages = !o.preview.empty();  // the preview shows every stage of the whole frame
  Simulation sim;
  bool started = false;
  auto start = [&](cv::Size size) -> MaybeError {
    params.camera.width = size.width;
    params.camera.height = size.height;
    started = true;
    return sim.Start(in.level, params, setup);
  };

  // --frames stops early; a level's script also ends with its duration
  int64_t limit = o.frames > 0 ? o.frames : in.frameCount;
  if (o.frames > 0 && in.frameCount > 0) limit = std::min(o.frames, in.frameCount);
  int64_t index = 0;
  int badFrames = 0;
  int failuresInARow = 0;
  constexpr int kMaxFailuresInARow = 10;
  constexpr int kReopenAttempts = 30;  // a second apart: a replugged Kinect takes a few seconds
  while (limit <= 0 || index < limit) {
    // the run starts with the first frame: its size is the camera size the sensor takes
    Result<FrameStatus> stepped = imageless ? FrameStatus::kOk : in.frames.Peek();
    // a fresh simulation for every image (of any size)
    if (stills) started = false;
    if (!started && stepped.ok() && stepped.value() == FrameStatus::kOk) {
      const cv::Size size =
          imageless ? cv::Size(params.camera.width, params.camera.height) : in.frames.PeekedSize();
      if (MaybeError s = start(size)) {
        std::cerr << me << s->Format() << "\n";
        return kExitBadInput;
      }
      // a live TUIO stream paces the frames: each waits up to a frame for the sender's
      TuioStream* tuio = in.frames.tuio();
      if (tuio && tuio->live()) tuio->SetWait(sim.FrameDuration());
    }
    if (stepped.ok() && stepped.value() == FrameStatus::kOk) stepped = in.frames.Step(sim);
    if (!stepped.ok()) {
      // the pipeline rejected the frame
      std::cerr << me << in.frames.Describe() << ": " << stepped.error().Format() << "\n";
      ++badFrames;
      ++index;
      if (++failuresInARow >= kMaxFailuresInARow) return kExitFailed;
      continue;
    }
    if (stepped.value() == FrameStatus::kEnd) break;
    if (stepped.value() == FrameStatus::kLost) {
      // a camera that disappears: say so, and try to get it back for a few seconds
      std::cerr << me << in.frames.LastError() << "; no input, retrying\n";
      bool back = false;
      int attempts = 0;
      while (attempts < kReopenAttempts && !back) {
        std::this_thread::sleep_for(std::chrono::seconds(1));
        ++attempts;
        back = !in.frames.Reconnect();
      }
      if (back) std::cerr << me << in.frames.Describe() << ": back after " << attempts << " s\n";
      if (!back) {
        std::cerr << me << in.frames.Describe() << ": gave up after " << kReopenAttempts
                  << " attempts\n";
        return kExitFailed;
      }
      continue;
    }
    if (stepped.value() == FrameStatus::kError) {
      std::cerr << me << in.frames.LastError() << "\n";
      ++badFrames;
      ++index;
      if (++failuresInARow >= kMaxFailuresInARow) {
        std::cerr << me << in.frames.Describe() << ": " << kMaxFailuresInARow
                  << " bad frames in a row, stopping\n";
        return kExitFailed;
      }
      continue;
    }
    failuresInARow = 0;
    std::cout << FrameJson(index, sim.contacts(), sim.contours().hover) << "\n";
    // a frame that cannot be sent is counted and the run goes on; the first one is reported
    if (output) {
      const bool firstFailure = output->sendErrors() == 0;
      if (MaybeError e = output->Send(sim); e && firstFailure)
        std::cerr << me << "--tuio-out: " << e->Format() << " (further failures are counted)\n";
    }
    ++index;
  }
  std::cout.flush();
  // what a TUIO stream brought, and what it dropped
  if (const TuioStream* tuio = in.frames.tuio()) std::cerr << me << tuio->Status() << "\n";
  if (output) {
    MaybeError closed = output->Close();
    std::cerr << me << output->Status() << "\n";
    if (closed) {
      std::cerr << me << "--tuio-out: " << closed->Format() << "\n";
      return kExitFailed;
    }
  }
  if (!o.preview.empty() && (!started || !WritePreview(sim, o.preview))) {
    std::cerr << me << "cannot write the sensing preview " << o.preview << "\n";
    return kExitFailed;
  }
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
                  "camera:N, /dev/videoN, video:FILE or a video file, an image file, folder:DIR or "
                  "a directory, "
                  "synthetic:fingers or synthetic:hands, tuio:PORT or tuio:ADDRESS:PORT (TUIO "
                  "over UDP), or a level file (*.toml)")
      ->required();
  cmd->add_option("--calibration", options.calibration,
                  "calibration YAML (proxygrasp calibrate); without it the image maps linearly "
                  "onto the table");
  cmd->add_option("--frames", options.frames, "stop after N frames (0: until the input ends)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--set", options.sets,
                  "set a parameter, e.g. --set sensing.threshold=50 (repeatable)");
  cmd->add_option("--preview", options.preview,
                  "write the last frame's filter stages side by side, with the contacts' outlines "
                  "and ids on the camera image, to this PNG (with --frames N: frame N-1); a depth "
                  "camera's: depth, surface, height above it, touch and hover");
  cmd->add_option("--tuio-out", options.tuioOut,
                  "also send each frame's contacts as TUIO 2.0 to HOST:PORT over UDP, or record "
                  "them to file:PATH (touchlib XML; time tags are the frames' times)");
  cmd->add_flag("--stills", options.stills,
                "sense each image on its own (a folder of unrelated images or photos): its "
                "background from the image alone, nothing carried from one to the next; a single "
                "image file is sensed so without it");
  cmd->add_flag("--tuio-cursors", options.tuioCursors,
                "with --tuio-out, also send TUIO 1.1 /tuio/2Dcur cursors for older clients")
      ->needs("--tuio-out");
  cmd->callback([&exitCode] { exitCode = RunSense(options); });
}

}  // namespace pg
