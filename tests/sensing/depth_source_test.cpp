#include "proxygrasp/sensing/depth_source.h"

#include "real_data.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace pg {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// a table 1 m away with a 15 mm step in one corner and a hole of no reading
cv::Mat DepthScene(int n) {
  cv::Mat mm(48, 64, CV_16UC1, cv::Scalar(1000));
  mm(cv::Rect(5 + n, 5, 10, 10)).setTo(985);
  mm(cv::Rect(40, 30, 4, 4)).setTo(0);
  return mm;
}

std::string RealDepthDir() {
  const std::string root = test::RealDataDir("depth");
  return root.empty() ? "" : root + "/depth";
}

constexpr const char* kNoRealDepth =
    "../shared/real/depth is absent (a clone of the project alone): no real depth recordings; set "
    "PROXYGRASP_REAL_DATA to the folder that holds depth/";

TEST(KinectDisparity, FollowsOpenKinectsFitAndInvertsWithinAStep) {
  EXPECT_EQ(KinectRawToMm(kKinectNoReading), 0.0);
  // OpenKinect: about 2.9 mm per raw step at 1 m and 6.4 mm at 1.5 m (../shared/real/depth/README)
  const int at1m = KinectMmToRaw(1000.0);
  EXPECT_NEAR(KinectRawToMm(at1m + 1) - KinectRawToMm(at1m), 2.9, 0.1);
  const int at15 = KinectMmToRaw(1500.0);
  EXPECT_NEAR(KinectRawToMm(at15 + 1) - KinectRawToMm(at15), 6.4, 0.2);
  for (double mm = 500.0; mm <= 4000.0; mm += 37.0) {
    const int raw = KinectMmToRaw(mm);
    ASSERT_NE(raw, kKinectNoReading) << mm;
    const double step = KinectRawToMm(raw + 1) - KinectRawToMm(raw);
    EXPECT_LE(std::abs(KinectRawToMm(raw) - mm), 0.5 * step + 1e-9) << mm;
  }
  EXPECT_EQ(KinectMmToRaw(0.0), kKinectNoReading);
  EXPECT_EQ(KinectMmToRaw(100.0), kKinectNoReading);  // nearer than the fit's nearest, 0.3 m
}

TEST(DepthFolder, WritesAndReadsBackSixteenBitMillimetres) {
  const std::string dir = FreshDir("depth_png");
  Result<DepthRecordingWriter> w =
      DepthRecordingWriter::Create(dir, DepthRecordingWriter::Format::kDepthPng);
  ASSERT_TRUE(w) << w.error().Format();
  for (int n = 0; n < 12; ++n) ASSERT_FALSE(w.value().Write(DepthScene(n), n / 60.0));
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("depth:" + dir);
  ASSERT_TRUE(src) << src.error().Format();
  cv::Mat frame;
  for (int n = 0; n < 12; ++n) {
    ASSERT_EQ(src.value()->Read(frame), FrameStatus::kOk) << src.value()->LastError();
    ASSERT_EQ(frame.type(), CV_16UC1);
    EXPECT_EQ(cv::norm(frame, DepthScene(n), cv::NORM_INF), 0.0) << n;  // exact, in name order
  }
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kEnd);
}

TEST(DepthFolder, AnEightBitImageIsAnErrorNamingTheFile) {
  const std::string dir = FreshDir("depth_8bit");
  cv::imwrite(dir + "/frame_0.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(90)));
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("depth:" + dir);
  ASSERT_FALSE(src);
  EXPECT_THAT(src.error().Format(), HasSubstr("frame_0.png"));
  EXPECT_THAT(src.error().Format(), HasSubstr("CV_8UC1 image where 16-bit"));
  // a missing folder names it
  Result<std::unique_ptr<FrameSource>> none = OpenFrameSource("depth:" + dir + "/nope");
  ASSERT_FALSE(none);
  EXPECT_THAT(none.error().Format(), HasSubstr("nope: no such folder"));
}

TEST(DepthFolder, ACorruptFrameIsReportedAndTheNextOneRead) {
  const std::string dir = FreshDir("depth_corrupt");
  cv::imwrite(dir + "/f_0.png", DepthScene(0));
  std::ofstream(dir + "/f_1.png") << "not a png at all";
  cv::imwrite(dir + "/f_2.png", cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(7)));
  cv::imwrite(dir + "/f_3.png", DepthScene(3));
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("depth:" + dir);
  ASSERT_TRUE(src) << src.error().Format();
  cv::Mat frame;
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kError);
  EXPECT_THAT(src.value()->LastError(), HasSubstr("f_1.png"));
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kError);
  EXPECT_THAT(src.value()->LastError(), HasSubstr("f_2.png: CV_8UC3 image"));
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(cv::norm(frame, DepthScene(3), cv::NORM_INF), 0.0);
}

TEST(Fakenect, WritesAndReadsBackWithinOneDisparityStep) {
  const std::string dir = FreshDir("fakenect_rt");
  Result<DepthRecordingWriter> w =
      DepthRecordingWriter::Create(dir, DepthRecordingWriter::Format::kFakenect);
  ASSERT_TRUE(w) << w.error().Format();
  for (int n = 0; n < 5; ++n) ASSERT_FALSE(w.value().Write(DepthScene(n), n / 30.0));
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("fakenect:" + dir);
  ASSERT_TRUE(src) << src.error().Format();
  EXPECT_NEAR(src.value()->FrameRate(), 30.0, 0.01);  // from the time stamps in the names
  cv::Mat frame;
  for (int n = 0; n < 5; ++n) {
    ASSERT_EQ(src.value()->Read(frame), FrameStatus::kOk) << src.value()->LastError();
    const cv::Mat truth = DepthScene(n);
    // half a raw step at 1 m is 1.45 mm, rounded to whole mm: at most 2
    cv::Mat diff;
    cv::absdiff(frame, truth, diff);
    EXPECT_LE(cv::norm(diff, cv::NORM_INF), 2.0) << n;
    EXPECT_EQ(frame.at<uint16_t>(31, 41), 0);  // no reading stays no reading (raw 2047)
  }
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kEnd);
}

TEST(Fakenect, BadRecordingsAreErrorsNamingWhatAndWhere) {
  const std::string dir = FreshDir("fakenect_bad");
  Result<DepthRecordingWriter> w =
      DepthRecordingWriter::Create(dir, DepthRecordingWriter::Format::kFakenect);
  ASSERT_TRUE(w);
  ASSERT_FALSE(w.value().Write(DepthScene(0), 0.0));
  ASSERT_FALSE(w.value().Write(DepthScene(1), 0.1));
  // a truncated frame: counted and skipped by the pipeline, named here
  const std::vector<std::string> names = [&] {
    std::vector<std::string> n;
    std::ifstream in(dir + "/INDEX.txt");
    for (std::string line; std::getline(in, line);) n.push_back(line);
    return n;
  }();
  ASSERT_EQ(names.size(), 2u);
  fs::resize_file(dir + "/" + names[1], 1000);
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("fakenect:" + dir);
  ASSERT_TRUE(src) << src.error().Format();
  cv::Mat frame;
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kError);
  EXPECT_THAT(src.value()->LastError(), HasSubstr(names[1] + ": truncated"));

  // a recording whose first frame is broken is no recording: refused at open, naming the frame
  fs::resize_file(dir + "/" + names[0], 10);
  Result<std::unique_ptr<FrameSource>> broken = OpenFrameSource("fakenect:" + dir);
  ASSERT_FALSE(broken);
  EXPECT_THAT(broken.error().Format(), HasSubstr(names[0] + ": "));

  // INDEX.txt naming a file that is not there: the line and the name
  std::ofstream(dir + "/INDEX.txt", std::ios::app) << "r-1.0-1.ppm\nd-1000000.2-9.pgm\n";
  Result<std::unique_ptr<FrameSource>> missing = OpenFrameSource("fakenect:" + dir);
  ASSERT_FALSE(missing);
  EXPECT_THAT(missing.error().Format(), HasSubstr("INDEX.txt:4:1: names d-1000000.2-9.pgm"));
}

TEST(DepthDevices, MissingDevicesAndFilesAreErrorsNamingThem) {
  Result<std::unique_ptr<FrameSource>> oni = OpenFrameSource("oni:/no/such.oni");
  ASSERT_FALSE(oni);
  EXPECT_THAT(oni.error().Format(), HasSubstr("/no/such.oni: no such ONI file"));
  Result<std::unique_ptr<FrameSource>> bad = OpenFrameSource("kinect:one");
  ASSERT_FALSE(bad);
  EXPECT_THAT(bad.error().Format(), HasSubstr("kinect:one"));
  // no Kinect is plugged into a test machine; a build without libfreenect says that instead
  Result<std::unique_ptr<FrameSource>> kinect = OpenFrameSource("kinect:7");
  ASSERT_FALSE(kinect);
  EXPECT_THAT(kinect.error().Format(),
              HasSubstr(HaveFreenect() ? "no Kinect 7" : "not built with libfreenect"));
  // an ONI file with no depth stream: a file that is no recording at all is refused by the driver
  const std::string dir = FreshDir("oni_bad");
  std::ofstream(dir + "/empty.oni") << "NI10 but nothing else";
  Result<std::unique_ptr<FrameSource>> broken = OpenFrameSource("oni:" + dir + "/empty.oni");
  ASSERT_FALSE(broken);
  EXPECT_THAT(broken.error().Format(), HasSubstr("empty.oni"));
}

// the real recordings (../shared/real/depth/README.md): frame counts, sizes, millimetre ranges
struct RealCounts {
  int frames = 0;
  cv::Size size;
  double nearest = 1e9, farthest = 0.0, noReading = 0.0;  // mm, mm, fraction of pixels
};

RealCounts ReadAll(const std::string& spec) {
  RealCounts c;
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource(spec);
  EXPECT_TRUE(src) << src.error().Format();
  if (!src) return c;
  cv::Mat frame;
  while (src.value()->Read(frame) == FrameStatus::kOk) {
    EXPECT_EQ(frame.type(), CV_16UC1);
    ++c.frames;
    c.size = frame.size();
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(frame, nullptr, &hi, nullptr, nullptr);
    cv::minMaxLoc(frame, &lo, nullptr, nullptr, nullptr, frame > 0);
    c.nearest = std::min(c.nearest, lo);
    c.farthest = std::max(c.farthest, hi);
    c.noReading += 1.0 - cv::countNonZero(frame) / static_cast<double>(frame.total());
  }
  c.noReading /= std::max(c.frames, 1);
  return c;
}

TEST(RealDepth, FakenectRecordingsReadWithTheirFramesAndDepths) {
  const std::string dir = RealDepthDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealDepth;
  // kinectcap: 4 frames of a room, a wall about 1 m away; 8% without a reading
  const RealCounts room = ReadAll("fakenect:" + dir + "/kinectcap");
  EXPECT_EQ(room.frames, 4);
  EXPECT_EQ(room.size, cv::Size(640, 480));
  EXPECT_GE(room.nearest, 400.0);
  EXPECT_LE(room.farthest, 10000.0);
  EXPECT_NEAR(room.noReading, 0.08, 0.02);
  // desk: 40 frames of a person at a desk 0.5 to 0.6 m away; about 47% without a reading
  const RealCounts desk = ReadAll("fakenect:" + dir + "/desk");
  EXPECT_EQ(desk.frames, 40);
  EXPECT_EQ(desk.size, cv::Size(640, 480));
  EXPECT_GE(desk.nearest, 400.0);
  EXPECT_LE(desk.farthest, 10000.0);
  EXPECT_NEAR(desk.noReading, 0.47, 0.03);
}

TEST(RealDepth, OpenNiOneRecordingPlaysThroughOpenNi2) {
  const std::string dir = RealDepthDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealDepth;
  if (!HaveOpenNi2()) GTEST_SKIP() << "not built with OpenNI2";
  // test.oni is an OpenNI 1 recording ("NI10"): OpenNI2's file driver plays its depth stream
  const RealCounts oni = ReadAll("oni:" + dir + "/test.oni");
  EXPECT_EQ(oni.frames, 12);
  EXPECT_EQ(oni.size, cv::Size(640, 480));
  EXPECT_GE(oni.nearest, 400.0);
  EXPECT_LE(oni.farthest, 10000.0);
}

}  // namespace
}  // namespace pg
