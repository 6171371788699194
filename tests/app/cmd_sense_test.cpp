#include "real_data.h"
#include "run_command.h"
#include "test_paths.h"
#include "udp_port.h"

#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/depth_source.h"
#include "proxygrasp/sensing/preview.h"
#include "proxygrasp/sensing/synthetic_camera.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/touchlib_xml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <arpa/inet.h>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <netinet/in.h>
#include <set>
#include <signal.h>
#include <spawn.h>
#include <sstream>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace pg {
namespace {

using test::FreePort;
using test::RunProxygrasp;
using ::testing::HasSubstr;
using ::testing::Not;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

int Count(const std::string& s, const std::string& what) {
  int n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// the first contact's centroid in a JSON line (no std::regex: GCC 12 warns inside it under ASan)
Vec2 Centroid(const std::string& line) {
  const std::string key = "\"centroid\": [";
  const size_t at = line.find(key);
  if (at == std::string::npos) return Vec2(-1e9, -1e9);
  const char* p = line.c_str() + at + key.size();
  char* end = nullptr;
  const double x = std::strtod(p, &end);
  const double y = std::strtod(end + 1, &end);
  return Vec2(x, y);
}

// true when text at `pos` is a number written with exactly four decimals, e.g. 12.3456
bool FourDecimals(const std::string& text, size_t pos) {
  size_t i = pos;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
  if (i == pos || i >= text.size() || text[i] != '.') return false;
  size_t digits = 0;
  for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) ++digits;
  return digits == 4;
}

TEST(SenseCommand, SyntheticFingersPrintOneJsonObjectPerFrame) {
  const auto r = RunProxygrasp("sense synthetic:fingers --frames 9");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::vector<std::string> lines = Lines(r.output);
  ASSERT_EQ(lines.size(), 9u) << r.output.substr(0, 500);
  // the demo starts with a clear table for five frames, then ten fingertips touch down together
  for (int i = 0; i < 9; ++i) {
    EXPECT_EQ(lines[i].rfind("{\"frame\": " + std::to_string(i) + ", \"contacts\": [", 0), 0u)
        << lines[i].substr(0, 80);
    EXPECT_EQ(lines[i].back(), '}');
  }
  EXPECT_EQ(lines[4], "{\"frame\": 4, \"contacts\": [], \"merges\": 0, \"splits\": 0}");
  EXPECT_EQ(Count(lines[5], "\"state\": \"new\""), 10);
  EXPECT_EQ(Count(lines[8], "\"state\": \"continuing\""), 10);
  EXPECT_EQ(Count(lines[8], "\"id\": "), 10);
  // ids 1..10, numbers with four decimals, contours as [[x, y], ...]
  EXPECT_THAT(lines[8], HasSubstr("\"id\": 10,"));
  EXPECT_THAT(lines[8], Not(HasSubstr("\"id\": 11,")));
  const std::string& l = lines[8];
  const size_t centroid = l.find("\"centroid\": [");
  ASSERT_NE(centroid, std::string::npos);
  EXPECT_TRUE(FourDecimals(l, centroid + 13)) << l.substr(centroid, 40);
  const size_t area = l.find("\"area\": ");
  ASSERT_NE(area, std::string::npos);
  EXPECT_TRUE(FourDecimals(l, area + 8)) << l.substr(area, 20);
  const size_t contour = l.find("\"contour\": [[");
  ASSERT_NE(contour, std::string::npos);
  EXPECT_TRUE(FourDecimals(l, contour + 13)) << l.substr(contour, 40);
}

TEST(SenseCommand, SyntheticHandsAreTwoContacts) {
  const auto r = RunProxygrasp("sense synthetic:hands --frames 7");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::vector<std::string> lines = Lines(r.output);
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(Count(lines[6], "\"state\": \"continuing\""), 2);
}

TEST(SenseCommand, FolderOfImagesAndCalibrationFile) {
  // frames rendered by the synthetic camera with lens distortion, read back from a folder and
  // sensed with the camera's true calibration: one fingertip near a corner, at table (6, 40) cm
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/sense_folder";
  fs::remove_all(dir);
  fs::create_directories(dir);
  SyntheticCameraParams p;
  p.distortion = -0.1;
  SyntheticCamera camera(p, TableParams{});
  ContactShape finger;
  finger.radius = 1.0;
  finger.pose.pos = {6.0, 40.0};
  cv::imwrite(dir + "/f0.png", camera.Render({}));
  for (int i = 1; i <= 3; ++i) {
    const ContactShape shapes[] = {finger};
    cv::imwrite(dir + "/f" + std::to_string(i) + ".png", camera.Render(shapes));
  }
  const std::string calib = dir + "/../sense_calib.yaml";
  ASSERT_FALSE(SaveCalibration(calib, CalibrationFromModel(camera.model())));
  const auto r = RunProxygrasp("sense " + dir + " --calibration " + calib);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::vector<std::string> lines = Lines(r.output);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "{\"frame\": 0, \"contacts\": [], \"merges\": 0, \"splits\": 0}");
  // the disc's centre within 0.05 cm (half a pixel)
  const Vec2 calibrated = Centroid(lines[3]);
  EXPECT_LT((calibrated - finger.pose.pos).norm(), 0.05) << lines[3].substr(0, 200);
  EXPECT_THAT(lines[3], HasSubstr("\"id\": 1, \"state\": \"continuing\""));

  // the same frames without the calibration land elsewhere: the lens bends them by a few mm
  const auto linear = RunProxygrasp("sense folder:" + dir);
  ASSERT_EQ(linear.exitCode, 0);
  const Vec2 uncalibrated = Centroid(Lines(linear.output)[3]);
  EXPECT_GT((uncalibrated - finger.pose.pos).norm(), 0.3);
}

// the number after `key` in a JSON line (-1e9 when absent)
double NumberAfter(const std::string& line, const std::string& key) {
  const size_t at = line.find(key);
  if (at == std::string::npos) return -1e9;
  return std::strtod(line.c_str() + at + key.size(), nullptr);
}

TEST(SenseCommand, DepthFolderPrintsContactsAndHoverWithHeights) {
  // 16-bit PNGs in mm (depth:DIR): a table 1 m away with 1.5 mm of noise, read for 15 frames
  // (the surface, [depth] surface_frames), then a fingertip touching (a disk of 0.8 cm, its top
  // 14 mm up) at table (20, 15) cm and a palm hovering (a disk of 4 cm, its top 50 mm up) at
  // (45, 30) cm; the image maps linearly onto the 61 x 46 cm table
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/sense_depth";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const double pxPerCm = 640.0 / 61.0, pyPerCm = 480.0 / 46.0;
  cv::RNG rng(5);
  for (int i = 0; i < 18; ++i) {
    cv::Mat mm(480, 640, CV_32F, cv::Scalar(1000.0));
    if (i >= 15) {
      // pixel (u, v) sees table ((u + 0.5) 61 / 640, 46 - (v + 0.5) 46 / 480); 4 bits of
      // sub-pixel position
      auto disk = [&](double x, double y, double r, double topMm) {
        const cv::Point centre(static_cast<int>(std::lround((x * pxPerCm - 0.5) * 16)),
                               static_cast<int>(std::lround(((46.0 - y) * pyPerCm - 0.5) * 16)));
        cv::circle(mm, centre, static_cast<int>(std::lround(r * pxPerCm * 16)),
                   cv::Scalar(1000.0 - topMm), cv::FILLED, cv::LINE_8, 4);
      };
      disk(20.0, 15.0, 0.8, 14.0);
      disk(45.0, 30.0, 4.0, 50.0);
    }
    cv::Mat noise(mm.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.5);
    mm += noise;
    cv::Mat out;
    mm.convertTo(out, CV_16UC1);
    char name[32];
    std::snprintf(name, sizeof name, "/d%02d.png", i);
    ASSERT_TRUE(cv::imwrite(dir + name, out));
  }
  const auto r = RunProxygrasp("sense depth:" + dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::vector<std::string> lines = Lines(r.output);
  ASSERT_EQ(lines.size(), 18u);
  EXPECT_EQ(lines[14], "{\"frame\": 14, \"contacts\": [], \"merges\": 0, \"splits\": 0}");
  for (size_t i = 15; i < 18; ++i) {
    const std::string& line = lines[i];
    EXPECT_EQ(Count(line, "\"id\""), 1) << line.substr(0, 300);
    // the fingertip: its centre within half a pixel (0.05 cm), its mean height 1.4 cm within
    // 1 mm (the median of 20 or more pixels of 1.5 mm noise: DepthSensor's tests), a height for
    // every contour point
    EXPECT_LT((Centroid(line) - Vec2(20.0, 15.0)).norm(), 0.05) << line.substr(0, 300);
    EXPECT_NEAR(NumberAfter(line, "\"height\": "), 1.4, 0.1) << line.substr(0, 300);
    EXPECT_THAT(line, HasSubstr("\"heights\": ["));
    const size_t heights = line.find("\"heights\": [");
    const size_t contour = line.find("\"contour\": [");
    ASSERT_NE(contour, std::string::npos);
    const int points = Count(line.substr(contour, line.find("]]", contour) - contour), "[") - 1;
    EXPECT_EQ(Count(line.substr(heights, line.find(']', heights) - heights), ",") + 1, points);
    // the palm: one hover region, its mean height 5 cm
    const size_t hover = line.find("\"hover\": [");
    ASSERT_NE(hover, std::string::npos) << line.substr(0, 300);
    EXPECT_NEAR(NumberAfter(line.substr(hover), "\"height\": "), 5.0, 0.1);
    EXPECT_LT((Centroid(line.substr(hover)) - Vec2(45.0, 30.0)).norm(), 0.05);
  }
}

TEST(SenseCommand, PreviewOfADepthFolderWritesTheDepthTiles) {
  // 16-bit PNGs in mm: a table 1000 mm away for the 15 frames of the surface ([depth]
  // surface_frames), then a fingertip (a disk of 12 px) 14 mm up at pixel (200, 240), in the band
  // (6 to 20 mm: DepthSensor's tests), and a hole (no reading) over x 500-539, y 100-129
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/sense_depth_preview";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (int i = 0; i < 16; ++i) {
    cv::Mat mm(480, 640, CV_16UC1, cv::Scalar(1000));
    if (i == 15) {
      cv::circle(mm, {200, 240}, 12, cv::Scalar(986), cv::FILLED);
      mm(cv::Rect(500, 100, 40, 30)).setTo(0);
    }
    char name[32];
    std::snprintf(name, sizeof name, "/d%02d.png", i);
    ASSERT_TRUE(cv::imwrite(dir + name, mm));
  }
  const std::string png = ::testing::TempDir() + "/sense_depth_preview.png";
  fs::remove(png);
  const auto r = RunProxygrasp("sense depth:" + dir + " --preview " + png);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(Count(r.output, "\"id\""), 1) << r.output.substr(0, 300);
  // five tiles of 640x480 in 3 columns: depth, surface, height; touch, hover
  const cv::Mat view = cv::imread(png);
  ASSERT_FALSE(view.empty()) << png;
  ASSERT_EQ(view.size(), cv::Size(3 * 640, 2 * 480));
  // the fingertip: band green in the height tile (no blue, no red), white in the touch tile and
  // black in the hover tile (left of its centre: its id is written up and right of it)
  const cv::Vec3b height = view.at<cv::Vec3b>(240, 2 * 640 + 195);
  EXPECT_EQ(height[0], 0);
  EXPECT_EQ(height[2], 0);
  EXPECT_GE(height[1], depth_colors::kBandDarkest);
  EXPECT_EQ(view.at<cv::Vec3b>(480 + 240, 195), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(view.at<cv::Vec3b>(480 + 240, 640 + 195), cv::Vec3b(0, 0, 0));
  // the hole: magenta in the depth tile, dark magenta on the touch mask
  EXPECT_EQ(view.at<cv::Vec3b>(115, 520), depth_colors::kNoReading);
  EXPECT_EQ(view.at<cv::Vec3b>(480 + 115, 520), depth_colors::kNoReadingMask);
  EXPECT_THAT(r.output, Not(HasSubstr("not drawn")));
}

TEST(SenseCommand, PreviewOfALevelOnTheDepthCameraWritesTheDepthTiles) {
  // side push on the synthetic depth camera: one fingertip touching from frame 0; frame 29's tiles
  const std::string png = ::testing::TempDir() + "/sense_depth_level_preview.png";
  std::filesystem::remove(png);
  const auto r = RunProxygrasp("sense " + std::string(pg::test::SourceDir()) +
                               "/levels/side_push.toml --set camera.kind=depth --frames 30 "
                               "--preview " +
                               png);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const cv::Mat view = cv::imread(png);
  ASSERT_FALSE(view.empty()) << png;
  ASSERT_EQ(view.size(), cv::Size(3 * 640, 2 * 480));
  // the touch tile (row 1, column 0, above its label) holds the fingertip: some white pixels
  cv::Mat touch;
  cv::extractChannel(view(cv::Rect(0, 480, 640, 440)), touch, 0);
  EXPECT_GT(cv::countNonZero(touch == 255), 20);
}

TEST(SenseCommand, CameraThatCannotBeOpened) {
  const auto r = RunProxygrasp("sense camera:99 --frames 3");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("proxygrasp sense: camera:99: cannot open the camera"));
}

TEST(SenseCommand, MissingInput) {
  const auto r = RunProxygrasp("sense /no/such/video.mp4");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("/no/such/video.mp4: no such file or directory"));
  const auto none = RunProxygrasp("sense");
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_THAT(none.output, HasSubstr("INPUT"));
}

TEST(SenseCommand, MissingAndMalformedCalibration) {
  const auto missing =
      RunProxygrasp("sense synthetic:fingers --frames 2 --calibration /no/calib.yaml");
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_THAT(missing.output, HasSubstr("/no/calib.yaml: calibration file not found"));

  const std::string path = ::testing::TempDir() + "/sense_bad_calib.yaml";
  std::ofstream(path) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
  const auto bad = RunProxygrasp("sense synthetic:fingers --frames 2 --calibration " + path);
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_THAT(bad.output, HasSubstr(path + ": field 'camera_matrix' is missing"));
}

TEST(SenseCommand, FramesOfTheWrongSizeAreReportedAndSkipped) {
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/sense_sizes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  cv::imwrite(dir + "/a1.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(40)));
  cv::imwrite(dir + "/a2.png", cv::Mat(240, 320, CV_8UC1, cv::Scalar(40)));
  cv::imwrite(dir + "/a3.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(40)));
  const auto r = RunProxygrasp("sense " + dir);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_THAT(r.output, HasSubstr("frame 1: frame is 320x240, expected 640x480"));
  EXPECT_THAT(r.output,
              HasSubstr("{\"frame\": 0, \"contacts\": [], \"merges\": 0, \"splits\": 0}"));
  EXPECT_THAT(r.output,
              HasSubstr("{\"frame\": 2, \"contacts\": [], \"merges\": 0, \"splits\": 0}"));
}

TEST(SenseCommand, LevelScriptIsInput) {
  // side push: one fingertip from (20, 23) towards (32, 23) over 1.5 s, then 1 s more
  const auto r =
      RunProxygrasp("sense " + std::string(pg::test::SourceDir()) + "/levels/side_push.toml");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 0, \"contacts\": [{\"id\": 1, \"state\": \"new\", "
                                  "\"parents\": [], \"centroid\": [20.0"));
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 149, "));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("{\"frame\": 150, ")));
  // --frames stops earlier, never later than the script's end
  const auto longer = RunProxygrasp("sense " + std::string(pg::test::SourceDir()) +
                                    "/levels/side_push.toml --frames 400");
  ASSERT_EQ(longer.exitCode, 0) << longer.output;
  EXPECT_THAT(longer.output, HasSubstr("{\"frame\": 149, "));
  EXPECT_THAT(longer.output, ::testing::Not(HasSubstr("{\"frame\": 150, ")));
}

TEST(SenseCommand, BadLevelFileExitsTwoWithLocation) {
  const std::string path = (std::filesystem::temp_directory_path() / "pg_sense_bad.toml").string();
  std::ofstream(path) << "[camera]\nwidht = 640\n";
  const auto r = RunProxygrasp("sense " + path);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr(path + ":2:1:"));
  EXPECT_THAT(r.output, HasSubstr("did you mean 'width'"));
  std::filesystem::remove(path);
}

// ---- --tuio-out ----

const std::string kReleaseLevel = std::string(pg::test::SourceDir()) + "/levels/release.toml";

// the ids of a JSON frame line's contacts that have not lifted
std::vector<int64_t> LiveIds(const std::string& line) {
  std::vector<int64_t> ids;
  const std::string key = "{\"id\": ";
  for (size_t at = line.find(key); at != std::string::npos; at = line.find(key, at + 1)) {
    const int64_t id = std::strtoll(line.c_str() + at + key.size(), nullptr, 10);
    const size_t state = line.find("\"state\": \"", at);
    if (line.compare(state + 10, 7, "lifted\"") != 0) ids.push_back(id);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

// the JSON frame lines of sense's output
std::vector<std::string> FrameLines(const std::string& output) {
  std::vector<std::string> frames;
  for (const std::string& line : Lines(output))
    if (line.rfind("{\"frame\": ", 0) == 0) frames.push_back(line);
  return frames;
}

// true when something is bound to the UDP port on the loopback address
bool PortTaken(int port) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool taken = bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0;
  close(fd);
  return taken;
}

bool HaveTool(const char* name) {
  return std::system(("command -v " + std::string(name) + " >/dev/null 2>&1").c_str()) == 0;
}

// one line of oscdump: "<time tag> <address> <types> <values...>"
struct DumpLine {
  std::string time, address, types;
  std::vector<std::string> values;
};

std::vector<DumpLine> ReadDump(const std::string& path) {
  std::vector<DumpLine> lines;
  std::ifstream in(path);
  std::string text;
  while (std::getline(in, text)) {
    std::istringstream words(text);
    DumpLine line;
    if (!(words >> line.time >> line.address)) continue;
    words >> line.types;
    for (std::string value; words >> value;) line.values.push_back(value);
    lines.push_back(std::move(line));
  }
  return lines;
}

std::string Hex(OscTimeTag t) {
  char text[32];
  std::snprintf(text, sizeof text, "%08x.%08x", t.seconds, t.fraction);
  return text;
}

TEST(SenseCommand, TuioOutSendsWhatOscdumpSeesWithTheJsonIds) {
  if (!HaveTool("oscdump"))
    GTEST_SKIP() << "oscdump is not installed (Debian package liblo-tools): no independent peer";
  const int port = FreePort();
  const std::string dump = ::testing::TempDir() + "/sense_oscdump_" + std::to_string(getpid());
  // oscdump -L PORT > dump, bound before sense sends anything
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, dump.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const std::string portText = std::to_string(port);
  char* argv[] = {const_cast<char*>("oscdump"), const_cast<char*>("-L"),
                  const_cast<char*>(portText.c_str()), nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawnp(&pid, "oscdump", &actions, nullptr, argv, environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  for (int k = 0; k < 300 && !PortTaken(port); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));

  constexpr int kFrames = 30;
  const auto r = RunProxygrasp("sense " + kReleaseLevel + " --frames " + std::to_string(kFrames) +
                               " --tuio-out 127.0.0.1:" + portText);
  // every frame's alv in the dump, or give up after 3 s
  std::vector<DumpLine> lines;
  for (int k = 0; k < 300; ++k) {
    lines = ReadDump(dump);
    if (std::count_if(lines.begin(), lines.end(),
                      [](const DumpLine& l) { return l.address == "/tuio2/alv"; }) >= kFrames)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
  std::remove(dump.c_str());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("tuio out 127.0.0.1:" + portText + ": 30 frames, 0 send errors"));
  const std::vector<std::string> json = FrameLines(r.output);
  ASSERT_EQ(json.size(), static_cast<size_t>(kFrames));

  // per frame: the sessions that sent ptr and ocg, and the alv list
  struct Seen {
    std::set<int64_t> ptr, ocg;
    std::vector<int64_t> alv;
    std::string time;
    bool ended = false;
  };
  std::map<int64_t, Seen> frames;
  int64_t frame = -1;
  std::set<std::string> addresses;
  for (const DumpLine& l : lines) {
    addresses.insert(l.address);
    if (l.address == "/tuio2/frm") {
      frame = std::stoll(l.values.at(0));
      frames[frame].time = l.values.at(1);
      EXPECT_EQ(l.time, l.values.at(1)) << "the bundle's time tag is frm's";
      continue;
    }
    ASSERT_GE(frame, 0) << l.address << " before any frm";
    Seen& seen = frames[frame];
    if (l.address == "/tuio2/ptr") seen.ptr.insert(std::stoll(l.values.at(0)));
    if (l.address == "/tuio2/ocg") seen.ocg.insert(std::stoll(l.values.at(0)));
    if (l.address == "/tuio2/alv") {
      for (const std::string& v : l.values) seen.alv.push_back(std::stoll(v));
      seen.ended = true;
    }
  }
  for (const char* address : {"/tuio2/frm", "/tuio2/ptr", "/tuio2/bnd", "/tuio2/ocg", "/tuio2/alv"})
    EXPECT_EQ(addresses.count(address), 1u) << address;
  ASSERT_EQ(frames.size(), static_cast<size_t>(kFrames));
  for (int64_t f = 0; f < kFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    ASSERT_EQ(frames.count(f), 1u);
    const Seen& seen = frames[f];
    const std::vector<int64_t> ids = LiveIds(json[f]);
    EXPECT_EQ(ids.size(), 4u) << json[f];
    EXPECT_TRUE(seen.ended);
    std::vector<int64_t> alv = seen.alv;
    std::sort(alv.begin(), alv.end());
    EXPECT_EQ(alv, ids);
    EXPECT_EQ(std::vector<int64_t>(seen.ptr.begin(), seen.ptr.end()), ids);
    EXPECT_EQ(std::vector<int64_t>(seen.ocg.begin(), seen.ocg.end()), ids);
    // the time tag is the frame's simulation time, 60 frames a second
    EXPECT_EQ(seen.time, Hex(OscTimeTag::FromSeconds(f / 60.0)));
  }
}

TEST(SenseCommand, TuioOutToAFileRecordsTheSameContacts) {
  const std::string path =
      ::testing::TempDir() + "/sense_tuio_" + std::to_string(getpid()) + ".xml";
  const auto r =
      RunProxygrasp("sense " + kReleaseLevel + " --tuio-out file:" + path + " --tuio-cursors");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("tuio out file:" + path + ": 210 frames, 0 write errors"));
  const std::vector<std::string> json = FrameLines(r.output);
  ASSERT_EQ(json.size(), 210u);
  Result<std::vector<OscBundle>> bundles = ReadTouchlibXml(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(bundles.ok()) << bundles.error().Format();
  // the TUIO 2.0 frames replayed hold the ids sense printed, frame by frame; each frame also has
  // its 2Dcur bundle
  std::vector<OscBundle> tuio2;
  size_t cursorBundles = 0;
  for (const OscBundle& b : bundles.value()) {
    if (b.messages.front().address == "/tuio2/frm") {
      tuio2.push_back(b);
    } else {
      EXPECT_EQ(b.messages.front().address, "/tuio/2Dcur");
      ++cursorBundles;
    }
  }
  EXPECT_EQ(cursorBundles, 210u);
  TuioParams params;  // release.toml's table is the default 61 x 46 cm
  const std::vector<TuioFrame> frames = ReplayTuio(tuio2, params);
  ASSERT_EQ(frames.size(), 210u);
  std::set<int64_t> lifted;
  for (size_t f = 0; f < frames.size(); ++f) {
    std::vector<int64_t> ids;
    for (const TuioContact& c : frames[f].contacts) ids.push_back(c.id);
    EXPECT_EQ(ids, LiveIds(json[f])) << "frame " << f;
    lifted.insert(frames[f].lifted.begin(), frames[f].lifted.end());
  }
  EXPECT_EQ(lifted.size(), 4u) << "every fingertip lifts";
}

TEST(SenseCommand, BadTuioOutSpecsExitTwoNamingTheOption) {
  struct Case {
    std::string spec, message;
  };
  const Case cases[] = {
      {"nohost", "--tuio-out nohost: TUIO output must be HOST:PORT or file:PATH"},
      {"host:0", "--tuio-out host:0: TUIO output port must be 1 to 65535"},
      {"file:", "--tuio-out file:: a TUIO recording needs a path"},
      {"file:/nonexistent/dir/out.xml",
       "--tuio-out file:/nonexistent/dir/out.xml: /nonexistent/dir/out.xml: cannot create the "
       "TUIO recording"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.spec);
    const auto r =
        RunProxygrasp("sense " + kReleaseLevel + " --frames 3 --tuio-out '" + c.spec + "'");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_THAT(r.output, HasSubstr(c.message));
    EXPECT_THAT(r.output, Not(HasSubstr("{\"frame\"")));
  }
}

TEST(SenseCommand, SetChangesParameters) {
  // a minimum area larger than any fingertip leaves no contacts
  const auto r = RunProxygrasp("sense synthetic:fingers --frames 7 --set sensing.min_area=50");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("\"id\"")));
  const auto bad = RunProxygrasp("sense synthetic:fingers --frames 1 --set sensing.treshold=5");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_THAT(bad.output, HasSubstr("threshold"));
}

// depth inputs (issue 43): what cannot be read at the start is an input error naming what and
// where (exit 2, no frame printed, no crash); a bad frame later is counted and skipped (exit 1)
TEST(SenseCommand, BadDepthInputsExitTwoNamingWhatAndWhere) {
  namespace fs = std::filesystem;
  // an 8-bit PNG where 16-bit depth is expected
  const std::string eight = test::FreshDir("sense_depth", "eight");
  cv::imwrite(eight + "/d_0.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(100)));
  // a fakenect recording whose first PGM is truncated, and one whose INDEX.txt names a frame
  // that is not there (its 3rd line)
  const std::string truncated = test::FreshDir("sense_depth", "truncated");
  const std::string unlisted = test::FreshDir("sense_depth", "unlisted");
  std::string firstFrame;
  for (const std::string& dir : {truncated, unlisted}) {
    Result<DepthRecordingWriter> w =
        DepthRecordingWriter::Create(dir, DepthRecordingWriter::Format::kFakenect);
    ASSERT_TRUE(w) << w.error().Format();
    ASSERT_FALSE(w.value().Write(cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)), 0.0));
    ASSERT_FALSE(w.value().Write(cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)), 0.1));
    std::ifstream index(dir + "/INDEX.txt");
    std::getline(index, firstFrame);
  }
  fs::resize_file(truncated + "/" + firstFrame, 100);
  std::ofstream(unlisted + "/INDEX.txt", std::ios::app) << "d-1000000.200000-00000002.pgm\n";
  struct Case {
    std::string input, message;
  };
  const std::vector<Case> cases = {
      {"kinect:7", HaveFreenect() ? "kinect:7: no Kinect 7 (0 found; is it plugged in"
                                  : "kinect:7: not built with libfreenect"},
      {"openni:nosuch://device",
       HaveOpenNi2() ? "openni:nosuch://device: no OpenNI2 device" : "not built with OpenNI2"},
      {"oni:/no/such.oni", "/no/such.oni: no such ONI file"},
      {"depth:/no/such/folder", "/no/such/folder: no such folder"},
      {"fakenect:/no/such/folder", "/no/such/folder: no such folder"},
      {"depth:" + eight, eight + "/d_0.png: CV_8UC1 image where 16-bit single-channel depth (mm)"},
      {"fakenect:" + truncated, truncated + "/" + firstFrame + ": truncated: 85 of 6144 bytes"},
      {"fakenect:" + unlisted,
       unlisted + "/INDEX.txt:3:1: names d-1000000.200000-00000002.pgm, which is not in the "
                  "folder"},
  };
  // 100 bytes of a PGM whose header "P5 64 48 65535\n" (its newline the one white-space byte
  // before the pixels) is 15 bytes: 85 of its 64 x 48 x 2 = 6144 bytes of pixels are there
  for (const Case& c : cases) {
    SCOPED_TRACE(c.input);
    const auto r = RunProxygrasp("sense '" + c.input + "' --frames 3");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("proxygrasp sense: " + c.message));
    EXPECT_THAT(r.output, Not(HasSubstr("{\"frame\"")));
  }
}

TEST(SenseCommand, AnOniRecordingWithoutADepthStreamExitsTwo) {
  const std::string real = test::RealDataDir("depth");
  if (real.empty())
    GTEST_SKIP() << "../shared/real/depth is absent (a clone of the project alone): no ONI "
                    "recording to make one without a depth stream from; set PROXYGRASP_REAL_DATA";
  if (!HaveOpenNi2()) GTEST_SKIP() << "not built with OpenNI2: oni:FILE cannot be read";
  // test.oni (OpenNI 1) declares its one stream in a node-added record: the name "Depth1", then
  // the node's type, 2 (depth); made 3 (image), the recording holds no depth stream
  std::ifstream in(real + "/depth/test.oni", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string name("Depth1\0", 7);
  const size_t at = bytes.find(name);
  ASSERT_NE(at, std::string::npos) << "test.oni has changed: no Depth1 node";
  ASSERT_EQ(bytes.substr(at + 7, 4), std::string("\x02\0\0\0", 4)) << "not a depth node";
  bytes[at + 7] = '\x03';
  const std::string file = test::FreshDir("sense_depth", "oni") + "/image_only.oni";
  std::ofstream(file, std::ios::binary) << bytes;
  const auto r = RunProxygrasp("sense oni:" + file + " --frames 3");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("proxygrasp sense: " + file +
                                  ": the ONI file has no depth "
                                  "stream"));
}

TEST(SenseCommand, ACorruptDepthFrameIsNamedCountedAndSkipped) {
  const std::string dir = test::FreshDir("sense_depth", "corrupt");
  for (int k = 0; k < 4; ++k)
    cv::imwrite(dir + "/d_" + std::to_string(k) + ".png",
                cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)));
  std::ofstream(dir + "/d_2.png", std::ios::trunc) << "not a png";
  const auto r = RunProxygrasp("sense depth:" + dir);
  // the run goes on past it, and ends saying it skipped frames (the exit of a run with bad frames)
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr(dir + "/d_2.png: cannot read the image (corrupt or not an "
                                        "image)"));
  EXPECT_THAT(r.output, HasSubstr("bad frame(s) skipped"));
  EXPECT_EQ(Count(r.output, "d_2.png"), 1) << r.output;
}

}  // namespace
}  // namespace pg
