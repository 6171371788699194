#include "proxygrasp/app/app.h"

#include "proxygrasp/app/hand_input.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/trace.h"
#include "proxygrasp/run/tuio_output.h"
#include "proxygrasp/sensing/depth_source.h"

#include <SDL.h>
#include <imgui.h>
#include <imgui_impl_sdl.h>
#include <imgui_impl_sdlrenderer.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

namespace pg {

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kRetrySeconds = 1.0;    // between attempts to reopen a lost camera
constexpr double kMessageSeconds = 4.0;  // how long a transient message stays on screen
constexpr double kFpsSmoothing = 0.1;    // weight of the newest frame in the frame-rate average

const std::vector<std::string> kHelpLines = {
    "Keys",
    "P  pause / resume          O  single step",
    "R  restart the level       L  reload the level file",
    "Tab  next level in the folder",
    "F  full screen             S  screenshot (PNG)",
    "V  start / stop recording (input .mkv + trace)",
    "E  force vectors           Y  successor links",
    "C  raw camera image        [ ]  one layer at a time",
    "I  sensing view: each filter stage, contacts and ids",
    "H  this help               Esc  quit",
    "",
    "Mouse",
    "left drag: one fingertip",
    "right drag: two-finger pinch around the cursor",
    "wheel: open / close the pinch; Ctrl+wheel or Alt+drag: turn it",
    "Shift: a flat hand instead",
};

// a file's modification time and size, to notice edits
struct FileStamp {
  std::filesystem::file_time_type time{};
  uintmax_t size = 0;
  bool operator==(const FileStamp&) const = default;
};

FileStamp StampOf(const std::string& path) {
  std::error_code ec;
  FileStamp stamp;
  stamp.time = std::filesystem::last_write_time(path, ec);
  stamp.size = std::filesystem::file_size(path, ec);
  return stamp;
}

// the Dear ImGui widgets of one parameter section; edits go into the struct the section refers to
class PanelVisitor : public ParamVisitor {
 public:
  bool committed = false;  // an edit finished: apply the edited parameters

  void Real(const char* key, double& value, double min, double max, const char* unit,
            FieldDoc doc) override {
    const double speed = std::max(std::abs(value) * 0.01, 1e-3);
    ImGui::DragScalar(Label(key, unit).c_str(), ImGuiDataType_Double, &value,
                      static_cast<float>(speed), &min, &max, "%.4g", ImGuiSliderFlags_AlwaysClamp);
    After(doc);
  }
  void Integer(const char* key, int& value, int min, int max, const char* unit,
               FieldDoc doc) override {
    ImGui::DragInt(Label(key, unit).c_str(), &value, 0.2f, min, max, "%d",
                   ImGuiSliderFlags_AlwaysClamp);
    After(doc);
  }
  void Boolean(const char* key, bool& value, FieldDoc doc) override {
    if (ImGui::Checkbox(key, &value)) committed = true;
    Tooltip(doc);
  }
  void Choice(const char* key, int& value, std::span<const char* const> names,
              FieldDoc doc) override {
    if (ImGui::Combo(key, &value, names.data(), static_cast<int>(names.size()))) committed = true;
    Tooltip(doc);
  }
  void Text(const char* key, std::string& value, FieldDoc doc) override {
    std::array<char, 512> buffer{};
    std::strncpy(buffer.data(), value.c_str(), buffer.size() - 1);
    if (ImGui::InputText(key, buffer.data(), buffer.size())) value = buffer.data();
    After(doc);
  }
  void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
              FieldDoc doc) override {
    ImGui::DragScalarN(Label(key, unit).c_str(), ImGuiDataType_Double, value.data(), 2, 0.05f, &min,
                       &max, "%.3g", ImGuiSliderFlags_AlwaysClamp);
    After(doc);
  }

 private:
  static std::string Label(const char* key, const char* unit) {
    const std::string u = unit;
    return (u.empty() || u == "1") ? std::string(key) : std::string(key) + " (" + u + ")";
  }
  // the doc, and for a key a running simulation cannot take, that a change restarts the run
  void Tooltip(FieldDoc doc) {
    if (!ImGui::IsItemHovered()) return;
    if (doc.apply == Apply::kRestart) {
      ImGui::SetTooltip("%s\n(a change restarts the run)", doc.text);
    } else {
      ImGui::SetTooltip("%s", doc.text);
    }
  }
  void After(FieldDoc doc) {
    if (ImGui::IsItemDeactivatedAfterEdit()) committed = true;
    Tooltip(doc);
  }
};

}  // namespace

struct App::Impl {
  AppOptions options;
  SDL_Window* window = nullptr;
  SDL_Renderer* renderer = nullptr;
  SDL_Texture* texture = nullptr;
  cv::Size textureSize;
  bool sdlUp = false;
  bool imguiUp = false;

  // the level and its run
  Level level;
  LevelParams params;  // what the simulation runs with
  LevelParams edit;    // what the panel edits
  Simulation sim;
  bool simOk = false;
  std::map<std::string, FileStamp> stamps;
  Clock::time_point lastReloadCheck = Clock::now();

  // drawing
  cv::Size outputSize;
  DisplayMap map;
  TableView view;
  ViewOptions viewOptions;
  cv::Mat picture;
  cv::Mat picture32;  // the picture as 32-bit B, G, R, X for the window
  std::string loadError;
  std::string runError;    // the pipeline's or the input's last error
  std::string message;     // transient status
  std::string tuneStatus;  // what the last parameter change did, shown in the panel
  Clock::time_point messageTime;

  // input
  InputKind input = InputKind::kMouse;
  std::string sourceSpec;
  FrameInput frames = FrameInput::Shapes();  // what steps the simulation
  bool noInput = false;
  Clock::time_point lastRetry = Clock::now();
  MouseHands mouse;
  TouchHands touch;

  // requests queued by keys, the panel and callers
  struct Pending {
    bool restart = false;
    bool reload = false;
    bool nextLevel = false;
    bool step = false;
    bool copyToml = false;
    std::optional<bool> pause;
    std::optional<bool> fullscreen;
    std::optional<bool> recording;
    std::optional<std::string> screenshot;
    std::optional<LevelParams> params;
  } pending;

  bool paused = false;
  bool quit = false;
  Result<std::string> screenshot = std::string();

  // recording
  TraceWriter recorder;  // input.mkv, objects.csv, frames.csv and contacts.csv of out/<level>_recN
  std::string recordDir;

  // every stepped frame's contacts sent on as TUIO (--tuio-out), or nothing
  std::unique_ptr<TuioOutput> tuioOut;

  // frame timing
  Clock::time_point lastTick = Clock::now();
  double fps = 0.0;
  std::vector<double> tickWorkMs;  // with options.timing

  ~Impl();
  MaybeError OpenWindow();
  Result<Level> ReadLevel(const std::string& path) const;
  MaybeError Adopt(Level next, const std::string& path);
  MaybeError Load(const std::string& path);
  MaybeError StartRun(const Level& runLevel, const LevelParams& runParams);
  void ApplyParams(const LevelParams& edited);
  MaybeError SetupInput();
  void Say(const std::string& text);
  void UpdateOutputSize();
  void HandleEvent(const SDL_Event& event);
  void HandleKey(SDL_Keycode key);
  Vec2 WindowToTable(int x, int y) const;
  void ApplyPending();
  void CheckLevelFiles();
  void StepInput();
  void Record();
  void SendTuio();
  void StartRecording();
  void StopRecording();
  void DrawPanel();
  void CopyToml();
  // the level file's name without folder and extension, for output file names
  std::string Stem() const { return std::filesystem::path(options.level).stem().string(); }
  std::string ChangedToml() const;
  void NextLevel();
  MaybeError WriteScreenshot(const std::string& path);
};

App::Impl::~Impl() {
  StopRecording();
  if (tuioOut) {
    if (MaybeError s = tuioOut->Close()) std::cerr << "proxygrasp play: " << s->Format() << "\n";
    std::cout << "proxygrasp play: " << tuioOut->Status() << std::endl;
  }
  if (imguiUp) {
    ImGui_ImplSDLRenderer_Shutdown();
    ImGui_ImplSDL2_Shutdown();
    ImGui::DestroyContext();
  }
  if (texture) SDL_DestroyTexture(texture);
  if (renderer) SDL_DestroyRenderer(renderer);
  if (window) SDL_DestroyWindow(window);
  if (sdlUp) SDL_Quit();
}

void App::Impl::Say(const std::string& text) {
  message = text;
  messageTime = Clock::now();
  std::cout << "proxygrasp play: " << text << std::endl;
}

MaybeError App::Impl::OpenWindow() {
  // no GPU is assumed: the software renderer works on every display, Xvfb included
  SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
  // and its picture goes straight to the window (XShm on X11): SDL would otherwise upload it to
  // an OpenGL texture each frame, which without a GPU is Mesa's software GL drawing it again
  // (12 ms of a 1280x960 frame under Xvfb, against 5 ms straight; docs/performance.md). The
  // environment variable SDL_FRAMEBUFFER_ACCELERATION still decides where it is set.
  SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
  if (SDL_Init(SDL_INIT_VIDEO) != 0)
    return MakeError({}, std::string("cannot open a window: ") + SDL_GetError());
  sdlUp = true;
  const int displays = SDL_GetNumVideoDisplays();
  if (options.display < 0 || options.display >= std::max(1, displays)) {
    return MakeError({}, "--display " + std::to_string(options.display) + ": there are " +
                             std::to_string(displays) + " displays (0 .. " +
                             std::to_string(displays - 1) + ")");
  }
  Uint32 flags = SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI;
  if (options.fullscreen) flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
  const int position = static_cast<int>(SDL_WINDOWPOS_CENTERED_DISPLAY(options.display));
  window = SDL_CreateWindow("proxygrasp", position, position, options.windowSize.width,
                            options.windowSize.height, flags);
  if (!window) return MakeError({}, std::string("cannot open a window: ") + SDL_GetError());
  renderer = SDL_CreateRenderer(window, -1, SDL_RENDERER_SOFTWARE);
  if (!renderer) return MakeError({}, std::string("cannot create a renderer: ") + SDL_GetError());

  // Dear ImGui over the SDL renderer; no imgui.ini is written
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplSDL2_InitForSDLRenderer(window);
  ImGui_ImplSDLRenderer_Init(renderer);
  imguiUp = true;
  UpdateOutputSize();
  return std::nullopt;
}

Result<Level> App::Impl::ReadLevel(const std::string& path) const {
  Result<Level> loaded = LoadLevel(path);
  if (!loaded.ok()) return loaded;
  if (MaybeError s = ApplyOverrides(loaded.value(), options.sets)) return *s;
  return loaded;
}

MaybeError App::Impl::Adopt(Level next, const std::string& path) {
  // the run starts before anything is replaced, so a level the pipeline rejects changes nothing
  const LevelParams nextParams = next.params;
  if (MaybeError s = StartRun(next, nextParams)) return s;
  stamps.clear();
  for (const std::string& file : next.files) stamps[file] = StampOf(file);
  stamps[path] = StampOf(path);
  options.level = path;
  level = std::move(next);
  params = nextParams;
  edit = params;
  loadError.clear();
  return std::nullopt;
}

MaybeError App::Impl::StartRun(const Level& runLevel, const LevelParams& runParams) {
  // frames from a depth source are not the synthetic camera's: the depth chain learns its surface
  // from their first frames
  SimulationOptions setup;
  setup.cameraBackground = !IsDepthSourceSpec(options.input);
  if (MaybeError s = sim.Start(runLevel, runParams, setup)) return s;
  // the level's own input (its script, recording or TUIO stream) starts again with the run
  if (input == InputKind::kScript) {
    Result<FrameInput> levelInput = FrameInput::ForLevel(runLevel);
    if (!levelInput.ok()) return levelInput.error();
    frames = std::move(levelInput.value());
  }
  StopRecording();
  view.Reset();
  mouse.Clear();
  touch.Clear();
  simOk = true;
  // a missing input's message stays until the input is back
  if (!noInput) runError.clear();
  Result<DisplayMap> m = LevelDisplayMap(runParams, outputSize);
  if (m.ok()) {
    map = m.value();
  } else {
    map = DisplayMap::Fit(runParams.table, outputSize);
    runError = m.error().Format();
  }
  return std::nullopt;
}

void App::Impl::ApplyParams(const LevelParams& edited) {
  auto join = [](const std::vector<std::string>& keys) {
    std::string text;
    for (const std::string& k : keys) text += (text.empty() ? "" : ", ") + k;
    return text;
  };
  auto say = [this](std::string status) {
    tuneStatus = std::move(status);
    Say(tuneStatus);
  };
  // a rejected value keeps the running parameters
  auto reject = [&](const Error& e) {
    runError = e.Format();
    edit = params;
    say("rejected: " + runError);
  };
  // another calibration file brings its tuned sensing values (the edit's other keys stay)
  LevelParams next = edited;
  if (next.sensing.calibration != params.sensing.calibration) {
    if (MaybeError s = ApplyCalibrationSensing(next)) return reject(*s);
  }
  // the running simulation takes what it can in place and keeps its objects and particles
  Result<RetuneReport> retuned = sim.Retune(next);
  if (!retuned.ok()) return reject(retuned.error());
  const RetuneReport& report = retuned.value();
  if (report.restart.empty()) {
    params = next;
    edit = params;
    if (!noInput) runError.clear();
    if (!report.live.empty()) say("applied live: " + join(report.live));
    return;
  }
  // the rest needs a new run: restart with every change, as before live tuning
  if (MaybeError s = StartRun(level, next)) return reject(*s);
  params = next;
  edit = params;
  say("restarted: " + join(report.restart) + " cannot change on a running simulation");
}

MaybeError App::Impl::Load(const std::string& path) {
  Result<Level> next = ReadLevel(path);
  if (!next.ok()) return next.error();
  return Adopt(std::move(next.value()), path);
}

MaybeError App::Impl::SetupInput() {
  const std::string& spec = options.input;
  if (spec.empty()) {
    // default: a camera when one opens, the mouse otherwise
    Result<FrameInput> camera = FrameInput::Open("camera:0");
    if (camera.ok()) {
      input = InputKind::kCamera;
      sourceSpec = "camera:0";
      frames = std::move(camera.value());
    } else {
      input = InputKind::kMouse;
      frames = FrameInput::Shapes();
    }
    return std::nullopt;
  }
  if (spec == "script") {
    input = InputKind::kScript;
    frames = FrameInput::Script();
  } else if (spec == "mouse" || spec == "touch") {
    input = spec == "mouse" ? InputKind::kMouse : InputKind::kTouch;
    frames = FrameInput::Shapes();
  } else if (spec.rfind("tuio:", 0) == 0) {
    // contacts from another tracker; the window's frame rate paces the run, so it never waits
    input = InputKind::kTuio;
    sourceSpec = spec;
    Result<FrameInput> tuio = FrameInput::Open(spec);
    if (!tuio.ok()) return MakeError({}, "--input " + spec + ": " + tuio.error().Format());
    frames = std::move(tuio.value());
  } else if (spec.rfind("camera:", 0) == 0 || spec.rfind("video:", 0) == 0 ||
             IsDepthSourceSpec(spec)) {
    // a camera or depth device that does not open now is retried: it may be plugged in later; a
    // video or depth recording replays from its start
    const bool live = spec.rfind("camera:", 0) == 0 || IsLiveDepthSourceSpec(spec);
    input = live ? InputKind::kCamera : InputKind::kVideo;
    sourceSpec = spec;
    Result<FrameInput> source = FrameInput::Open(spec, /*keepMissing=*/live);
    if (!source.ok()) return MakeError({}, "--input " + spec + ": " + source.error().Format());
    frames = std::move(source.value());
    if (!frames.HasSource()) {
      noInput = true;
      runError = frames.LastError();
    }
  } else {
    return MakeError(
        {}, "--input " + spec +
                ": expected camera:N, video:FILE, a depth source (kinect[:N], openni[:URI], "
                "oni:FILE, depth:DIR, fakenect:DIR), tuio:PORT, script, mouse or "
                "touch");
  }
  return std::nullopt;
}

void App::Impl::UpdateOutputSize() {
  int w = 0;
  int h = 0;
  SDL_GetRendererOutputSize(renderer, &w, &h);
  const cv::Size size(std::max(1, w), std::max(1, h));
  if (size == outputSize) return;
  outputSize = size;
  if (simOk) {
    Result<DisplayMap> m = LevelDisplayMap(params, outputSize);
    map = m.ok() ? m.value() : DisplayMap::Fit(params.table, outputSize);
  }
}

Vec2 App::Impl::WindowToTable(int x, int y) const {
  // window coordinates to renderer pixels (they differ on high-DPI screens), then to the table
  int ww = 1;
  int wh = 1;
  SDL_GetWindowSize(window, &ww, &wh);
  const double sx = static_cast<double>(outputSize.width) / std::max(1, ww);
  const double sy = static_cast<double>(outputSize.height) / std::max(1, wh);
  return map.ToTable(view.PictureToDisplay({(x + 0.5) * sx, (y + 0.5) * sy}));
}

void App::Impl::HandleKey(SDL_Keycode key) {
  switch (key) {
    case SDLK_p:
      pending.pause = !paused;
      break;
    case SDLK_o:
      pending.step = true;
      break;
    case SDLK_r:
      pending.restart = true;
      break;
    case SDLK_l:
      pending.reload = true;
      break;
    case SDLK_TAB:
      pending.nextLevel = true;
      break;
    case SDLK_f:
      pending.fullscreen = (SDL_GetWindowFlags(window) & SDL_WINDOW_FULLSCREEN_DESKTOP) == 0;
      break;
    case SDLK_s:
      pending.screenshot = std::string();
      break;
    case SDLK_v:
      pending.recording = !recorder.IsOpen();
      break;
    case SDLK_h:
      viewOptions.help = !viewOptions.help;
      break;
    case SDLK_e:
      viewOptions.forces = !viewOptions.forces;
      break;
    case SDLK_y:
      viewOptions.successors = !viewOptions.successors;
      break;
    case SDLK_c:
      viewOptions.cameraImage = !viewOptions.cameraImage;
      break;
    case SDLK_i:
      viewOptions.sensing = !viewOptions.sensing;
      break;
    case SDLK_RIGHTBRACKET:
      viewOptions.layer =
          viewOptions.layer + 1 >= params.physics.layers ? -1 : viewOptions.layer + 1;
      break;
    case SDLK_LEFTBRACKET:
      viewOptions.layer = viewOptions.layer < 0 ? params.physics.layers - 1 : viewOptions.layer - 1;
      break;
    case SDLK_ESCAPE:
      quit = true;
      break;
    default:
      break;
  }
}

void App::Impl::HandleEvent(const SDL_Event& event) {
  ImGui_ImplSDL2_ProcessEvent(&event);
  const ImGuiIO& io = ImGui::GetIO();
  const bool rotate = (SDL_GetModState() & (KMOD_CTRL | KMOD_ALT)) != 0;
  const bool flat = (SDL_GetModState() & KMOD_SHIFT) != 0;
  switch (event.type) {
    case SDL_QUIT:
      quit = true;
      break;
    case SDL_WINDOWEVENT:
      if (event.window.event == SDL_WINDOWEVENT_CLOSE) quit = true;
      if (event.window.event == SDL_WINDOWEVENT_FOCUS_LOST) mouse.Clear();
      break;
    case SDL_KEYDOWN:
      if (!io.WantCaptureKeyboard && event.key.repeat == 0) HandleKey(event.key.keysym.sym);
      break;
    case SDL_MOUSEBUTTONDOWN:
      // touches also arrive as mouse events; the touch input takes them as fingers instead
      if (input != InputKind::kMouse || io.WantCaptureMouse ||
          event.button.which == SDL_TOUCH_MOUSEID)
        break;
      if (event.button.button == SDL_BUTTON_LEFT)
        mouse.Press(MouseHands::Button::kLeft, WindowToTable(event.button.x, event.button.y), flat);
      if (event.button.button == SDL_BUTTON_RIGHT)
        mouse.Press(MouseHands::Button::kRight, WindowToTable(event.button.x, event.button.y),
                    flat);
      break;
    case SDL_MOUSEBUTTONUP:
      if (input != InputKind::kMouse || event.button.which == SDL_TOUCH_MOUSEID) break;
      if (event.button.button == SDL_BUTTON_LEFT) mouse.Release(MouseHands::Button::kLeft);
      if (event.button.button == SDL_BUTTON_RIGHT) mouse.Release(MouseHands::Button::kRight);
      break;
    case SDL_MOUSEMOTION:
      if (input != InputKind::kMouse || event.motion.which == SDL_TOUCH_MOUSEID) break;
      mouse.Move(WindowToTable(event.motion.x, event.motion.y),
                 (SDL_GetModState() & KMOD_ALT) != 0);
      break;
    case SDL_MOUSEWHEEL: {
      if (input != InputKind::kMouse || io.WantCaptureMouse) break;
      const double notches =
          event.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -event.wheel.y : event.wheel.y;
      mouse.Wheel(notches, rotate);
      break;
    }
    case SDL_FINGERDOWN:
    case SDL_FINGERMOTION:
      if (input != InputKind::kTouch) break;
      touch.Move(static_cast<int64_t>(event.tfinger.fingerId),
                 map.ToTable(view.PictureToDisplay(
                     {event.tfinger.x * outputSize.width, event.tfinger.y * outputSize.height})));
      break;
    case SDL_FINGERUP:
      if (input == InputKind::kTouch) touch.Lift(static_cast<int64_t>(event.tfinger.fingerId));
      break;
    default:
      break;
  }
}

void App::Impl::NextLevel() {
  // the level files of the current level's folder, in name order; the one after this one
  namespace fs = std::filesystem;
  const fs::path current = fs::path(options.level);
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(
           current.parent_path().empty() ? fs::path(".") : current.parent_path(), ec)) {
    if (entry.path().extension() == ".toml") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) return;
  auto it = std::find_if(files.begin(), files.end(),
                         [&](const std::string& f) { return fs::equivalent(f, current, ec); });
  const std::string next = (it == files.end() || it + 1 == files.end()) ? files.front() : *(it + 1);
  if (MaybeError s = Load(next)) {
    loadError = s->Format();
    std::cerr << loadError << "\n";
    return;
  }
  Say("level " + level.name + " (" + next + ")");
}

void App::Impl::ApplyPending() {
  Pending p = std::move(pending);
  pending = Pending{};
  if (p.pause) paused = *p.pause;
  if (p.fullscreen) {
    SDL_SetWindowFullscreen(window, *p.fullscreen ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0);
  }
  if (p.nextLevel) NextLevel();
  if (p.reload) {
    // a failed reload keeps the running level and shows why
    if (MaybeError s = Load(options.level)) {
      loadError = s->Format();
      std::cerr << "proxygrasp play: reload failed, keeping the running level\n"
                << loadError << std::endl;
      // the broken files are not retried until they change again
      for (auto& [file, stamp] : stamps) stamp = StampOf(file);
    } else {
      Say("reloaded " + options.level);
    }
  }
  if (p.params) {
    ApplyParams(*p.params);
  } else if (p.restart) {
    if (MaybeError s = StartRun(level, params)) runError = s->Format();
  }
  if (p.recording) {
    if (*p.recording) {
      StartRecording();
    } else {
      StopRecording();
    }
  }
  if (p.copyToml) CopyToml();
  if (p.step) {
    paused = true;
    StepInput();
  }
  if (p.screenshot) pending.screenshot = p.screenshot;  // written after drawing, below
}

void App::Impl::CheckLevelFiles() {
  const Clock::time_point now = Clock::now();
  if (std::chrono::duration<double>(now - lastReloadCheck).count() < options.reloadInterval) return;
  lastReloadCheck = now;
  for (const auto& [file, stamp] : stamps) {
    if (StampOf(file) != stamp) {
      pending.reload = true;
      return;
    }
  }
}

void App::Impl::StepInput() {
  if (!simOk) return;
  switch (input) {
    case InputKind::kScript:
      // the script loops
      if (sim.Time() >= level.script.duration - 1e-9) {
        if (MaybeError s = StartRun(level, params)) {
          runError = s->Format();
          return;
        }
      }
      break;
    case InputKind::kMouse:
      frames.SetShapes(mouse.Shapes());
      break;
    case InputKind::kTouch:
      frames.SetShapes(touch.Shapes());
      break;
    case InputKind::kTuio:
      break;
    case InputKind::kCamera:
    case InputKind::kVideo: {
      // a lost or missing source shows "no input" and is retried, never fatal
      const Clock::time_point now = Clock::now();
      if (noInput) {
        if (std::chrono::duration<double>(now - lastRetry).count() < kRetrySeconds) return;
        lastRetry = now;
        if (MaybeError s = frames.Reconnect()) {
          runError = s->Format();
          return;
        }
        noInput = false;
        runError.clear();
      }
      break;
    }
  }
  // the sensing view shows every filter stage of the whole frame
  sim.SetWholeStages(viewOptions.sensing);
  Result<FrameStatus> stepped = frames.Step(sim);
  if (!stepped.ok()) {
    runError = stepped.error().Format();
    return;
  }
  switch (stepped.value()) {
    case FrameStatus::kOk:
      Record();
      SendTuio();
      return;
    case FrameStatus::kEnd:
      // a video replays from its start, with a fresh run
      noInput = true;
      lastRetry = Clock::now() - std::chrono::seconds(10);
      if (MaybeError s = StartRun(level, params)) runError = s->Format();
      return;
    case FrameStatus::kLost:
      noInput = true;
      runError = frames.Describe() + ": " + frames.LastError();
      return;
    case FrameStatus::kError:
      runError = frames.LastError();
      return;
  }
}

void App::Impl::StartRecording() {
  if (recorder.IsOpen() || !simOk) return;
  // a fresh folder out/<level>_recN with input.mkv, objects.csv, frames.csv and contacts.csv
  std::string dir;
  for (int k = 1;; ++k) {
    dir = options.outDir + "/" + Stem() + "_rec" + std::to_string(k);
    if (!std::filesystem::exists(dir)) break;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  // depth frames (the depth camera's, or a depth source's) as a depth:DIR recording beside them
  const bool depth = params.camera.kind == CameraKind::kDepth ||
                     (!sim.cameraImage().empty() && sim.cameraImage().type() == CV_16UC1);
  const std::string camera = depth ? "depth:" + dir + "/depth" : dir + "/input.mkv";
  if (MaybeError s = recorder.Open(dir, camera, sim.CameraSize(), params.physics.frameRate)) {
    runError = s->Format();
    return;
  }
  recordDir = dir;
  Say("recording into " + dir);
}

void App::Impl::StopRecording() {
  if (!recorder.IsOpen()) return;
  const int64_t recorded = recorder.frames();
  if (MaybeError s = recorder.Close()) {
    runError = s->Format();
  } else {
    Say("recorded " + std::to_string(recorded) + " frames into " + recordDir);
  }
}

void App::Impl::Record() {
  if (!recorder.IsOpen()) return;
  if (MaybeError s = recorder.Write(sim)) {
    runError = s->Format();
    StopRecording();
  }
}

void App::Impl::SendTuio() {
  if (!tuioOut) return;
  // a frame that cannot be sent is counted in the status line, never fatal; the first is logged
  const bool firstFailure = tuioOut->sendErrors() == 0;
  if (MaybeError s = tuioOut->Send(sim); s && firstFailure)
    std::cerr << "proxygrasp play: --tuio-out: " << s->Format() << " (further failures are counted)"
              << std::endl;
}

std::string App::Impl::ChangedToml() const {
  // the parameters that differ from the level file, section by section
  LevelParams fileParams = level.params;
  LevelParams current = params;
  const std::vector<ParamSection> now = Sections(current);
  const std::vector<ParamSection> before = Sections(fileParams);
  std::string toml;
  for (size_t i = 0; i < now.size(); ++i) {
    const std::string changed = ChangedFieldsAsToml(now[i], before[i]);
    if (changed.empty()) continue;
    if (!toml.empty()) toml += "\n";
    toml += changed;
  }
  if (toml.empty()) toml = "# no parameter differs from " + options.level + "\n";
  return toml;
}

void App::Impl::CopyToml() {
  const std::string toml = ChangedToml();
  SDL_SetClipboardText(toml.c_str());
  std::cout << toml << std::flush;
  Say("copied the changed parameters as TOML");
}

void App::Impl::DrawPanel() {
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(outputSize.width) - 10.0f, 10.0f),
                          ImGuiCond_FirstUseEver, ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(420, 560), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Tuning")) {
    ImGui::End();
    return;
  }
  ImGui::Text("%s (%s), input: %s", level.name.c_str(), options.level.c_str(),
              kInputKindNames[static_cast<int>(input)]);
  bool pause = paused;
  if (ImGui::Checkbox("pause", &pause)) pending.pause = pause;
  ImGui::SameLine();
  if (ImGui::Button("step")) pending.step = true;
  ImGui::SameLine();
  if (ImGui::Button("restart")) pending.restart = true;
  ImGui::SameLine();
  if (ImGui::Button("reload")) pending.reload = true;

  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("force vectors", &viewOptions.forces);
    ImGui::Checkbox("successor links", &viewOptions.successors);
    ImGui::Checkbox("raw camera image", &viewOptions.cameraImage);
    ImGui::Checkbox("sensing view (filter stages)", &viewOptions.sensing);
    ImGui::SliderInt("layer (-1 all)", &viewOptions.layer, -1, params.physics.layers - 1);
  }

  ImGui::Separator();
  // which keys restart the run comes from the parameters' descriptions
  static const std::string restartText = [] {
    std::string text =
        "Level parameters: a finished edit applies at once to the running level; these restart "
        "the run:";
    for (const std::string& key : RestartKeys()) text += " " + key;
    return text;
  }();
  ImGui::TextWrapped("%s", restartText.c_str());
  if (!tuneStatus.empty()) ImGui::TextWrapped("%s", tuneStatus.c_str());
  if (ImGui::Button("Copy as TOML")) pending.copyToml = true;
  ImGui::SameLine();
  if (ImGui::Button("Revert to the file")) pending.params = level.params;
  PanelVisitor visitor;
  for (const ParamSection& section : Sections(edit)) {
    if (!ImGui::CollapsingHeader(section.name.c_str())) continue;
    ImGui::PushID(section.name.c_str());
    section.describe(visitor);
    ImGui::PopID();
  }
  if (visitor.committed) pending.params = edit;
  ImGui::End();
}

MaybeError App::Impl::WriteScreenshot(const std::string& path) {
  cv::Mat pixels(outputSize, CV_8UC3);
  if (SDL_RenderReadPixels(renderer, nullptr, SDL_PIXELFORMAT_BGR24, pixels.data,
                           static_cast<int>(pixels.step)) != 0) {
    return MakeError({path}, std::string("cannot read the window: ") + SDL_GetError());
  }
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (!cv::imwrite(path, pixels)) return MakeError({path}, "cannot write the PNG");
  return std::nullopt;
}

App::App() : m_impl(std::make_unique<Impl>()) {}
App::~App() = default;

MaybeError App::Open(const AppOptions& options) {
  Impl& a = *m_impl;
  assert(!a.sdlUp && "an App opens once");
  a.options = options;
  a.viewOptions = options.view;
  // the level first: a bad file is reported before any window appears
  Result<Level> level = a.ReadLevel(options.level);
  if (!level.ok()) return level.error();
  if (MaybeError s = a.SetupInput()) return s;
  if (!options.tuioOut.empty()) {
    TuioEncoderParams encoding;
    encoding.cursors11 = options.tuioCursors;
    Result<std::unique_ptr<TuioOutput>> out = TuioOutput::Open(options.tuioOut, encoding);
    if (!out.ok())
      return MakeError({}, "--tuio-out " + options.tuioOut + ": " + out.error().Format());
    a.tuioOut = std::move(out.value());
  }
  if (MaybeError s = a.OpenWindow()) return s;
  if (MaybeError s = a.Adopt(std::move(level.value()), options.level)) return s;
  SDL_SetWindowTitle(a.window, ("proxygrasp - " + a.level.name).c_str());
  return std::nullopt;
}

bool App::Tick() {
  Impl& a = *m_impl;
  const Clock::time_point start = Clock::now();

  // events, then the requests they and the UI queued, then the level files
  SDL_Event event;
  while (SDL_PollEvent(&event)) a.HandleEvent(event);
  if (a.quit) return false;
  a.ApplyPending();
  a.CheckLevelFiles();

  // one pipeline step
  if (!a.paused) a.StepInput();

  // the drawing
  a.UpdateOutputSize();
  Overlay overlay;
  overlay.fps = a.fps;
  std::string status = std::string("input: ") + kInputKindNames[static_cast<int>(a.input)];
  if (a.input == InputKind::kCamera || a.input == InputKind::kVideo)
    status += a.noInput ? " - no input, retrying" : " (" + a.sourceSpec + ")";
  if (const TuioStream* tuio = a.frames.tuio()) status += " (" + tuio->Status() + ")";
  if (a.frames.skippedFrames() > 0)
    status += "   " + std::to_string(a.frames.skippedFrames()) + " bad frame(s) skipped";
  if (a.paused) status += "   PAUSED";
  if (a.recorder.IsOpen()) status += "   REC " + a.recordDir;
  if (a.tuioOut) status += "   " + a.tuioOut->Status();
  if (!a.message.empty() &&
      std::chrono::duration<double>(start - a.messageTime).count() < kMessageSeconds)
    status += "   " + a.message;
  overlay.status = status;
  overlay.error = a.loadError;
  if (!a.runError.empty()) overlay.error += (overlay.error.empty() ? "" : "\n") + a.runError;
  overlay.help = kHelpLines;
  if (a.simOk) {
    a.view.Draw(a.sim, a.map, a.outputSize, a.viewOptions, overlay, a.picture);
  } else {
    a.picture.create(a.outputSize, CV_8UC3);
    a.picture.setTo(view_colors::kOutside);
  }

  // upload it, then the UI on top
  // as 32-bit B, G, R, X pixels, the window's own layout on X11, so that the software renderer
  // copies them instead of converting each pixel from 24 bits (1.8 ms a 1280x960 frame)
  if (!a.texture || a.textureSize != a.outputSize) {
    if (a.texture) SDL_DestroyTexture(a.texture);
    a.texture = SDL_CreateTexture(a.renderer, SDL_PIXELFORMAT_RGB888, SDL_TEXTUREACCESS_STREAMING,
                                  a.outputSize.width, a.outputSize.height);
    a.textureSize = a.outputSize;
  }
  cv::cvtColor(a.picture, a.picture32, cv::COLOR_BGR2BGRA);
  SDL_UpdateTexture(a.texture, nullptr, a.picture32.data, static_cast<int>(a.picture32.step));
  SDL_RenderClear(a.renderer);
  SDL_RenderCopy(a.renderer, a.texture, nullptr, nullptr);
  ImGui_ImplSDLRenderer_NewFrame();
  ImGui_ImplSDL2_NewFrame();
  ImGui::NewFrame();
  a.DrawPanel();
  ImGui::Render();
  ImGui_ImplSDLRenderer_RenderDrawData(ImGui::GetDrawData());

  // a requested screenshot is what is about to be presented
  if (a.pending.screenshot) {
    std::string path = *a.pending.screenshot;
    a.pending.screenshot.reset();
    if (path.empty())
      path = a.options.outDir + "/" + a.Stem() + "_" + std::to_string(a.sim.Frame()) + ".png";
    if (MaybeError s = a.WriteScreenshot(path)) {
      a.screenshot = *s;
      a.runError = s->Format();
    } else {
      a.screenshot = path;
      a.Say("screenshot " + path);
    }
  }
  SDL_RenderPresent(a.renderer);

  // pace to the level's frame rate, and measure the loop
  const double spent = std::chrono::duration<double>(Clock::now() - start).count();
  if (a.options.timing) a.tickWorkMs.push_back(1000.0 * spent);
  if (a.options.realtime) {
    const double period = 1.0 / a.params.physics.frameRate;
    if (spent < period) SDL_Delay(static_cast<Uint32>((period - spent) * 1000.0));
  }
  const Clock::time_point end = Clock::now();
  const double seconds = std::chrono::duration<double>(end - a.lastTick).count();
  a.lastTick = end;
  if (seconds > 0) a.fps = a.fps == 0 ? 1.0 / seconds : Lerp(a.fps, 1.0 / seconds, kFpsSmoothing);
  return !a.quit;
}

void App::RequestPause(bool paused) {
  m_impl->pending.pause = paused;
}
void App::RequestStep() {
  m_impl->pending.step = true;
}
void App::RequestRestart() {
  m_impl->pending.restart = true;
}
void App::RequestReload() {
  m_impl->pending.reload = true;
}
void App::RequestNextLevel() {
  m_impl->pending.nextLevel = true;
}
void App::RequestFullscreen(bool fullscreen) {
  m_impl->pending.fullscreen = fullscreen;
}
void App::RequestScreenshot(const std::string& path) {
  m_impl->pending.screenshot = path;
}
void App::RequestParams(const LevelParams& params) {
  m_impl->pending.params = params;
}
const std::string& App::tuneStatus() const {
  return m_impl->tuneStatus;
}
std::string App::ChangedParamsToml() const {
  return m_impl->ChangedToml();
}
void App::RequestRecording(bool on) {
  m_impl->pending.recording = on;
}

const Simulation& App::simulation() const {
  return m_impl->sim;
}
const Level& App::level() const {
  return m_impl->level;
}
const DisplayMap& App::displayMap() const {
  return m_impl->map;
}
const cv::Mat& App::picture() const {
  return m_impl->picture;
}
const TableView& App::tableView() const {
  return m_impl->view;
}
const std::string& App::loadError() const {
  return m_impl->loadError;
}
const std::string& App::runError() const {
  return m_impl->runError;
}
bool App::noInput() const {
  return m_impl->noInput;
}
const Result<std::string>& App::screenshotStatus() const {
  return m_impl->screenshot;
}
const std::vector<double>& App::tickWorkMs() const {
  return m_impl->tickWorkMs;
}
InputKind App::input() const {
  return m_impl->input;
}
bool App::paused() const {
  return m_impl->paused;
}
bool App::recording() const {
  return m_impl->recorder.IsOpen();
}
uint32_t App::windowId() const {
  return m_impl->window ? SDL_GetWindowID(m_impl->window) : 0;
}
const std::string& App::recordingDir() const {
  return m_impl->recordDir;
}

}  // namespace pg
