#include "proxygrasp/sensing/sensor.h"

#include "proxygrasp/core/params.h"
#include "proxygrasp/core/units.h"

#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>

namespace pg {

namespace {

// the settling's time constant where the frame reads darker than the background, and the pace at
// which its floor follows the frames' spatial estimates (SettleDark, LowerSettleFloor)
constexpr double kDarkTime = 0.25;  // s

std::string SizeText(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

// Sample without the clamping, for a point with x in [0, cols - 2] and y in [0, rows - 2], in
// float (a 640 px image's coordinates to 1/16,000 px).
inline float SampleInterior(const uint8_t* data, size_t step, float x, float y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const uint8_t* r0 = data + static_cast<size_t>(y0) * step + x0;
  const uint8_t* r1 = r0 + step;
  const float top = r0[0] + (r0[1] - r0[0]) * fx;
  const float bottom = r1[0] + (r1[1] - r1[0]) * fx;
  return top + (bottom - top) * fy;
}

// bilinear sample of an 8-bit image at a sub-pixel position, clamped to the border
inline float Sample(const cv::Mat& img, double x, double y) {
  const int w = img.cols, h = img.rows;
  x = std::clamp(x, 0.0, w - 1.0);
  y = std::clamp(y, 0.0, h - 1.0);
  const int x0 = std::min(static_cast<int>(x), w - 2 < 0 ? 0 : w - 2);
  const int y0 = std::min(static_cast<int>(y), h - 2 < 0 ? 0 : h - 2);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const uint8_t* r0 = img.ptr<uint8_t>(y0);
  const uint8_t* r1 = img.ptr<uint8_t>(y1);
  const float top = r0[x0] + (r0[x1] - r0[x0]) * fx;
  const float bottom = r1[x0] + (r1[x1] - r1[x0]) * fx;
  return top + (bottom - top) * fy;
}

Vec2 ApplyHomography(const cv::Matx33d& h, double x, double y) {
  const double w = h(2, 0) * x + h(2, 1) * y + h(2, 2);
  return Vec2((h(0, 0) * x + h(0, 1) * y + h(0, 2)) / w, (h(1, 0) * x + h(1, 1) * y + h(1, 2)) / w);
}

// what Configure and SetParams require beyond the described ranges
// every range comes from the parameters' description
MaybeError CheckSensingParams(const SensingParams& params) {
  return CheckDescribed("sensing", params);
}

// Gives `image` a buffer of its own if it shares one of `upstream`'s (a stage that changed
// nothing showed its input), so that writing it leaves them alone.
void Unshare(cv::Mat& image, std::initializer_list<const cv::Mat*> upstream) {
  for (const cv::Mat* u : upstream) {
    if (image.data != nullptr && image.data == u->data) {
      image.release();
      return;
    }
  }
}

// One pass of a 3x3 cross (the ellipse of radius 1) over `area` of dst: each pixel there becomes
// the minimum (Min = true) or the maximum of itself and its four side neighbours in src (read
// beyond `area` where the image goes on); a neighbour beyond the image's edge is left out, as
// cv::erode and cv::dilate leave it out with their default border.
template <bool Min>
void CrossPass(const cv::Mat& src, cv::Mat& dst, const cv::Rect& area) {
  const int rows = src.rows, cols = src.cols;
  const int x0 = area.x, x1 = area.x + area.width;
  auto pick = [](uint8_t a, uint8_t b) { return Min ? std::min(a, b) : std::max(a, b); };
  for (int y = area.y; y < area.y + area.height; ++y) {
    const uint8_t* c = src.ptr<uint8_t>(y);
    // a missing row is the row itself: the minimum and the maximum do not change with it
    const uint8_t* up = y > 0 ? src.ptr<uint8_t>(y - 1) : c;
    const uint8_t* down = y + 1 < rows ? src.ptr<uint8_t>(y + 1) : c;
    uint8_t* out = dst.ptr<uint8_t>(y);
    auto one = [&](int x) {
      uint8_t v = pick(c[x], pick(up[x], down[x]));
      if (x > 0) v = pick(v, c[x - 1]);
      if (x + 1 < cols) v = pick(v, c[x + 1]);
      out[x] = v;
    };
    int x = x0;
    if (x == 0 && x < x1) one(x++);
#if defined(__SSE2__)
    // 16 pixels at a time while the right neighbour of the last, x + 16, is in the row
    for (; x + 16 <= x1 && x + 17 <= cols; x += 16) {
      const __m128i m = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + x));
      const __m128i l = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + x - 1));
      const __m128i r = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + x + 1));
      const __m128i u = _mm_loadu_si128(reinterpret_cast<const __m128i*>(up + x));
      const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(down + x));
      __m128i v;
      if constexpr (Min) {
        v = _mm_min_epu8(_mm_min_epu8(_mm_min_epu8(m, l), _mm_min_epu8(r, u)), d);
      } else {
        v = _mm_max_epu8(_mm_max_epu8(_mm_max_epu8(m, l), _mm_max_epu8(r, u)), d);
      }
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + x), v);
    }
#endif
    for (; x < x1; ++x) one(x);
  }
}

// Marks in `mask` (0 or 255, same size) the glows: pixels of `grey` brighter than `background`
// by more than `margin` grey where the background is not below `reference` by more than it
// (whole levels: grey - background > margin and reference - background <= margin), and returns
// how many there are, marked before or not. One pass, 16 pixels at a time where SSE2 is there.
size_t MarkGlows(const cv::Mat& grey, const cv::Mat& background, const cv::Mat& reference,
                 double margin, cv::Mat& mask) {
  const int above = static_cast<int>(std::floor(margin));  // the largest excess that is not more
  const uint8_t step = static_cast<uint8_t>(std::clamp(above, 0, 255));
  size_t marked = 0;
  for (int y = 0; y < grey.rows; ++y) {
    const uint8_t* g = grey.ptr<uint8_t>(y);
    const uint8_t* b = background.ptr<uint8_t>(y);
    const uint8_t* r = reference.ptr<uint8_t>(y);
    uint8_t* m = mask.ptr<uint8_t>(y);
    int x = 0;
#if defined(__SSE2__)
    const __m128i limit = _mm_set1_epi8(static_cast<char>(step));
    const __m128i zero = _mm_setzero_si128();
    // per-byte counts (each bright byte is -1, so subtracting it adds 1), summed every 255 steps
    __m128i counts = zero;
    int pending = 0;
    auto flush = [&] {
      const __m128i sums = _mm_sad_epu8(counts, zero);
      marked += static_cast<size_t>(_mm_cvtsi128_si32(sums)) +
                static_cast<size_t>(_mm_cvtsi128_si32(_mm_srli_si128(sums, 8)));
      counts = zero;
      pending = 0;
    };
    for (; x + 16 <= grey.cols; x += 16) {
      const __m128i gv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(g + x));
      const __m128i bv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + x));
      const __m128i rv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r + x));
      const __m128i mv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(m + x));
      // (g - b) saturated, less the limit, saturated: non-zero where g - b > limit; the same for
      // r - b: zero where the background is not below the reference by more than the limit
      const __m128i over = _mm_subs_epu8(_mm_subs_epu8(gv, bv), limit);
      const __m128i low = _mm_subs_epu8(_mm_subs_epu8(rv, bv), limit);
      const __m128i bright =
          _mm_andnot_si128(_mm_cmpeq_epi8(over, zero), _mm_cmpeq_epi8(low, zero));
      counts = _mm_sub_epi8(counts, bright);
      if (++pending == 255) flush();
      _mm_storeu_si128(reinterpret_cast<__m128i*>(m + x), _mm_or_si128(mv, bright));
    }
    flush();
#endif
    for (; x < grey.cols; ++x) {
      if (g[x] - b[x] > above && r[x] - b[x] <= above) {
        ++marked;
        m[x] = 255;
      }
    }
  }
  return marked;
}

// A fingertip's circle (Sensor::TipLike, Sensor::HoldOutHandLike): the 16 points of a circle of
// radius r px round (cx, cy), each marked where `onTable(x, y)` says the table shows there. One
// beyond the image does not: what the image cuts off goes on. Returns how many are marked.
constexpr int kCirclePoints = 16;
template <class OnTable>
int CircleOnTable(double cx, double cy, double r, cv::Size image, const OnTable& onTable,
                  bool (&marked)[kCirclePoints]) {
  int table = 0;
  for (int k = 0; k < kCirclePoints; ++k) {
    const double a = 2.0 * kPi * k / kCirclePoints;
    const int x = static_cast<int>(std::lround(cx + r * std::cos(a)));
    const int y = static_cast<int>(std::lround(cy + r * std::sin(a)));
    marked[k] = x >= 0 && y >= 0 && x < image.width && y < image.height && onTable(x, y);
    table += marked[k] ? 1 : 0;
  }
  return table;
}

}  // namespace

void OpenCross3(cv::Mat& image, cv::Mat& scratch, const std::vector<cv::Rect>* areas) {
  assert(image.type() == CV_8UC1 && "the cross opening takes an 8-bit single-channel image");
  const cv::Rect whole(0, 0, image.cols, image.rows);
  scratch.create(image.size(), CV_8UC1);
  if (!areas) {
    CrossPass<true>(image, scratch, whole);   // erode
    CrossPass<false>(scratch, image, whole);  // dilate
    return;
  }
  // Outside the areas the image is 0, and so is its erosion; the opening is 0 beyond the areas
  // grown by 1 px, where the image already holds it. Every erosion comes first, so each area's
  // dilation reads its ring (the areas grown by 2 px) eroded, whatever the other areas are.
  auto grown = [&](const cv::Rect& a, int by) {
    return cv::Rect(a.x - by, a.y - by, a.width + 2 * by, a.height + 2 * by) & whole;
  };
  for (const cv::Rect& a : *areas) CrossPass<true>(image, scratch, grown(a, 2));
  for (const cv::Rect& a : *areas) CrossPass<false>(scratch, image, grown(a, 1));
}

cv::Mat OpeningKernel(int radius) {
  if (radius <= 0) return cv::Mat();
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
}

MaybeError Sensor::Configure(const SensingParams& params, const TableParams& table,
                             cv::Size imageSize) {
  if (params.calibration.empty())
    return Configure(params, table, LinearCalibration(imageSize, table), "linear calibration");
  Result<Calibration> c = LoadCalibration(params.calibration, imageSize);
  if (!c) return c.error();
  return Configure(params, table, c.value(), params.calibration);
}

MaybeError Sensor::Configure(const SensingParams& params, const TableParams& table,
                             const Calibration& calibration, const std::string& source) {
  m_configured = false;
  if (MaybeError s = CheckSensingParams(params)) return s;
  Result<CameraModel> model = ModelFromCalibration(calibration, source);
  if (!model) return model.error();

  m_params = params;
  m_table = table;
  m_calibration = calibration;
  m_model = model.value();
  m_linear = !m_model.HasDistortion();
  m_background = calibration.background.empty() ? cv::Mat() : calibration.background.clone();
  ForgetLearned();
  m_haveTime = false;
  m_tableMapX.release();
  m_tableMapY.release();
  m_kernel = OpeningKernel(params.morphology);
  m_configured = true;
  return std::nullopt;
}

MaybeError Sensor::SetParams(const SensingParams& params) {
  if (!m_configured) return MakeError({"sensing"}, "the sensor is not configured");
  if (MaybeError s = CheckSensingParams(params)) return s;
  const std::vector<std::string> fixed = FixedKeysChanged(params);
  if (!fixed.empty()) {
    return MakeError({"sensing." + fixed.front()},
                     "cannot change on a configured sensor (Configure it again)");
  }
  // the kernel and the table image maps follow the values they are built from
  if (params.morphology != m_params.morphology) m_kernel = OpeningKernel(params.morphology);
  if (params.tableCmPerPixel != m_params.tableCmPerPixel) {
    m_tableMapX.release();
    m_tableMapY.release();
  }
  // a threshold mode switched to adaptive starts again from the fixed threshold
  if (params.thresholdMode != m_params.thresholdMode) {
    m_level = -1.0;
    m_brightest = 0.0;
  }
  m_params = params;
  return std::nullopt;
}

std::vector<std::string> Sensor::FixedKeysChanged(const SensingParams& params) const {
  // the keys described as needing a restart (Apply::kRestart)
  return RestartKeysChanged("sensing", m_params, params);
}

MaybeError Sensor::SetBackground(const cv::Mat& background) {
  const cv::Size expected = m_model.imageSize;
  if (background.empty() || background.type() != CV_8UC1 || background.size() != expected)
    return MakeError({"background"},
                     "must be an 8-bit grey (CV_8UC1) image of " + SizeText(expected));
  m_background = background.clone();
  ForgetLearned();
  return std::nullopt;
}

void Sensor::ForgetLearned() {
  m_learned.release();
  m_reference.release();
  m_reference8.release();
  m_warmup = false;
  m_spatial.release();
  m_settleFloor.release();
  m_lowMean.release();
  m_lowest.release();
  m_stillState.release();
  m_captureSum.release();
  m_captured = 0;
  m_noise = -1.0;
  m_level = -1.0;
  m_noisePhase = 0;
  m_noiseSum = 0.0;
  m_noiseTime = 0.0;
  m_noiseFrames = 0;
  m_brightest = 0.0;
}

Result<ContourFrame> Sensor::Step(const cv::Mat& frame, int64_t index, double time,
                                  bool wantTableImage) {
  const SourceLoc where{"frame " + std::to_string(index)};
  if (!m_configured) return MakeError(where, "the sensor is not configured");
  const cv::Size expected = m_model.imageSize;
  // reject what the pipeline cannot read, saying what it expected
  if (frame.empty())
    return MakeError(where,
                     "empty frame (expected " + SizeText(expected) + " 8-bit grey, CV_8UC1)");
  const int type = frame.type();
  if (type != CV_8UC1 && type != CV_8UC3 && type != CV_8UC4)
    return MakeError(where, "frame type is " + cv::typeToString(type) +
                                ", expected 8-bit grey (CV_8UC1) or colour (CV_8UC3, CV_8UC4)");
  if (frame.size() != expected)
    return MakeError(where,
                     "frame is " + SizeText(frame.size()) + ", expected " + SizeText(expected));

  ContourFrame out;
  out.index = index;
  out.time = time;

  // colour cameras: grey is all the chain looks at
  if (type == CV_8UC1)
    m_grey = frame;
  else
    cv::cvtColor(frame, m_grey, type == CV_8UC3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);

  // a still is sensed on its own: nothing from the frames before it
  if (m_params.stills) {
    m_background.release();
    ForgetLearned();
    m_haveTime = false;
  }

  // background: loaded or set, else averaged over the first frames, else estimated from this one
  if (m_background.empty()) {
    if (m_params.backgroundFrames > 0) {
      if (m_captureSum.empty()) m_captureSum = cv::Mat::zeros(expected, CV_32F);
      cv::accumulate(m_grey, m_captureSum);
      if (++m_captured >= m_params.backgroundFrames) {
        m_captureSum.convertTo(m_background, CV_8UC1, 1.0 / m_captured);
        m_captureSum.release();
      }
      return out;
    }
    // An estimate at the scale of a hand, without the fingertips and hands on the table now;
    // the warm-up then takes in what is static from the start (EstimateBackground).
    m_spatial = EstimateBackground(m_grey, PixelsPerCm());
    m_background = m_spatial.clone();
    m_grey.convertTo(m_lowMean, CV_32F);
    m_lowest = m_lowMean.clone();
    m_startTime = time;
    m_warmup = true;
  }
  const double frameDt = m_haveTime ? time - m_lastTime : 0.0;
  // before this frame is filtered: a hand that lay still through the warm-up and starts to move
  // now is a contact in this frame
  if (!m_stillState.empty() && frameDt > 0.0) TrackStillRegions(time, frameDt);
  if (m_params.thresholdMode == ThresholdMode::kAdaptive) MeasureNoise(frameDt);

  // The adaptive level: a fraction of the brightest fingertip-like touch the table has shown
  // lately (BrightestTipAbove), at least noise_factor deviations of the camera noise and at most
  // the fixed threshold, from the first frame on. Until a touch has been seen, the threshold for
  // a second and then falling by a factor e a second to the noise floor: a table whose touches
  // are bright but not yet seen does not show its glows meanwhile. The filter works out where a
  // pixel could pass the noise floor (or, once the remembered touch holds the level at the
  // threshold, the threshold: a brighter touch could not raise it further).
  double level = m_params.threshold;
  const bool adaptive = m_params.thresholdMode == ThresholdMode::kAdaptive && m_noise >= 0.0;
  double remembered = 0.0, falling = m_params.threshold, probe = level;
  bool capped = false;
  if (adaptive) {
    if (m_level < 0.0) {
      m_level = m_params.threshold;
      m_falling = m_params.threshold;
      m_fallStart = time;
      m_brightestTime = time;
    }
    constexpr double kLevelHold = 1.0;  // s at the threshold before it falls
    constexpr double kLevelFall = 1.0;  // s, its time constant
    const double held = time - m_fallStart - kLevelHold;
    if (held > 0.0) falling = m_params.threshold * std::exp(-held / kLevelFall);
    const double dt = std::max(0.0, time - m_brightestTime);
    remembered = m_brightest * std::exp(-dt / m_params.contrastMemory);
    capped = m_params.contrastFraction * remembered >= m_params.threshold;
    if (capped)
      probe = AdaptiveLevel(remembered);
    else if (m_params.stills || !WarmingUp())
      probe = AdaptiveLevel(0.0);
    else
      probe = remembered > 0.0
                  ? AdaptiveLevel(remembered)
                  : std::max(std::min(falling, m_params.threshold), AdaptiveLevel(0.0));
  }

  // the whole frame's stages when they are looked at, and where the threshold reads them all
  Filter(m_wholeStages || wantTableImage || m_params.thresholdMode == ThresholdMode::kAuto,
         adaptive ? probe : level);

  if (adaptive) {
    // The frame's own brightest touch counts at once, and is remembered, once the background
    // has warmed up. Before, against the spatial estimate, the table's own fingertip-sized
    // marks look like touches (hard-5point.avi's streaks, 90 grey above it): a camera's first
    // 0.2 s are left at the threshold, while a still, which has no later frames, takes its
    // level from them.
    const bool evidence = m_params.stills || !WarmingUp();
    const double seen = capped || !evidence ? 0.0 : BrightestTipAbove(probe);
    const double brightest = std::max(remembered, seen);
    m_brightest = WarmingUp() ? remembered : brightest;
    m_brightestTime = time;
    level = brightest > 0.0 ? AdaptiveLevel(brightest)
                            : std::max(std::min(falling, m_params.threshold), AdaptiveLevel(0.0));
    m_level = level;
  }

  // threshold, and an opening that removes specks and one-pixel bridges (no closing: holes are
  // ignored anyway, and closing would fill finger crotches and join fingers)
  if (m_params.thresholdMode == ThresholdMode::kAuto) {
    cv::Mat scratch;
    level =
        std::max(cv::threshold(m_normalized, scratch, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU),
                 m_params.autoFloor);
  }
  m_lastThreshold = level;
  cv::threshold(m_normalized, m_binary, level, 255, cv::THRESH_BINARY);
  if (!m_kernel.empty()) {
    // radius 1 (the default) is a 3x3 cross, opened by two passes of our own (OpenCross3) that
    // work only the areas the high-pass worked out: the binary image is 0 outside them, and so
    // is its opening. Over a frame of four hands that is 0.015 ms instead of OpenCV's 0.04 for
    // the whole frame (bit for bit the same image). Larger ellipses are opened by OpenCV.
    if (m_params.morphology == 1)
      OpenCross3(m_binary, m_eroded, m_areasOnly ? &m_areas : nullptr);
    else
      cv::morphologyEx(m_binary, m_binary, cv::MORPH_OPEN, m_kernel);
  }

  ExtractBlobs(out.blobs);
  LearnBackground(time);

  if (wantTableImage) {
    if (m_tableMapX.empty()) BuildTableMaps();
    out.tableImage.cmPerPixel = m_params.tableCmPerPixel;
    out.tableImage.origin = Vec2::Zero();
    cv::remap(m_normalized, out.tableImage.image, m_tableMapX, m_tableMapY, cv::INTER_LINEAR,
              cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  return out;
}

double Sensor::PixelsPerCm() const {
  const Vec2 centre(0.5 * m_model.imageSize.width, 0.5 * m_model.imageSize.height);
  return 1.0 / m_model.CmPerPixel(centre);
}

double Sensor::AdaptiveLevel(double brightest) const {
  const double noise = NoiseDeviation();
  return std::min(m_params.threshold, std::max(m_params.gain * m_params.noiseFactor * noise,
                                               m_params.contrastFraction * brightest));
}

double Sensor::BrightMargin() const {
  // 3 noise deviations of the camera (a running mean's own noise is a third of it, so noise alone
  // is 9 of its deviations off), at least a grey level; with a fixed level, half of it (the noise
  // is not measured then)
  const bool adaptive = m_params.thresholdMode == ThresholdMode::kAdaptive && m_noise >= 0.0;
  return adaptive ? std::max(3.0 * NoiseDeviation(), 1.0)
                  : std::max(1.0, 0.5 * m_params.threshold / std::max(1e-6, m_params.gain));
}

double Sensor::NoiseDeviation() const {
  // An 8-bit camera's noise is never below the rounding of frame and background to whole grey
  // levels (uniform, variance 1/12 each), even where the measured median is 0 (a noiseless image).
  const double kRounding = std::sqrt(2.0 / 12.0);
  return std::max(m_noise, kRounding);
}

bool Sensor::WarmingUp() const {
  return m_background.empty() ||
         (m_warmup && m_params.backgroundWarmup > 0.0 &&
          (m_learned.empty() || m_learnedTime <= m_params.backgroundWarmup));
}

void Sensor::MeasureNoise(double dt) {
  // |frame - background| on every 8th column of every 32nd row, the rows shifted by 8 each frame
  // (1,200 samples of a 640x480 frame; the smoothing below pools the frames): most of a frame is
  // clear table, so its median is the noise's (a hand covering less than half the frame moves it
  // little; more makes the level higher, never lower). For Gaussian noise the median of |d| is
  // 0.6745 sigma. The differences are whole grey levels: the median is interpolated within its
  // level's bin, a level k standing for [k - 0.5, k + 0.5) (0 for [0, 0.5)), so that a deviation
  // under one grey level is still measured.
  constexpr int kStep = 8, kRowStep = 32;
  std::array<int, 256> counts{};
  int n = 0;
  m_noisePhase = (m_noisePhase + kStep) % kRowStep;
  for (int y = kStep / 2 + m_noisePhase; y < m_grey.rows; y += kRowStep) {
    const uint8_t* g = m_grey.ptr<uint8_t>(y);
    const uint8_t* b = m_background.ptr<uint8_t>(y);
    for (int x = kStep / 2; x < m_grey.cols; x += kStep) ++counts[std::abs(g[x] - b[x])];
  }
  for (const int c : counts) n += c;
  if (n == 0) return;
  const double half = 0.5 * n;
  double below = 0.0, median = 255.0;
  for (int v = 0; v < 256; ++v) {
    if (below + counts[v] >= half) {
      const double start = v == 0 ? 0.0 : v - 0.5, width = v == 0 ? 0.5 : 1.0;
      median = start + width * (half - below) / counts[v];
      break;
    }
    below += counts[v];
  }
  const double sigma = median / 0.6745;
  // Against an estimated background still warming up (the spatial estimate: the table's own
  // pattern is in the differences), each frame's value on its own: it can only be too high. After
  // that, the first second after the background is seeded (or warmed up) is averaged, the mean so
  // far standing meanwhile: a compressed video copies still blocks from frame to frame, so the
  // frames just after a warm-up share their noise with the background and show less of it. Then
  // smoothed over about a second, so the level does not flicker with the frames.
  constexpr double kNoiseTime = 1.0;  // s
  if (WarmingUp()) {
    m_noise = sigma;
    m_noiseSum = 0.0;
    m_noiseFrames = 0;
    m_noiseTime = 0.0;
  } else if (m_noiseTime < kNoiseTime) {
    m_noiseSum += sigma;
    ++m_noiseFrames;
    m_noiseTime += std::max(0.0, dt);
    m_noise = m_noiseSum / m_noiseFrames;
  } else if (dt > 0.0) {
    m_noise += (1.0 - std::exp(-dt / kNoiseTime)) * (sigma - m_noise);
  }
}

double Sensor::PeakAround(cv::Point at, double level) const {
  // The highest 3x3 mean centred on `at` or one of its 8 neighbours, each pixel counted only
  // above `level` (one pixel's value adds the noise's peak): the first of a flat-topped touch's
  // brightest pixels lies on its rim, and the mean there reads the edge. Every pixel above
  // `level` lies where the filter worked, with the whole frame's value there.
  const int rows = m_normalized.rows, cols = m_normalized.cols;
  const auto value = [&](int x, int y) -> double {
    if (x < 0 || y < 0 || x >= cols || y >= rows) return 0.0;
    const uint8_t v = m_normalized.ptr<uint8_t>(y)[x];
    return v > level ? v : 0.0;
  };
  double highest = 0.0;
  for (int cy = at.y - 1; cy <= at.y + 1; ++cy) {
    for (int cx = at.x - 1; cx <= at.x + 1; ++cx) {
      double sum = 0.0;
      for (int y = cy - 1; y <= cy + 1; ++y)
        for (int x = cx - 1; x <= cx + 1; ++x) sum += value(x, y);
      highest = std::max(highest, sum / 9.0);
    }
  }
  return highest;
}

bool Sensor::TipLike(cv::Point at, double peak) const {
  // A fingertip is about 1.5 cm across: on a circle 3 cm across around its brightest pixel, most
  // of the points lie on the table (a finger's own length, and a neighbour or two pressed
  // against it, cover the rest). Inside a palm, a hot spot of the illuminator or a glow (all
  // wider than 3 cm) the whole circle is bright; a touch is "fingertip-like" when at least 5 of
  // 16 points read under half its peak. Points beyond the image count as bright.
  constexpr double kRingCm = 1.5;  // radius
  constexpr int kTableAtLeast = 5;
  bool onTable[kCirclePoints];
  // Along the spans the filtered image holds its levels; elsewhere (m_areasOnly) it holds 0, and
  // a point there whose smoothed level, gained, reaches half the peak is worked out on its own
  // (the high-pass never adds), so that the level is the whole frame's.
  const auto level = [&](int x, int y) -> double {
    const uint8_t v = m_normalized.ptr<uint8_t>(y)[x];
    if (!m_areasOnly || v != 0) return v;
    if (m_spans.Gain(m_smoothed.ptr<uint8_t>(y)[x]) < 0.5 * peak) return v;
    return m_spans.Gain(m_spans.At(x, y));
  };
  const int table = CircleOnTable(
      at.x, at.y, kRingCm * PixelsPerCm(), m_normalized.size(),
      [&](int x, int y) { return level(x, y) < 0.5 * peak; }, onTable);
  return table >= kTableAtLeast;
}

double Sensor::BrightestTipAbove(double level) {
  // The brightest pixel of each 64 x 32 px tile where the filter worked, brightest first; the
  // first of them that is fingertip-like gives the touch (its 3x3 peak). Sixteen are tried: a
  // frame's hot spots, palms and glows hold at most a few tiles' maxima each before a fingertip's.
  constexpr int kTileRows = 32, kTileCols = 64, kTries = 16;
  m_candidates.clear();
  const auto scan = [&](const cv::Rect& area) {
    for (int y = area.y; y < area.y + area.height; y += kTileRows) {
      for (int x = area.x; x < area.x + area.width; x += kTileCols) {
        const cv::Rect tile = cv::Rect(x, y, kTileCols, kTileRows) & area;
        double hi = 0.0;
        cv::Point loc;
        cv::minMaxLoc(m_normalized(tile), nullptr, &hi, nullptr, &loc);
        if (hi > level) m_candidates.emplace_back(static_cast<uint8_t>(hi), loc + tile.tl());
      }
    }
  };
  if (m_areasOnly) {
    for (const cv::Rect& r : m_areas) scan(r);
  } else {
    scan(cv::Rect(0, 0, m_normalized.cols, m_normalized.rows));
  }
  // brightest first; of equal ones the first in raster order (the same in a whole frame as over
  // areas)
  std::sort(m_candidates.begin(), m_candidates.end(), [](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first > b.first;
    return a.second.y != b.second.y ? a.second.y < b.second.y : a.second.x < b.second.x;
  });
  const int tries = std::min<int>(kTries, static_cast<int>(m_candidates.size()));
  for (int i = 0; i < tries; ++i) {
    const double peak = PeakAround(m_candidates[i].second, level);
    if (peak > level && TipLike(m_candidates[i].second, peak)) return peak;
  }
  return 0.0;
}

void Sensor::Filter(bool whole, double level) {
  const double pxPerCm = PixelsPerCm();
  m_areasOnly = false;  // until the high-pass works out only some areas
  // background subtracted: what is brighter than the clear table (darker is clipped to 0)
  cv::subtract(m_grey, m_background, m_subtracted);

  // smoothing: a small Gaussian against sensor noise
  // A stage that changes nothing (no smoothing, a gain of 1) shows its input: the stage image
  // shares it rather than copying it, which keeps the frame's images fewer (and in cache). A
  // stage that works again writes into an image of its own, never into the one it shares.
  const double sigma = m_params.smooth * pxPerCm;
  if (sigma >= 0.3) {
    Unshare(m_smoothed, {&m_subtracted});
    cv::GaussianBlur(m_subtracted, m_smoothed, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
  } else {
    m_smoothed = m_subtracted;
  }

  // high-pass: minus a wide box blur of itself, at most highpass_cap, so that wide glows (palms and
  // arms above the surface, uneven light) fade while small bright contacts stay
  const int width = static_cast<int>(std::lround(m_params.highpassWidth * pxPerCm)) | 1;
  const bool gained = m_params.gain != 1.0;
  if (m_params.highpassWidth > 0.0 && width >= 3 && m_params.highpassCap > 0.0) {
    const cv::Size size = m_smoothed.size();
    Unshare(m_highpass, {&m_subtracted, &m_smoothed});
    m_highpass.create(size, CV_8UC1);
    if (gained) {
      Unshare(m_normalized, {&m_subtracted, &m_smoothed, &m_highpass});
      m_normalized.create(size, CV_8UC1);
    } else {
      m_normalized = m_highpass;
    }
    m_areas.clear();
    m_areasOnly = !whole;
    if (whole) {
      HighpassWhole(width);
    } else {
      HighpassWhereContactsCanBe(width, level);
    }
    return;
  }
  m_highpass = m_smoothed;

  // gain
  if (gained) {
    Unshare(m_normalized, {&m_subtracted, &m_smoothed, &m_highpass});
    m_highpass.convertTo(m_normalized, CV_8UC1, m_params.gain);
  } else {
    m_normalized = m_highpass;
  }
}

void Sensor::HighpassWhole(int width) {
  cv::blur(m_smoothed, m_wide, cv::Size(width, width), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  if (m_params.highpassCap < 255.0) cv::min(m_wide, m_params.highpassCap, m_wide);
  cv::subtract(m_smoothed, m_wide, m_highpass);
  if (m_params.gain != 1.0) m_highpass.convertTo(m_normalized, CV_8UC1, m_params.gain);
}

void Sensor::HighpassWhereContactsCanBe(int width, double level) {
  // The high-pass never adds: highpass = smoothed - min(wide, cap) <= smoothed, and the gain and
  // the threshold are monotonic. So a pixel whose smoothed level s does not pass the threshold
  // once gained (gain s, rounded as convertTo rounds, not above the threshold) passes it after
  // the high-pass neither. Only the spans of rows round pixels that could pass are worked out;
  // the binary image elsewhere is 0, as it would be had every pixel been worked out.
  // The lowest smoothed level that could pass, found with the chain's own arithmetic (convertTo,
  // then threshold) on every 8-bit level, one below it to be safe from any rounding.
  cv::Mat levels(1, 256, CV_8UC1), passing;
  for (int v = 0; v < 256; ++v) levels.at<uint8_t>(0, v) = static_cast<uint8_t>(v);
  if (m_params.gain != 1.0)
    levels.convertTo(passing, CV_8UC1, m_params.gain);
  else
    passing = levels;
  cv::threshold(passing, passing, level, 255, cv::THRESH_BINARY);
  int lowest = 256;
  for (int v = 0; v < 256; ++v) {
    if (passing.at<uint8_t>(0, v) != 0) {
      lowest = std::max(0, v - 1);
      break;
    }
  }

  // what is not worked out is 0; the spans' high-pass is set up for this frame first (TipLike
  // reads single pixels through it whenever only areas were worked out)
  const cv::Size size = m_smoothed.size();
  m_highpass.setTo(0);
  if (m_params.gain != 1.0) m_normalized.setTo(0);
  m_spans.Configure(width, cv::saturate_cast<uint8_t>(m_params.highpassCap), m_params.gain);
  m_spans.Begin(m_smoothed);
  if (lowest > 255) return;

  // tiles of kTileRows x kTileCols px: mark those with a pixel at or above `lowest`
  constexpr int kTileRows = 32, kTileCols = 64;
  const int tileRows = (size.height + kTileRows - 1) / kTileRows;
  const int tileCols = (size.width + kTileCols - 1) / kTileCols;
  m_tileMarks.assign(static_cast<size_t>(tileRows * tileCols), 0);
  const uint8_t floor = static_cast<uint8_t>(lowest);
  for (int y = 0; y < size.height; ++y) {
    const uint8_t* row = m_smoothed.ptr<uint8_t>(y);
    uint8_t* marks = &m_tileMarks[static_cast<size_t>((y / kTileRows) * tileCols)];
    for (int tc = 0; tc < tileCols; ++tc) {
      if (marks[tc] != 0) continue;
      const int x0 = tc * kTileCols, x1 = std::min(size.width, x0 + kTileCols);
      uint8_t any = 0;
      for (int x = x0; x < x1; ++x) any |= static_cast<uint8_t>(row[x] >= floor);
      marks[tc] = any;
    }
  }

  // Each group of marked tiles (touching at a side or a corner) gives one rectangle, its bounding
  // box: the areas (m_areas) the fingertip search scans and the opening works in. Rectangles of
  // two groups may overlap.
  m_tileStack.clear();
  for (int start = 0; start < tileRows * tileCols; ++start) {
    if (m_tileMarks[static_cast<size_t>(start)] != 1) continue;
    // flood the group from `start`, marking its tiles 2 (done)
    int r0 = tileRows, r1 = -1, c0 = tileCols, c1 = -1;
    m_tileMarks[static_cast<size_t>(start)] = 2;
    m_tileStack.push_back(start);
    while (!m_tileStack.empty()) {
      const int t = m_tileStack.back();
      m_tileStack.pop_back();
      const int tr = t / tileCols, tc = t % tileCols;
      r0 = std::min(r0, tr);
      r1 = std::max(r1, tr);
      c0 = std::min(c0, tc);
      c1 = std::max(c1, tc);
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int nr = tr + dr, nc = tc + dc;
          if (nr < 0 || nr >= tileRows || nc < 0 || nc >= tileCols) continue;
          uint8_t& mark = m_tileMarks[static_cast<size_t>(nr * tileCols + nc)];
          if (mark != 1) continue;
          mark = 2;
          m_tileStack.push_back(nr * tileCols + nc);
        }
      }
    }
    const int x0 = c0 * kTileCols, y0 = r0 * kTileRows;
    m_areas.emplace_back(x0, y0, std::min(size.width, (c1 + 1) * kTileCols) - x0,
                         std::min(size.height, (r1 + 1) * kTileRows) - y0);
  }

  // Within the marked tiles, each row is worked out along spans round its pixels that could
  // pass (SpanHighpass): a box's sum is run along a span at one add and one subtract a pixel,
  // and starting a span costs a box's width of adds, so pixels closer than that join one span.
  // Over a frame of eight flat hands the marked tiles' rectangles, with the blur's border round
  // each, came to about as many pixels as the whole frame; the spans are a third of it.
  for (int tr = 0; tr < tileRows; ++tr) {
    const uint8_t* marks = &m_tileMarks[static_cast<size_t>(tr * tileCols)];
    const int yEnd = std::min(size.height, (tr + 1) * kTileRows);
    for (int y = tr * kTileRows; y < yEnd; ++y) {
      const uint8_t* row = m_smoothed.ptr<uint8_t>(y);
      int spanStart = -1, spanEnd = -1;  // the open span, [start, end)
      for (int tc = 0; tc < tileCols; ++tc) {
        if (marks[tc] == 0) continue;
        const int x1 = std::min(size.width, (tc + 1) * kTileCols);
        const auto take = [&](int x) {
          if (spanStart >= 0 && x - spanEnd > width) {
            m_spans.Span(y, spanStart, spanEnd, m_highpass, m_normalized);
            spanStart = -1;
          }
          if (spanStart < 0) spanStart = x;
          spanEnd = x + 1;
        };
        int x = tc * kTileCols;
#if defined(__SSE2__)
        // 16 pixels at a time: most of a tile's are below the floor
        const __m128i low = _mm_set1_epi8(static_cast<char>(floor));
        for (; x + 16 <= x1; x += 16) {
          const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x));
          unsigned bits =
              static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(v, low), v)));
          if (bits == 0) continue;
          if (width >= 16) {
            // no gap within 16 pixels splits a span: its first and its last pixel
            take(x + __builtin_ctz(bits));
            spanEnd = x + 32 - __builtin_clz(bits);
            continue;
          }
          while (bits != 0) {
            take(x + __builtin_ctz(bits));
            bits &= bits - 1;
          }
        }
#endif
        for (; x < x1; ++x)
          if (row[x] >= floor) take(x);
      }
      if (spanStart >= 0) m_spans.Span(y, spanStart, spanEnd, m_highpass, m_normalized);
    }
  }
}

double Sensor::LearnBackground(double time) {
  const double dt = m_haveTime ? time - m_lastTime : 0.0;
  m_lastTime = time;
  m_haveTime = true;
  if (!(dt > 0.0)) return dt;
  if (m_learned.empty()) {
    m_background.convertTo(m_learned, CV_32F);
    m_learned.copyTo(m_reference);
    m_background.copyTo(m_reference8);
    m_learnedTime = 0.0;
    m_bandsStarted = false;
  }
  m_learnedTime += dt;
  if (!m_lowest.empty() && !(m_params.backgroundWarmup > 0.0)) {
    // no warm-up: the spatial estimate alone
    m_lowMean.release();
    m_lowest.release();
  }
  if (!m_lowest.empty()) {
    // Warm-up: the spatial estimate stays the background while each pixel's lowest running mean
    // (time constant a third of the warm-up: the camera noise averaged over a few frames) is
    // kept. What is static from the start, like an illuminator's hot spot, is that bright all
    // along; where a hand moved away the table showed. At its end that is the background.
    const double alpha = 1.0 - std::exp(-dt / std::max(1e-3, m_params.backgroundWarmup / 3.0));
    cv::accumulateWeighted(m_grey, m_lowMean, alpha);
    cv::min(m_lowest, m_lowMean, m_lowest);
    if (WarmingUp()) return dt;
    FinishWarmup();
  }
  LowerSettleFloor(time);
  if (m_params.backgroundLearning <= 0.0) {
    // learning is off: when it comes back on, the time it was off is not learned
    m_bandsStarted = false;
    return dt;
  }
  if (!m_bandsStarted) {
    // every band was last learned at the previous frame
    m_bandTime.fill(time - dt);
    m_touchTime.fill(time - dt);
    m_nextBand = 0;
    m_bandsStarted = true;
  }
  // One band of rows a frame, in turn, each with the rate for the time since it was last
  // learned: the same time constant as learning every row every frame (1 - e^(-sum dt / T)),
  // at an eighth of the cost. The band's frames are fewer (one in kLearnBands), so the noise
  // left in the background is sqrt(kLearnBands) times larger: with T = 10 s at 60 Hz,
  // sqrt(alpha / 2) = 0.08 of the camera's noise instead of 0.03, far below any threshold.
  const int band = m_nextBand;
  m_nextBand = (m_nextBand + 1) % kLearnBands;
  const double bandDt = time - m_bandTime[band];
  m_bandTime[band] = time;
  if (!(bandDt > 0.0)) return dt;
  const int rows = m_grey.rows;
  const int r0 = rows * band / kLearnBands, r1 = rows * (band + 1) / kLearnBands;
  if (r1 <= r0) return dt;
  // where nothing touches: outside the contacts dilated by a margin, so the dilation sees the
  // margin's rows beyond the band
  constexpr int kMargin = 3;  // px around contacts the learning leaves alone
  const int m0 = std::max(0, r0 - kMargin), m1 = std::min(rows, r1 + kMargin);
  const cv::Range cols = cv::Range::all();
  cv::dilate(m_binary(cv::Range(m0, m1), cols), m_still, cv::Mat(), cv::Point(-1, -1), kMargin);
  cv::Mat still = m_still(cv::Range(r0 - m0, r1 - m0), cols);
  cv::Mat learned = m_learned(cv::Range(r0, r1), cols);
  {
    // Only what reads as table is learned at background_learning. A pixel brighter than the
    // background by the bright margin (3 noise deviations, at least a grey level; with a fixed
    // level, half of it) is a hand's glow or a touch below the level: learned as a contact is, at
    // touch_learning. Not where the background lies below its long-term level (m_reference) by
    // more than the margin: something dark that lay there (a shadow) was learned, and the table
    // that shows again is brighter than it; that is learned back at background_learning. A band
    // where such bright pixels (contacts' included) cover half its pixels or more is the table's
    // lighting changing, and is learned as before (its contacts marked again: rare, so the common
    // case takes one pass).
    const double margin = BrightMargin();
    if (!m_spatial.empty() &&
        m_lastTime - m_startTime <= m_params.backgroundWarmup + m_params.backgroundSettle) {
      // while an estimated background settles, what it is set to (a hand held out, the table
      // that showed where one lay) is its level: the long-term one starts when it has settled
      learned.copyTo(m_reference(cv::Range(r0, r1), cols));
      m_background(cv::Range(r0, r1), cols).copyTo(m_reference8(cv::Range(r0, r1), cols));
    }
    const size_t bright =
        MarkGlows(m_grey(cv::Range(r0, r1), cols), m_background(cv::Range(r0, r1), cols),
                  m_reference8(cv::Range(r0, r1), cols), margin, still);
    if (2 * bright >= still.total()) {
      cv::dilate(m_binary(cv::Range(m0, m1), cols), m_still, cv::Mat(), cv::Point(-1, -1), kMargin);
      still = m_still(cv::Range(r0 - m0, r1 - m0), cols);
    }
  }
  cv::bitwise_not(still, still);
  const double alpha = 1.0 - std::exp(-bandDt / m_params.backgroundLearning);
  cv::accumulateWeighted(m_grey(cv::Range(r0, r1), cols), learned, alpha, still);
  const double touchDt = time - m_touchTime[band];
  if (m_params.touchLearning > 0.0 && touchDt >= 0.01 * m_params.touchLearning) {
    // Under the contacts too, far more slowly: a contact that never changes (a lamp left on,
    // something bright left on the table, a drift the background did not follow) would otherwise
    // keep the background from learning it, and stay for good. A band learned under contacts
    // once a hundredth of the time constant has passed (3 s at 300 s), at the rate for that
    // time, follows the same curve as every frame to within a hundredth, for a fraction of the
    // work.
    m_touchTime[band] = time;
    cv::bitwise_not(still, still);
    const double touchAlpha = 1.0 - std::exp(-touchDt / m_params.touchLearning);
    cv::accumulateWeighted(m_grey(cv::Range(r0, r1), cols), learned, touchAlpha, still);
    // the long-term level follows every pixel at the same rate
    cv::Mat reference = m_reference(cv::Range(r0, r1), cols);
    cv::accumulateWeighted(m_grey(cv::Range(r0, r1), cols), reference, touchAlpha);
    reference.convertTo(m_reference8(cv::Range(r0, r1), cols), CV_8UC1);
  }
  SettleDark(r0, r1, bandDt);
  cv::Mat background = m_background(cv::Range(r0, r1), cols);
  learned.convertTo(background, CV_8UC1);
  return dt;
}

void Sensor::FinishWarmup() {
  // The lowest running mean, but never more than 2 noise deviations below the spatial estimate:
  // a shadow that lay on the table all through the warm-up (a hand hovering in ambient light) is
  // darker than the table, and learned it would read as a touch once it goes. The spatial
  // estimate is the table's level within its blocks' noise (a median of a few hundred pixels);
  // 2 deviations leave a spot that read darker than it at most 2 deviations bright afterwards,
  // under the noise floor of the level (noise_factor 5).
  // The lowest of a running mean lies below its mean by the mean's own noise (about one of its
  // deviations over a 0.2 s warm-up at 60 Hz): where nothing moved the difference between the
  // last running mean and its lowest is that offset and nothing else, and most of a table is such,
  // so their median (a sample of every 8th pixel of every 8th row) is added back.
  std::vector<float> offsets;
  offsets.reserve(static_cast<size_t>((m_lowest.rows / 8 + 1) * (m_lowest.cols / 8 + 1)));
  for (int y = 4; y < m_lowest.rows; y += 8) {
    const float* mean = m_lowMean.ptr<float>(y);
    const float* low = m_lowest.ptr<float>(y);
    for (int x = 4; x < m_lowest.cols; x += 8) offsets.push_back(mean[x] - low[x]);
  }
  m_lowOffset = 0.0f;
  if (!offsets.empty()) {
    std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2, offsets.end());
    m_lowOffset = offsets[offsets.size() / 2];
    m_lowest += m_lowOffset;
  }
  const double noise = NoiseDeviation();
  cv::Mat floor;
  m_spatial.convertTo(floor, CV_32F, 1.0, -2.0 * noise);
  cv::max(m_lowest, floor, m_learned);
  m_learned.convertTo(m_background, CV_8UC1);
  m_learned.copyTo(m_reference);
  m_background.copyTo(m_reference8);

  // What the warm-up took in that is bright against the spatial estimate is either the table's
  // own (a hot spot, a bright mark) or a hand that lay still through it: kept apart for the
  // settling (TrackStillRegions). Bright: 3 noise deviations above the estimate (the running
  // mean's own noise is a third of the camera's, so noise alone is 9 of its deviations off) and
  // at least a grey level; with a fixed level, half of it (the noise is not measured then).
  m_stillState.release();
  if (m_params.backgroundSettle > 0.0 && m_params.backgroundStill > 0.0) {
    m_brightMargin = static_cast<float>(BrightMargin());
    cv::Mat raised, bright;
    m_spatial.convertTo(raised, CV_32F, 1.0, m_brightMargin);
    cv::compare(m_lowest, raised, bright, cv::CMP_GT);
    m_brightRect = cv::boundingRect(bright);
    if (m_brightRect.area() > 0) {
      bright(m_brightRect).copyTo(m_stillState);
      m_stillState &= kStillIn;
      m_lowMean(m_brightRect).copyTo(m_stillMean);
      m_lowest(m_brightRect).copyTo(m_stillLow);
      m_movedTime = cv::Mat::zeros(m_brightRect.size(), CV_32F);
      m_stillOut = false;
      HoldOutHandLike();
    }
  }
  m_lowMean.release();
  m_lowest.release();
}

void Sensor::HoldOutHandLike() {
  // A hand that lies still through the warm-up is taken in with the table's own bright things (a
  // hot spot of the illuminator, a bezel, a mark). A hand is told from them by its shape: it
  // ends in several fingertips. A piece of what was taken in that is hand-sized and holds 3
  // fingertip ends is held out at once, as TrackStillRegions holds out a region that moved, so a
  // hand resting at the start stays a contact; it goes back in after background_still unless it
  // moves (the same rule as a region that moved: a hand-shaped mark of the table does not stay a
  // contact).
  // All on the warm-up's excess over the spatial estimate, its 3x3 mean, every other pixel:
  // - a fingertip end is the highest within 0.75 cm (half a fingertip) to the bright margin (a
  //   plateau's noise; the flank of a glow is not), at least twice the margin, and on a circle
  //   3 cm across round it at least 9 of 16 points read under half of it with the others in one
  //   arc: the finger goes on one way only. The middle of a finger, a bezel or a streak has two
  //   arcs, a round spot (a hot spot, a lone mark) none, and a point on the edge of anything
  //   wider than 3 cm (a palm, a glow) half of the circle;
  // - of the ends in one region, those 1.5 cm apart (brightest first) are its fingertips, and
  //   their median its contrast c;
  // - the region's pixels within [c / 2, 1.5 c + 3 noise deviations] (what is brighter by more is
  //   a hot spot under the hand, what is less than half as bright the table's pattern, and both
  //   join a hand to the marks round it at the bright margin), 8-connected, are its pieces; a
  //   piece is held out when it holds 3 of the fingertips and is the size of a hand: 15 cm^2 or
  //   more (three fingers' last two segments as bright as their tips) and at most 25 cm across
  //   (a spread hand is 20 to 23).
  constexpr double kEndReachCm = 0.75, kRingCm = 1.5, kHandAreaCm2 = 15.0, kHandSpanCm = 25.0;
  constexpr int kTableAtLeast = 9, kTipsAtLeast = 3;
  const cv::Rect rect = m_brightRect;
  const float margin = m_brightMargin;
  const float noise = static_cast<float>(NoiseDeviation());
  const double pxPerCm = PixelsPerCm();
  cv::Mat spatial, excess, mean, highest;
  m_spatial(rect).convertTo(spatial, CV_32F);
  cv::subtract(m_lowest(rect), spatial, excess);
  cv::blur(excess, mean, cv::Size(3, 3));
  const int reach = std::max(1, static_cast<int>(std::lround(kEndReachCm * pxPerCm)));
  cv::dilate(mean, highest,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * reach + 1, 2 * reach + 1)));
  const int regions = cv::connectedComponents(m_stillState, m_labels, 8, CV_32S);
  struct End {
    float peak;
    int x, y;
  };
  std::vector<std::vector<End>> ends(static_cast<size_t>(regions));
  const double ring = kRingCm * pxPerCm;
  for (int y = 0; y < rect.height; y += 2) {
    const uint8_t* state = m_stillState.ptr<uint8_t>(y);
    const float* m = mean.ptr<float>(y);
    const float* h = highest.ptr<float>(y);
    const int* label = m_labels.ptr<int>(y);
    for (int x = 0; x < rect.width; x += 2) {
      const float peak = m[x];
      if (state[x] == kStillNone || peak < 2.0f * margin || peak < h[x] - margin) continue;
      // the circle's points on the table, and the arcs of the others
      bool onTable[kCirclePoints];
      const int table = CircleOnTable(
          x + rect.x, y + rect.y, ring, m_lowest.size(),
          [&](int u, int v) {
            return m_lowest.ptr<float>(v)[u] - m_spatial.ptr<uint8_t>(v)[u] < 0.5f * peak;
          },
          onTable);
      int arcs = 0;
      for (int i = 0; i < kCirclePoints; ++i)
        arcs += !onTable[i] && onTable[(i + 1) % kCirclePoints] ? 1 : 0;
      if (table >= kTableAtLeast && arcs == 1)
        ends[static_cast<size_t>(label[x])].push_back({peak, x, y});
    }
  }
  const float now = static_cast<float>(m_lastTime - m_startTime);
  std::vector<End> tips;
  std::vector<int> count;
  cv::Mat part, pieceOf, stats, centroids;  // once a run: no members kept for them
  for (size_t k = 1; k < ends.size(); ++k) {
    std::vector<End>& e = ends[k];
    if (e.size() < static_cast<size_t>(kTipsAtLeast)) continue;
    std::sort(e.begin(), e.end(), [](const End& a, const End& b) { return a.peak > b.peak; });
    tips.clear();
    for (const End& t : e) {
      bool apart = true;
      for (const End& o : tips) apart = apart && std::hypot(t.x - o.x, t.y - o.y) >= ring;
      if (apart) tips.push_back(t);
    }
    if (tips.size() < static_cast<size_t>(kTipsAtLeast)) continue;
    const float c = tips[tips.size() / 2].peak;
    const float lo = 0.5f * c, hi = 1.5f * c + 3.0f * noise;
    part.create(rect.size(), CV_8UC1);
    for (int y = 0; y < rect.height; ++y) {
      const int* label = m_labels.ptr<int>(y);
      const float* ex = excess.ptr<float>(y);
      uint8_t* in = part.ptr<uint8_t>(y);
      for (int x = 0; x < rect.width; ++x)
        in[x] = static_cast<size_t>(label[x]) == k && ex[x] >= lo && ex[x] <= hi ? 1 : 0;
    }
    const int pieces = cv::connectedComponentsWithStats(part, pieceOf, stats, centroids, 8, CV_32S);
    count.assign(static_cast<size_t>(pieces), 0);
    for (const End& t : tips) ++count[static_cast<size_t>(pieceOf.at<int>(t.y, t.x))];
    count[0] = 0;  // outside the pieces
    // from here on count[q] is 1 for a piece held out, 0 for the rest
    bool any = false;
    for (int q = 1; q < pieces; ++q) {
      const double area = stats.at<int>(q, cv::CC_STAT_AREA) / (pxPerCm * pxPerCm);
      const double span =
          std::max(stats.at<int>(q, cv::CC_STAT_WIDTH), stats.at<int>(q, cv::CC_STAT_HEIGHT)) /
          pxPerCm;
      const bool hand = count[static_cast<size_t>(q)] >= kTipsAtLeast && area >= kHandAreaCm2 &&
                        span <= kHandSpanCm;
      count[static_cast<size_t>(q)] = hand ? 1 : 0;
      any = any || hand;
    }
    for (int y = 0; any && y < rect.height; ++y) {
      const int* piece = pieceOf.ptr<int>(y);
      uint8_t* state = m_stillState.ptr<uint8_t>(y);
      const float* lowMean = m_lowMean.ptr<float>(y + rect.y) + rect.x;
      const uint8_t* sp = m_spatial.ptr<uint8_t>(y + rect.y) + rect.x;
      float* b = m_learned.ptr<float>(y + rect.y) + rect.x;
      float* low = m_stillLow.ptr<float>(y);
      float* moved = m_movedTime.ptr<float>(y);
      for (int x = 0; x < rect.width; ++x) {
        if (count[static_cast<size_t>(piece[x])] == 0) continue;
        state[x] = kStillOut;
        low[x] = lowMean[x];
        b[x] = std::min(b[x], static_cast<float>(sp[x]));
        moved[x] = now;
        m_stillOut = true;
      }
    }
  }
  if (m_stillOut) m_learned(rect).convertTo(m_background(rect), CV_8UC1);
}

void Sensor::TrackStillRegions(double time, double dt) {
  // A region the warm-up took in comes out of the background as a whole once part of it shows
  // the table (enough of its pixels darker than the background by 3 noise deviations, the
  // darkest by twice the bright margin or more: a hand that lay still at the start has begun to
  // move): the
  // background under it goes back to the table's level (the spatial estimate, raised by what
  // the table that showed reads above it), so the part of the hand that still covers where it
  // lay is a contact again, not only the part that moved onto clear table. Pixels brighter than
  // the table by half again the hand's contrast stay in (a hot spot the palm lay on). Held out,
  // each pixel keeps its running low; where that comes down to the table it is table again.
  // What is held out goes back in once its region has not moved for background_still and no
  // contact joins it to clear table (a bright mark of the table the hand lay on; a hand that
  // has moved stays out, whatever it covers of where it lay). After background_settle the
  // tracking ends: what is still held out and joined stays so, the rest goes in.
  const double since = time - m_startTime;
  const cv::Rect rect = m_brightRect;
  const float noise = static_cast<float>(NoiseDeviation());
  const float margin = m_brightMargin;
  const float now = static_cast<float>(since);
  const float still = static_cast<float>(m_params.backgroundStill);
  const bool last = since > m_params.backgroundWarmup + m_params.backgroundSettle;
  const double alpha = 1.0 - std::exp(-dt / std::max(1e-3, m_params.backgroundWarmup / 3.0));
  cv::accumulateWeighted(m_grey(rect), m_stillMean, alpha);

  // Held-out pixels in a contact (the last frame's) that also covers clear table: their time
  // starts again. m_shown marks them until the loop below reads them.
  m_shown.create(rect.size(), CV_8UC1);
  m_shown.setTo(0);
  if (m_stillOut) {
    // clear table inside the contact, 2 px in from its edge: the smoothing spreads any contact
    // a pixel or two over the table round it, a phantom's too
    const int n = cv::connectedComponents(m_binary(rect), m_labels, 8, CV_32S);
    cv::erode(m_binary(rect), m_still, cv::Mat(), cv::Point(-1, -1), 2);
    m_regionFlags.assign(static_cast<size_t>(n), 0);  // per contact: it covers clear table
    for (int y = 0; y < rect.height; ++y) {
      const int* label = m_labels.ptr<int>(y);
      const uint8_t* state = m_stillState.ptr<uint8_t>(y);
      const uint8_t* inside = m_still.ptr<uint8_t>(y);
      for (int x = 0; x < rect.width; ++x)
        if (state[x] == kStillNone && inside[x] != 0)
          m_regionFlags[static_cast<size_t>(label[x])] = 1;
    }
    m_regionFlags[0] = 0;  // no contact
    for (int y = 0; y < rect.height; ++y) {
      const int* label = m_labels.ptr<int>(y);
      const uint8_t* state = m_stillState.ptr<uint8_t>(y);
      uint8_t* joined = m_shown.ptr<uint8_t>(y);
      float* moved = m_movedTime.ptr<float>(y);
      for (int x = 0; x < rect.width; ++x) {
        if (state[x] != kStillOut || m_regionFlags[static_cast<size_t>(label[x])] == 0) continue;
        joined[x] = 1;
        moved[x] = now;
      }
    }
  }

  // Each pixel: in, does it show the table; out, is it table, or back in.
  bool anyShown = false, anyOut = false, changed = false;
  for (int y = 0; y < rect.height; ++y) {
    uint8_t* state = m_stillState.ptr<uint8_t>(y);
    uint8_t* shown = m_shown.ptr<uint8_t>(y);
    const float* mean = m_stillMean.ptr<float>(y);
    const uint8_t* grey = m_grey.ptr<uint8_t>(y + rect.y) + rect.x;
    float* low = m_stillLow.ptr<float>(y);
    const float* moved = m_movedTime.ptr<float>(y);
    const uint8_t* sp = m_spatial.ptr<uint8_t>(y + rect.y) + rect.x;
    float* b = m_learned.ptr<float>(y + rect.y) + rect.x;
    for (int x = 0; x < rect.width; ++x) {
      const bool joined = shown[x] != 0;
      shown[x] = 0;
      if (state[x] == kStillIn) {
        const float darker = b[x] - grey[x];
        shown[x] = darker > 3.0f * noise ? 1 : 0;
      } else if (state[x] == kStillOut) {
        low[x] = std::min(low[x], mean[x]);
        if (low[x] <= sp[x] + margin) {
          // the table shows here: it is table, at its low (never above the bright margin)
          state[x] = kStillNone;
          b[x] = std::max(sp[x] - 2.0f * noise, std::min(low[x] + m_lowOffset, sp[x] + margin));
          shown[x] = 1;
          changed = true;
        } else if (!joined && (last || now - moved[x] >= still)) {
          state[x] = kStillIn;
          b[x] = std::max(b[x], low[x] + m_lowOffset);
          changed = true;
        }
      }
      anyShown = anyShown || shown[x] != 0;
      anyOut = anyOut || state[x] == kStillOut;
    }
  }

  if (anyShown && !last) {
    // The regions (8-connected, with the pixels that showed the table this frame), how many of
    // each showed it, by how much it came down and the table's level there. A region has moved
    // when enough of it showed the table (a few pixels are the noise of a soft edge, whose
    // running low creeps down) by twice the bright margin (a compressed video's blocks show
    // 5 deviations at times; a hand is brighter than that to be a contact at all).
    m_shown.copyTo(m_still);
    for (int y = 0; y < rect.height; ++y) {
      uint8_t* u = m_still.ptr<uint8_t>(y);
      const uint8_t* state = m_stillState.ptr<uint8_t>(y);
      for (int x = 0; x < rect.width; ++x) u[x] = (u[x] != 0 || state[x] != kStillNone) ? 1 : 0;
    }
    const int n =
        cv::connectedComponentsWithStats(m_still, m_labels, m_stats, m_centroids, 8, CV_32S);
    m_shownCount.assign(static_cast<size_t>(n), 0);
    m_shownContrast.assign(static_cast<size_t>(n), 0.0f);
    m_shownTable.assign(static_cast<size_t>(n), 0.0f);
    m_shownIn.assign(static_cast<size_t>(n), 0);
    m_regionFlags.assign(static_cast<size_t>(n), 0);  // per region: it has moved
    for (int y = 0; y < rect.height; ++y) {
      const int* label = m_labels.ptr<int>(y);
      const uint8_t* shown = m_shown.ptr<uint8_t>(y);
      const uint8_t* state = m_stillState.ptr<uint8_t>(y);
      const uint8_t* grey = m_grey.ptr<uint8_t>(y + rect.y) + rect.x;
      const uint8_t* sp = m_spatial.ptr<uint8_t>(y + rect.y) + rect.x;
      const float* b = m_learned.ptr<float>(y + rect.y) + rect.x;
      for (int x = 0; x < rect.width; ++x) {
        if (shown[x] == 0) continue;
        const size_t k = static_cast<size_t>(label[x]);
        ++m_shownCount[k];
        if (state[x] != kStillIn) continue;
        m_shownContrast[k] = std::max(m_shownContrast[k], b[x] - grey[x]);
        m_shownTable[k] += static_cast<float>(grey[x] - sp[x]);
        ++m_shownIn[k];
      }
    }
    bool anyMoved = false;
    for (size_t k = 1; k < static_cast<size_t>(n); ++k) {
      const int area = m_stats.at<int>(static_cast<int>(k), cv::CC_STAT_AREA);
      const bool movedNow =
          m_shownCount[k] >= 4 + area / 200 && m_shownContrast[k] >= 2.0f * margin;
      m_regionFlags[k] = movedNow ? 1 : 0;
      anyMoved = anyMoved || movedNow;
      // where the table showed, its level against the spatial estimate (which the hand-wide
      // opening biases low beside bright things): the region is held out at that level
      const float table = m_shownTable[k] / static_cast<float>(std::max(1, m_shownIn[k]));
      m_shownTable[k] = std::clamp(table, -2.0f * noise, margin);
    }
    for (int y = 0; anyMoved && y < rect.height; ++y) {
      const int* label = m_labels.ptr<int>(y);
      uint8_t* state = m_stillState.ptr<uint8_t>(y);
      float* low = m_stillLow.ptr<float>(y);
      const float* mean = m_stillMean.ptr<float>(y);
      float* moved = m_movedTime.ptr<float>(y);
      const uint8_t* shown = m_shown.ptr<uint8_t>(y);
      const uint8_t* sp = m_spatial.ptr<uint8_t>(y + rect.y) + rect.x;
      float* b = m_learned.ptr<float>(y + rect.y) + rect.x;
      for (int x = 0; x < rect.width; ++x) {
        const size_t k = static_cast<size_t>(label[x]);
        if (state[x] == kStillNone || m_regionFlags[k] == 0) continue;
        if (state[x] == kStillIn && shown[x] != 0) {
          // it showed the table: held out where it is, it is table from the next frame on
          state[x] = kStillOut;
          low[x] = mean[x];
          anyOut = true;
          moved[x] = now;
          continue;
        }
        // What moved is as bright as the table it showed is darker. A pixel brighter than that
        // by half again is something else under it (a hot spot a palm lay on), and one less
        // than half as bright is the table's own pattern, which the spatial estimate misses:
        // both stay in.
        const float excess = b[x] - sp[x];
        if (state[x] == kStillIn && (excess > 1.5f * m_shownContrast[k] + 3.0f * noise ||
                                     excess < 0.5f * m_shownContrast[k]))
          continue;
        if (state[x] == kStillIn) {
          state[x] = kStillOut;
          low[x] = mean[x];
          b[x] = std::min(b[x], sp[x] + m_shownTable[k]);
          anyOut = true;
          changed = true;
        }
        moved[x] = now;
      }
    }
  }
  m_stillOut = anyOut;
  if (changed) m_learned(rect).convertTo(m_background(rect), CV_8UC1);
  if (last) {
    m_stillState.release();
    m_stillMean.release();
    m_stillLow.release();
    m_movedTime.release();
  }
}

bool Sensor::Settling() const {
  // an estimated background, past its warm-up and within background_settle after it (m_lastTime
  // is this frame's)
  return !m_spatial.empty() && m_params.backgroundSettle > 0.0 && m_lowest.empty() &&
         m_lastTime - m_startTime <= m_params.backgroundWarmup + m_params.backgroundSettle;
}

void Sensor::LowerSettleFloor(double time) {
  // The settling's floor (SettleDark) starts at the first frame's spatial estimate. A hand that
  // hovered over the table then raised it by its glow where the glow is wider than the estimate's
  // opening (a DI table's hand lit from below, t2.avi's: 5 grey over the table there), and the
  // table that shows when the hand moves off could not pull the background below it. Every
  // kDarkTime of the settling the floor comes down to the spatial estimate of that frame where it
  // is lower: as the hands move, the estimates see the table they uncover. A shadow narrower than
  // the estimate's closing (3 cm) is not in it; a wider one lowers it, which the high-pass's
  // width takes away when it goes (FirstFrames.EmptyTableShadowsAndDarkSpotsLeaveNoContact).
  if (!Settling()) return;
  if (m_settleFloor.empty()) {
    m_settleFloor = m_spatial.clone();
    m_floorTime = time;
  } else if (time - m_floorTime >= kDarkTime) {
    m_floorTime = time;
    cv::min(m_settleFloor, EstimateBackground(m_grey, PixelsPerCm()), m_settleFloor);
  }
}

void Sensor::SettleDark(int r0, int r1, double bandDt) {
  // For background_settle seconds after the warm-up: a hand that lay still through the warm-up
  // is in the background, and where it has moved away the frame reads darker than the background
  // by its contrast. There the background comes down fast (time constant kDarkTime), never below
  // the settling's floor less 2 noise deviations: the first frame's spatial estimate, lowered by
  // those of the settling's frames (LowerSettleFloor). A hovering hand's shadow, darker than the
  // table, is not learned below the table. Pixels darker by more than 3
  // deviations only: the noise alone does that once in 740 frames, so the background is not
  // pulled down by it.
  if (!Settling()) return;
  const float noise = static_cast<float>(NoiseDeviation());
  const float alpha = static_cast<float>(1.0 - std::exp(-bandDt / kDarkTime));
  for (int y = r0; y < r1; ++y) {
    const uint8_t* g = m_grey.ptr<uint8_t>(y);
    const uint8_t* sp = m_settleFloor.ptr<uint8_t>(y);  // set by LowerSettleFloor first
    float* b = m_learned.ptr<float>(y);
    for (int x = 0; x < m_grey.cols; ++x) {
      if (g[x] + 3.0f * noise >= b[x]) continue;
      const float target = std::max(static_cast<float>(g[x]), sp[x] - 2.0f * noise);
      if (target < b[x]) b[x] += alpha * (target - b[x]);
    }
  }
}

const cv::Mat& Sensor::StageImage(SensingStage stage) const {
  switch (stage) {
    case SensingStage::kCamera:
      return m_grey;
    case SensingStage::kBackground:
      return m_background;
    case SensingStage::kSubtracted:
      return m_subtracted;
    case SensingStage::kSmoothed:
      return m_smoothed;
    case SensingStage::kHighpass:
      return m_highpass;
    case SensingStage::kGained:
      return m_normalized;
    case SensingStage::kBinary:
      return m_binary;
  }
  return m_grey;
}

void Sensor::ExtractBlobs(std::vector<Blob>& blobs) {
  blobs.clear();
  // one pass finds every component's outer border and its holes (Suzuki-Abe border following)
  cv::findContours(m_binary, m_contours, m_hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);
  for (size_t i = 0; i < m_contours.size(); ++i) {
    if (m_hierarchy[i][3] >= 0) continue;  // a hole's border: holes are ignored
    const std::vector<cv::Point>& pixels = m_contours[i];

    // cheap reject of specks: the pixel-centre polygon plus half a pixel all round
    const double cmpp = m_model.CmPerPixel(Vec2(pixels[0].x, pixels[0].y));
    const double pixelArea =
        std::abs(cv::contourArea(pixels)) + 0.5 * cv::arcLength(pixels, true) + 1.0;
    if (pixelArea * cmpp * cmpp < 0.5 * m_params.minArea) continue;

    // sub-pixel edge points, mapped to the table
    RefineToEdge(pixels, m_refined);
    Contour dense(2, static_cast<Eigen::Index>(m_refined.size()));
    for (size_t k = 0; k < m_refined.size(); ++k) {
      const Vec2& p = m_refined[k];
      dense.col(static_cast<Eigen::Index>(k)) =
          m_linear ? ApplyHomography(m_model.cameraToTable, p.x(), p.y())
                   : m_model.CameraToTable(p);
    }
    const double area = std::abs(SignedArea(dense));
    if (area < m_params.minArea || dense.cols() < 3) continue;

    Blob blob;
    const Contour ccw = MakeCounterClockwise(dense);
    blob.area = area;
    blob.centroid = PolygonCentroid(ccw);
    blob.boundsMin = ccw.rowwise().minCoeff();
    blob.boundsMax = ccw.rowwise().maxCoeff();
    blob.contour = ResampleClosed(ccw, m_params.spacing, 3);
    blobs.push_back(std::move(blob));
  }
  std::sort(blobs.begin(), blobs.end(),
            [](const Blob& a, const Blob& b) { return a.area > b.area; });
}

namespace {

// WrapIndex for an offset of less than n either way, without a division (RefineToEdge's loops)
inline int Around(int i, int n) {
  return i < 0 ? i + n : (i >= n ? i - n : i);
}

}  // namespace

void Sensor::RefineToEdge(const std::vector<cv::Point>& pixels, std::vector<Vec2>& out) {
  const int n = static_cast<int>(pixels.size());
  // A long border (a hand's, not a fingertip's) keeps every second pixel where it runs straight
  // and every pixel where it bends: where the chains of 3 pixels before and after it turn by more
  // than 30 degrees (the crotches between fingers, fingertips of small hands). The points are
  // resampled `spacing` apart (0.3 cm, 3 px) afterwards; between two kept pixels (about 2.3 px
  // apart) the border is a chord, whose sagitta on a circle of radius R is c^2 / (8 R), at most
  // 0.06 px where a turn of 30 degrees over 6 px (R >= 11 px) lets it thin. The synthetic
  // hands' Hausdorff distances to their true outlines stay within 0.02 px of those of every pixel
  // (Shapes/ContourAccuracy), and a hand's edge search and mapping do about half the work.
  // Fingertips keep every pixel: thinned, a small oval's resampled points move along its border
  // by up to 0.19 cm as it turns (Churn.KeptParticlesTurnWithAnOval).
  constexpr int kThinFrom = 120;  // border pixels
  const double kThinTurn = std::sin(DegToRad(30.0));
  m_keep.clear();
  for (int i = 0; i < n; ++i) {
    bool keep = n < kThinFrom || i % 2 == 0 || i == n - 1;
    if (!keep) {
      const cv::Point& a = pixels[Around(i - 3, n)];
      const cv::Point& c = pixels[Around(i + 3, n)];
      const cv::Point& b = pixels[i];
      const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y;
      const double cross = ux * vy - uy * vx;
      keep = std::abs(cross) > kThinTurn * std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    }
    if (keep) m_keep.push_back(i);
  }
  const int kept = static_cast<int>(m_keep.size());
  out.resize(static_cast<size_t>(kept));
  for (int k = 0; k < kept; ++k) out[k] = Vec2(pixels[m_keep[k]].x, pixels[m_keep[k]].y);
  if (!m_params.subpixel || n < 3) return;

  // orientation: with a positive shoelace sum the outward normal of tangent t is (t.y, -t.x)
  double shoelace = 0.0;
  for (int i = 0, j = n - 1; i < n; j = i++)
    shoelace += static_cast<double>(pixels[j].x) * pixels[i].y -
                static_cast<double>(pixels[i].x) * pixels[j].y;
  const double sign = shoelace >= 0.0 ? 1.0 : -1.0;
  const int reach = n >= 5 ? 2 : 1;
  // edges are searched on the background-subtracted image, whose levels the smoothing and the
  // high-pass have not moved; the threshold is in gained levels
  const float minContrast = static_cast<float>(0.5 * m_lastThreshold / m_params.gain);
  constexpr double kReach = 2.0;  // px: the farthest sample from the border pixel
  const uint8_t* data = m_subtracted.data;
  const size_t step = m_subtracted.step[0];
  const double cols = m_subtracted.cols, rows = m_subtracted.rows;

  for (int k = 0; k < kept; ++k) {
    const int i = m_keep[k];
    const cv::Point& a = pixels[Around(i - reach, n)];
    const cv::Point& b = pixels[Around(i + reach, n)];
    // in scalars: an Eigen pair here went through the stack and stalled the loads after it
    const double sx = sign * (b.y - a.y), sy = -sign * (b.x - a.x);
    const double len = std::sqrt(sx * sx + sy * sy);
    if (len < 1e-9) continue;
    const Vec2 normal(sx / len, sy / len);
    const Vec2 p = out[k];
    // every sample is within kReach (2 px) of p along the normal: away from the image's last
    // rows and columns no sample needs clamping
    const bool interior = p.x() >= kReach && p.x() <= cols - 2 - kReach && p.y() >= kReach &&
                          p.y() <= rows - 2 - kReach;
    const float px = static_cast<float>(p.x()), py = static_cast<float>(p.y());
    const float nx = static_cast<float>(normal.x()), ny = static_cast<float>(normal.y());
    auto g = [&](double t) {
      if (interior) {
        const float tf = static_cast<float>(t);
        return SampleInterior(data, step, px + tf * nx, py + tf * ny);
      }
      return Sample(m_subtracted, p.x() + t * normal.x(), p.y() + t * normal.y());
    };

    // the edge is where the level crosses halfway between inside and outside
    const float inside = std::max({g(-1.0), g(-1.5), g(-2.0)});
    const float outside = std::min({g(1.0), g(1.5), g(2.0)});
    if (inside - outside < minContrast) continue;
    const float half = 0.5f * (inside + outside);
    constexpr double kStep = 0.25;  // px
    double t = 0.0;
    float prev = g(0.0);
    if (prev >= half) {
      // walk outwards to the first sample below the half level
      for (double s = kStep; s <= kReach + 1e-9; s += kStep) {
        const float cur = g(s);
        if (cur < half) {
          t = s - kStep + kStep * (prev - half) / (prev - cur);
          break;
        }
        prev = cur;
      }
    } else {
      // walk inwards to the first sample at or above the half level
      for (double s = -kStep; s >= -kReach - 1e-9; s -= kStep) {
        const float cur = g(s);
        if (cur >= half) {
          t = s + kStep * (half - cur) / (prev - cur);
          break;
        }
        prev = cur;
      }
    }
    out[k] = p + t * normal;
  }
}

void Sensor::BuildTableMaps() {
  const double cmpp = m_params.tableCmPerPixel;
  const int cols = static_cast<int>(std::ceil(m_table.width / cmpp));
  const int rows = static_cast<int>(std::ceil(m_table.height / cmpp));
  m_tableMapX.create(rows, cols, CV_32F);
  m_tableMapY.create(rows, cols, CV_32F);
  // table pixel (u, v) covers (u + 0.5, v + 0.5) * cmpp: sample the camera pixel that sees it
  for (int v = 0; v < rows; ++v) {
    for (int u = 0; u < cols; ++u) {
      const Vec2 px = m_model.TableToCamera(Vec2((u + 0.5) * cmpp, (v + 0.5) * cmpp));
      m_tableMapX.at<float>(v, u) = static_cast<float>(px.x());
      m_tableMapY.at<float>(v, u) = static_cast<float>(px.y());
    }
  }
}

}  // namespace pg
