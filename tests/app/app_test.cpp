// The app in a real window on a private X server: injected mouse events grasp and move a box, and
// edits of the level file reload it (a broken edit keeps the running level and shows the error).
#include "proxygrasp/app/app.h"

#include "pixels.h"
#include "test_paths.h"
#include "xvfb.h"

#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/preview.h"

#include <SDL.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pg {
namespace {

const std::string kTestData = pg::test::TestDataDir();

class AppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
    ASSERT_TRUE(m_xvfb.Start()) << "Xvfb did not start";
    setenv("DISPLAY", m_xvfb.display().c_str(), 1);
    unsetenv("WAYLAND_DISPLAY");
    unsetenv("SDL_VIDEODRIVER");
  }

  // what a test's app wrote (recordings, screenshots) goes with the test
  void TearDown() override { std::filesystem::remove_all(OutDir()); }

  static std::string OutDir() {
    return (std::filesystem::temp_directory_path() / ("pg_app_out_" + std::to_string(getpid())))
        .string();
  }

  AppOptions Options(const std::string& level, const std::string& input) {
    AppOptions options;
    options.level = level;
    options.input = input;
    options.windowSize = {800, 600};
    options.realtime = false;
    options.reloadInterval = 0.0;  // look at the file every frame
    options.outDir = OutDir();
    return options;
  }

  test::Xvfb m_xvfb;
};

// SDL events as a mouse would send them to the app's window
void PushButton(const App& app, Uint32 type, Uint8 button, cv::Point at) {
  SDL_Event e{};
  e.type = type;
  e.button.windowID = app.windowId();
  e.button.which = 0;
  e.button.button = button;
  e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
  e.button.clicks = 1;
  e.button.x = at.x;
  e.button.y = at.y;
  ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
}

void PushMotion(const App& app, cv::Point at, Uint32 buttons) {
  SDL_Event e{};
  e.type = SDL_MOUSEMOTION;
  e.motion.windowID = app.windowId();
  e.motion.which = 0;
  e.motion.state = buttons;
  e.motion.x = at.x;
  e.motion.y = at.y;
  ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
}

void PushWheel(const App& app, int notches) {
  SDL_Event e{};
  e.type = SDL_MOUSEWHEEL;
  e.wheel.windowID = app.windowId();
  e.wheel.which = 0;
  e.wheel.y = notches;
  e.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
  ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
}

ObjectState Box(const App& app) {
  return app.simulation().world().Object(0);
}

TEST_F(AppTest, MousePinchGraspsAndDragMovesTheBox) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_only.toml", "mouse")));
  ASSERT_EQ(app.input(), InputKind::kMouse);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(app.Tick());
  const Vec2 start = Box(app).pose.pos;
  const DisplayMap& map = app.displayMap();
  const cv::Point centre(map.ToDisplay(start));

  // open the pinch to 10 cm (4 notches of 0.5 cm from 8) and put it down around the 6 cm box
  PushWheel(app, 4);
  PushButton(app, SDL_MOUSEBUTTONDOWN, SDL_BUTTON_RIGHT, centre);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().shapes().size(), 2u);
  EXPECT_EQ(app.simulation().stats().contacts, 2);
  // the box has not moved yet: the fingertips are 1.2 cm clear of its sides
  EXPECT_NEAR(Box(app).pose.pos.x(), start.x(), 0.05);

  // squeeze: close to 5.5 cm, a notch a frame, the fingertips press into the sides
  for (int i = 0; i < 9; ++i) {
    PushWheel(app, -1);
    ASSERT_TRUE(app.Tick());
  }
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(app.Tick());
  const Vec2 squeezed = Box(app).pose.pos;
  // squeezing from both sides does not push it away (the two sides balance)
  EXPECT_NEAR(squeezed.x(), start.x(), 1.0);

  // drag 8 cm to the right over a second, then hold still
  const cv::Point target(map.ToDisplay(start + Vec2(8, 0)));
  constexpr int kSteps = 60;
  int heldFrames = 0;
  for (int i = 1; i <= kSteps; ++i) {
    PushMotion(app, centre + (target - centre) * i / kSteps, SDL_BUTTON_RMASK);
    ASSERT_TRUE(app.Tick());
    heldFrames += Box(app).held ? 1 : 0;
  }
  // the physics calls it held (opposing contacts, not slipping) through nearly all of the drag
  EXPECT_GE(heldFrames, 50) << "of " << kSteps;
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(app.Tick());
  const Vec2 moved = Box(app).pose.pos;
  // the held box follows the pinch through the 8 cm drag; 2 cm of slack for slipping while the
  // drag starts, and no more than the drag plus the squeeze's 1 cm give
  EXPECT_GT(moved.x() - start.x(), 6.0) << "box at " << moved.transpose();
  EXPECT_LT(moved.x() - start.x(), 9.0) << "box at " << moved.transpose();
  EXPECT_NEAR(moved.y(), start.y(), 1.5);

  // releasing lifts both fingertips
  PushButton(app, SDL_MOUSEBUTTONUP, SDL_BUTTON_RIGHT, target);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_TRUE(app.simulation().shapes().empty());
}

TEST_F(AppTest, LeftDragPushesTheBox) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_only.toml", "mouse")));
  const DisplayMap& map = app.displayMap();
  const cv::Point from(map.ToDisplay({20, 23}));
  const cv::Point to(map.ToDisplay({32, 23}));
  PushButton(app, SDL_MOUSEBUTTONDOWN, SDL_BUTTON_LEFT, from);
  constexpr int kSteps = 60;
  for (int i = 1; i <= kSteps; ++i) {
    PushMotion(app, from + (to - from) * i / kSteps, SDL_BUTTON_LMASK);
    ASSERT_TRUE(app.Tick());
  }
  // the fingertip ends 2 cm into where the box started (side at 27 cm): pushed by about that
  EXPECT_GT(Box(app).pose.pos.x() - 30.0, 2.0) << Box(app).pose.pos.transpose();
}

TEST_F(AppTest, TouchFingersAreFingertips) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_only.toml", "touch")));
  ASSERT_EQ(app.input(), InputKind::kTouch);
  ASSERT_TRUE(app.Tick());
  const cv::Point2d at = app.displayMap().ToDisplay({12, 30});
  const cv::Size size = app.picture().size();
  // touch positions are fractions of the window
  SDL_Event e{};
  e.type = SDL_FINGERDOWN;
  e.tfinger.touchId = 1;
  e.tfinger.fingerId = 5;
  e.tfinger.x = static_cast<float>(at.x / size.width);
  e.tfinger.y = static_cast<float>(at.y / size.height);
  e.tfinger.pressure = 1.0f;
  ASSERT_EQ(SDL_PushEvent(&e), 1);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  ASSERT_EQ(app.simulation().shapes().size(), 1u);
  // a float's precision of a window fraction: well under a pixel (0.06 cm here)
  EXPECT_NEAR(app.simulation().shapes()[0].pose.pos.x(), 12.0, 0.06);
  EXPECT_NEAR(app.simulation().shapes()[0].pose.pos.y(), 30.0, 0.06);
  EXPECT_EQ(app.simulation().stats().contacts, 1);
  e.type = SDL_FINGERUP;
  ASSERT_EQ(SDL_PushEvent(&e), 1);
  ASSERT_TRUE(app.Tick());
  EXPECT_TRUE(app.simulation().shapes().empty());
}

TEST_F(AppTest, InTheSensingViewTheMouseActsWhereTheSmallTableShowsIt) {
  AppOptions options = Options(kTestData + "/box_only.toml", "mouse");
  options.view.sensing = true;
  App app;
  ASSERT_FALSE(app.Open(options));
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  const cv::Rect table = app.tableView().tableRect();
  const cv::Size size = app.picture().size();
  ASSERT_LT(table.width, size.width / 2);  // the table drawing is one tile of the grid
  // where the small table shows (12, 30) cm
  const cv::Point2d full = app.displayMap().ToDisplay({12, 30});
  const cv::Point at(static_cast<int>(table.x + full.x * table.width / size.width),
                     static_cast<int>(table.y + full.y * table.height / size.height));
  PushButton(app, SDL_MOUSEBUTTONDOWN, SDL_BUTTON_LEFT, at);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  ASSERT_EQ(app.simulation().shapes().size(), 1u);
  // a window pixel there is size.width / table.width drawing pixels: the pixel the press rounds
  // to is within that many drawing pixels, over the map's pixels per cm
  const double cm =
      static_cast<double>(size.width) / table.width / app.displayMap().PixelsPerCm({12, 30});
  EXPECT_NEAR(app.simulation().shapes()[0].pose.pos.x(), 12.0, cm);
  EXPECT_NEAR(app.simulation().shapes()[0].pose.pos.y(), 30.0, cm);
  PushButton(app, SDL_MOUSEBUTTONUP, SDL_BUTTON_LEFT, at);
  ASSERT_TRUE(app.Tick());
  EXPECT_TRUE(app.simulation().shapes().empty());
}

TEST_F(AppTest, ReloadsAValidEditAndKeepsTheLevelOnABrokenOne) {
  // a copy of the level to edit
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("pg_app_reload_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "level.toml").string();
  std::string text;
  {
    std::ifstream in(kTestData + "/box_goal.toml");
    std::stringstream buffer;
    buffer << in.rdbuf();
    text = buffer.str();
  }
  {
    std::ofstream out(path);
    out << text;
  }

  App app;
  ASSERT_FALSE(app.Open(Options(path, "script")));
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_NEAR(Box(app).pose.pos.x(), 30.0, 0.05);

  // a valid edit: the box starts elsewhere
  const size_t at = text.find("pos = [30, 23]");
  ASSERT_NE(at, std::string::npos);
  std::string moved = text;
  moved.replace(at, 14, "pos = [15, 35]");
  {
    std::ofstream out(path);
    out << moved;
  }
  bool reloaded = false;
  for (int i = 0; i < 200 && !reloaded; ++i) {
    ASSERT_TRUE(app.Tick());
    reloaded = std::abs(Box(app).pose.pos.x() - 15.0) < 0.05;
  }
  ASSERT_TRUE(reloaded) << "the edit did not take effect";
  EXPECT_NEAR(Box(app).pose.pos.y(), 35.0, 0.05);
  EXPECT_EQ(app.loadError(), "");

  // a broken edit: a string where a number belongs, on line 15
  std::string broken = moved;
  const size_t mass = broken.find("mass = 100");
  ASSERT_NE(mass, std::string::npos);
  broken.replace(mass, 10, "mass = \"heavy\"");
  {
    std::ofstream out(path);
    out << broken;
  }
  for (int i = 0; i < 200 && app.loadError().empty(); ++i) ASSERT_TRUE(app.Tick());
  ASSERT_NE(app.loadError(), "");
  // file:line:col: message
  EXPECT_NE(app.loadError().find(path + ":15:"), std::string::npos) << app.loadError();
  EXPECT_NE(app.loadError().find("mass"), std::string::npos) << app.loadError();
  // the old level keeps running
  const int64_t frame = app.simulation().Frame();
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), frame + 5);
  EXPECT_NEAR(Box(app).pose.pos.x(), 15.0, 0.05);
  EXPECT_DOUBLE_EQ(app.level().objects[0].mass, 100.0);
  // and the error is on the picture, in red
  EXPECT_GT(test::FindColor(app.picture(), view_colors::kError, 30).count, 100);

  // fixing the file clears the error
  {
    std::ofstream out(path);
    out << moved;
  }
  for (int i = 0; i < 200 && !app.loadError().empty(); ++i) ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.loadError(), "");
  std::filesystem::remove_all(dir);
}

TEST_F(AppTest, KeysQueueRequestsAppliedBetweenFrames) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "script")));
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), 3);
  // pause: frames stop; single step: exactly one more
  app.RequestPause(true);
  ASSERT_TRUE(app.Tick());
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), 3);
  app.RequestStep();
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), 4);
  EXPECT_TRUE(app.paused());
  // restart: from frame 0
  app.RequestRestart();
  app.RequestPause(false);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), 1);

  // a screenshot of the window
  const std::string shot = (std::filesystem::temp_directory_path() /
                            ("pg_app_shot_" + std::to_string(getpid()) + ".png"))
                               .string();
  app.RequestScreenshot(shot);
  ASSERT_TRUE(app.Tick());
  ASSERT_TRUE(app.screenshotStatus().ok()) << app.screenshotStatus().error().Format();
  EXPECT_TRUE(std::filesystem::exists(shot));
  std::filesystem::remove(shot);

  // Escape closes the window
  SDL_Event e{};
  e.type = SDL_KEYDOWN;
  e.key.windowID = app.windowId();
  e.key.state = SDL_PRESSED;
  e.key.keysym.sym = SDLK_ESCAPE;
  e.key.keysym.scancode = SDL_SCANCODE_ESCAPE;
  ASSERT_EQ(SDL_PushEvent(&e), 1);
  EXPECT_FALSE(app.Tick());
}

// a key press as the keyboard sends it to the app's window
void PushKey(const App& app, SDL_Keycode key, SDL_Scancode scancode) {
  SDL_Event e{};
  e.type = SDL_KEYDOWN;
  e.key.windowID = app.windowId();
  e.key.state = SDL_PRESSED;
  e.key.keysym.sym = key;
  e.key.keysym.scancode = scancode;
  ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
}

TEST_F(AppTest, KeyIShowsTheSensingViewAndHidesItAgain) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "script")));
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  // the box's top colour: drawn full size, then in the sensing view's first tile (a third of the
  // window's width, so about a ninth of the pixels), then full size again
  const auto boxPixels = [&] {
    return test::FindColor(app.picture(), view_colors::Object(0), 12).count;
  };
  const int plain = boxPixels();
  ASSERT_GT(plain, 0);
  PushKey(app, SDLK_i, SDL_SCANCODE_I);
  ASSERT_TRUE(app.Tick());
  const int tiled = boxPixels();
  EXPECT_GT(tiled, 0);
  EXPECT_LT(tiled, plain / 4);
  PushKey(app, SDLK_i, SDL_SCANCODE_I);
  ASSERT_TRUE(app.Tick());
  EXPECT_GT(boxPixels(), plain / 2);
}

TEST_F(AppTest, LiveParameterChangesKeepTheRunningLevel) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "script")));
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(app.Tick());
  ASSERT_EQ(app.simulation().stats().contacts, 1);
  // paused, so that the change is the only thing that happens in the next Tick
  app.RequestPause(true);
  ASSERT_TRUE(app.Tick());
  const int64_t frame = app.simulation().Frame();
  const uint64_t world = app.simulation().world().StateHash();
  const int particles = app.simulation().stats().particles;
  ASSERT_GT(particles, 5);

  // a fixed threshold above the fingertip's brightness (the adaptive level would take 0.3 of
  // its contrast, under this ceiling), and a tracking distance
  LevelParams params = app.simulation().params();
  params.sensing.thresholdMode = ThresholdMode::kFixed;
  params.sensing.threshold = 200.0;
  params.tracking.maxDistance = 1.5;
  params.tracking.keepLost = 0;  // an unseen contact is lifted at once
  app.RequestParams(params);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.tuneStatus(),
            "applied live: sensing.threshold_mode, sensing.threshold, tracking.max_distance, "
            "tracking.keep_lost");
  EXPECT_EQ(app.runError(), "");
  // the run was not restarted: same frame, the world bit for bit as it was
  EXPECT_EQ(app.simulation().Frame(), frame);
  EXPECT_EQ(app.simulation().world().StateHash(), world);
  EXPECT_EQ(app.simulation().params().sensing.threshold, 200.0);
  EXPECT_EQ(app.simulation().params().tracking.maxDistance, 1.5);
  const std::string toml = app.ChangedParamsToml();
  EXPECT_NE(toml.find("[sensing]\nthreshold_mode = \"fixed\"\nthreshold = 200\n"),
            std::string::npos)
      << toml;

  // and the running pipeline uses it: the fingertip is no longer seen, its particles end
  app.RequestPause(false);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), frame + 1);
  EXPECT_EQ(app.simulation().stats().contacts, 0);
  EXPECT_EQ(app.simulation().stats().deleted, particles);
}

TEST_F(AppTest, ChangesARunningLevelCannotTakeRestartItAndBadValuesAreRejected) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "script")));
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_NE(app.ChangedParamsToml().find("# no parameter differs"), std::string::npos);

  // the layer count shapes the physics world: the run restarts with every change
  LevelParams params = app.simulation().params();
  params.physics.layers = 6;
  params.proxies.mode = ProxyMode::kInstant;
  app.RequestParams(params);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), 1);
  EXPECT_EQ(app.tuneStatus(), "restarted: physics.layers cannot change on a running simulation");
  EXPECT_EQ(app.simulation().params().physics.layers, 6);
  EXPECT_EQ(app.simulation().params().proxies.mode, ProxyMode::kInstant);
  const std::string toml = app.ChangedParamsToml();
  EXPECT_NE(toml.find("[physics]\nlayers = 6\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("[proxies]\nmode = \"instant\"\n"), std::string::npos) << toml;
  // only what changed
  EXPECT_EQ(toml.find("frame_rate"), std::string::npos) << toml;

  // more than 16 layers is out of range: the running parameters and run stay
  LevelParams bad = app.simulation().params();
  bad.physics.layers = 40;
  bad.tracking.maxDistance = 2.0;
  app.RequestParams(bad);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().params().physics.layers, 6);  // the restart above set 6
  EXPECT_EQ(app.simulation().params().tracking.maxDistance, 4.0);
  EXPECT_EQ(app.simulation().Frame(), 2);
  EXPECT_EQ(app.runError(), "physics.layers must be in [1, 16] (got 40)");
  EXPECT_EQ(app.tuneStatus(), "rejected: physics.layers must be in [1, 16] (got 40)");
}

TEST_F(AppTest, ACalibrationNamedInThePanelBringsItsTunedSensingValues) {
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "script")));
  ASSERT_TRUE(app.Tick());
  // a calibration for the synthetic camera (640x480) whose tuned values raise the gain
  Calibration c = LinearCalibration({640, 480}, app.simulation().params().table);
  c.sensing = {{"gain", "2.5"}, {"threshold", "45"}};
  const std::string path = OutDir() + "/tuned.yaml";
  std::filesystem::create_directories(OutDir());
  ASSERT_FALSE(SaveCalibration(path, c));
  LevelParams params = app.simulation().params();
  params.sensing.calibration = path;
  params.tracking.maxDistance = 3.0;  // an edit of another key at the same time stays
  app.RequestParams(params);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.runError(), "");
  EXPECT_EQ(app.simulation().params().sensing.gain, 2.5);
  EXPECT_EQ(app.simulation().params().sensing.threshold, 45.0);
  EXPECT_EQ(app.simulation().params().tracking.maxDistance, 3.0);
  // a calibration with a bad tuned key is rejected and the running values stay
  c.sensing = {{"gian", "2"}};
  const std::string bad = OutDir() + "/bad.yaml";
  ASSERT_FALSE(SaveCalibration(bad, c));
  params = app.simulation().params();
  params.sensing.calibration = bad;
  app.RequestParams(params);
  ASSERT_TRUE(app.Tick());
  EXPECT_NE(app.runError().find("bad.yaml: field 'sensing.gian'"), std::string::npos)
      << app.runError();
  EXPECT_EQ(app.simulation().params().sensing.calibration, path);
}

TEST_F(AppTest, RecordsInputAndTrace) {
  App app;
  const AppOptions options = Options(kTestData + "/box_goal.toml", "script");
  ASSERT_FALSE(app.Open(options));
  app.RequestRecording(true);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(app.Tick());
  ASSERT_TRUE(app.recording());
  app.RequestRecording(false);
  ASSERT_TRUE(app.Tick());
  EXPECT_FALSE(app.recording());
  const std::string dir = app.recordingDir();
  ASSERT_FALSE(dir.empty());
  EXPECT_TRUE(std::filesystem::exists(dir + "/input.mkv"));
  // header plus one row per recorded frame: the stop applies before the next frame
  std::ifstream frames(dir + "/frames.csv");
  int lines = 0;
  for (std::string line; std::getline(frames, line);) ++lines;
  EXPECT_EQ(lines, 1 + 10);
}

TEST_F(AppTest, ReplaysARecordingThroughThePipeline) {
  // record 20 frames of the script, then play them back as a video input
  AppOptions options = Options(kTestData + "/box_goal.toml", "script");
  std::string dir;
  {
    App app;
    ASSERT_FALSE(app.Open(options));
    app.RequestRecording(true);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(app.Tick());
    app.RequestRecording(false);
    ASSERT_TRUE(app.Tick());
    dir = app.recordingDir();
  }
  options.input = "video:" + dir + "/input.mkv";
  App replay;
  ASSERT_FALSE(replay.Open(options));
  EXPECT_EQ(replay.input(), InputKind::kVideo);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(replay.Tick());
  // the recorded fingertip is sensed again: one contact, with particles
  EXPECT_EQ(replay.simulation().Frame(), 10);
  EXPECT_EQ(replay.simulation().stats().contacts, 1);
  EXPECT_GT(replay.simulation().stats().particles, 5);
  EXPECT_EQ(replay.runError(), "");
  std::filesystem::remove_all(options.outDir);
}

TEST_F(AppTest, AMissingCameraShowsNoInputAndKeepsRunning) {
  App app;
  // no camera 9 on any test machine: the app opens anyway and retries
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "camera:9")));
  EXPECT_EQ(app.input(), InputKind::kCamera);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_TRUE(app.noInput());
  EXPECT_NE(app.runError().find("camera"), std::string::npos) << app.runError();
  EXPECT_EQ(app.simulation().Frame(), 0);
  // the picture still shows the level and the error
  EXPECT_GT(test::FindColor(app.picture(), view_colors::Object(0), 12).count, 1000);
  EXPECT_GT(test::FindColor(app.picture(), view_colors::kError, 30).count, 50);
}

TEST_F(AppTest, TheSensingViewShowsTheDepthChainAndTheBandTunesLive) {
  // a depth recording (16-bit PNGs, mm): a table 1000 mm away for the 15 frames of the surface,
  // then 15 frames of a fingertip (a disk of 12 px, about 4 cm^2 of the 61 x 46 cm table mapped
  // linearly from 640x480) 14 mm up at pixel (200, 240), in the touch band (about 6 to 20 mm:
  // DepthSensor's tests), and a hole (no reading) over x 500-539, y 100-129
  const std::string dir = OutDir() + "/depth_in";
  std::filesystem::create_directories(dir);
  for (int i = 0; i < 30; ++i) {
    cv::Mat mm(480, 640, CV_16UC1, cv::Scalar(1000));
    if (i >= 15) {
      cv::circle(mm, {200, 240}, 12, cv::Scalar(986), cv::FILLED);
      mm(cv::Rect(500, 100, 40, 30)).setTo(0);
    }
    char name[32];
    std::snprintf(name, sizeof name, "/d%02d.png", i);
    ASSERT_TRUE(cv::imwrite(dir + name, mm));
  }
  AppOptions options = Options(kTestData + "/box_goal.toml", "depth:" + dir);
  options.view.sensing = true;
  options.view.hud = false;
  App app;
  ASSERT_FALSE(app.Open(options));
  for (int i = 0; i < 18; ++i) ASSERT_TRUE(app.Tick());
  ASSERT_EQ(app.simulation().contours().blobs.size(), 1u);
  ASSERT_TRUE(app.simulation().contours().hover.empty());

  // six tiles without the heads-up lines: the table, then depth, surface, height, touch, hover
  const std::vector<cv::Rect> tiles = SensingTiles(app.picture().size(), {640, 480}, 0, 6);
  ASSERT_EQ(tiles.size(), 6u);
  // pixels of a colour range in a tile's top three quarters (the height tile's legend strip, in
  // the band's and the hover's colours, and the labels lie below them)
  const auto count = [&](int tile, const cv::Scalar& lo, const cv::Scalar& hi) {
    cv::Rect r = tiles[static_cast<size_t>(tile)];
    r.height = r.height * 3 / 4;
    cv::Mat mask;
    cv::inRange(app.picture()(r), lo, hi, mask);
    return cv::countNonZero(mask);
  };
  // band green (blue and red 0, green 140 to 255) in the height tile, magenta where the hole is
  // in the depth tile; the fingertip's 450 px shrink with the tile (about 0.4 of its width) to
  // some 70, the hole's 1200 to some 190: at least a third of each, for the averaged edges
  const cv::Scalar bandLo(0, depth_colors::kBandDarkest, 0), bandHi(0, 255, 0);
  const cv::Scalar hoverLo(255, 0, 0), hoverHi(255, 200, 0);
  EXPECT_GT(count(3, bandLo, bandHi), 20);
  EXPECT_EQ(count(3, hoverLo, hoverHi), 0);
  EXPECT_GT(count(1, cv::Scalar(depth_colors::kNoReading), cv::Scalar(depth_colors::kNoReading)),
            60);

  // touch_high down to 1.2 cm, paused so that the change is all that happens: live, and from the
  // next frame the fingertip (14 mm) is above the band, a hover region (hover_min_area 1 cm^2)
  app.RequestPause(true);
  ASSERT_TRUE(app.Tick());
  const int64_t frame = app.simulation().Frame();
  LevelParams params = app.simulation().params();
  params.depth.touchHigh = 1.2;
  app.RequestParams(params);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.tuneStatus(), "applied live: depth.touch_high");
  EXPECT_EQ(app.simulation().Frame(), frame);
  app.RequestPause(false);
  ASSERT_TRUE(app.Tick());
  EXPECT_EQ(app.simulation().Frame(), frame + 1);
  EXPECT_TRUE(app.simulation().contours().blobs.empty());
  EXPECT_EQ(app.simulation().contours().hover.size(), 1u);
  // the height tile shows it: hover blue (255, 200 t, 0 with t = (14 - 12) / 288, so green 1)
  // where the band's green was
  EXPECT_GT(count(3, hoverLo, cv::Scalar(255, 10, 0)), 20);
  EXPECT_EQ(count(3, bandLo, bandHi), 0);
}

TEST_F(AppTest, DepthInputsMissingDeviceRetriedMissingRecordingRefused) {
  // no Kinect 7 on any test machine: the app opens anyway and retries, as for a camera
  App app;
  ASSERT_FALSE(app.Open(Options(kTestData + "/box_goal.toml", "kinect:7")));
  EXPECT_EQ(app.input(), InputKind::kCamera);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(app.Tick());
  EXPECT_TRUE(app.noInput());
  EXPECT_NE(app.runError().find("kinect:7"), std::string::npos) << app.runError();
  EXPECT_EQ(app.simulation().Frame(), 0);
  // a recording that is not there is an error naming it
  App replay;
  const MaybeError missing = replay.Open(Options(kTestData + "/box_goal.toml", "depth:/no/dir"));
  ASSERT_TRUE(missing);
  EXPECT_NE(missing->Format().find("--input depth:/no/dir: /no/dir: no such folder"),
            std::string::npos)
      << missing->Format();
}

}  // namespace
}  // namespace pg
