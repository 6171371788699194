#include "proxygrasp/sensing/depth_plane.h"

#include "proxygrasp/core/rng.h"
#include "proxygrasp/sensing/depth_source.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace pg {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The depth at one pixel of a CV_16UC1 or CV_32FC1 image, mm (0 or not finite: no reading).
double DepthAt(const cv::Mat& depthMm, int y, int x) {
  return depthMm.type() == CV_16UC1 ? depthMm.at<uint16_t>(y, x)
                                    : static_cast<double>(depthMm.at<float>(y, x));
}

bool IsReading(double zMm) {
  return zMm > 0.0 && std::isfinite(zMm);
}

// normal . (x', y', 1) at image px (x, y), with x', y' the normalised image coordinates: a reading
// z there lies z times this plus the offset above the plane (linear in z per pixel).
struct RayDotNormal {
  double ax, ay, a0;
  RayDotNormal(const DepthIntrinsics& k, const TablePlane& plane)
      : ax(plane.normal.x() / k.fx),
        ay(plane.normal.y() / k.fy),
        a0(plane.normal.z() - ax * k.cx - ay * k.cy) {}
  double Row(int y) const { return ay * y + a0; }
};

// The sampled readings of a depth image as camera-frame points, mm.
std::vector<Eigen::Vector3d> SamplePoints(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                          int step) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>((depthMm.rows / step + 1) * (depthMm.cols / step + 1)));
  for (int y = step / 2; y < depthMm.rows; y += step) {
    for (int x = step / 2; x < depthMm.cols; x += step) {
      const double z = DepthAt(depthMm, y, x);
      if (IsReading(z)) points.push_back(BackProject(k, x, y, z));
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

// A reading's tolerance: the quantisation of its depth, or the floor, mm.
double Tolerance(double zMm, const PlaneFitParams& params) {
  return std::max(params.tolerance, params.toleranceSteps * KinectStepMm(zMm));
}

// The image of depth pixels as one check each: a CV_16UC1 or CV_32FC1 image, or an Error.
MaybeError CheckDepthImage(const cv::Mat& depthMm) {
  if (!depthMm.empty() && (depthMm.type() == CV_16UC1 || depthMm.type() == CV_32FC1)) return {};
  return MakeError({"depth image"}, cv::typeToString(depthMm.type()) +
                                        " image where depth in mm (16-bit or float, single "
                                        "channel) is expected");
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

double TablePlane::TiltDeg() const {
  // the optical axis points from the camera to the table: the normal toward the camera is -z
  const double c = std::clamp(-normal.z(), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

Result<TablePlane> FitTablePlane(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                 const PlaneFitParams& params) {
  if (MaybeError bad = CheckDepthImage(depthMm)) return *bad;
  if (params.step < 1 || params.iterations < 1 || !(params.minShare > 0.0) || params.candidates < 1)
    return MakeError({"plane fit"},
                     "step, iterations and candidates must be at least 1, the share positive");
  const std::vector<Eigen::Vector3d> points = SamplePoints(depthMm, k, params.step);
  constexpr size_t kFewest = 30;  // readings below which a plane means nothing
  if (points.size() < kFewest)
    return MakeError({"depth image"}, "only " + std::to_string(points.size()) +
                                          " sampled pixels have a reading (need " +
                                          std::to_string(kFewest) + "): no plane to fit");
  std::vector<double> tolerance(points.size());
  for (size_t i = 0; i < points.size(); ++i) tolerance[i] = Tolerance(points[i].z(), params);

  // Sequential RANSAC: the plane through three random readings that holds the most of the
  // readings left, refitted by least squares; its readings are taken away and the next is sought.
  // Each plane holding at least minShare of all readings is a candidate.
  Rng rng(params.seed);
  std::vector<Eigen::Vector3d> left = points;
  std::vector<double> leftTolerance = tolerance;
  const size_t needed =
      static_cast<size_t>(std::ceil(params.minShare * static_cast<double>(points.size())));
  std::vector<TablePlane> candidates;
  TablePlane largest;
  int largestCount = 0;
  for (int round = 0; round < params.candidates && left.size() >= std::max<size_t>(needed, 3);
       ++round) {
    const auto pick = [&] {
      return static_cast<size_t>(rng.Uniform() * static_cast<double>(left.size())) % left.size();
    };
    TablePlane best;
    int bestCount = -1;
    for (int it = 0; it < params.iterations; ++it) {
      const Eigen::Vector3d& a = left[pick()];
      const Eigen::Vector3d& b = left[pick()];
      const Eigen::Vector3d& c = left[pick()];
      const Eigen::Vector3d n = (b - a).cross(c - a);
      // three readings nearly in a line (or repeated) give no plane: their triangle's area is
      // under a square centimetre
      if (n.norm() < 2.0 * 100.0) continue;
      const TablePlane candidate = Oriented(n.normalized(), a);
      const int count = CountInliers(left, candidate, leftTolerance);
      if (count > bestCount) {
        bestCount = count;
        best = candidate;
      }
    }
    if (bestCount < 0) break;
    // least squares on the inliers, twice (the inliers of the refined plane)
    for (int pass = 0; pass < 2; ++pass) best = Refit(left, best, leftTolerance);
    const int count = CountInliers(left, best, leftTolerance);
    if (count > largestCount) {
      largestCount = count;
      largest = best;
    }
    if (static_cast<size_t>(count) < needed) break;
    candidates.push_back(best);
    size_t kept = 0;
    for (size_t i = 0; i < left.size(); ++i) {
      if (std::abs(best.Height(left[i])) <= leftTolerance[i]) continue;
      left[kept] = left[i];
      leftTolerance[kept] = leftTolerance[i];
      ++kept;
    }
    left.resize(kept);
    leftTolerance.resize(kept);
  }

  // The table: the nearest candidate facing the camera. A floor seen around a table is larger
  // but farther; walls and a desk's front are seen edge-on.
  const TablePlane* chosen = nullptr;
  for (const TablePlane& c : candidates)
    if (c.TiltDeg() <= params.maxTiltDeg && (!chosen || c.offset < chosen->offset)) chosen = &c;
  if (!chosen) {
    char text[200];
    if (candidates.empty())
      std::snprintf(text, sizeof text,
                    "the largest plane holds %.0f%% of the readings (need %.0f%%): no table in "
                    "view",
                    100.0 * largestCount / static_cast<double>(points.size()),
                    100.0 * params.minShare);
    else
      std::snprintf(text, sizeof text,
                    "no plane holding %.0f%% of the readings faces the camera (within %.0f "
                    "degrees; the largest is tilted %.0f): no table in view",
                    100.0 * params.minShare, params.maxTiltDeg, candidates.front().TiltDeg());
    return MakeError({"depth image"}, text);
  }
  TablePlane out = *chosen;
  double sumSq = 0.0;
  int inliers = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double h = out.Height(points[i]);
    if (std::abs(h) > tolerance[i]) continue;
    sumSq += h * h;
    ++inliers;
  }
  out.inliers = inliers;
  out.samples = static_cast<int>(points.size());
  out.rms = inliers > 0 ? std::sqrt(sumSq / inliers) : 0.0;
  return out;
}

void HeightAbovePlane(const cv::Mat& depthMm, const DepthIntrinsics& k, const TablePlane& plane,
                      cv::Mat& heightMm) {
  CV_Assert(depthMm.type() == CV_16UC1 || depthMm.type() == CV_32FC1);
  heightMm.create(depthMm.size(), CV_32FC1);
  const RayDotNormal dot(k, plane);
  for (int y = 0; y < depthMm.rows; ++y) {
    float* out = heightMm.ptr<float>(y);
    const double rowTerm = dot.Row(y);
    for (int x = 0; x < depthMm.cols; ++x) {
      const double z = DepthAt(depthMm, y, x);
      out[x] = IsReading(z) ? static_cast<float>(z * (dot.ax * x + rowTerm) + plane.offset) : 0.0f;
    }
  }
}

void PlaneHeightScale(const DepthIntrinsics& k, const TablePlane& plane, cv::Size size,
                      cv::Mat& scale) {
  scale.create(size, CV_32FC1);
  // a step dz along the axis is dz (n . (x', y', 1)) along the normal, negative toward the camera
  const RayDotNormal dot(k, plane);
  for (int y = 0; y < size.height; ++y) {
    float* out = scale.ptr<float>(y);
    const double row = dot.Row(y);
    for (int x = 0; x < size.width; ++x) out[x] = static_cast<float>(-(dot.ax * x + row));
  }
}

cv::Point2d FootPixel(const DepthIntrinsics& k, const TablePlane& plane, cv::Point2d px,
                      double zMm) {
  const Eigen::Vector3d x = BackProject(k, px.x, px.y, zMm);
  const Eigen::Vector3d foot = x - plane.Height(x) * plane.normal;
  return {k.fx * foot.x() / foot.z() + k.cx, k.fy * foot.y() / foot.z() + k.cy};
}

DepthIntrinsics IntrinsicsOf(const Calibration& calibration) {
  DepthIntrinsics k;
  const cv::Mat& m = calibration.cameraMatrix;
  if (m.rows != 3 || m.cols != 3 || m.type() != CV_64F) return k;
  k.fx = m.at<double>(0, 0);
  k.fy = m.at<double>(1, 1);
  k.cx = m.at<double>(0, 2);
  k.cy = m.at<double>(1, 2);
  return k;
}

std::optional<TablePlane> PlaneOf(const Calibration& calibration) {
  const cv::Mat& p = calibration.depthPlane;
  if (p.total() != 4 || p.type() != CV_64F) return std::nullopt;
  TablePlane plane;
  plane.normal = Eigen::Vector3d(p.at<double>(0), p.at<double>(1), p.at<double>(2)).normalized();
  plane.offset = p.at<double>(3);
  return plane;
}

namespace {

// Where a ray through image px (u, v) meets the plane, camera frame, mm.
Eigen::Vector3d OnPlane(const DepthIntrinsics& k, const TablePlane& plane, cv::Point2d px) {
  const Eigen::Vector3d ray((px.x - k.cx) / k.fx, (px.y - k.cy) / k.fy, 1.0);
  return ray * (-plane.offset / plane.normal.dot(ray));
}

}  // namespace

Result<TableRectangle> FindTableRectangle(const cv::Mat& depthMm, const DepthIntrinsics& k,
                                          const TablePlane& plane, const PlaneFitParams& params,
                                          int gapPx) {
  if (MaybeError bad = CheckDepthImage(depthMm)) return *bad;
  cv::Mat height;
  HeightAbovePlane(depthMm, k, plane, height);
  cv::Mat on(depthMm.size(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < depthMm.rows; ++y) {
    const float* h = height.ptr<float>(y);
    uint8_t* o = on.ptr<uint8_t>(y);
    for (int x = 0; x < depthMm.cols; ++x) {
      const double z = DepthAt(depthMm, y, x);
      if (IsReading(z) && std::abs(h[x]) <= Tolerance(z, params)) o[x] = 255;
    }
  }
  // hands and things on the table, and holes in the readings, closed over
  cv::Mat region;
  if (gapPx > 0) {
    const cv::Mat disc =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * gapPx + 1, 2 * gapPx + 1));
    cv::morphologyEx(on, region, cv::MORPH_CLOSE, disc);
  } else {
    region = on.clone();
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(region, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  if (contours.empty()) return MakeError({"depth image"}, "no pixel lies on the table's plane");
  size_t largest = 0;
  double largestArea = 0.0;
  for (size_t i = 0; i < contours.size(); ++i) {
    const double a = cv::contourArea(contours[i]);
    if (a > largestArea) {
      largestArea = a;
      largest = i;
    }
  }
  const std::vector<cv::Point>& outline = contours[largest];

  // the table must lie wholly in view: an outline running along a border for more than a tenth of
  // it has the table cut off there
  const char* borders[4] = {"left", "right", "top", "bottom"};
  int along[4] = {};
  for (const cv::Point& p : outline) {
    along[0] += p.x <= 0;
    along[1] += p.x >= depthMm.cols - 1;
    along[2] += p.y <= 0;
    along[3] += p.y >= depthMm.rows - 1;
  }
  for (int b = 0; b < 4; ++b) {
    const int length = b < 2 ? depthMm.rows : depthMm.cols;
    if (along[b] > length / 10)
      return MakeError({"depth image"}, std::string("the table runs out of the image at its ") +
                                            borders[b] +
                                            " edge: the camera must see the whole table top");
  }

  std::vector<cv::Point> hull, quad;
  cv::convexHull(outline, hull);
  const double perimeter = cv::arcLength(hull, true);
  for (double eps = 0.01; eps <= 0.1 && quad.size() != 4; eps += 0.005)
    cv::approxPolyDP(hull, quad, eps * perimeter, true);
  if (quad.size() != 4)
    return MakeError({"depth image"}, "the table top's outline is no quadrilateral (" +
                                          std::to_string(quad.size()) + " corners)");

  // far left: least x + y; far right: most x - y; near right: most x + y; near left: least x - y
  TableRectangle rect;
  const auto pick = [&](auto score) {
    cv::Point best = quad[0];
    for (const cv::Point& p : quad)
      if (score(p) > score(best)) best = p;
    return cv::Point2d(best.x, best.y);
  };
  rect.corners[0] = pick([](cv::Point p) { return -(p.x + p.y); });
  rect.corners[1] = pick([](cv::Point p) { return p.x - p.y; });
  rect.corners[2] = pick([](cv::Point p) { return p.x + p.y; });
  rect.corners[3] = pick([](cv::Point p) { return -(p.x - p.y); });

  Eigen::Vector3d c[4];
  for (int i = 0; i < 4; ++i) c[i] = OnPlane(k, plane, rect.corners[i]);
  rect.widthMm = 0.5 * ((c[1] - c[0]).norm() + (c[2] - c[3]).norm());
  rect.depthMm = 0.5 * ((c[3] - c[0]).norm() + (c[2] - c[1]).norm());
  cv::Mat inside(depthMm.size(), CV_8UC1, cv::Scalar(0));
  cv::fillConvexPoly(inside, quad, cv::Scalar(255));
  const int area = cv::countNonZero(inside);
  cv::Mat onInside;
  cv::bitwise_and(on, inside, onInside);
  rect.fill = area > 0 ? static_cast<double>(cv::countNonZero(onInside)) / area : 0.0;
  return rect;
}

cv::Matx33d RectangleToTable(const TableRectangle& rect, double widthCm, double heightCm) {
  const cv::Point2f from[4] = {rect.corners[0], rect.corners[1], rect.corners[2], rect.corners[3]};
  const cv::Point2f to[4] = {{0.0f, static_cast<float>(heightCm)},
                             {static_cast<float>(widthCm), static_cast<float>(heightCm)},
                             {static_cast<float>(widthCm), 0.0f},
                             {0.0f, 0.0f}};
  const cv::Mat h = cv::getPerspectiveTransform(from, to);
  return cv::Matx33d(h.ptr<double>());
}

}  // namespace pg

namespace pg {

Result<cv::Mat> MedianDepth(std::span<const cv::Mat> frames) {
  if (frames.empty()) return MakeError({"depth frames"}, "no frames to take the median of");
  const cv::Size size = frames.front().size();
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].type() != CV_16UC1 || frames[i].size() != size)
      return MakeError({"depth frame " + std::to_string(i)},
                       cv::typeToString(frames[i].type()) + " " + std::to_string(frames[i].cols) +
                           "x" + std::to_string(frames[i].rows) + " where " +
                           std::to_string(size.width) + "x" + std::to_string(size.height) +
                           " 16-bit depth (mm) like the first frame's is expected");
  }
  cv::Mat median(size, CV_32FC1);
  std::vector<uint16_t> values;
  values.reserve(frames.size());
  for (int y = 0; y < size.height; ++y) {
    float* out = median.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      values.clear();
      for (const cv::Mat& f : frames) {
        const uint16_t v = f.at<uint16_t>(y, x);
        if (v > 0) values.push_back(v);
      }
      if (values.empty()) {
        out[x] = 0.0f;
        continue;
      }
      const size_t mid = values.size() / 2;
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid),
                       values.end());
      out[x] = values[mid];
    }
  }
  return median;
}

Result<DepthCalibration> CalibrateDepth(std::span<const cv::Mat> frames, const TableParams& table,
                                        const DepthIntrinsics& k, double sizeTolerance) {
  Result<cv::Mat> surface = MedianDepth(frames);
  if (!surface) return surface.error();
  Result<TablePlane> plane = FitTablePlane(surface.value(), k);
  if (!plane) return plane.error();
  Result<TableRectangle> rect = FindTableRectangle(surface.value(), k, plane.value());
  if (!rect) return rect.error();
  const double widthCm = 0.1 * rect.value().widthMm, heightCm = 0.1 * rect.value().depthMm;
  if (std::abs(widthCm - table.width) > sizeTolerance * table.width ||
      std::abs(heightCm - table.height) > sizeTolerance * table.height) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "the table top measures %.1f x %.1f cm on its plane but the table is %.1f x "
                  "%.1f cm (more than %.0f%% apart): give the table's size, or clear the view of "
                  "other flat things",
                  widthCm, heightCm, table.width, table.height, 100.0 * sizeTolerance);
    return MakeError({"depth frames"}, text);
  }
  DepthCalibration out;
  out.plane = plane.value();
  out.rectangle = rect.value();
  Calibration& c = out.calibration;
  c.imageSize = surface.value().size();
  c.cameraMatrix = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  c.distCoeffs = cv::Mat::zeros(1, 5, CV_64F);
  c.cameraToTable = RectangleToTable(rect.value(), table.width, table.height);
  c.tableToDisplay = DefaultTableToDisplay(table);
  const TablePlane& p = out.plane;
  c.depthPlane = (cv::Mat_<double>(1, 4) << p.normal.x(), p.normal.y(), p.normal.z(), p.offset);
  return out;
}

}  // namespace pg
