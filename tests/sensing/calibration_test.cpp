#include "proxygrasp/sensing/calibration.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <cmath>
#include <fstream>

namespace pg {
namespace {

using ::testing::HasSubstr;

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

CameraModel DistortedModel() {
  CameraModel m;
  m.imageSize = {640, 480};
  m.cameraMatrix = cv::Matx33d(580, 0, 319.5, 0, 575, 239.5, 0, 0, 1);
  m.distCoeffs = cv::Vec<double, 5>(-0.12, 0.03, 0.001, -0.002, 0.0);
  m.cameraToTable = cv::Matx33d(0.095, 0.002, 0.3, 0.001, -0.096, 46.0, 0.00001, 0.00002, 1.0);
  return m;
}

TEST(CameraModel, UndistortInvertsDistort) {
  const CameraModel m = DistortedModel();
  for (double u : {0.0, 100.0, 319.5, 639.0}) {
    for (double v : {0.0, 240.0, 479.0}) {
      const Vec2 px(u, v);
      // Newton converges to far below a micro-pixel
      EXPECT_LT((m.Distort(m.Undistort(px)) - px).norm(), 1e-6) << u << "," << v;
    }
  }
}

TEST(CameraModel, TableToCameraInvertsCameraToTable) {
  const CameraModel m = DistortedModel();
  for (const Vec2& px : {Vec2(5, 5), Vec2(320, 240), Vec2(630, 470), Vec2(100, 400)}) {
    EXPECT_LT((m.TableToCamera(m.CameraToTable(px)) - px).norm(), 1e-6);
  }
}

TEST(CameraModel, DistortMatchesOpenCvProjectPoints) {
  // the closed form is OpenCV's model: compare with cv::projectPoints on the same coefficients
  const CameraModel m = DistortedModel();
  const cv::Matx33d k = m.cameraMatrix;
  const Vec2 undistorted(600.0, 30.0);
  std::vector<cv::Point3d> object{
      {(undistorted.x() - k(0, 2)) / k(0, 0), (undistorted.y() - k(1, 2)) / k(1, 1), 1.0}};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(k),
                    cv::Mat(m.distCoeffs), image);
  const Vec2 ours = m.Distort(undistorted);
  EXPECT_NEAR(ours.x(), image[0].x, 1e-9);
  EXPECT_NEAR(ours.y(), image[0].y, 1e-9);
}

TEST(LinearCalibration, ImageEdgesAreTableEdges) {
  const TableParams table;  // 61 x 46 cm
  Result<CameraModel> m = ModelFromCalibration(LinearCalibration({640, 480}, table));
  ASSERT_TRUE(m);
  // the top-left image corner (-0.5, -0.5) is the table's far-left corner (0, 46); y points up
  EXPECT_LT((m.value().CameraToTable(Vec2(-0.5, -0.5)) - Vec2(0.0, 46.0)).norm(), 1e-12);
  EXPECT_LT((m.value().CameraToTable(Vec2(639.5, 479.5)) - Vec2(61.0, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(m.value().CmPerPixel(Vec2(320, 240)), std::sqrt(61.0 / 640 * 46.0 / 480), 1e-9);
}

TEST(Calibration, SaveLoadRoundTrip) {
  Calibration c =
      CalibrationFromModel(DistortedModel(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(37)));
  c.tableToDisplay = cv::Matx33d(16, 0, 3, 0, -16, 760, 0, 0, 1);
  const std::string path = ::testing::TempDir() + "/roundtrip.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> back = LoadCalibration(path);
  ASSERT_TRUE(back) << back.error().Format();
  EXPECT_EQ(back.value().imageSize, c.imageSize);
  EXPECT_EQ(cv::norm(back.value().cameraMatrix, c.cameraMatrix, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(back.value().distCoeffs, c.distCoeffs, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(cv::Mat(back.value().cameraToTable), cv::Mat(c.cameraToTable), cv::NORM_INF),
            0.0);
  EXPECT_EQ(cv::norm(cv::Mat(back.value().tableToDisplay), cv::Mat(c.tableToDisplay), cv::NORM_INF),
            0.0);
  ASSERT_EQ(back.value().background.size(), cv::Size(640, 480));
  EXPECT_EQ(back.value().background.at<uint8_t>(100, 100), 37);
}

TEST(Calibration, TunedSensingValuesRoundTripInOrder) {
  Calibration c = LinearCalibration({640, 480}, TableParams());
  c.sensing = {{"gain", "8.57143"}, {"threshold", "30"}, {"threshold_mode", "\"fixed\""}};
  const std::string path = ::testing::TempDir() + "/tuned.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> back = LoadCalibration(path);
  ASSERT_TRUE(back) << back.error().Format();
  ASSERT_EQ(back.value().sensing.size(), 3u);
  EXPECT_EQ(back.value().sensing[0].first, "gain");
  EXPECT_DOUBLE_EQ(std::stod(back.value().sensing[0].second), 8.57143);
  EXPECT_EQ(back.value().sensing[1].first, "threshold");
  EXPECT_DOUBLE_EQ(std::stod(back.value().sensing[1].second), 30.0);
  EXPECT_EQ(back.value().sensing[2],
            std::make_pair(std::string("threshold_mode"), std::string("\"fixed\"")));
}

TEST(Calibration, SensingThatIsNotAMapOfValuesIsNamed) {
  const std::string head =
      "%YAML:1.0\nimage_width: 640\nimage_height: 480\n"
      "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
      "  data: [640, 0, 320, 0, 640, 240, 0, 0, 1]\n"
      "dist_coeffs: !!opencv-matrix\n  rows: 1\n  cols: 5\n  dt: d\n  data: [0, 0, 0, 0, 0]\n"
      "camera_to_table: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
      "  data: [0.1, 0, 0, 0, -0.1, 48, 0, 0, 1]\n";
  Result<Calibration> r =
      LoadCalibration(WriteFile("sensing_list.yaml", head + "sensing: [1, 2]\n"));
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("field 'sensing' must be a map"));
  r = LoadCalibration(WriteFile("sensing_nested.yaml", head + "sensing:\n  gain: [1, 2]\n"));
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("sensing_nested.yaml: field 'sensing.gain'"));
}

TEST(Calibration, MissingFileNamesIt) {
  Result<Calibration> r = LoadCalibration("/no/such/dir/calib.yaml");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), "/no/such/dir/calib.yaml: calibration file not found");
}

TEST(Calibration, MalformedYamlNamesTheFile) {
  const std::string path =
      WriteFile("malformed.yaml", "%YAML:1.0\ncamera_matrix: [1, 2\n  : : :\n");
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr(path + ": not a valid OpenCV YAML file"));
}

TEST(Calibration, EmptyOrHeaderlessFileSaysWhatIsWrong) {
  const std::string empty = WriteFile("empty.yaml", "");
  Result<Calibration> r = LoadCalibration(empty);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), empty + ": calibration file is empty");
  const std::string headerless = WriteFile("headerless.yaml", "image_width: 640\n");
  r = LoadCalibration(headerless);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(),
            headerless + ": not an OpenCV YAML file: the first line must be %YAML:1.0");
}

TEST(Calibration, ADepthCamerasPlaneRoundTripsAndMustHaveAUnitNormal) {
  Calibration c = CalibrationFromModel(DistortedModel());
  const double n[3] = {0.06, -0.04, -0.9974};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  c.depthPlane = (cv::Mat_<double>(1, 4) << n[0] / len, n[1] / len, n[2] / len, 1012.5);
  const std::string path = ::testing::TempDir() + "/depth_plane.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> back = LoadCalibration(path);
  ASSERT_TRUE(back) << back.error().Format();
  ASSERT_EQ(back.value().depthPlane.size(), cv::Size(4, 1));
  // written in full precision: read back within a rounding of the last digit
  EXPECT_LE(cv::norm(back.value().depthPlane, c.depthPlane, cv::NORM_INF), 1e-12);
  // an IR camera's file has none
  ASSERT_FALSE(SaveCalibration(path, CalibrationFromModel(DistortedModel())));
  Result<Calibration> none = LoadCalibration(path);
  ASSERT_TRUE(none) << none.error().Format();
  EXPECT_TRUE(none.value().depthPlane.empty());
  // a normal that is not of unit length is named
  c.depthPlane = (cv::Mat_<double>(1, 4) << 0.0, 0.0, -2.0, 1000.0);
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> bad = LoadCalibration(path);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().Format(),
            path + ": field 'depth_plane' must start with a unit normal (its length is 2)");
}

TEST(Calibration, MissingFieldIsNamed) {
  const std::string path = WriteFile("nofield.yaml",
                                     "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                     "dist_coeffs: !!opencv-matrix\n  rows: 1\n  cols: 5\n  dt: d\n"
                                     "  data: [0, 0, 0, 0, 0]\n");
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), path + ": field 'camera_matrix' is missing");
}

TEST(Calibration, MisshapenFieldIsNamed) {
  const std::string path = WriteFile("misshapen.yaml",
                                     "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                     "camera_matrix: !!opencv-matrix\n  rows: 2\n  cols: 3\n  dt: "
                                     "d\n  data: [1, 0, 0, 0, 1, 0]\n");
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), path + ": field 'camera_matrix' must be a 3x3 matrix (got 2x3)");
}

TEST(Calibration, WrongTypeFieldIsNamed) {
  const std::string path =
      WriteFile("wrongtype.yaml", "%YAML:1.0\n---\nimage_width: wide\nimage_height: 480\n");
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().Format(), path + ": field 'image_width' must be a positive integer");
}

TEST(Calibration, SingularHomographyIsRejected) {
  Calibration c = LinearCalibration({640, 480}, TableParams{});
  c.cameraToTable = cv::Matx33d::zeros();
  const std::string path = ::testing::TempDir() + "/singular.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(),
              HasSubstr(path + ": field 'camera_to_table' must be a finite, invertible"));
}

TEST(Calibration, BackgroundOfWrongSizeIsRejected) {
  Calibration c = LinearCalibration({640, 480}, TableParams{});
  c.background = cv::Mat(10, 10, CV_8UC1, cv::Scalar(0));
  const std::string path = ::testing::TempDir() + "/smallbg.yaml";
  ASSERT_FALSE(SaveCalibration(path, c));
  Result<Calibration> r = LoadCalibration(path);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr(path + ": field 'background' must be an 8-bit"));
}

TEST(Calibration, UnsupportedDistortionTermsAreRejected) {
  Calibration c = LinearCalibration({640, 480}, TableParams{});
  c.distCoeffs = cv::Mat::zeros(1, 8, CV_64F);
  c.distCoeffs.at<double>(0, 6) = 0.1;
  Result<CameraModel> m = ModelFromCalibration(c, "calib.yaml");
  ASSERT_FALSE(m);
  EXPECT_THAT(m.error().Format(), HasSubstr("calib.yaml: field 'dist_coeffs'"));
}

TEST(Calibration, DirectoryIsNotAFile) {
  Result<Calibration> r = LoadCalibration(::testing::TempDir());
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().Format(), HasSubstr("is a directory"));
}

}  // namespace
}  // namespace pg
