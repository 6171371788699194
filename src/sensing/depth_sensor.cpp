#include "proxygrasp/sensing/depth_sensor.h"

#include "proxygrasp/sensing/sensor.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace pg {

namespace {

// the least deviation a pixel's noise is taken to have at a reading of z mm is f z^2 (noise_floor
// at 1 m, growing with distance squared as a triangulating camera's depth resolution does): f
float NoiseFloorPerMm2(const DepthParams& p) {
  return static_cast<float>(p.noiseFloor * 1e-6);
}

// how far around something near the surface the surface does not learn, px (half a fingertip at
// 0.1 cm per pixel: a finger's rim, lower than the band, is not learned into the surface)
constexpr int kNearMargin = 4;

Vec2 Homography(const cv::Matx33d& h, double x, double y) {
  const double w = h(2, 0) * x + h(2, 1) * y + h(2, 2);
  return Vec2((h(0, 0) * x + h(0, 1) * y + h(0, 2)) / w, (h(1, 0) * x + h(1, 1) * y + h(1, 2)) / w);
}

// the median of values (the upper one of an even count), 0 for none; reorders values
float Median(std::vector<float>& values) {
  if (values.empty()) return 0.0f;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

void Describe(DepthParams& p, ParamVisitor& v) {
  v.Integer("surface_frames", p.surfaceFrames, 1, 600, "frames",
            {"depth frames averaged into the surface model (mean and deviation per pixel) at "
             "start; they report no contacts, so the table should be clear then",
             Apply::kRestart});
  v.Real("surface_learning", p.surfaceLearning, 0, 3600, "s",
         "time constant with which the surface follows the frames where nothing is near it (0 "
         "keeps it fixed)");
  v.Real("surface_recovery", p.surfaceRecovery, 0.01, 3600, "s",
         "time constant with which the surface follows where it reads farther than learned: "
         "something that was on the table at the start has gone");
  v.Real("touch_low", p.touchLow, 0, 10, "cm",
         "lower edge of the touch band above the surface (at least noise_factor deviations of "
         "each pixel's noise)");
  v.Real("touch_high", p.touchHigh, 0.1, 20, "cm",
         "upper edge of the touch band: a finger's thickness and the noise; above it is hover");
  v.Real("hover_ceiling", p.hoverCeiling, 0.5, 200, "cm",
         "highest a hover region reaches above the surface");
  v.Real("noise_factor", p.noiseFactor, 0, 50, "1",
         "a pixel touches only this many deviations of its own measured noise above the surface");
  v.Real("noise_floor", p.noiseFloor, 0, 100, "mm",
         "least deviation a pixel's noise is taken to have at 1 m (a Kinect v1's), growing with "
         "distance squared; a deviation measured over few frames can be far too low");
  v.Real("hover_min_area", p.hoverMinArea, 0, 10000, "cm^2", "smallest hover region kept");
  v.Real("height_radius", p.heightRadius, 0, 5, "cm",
         "a contour point's height is the median of its region's heights within this distance");
}

MaybeError DepthSensor::Configure(const DepthParams& depth, const SensingParams& sensing,
                                  const TableParams& table, cv::Size imageSize) {
  if (MaybeError s = CheckDescribed("depth", depth)) return s;
  if (MaybeError s = CheckDescribed("sensing", sensing)) return s;
  Calibration calibration;
  std::string source = "calibration";
  if (sensing.calibration.empty()) {
    calibration = LinearCalibration(imageSize, table);
  } else {
    Result<Calibration> loaded = LoadCalibration(sensing.calibration, imageSize);
    if (!loaded.ok()) return loaded.error();
    calibration = std::move(loaded.value());
    source = sensing.calibration;
  }
  Result<CameraModel> model = ModelFromCalibration(calibration, source);
  if (!model.ok()) return model.error();
  DepthSensor next;
  next.m_depth = depth;
  next.m_sensing = sensing;
  next.m_table = table;
  next.m_model = model.value();
  next.m_tableToCamera = next.m_model.cameraToTable.inv();
  next.m_size = imageSize;
  next.m_kernel = OpeningKernel(sensing.morphology);
  next.m_configured = true;
  *this = std::move(next);
  return std::nullopt;
}

MaybeError DepthSensor::SetParams(const DepthParams& depth, const SensingParams& sensing) {
  if (!m_configured) return MakeError({"depth"}, "the depth sensor is not configured");
  if (MaybeError s = CheckDescribed("depth", depth)) return s;
  if (MaybeError s = CheckDescribed("sensing", sensing)) return s;
  for (const std::string& key : RestartKeysChanged("depth", m_depth, depth))
    return MakeError({"depth." + key}, "cannot change on a configured sensor (Configure it again)");
  if (sensing.calibration != m_sensing.calibration)
    return MakeError({"sensing.calibration"},
                     "cannot change on a configured sensor (Configure it again)");
  if (sensing.morphology != m_sensing.morphology) m_kernel = OpeningKernel(sensing.morphology);
  const bool band = depth.touchLow != m_depth.touchLow ||
                    depth.noiseFactor != m_depth.noiseFactor ||
                    depth.noiseFloor != m_depth.noiseFloor;
  // the band's other edges too, over the whole image from the next frame (Learn refreshes them
  // only a band of rows at a time)
  const bool bounds =
      depth.touchHigh != m_depth.touchHigh || depth.hoverCeiling != m_depth.hoverCeiling;
  m_depth = depth;
  m_sensing = sensing;
  if (band && m_seeded)
    UpdateBand();
  else if (bounds && m_seeded)
    UpdateBounds(0, m_size.height);
  return std::nullopt;
}

void DepthSensor::UpdateBand() {
  m_threshold.create(m_noise.size(), CV_32F);
  const float low = static_cast<float>(10.0 * m_depth.touchLow);
  const float k = static_cast<float>(m_depth.noiseFactor);
  const float floor = NoiseFloorPerMm2(m_depth);
  for (int y = 0; y < m_noise.rows; ++y) {
    const float* n = m_noise.ptr<float>(y);
    const float* s = m_surface.ptr<float>(y);
    float* t = m_threshold.ptr<float>(y);
    for (int x = 0; x < m_noise.cols; ++x)
      t[x] = std::max(low, k * std::max(n[x], floor * s[x] * s[x]));
  }
  UpdateBounds(0, m_size.height);
}

MaybeError DepthSensor::SetSurface(const cv::Mat& surfaceMm, double noiseMm) {
  if (!m_configured) return MakeError({"depth"}, "the depth sensor is not configured");
  if (surfaceMm.type() != CV_32F || surfaceMm.size() != m_size)
    return MakeError({"depth"}, "the surface must be CV_32F of the configured size");
  m_surface = surfaceMm.clone();
  FillHoles(m_surface, m_surface > 0);
  m_noise = cv::Mat(m_size, CV_32F, cv::Scalar(std::max(0.0, noiseMm)));
  m_seeded = true;
  m_seedFrames = m_depth.surfaceFrames;
  UpdateBand();
  return std::nullopt;
}

const cv::Mat& DepthSensor::StageImage(DepthStage stage) const {
  switch (stage) {
    case DepthStage::kDepth:
      return m_frame;
    case DepthStage::kSurface:
      return m_surface;
    case DepthStage::kHeight:
      return m_height;
    case DepthStage::kTouch:
      return m_touch;
    case DepthStage::kHover:
      return m_hover;
  }
  return m_frame;
}

Result<ContourFrame> DepthSensor::Step(const cv::Mat& depthMm, int64_t index, double time) {
  const std::string where = "frame " + std::to_string(index);
  if (!m_configured) return MakeError({where}, "the depth sensor is not configured");
  if (depthMm.empty()) return MakeError({where}, "empty frame");
  if (depthMm.type() != CV_16UC1)
    return MakeError({where}, "frame type is " + cv::typeToString(depthMm.type()) +
                                  ", expected 16-bit depth in mm (CV_16UC1)");
  if (depthMm.size() != m_size)
    return MakeError({where}, "frame is " + std::to_string(depthMm.cols) + "x" +
                                  std::to_string(depthMm.rows) + ", expected " +
                                  std::to_string(m_size.width) + "x" +
                                  std::to_string(m_size.height));
  m_frame = depthMm;
  ContourFrame out;
  out.index = index;
  out.time = time;
  const double dt = m_haveTime ? std::max(0.0, time - m_lastTime) : 0.0;
  m_lastTime = time;
  m_haveTime = true;

  // the surface: averaged over the first frames, which report nothing
  if (!m_seeded) {
    Seed(depthMm);
    return out;
  }

  // heights, the band and the hover above it; the opening takes specks and one-pixel rims away
  Classify(depthMm);
  if (!m_kernel.empty()) {
    cv::morphologyEx(m_touch, m_touch, cv::MORPH_OPEN, m_kernel);
    cv::morphologyEx(m_hover, m_hover, cv::MORPH_OPEN, m_kernel);
  }
  Extract(m_touch, m_sensing.minArea, out.blobs);
  Extract(m_hover, m_depth.hoverMinArea, out.hover);
  Learn(depthMm, dt);
  return out;
}

void DepthSensor::Seed(const cv::Mat& depthMm) {
  if (m_seedFrames == 0) {
    m_sum = cv::Mat::zeros(m_size, CV_64F);
    m_sumSq = cv::Mat::zeros(m_size, CV_64F);
    m_count = cv::Mat::zeros(m_size, CV_32S);
  }
  for (int y = 0; y < m_size.height; ++y) {
    const uint16_t* d = depthMm.ptr<uint16_t>(y);
    double* s = m_sum.ptr<double>(y);
    double* q = m_sumSq.ptr<double>(y);
    int* c = m_count.ptr<int>(y);
    for (int x = 0; x < m_size.width; ++x) {
      if (!d[x]) continue;
      s[x] += d[x];
      q[x] += static_cast<double>(d[x]) * d[x];
      ++c[x];
    }
  }
  if (++m_seedFrames < m_depth.surfaceFrames) return;

  // mean and deviation where there were readings; holes filled from their neighbours
  m_surface.create(m_size, CV_32F);
  m_noise.create(m_size, CV_32F);
  cv::Mat valid(m_size, CV_8UC1);
  for (int y = 0; y < m_size.height; ++y) {
    const double* s = m_sum.ptr<double>(y);
    const double* q = m_sumSq.ptr<double>(y);
    const int* c = m_count.ptr<int>(y);
    float* m = m_surface.ptr<float>(y);
    float* n = m_noise.ptr<float>(y);
    uint8_t* v = valid.ptr<uint8_t>(y);
    for (int x = 0; x < m_size.width; ++x) {
      v[x] = c[x] > 0 ? 255 : 0;
      if (!c[x]) {
        m[x] = n[x] = 0.0f;
        continue;
      }
      const double mean = s[x] / c[x];
      const double var = std::max(0.0, q[x] / c[x] - mean * mean);
      m[x] = static_cast<float>(mean);
      n[x] = static_cast<float>(std::sqrt(var));
    }
  }
  FillHoles(m_surface, valid);
  FillHoles(m_noise, valid);
  m_sum.release();
  m_sumSq.release();
  m_count.release();
  m_seeded = true;
  UpdateBand();
}

void DepthSensor::Classify(const cv::Mat& depthMm) {
  // height above the surface, then each band by its per-pixel edges (UpdateBounds); a pixel
  // without a reading (0) stands the whole surface distance up, above both bands' upper edges
  depthMm.convertTo(m_float, CV_32F);
  cv::subtract(m_surface, m_float, m_height);
  cv::inRange(m_height, m_threshold, m_touchHigh, m_touch);
  cv::inRange(m_height, m_hoverLow, m_hoverHigh, m_hover);
}

void DepthSensor::UpdateBounds(int y0, int y1) {
  // touch: from the noise edge to touch_high; hover: above both up to hover_ceiling (it too must
  // stand out of the pixel's noise, which far from the camera is more than the band); both end
  // half a mm short of the surface's own distance, so that no reading (0) is in neither
  const float high = static_cast<float>(10.0 * m_depth.touchHigh);
  const float ceiling = static_cast<float>(10.0 * m_depth.hoverCeiling);
  constexpr float kAbove = 1e-3f;  // mm: the bands do not share their common edge
  m_touchHigh.create(m_size, CV_32F);
  m_hoverLow.create(m_size, CV_32F);
  m_hoverHigh.create(m_size, CV_32F);
  for (int y = y0; y < y1; ++y) {
    const float* s = m_surface.ptr<float>(y);
    const float* t = m_threshold.ptr<float>(y);
    float* th = m_touchHigh.ptr<float>(y);
    float* hl = m_hoverLow.ptr<float>(y);
    float* hh = m_hoverHigh.ptr<float>(y);
    for (int x = 0; x < m_size.width; ++x) {
      th[x] = std::min(high, s[x] - 0.5f);
      hl[x] = std::max(high, t[x]) + kAbove;
      hh[x] = std::min(ceiling, s[x] - 0.5f);
    }
  }
}

void DepthSensor::Learn(const cv::Mat& depthMm, double dt) {
  if (dt <= 0.0) return;
  // one band of rows a frame, in turn, each at the rate for the time since it last learned
  const int band = m_nextBand;
  m_nextBand = (m_nextBand + 1) % kLearnBands;
  const int y0 = band * m_size.height / kLearnBands;
  const int y1 = (band + 1) * m_size.height / kLearnBands;
  const double now = m_lastTime;
  const double since = m_bandTime[band] > 0.0 ? now - m_bandTime[band] : dt;
  m_bandTime[band] = now;
  if (since <= 0.0) return;
  const float slow = m_depth.surfaceLearning > 0.0
                         ? static_cast<float>(1.0 - std::exp(-since / m_depth.surfaceLearning))
                         : 0.0f;
  const float fast = static_cast<float>(1.0 - std::exp(-since / m_depth.surfaceRecovery));

  // where something is near (touch or hover, grown), the surface does not learn
  const int a = std::max(0, y0 - kNearMargin), b = std::min(m_size.height, y1 + kNearMargin);
  const cv::Rect rows(0, a, m_size.width, b - a);
  cv::bitwise_or(m_touch(rows), m_hover(rows), m_scratch);
  cv::dilate(m_scratch, m_near,
             cv::getStructuringElement(cv::MORPH_RECT,
                                       cv::Size(2 * kNearMargin + 1, 2 * kNearMargin + 1)));
  const float low = static_cast<float>(10.0 * m_depth.touchLow);
  const float k = static_cast<float>(m_depth.noiseFactor);
  const float floor = NoiseFloorPerMm2(m_depth);
  for (int y = y0; y < y1; ++y) {
    const uint16_t* d = depthMm.ptr<uint16_t>(y);
    const uint8_t* near = m_near.ptr<uint8_t>(y - a);
    float* s = m_surface.ptr<float>(y);
    float* n = m_noise.ptr<float>(y);
    float* t = m_threshold.ptr<float>(y);
    for (int x = 0; x < m_size.width; ++x) {
      if (!d[x] || near[x]) continue;
      const float diff = static_cast<float>(d[x]) - s[x];  // > 0: farther than the surface
      if (diff > t[x]) {
        // something that was there has gone: the surface moves back, its noise stays (a step
        // is no noise)
        s[x] += fast * diff;
        continue;
      }
      if (diff < -t[x]) continue;  // above the band's lower edge: not the surface
      // the surface itself: its mean and deviation follow slowly
      s[x] += slow * diff;
      const float var = (1.0f - slow) * (n[x] * n[x] + slow * diff * diff);
      n[x] = std::sqrt(var);
      t[x] = std::max(low, k * std::max(n[x], floor * s[x] * s[x]));
    }
  }
  UpdateBounds(y0, y1);
}

void DepthSensor::Extract(const cv::Mat& mask, double minArea, std::vector<Blob>& blobs) {
  blobs.clear();
  cv::findContours(mask, m_contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  const bool linear = !m_model.HasDistortion();
  for (const std::vector<cv::Point>& pixels : m_contours) {
    // cheap reject of specks, as the IR chain does
    const double cmpp = m_model.CmPerPixel(Vec2(pixels[0].x, pixels[0].y));
    const double pixelArea =
        std::abs(cv::contourArea(pixels)) + 0.5 * cv::arcLength(pixels, true) + 1.0;
    if (pixelArea * cmpp * cmpp < 0.5 * minArea) continue;

    Contour dense(2, static_cast<Eigen::Index>(pixels.size()));
    for (size_t k = 0; k < pixels.size(); ++k) {
      dense.col(static_cast<Eigen::Index>(k)) =
          linear ? Homography(m_model.cameraToTable, pixels[k].x, pixels[k].y)
                 : m_model.CameraToTable(Vec2(pixels[k].x, pixels[k].y));
    }
    Contour contour = ResampleClosed(MakeCounterClockwise(dense), m_sensing.spacing, 3);
    // the border pixels' centres lie half a pixel inside the region's edge: move them out
    const Eigen::Index n = contour.cols();
    if (n < 3) continue;
    Contour moved(2, n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const Vec2 tangent = contour.col((k + 1) % n) - contour.col((k + n - 1) % n);
      const double len = tangent.norm();
      const Vec2 outward = len > 0.0 ? Vec2(Vec2(tangent.y(), -tangent.x()) / len) : Vec2(0.0, 0.0);
      moved.col(k) = contour.col(k) + 0.5 * cmpp * outward;
    }
    const double area = std::abs(SignedArea(moved));
    if (area < minArea) continue;

    Blob blob;
    blob.contour = std::move(moved);
    blob.area = area;
    blob.centroid = PolygonCentroid(blob.contour);
    blob.boundsMin = blob.contour.rowwise().minCoeff();
    blob.boundsMax = blob.contour.rowwise().maxCoeff();
    // each point's height: the median of its region's heights within height_radius of it, cm
    // (robust to the noise and to the mixed pixels a depth camera gives at an edge)
    const int r = std::max(0, static_cast<int>(std::lround(m_depth.heightRadius / cmpp)));
    blob.heights.resize(static_cast<size_t>(n));
    for (Eigen::Index k = 0; k < n; ++k) {
      const Vec2 table = blob.contour.col(k);
      const Vec2 px =
          linear ? Homography(m_tableToCamera, table.x(), table.y()) : m_model.TableToCamera(table);
      const int cx = static_cast<int>(std::lround(px.x()));
      const int cy = static_cast<int>(std::lround(px.y()));
      m_values.clear();
      // every second pixel each way: a quarter of the work, and still 20 or more of them
      for (int y = std::max(0, cy - r); y <= std::min(m_size.height - 1, cy + r); y += 2) {
        const uint8_t* in = mask.ptr<uint8_t>(y);
        const float* h = m_height.ptr<float>(y);
        for (int x = std::max(0, cx - r); x <= std::min(m_size.width - 1, cx + r); x += 2) {
          if (in[x] && (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) m_values.push_back(h[x]);
        }
      }
      blob.heights[static_cast<size_t>(k)] = 0.1 * Median(m_values);
    }
    blobs.push_back(std::move(blob));
  }
  std::sort(blobs.begin(), blobs.end(),
            [](const Blob& a, const Blob& b) { return a.area > b.area; });
}

void FillHoles(cv::Mat& image, const cv::Mat& valid) {
  CV_Assert(image.type() == CV_32F && valid.type() == CV_8UC1 && image.size() == valid.size());
  if (cv::countNonZero(valid) == 0 || cv::countNonZero(valid) == static_cast<int>(valid.total()))
    return;
  // normalized convolution at growing box sizes until every hole has valid neighbours
  cv::Mat weight, value, wsum, vsum;
  valid.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::multiply(image, weight, value);
  cv::Mat missing = valid == 0;
  for (int size = 3; cv::countNonZero(missing) > 0; size = size * 2 + 1) {
    cv::boxFilter(weight, wsum, CV_32F, cv::Size(size, size), cv::Point(-1, -1), false,
                  cv::BORDER_REPLICATE);
    cv::boxFilter(value, vsum, CV_32F, cv::Size(size, size), cv::Point(-1, -1), false,
                  cv::BORDER_REPLICATE);
    for (int y = 0; y < image.rows; ++y) {
      uint8_t* m = missing.ptr<uint8_t>(y);
      const float* w = wsum.ptr<float>(y);
      const float* v = vsum.ptr<float>(y);
      float* out = image.ptr<float>(y);
      for (int x = 0; x < image.cols; ++x) {
        if (m[x] && w[x] > 0.5f) {
          out[x] = v[x] / w[x];
          m[x] = 0;
        }
      }
    }
    if (size > 4 * std::max(image.rows, image.cols)) break;
  }
}

}  // namespace pg
