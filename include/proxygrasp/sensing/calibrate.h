// The calibration computation behind `proxygrasp calibrate`, free of any window or camera: the
// chessboard the projector shows, finding it in a camera frame, fitting lens distortion and the
// camera-to-table homography, rejecting bad detections, and averaging clear-table frames into the
// background. See docs/calibration.md.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/calibration.h"

#include <opencv2/core.hpp>

#include <optional>
#include <span>
#include <vector>

namespace pg {

/// What the calibration needs to know beyond the frames.
struct CalibrateParams {
  cv::Size displaySize{1024, 768};  ///< projector resolution, display px
  int squarePx = 64;                ///< side of one chessboard square, display px
  double maxErrorCm = 0.1;  ///< a fit whose worst corner is off by more than this is rejected, cm
  bool estimateDistortion = true;  ///< fit radial distortion (else use `intrinsics`)
  /// Radial terms fitted: 1 fits k1, 2 fits k1 and k2. One extrapolates more safely beyond the
  /// board, towards the table's edges.
  int radialTerms = 1;
  /// Lens to assume when estimateDistortion is false: its camera matrix and distortion are kept and
  /// only the homography is fitted. Without it the camera is taken as distortion-free.
  std::optional<CameraModel> intrinsics;
};

/// The chessboard the projector shows, and where its corners lie on the table.
struct ChessboardTarget {
  cv::Mat displayImage;            ///< CV_8UC1 projector image: black squares on white, a marker
  cv::Size innerCorners;           ///< inner corners per row and rows (findChessboardCorners size)
  std::vector<Vec2> tableCorners;  ///< inner corners in table cm, row by row from the marker end
  cv::Matx33d tableToDisplay;      ///< table cm -> display px (the display covers the table)
  double squareCm = 0.0;           ///< side of one square on the table along x, cm
};

/// Builds the chessboard for a table: squares of params.squarePx with a one-square white margin
/// filling the display, and a black disc in the margin beyond the first inner corner's square that
/// tells the board's orientation (an under-table camera may see it mirrored). Errors when the
/// display holds fewer than 3x3 inner corners.
Result<ChessboardTarget> MakeChessboardTarget(const TableParams& table,
                                              const CalibrateParams& params);

/// Finds the chessboard in a CV_8UC1 camera frame: the inner corners refined to sub-pixel, ordered
/// as target.tableCorners (the marker decides which detected corner is the first). Errors say
/// what went wrong: no board, a partial board, no marker.
Result<std::vector<Vec2>> DetectChessboard(const cv::Mat& frame, const ChessboardTarget& target);

/// A fitted camera and how well it explains the corners.
struct CameraFit {
  CameraModel model;      ///< intrinsics, distortion and camera px -> table cm
  double rmsErrorCm = 0;  ///< RMS distance between the mapped image corners and the true ones, cm
  double maxErrorCm = 0;  ///< the worst such distance, cm
  int corners = 0;        ///< corners used
};

/// Fits the camera to corresponding image corners (px) and table corners (cm): radial distortion
/// (params.radialTerms of k1, k2) about the image centre and the homography by Levenberg-Marquardt
/// on pixel residuals when params.estimateDistortion, otherwise cv::findHomography on the points
/// undistorted with params.intrinsics. Errors on too few points, a degenerate homography, or a
/// worst corner off by more than params.maxErrorCm.
Result<CameraFit> FitCamera(std::span<const Vec2> imageCorners, std::span<const Vec2> tableCorners,
                            cv::Size imageSize, const CalibrateParams& params);

/// DetectChessboard then FitCamera on one frame.
Result<CameraFit> CalibrateFromFrame(const cv::Mat& frame, const ChessboardTarget& target,
                                     const CalibrateParams& params);

/// The per-pixel mean of clear-table frames (CV_8UC1, all the same size), rounded. Errors name the
/// first frame that is empty, of another type or of another size.
Result<cv::Mat> AverageFrames(std::span<const cv::Mat> frames);

/// The calibration file's content: the fitted camera, the table-to-display map and the background
/// (may be empty).
Calibration MakeCalibration(const CameraFit& fit, const cv::Matx33d& tableToDisplay,
                            cv::Mat background);

}  // namespace pg
