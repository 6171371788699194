#include "proxygrasp/sensing/calibrate.h"

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace pg {

namespace {

using Params = Eigen::Matrix<double, 10, 1>;  // g00..g21 of the normalized homography, k1, k2

// how far beyond its board corner the orientation marker sits, in squares along each axis, and its
// radius, in squares
constexpr double kMarkerOffset = 0.5;
constexpr double kMarkerRadius = 0.3;

std::string Cm(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3f cm", v);
  return buffer;
}

Vec2 ApplyHomography(const cv::Matx33d& h, const Vec2& p) {
  const cv::Vec3d q = h * cv::Vec3d(p.x(), p.y(), 1.0);
  return Vec2(q[0] / q[2], q[1] / q[2]);
}

// the mean grey level of a 5x5 window at p, or NaN when it does not lie inside the image
double SampleMean(const cv::Mat& frame, const Vec2& p) {
  const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
  if (u < 2 || v < 2 || u >= frame.cols - 2 || v >= frame.rows - 2)
    return std::numeric_limits<double>::quiet_NaN();
  return cv::mean(frame(cv::Rect(u - 2, v - 2, 5, 5)))[0];
}

// the table-to-pixel model of the fit: a homography from normalized table points to normalized
// undistorted camera coordinates, then radial distortion
Vec2 ProjectNormalized(const Params& p, const Vec2& t) {
  const double x = p[0] * t.x() + p[1] * t.y() + p[2];
  const double y = p[3] * t.x() + p[4] * t.y() + p[5];
  const double w = p[6] * t.x() + p[7] * t.y() + 1.0;
  const Vec2 n(x / w, y / w);
  const double r2 = n.squaredNorm();
  return n * (1.0 + r2 * (p[8] + r2 * p[9]));
}

double Cost(const Params& p, const std::vector<Vec2>& table, const std::vector<Vec2>& image) {
  double sum = 0.0;
  for (size_t i = 0; i < table.size(); ++i)
    sum += (ProjectNormalized(p, table[i]) - image[i]).squaredNorm();
  return sum;
}

// Levenberg-Marquardt with a central-difference Jacobian; a few hundred corners and ten unknowns
// with radialTerms = 1 the k2 column is held at zero
void Refine(Params& p, const std::vector<Vec2>& table, const std::vector<Vec2>& image,
            int radialTerms) {
  const int n = static_cast<int>(table.size());
  double lambda = 1e-3;
  double cost = Cost(p, table, image);
  constexpr double kStep = 1e-7;  // normalized units: all unknowns are of order 1 or less
  for (int iter = 0; iter < 100; ++iter) {
    Eigen::MatrixXd jacobian(2 * n, 10);
    Eigen::VectorXd residual(2 * n);
    for (int i = 0; i < n; ++i)
      residual.segment<2>(2 * i) = ProjectNormalized(p, table[i]) - image[i];
    for (int k = 0; k < 10; ++k) {
      Params hi = p, lo = p;
      hi[k] += kStep;
      lo[k] -= kStep;
      for (int i = 0; i < n; ++i) {
        jacobian.block<2, 1>(2 * i, k) =
            (ProjectNormalized(hi, table[i]) - ProjectNormalized(lo, table[i])) / (2 * kStep);
      }
    }
    if (radialTerms < 2) jacobian.col(9).setZero();
    Eigen::Matrix<double, 10, 10> normal = jacobian.transpose() * jacobian;
    if (radialTerms < 2) normal(9, 9) = 1.0;
    const Params gradient = jacobian.transpose() * residual;
    // try damped steps until one lowers the cost
    bool improved = false;
    while (lambda < 1e10) {
      Eigen::Matrix<double, 10, 10> damped = normal;
      damped.diagonal() += lambda * normal.diagonal().cwiseMax(1e-12);
      const Params step = damped.ldlt().solve(-gradient);
      const Params next = p + step;
      const double nextCost = Cost(next, table, image);
      if (std::isfinite(nextCost) && nextCost < cost) {
        const double gain = cost - nextCost;
        p = next;
        cost = nextCost;
        lambda = std::max(lambda / 10, 1e-12);
        improved = gain > 1e-15 * (1.0 + cost);
        break;
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
}

}  // namespace

Result<ChessboardTarget> MakeChessboardTarget(const TableParams& table,
                                              const CalibrateParams& params) {
  const int s = params.squarePx;
  const cv::Size display = params.displaySize;
  // one square of white margin on every side, the board centred in what is left
  const int nx = s > 0 ? display.width / s - 2 : 0;
  const int ny = s > 0 ? display.height / s - 2 : 0;
  if (nx < 4 || ny < 4) {
    return MakeError({}, "a chessboard of " + std::to_string(s) + " px squares on a " +
                             std::to_string(display.width) + "x" + std::to_string(display.height) +
                             " display has fewer than 3x3 inner corners");
  }
  ChessboardTarget target;
  target.tableToDisplay = DefaultTableToDisplay(table, display);
  target.innerCorners = cv::Size(nx - 1, ny - 1);
  target.squareCm = s * table.width / display.width;
  const int x0 = (display.width - nx * s) / 2, y0 = (display.height - ny * s) / 2;

  // squares: the one at the marker corner is black
  target.displayImage = cv::Mat(display, CV_8UC1, cv::Scalar(255));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if ((i + j) % 2 != 0) continue;
      target.displayImage(cv::Rect(x0 + i * s, y0 + j * s, s, s)).setTo(cv::Scalar(0));
    }
  }
  // the orientation marker beyond the board's top-left corner (display px, pixel centres at +0.5)
  const double markerX = x0 - kMarkerOffset * s, markerY = y0 - kMarkerOffset * s;
  for (int v = 0; v < y0; ++v) {
    for (int u = 0; u < x0; ++u) {
      const double dx = u + 0.5 - markerX, dy = v + 0.5 - markerY;
      if (dx * dx + dy * dy <= kMarkerRadius * kMarkerRadius * s * s)
        target.displayImage.at<uint8_t>(v, u) = 0;
    }
  }
  // inner corners, row by row from the marker end, through display -> table
  const cv::Matx33d displayToTable = target.tableToDisplay.inv();
  for (int j = 1; j < ny; ++j) {
    for (int i = 1; i < nx; ++i)
      target.tableCorners.push_back(ApplyHomography(displayToTable, Vec2(x0 + i * s, y0 + j * s)));
  }
  return target;
}

Result<std::vector<Vec2>> DetectChessboard(const cv::Mat& frame, const ChessboardTarget& target) {
  if (frame.empty() || frame.type() != CV_8UC1)
    return MakeError({}, "the camera frame is empty or not 8-bit grey");
  const cv::Size pattern = target.innerCorners;
  const std::string expected =
      std::to_string(pattern.width) + "x" + std::to_string(pattern.height) + " inner corners";

  // the board, all of it; fast check skips frames without one quickly
  std::vector<cv::Point2f> found;
  const int flags =
      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
  if (!cv::findChessboardCorners(frame, pattern, found, flags)) {
    return MakeError({}, "chessboard not found (" + std::to_string(found.size()) + " of " +
                             expected +
                             " seen): is the projector on, the table clear and the whole board "
                             "in the camera's view?");
  }
  if (static_cast<int>(found.size()) != pattern.area()) {
    return MakeError({}, "too few corners: " + std::to_string(found.size()) + " of " + expected);
  }

  // sub-pixel corners, with a search window well inside one square
  double spacing = std::numeric_limits<double>::infinity();
  for (int j = 0; j < pattern.height; ++j) {
    for (int i = 0; i + 1 < pattern.width; ++i) {
      const cv::Point2f d = found[j * pattern.width + i + 1] - found[j * pattern.width + i];
      spacing = std::min(spacing, static_cast<double>(std::hypot(d.x, d.y)));
    }
  }
  const int half = std::clamp(static_cast<int>(spacing / 4), 2, 10);
  cv::cornerSubPix(frame, found, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.001));

  // the marker: which grid corner has the dark disc beyond it
  const int w = pattern.width, h = pattern.height;
  auto at = [&](int i, int j) { return Vec2(found[j * w + i].x, found[j * w + i].y); };
  const int cornerI[4] = {0, w - 1, 0, w - 1};
  const int cornerJ[4] = {0, 0, h - 1, h - 1};
  double level[4];
  for (int k = 0; k < 4; ++k) {
    const int i = cornerI[k], j = cornerJ[k];
    const int di = i == 0 ? 1 : -1, dj = j == 0 ? 1 : -1;
    // from the inner corner out to the board corner (one square) and on to the marker's centre
    const Vec2 c = at(i, j);
    level[k] = SampleMean(frame, c + (1.0 + kMarkerOffset) * (c - at(i + di, j + dj)));
  }
  int darkest = -1;
  double bright = -1.0;
  for (int k = 0; k < 4; ++k) {
    if (std::isnan(level[k])) continue;
    if (darkest < 0 || level[k] < level[darkest]) darkest = k;
    bright = std::max(bright, level[k]);
  }
  double secondDarkest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    if (k != darkest && !std::isnan(level[k])) secondDarkest = std::min(secondDarkest, level[k]);
  }
  constexpr double kMinContrast = 20.0;  // grey; the marker is as dark as the black squares
  if (darkest < 0 || !std::isfinite(secondDarkest) || bright - level[darkest] < kMinContrast ||
      secondDarkest - level[darkest] < 0.5 * (bright - level[darkest])) {
    return MakeError({},
                     "cannot tell the board's orientation: the marker disc beyond one corner is "
                     "not seen (is the board's margin inside the camera's view?)");
  }

  // reorder so the marker's corner comes first, rows along the board's own rows
  const bool flipI = cornerI[darkest] != 0, flipJ = cornerJ[darkest] != 0;
  std::vector<Vec2> ordered;
  ordered.reserve(found.size());
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) ordered.push_back(at(flipI ? w - 1 - i : i, flipJ ? h - 1 - j : j));
  }
  return ordered;
}

Result<CameraFit> FitCamera(std::span<const Vec2> imageCorners, std::span<const Vec2> tableCorners,
                            cv::Size imageSize, const CalibrateParams& params) {
  const size_t n = imageCorners.size();
  // 10 unknowns with distortion, 8 without; ask for a margin beyond that
  const size_t needed = params.estimateDistortion ? 9 : 4;
  if (n != tableCorners.size() || n < needed) {
    return MakeError({}, "too few corners to fit the camera: " + std::to_string(n) + " (need " +
                             std::to_string(needed) + ")");
  }
  CameraFit fit;
  fit.corners = static_cast<int>(n);
  CameraModel& model = fit.model;
  model.imageSize = imageSize;
  cv::Matx33d cameraToTable;

  if (params.estimateDistortion) {
    // a nominal lens: focal length = image width, principal point at the centre; only k / f^2
    // matters to the mapping, so the nominal f costs nothing (docs/calibration.md)
    const double f = imageSize.width;
    const Vec2 c((imageSize.width - 1) / 2.0, (imageSize.height - 1) / 2.0);
    model.cameraMatrix = cv::Matx33d(f, 0, c.x(), 0, f, c.y(), 0, 0, 1);

    // table points centred and scaled to about unit size; image points normalized by the lens
    Vec2 mean = Vec2::Zero();
    for (const Vec2& t : tableCorners) mean += t;
    mean /= static_cast<double>(n);
    double spread = 0.0;
    for (const Vec2& t : tableCorners) spread += (t - mean).norm();
    spread = std::max(spread / static_cast<double>(n), 1e-9);
    std::vector<Vec2> table, image;
    std::vector<cv::Point2d> tablePts, imagePts;
    for (size_t i = 0; i < n; ++i) {
      table.push_back((tableCorners[i] - mean) / spread);
      image.push_back((imageCorners[i] - c) / f);
      tablePts.emplace_back(table.back().x(), table.back().y());
      imagePts.emplace_back(image.back().x(), image.back().y());
    }

    // start from the plain homography, then fit distortion and homography together
    const cv::Mat h0 = cv::findHomography(tablePts, imagePts, 0);
    if (h0.empty() || std::abs(h0.at<double>(2, 2)) < 1e-12)
      return MakeError({}, "degenerate homography: the corners do not span the table");
    Params p;
    for (int k = 0; k < 8; ++k) p[k] = h0.at<double>(k / 3, k % 3) / h0.at<double>(2, 2);
    p[8] = p[9] = 0.0;
    Refine(p, table, image, params.radialTerms);
    model.distCoeffs = cv::Vec<double, 5>(p[8], p[9], 0, 0, 0);

    // table cm -> undistorted px = K * G * normalization; its inverse maps the camera to the table
    const cv::Matx33d g(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], 1.0);
    const cv::Matx33d normalize(1 / spread, 0, -mean.x() / spread, 0, 1 / spread,
                                -mean.y() / spread, 0, 0, 1);
    cameraToTable = (model.cameraMatrix * g * normalize).inv();
  } else {
    // a known lens (or none): undistort the corners, then one homography
    if (params.intrinsics) {
      model.cameraMatrix = params.intrinsics->cameraMatrix;
      model.distCoeffs = params.intrinsics->distCoeffs;
    } else {
      model.cameraMatrix = cv::Matx33d(imageSize.width, 0, (imageSize.width - 1) / 2.0, 0,
                                       imageSize.width, (imageSize.height - 1) / 2.0, 0, 0, 1);
    }
    std::vector<cv::Point2d> undistorted, tablePts;
    for (size_t i = 0; i < n; ++i) {
      const Vec2 u = model.Undistort(imageCorners[i]);
      undistorted.emplace_back(u.x(), u.y());
      tablePts.emplace_back(tableCorners[i].x(), tableCorners[i].y());
    }
    const cv::Mat h = cv::findHomography(undistorted, tablePts, 0);
    if (h.empty()) return MakeError({}, "degenerate homography: the corners do not span the table");
    cameraToTable = cv::Matx33d(h.ptr<double>());
  }

  // a finite, well-conditioned homography, scaled to unit norm
  const double norm = cv::norm(cameraToTable);
  if (!std::isfinite(norm) || norm == 0.0)
    return MakeError({}, "degenerate homography: not finite");
  cameraToTable *= 1.0 / norm;
  if (std::abs(cv::determinant(cameraToTable)) < 1e-12)
    return MakeError({}, "degenerate homography: it is singular (the corners are collinear?)");
  if (std::abs(cameraToTable(2, 2)) > 1e-12) cameraToTable *= 1.0 / cameraToTable(2, 2);
  model.cameraToTable = cameraToTable;

  // how far each image corner lands from where it is on the table
  double sum = 0.0;
  int worst = 0;
  for (size_t i = 0; i < n; ++i) {
    const double e = (model.CameraToTable(imageCorners[i]) - tableCorners[i]).norm();
    if (!std::isfinite(e)) return MakeError({}, "degenerate homography: a corner maps to infinity");
    sum += e * e;
    if (e > fit.maxErrorCm) {
      fit.maxErrorCm = e;
      worst = static_cast<int>(i);
    }
  }
  fit.rmsErrorCm = std::sqrt(sum / static_cast<double>(n));
  if (!(fit.maxErrorCm <= params.maxErrorCm)) {
    return MakeError({}, "the fit is off by up to " + Cm(fit.maxErrorCm) + " (corner " +
                             std::to_string(worst + 1) + ", RMS " + Cm(fit.rmsErrorCm) +
                             "), more than the limit of " + Cm(params.maxErrorCm) +
                             ": the detection or the lens model is unreliable");
  }
  return fit;
}

Result<CameraFit> CalibrateFromFrame(const cv::Mat& frame, const ChessboardTarget& target,
                                     const CalibrateParams& params) {
  Result<std::vector<Vec2>> corners = DetectChessboard(frame, target);
  if (!corners.ok()) return corners.error();
  return FitCamera(corners.value(), target.tableCorners, frame.size(), params);
}

Result<cv::Mat> AverageFrames(std::span<const cv::Mat> frames) {
  if (frames.empty()) return MakeError({}, "no clear-table frames to average");
  cv::Mat sum = cv::Mat::zeros(frames[0].size(), CV_64F);
  for (size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat& f = frames[i];
    if (f.empty() || f.type() != CV_8UC1 || f.size() != frames[0].size()) {
      return MakeError({"background frame " + std::to_string(i)},
                       "expected a non-empty 8-bit grey frame of " +
                           std::to_string(frames[0].cols) + "x" + std::to_string(frames[0].rows));
    }
    cv::accumulate(f, sum);
  }
  cv::Mat mean;
  sum.convertTo(mean, CV_8UC1, 1.0 / static_cast<double>(frames.size()));
  return mean;
}

Calibration MakeCalibration(const CameraFit& fit, const cv::Matx33d& tableToDisplay,
                            cv::Mat background) {
  Calibration c;
  c.imageSize = fit.model.imageSize;
  c.cameraMatrix = cv::Mat(fit.model.cameraMatrix).clone();
  c.distCoeffs = cv::Mat(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) c.distCoeffs.at<double>(0, i) = fit.model.distCoeffs[i];
  c.cameraToTable = fit.model.cameraToTable;
  c.tableToDisplay = tableToDisplay;
  c.background = std::move(background);
  return c;
}

}  // namespace pg
