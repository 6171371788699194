// The table app: an SDL2 window (or a full screen on the projector over the table) that plays a
// level. Every input except a camera goes through the synthetic table camera, so the real pipeline
// always runs. A Dear ImGui panel tunes every level parameter; the level file is reloaded when it
// changes. UI actions queue requests that Tick applies between frames (MuJoCo simulate's pending_).
#pragma once

#include "proxygrasp/app/table_view.h"
#include "proxygrasp/core/error.h"
#include "proxygrasp/run/simulation.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pg {

/// The level `play` opens when none is named: a name, found as LevelSearchDirs says.
inline constexpr const char* kDefaultLevel = "demo_sort";

/// What drives the pipeline.
enum class InputKind { kCamera, kVideo, kScript, kMouse, kTouch, kTuio };
/// Names of InputKind values, in enum order.
inline constexpr const char* kInputKindNames[] = {"camera", "video", "script",
                                                  "mouse",  "touch", "tuio"};

/// How the app starts.
struct AppOptions {
  std::string level;              ///< the level file
  std::vector<std::string> sets;  ///< "section.key=value" overrides, kept across reloads
  /// "camera:N", "video:FILE", "script", "mouse", "touch", or "tuio:PORT" / "tuio:ADDRESS:PORT"
  /// (TUIO over UDP); "" takes camera 0 when it opens and the mouse otherwise.
  std::string input;
  bool fullscreen = false;         ///< full screen (desktop resolution) on `display`
  int display = 0;                 ///< display index for the window or full screen
  cv::Size windowSize{1280, 960};  ///< window size when not full screen, px
  std::string outDir = "out";      ///< where S screenshots and V recordings go
  bool realtime = true;            ///< pace frames at the level's frame rate
  /// Keep the work time of every frame (tickWorkMs), for `play --timing`.
  bool timing = false;
  double reloadInterval = 0.25;  ///< s between checks of the level files for changes
  ViewOptions view;              ///< the overlays shown at start
  /// "HOST:PORT" (UDP) or "file:PATH" (a touchlib XML recording): every stepped frame's contacts
  /// also go out as TUIO (run/tuio_output.h); "" sends nothing.
  std::string tuioOut;
  bool tuioCursors = false;  ///< with tuioOut, also TUIO 1.1 /tuio/2Dcur cursors
};

/// The app. Only one may be open at a time (SDL and Dear ImGui keep process-wide state).
class App {
 public:
  App();
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  /// Opens the window with a software renderer and starts the level. Errors say why: no display
  /// (SDL's message), a bad level file (file:line:col: message), a bad --set, a bad input spec,
  /// a TUIO output that cannot be opened.
  MaybeError Open(const AppOptions& options);

  /// One frame: events, queued requests, the level file check, one pipeline step (unless
  /// paused), drawing, the UI and presenting. False once the window is closed or Escape pressed.
  bool Tick();

  // Requests, applied at the start of the next Tick (the keys and the panel queue the same).
  void RequestPause(bool paused);
  void RequestStep();
  void RequestRestart();
  void RequestReload();
  void RequestNextLevel();
  void RequestFullscreen(bool fullscreen);
  /// Writes the presented window (drawing and UI) to a PNG at the next Tick; "" picks
  /// outDir/<level>_<frame>.png. The outcome is in screenshotStatus() after that Tick.
  void RequestScreenshot(const std::string& path = "");
  /// Adopts these parameters at the next Tick (what a finished panel edit does): the running
  /// simulation takes the live ones in place and keeps its state (Simulation::Retune); a change
  /// only a new run can make restarts the level with all of them. Values out of range keep the
  /// running parameters and set runError(). tuneStatus() says which of the three happened.
  void RequestParams(const LevelParams& params);
  /// What the last parameter change did: "applied live: tracking.max_distance", "restarted:
  /// physics.layers cannot change on a running simulation" or "rejected: <error>"; "" before
  /// any change.
  const std::string& tuneStatus() const;
  /// The parameters that differ from the level file's, as TOML tables (what "Copy as TOML" puts
  /// on the clipboard); a comment line when none differ.
  std::string ChangedParamsToml() const;
  /// Starts or stops recording the raw input frames (lossless .mkv) and the run's trace.
  void RequestRecording(bool on);

  /// The running simulation.
  const Simulation& simulation() const;
  /// The loaded level, with the --set overrides.
  const Level& level() const;
  /// The table-to-window-pixel map in use.
  const DisplayMap& displayMap() const;
  /// The drawing of the last frame (BGR, window pixels), without the UI.
  const cv::Mat& picture() const;
  /// What drew it: where the table drawing lies in the picture (TableView::tableRect).
  const TableView& tableView() const;
  /// The last reload's or start's error (file:line:col: message), "" when the level loaded.
  const std::string& loadError() const;
  /// The input's or the pipeline's last error (a lost camera, a rejected frame), "" when none.
  const std::string& runError() const;
  /// True while a camera or video source delivers nothing (the app retries every second).
  bool noInput() const;
  /// The last screenshot's path, or its error.
  const Result<std::string>& screenshotStatus() const;
  /// With AppOptions::timing, the wall time of each Tick's work (events, the pipeline step,
  /// drawing and presenting; not the wait that paces the loop), ms.
  const std::vector<double>& tickWorkMs() const;
  /// What drives the pipeline now.
  InputKind input() const;
  bool paused() const;
  bool recording() const;
  /// SDL's id of the window, for events injected in tests.
  uint32_t windowId() const;
  /// Where the last recording went (its folder), "" before any.
  const std::string& recordingDir() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pg
