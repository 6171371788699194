#include "run_command.h"

#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pg {
namespace {

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
  EXPECT_EQ(lines[4], "{\"frame\": 4, \"contacts\": []}");
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
  EXPECT_EQ(lines[0], "{\"frame\": 0, \"contacts\": []}");
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
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 0, \"contacts\": []}"));
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 2, \"contacts\": []}"));
}

TEST(SenseCommand, LevelScriptIsInput) {
  // side push: one fingertip from (20, 23) towards (32, 23) over 1.5 s, then 1 s more
  const auto r =
      RunProxygrasp("sense " + std::string(PROXYGRASP_SOURCE_DIR) + "/levels/side_push.toml");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 0, \"contacts\": [{\"id\": 1, \"state\": \"new\", "
                                  "\"centroid\": [20.0"));
  EXPECT_THAT(r.output, HasSubstr("{\"frame\": 149, "));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("{\"frame\": 150, ")));
  // --frames stops earlier, never later than the script's end
  const auto longer = RunProxygrasp("sense " + std::string(PROXYGRASP_SOURCE_DIR) +
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

TEST(SenseCommand, SetChangesParameters) {
  // a minimum area larger than any fingertip leaves no contacts
  const auto r = RunProxygrasp("sense synthetic:fingers --frames 7 --set sensing.min_area=50");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("\"id\"")));
  const auto bad = RunProxygrasp("sense synthetic:fingers --frames 1 --set sensing.treshold=5");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_THAT(bad.output, HasSubstr("threshold"));
}

}  // namespace
}  // namespace pg
