// The camera model and the calibration file: lens distortion (OpenCV's model), the camera-to-table
// homography, the table-to-display map and an optional background frame. Files are YAML written
// with cv::FileStorage (the OpenCV convention). Conventions are in docs/sensing.md.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/table.h"

#include <opencv2/core.hpp>

#include <string>
#include <utility>
#include <vector>

namespace pg {

/// A pinhole camera with OpenCV radial/tangential distortion looking at the table. Camera pixels
/// have (0, 0) at the centre of the top-left pixel, x right, y down.
struct CameraModel {
  cv::Size imageSize{640, 480};
  cv::Matx33d cameraMatrix = cv::Matx33d::eye();   ///< intrinsics K, pixels
  cv::Vec<double, 5> distCoeffs{0, 0, 0, 0, 0};    ///< k1, k2, p1, p2, k3, non-dimensional
  cv::Matx33d cameraToTable = cv::Matx33d::eye();  ///< undistorted camera px -> table cm

  /// True when any distortion coefficient is non-zero.
  bool HasDistortion() const;
  /// Applies the lens distortion to an undistorted pixel position, px.
  Vec2 Distort(const Vec2& undistortedPx) const;
  /// Removes the lens distortion from a camera pixel position (Newton iteration), px.
  Vec2 Undistort(const Vec2& px) const;
  /// Maps a camera pixel (distorted, as the camera sees it) to the table, cm.
  Vec2 CameraToTable(const Vec2& px) const;
  /// Maps a table point (cm) to the camera pixel that sees it, px.
  Vec2 TableToCamera(const Vec2& table) const;
  /// Local table size of one camera pixel near px: sqrt(|det J|) of CameraToTable, cm/px.
  double CmPerPixel(const Vec2& px) const;
};

/// What a calibration file holds. Fields and units are listed in docs/sensing.md.
struct Calibration {
  cv::Size imageSize{640, 480};                     ///< camera image size, px
  cv::Mat cameraMatrix;                             ///< 3x3 CV_64F intrinsics, px
  cv::Mat distCoeffs;                               ///< 1xN CV_64F (N = 4, 5, 8, ...), OpenCV order
  cv::Matx33d cameraToTable = cv::Matx33d::eye();   ///< undistorted camera px -> table cm
  cv::Matx33d tableToDisplay = cv::Matx33d::eye();  ///< table cm -> display px
  cv::Mat background;  ///< optional CV_8UC1 clear-table frame of imageSize; empty when absent
  /// Optional, depth cameras: the table's plane in the camera frame as 1x4 CV_64F (nx, ny, nz,
  /// offset mm; a point X, mm, lies n . X + offset above it), fitted with cameraMatrix as the depth
  /// camera's intrinsics (`calibrate --depth`). Empty when absent.
  cv::Mat depthPlane;
  /// Optional sensing values tuned for this table (`proxygrasp tune`): a [sensing] key and its
  /// value as TOML text ("9.2", "\"fixed\""), in file order. See ApplyCalibrationSensing.
  std::vector<std::pair<std::string, std::string>> sensing;
};

/// Reads a calibration YAML file. Errors name the file and the field ("calib.yaml: field
/// 'camera_matrix' must be a 3x3 matrix (got 3x2)"); nothing is half-loaded.
Result<Calibration> LoadCalibration(const std::string& path);

/// The same for a camera that delivers frames of `imageSize`: a file made for another size is an
/// Error naming its size fields ("calib.yaml: field 'image_width'/'image_height' is 320x240 but
/// the camera delivers 640x480").
Result<Calibration> LoadCalibration(const std::string& path, cv::Size imageSize);

/// Writes a calibration YAML file that LoadCalibration reads back.
MaybeError SaveCalibration(const std::string& path, const Calibration& calibration);

/// The calibration used when there is no file: no distortion, the whole image maps linearly onto
/// the whole table (image top = table far edge, y up), and the table onto a 1024x768 display.
Calibration LinearCalibration(cv::Size image, const TableParams& table);

/// The camera model of a calibration (the first five distortion coefficients are used; the others
/// must be zero). Errors name `source` and the field.
Result<CameraModel> ModelFromCalibration(const Calibration& calibration,
                                         const std::string& source = "calibration");

/// A calibration that holds exactly the given camera model.
Calibration CalibrationFromModel(const CameraModel& model, cv::Mat background = cv::Mat());

/// Maps table cm onto a display of displaySize px with y flipped (display y points down).
cv::Matx33d DefaultTableToDisplay(const TableParams& table, cv::Size displaySize = {1024, 768});

}  // namespace pg
