#include "proxygrasp/sensing/frame_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

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

// a frame whose pixel (0, 0) holds its number, so order can be checked
cv::Mat Numbered(int n, int type = CV_8UC1) {
  cv::Mat m(48, 64, type, cv::Scalar::all(0));
  m.setTo(cv::Scalar::all(n * 10));
  return m;
}

TEST(FolderSource, ReadsNumberedImagesInNumericOrder) {
  const std::string dir = FreshDir("numbered");
  // written out of order, with names whose text order differs from their number order, and one
  // in colour: the source delivers grey frames 1, 2, 10
  cv::imwrite(dir + "/frame_10.png", Numbered(10));
  cv::imwrite(dir + "/frame_2.png", Numbered(2, CV_8UC3));
  cv::imwrite(dir + "/frame_1.png", Numbered(1));
  std::ofstream(dir + "/notes.txt") << "not an image";
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource(dir);
  ASSERT_TRUE(src) << src.error().Format();
  EXPECT_EQ(src.value()->Describe(), "folder " + dir);
  cv::Mat frame;
  for (int expected : {1, 2, 10}) {
    ASSERT_EQ(src.value()->Read(frame), FrameStatus::kOk);
    ASSERT_EQ(frame.type(), CV_8UC1);
    EXPECT_EQ(frame.at<uint8_t>(0, 0), expected * 10);
  }
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kEnd);
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kEnd) << "the end is sticky";
}

TEST(FolderSource, BrokenImageIsAnErrorNamingTheFileAndReadingGoesOn) {
  const std::string dir = FreshDir("broken");
  cv::imwrite(dir + "/f1.png", Numbered(1));
  std::ofstream(dir + "/f2.png") << "garbage, not a png";
  cv::imwrite(dir + "/f3.png", Numbered(3));
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("folder:" + dir);
  ASSERT_TRUE(src);
  cv::Mat frame;
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kError);
  EXPECT_THAT(src.value()->LastError(), HasSubstr("f2.png: cannot read"));
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(frame.at<uint8_t>(0, 0), 30);
  EXPECT_EQ(src.value()->LastError(), "");
}

TEST(FolderSource, EmptyFolderAndWrongKinds) {
  const std::string dir = FreshDir("empty");
  Result<std::unique_ptr<FrameSource>> r = OpenFrameSource(dir);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(),
            dir + ": the folder holds no image files (png, jpg, bmp, tif, pgm, ppm)");
  r = OpenFrameSource("video:" + dir);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("is a directory"));
  const std::string file = dir + "/file.txt";
  std::ofstream(file) << "x";
  r = OpenFrameSource("folder:" + file);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("is not a directory"));
}

TEST(OpenFrameSource, MissingPathsAndBadSpecs) {
  Result<std::unique_ptr<FrameSource>> r = OpenFrameSource("/no/such/clip.avi");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), "/no/such/clip.avi: no such file or directory");
  r = OpenFrameSource("");
  ASSERT_FALSE(r);
  r = OpenFrameSource("camera:abc");
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("camera index must be a number"));
  r = OpenFrameSource("synthetic:nothing");
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(),
              HasSubstr("unknown synthetic scene 'nothing' (known: fingers, hands)"));
  r = OpenFrameSource("/dev/video99");
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("/dev/video99"));
}

TEST(OpenFrameSource, CameraThatCannotBeOpenedIsAnError) {
  // no machine running the tests has 99 cameras; opening fails cleanly, no crash
  Result<std::unique_ptr<FrameSource>> r = OpenFrameSource("camera:99");
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("camera:99: cannot open the camera"));
}

TEST(OpenFrameSource, FileThatIsNotAVideo) {
  const std::string dir = FreshDir("notvideo");
  const std::string file = dir + "/clip.avi";
  std::ofstream(file) << "this is not a video";
  Result<std::unique_ptr<FrameSource>> r = OpenFrameSource(file);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr(file + ": cannot open as a video"));
}

TEST(VideoSource, ReadsAVideoFileAsGreyFrames) {
  const std::string dir = FreshDir("video");
  const std::string file = dir + "/clip.avi";
  {
    cv::VideoWriter writer(file, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30.0,
                           cv::Size(64, 48), true);
    if (!writer.isOpened()) GTEST_SKIP() << "this OpenCV build cannot write MJPG AVI files";
    for (int i = 0; i < 5; ++i) writer.write(Numbered(i + 1, CV_8UC3));
  }
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("video:" + file);
  ASSERT_TRUE(src) << src.error().Format();
  EXPECT_EQ(src.value()->Describe(), "video " + file);
  EXPECT_NEAR(src.value()->FrameRate(), 30.0, 1e-6);
  cv::Mat frame;
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(src.value()->Read(frame), FrameStatus::kOk) << i;
    ASSERT_EQ(frame.type(), CV_8UC1);
    // JPEG compression: the flat level survives within a few grey
    EXPECT_NEAR(frame.at<uint8_t>(20, 20), (i + 1) * 10, 4);
  }
  EXPECT_EQ(src.value()->Read(frame), FrameStatus::kEnd);
}

TEST(SyntheticSource, DemoScenesRenderThroughTheCamera) {
  Result<std::unique_ptr<FrameSource>> src = OpenFrameSource("synthetic:fingers");
  ASSERT_TRUE(src) << src.error().Format();
  EXPECT_EQ(src.value()->Describe(), "synthetic:fingers");
  EXPECT_DOUBLE_EQ(src.value()->FrameRate(), 60.0);
  cv::Mat frame;
  ASSERT_EQ(src.value()->Read(frame), FrameStatus::kOk);
  EXPECT_EQ(frame.size(), cv::Size(640, 480));
  EXPECT_EQ(frame.type(), CV_8UC1);
  // the reopen of a non-camera source is refused with a message, not a crash
  MaybeError s = src.value()->Reopen();
  ASSERT_TRUE(s);
  EXPECT_THAT(s->Format(), HasSubstr("cannot be reopened"));
}

TEST(SyntheticSource, ScriptEndsTheStream) {
  int calls = 0;
  SyntheticSource src(
      "three", SyntheticCameraParams{}, TableParams{},
      [&calls](int64_t frame, std::vector<ContactShape>& shapes) {
        ++calls;
        shapes.assign(1, ContactShape{});
        shapes[0].pose.pos = {10.0 + frame, 10.0};
        return frame < 3;
      },
      -1);
  cv::Mat frame;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(src.Read(frame), FrameStatus::kOk);
    EXPECT_DOUBLE_EQ(src.shapes()[0].pose.pos.x(), 10.0 + i);
  }
  EXPECT_EQ(src.Read(frame), FrameStatus::kEnd);
  EXPECT_EQ(calls, 4);
  // a frame count stops it earlier
  SyntheticSource two(
      "two", SyntheticCameraParams{}, TableParams{},
      [](int64_t, std::vector<ContactShape>& shapes) {
        shapes.clear();
        return true;
      },
      2);
  EXPECT_EQ(two.Read(frame), FrameStatus::kOk);
  EXPECT_EQ(two.Read(frame), FrameStatus::kOk);
  EXPECT_EQ(two.Read(frame), FrameStatus::kEnd);
}

TEST(NumberedImages, OrdersByTheLastNumber) {
  const std::string dir = FreshDir("order");
  for (const char* name : {"shot9.png", "shot10.png", "shot08.png", "a.bmp", "clip_3_x.jpg"})
    cv::imwrite(dir + "/" + name, Numbered(1));
  const std::vector<std::string> files = NumberedImages(dir);
  ASSERT_EQ(files.size(), 5u);
  EXPECT_EQ(fs::path(files[0]).filename(), "a.bmp");  // no number sorts first
  EXPECT_EQ(fs::path(files[1]).filename(), "clip_3_x.jpg");
  EXPECT_EQ(fs::path(files[2]).filename(), "shot08.png");
  EXPECT_EQ(fs::path(files[3]).filename(), "shot9.png");
  EXPECT_EQ(fs::path(files[4]).filename(), "shot10.png");
}

}  // namespace
}  // namespace pg
