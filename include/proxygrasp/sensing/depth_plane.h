// The table's plane seen by a depth camera (issue 43, calibration): depth pixels back-projected
// through the camera's intrinsics, a robust plane fit (RANSAC, then least squares on its inliers),
// and heights measured along the plane's normal rather than along the camera's rays. A depth
// camera above a table is never exactly square to it: a tilt of 3 degrees over a 60 cm table
// changes the depth by 31 mm from edge to edge, more than a fingertip's thickness, so heights
// above the surface are taken from this plane once it is known. docs/sensing.md, "The table's
// plane".
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/calibration.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <span>

namespace pg {

/// A depth camera's pinhole intrinsics for its depth image, px. Depth is along the optical axis
/// (z), as every depth source delivers it.
struct DepthIntrinsics {
  double fx = 589.3;  ///< focal length along x, px
  double fy = 589.3;  ///< focal length along y, px
  double cx = 319.5;  ///< principal point, px
  double cy = 239.5;

  /// A Kinect v1's depth camera (horizontal field of view 57 degrees, so fx = 320 px /
  /// tan(28.5 deg) = 589.3 px at 640x480; one device calibrated by N. Burrus read 594 and 591),
  /// square pixels, the principal point at the centre, scaled to an image of `size`.
  static DepthIntrinsics KinectV1(cv::Size size);
};

/// The camera-frame point (mm; x right, y down, z along the optical axis) a depth pixel sees.
Eigen::Vector3d BackProject(const DepthIntrinsics& k, double u, double v, double zMm);

/// A plane in the camera frame: the height of a point above it is normal . X + offset (mm),
/// positive on the camera's side.
struct TablePlane {
  Eigen::Vector3d normal{0.0, 0.0, -1.0};  ///< unit, pointing from the table toward the camera
  double offset = 0.0;                     ///< mm
  double rms = 0.0;                        ///< rms distance of the inliers from the plane, mm
  int inliers = 0;                         ///< sampled readings within the tolerance
  int samples = 0;                         ///< sampled readings (pixels with a reading)

  double Height(const Eigen::Vector3d& x) const { return normal.dot(x) + offset; }
  /// The angle between the plane's normal and the camera's optical axis, degrees.
  double TiltDeg() const;
  /// The distance from the camera's centre to the plane, mm.
  double Distance() const { return offset; }
};

/// How the table's plane is fitted. The defaults are derived in docs/sensing.md.
struct PlaneFitParams {
  int step = 4;               ///< every step-th pixel of every step-th row is sampled, px
  int iterations = 300;       ///< RANSAC draws of three points
  double tolerance = 5.0;     ///< a reading within max(tolerance, tolerance_steps x its depth's
  double toleranceSteps = 2;  ///< quantisation step) of the plane is an inlier, mm and steps
  double minShare = 0.2;      ///< a candidate plane holds at least this share of the readings
  int candidates = 4;         ///< planes sought one after the other, each without the last's
  double maxTiltDeg = 45.0;   ///< the table faces the camera: its normal within this of the axis
  uint64_t seed = 1;          ///< the draws' seed: the same image gives the same plane
};

/// Finds the table's plane in a depth image (CV_16UC1 or CV_32F, mm, 0 = no reading): of the
/// planes that each hold params.minShare of the readings (sought largest first), the nearest one
/// facing the camera (tilted at most params.maxTiltDeg). A floor around the table is larger but
/// farther; walls are seen edge-on. An Error names the image's type, or says how few readings it
/// has, or why no plane qualified.
Result<TablePlane> FitTablePlane(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                 const PlaneFitParams& params = {});

/// The height of every pixel above the plane (CV_32F, mm; 0 where there is no reading).
void HeightAbovePlane(const cv::Mat& depthMm, const DepthIntrinsics& k, const TablePlane& plane,
                      cv::Mat& heightMm);

/// Per pixel of an image of `size`, the height along the plane's normal of one mm of depth along
/// the optical axis (CV_32F): a reading dz mm nearer than the surface on the same ray lies
/// dz * scale above it. 1 everywhere for a camera square to the table; for a tilted one it is the
/// cosine between the pixel's ray and the normal over the ray's z (-normal . (x', y', 1) with x',
/// y' the normalised image coordinates).
void PlaneHeightScale(const DepthIntrinsics& k, const TablePlane& plane, cv::Size size,
                      cv::Mat& scale);

/// Where the point seen at image px `px` at depth `zMm` stands on the plane: the image px of the
/// foot of its perpendicular. A raised point seen off the image centre appears outward of where it
/// stands (parallax); its foot is where it is on the table. A point on the plane is its own foot.
cv::Point2d FootPixel(const DepthIntrinsics& k, const TablePlane& plane, cv::Point2d px,
                      double zMm);

/// The intrinsics of a calibration's cameraMatrix (fx, fy, cx, cy), for the plane it holds.
DepthIntrinsics IntrinsicsOf(const Calibration& calibration);
/// A calibration's depthPlane (1x4: normal x, y, z, offset mm), or nothing when it has none.
std::optional<TablePlane> PlaneOf(const Calibration& calibration);

/// The table's top as a quadrilateral in the depth image, and its size measured on the plane.
struct TableRectangle {
  /// Corners in image px: the far left (nearest the image's top-left), far right, near right,
  /// near left, as the uncalibrated mapping has the image's top at the table's far edge.
  cv::Point2d corners[4];
  double widthMm = 0.0;  ///< mean length of the far and near edges on the plane, mm
  double depthMm = 0.0;  ///< mean length of the left and right edges on the plane, mm
  double fill = 0.0;     ///< share of the quadrilateral's pixels that lie on the plane
};

/// Finds the table's top: the largest connected region of pixels on `plane` (within the fit's
/// tolerance, with gaps up to `gapPx` closed: hands and things on the table, holes in the
/// readings), fitted with a quadrilateral. The table must lie wholly in view: a region that reaches
/// the image's border is an Error naming the border ("the table runs out of the image at its left
/// edge"), as is a region whose outline is no quadrilateral.
Result<TableRectangle> FindTableRectangle(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                          const TablePlane& plane,
                                          const PlaneFitParams& params = {}, int gapPx = 15);

/// The homography from undistorted depth-image px to table cm that puts the rectangle's corners on
/// a table of `widthCm` x `heightCm` with the proxygrasp table convention (origin at the near-left
/// corner, x right, y toward the far edge).
cv::Matx33d RectangleToTable(const TableRectangle& rect, double widthCm, double heightCm);

/// The per-pixel median of depth frames (CV_16UC1, mm, all one size), readings only: a pixel with
/// no reading in any frame is 0. Hands passing over a still table leave it. CV_32F, mm.
Result<cv::Mat> MedianDepth(std::span<const cv::Mat> frames);

/// A depth camera's calibration from frames of the table (`calibrate` with a depth source).
struct DepthCalibration {
  Calibration calibration;  ///< intrinsics, no distortion, the homography and the plane
  TablePlane plane;
  TableRectangle rectangle;
};

/// Fits the table's plane to the frames' median, finds the table top in it, checks that the top
/// measures `table` (within `sizeTolerance` of each side: a wrong --table, or another flat thing
/// taken for the table, is an Error saying both sizes), and maps the top's corners onto the table.
Result<DepthCalibration> CalibrateDepth(std::span<const cv::Mat> frames, const TableParams& table,
                                        const DepthIntrinsics& k, double sizeTolerance = 0.05);

}  // namespace pg
