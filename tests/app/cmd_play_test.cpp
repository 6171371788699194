// `proxygrasp play` as a user runs it: in a window on a private X server for a number of frames
// with a screenshot, and with no display at all (headless video and PNG).
#include "pixels.h"
#include "run_command.h"
#include "test_paths.h"
#include "xvfb.h"

#include "proxygrasp/app/table_view.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/touchlib_xml.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>

namespace pg {
namespace {

const std::string kLevel = std::string(pg::test::TestDataDir()) + "/box_goal.toml";
constexpr int kColorTolerance = 12;  // per channel; antialiased edges blend, interiors are exact

// runs proxygrasp through env(1) with these environment changes ("-u NAME", "NAME=value")
test::CommandResult RunWithEnv(const std::string& env, const std::string& args) {
  test::CommandResult result;
  const std::string command = "env " + env + " " + pg::test::ProxygraspBin() + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof(buffer), pipe)) > 0;) result.output.append(buffer, n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string TempDir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("pg_play_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::create_directories(dir);
  return dir.string();
}

TEST(PlayCommand, TimingReportsTheFramesAfterTheFirstSecondAgainstTheFramePeriod) {
  // box_goal runs at 60 frames/s: of 90 frames, the first 60 (one second) are not timed, and the
  // line compares the other 30 with 1000 / 60 = 16.7 ms and says what they carried
  if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
  test::Xvfb xvfb;
  ASSERT_TRUE(xvfb.Start());
  const std::string dir = TempDir("timing");
  auto playTimed = [&](int frames) {
    return RunWithEnv("-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=" + xvfb.display(),
                      "play " + kLevel + " --input script --frames " + std::to_string(frames) +
                          " --timing --size 640x480 --out " + dir);
  };
  const test::CommandResult r = playTimed(90);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("timing: 30 frames after the first 60, work per frame median "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(" over the 16.7 ms of a frame at 60 Hz"), std::string::npos) << r.output;
  // the level's one scripted fingertip is down in every frame
  EXPECT_NE(r.output.find("; per frame 1.00 contacts, "), std::string::npos) << r.output;

  // too few frames to time says so
  const test::CommandResult few = playTimed(20);
  ASSERT_EQ(few.exitCode, 0) << few.output;
  EXPECT_NE(few.output.find("timing: 20 frames, too few to time (the first 60 are skipped)"),
            std::string::npos)
      << few.output;
}

TEST(PlayCommand, ScreenshotShowsObjectsParticlesAndTheGoal) {
  if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
  test::Xvfb xvfb;
  ASSERT_TRUE(xvfb.Start());
  const std::string dir = TempDir("shot");
  const std::string shot = dir + "/shot.png";
  constexpr int kFrames = 30;
  const test::CommandResult r =
      RunWithEnv("-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=" + xvfb.display(),
                 "play " + kLevel + " --input script --frames " + std::to_string(kFrames) +
                     " --screenshot " + shot + " --size 800x600 --out " + dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("screenshot: " + shot), std::string::npos) << r.output;

  const cv::Mat picture = cv::imread(shot);
  ASSERT_FALSE(picture.empty());
  ASSERT_EQ(picture.size(), cv::Size(800, 600));
  Result<Level> level = LoadLevel(kLevel);
  ASSERT_TRUE(level.ok());
  const DisplayMap map = DisplayMap::Fit(level.value().params.table, picture.size());
  const double ppcm = map.PixelsPerCm({30, 23});

  // the box, untouched, where the level puts it: 6 x 6 cm at (30, 23)
  const test::ColorPixels box = test::FindColor(picture, view_colors::Object(0), kColorTolerance);
  EXPECT_GT(box.count, 0.9 * 36 * ppcm * ppcm);
  EXPECT_LT(box.count, 1.02 * 36 * ppcm * ppcm);
  const Vec2 boxAt = map.ToTable(box.centroid - cv::Point2d(0.5, 0.5));
  // 0.15 cm is 2 px here: more than the outline and the turn tick move the centroid
  EXPECT_NEAR(boxAt.x(), 30.0, 0.15);
  EXPECT_NEAR(boxAt.y(), 23.0, 0.15);

  // the fingertip's particles: a ring about the scripted position at the last frame's time,
  // x = 10 + 5 cm/s * (kFrames - 1) / 60 s, y = 10
  const test::ColorPixels particles =
      test::FindColor(picture, view_colors::Layer(0), kColorTolerance);
  ASSERT_GT(particles.count, 20);
  const Vec2 fingerAt = map.ToTable(particles.centroid - cv::Point2d(0.5, 0.5));
  const double fingerX = 10.0 + 5.0 * (kFrames - 1) / 60.0;
  // an evenly sampled ring's centroid is its centre; noise and a frame's motion stay within 0.3
  EXPECT_NEAR(fingerAt.x(), fingerX, 0.3);
  EXPECT_NEAR(fingerAt.y(), 10.0, 0.3);

  // the goal zone's outline, [45, 55] x [30, 40] cm
  const test::ColorPixels goal = test::FindColor(picture, view_colors::kGoal, kColorTolerance);
  const cv::Point2d lo = map.ToDisplay({45, 30});
  const cv::Point2d hi = map.ToDisplay({55, 40});
  EXPECT_NEAR(goal.bounds.x, lo.x, 2.5);
  EXPECT_NEAR(goal.bounds.x + goal.bounds.width, hi.x, 2.5);
  EXPECT_NEAR(goal.bounds.y, hi.y, 2.5);
  EXPECT_NEAR(goal.bounds.y + goal.bounds.height, lo.y, 2.5);
  EXPECT_GT(goal.count, 4 * 10 * ppcm);

  std::filesystem::remove_all(dir);
}

TEST(PlayCommand, ShowSensingShowsTheFilterStagesInTheWindow) {
  if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
  test::Xvfb xvfb;
  ASSERT_TRUE(xvfb.Start());
  const std::string dir = TempDir("sensing");
  // the same frames with and without the sensing view
  cv::Mat shots[2];
  for (int i = 0; i < 2; ++i) {
    const std::string shot = dir + "/shot" + std::to_string(i) + ".png";
    const test::CommandResult r =
        RunWithEnv("-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=" + xvfb.display(),
                   "play " + kLevel + " --input script --frames 10 --screenshot " + shot +
                       " --size 800x600 --out " + dir + (i == 1 ? " --show sensing" : ""));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    shots[i] = cv::imread(shot);
    ASSERT_EQ(shots[i].size(), cv::Size(800, 600)) << shot;
  }
  // the box (its top slice's full colour) is drawn full size without, in a tile a third as wide
  // (a ninth of the area) with the view on
  const int plain = test::FindColor(shots[0], view_colors::Object(0), kColorTolerance).count;
  const int tiled = test::FindColor(shots[1], view_colors::Object(0), kColorTolerance).count;
  EXPECT_GT(plain, 0);
  EXPECT_GT(tiled, 0);
  EXPECT_LT(tiled, plain / 4);
  // the stages' grey images fill the window where the table drawing was
  EXPECT_GT(cv::norm(shots[0], shots[1], cv::NORM_L1), 0.0);
  std::filesystem::remove_all(dir);
}

TEST(PlayCommand, WithoutADisplayWritesAVideoAndAPng) {
  const std::string dir = TempDir("headless");
  const test::CommandResult r = RunWithEnv("-u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER",
                                           "play " + kLevel + " --frames 12 --out " + dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string video = dir + "/box_goal.mp4";
  const std::string png = dir + "/box_goal.png";
  EXPECT_NE(r.output.find("video: " + video), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("picture: " + png), std::string::npos) << r.output;
  cv::VideoCapture capture(video);
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  for (cv::Mat frame; capture.read(frame);) ++frames;
  EXPECT_EQ(frames, 12);
  EXPECT_FALSE(cv::imread(png).empty());
  std::filesystem::remove_all(dir);
}

TEST(PlayCommand, ABadLevelIsReportedWithItsLocation) {
  const std::string dir = TempDir("bad");
  const std::string path = dir + "/bad.toml";
  {
    FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("[physics]\nsubstep = 4\n", f);
    std::fclose(f);
  }
  const test::CommandResult r = test::RunProxygrasp("play " + path + " --frames 1");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(path + ":2:1:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did you mean 'substeps'"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

// the frames of a recording play wrote with --tuio-out: TUIO 2.0 bundles and, when asked, 2Dcur
void ExpectRecordedFrames(const std::string& path, int frames, bool cursors) {
  SCOPED_TRACE(path);
  Result<std::vector<OscBundle>> bundles = ReadTouchlibXml(path);
  ASSERT_TRUE(bundles.ok()) << bundles.error().Format();
  std::vector<OscBundle> tuio2;
  int cursorBundles = 0;
  for (const OscBundle& b : bundles.value()) {
    if (b.messages.front().address == "/tuio2/frm") {
      tuio2.push_back(b);
      // the time tag is the frame's time in the level, 60 frames a second
      EXPECT_EQ(b.time, OscTimeTag::FromSeconds(b.messages.front().args[0].i / 60.0));
    } else {
      ++cursorBundles;
    }
  }
  EXPECT_EQ(cursorBundles, cursors ? frames : 0);
  const std::vector<TuioFrame> replayed = ReplayTuio(tuio2, TuioParams());
  ASSERT_EQ(static_cast<int>(replayed.size()), frames);
  // the level's one fingertip, new in the first frame and there in every one
  for (int f = 0; f < frames; ++f) {
    ASSERT_EQ(replayed[f].frame, f);
    ASSERT_EQ(replayed[f].contacts.size(), 1u) << "frame " << f;
    EXPECT_EQ(replayed[f].contacts[0].isNew, f == 0);
  }
}

TEST(PlayCommand, TuioOutRecordsEveryFrameInAWindowAndWithoutADisplay) {
  const std::string dir = TempDir("tuio");
  constexpr int kFrames = 12;
  const std::string headless = dir + "/headless.xml";
  test::CommandResult r = RunWithEnv("-u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER",
                                     "play " + kLevel + " --frames " + std::to_string(kFrames) +
                                         " --out " + dir + " --tuio-out file:" + headless);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("tuio out file:" + headless + ": 12 frames, 0 write errors"),
            std::string::npos)
      << r.output;
  ExpectRecordedFrames(headless, kFrames, false);

  if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
  test::Xvfb xvfb;
  ASSERT_TRUE(xvfb.Start());
  const std::string window = dir + "/window.xml";
  r = RunWithEnv("-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=" + xvfb.display(),
                 "play " + kLevel + " --input script --frames " + std::to_string(kFrames) +
                     " --size 800x600 --out " + dir + " --tuio-out file:" + window +
                     " --tuio-cursors");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("tuio out file:" + window + ": 12 frames, 0 write errors"),
            std::string::npos)
      << r.output;
  ExpectRecordedFrames(window, kFrames, true);
  std::filesystem::remove_all(dir);
}

TEST(PlayCommand, ABadTuioOutIsReportedNamingTheOption) {
  const std::string args = "play " + kLevel + " --frames 1 --tuio-out nohost";
  const std::string message = "--tuio-out nohost: TUIO output must be HOST:PORT or file:PATH";
  test::CommandResult r = RunWithEnv("-u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER", args);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << r.output;

  if (!std::filesystem::exists(test::kXvfb)) GTEST_SKIP() << "Xvfb is not installed";
  test::Xvfb xvfb;
  ASSERT_TRUE(xvfb.Start());
  r = RunWithEnv("-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=" + xvfb.display(),
                 args + " --input script");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
}

TEST(RunCommand, VideoOptionDrawsTheRun) {
  const std::string dir = TempDir("run");
  const test::CommandResult r = test::RunProxygrasp("run " + kLevel + " --frames 6 --video " + dir +
                                                    "/out.mp4 --png " + dir + "/out.png");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("video: " + dir + "/out.mp4"), std::string::npos) << r.output;
  cv::VideoCapture capture(dir + "/out.mp4");
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  for (cv::Mat frame; capture.read(frame);) ++frames;
  EXPECT_EQ(frames, 6);
  EXPECT_FALSE(cv::imread(dir + "/out.png").empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pg
