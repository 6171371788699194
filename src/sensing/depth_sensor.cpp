#include "proxygrasp/sensing/depth_sensor.h"

#include "proxygrasp/sensing/depth_plane.h"
#include "proxygrasp/sensing/sensor.h"

#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <climits>

#include <algorithm>
#include <cmath>

namespace pg {

namespace {

// A strip where the side of a body above the band passes through it lies along that body: one of
// its two long sides, half its border, is within kSideReach of a hover pixel (the opening trims a
// pixel off each mask, so a pixel lies between them); a fingertip's pad meets hover only where
// its finger rises out of the band, a small share of its border. docs/sensing.md, "Touch from
// depth" (min_width).
constexpr double kSideShare = 0.4;
constexpr double kSideReach = 0.2;  // cm

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
  v.Real("min_width", p.minWidth, 0, 10, "cm",
         "a touch region narrower than this everywhere (no disk this wide fits in it) that lies "
         "along hover is the side or rim of a body above the band, such as a forearm, and is "
         "dropped (0 keeps every one)");
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
  // a calibration with the table's plane (calibrate with a depth source): heights along its
  // normal, not along the camera's axis (docs/sensing.md, "The table's plane")
  if (const std::optional<TablePlane> plane = PlaneOf(calibration))
    PlaneHeightScale(IntrinsicsOf(calibration), *plane, imageSize, next.m_heightScale);
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
  m_depth = depth;
  m_sensing = sensing;
  // the lower edge is per pixel (it follows the noise); touch_high and hover_ceiling are read by
  // every frame's classification, so they apply from the next frame as they are
  if (band && m_seeded) UpdateBand();
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
    // with the table's plane, touch_low is a height along its normal: that over the pixel's scale
    // along the axis (the noise is along the axis as it is)
    const float* scale = m_heightScale.empty() ? nullptr : m_heightScale.ptr<float>(y);
    for (int x = 0; x < m_noise.cols; ++x)
      t[x] = std::max(scale ? low / scale[x] : low, k * std::max(n[x], floor * s[x] * s[x]));
  }
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
  const bool touchAreas = Open(m_touch, m_touchRows, m_touchAreas);
  const bool hoverAreas = Open(m_hover, m_hoverRows, m_hoverAreas);
  Extract(m_touch, touchAreas ? &m_touchAreas : nullptr, m_sensing.minArea, m_depth.minWidth,
          out.blobs);
  Extract(m_hover, hoverAreas ? &m_hoverAreas : nullptr, m_depth.hoverMinArea, 0.0, out.hover);
  for (Blob& b : out.hover) b.hover = true;
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
  // one pass: the height above the surface; touch from the noise edge (m_threshold) to
  // touch_high; hover above both (it too must stand out of the pixel's noise, which far from the
  // camera is more than the band) up to hover_ceiling; both bands end half a mm short of the
  // surface's own distance, so that a pixel without a reading (0), which stands the whole
  // surface distance up, is in neither. Each edge is inclusive, as cv::inRange's. Each mask's
  // rows holding a pixel are marked for the opening.
  const float high = static_cast<float>(10.0 * m_depth.touchHigh);
  const float ceiling = static_cast<float>(10.0 * m_depth.hoverCeiling);
  constexpr float kAbove = 1e-3f;  // mm: the bands do not share their common edge
  m_height.create(m_size, CV_32F);
  m_touch.create(m_size, CV_8UC1);
  m_hover.create(m_size, CV_8UC1);
  m_touchRows.assign(static_cast<size_t>(m_size.height), 0);
  m_hoverRows.assign(static_cast<size_t>(m_size.height), 0);
  for (int y = 0; y < m_size.height; ++y) {
    const uint16_t* d = depthMm.ptr<uint16_t>(y);
    const float* s = m_surface.ptr<float>(y);
    const float* t = m_threshold.ptr<float>(y);
    float* h = m_height.ptr<float>(y);
    uint8_t* touch = m_touch.ptr<uint8_t>(y);
    uint8_t* hover = m_hover.ptr<uint8_t>(y);
    uint8_t anyTouch = 0, anyHover = 0;
    int x = 0;
#if defined(__SSE2__)
    // 16 pixels at a time, the same float operations as below
    const __m128 highV = _mm_set1_ps(high), ceilingV = _mm_set1_ps(ceiling);
    const __m128 halfV = _mm_set1_ps(0.5f), aboveV = _mm_set1_ps(kAbove);
    __m128i anyTouchV = _mm_setzero_si128(), anyHoverV = _mm_setzero_si128();
    for (; x + 16 <= m_size.width; x += 16) {
      __m128i in[4], above[4];
      for (int half = 0; half < 2; ++half) {
        const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(d + x + 8 * half));
        const __m128i wide[2] = {_mm_unpacklo_epi16(raw, _mm_setzero_si128()),
                                 _mm_unpackhi_epi16(raw, _mm_setzero_si128())};
        for (int q = 0; q < 2; ++q) {
          const int i = x + 8 * half + 4 * q;
          const __m128 sv = _mm_loadu_ps(s + i), tv = _mm_loadu_ps(t + i);
          const __m128 height = _mm_sub_ps(sv, _mm_cvtepi32_ps(wide[q]));
          const __m128 edge = _mm_sub_ps(sv, halfV);
          _mm_storeu_ps(h + i, height);
          in[2 * half + q] = _mm_castps_si128(
              _mm_and_ps(_mm_cmpge_ps(height, tv), _mm_cmple_ps(height, _mm_min_ps(highV, edge))));
          above[2 * half + q] = _mm_castps_si128(
              _mm_and_ps(_mm_cmpge_ps(height, _mm_add_ps(_mm_max_ps(highV, tv), aboveV)),
                         _mm_cmple_ps(height, _mm_min_ps(ceilingV, edge))));
        }
      }
      // all-ones lanes packed down to 255 bytes
      const __m128i touchBytes =
          _mm_packs_epi16(_mm_packs_epi32(in[0], in[1]), _mm_packs_epi32(in[2], in[3]));
      const __m128i hoverBytes =
          _mm_packs_epi16(_mm_packs_epi32(above[0], above[1]), _mm_packs_epi32(above[2], above[3]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(touch + x), touchBytes);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(hover + x), hoverBytes);
      anyTouchV = _mm_or_si128(anyTouchV, touchBytes);
      anyHoverV = _mm_or_si128(anyHoverV, hoverBytes);
    }
    anyTouch = _mm_movemask_epi8(anyTouchV) ? 255 : 0;
    anyHover = _mm_movemask_epi8(anyHoverV) ? 255 : 0;
#endif
    for (; x < m_size.width; ++x) {
      const float height = s[x] - static_cast<float>(d[x]);
      const float edge = s[x] - 0.5f;
      const uint8_t in = (height >= t[x]) & (height <= std::min(high, edge)) ? 255 : 0;
      const uint8_t above =
          (height >= std::max(high, t[x]) + kAbove) & (height <= std::min(ceiling, edge)) ? 255 : 0;
      h[x] = height;
      touch[x] = in;
      hover[x] = above;
      anyTouch |= in;
      anyHover |= above;
    }
    m_touchRows[static_cast<size_t>(y)] = anyTouch ? 1 : 0;
    m_hoverRows[static_cast<size_t>(y)] = anyHover ? 1 : 0;
  }
}

bool DepthSensor::Open(cv::Mat& mask, std::vector<uint8_t>& rows, std::vector<cv::Rect>& areas) {
  areas.clear();
  if (m_kernel.empty()) return false;
  if (m_sensing.morphology != 1) {
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, m_kernel);
    return false;
  }
  // the 3x3 cross (radius 1, the default): a pixel survives the erosion only with its rows above
  // and below holding pixels too, so only runs of three or more rows holding any can hold any
  // after the opening. Shorter runs (specks) are cleared, which is what the opening does to
  // them; the runs are opened by OpenCross3, bit for bit as cv::morphologyEx, and the rest of
  // the frame, 0 before, is 0 after.
  const int height = m_size.height;
  for (int y = 0; y < height;) {
    if (!rows[static_cast<size_t>(y)]) {
      ++y;
      continue;
    }
    int end = y;
    while (end < height && rows[static_cast<size_t>(end)]) ++end;
    if (end - y >= 3) {
      areas.emplace_back(0, y, m_size.width, end - y);
    } else {
      mask.rowRange(y, end).setTo(0);
      std::fill(rows.begin() + y, rows.begin() + end, uint8_t{0});
    }
    y = end;
  }
  if (!areas.empty()) OpenCross3(mask, m_eroded, &areas);
  return true;
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
  bool anyNear = false;
  for (int y = a; y < b && !anyNear; ++y)
    anyNear = m_touchRows[static_cast<size_t>(y)] || m_hoverRows[static_cast<size_t>(y)];
  if (anyNear) {
    cv::bitwise_or(m_touch(rows), m_hover(rows), m_scratch);
    cv::dilate(m_scratch, m_near,
               cv::getStructuringElement(cv::MORPH_RECT,
                                         cv::Size(2 * kNearMargin + 1, 2 * kNearMargin + 1)));
  } else {
    // nothing near in these rows (the masks' rows hold no pixel): the dilation would be 0
    m_near.create(rows.size(), CV_8UC1);
    m_near.setTo(0);
  }
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
}

double DepthSensor::InscribedWidth(const std::vector<cv::Point>& pixels) {
  // the region's outline filled (the holes that noise punches in a fingertip's pad do not narrow
  // it; a ring is as wide as what it encloses) on a border of 0, and each pixel's distance to the
  // nearest 0: a pixel at distance d is the centre of a disk 2d - 1 pixels across (one pixel: 1;
  // the middle of a line three wide: 3)
  const cv::Rect box = cv::boundingRect(pixels);
  const cv::Rect framed(box.x - 1, box.y - 1, box.width + 2, box.height + 2);
  m_region.create(framed.size(), CV_8UC1);
  m_region.setTo(0);
  const std::vector<std::vector<cv::Point>> outline{pixels};
  cv::drawContours(m_region, outline, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(),
                   INT_MAX, -framed.tl());
  cv::distanceTransform(m_region, m_distance, cv::DIST_L2, cv::DIST_MASK_5);
  double widest = 0.0;
  cv::minMaxLoc(m_distance, nullptr, &widest);
  return std::max(0.0, 2.0 * widest - 1.0);
}

double DepthSensor::HoverShare(const std::vector<cv::Point>& pixels, int reach) const {
  // each border pixel: is a hover pixel within `reach` px (a square)
  int near = 0;
  for (const cv::Point& p : pixels) {
    const int x0 = std::max(0, p.x - reach), x1 = std::min(m_size.width - 1, p.x + reach);
    const int y0 = std::max(0, p.y - reach), y1 = std::min(m_size.height - 1, p.y + reach);
    bool found = false;
    for (int y = y0; y <= y1 && !found; ++y) {
      const uint8_t* h = m_hover.ptr<uint8_t>(y);
      for (int x = x0; x <= x1 && !found; ++x) found = h[x] != 0;
    }
    near += found ? 1 : 0;
  }
  return pixels.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(pixels.size());
}

void DepthSensor::Extract(const cv::Mat& mask, const std::vector<cv::Rect>* areas, double minArea,
                          double minWidth, std::vector<Blob>& blobs) {
  blobs.clear();
  if (!areas) {
    cv::findContours(mask, m_contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  } else {
    // the areas are runs of rows with empty rows between them and the mask 0 outside them: each
    // region lies in one. findContours lists the regions it meets last first, so the areas from
    // the bottom give them in the order (and with the points) that the whole mask gives
    m_contours.clear();
    for (auto area = areas->rbegin(); area != areas->rend(); ++area) {
      cv::findContours(mask(*area), m_areaContours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE,
                       area->tl());
      for (std::vector<cv::Point>& c : m_areaContours) m_contours.push_back(std::move(c));
    }
  }
  const bool linear = !m_model.HasDistortion();
  for (const std::vector<cv::Point>& pixels : m_contours) {
    // cheap reject of specks, as the IR chain does
    const double cmpp = m_model.CmPerPixel(Vec2(pixels[0].x, pixels[0].y));
    const double pixelArea =
        std::abs(cv::contourArea(pixels)) + 0.5 * cv::arcLength(pixels, true) + 1.0;
    if (pixelArea * cmpp * cmpp < 0.5 * minArea) continue;
    // the side of a forearm or the rim of a palm above the band: a strip, nowhere as wide as
    // the narrowest touch, lying along the body (docs/sensing.md, "Touch from depth")
    // (the share first: it is the cheaper, and a fingertip away from hover needs no more)
    if (minWidth > 0.0 &&
        HoverShare(pixels, std::max(1, static_cast<int>(std::lround(kSideReach / cmpp)))) >=
            kSideShare &&
        InscribedWidth(pixels) * cmpp < minWidth)
      continue;

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
      // along the table plane's normal when the calibration has one
      const double scale = m_heightScale.empty()
                               ? 1.0
                               : m_heightScale.at<float>(std::clamp(cy, 0, m_size.height - 1),
                                                         std::clamp(cx, 0, m_size.width - 1));
      blob.heights[static_cast<size_t>(k)] = 0.1 * scale * Median(m_values);
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
