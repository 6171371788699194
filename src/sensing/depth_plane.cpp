#include "proxygrasp/sensing/depth_plane.h"

#include "proxygrasp/core/rng.h"

#include <Eigen/Eigenvalues>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace pg {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The sampled readings of a depth image as camera-frame points, mm.
std::vector<Eigen::Vector3d> SamplePoints(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                          int step) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>((depthMm.rows / step + 1) * (depthMm.cols / step + 1)));
  for (int y = step / 2; y < depthMm.rows; y += step) {
    for (int x = step / 2; x < depthMm.cols; x += step) {
      const double z = depthMm.type() == CV_16UC1 ? depthMm.at<uint16_t>(y, x)
                                                  : static_cast<double>(depthMm.at<float>(y, x));
      if (z > 0.0 && std::isfinite(z)) points.push_back(BackProject(k, x, y, z));
    }
  }
  return points;
}

// A plane with its normal toward the camera (the camera's centre, the origin, has a positive
// height), from a unit normal n and a point on it.
TablePlane Oriented(Eigen::Vector3d n, const Eigen::Vector3d& on) {
  TablePlane plane;
  double offset = -n.dot(on);
  if (offset < 0.0) {
    n = -n;
    offset = -offset;
  }
  plane.normal = n;
  plane.offset = offset;
  return plane;
}

// A point's tolerance: the quantisation of its depth, or the floor.
double Tolerance(const Eigen::Vector3d& p, const PlaneFitParams& params) {
  return std::max(params.tolerance, params.toleranceSteps * KinectDepthStep(p.z()));
}

int CountInliers(const std::vector<Eigen::Vector3d>& points, const TablePlane& plane,
                 const std::vector<double>& tolerance) {
  int count = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(plane.Height(points[i])) <= tolerance[i]) ++count;
  return count;
}

// The least-squares plane of the inliers of `plane`: through their centroid, normal along the
// covariance's smallest eigenvector.
TablePlane Refit(const std::vector<Eigen::Vector3d>& points, const TablePlane& plane,
                 const std::vector<double>& tolerance) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::abs(plane.Height(points[i])) > tolerance[i]) continue;
    sum += points[i];
    ++n;
  }
  if (n < 3) return plane;
  const Eigen::Vector3d centroid = sum / n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::abs(plane.Height(points[i])) > tolerance[i]) continue;
    const Eigen::Vector3d d = points[i] - centroid;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  // eigenvalues ascend: the first vector is the normal
  return Oriented(solver.eigenvectors().col(0).normalized(), centroid);
}

}  // namespace

DepthIntrinsics DepthIntrinsics::KinectV1(cv::Size size) {
  constexpr double kHalfFovDeg = 28.5;  // half of the 57 degree horizontal field of view
  DepthIntrinsics k;
  k.fx = 0.5 * size.width / std::tan(kHalfFovDeg * kPi / 180.0);
  k.fy = k.fx;
  k.cx = 0.5 * (size.width - 1);
  k.cy = 0.5 * (size.height - 1);
  return k;
}

Eigen::Vector3d BackProject(const DepthIntrinsics& k, double u, double v, double zMm) {
  return {(u - k.cx) * zMm / k.fx, (v - k.cy) * zMm / k.fy, zMm};
}

double KinectDepthStep(double zMm) {
  // z = a tan(raw / b + c) with a = 123.6 mm, b = 2842.5: dz/draw = (a / b) sec^2 = (a / b)
  // (1 + (z / a)^2)
  constexpr double a = 123.6, b = 2842.5;
  const double t = zMm / a;
  return a / b * (1.0 + t * t);
}

double TablePlane::TiltDeg() const {
  // the optical axis points from the camera to the table: the normal toward the camera is -z
  const double c = std::clamp(-normal.z(), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

Result<TablePlane> FitTablePlane(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                 const PlaneFitParams& params) {
  if (depthMm.empty() || (depthMm.type() != CV_16UC1 && depthMm.type() != CV_32FC1))
    return MakeError({"depth image"}, cv::typeToString(depthMm.type()) +
                                          " image where depth in mm (16-bit or float, single "
                                          "channel) is expected");
  if (params.step < 1 || params.iterations < 1 || !(params.minShare > 0.0))
    return MakeError({"plane fit"}, "step and iterations must be at least 1, the share positive");
  const std::vector<Eigen::Vector3d> points = SamplePoints(depthMm, k, params.step);
  constexpr size_t kFewest = 30;  // readings below which a plane means nothing
  if (points.size() < kFewest)
    return MakeError({"depth image"}, "only " + std::to_string(points.size()) +
                                          " sampled pixels have a reading (need " +
                                          std::to_string(kFewest) + "): no plane to fit");
  std::vector<double> tolerance(points.size());
  for (size_t i = 0; i < points.size(); ++i) tolerance[i] = Tolerance(points[i], params);

  // RANSAC: the plane through three random readings that holds the most of them
  Rng rng(params.seed);
  const auto pick = [&] {
    return static_cast<size_t>(rng.Uniform() * static_cast<double>(points.size())) %
           points.size();
  };
  TablePlane best;
  int bestCount = -1;
  for (int it = 0; it < params.iterations; ++it) {
    const Eigen::Vector3d& a = points[pick()];
    const Eigen::Vector3d& b = points[pick()];
    const Eigen::Vector3d& c = points[pick()];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    // three readings nearly in a line (or repeated) give no plane: their triangle's area is under
    // a square centimetre
    if (n.norm() < 2.0 * 100.0) continue;
    const TablePlane candidate = Oriented(n.normalized(), a);
    const int count = CountInliers(points, candidate, tolerance);
    if (count > bestCount) {
      bestCount = count;
      best = candidate;
    }
  }
  if (bestCount < 0)
    return MakeError({"depth image"}, "its readings lie in a line: no plane to fit");
  // least squares on the inliers, twice (the inliers of the refined plane)
  for (int pass = 0; pass < 2; ++pass) best = Refit(points, best, tolerance);

  double sumSq = 0.0;
  int inliers = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double h = best.Height(points[i]);
    if (std::abs(h) > tolerance[i]) continue;
    sumSq += h * h;
    ++inliers;
  }
  best.inliers = inliers;
  best.samples = static_cast<int>(points.size());
  best.rms = inliers > 0 ? std::sqrt(sumSq / inliers) : 0.0;
  const double share = static_cast<double>(inliers) / static_cast<double>(points.size());
  if (share < params.minShare) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the largest plane holds %.0f%% of the readings (need %.0f%%): no table in view",
                  100.0 * share, 100.0 * params.minShare);
    return MakeError({"depth image"}, text);
  }
  return best;
}

void HeightAbovePlane(const cv::Mat& depthMm, const DepthIntrinsics& k, const TablePlane& plane,
                      cv::Mat& heightMm) {
  CV_Assert(depthMm.type() == CV_16UC1 || depthMm.type() == CV_32FC1);
  heightMm.create(depthMm.size(), CV_32FC1);
  // normal . X + offset with X = z ((u - cx) / fx, (v - cy) / fy, 1): linear in z per pixel
  const double nx = plane.normal.x() / k.fx, ny = plane.normal.y() / k.fy;
  const double nz = plane.normal.z() - nx * k.cx - ny * k.cy;
  for (int y = 0; y < depthMm.rows; ++y) {
    float* out = heightMm.ptr<float>(y);
    const double rowTerm = ny * y + nz;
    for (int x = 0; x < depthMm.cols; ++x) {
      const double z = depthMm.type() == CV_16UC1 ? depthMm.at<uint16_t>(y, x)
                                                  : static_cast<double>(depthMm.at<float>(y, x));
      out[x] = z > 0.0 && std::isfinite(z)
                   ? static_cast<float>(z * (nx * x + rowTerm) + plane.offset)
                   : 0.0f;
    }
  }
}

}  // namespace pg
