#include "run_command.h"

#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

namespace pg {
namespace {

namespace fs = std::filesystem;
using test::RunProxygrasp;
using ::testing::HasSubstr;

std::string Dir(const std::string& name) {
  return test::FreshDir("cmd_tune_test", name);
}

// A dim table (touches 10 grey above the table, noise 1 grey): `clear` frames of the clear table,
// then `touched` frames with two fingertips, written as numbered PNGs
void WriteCapture(const std::string& dir, int clear, int touched) {
  SyntheticCameraParams p;
  p.background = 40.0;
  p.contactLevel = 50.0;
  p.noise = 1.0;
  SyntheticCamera camera(p, TableParams());
  std::vector<ContactShape> touches(2);
  touches[0].pose.pos = {20.0, 20.0};
  touches[1].pose.pos = {40.0, 25.0};
  for (ContactShape& s : touches) s.radius = 0.8;
  for (int i = 0; i < clear + touched; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/%04d.png", i);
    ASSERT_TRUE(
        cv::imwrite(dir + name, camera.Render(i < clear ? std::vector<ContactShape>() : touches)));
  }
}

// the number of contacts `sense` printed for one frame (its JSON line), -1 when it printed none
int ContactsOfFrame(const std::string& output, int frame) {
  const std::string head = "{\"frame\": " + std::to_string(frame) + ",";
  const size_t begin = output.find(head);
  if (begin == std::string::npos) return -1;
  const std::string line = output.substr(begin, output.find('\n', begin) - begin);
  int count = 0;
  for (size_t at = line.find("\"id\":"); at != std::string::npos; at = line.find("\"id\":", at + 1))
    ++count;
  return count;
}

TEST(TuneCommand, WritesValuesThatSenseThenUses) {
  const std::string dir = Dir("dim");
  fs::create_directories(dir + "/frames");
  WriteCapture(dir + "/frames", 30, 30);
  const std::string out = dir + "/table.yaml";
  // folder frames carry no rate: 30 Hz makes the 30 clear frames the first second; --seconds
  // 1.5 reads 45 frames of the 60
  auto r = RunProxygrasp("tune folder:" + dir + "/frames --fps 30 --seconds 1.5 --output " + out);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("30 clear-table frames, 15 frames of touches"));
  EXPECT_THAT(r.output, HasSubstr("wrote " + out));
  Result<Calibration> c = LoadCalibration(out);
  ASSERT_TRUE(c) << c.error().Format();
  EXPECT_FALSE(c.value().background.empty());
  ASSERT_EQ(c.value().sensing.size(), 3u);
  EXPECT_EQ(c.value().sensing[0].first, "gain");
  EXPECT_GT(std::stod(c.value().sensing[0].second), 1.0);

  // sense sees the two touches with the tuned file, and none on the clear frames
  r = RunProxygrasp("sense folder:" + dir + "/frames --calibration " + out);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(ContactsOfFrame(r.output, 59), 2);
  EXPECT_EQ(ContactsOfFrame(r.output, 29), 0);
  // The fixed threshold of 30 sees none of them without it (10 grey < 30). The adaptive
  // default takes its level from the touches once they land (issue 45: 0.3 of their 10 grey
  // peak, at least 5 noise deviations, about 6 grey), so it finds them as well.
  r = RunProxygrasp("sense folder:" + dir + "/frames --set sensing.threshold_mode=fixed");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(ContactsOfFrame(r.output, 59), 0);
  r = RunProxygrasp("sense folder:" + dir + "/frames");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(ContactsOfFrame(r.output, 29), 0);
  EXPECT_EQ(ContactsOfFrame(r.output, 59), 2);
}

TEST(TuneCommand, BadInputIsNamedWithANonZeroExit) {
  auto r = RunProxygrasp("tune /no/such/clip.avi");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("/no/such/clip.avi"));
  r = RunProxygrasp("tune --clear 0 x.avi");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("--clear"));
  // a capture that never leaves the clear part: tuning fails and says why, writing nothing
  const std::string dir = Dir("short");
  fs::create_directories(dir + "/frames");
  WriteCapture(dir + "/frames", 10, 0);
  r = RunProxygrasp("tune folder:" + dir + "/frames --output " + dir + "/t.yaml");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_THAT(r.output, HasSubstr("ended within its clear part"));
  EXPECT_FALSE(fs::exists(dir + "/t.yaml"));
  // a calibration of another image size
  Calibration other = LinearCalibration({320, 240}, TableParams());
  ASSERT_FALSE(SaveCalibration(dir + "/small.yaml", other));
  r = RunProxygrasp("tune folder:" + dir + "/frames --calibration " + dir + "/small.yaml");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output,
              HasSubstr("small.yaml: field 'image_width'/'image_height' is 320x240 but "));
  // a calibration that does not exist
  r = RunProxygrasp("tune folder:" + dir + "/frames --calibration " + dir + "/none.yaml");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("none.yaml: calibration file not found"));
}

}  // namespace
}  // namespace pg
