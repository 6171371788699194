// `proxygrasp calibrate`: shows a chessboard on the table's projector, finds it in the camera
// image, fits the lens and the camera-to-table homography, captures the clear-table background and
// saves the calibration file that sensing reads. A bad detection is reported and retried, never
// saved. With --synthetic the board is rendered through the synthetic table camera instead (no
// window, no camera). See docs/calibration.md.
#include "commands.h"

#include "proxygrasp/sensing/calibrate.h"
#include "proxygrasp/sensing/depth_plane.h"
#include "proxygrasp/sensing/depth_source.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <opencv2/imgproc.hpp>

#if PROXYGRASP_WITH_SDL
#define SDL_MAIN_HANDLED
#include <SDL.h>
#endif

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace pg {

namespace {

struct CalibrateArgs {
  std::string camera = "camera:0";
  bool synthetic = false;
  std::string output = "calibration.yaml";
  int display = 0;
  std::string displaySize = "1024x768";
  std::string tableSize = "61x46";
  int squarePx = 64;
  int retries = 3;
  int backgroundFrames = 30;
  double maxError = 0.1;
  int radialTerms = 1;
  std::string intrinsics;
  // the synthetic camera
  double perspective = 0.06;
  double distortion = -0.05;
  double noise = 3.0;
  int seed = 1;
  double shift = 0.0;
};

// "WxH" with positive numbers
template <typename T>
bool ParseSize(const std::string& text, T& w, T& h) {
  std::istringstream in(text);
  char x = 0;
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || !(w > 0) || !(h > 0)) return false;
  char rest = 0;
  return !(in >> rest);
}

// where the board is shown and the camera frames come from
class Rig {
 public:
  virtual ~Rig() = default;
  /// Shows a display-sized CV_8UC1 image on the table and waits until the camera sees it.
  virtual MaybeError Show(const cv::Mat& display) = 0;
  /// The next camera frame, CV_8UC1.
  virtual Result<cv::Mat> Grab() = 0;
};

// the synthetic table camera looking at a perfectly aligned projector (or one shifted along x)
class SyntheticRig final : public Rig {
 public:
  SyntheticRig(const SyntheticCameraParams& params, const TableParams& table, double shiftCm)
      : m_camera(params, table), m_table(table), m_shiftCm(shiftCm) {}

  MaybeError Show(const cv::Mat& display) override {
    m_shown = display.clone();
    if (m_shiftCm != 0.0) {
      // a misaligned projector: the image lands shifted on the table
      const double px = m_shiftCm * display.cols / m_table.width;
      cv::warpAffine(display, m_shown, cv::Matx23d(1, 0, px, 0, 1, 0), display.size(),
                     cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
    }
    return std::nullopt;
  }
  Result<cv::Mat> Grab() override { return m_camera.RenderTableImage(m_shown); }

 private:
  SyntheticCamera m_camera;
  TableParams m_table;
  double m_shiftCm;
  cv::Mat m_shown;
};

#if PROXYGRASP_WITH_SDL
// a full-screen window on the projector's display and a real camera
class CameraRig final : public Rig {
 public:
  ~CameraRig() override {
    if (m_texture) SDL_DestroyTexture(m_texture);
    if (m_renderer) SDL_DestroyRenderer(m_renderer);
    if (m_window) SDL_DestroyWindow(m_window);
    if (m_sdl) SDL_Quit();
  }

  MaybeError Open(const std::string& spec, int display) {
    Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(spec);
    if (!source.ok()) return source.error();
    m_source = std::move(source.value());
    if (SDL_Init(SDL_INIT_VIDEO) != 0) return MakeError({}, std::string("SDL: ") + SDL_GetError());
    m_sdl = true;
    const int displays = SDL_GetNumVideoDisplays();
    if (display < 0 || display >= displays) {
      return MakeError({"--display " + std::to_string(display)},
                       "no such display (" + std::to_string(displays) + " connected)");
    }
    SDL_Rect bounds;
    SDL_GetDisplayBounds(display, &bounds);
    m_window = SDL_CreateWindow("proxygrasp calibrate", bounds.x, bounds.y, bounds.w, bounds.h,
                                SDL_WINDOW_FULLSCREEN_DESKTOP | SDL_WINDOW_BORDERLESS);
    if (!m_window) return MakeError({}, std::string("SDL window: ") + SDL_GetError());
    m_renderer = SDL_CreateRenderer(m_window, -1, 0);
    if (!m_renderer) return MakeError({}, std::string("SDL renderer: ") + SDL_GetError());
    return std::nullopt;
  }

  MaybeError Show(const cv::Mat& display) override {
    // the image stretched over the whole display
    cv::Mat rgb;
    cv::cvtColor(display, rgb, cv::COLOR_GRAY2RGB);
    if (m_texture) SDL_DestroyTexture(m_texture);
    m_texture = SDL_CreateTexture(m_renderer, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STATIC,
                                  rgb.cols, rgb.rows);
    if (!m_texture) return MakeError({}, std::string("SDL texture: ") + SDL_GetError());
    SDL_UpdateTexture(m_texture, nullptr, rgb.data, static_cast<int>(rgb.step));
    // the projector and the camera's exposure need a moment: drop the frames of that time
    for (int i = 0; i < kSettleFrames; ++i) {
      SDL_RenderClear(m_renderer);
      SDL_RenderCopy(m_renderer, m_texture, nullptr, nullptr);
      SDL_RenderPresent(m_renderer);
      Result<cv::Mat> dropped = Grab();
      if (!dropped.ok()) return dropped.error();
    }
    return std::nullopt;
  }

  Result<cv::Mat> Grab() override {
    // Escape or closing the window cancels
    for (SDL_Event e; SDL_PollEvent(&e);) {
      if (e.type == SDL_QUIT || (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_ESCAPE))
        return MakeError({}, "cancelled");
    }
    cv::Mat frame;
    switch (m_source->Read(frame)) {
      case FrameStatus::kOk:
        return frame;
      case FrameStatus::kEnd:
        return MakeError({m_source->Describe()}, "the source ended");
      case FrameStatus::kLost:
      case FrameStatus::kError:
        break;
    }
    return MakeError({m_source->Describe()}, m_source->LastError());
  }

 private:
  static constexpr int kSettleFrames = 20;  // 1/3 s at 60 Hz

  std::unique_ptr<FrameSource> m_source;
  bool m_sdl = false;
  SDL_Window* m_window = nullptr;
  SDL_Renderer* m_renderer = nullptr;
  SDL_Texture* m_texture = nullptr;
};
#endif

// A depth camera needs no projector: the table's plane and its top's corners come from the depth
// frames themselves (docs/calibration.md, "Depth cameras").
int CalibrateDepthCamera(const CalibrateArgs& args, const TableParams& table) {
  Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(args.camera);
  if (!source.ok()) {
    std::cerr << "proxygrasp calibrate: " << source.error().Format() << "\n";
    return kExitBadInput;
  }
  const int wanted = args.backgroundFrames > 0 ? args.backgroundFrames : 1;
  std::cout << "clear the table: reading " << wanted << " depth frames from "
            << source.value()->Describe() << "\n";
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  while (static_cast<int>(frames.size()) < wanted) {
    const FrameStatus status = source.value()->Read(frame);
    if (status == FrameStatus::kEnd) break;
    if (status != FrameStatus::kOk) {
      std::cerr << "proxygrasp calibrate: " << source.value()->Describe() << ": "
                << source.value()->LastError() << "\n";
      return kExitBadInput;
    }
    frames.push_back(frame.clone());
  }
  if (frames.empty()) {
    std::cerr << "proxygrasp calibrate: " << source.value()->Describe()
              << ": no depth frame to calibrate from\n";
    return kExitBadInput;
  }
  Result<DepthCalibration> fit =
      CalibrateDepth(frames, table, DepthIntrinsics::KinectV1(frames.front().size()));
  if (!fit.ok()) {
    std::cerr << "proxygrasp calibrate: " << source.value()->Describe() << ": "
              << fit.error().Format() << "; nothing saved\n";
    return kExitFailed;
  }
  const DepthCalibration& d = fit.value();
  char summary[320];
  std::snprintf(summary, sizeof(summary),
                "table plane %.0f mm from the camera, tilted %.2f degrees, rms %.2f mm over %d of "
                "%d readings; table top %.1f x %.1f cm, %.0f%% of it seen\n",
                d.plane.Distance(), d.plane.TiltDeg(), d.plane.rms, d.plane.inliers,
                d.plane.samples, 0.1 * d.rectangle.widthMm, 0.1 * d.rectangle.depthMm,
                100.0 * d.rectangle.fill);
  std::cout << "read " << frames.size() << " frames; " << summary;
  if (MaybeError s = SaveCalibration(args.output, d.calibration)) {
    std::cerr << "proxygrasp calibrate: " << s->Format() << "\n";
    return kExitBadInput;
  }
  std::cout << "saved " << args.output << "\n";
  return kExitOk;
}

int Calibrate(const CalibrateArgs& args) {
  // options
  CalibrateParams params;
  TableParams table;
  if (!ParseSize(args.displaySize, params.displaySize.width, params.displaySize.height)) {
    std::cerr << "proxygrasp calibrate: --display-size " << args.displaySize
              << ": expected WxH in pixels, e.g. 1024x768\n";
    return kExitBadInput;
  }
  if (!ParseSize(args.tableSize, table.width, table.height)) {
    std::cerr << "proxygrasp calibrate: --table " << args.tableSize
              << ": expected WxH in cm, e.g. 61x46\n";
    return kExitBadInput;
  }
  params.squarePx = args.squarePx;
  params.maxErrorCm = args.maxError;
  params.radialTerms = args.radialTerms;
  if (!args.intrinsics.empty()) {
    // a known lens: keep its intrinsics and distortion, fit only the homography
    Result<Calibration> known = LoadCalibration(args.intrinsics);
    if (!known.ok()) {
      std::cerr << "proxygrasp calibrate: --intrinsics: " << known.error().Format() << "\n";
      return kExitBadInput;
    }
    Result<CameraModel> model = ModelFromCalibration(known.value(), args.intrinsics);
    if (!model.ok()) {
      std::cerr << "proxygrasp calibrate: --intrinsics: " << model.error().Format() << "\n";
      return kExitBadInput;
    }
    params.estimateDistortion = false;
    params.intrinsics = model.value();
  }
  // the output's folder must exist before anything is shown
  const std::filesystem::path output(args.output);
  const std::filesystem::path folder =
      output.parent_path().empty() ? std::filesystem::path(".") : output.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    std::cerr << "proxygrasp calibrate: " << args.output << ": cannot write the calibration file ("
              << folder.string() << " is not a folder)\n";
    return kExitBadInput;
  }
  if (!args.synthetic && IsDepthSourceSpec(args.camera)) return CalibrateDepthCamera(args, table);
  Result<ChessboardTarget> target = MakeChessboardTarget(table, params);
  if (!target.ok()) {
    std::cerr << "proxygrasp calibrate: " << target.error().Format() << "\n";
    return kExitBadInput;
  }

  // the rig
  std::unique_ptr<Rig> rig;
  if (args.synthetic) {
    SyntheticCameraParams camera;
    camera.perspective = args.perspective;
    camera.distortion = args.distortion;
    camera.noise = args.noise;
    camera.seed = args.seed;
    rig = std::make_unique<SyntheticRig>(camera, table, args.shift);
  } else {
#if PROXYGRASP_WITH_SDL
    auto cameraRig = std::make_unique<CameraRig>();
    if (MaybeError s = cameraRig->Open(args.camera, args.display)) {
      std::cerr << "proxygrasp calibrate: " << s->Format() << "\n";
      return kExitBadInput;
    }
    rig = std::move(cameraRig);
#else
    std::cerr << "proxygrasp calibrate: built without SDL2, so only --synthetic works\n";
    return kExitBadInput;
#endif
  }

  // the board, until it is found and fits, or the attempts run out
  const int attempts = 1 + std::max(args.retries, 0);
  std::optional<CameraFit> fit;
  cv::Size imageSize;
  for (int attempt = 1; attempt <= attempts && !fit; ++attempt) {
    Result<cv::Mat> frame = cv::Mat();
    if (MaybeError s = rig->Show(target.value().displayImage)) {
      frame = *s;
    } else {
      frame = rig->Grab();
    }
    if (!frame.ok()) {
      std::cerr << "proxygrasp calibrate: " << frame.error().Format() << "\n";
      return kExitBadInput;
    }
    Result<CameraFit> one = CalibrateFromFrame(frame.value(), target.value(), params);
    if (!one.ok()) {
      std::cerr << "attempt " << attempt << " of " << attempts << ": " << one.error().Format()
                << "\n";
      continue;
    }
    fit = one.value();
    imageSize = frame.value().size();
  }
  if (!fit) {
    std::cerr << "proxygrasp calibrate: no good detection in " << attempts
              << " attempts; nothing saved\n";
    return kExitFailed;
  }
  char summary[256];
  std::snprintf(summary, sizeof(summary),
                "found %d corners: RMS %.4f cm, worst %.4f cm (limit %.3f cm); k1 %.5f, k2 %.5f\n",
                fit->corners, fit->rmsErrorCm, fit->maxErrorCm, params.maxErrorCm,
                fit->model.distCoeffs[0], fit->model.distCoeffs[1]);
  std::cout << summary;

  // a clear table (the projector black) for the background
  cv::Mat background;
  if (args.backgroundFrames > 0) {
    std::cout << "clear the table: capturing " << args.backgroundFrames << " background frames\n";
    if (MaybeError s = rig->Show(cv::Mat::zeros(params.displaySize, CV_8UC1))) {
      std::cerr << "proxygrasp calibrate: " << s->Format() << "\n";
      return kExitBadInput;
    }
    std::vector<cv::Mat> frames;
    for (int i = 0; i < args.backgroundFrames; ++i) {
      Result<cv::Mat> frame = rig->Grab();
      if (!frame.ok()) {
        std::cerr << "proxygrasp calibrate: " << frame.error().Format() << "\n";
        return kExitBadInput;
      }
      frames.push_back(frame.value());
    }
    Result<cv::Mat> mean = AverageFrames(frames);
    if (!mean.ok() || mean.value().size() != imageSize) {
      std::cerr << "proxygrasp calibrate: "
                << (mean.ok() ? "the background frames changed size" : mean.error().Format())
                << "; nothing saved\n";
      return kExitFailed;
    }
    background = mean.value();
  }

  // save
  if (MaybeError s = SaveCalibration(
          args.output, MakeCalibration(*fit, target.value().tableToDisplay, background))) {
    std::cerr << "proxygrasp calibrate: " << s->Format() << "\n";
    return kExitBadInput;
  }
  std::cout << "saved " << args.output << "\n";
  return kExitOk;
}

}  // namespace

void AddCalibrateCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Calibrate camera, table and projector: chessboard, homographies, background");
  // CLI11 binds options by reference, so they live as long as the program
  static CalibrateArgs args;
  CLI::Option* camera =
      cmd->add_option("--camera", args.camera, "Camera to calibrate (a frame source spec)")
          ->capture_default_str();
  CLI::Option* synthetic =
      cmd->add_flag("--synthetic", args.synthetic,
                    "Render the board through the synthetic table camera (no window, no camera)");
  camera->excludes(synthetic);
  cmd->add_option("--output", args.output, "Calibration file to write (YAML)")
      ->capture_default_str();
  cmd->add_option("--display", args.display, "Display index of the projector")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--display-size", args.displaySize, "Projector resolution WxH, px")
      ->capture_default_str();
  cmd->add_option("--table", args.tableSize, "Table size WxH, cm")->capture_default_str();
  cmd->add_option("--square", args.squarePx, "Chessboard square, display px")
      ->capture_default_str()
      ->check(CLI::Range(8, 1024));
  cmd->add_option("--retries", args.retries, "Further attempts after a bad detection")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd->add_option("--background-frames", args.backgroundFrames,
                  "Clear-table frames averaged into the background (0 = none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 600));
  cmd->add_option("--max-error", args.maxError,
                  "Reject a fit whose worst corner is off by more, cm")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 10.0));
  cmd->add_option("--radial-terms", args.radialTerms,
                  "Radial distortion terms fitted: 1 (k1), 2 (k1, k2)")
      ->capture_default_str()
      ->check(CLI::Range(1, 2));
  cmd->add_option("--intrinsics", args.intrinsics,
                  "Keep the lens of this calibration file; fit only the homography");
  cmd->add_option("--perspective", args.perspective, "--synthetic: keystone, fraction of the width")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.3));
  cmd->add_option("--distortion", args.distortion, "--synthetic: radial distortion k1")
      ->capture_default_str()
      ->check(CLI::Range(-1.0, 1.0));
  cmd->add_option("--noise", args.noise, "--synthetic: sensor noise, grey")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 64.0));
  cmd->add_option("--seed", args.seed, "--synthetic: noise seed")->capture_default_str();
  cmd->add_option("--shift", args.shift,
                  "--synthetic: projector misaligned by this along x, cm (shows the failure path)")
      ->capture_default_str();
  cmd->callback([&exitCode] { exitCode = Calibrate(args); });
}

}  // namespace pg
