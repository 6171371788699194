// The table's plane seen by a depth camera (issue 43, calibration): depth pixels back-projected
// through the camera's intrinsics, a robust plane fit (RANSAC, then least squares on its inliers),
// and heights measured along the plane's normal rather than along the camera's rays. A depth
// camera above a table is never exactly square to it: a tilt of 3 degrees over a 60 cm table
// changes the depth by 31 mm from edge to edge, more than a fingertip's thickness, so heights
// above the surface are taken from this plane once it is known. docs/sensing.md, "The table's
// plane".
#pragma once

#include "proxygrasp/core/error.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <cstdint>

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

/// The quantisation step of a Kinect v1's depth at zMm (the change in depth of one raw disparity
/// step: dz/draw = 0.1236 m / 2842.5 x (1 + (z / 0.1236 m)^2)), mm. 2.9 mm at 1 m.
double KinectDepthStep(double zMm);

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
  double minShare = 0.3;      ///< the plane must hold this share of the sampled readings
  uint64_t seed = 1;          ///< the draws' seed: the same image gives the same plane
};

/// Fits the largest plane of a depth image (CV_16UC1 or CV_32F, mm, 0 = no reading): on a table
/// seen from above that is the table. An Error names the image's type, or says how few readings
/// it has, or what share of them the best plane held.
Result<TablePlane> FitTablePlane(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                 const PlaneFitParams& params = {});

/// The height of every pixel above the plane (CV_32F, mm; 0 where there is no reading).
void HeightAbovePlane(const cv::Mat& depthMm, const DepthIntrinsics& k, const TablePlane& plane,
                      cv::Mat& heightMm);

}  // namespace pg
