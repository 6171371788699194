#include "proxygrasp/sensing/calibration.h"

#include "proxygrasp/core/text.h"

#include <opencv2/core/persistence.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace pg {

namespace {

Vec2 ApplyHomography(const cv::Matx33d& h, const Vec2& p) {
  const double x = h(0, 0) * p.x() + h(0, 1) * p.y() + h(0, 2);
  const double y = h(1, 0) * p.x() + h(1, 1) * p.y() + h(1, 2);
  const double w = h(2, 0) * p.x() + h(2, 1) * p.y() + h(2, 2);
  return Vec2(x / w, y / w);
}

std::string SizeText(const cv::Mat& m) {
  return std::to_string(m.rows) + "x" + std::to_string(m.cols);
}

// an image size as width x height
std::string SizeText(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

bool AllFinite(const cv::Mat& m) {
  cv::Mat d;
  m.convertTo(d, CV_64F);
  return cv::checkRange(d);
}

}  // namespace

bool CameraModel::HasDistortion() const {
  for (int i = 0; i < 5; ++i)
    if (distCoeffs[i] != 0.0) return true;
  return false;
}

Vec2 CameraModel::Distort(const Vec2& undistortedPx) const {
  if (!HasDistortion()) return undistortedPx;
  const double fx = cameraMatrix(0, 0), fy = cameraMatrix(1, 1);
  const double cx = cameraMatrix(0, 2), cy = cameraMatrix(1, 2);
  const double k1 = distCoeffs[0], k2 = distCoeffs[1], p1 = distCoeffs[2], p2 = distCoeffs[3],
               k3 = distCoeffs[4];
  // normalized coordinates, then OpenCV's radial and tangential terms
  const double x = (undistortedPx.x() - cx) / fx;
  const double y = (undistortedPx.y() - cy) / fy;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  return Vec2(xd * fx + cx, yd * fy + cy);
}

Vec2 CameraModel::Undistort(const Vec2& px) const {
  if (!HasDistortion()) return px;
  // Newton's method on Distort(u) = px with a finite-difference Jacobian, starting at px
  Vec2 u = px;
  constexpr double kStep = 1e-3;  // px, finite-difference step
  for (int iter = 0; iter < 20; ++iter) {
    const Vec2 f = Distort(u) - px;
    if (f.squaredNorm() < 1e-16) break;
    const Vec2 dx = (Distort(u + Vec2(kStep, 0.0)) - Distort(u)) / kStep;
    const Vec2 dy = (Distort(u + Vec2(0.0, kStep)) - Distort(u)) / kStep;
    const double det = dx.x() * dy.y() - dy.x() * dx.y();
    if (std::abs(det) < 1e-12) break;
    const Vec2 step((dy.y() * f.x() - dy.x() * f.y()) / det,
                    (-dx.y() * f.x() + dx.x() * f.y()) / det);
    u -= step;
    if (step.squaredNorm() < 1e-16) break;
  }
  return u;
}

Vec2 CameraModel::CameraToTable(const Vec2& px) const {
  return ApplyHomography(cameraToTable, Undistort(px));
}

Vec2 CameraModel::TableToCamera(const Vec2& table) const {
  return Distort(ApplyHomography(cameraToTable.inv(), table));
}

double CameraModel::CmPerPixel(const Vec2& px) const {
  constexpr double kStep = 0.5;  // px
  const Vec2 c = CameraToTable(px);
  const Vec2 jx = (CameraToTable(px + Vec2(kStep, 0.0)) - c) / kStep;
  const Vec2 jy = (CameraToTable(px + Vec2(0.0, kStep)) - c) / kStep;
  return std::sqrt(std::abs(jx.x() * jy.y() - jx.y() * jy.x()));
}

cv::Matx33d DefaultTableToDisplay(const TableParams& table, cv::Size displaySize) {
  const double sx = displaySize.width / table.width;
  const double sy = displaySize.height / table.height;
  return cv::Matx33d(sx, 0, 0, 0, -sy, displaySize.height, 0, 0, 1);
}

Calibration LinearCalibration(cv::Size image, const TableParams& table) {
  Calibration c;
  c.imageSize = image;
  const double cx = (image.width - 1) / 2.0, cy = (image.height - 1) / 2.0;
  c.cameraMatrix = (cv::Mat_<double>(3, 3) << image.width, 0, cx, 0, image.width, cy, 0, 0, 1);
  c.distCoeffs = cv::Mat::zeros(1, 5, CV_64F);
  // pixel (u, v) covers table ((u + 0.5) sx, H - (v + 0.5) sy): the image edges are the table's
  const double sx = table.width / image.width;
  const double sy = table.height / image.height;
  c.cameraToTable = cv::Matx33d(sx, 0, 0.5 * sx, 0, -sy, table.height - 0.5 * sy, 0, 0, 1);
  c.tableToDisplay = DefaultTableToDisplay(table);
  return c;
}

Result<CameraModel> ModelFromCalibration(const Calibration& c, const std::string& source) {
  auto fail = [&](const std::string& what) { return MakeError({source}, what); };
  if (c.imageSize.width <= 0 || c.imageSize.height <= 0)
    return fail("field 'image_width'/'image_height' must be positive");
  if (c.cameraMatrix.rows != 3 || c.cameraMatrix.cols != 3)
    return fail("field 'camera_matrix' must be a 3x3 matrix (got " + SizeText(c.cameraMatrix) +
                ")");
  if (!AllFinite(c.cameraMatrix)) return fail("field 'camera_matrix' holds a non-finite number");
  CameraModel m;
  m.imageSize = c.imageSize;
  cv::Mat k;
  c.cameraMatrix.convertTo(k, CV_64F);
  m.cameraMatrix = cv::Matx33d(k.ptr<double>());
  if (m.cameraMatrix(0, 0) <= 0.0 || m.cameraMatrix(1, 1) <= 0.0)
    return fail("field 'camera_matrix' must have positive focal lengths fx, fy");
  if (!c.distCoeffs.empty()) {
    if (c.distCoeffs.rows != 1 && c.distCoeffs.cols != 1)
      return fail("field 'dist_coeffs' must be a vector (got " + SizeText(c.distCoeffs) + ")");
    cv::Mat d;
    c.distCoeffs.reshape(1, 1).convertTo(d, CV_64F);
    if (!AllFinite(d)) return fail("field 'dist_coeffs' holds a non-finite number");
    for (int i = 0; i < d.cols; ++i) {
      if (i < 5)
        m.distCoeffs[i] = d.at<double>(0, i);
      else if (d.at<double>(0, i) != 0.0)
        return fail("field 'dist_coeffs': only k1, k2, p1, p2, k3 are supported (coefficient " +
                    std::to_string(i + 1) + " is not zero)");
    }
  }
  m.cameraToTable = c.cameraToTable;
  if (!cv::checkRange(cv::Mat(c.cameraToTable)) ||
      std::abs(cv::determinant(c.cameraToTable)) < 1e-15)
    return fail("field 'camera_to_table' must be a finite, invertible 3x3 matrix");
  if (!c.background.empty() &&
      (c.background.type() != CV_8UC1 || c.background.size() != c.imageSize))
    return fail("field 'background' must be an 8-bit single-channel image of " +
                std::to_string(c.imageSize.width) + "x" + std::to_string(c.imageSize.height));
  return m;
}

Calibration CalibrationFromModel(const CameraModel& model, cv::Mat background) {
  Calibration c;
  c.imageSize = model.imageSize;
  c.cameraMatrix = cv::Mat(model.cameraMatrix).clone();
  c.distCoeffs = cv::Mat(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) c.distCoeffs.at<double>(0, i) = model.distCoeffs[i];
  c.cameraToTable = model.cameraToTable;
  c.tableToDisplay = DefaultTableToDisplay(TableParams{});
  c.background = std::move(background);
  return c;
}

MaybeError SaveCalibration(const std::string& path, const Calibration& c) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) return MakeError({path}, "cannot write calibration file");
    fs << "image_width" << c.imageSize.width;
    fs << "image_height" << c.imageSize.height;
    fs << "camera_matrix" << c.cameraMatrix;
    fs << "dist_coeffs" << c.distCoeffs;
    fs << "camera_to_table" << cv::Mat(c.cameraToTable);
    fs << "table_to_display" << cv::Mat(c.tableToDisplay);
    if (!c.background.empty()) fs << "background" << c.background;
    if (!c.depthPlane.empty()) fs << "depth_plane" << c.depthPlane;
    if (!c.sensing.empty()) {
      // numbers as numbers, quoted TOML strings as strings
      fs << "sensing"
         << "{";
      for (const auto& [key, text] : c.sensing) {
        fs << key;
        char* end = nullptr;
        const double number = std::strtod(text.c_str(), &end);
        if (!text.empty() && end == text.c_str() + text.size())
          fs << number;
        else if (text.size() >= 2 && text.front() == '"' && text.back() == '"')
          fs << text.substr(1, text.size() - 2);
        else
          fs << text;
      }
      fs << "}";
    }
    fs.release();
  } catch (const cv::Exception& e) {
    return MakeError({path}, std::string("cannot write calibration file: ") + e.what());
  }
  return std::nullopt;
}

namespace {

// reads a required matrix field of a given shape; a missing or misshapen field is an error
MaybeError ReadMatrix(const cv::FileStorage& fs, const std::string& path, const char* key, int rows,
                      int cols, cv::Mat& out) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone())
    return MakeError({path}, std::string("field '") + key + "' is missing");
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty())
    return MakeError({path},
                     std::string("field '") + key + "' is not an OpenCV matrix (!!opencv-matrix)");
  if ((rows > 0 && m.rows != rows) || (cols > 0 && m.cols != cols))
    return MakeError({path}, std::string("field '") + key + "' must be a " + std::to_string(rows) +
                                 "x" + std::to_string(cols) + " matrix (got " + SizeText(m) + ")");
  if (m.channels() != 1 || !AllFinite(m))
    return MakeError({path}, std::string("field '") + key + "' must hold finite numbers");
  m.convertTo(out, CV_64F);
  return std::nullopt;
}

MaybeError ReadPositiveInt(const cv::FileStorage& fs, const std::string& path, const char* key,
                           int& out) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone())
    return MakeError({path}, std::string("field '") + key + "' is missing");
  if (!node.isInt() || static_cast<int>(node) <= 0)
    return MakeError({path}, std::string("field '") + key + "' must be a positive integer");
  out = static_cast<int>(node);
  return std::nullopt;
}

}  // namespace

Result<Calibration> LoadCalibration(const std::string& path) {
  if (!std::filesystem::exists(path)) return MakeError({path}, "calibration file not found");
  if (std::filesystem::is_directory(path))
    return MakeError({path}, "calibration file is a directory");
  std::ifstream probe(path);
  if (!probe) return MakeError({path}, "cannot read calibration file");
  // OpenCV's YAML reader needs its header line; say so rather than "input file is invalid"
  std::string firstLine;
  if (!std::getline(probe, firstLine)) return MakeError({path}, "calibration file is empty");
  if (firstLine.rfind("%YAML", 0) != 0)
    return MakeError({path}, "not an OpenCV YAML file: the first line must be %YAML:1.0");

  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    // OpenCV's parser messages carry the line; keep the useful tail
    std::string what = e.err.empty() ? e.what() : e.err;
    return MakeError({path}, "not a valid OpenCV YAML file: " + what);
  }
  if (!fs.isOpened()) return MakeError({path}, "not a valid OpenCV YAML file");

  Calibration c;
  cv::Mat k, d, h, disp;
  // parse every field, then validate as a whole
  if (MaybeError s = ReadPositiveInt(fs, path, "image_width", c.imageSize.width)) return *s;
  if (MaybeError s = ReadPositiveInt(fs, path, "image_height", c.imageSize.height)) return *s;
  if (MaybeError s = ReadMatrix(fs, path, "camera_matrix", 3, 3, k)) return *s;
  if (MaybeError s = ReadMatrix(fs, path, "dist_coeffs", 0, 0, d)) return *s;
  if (d.rows != 1 && d.cols != 1)
    return MakeError({path}, "field 'dist_coeffs' must be a vector (got " + SizeText(d) + ")");
  if (MaybeError s = ReadMatrix(fs, path, "camera_to_table", 3, 3, h)) return *s;
  c.cameraMatrix = k;
  c.distCoeffs = d.reshape(1, 1).clone();
  c.cameraToTable = cv::Matx33d(h.ptr<double>());
  // table_to_display is optional: the app falls back to the default display map
  if (!fs["table_to_display"].empty()) {
    if (MaybeError s = ReadMatrix(fs, path, "table_to_display", 3, 3, disp)) return *s;
    c.tableToDisplay = cv::Matx33d(disp.ptr<double>());
  } else {
    c.tableToDisplay = DefaultTableToDisplay(TableParams{});
  }
  // background is optional; when present it must be a clear-table frame of the image size
  const cv::FileNode bg = fs["background"];
  if (!bg.empty() && !bg.isNone()) {
    try {
      bg >> c.background;
    } catch (const cv::Exception&) {
      c.background.release();
    }
    if (c.background.empty())
      return MakeError({path}, "field 'background' is not an OpenCV matrix (!!opencv-matrix)");
  }

  // depth_plane is optional: the table's plane of a depth camera, a unit normal and an offset
  if (!fs["depth_plane"].empty()) {
    cv::Mat plane;
    if (MaybeError s = ReadMatrix(fs, path, "depth_plane", 1, 4, plane)) return *s;
    const double n = std::sqrt(plane.at<double>(0) * plane.at<double>(0) +
                               plane.at<double>(1) * plane.at<double>(1) +
                               plane.at<double>(2) * plane.at<double>(2));
    if (std::abs(n - 1.0) > 1e-6)
      return MakeError({path}, "field 'depth_plane' must start with a unit normal (its length is " +
                                   FormatDouble(n) + ")");
    c.depthPlane = plane;
  }

  // sensing is optional: a map of [sensing] keys to numbers or names (checked where applied)
  const cv::FileNode sensing = fs["sensing"];
  if (!sensing.empty() && !sensing.isNone()) {
    if (!sensing.isMap())
      return MakeError({path}, "field 'sensing' must be a map of sensing keys to values");
    for (cv::FileNodeIterator it = sensing.begin(); it != sensing.end(); ++it) {
      const cv::FileNode value = *it;
      const std::string key = value.name();
      if (value.isInt() || value.isReal()) {
        c.sensing.emplace_back(key, FormatDouble(static_cast<double>(value)));
      } else if (value.isString()) {
        c.sensing.emplace_back(key, "\"" + static_cast<std::string>(value) + "\"");
      } else {
        return MakeError({path}, "field 'sensing." + key + "' must be a number or a name");
      }
    }
  }

  Result<CameraModel> model = ModelFromCalibration(c, path);
  if (!model) return model.error();
  return c;
}

Result<Calibration> LoadCalibration(const std::string& path, cv::Size imageSize) {
  Result<Calibration> c = LoadCalibration(path);
  if (!c) return c;
  if (c.value().imageSize != imageSize)
    return MakeError({path}, "field 'image_width'/'image_height' is " +
                                 SizeText(c.value().imageSize) + " but the camera delivers " +
                                 SizeText(imageSize));
  return c;
}

}  // namespace pg
