#include "proxygrasp/sensing/tune.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pg {

namespace {

constexpr double kMaxGain = 32.0;  // the gain's range ends there (docs/levels.md)

std::string SizeOf(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace

// What is thresholded is round(h * gain) > threshold. With gain = threshold / (T + 0.5) and
// T < threshold - 0.5, h = T gives threshold - threshold / (2T + 1) < threshold - 0.5, which
// rounds below the threshold, and h = T + 1 gives more than threshold + 0.5: exactly h > T.
// Past the largest gain the threshold comes down instead, to kMaxGain (T + 0.5). Levels at or
// above the threshold keep gain 1 and take T as the threshold itself. The gain is rounded to the
// 6 digits it is written with: at most 255 * 5e-7 of a grey level, well inside the margins above.
void SetContactLevel(SensingParams& params, int level) {
  params.thresholdMode = ThresholdMode::kFixed;
  if (level + 0.5 < params.threshold) {
    params.gain = params.threshold / (level + 0.5);
    if (params.gain > kMaxGain) {
      params.gain = kMaxGain;
      params.threshold = kMaxGain * (level + 0.5);
    }
  } else {
    params.gain = 1.0;
    params.threshold = std::clamp(level, 1, 254);
  }
  params.gain = std::stod(Number(params.gain));
}

MaybeError SensingTuner::Configure(const SensingParams& params, const TableParams& table,
                                   const Calibration& calibration, const TuneOptions& options) {
  m_configured = false;
  if (!(options.clearSeconds > 0.0))
    return MakeError({"tune"}, "the clear part must last more than 0 s (got " +
                                   Number(options.clearSeconds) + ")");
  if (!(options.weakQuantile >= 0.0 && options.weakQuantile <= 1.0))
    return MakeError({"tune"}, "the weak touch quantile must be in [0, 1]");
  // the tuner reads the high-pass stage: gain 1 and a fixed threshold keep the rest of the chain
  // as cheap as it can be
  m_given = params;
  SensingParams highpass = params;
  highpass.gain = 1.0;
  highpass.thresholdMode = ThresholdMode::kFixed;
  highpass.threshold = 254.0;
  Calibration probe = calibration;
  probe.background.release();
  if (MaybeError s = m_sensor.Configure(highpass, table, probe, "calibration")) return s;
  m_options = options;
  m_haveStart = false;
  m_clear.clear();
  m_touching = false;
  m_clearFrames = m_touchFrames = 0;
  m_noiseLevel = 0;
  m_peaks.clear();
  m_kernel = OpeningKernel(params.morphology);
  const Vec2 centre(0.5 * probe.imageSize.width, 0.5 * probe.imageSize.height);
  const double cmpp = m_sensor.model().CmPerPixel(centre);
  m_minPixels = std::max(1.0, params.minArea / (cmpp * cmpp));
  m_configured = true;
  return std::nullopt;
}

MaybeError SensingTuner::AddFrame(const cv::Mat& frame, int64_t index, double time) {
  const SourceLoc where{"frame " + std::to_string(index)};
  if (!m_configured) return MakeError(where, "the tuner is not configured");
  const int type = frame.type();
  if (frame.empty() || (type != CV_8UC1 && type != CV_8UC3 && type != CV_8UC4))
    return MakeError(where, "expected an 8-bit grey or colour frame");
  const cv::Size expected = m_sensor.model().imageSize;
  if (frame.size() != expected)
    return MakeError(where, "frame is " + SizeOf(frame.size()) + ", expected " + SizeOf(expected));
  if (!m_haveStart) {
    m_startTime = time;
    m_haveStart = true;
  }
  if (!m_touching && time - m_startTime < m_options.clearSeconds) {
    cv::Mat grey;
    if (type == CV_8UC1)
      grey = frame.clone();
    else
      cv::cvtColor(frame, grey, type == CV_8UC3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    m_clear.emplace_back(std::move(grey), time);
    return std::nullopt;
  }
  if (!m_touching) {
    if (MaybeError s = StartTouches()) return s;
  }
  Result<ContourFrame> r = m_sensor.Step(frame, index, time);
  if (!r) return r.error();
  ++m_touchFrames;
  CollectTouchPeaks(m_sensor.StageImage(SensingStage::kHighpass));
  return std::nullopt;
}

// The clear part is over: its mean is the background, and each of its frames, seen against that
// background, gives the level above which it shows no contact. N is the highest of them.
MaybeError SensingTuner::StartTouches() {
  m_touching = true;
  if (m_clear.empty()) return std::nullopt;
  cv::Mat sum = cv::Mat::zeros(m_sensor.model().imageSize, CV_32F);
  for (const auto& [grey, time] : m_clear) cv::accumulate(grey, sum);
  sum.convertTo(m_background, CV_8UC1, 1.0 / static_cast<double>(m_clear.size()));
  if (MaybeError s = m_sensor.SetBackground(m_background)) return s;
  int index = 0;
  for (const auto& [grey, time] : m_clear) {
    Result<ContourFrame> r = m_sensor.Step(grey, index++, time);
    if (!r) return r.error();
    const cv::Mat& highpass = m_sensor.StageImage(SensingStage::kHighpass);
    // contacts above a level shrink as the level rises: the first level that shows none, by
    // bisection in [m_noiseLevel, 255] (the frames before already show none above m_noiseLevel)
    if (!ShowsContact(highpass, m_noiseLevel)) continue;
    int low = m_noiseLevel, high = 255;  // shows at low, none at high
    while (high - low > 1) {
      const int mid = (low + high) / 2;
      (ShowsContact(highpass, mid) ? low : high) = mid;
    }
    m_noiseLevel = high;
  }
  m_clearFrames = static_cast<int>(m_clear.size());
  m_clear.clear();
  m_clear.shrink_to_fit();
  return std::nullopt;
}

bool SensingTuner::ShowsContact(const cv::Mat& highpass, int level) {
  cv::threshold(highpass, m_binary, level, 255, cv::THRESH_BINARY);
  if (!m_kernel.empty()) cv::morphologyEx(m_binary, m_binary, cv::MORPH_OPEN, m_kernel);
  const int count = cv::connectedComponentsWithStats(m_binary, m_labels, m_stats, m_centroids, 8);
  for (int k = 1; k < count; ++k) {
    if (m_stats.at<int>(k, cv::CC_STAT_AREA) >= m_minPixels) return true;
  }
  return false;
}

// Every component above N that is large enough to be a contact, and its peak level: the highest
// 3x3 mean in it. A single pixel's maximum would add about 2.5 sigma of camera noise to a touch's
// contrast (the most of ~50 noisy pixels); the 3x3 mean cuts that to a third and leaves the centre
// of a touch wider than 3 px as it is.
void SensingTuner::CollectTouchPeaks(const cv::Mat& highpass) {
  cv::blur(highpass, m_mean, cv::Size(3, 3));
  cv::threshold(highpass, m_binary, m_noiseLevel, 255, cv::THRESH_BINARY);
  if (!m_kernel.empty()) cv::morphologyEx(m_binary, m_binary, cv::MORPH_OPEN, m_kernel);
  const int count = cv::connectedComponentsWithStats(m_binary, m_labels, m_stats, m_centroids, 8);
  if (count <= 1) return;
  std::vector<int> peak(static_cast<size_t>(count), 0);
  for (int k = 1; k < count; ++k) {
    const int x0 = m_stats.at<int>(k, cv::CC_STAT_LEFT), y0 = m_stats.at<int>(k, cv::CC_STAT_TOP);
    const int x1 = x0 + m_stats.at<int>(k, cv::CC_STAT_WIDTH);
    const int y1 = y0 + m_stats.at<int>(k, cv::CC_STAT_HEIGHT);
    if (m_stats.at<int>(k, cv::CC_STAT_AREA) < m_minPixels) continue;
    for (int y = y0; y < y1; ++y) {
      const int* label = m_labels.ptr<int>(y);
      const uint8_t* h = m_mean.ptr<uint8_t>(y);
      for (int x = x0; x < x1; ++x)
        if (label[x] == k) peak[static_cast<size_t>(k)] = std::max<int>(peak[k], h[x]);
    }
    m_peaks.push_back(peak[static_cast<size_t>(k)]);
  }
}

Result<TuneProposal> SensingTuner::Propose() const {
  if (!m_configured) return MakeError({"tune"}, "the tuner is not configured");
  if (!m_touching || m_touchFrames == 0)
    return MakeError({"tune"}, "the capture ended within its clear part (the first " +
                                   Number(m_options.clearSeconds) +
                                   " s): touch the table after it");
  if (m_clearFrames == 0)
    return MakeError({"tune"},
                     "the capture has no clear-table frame: its first frame came after "
                     "the clear part");
  if (static_cast<int>(m_peaks.size()) < m_options.minTouches)
    return MakeError({"tune"}, std::to_string(m_peaks.size()) + " touches brighter than the " +
                                   "clear table (high-pass level above " +
                                   std::to_string(m_noiseLevel) + ") in " +
                                   std::to_string(m_touchFrames) + " frames; " +
                                   std::to_string(m_options.minTouches) +
                                   " are needed: was the table clear at first, and touched after?");
  TuneProposal p;
  p.background = m_background.clone();
  p.clearFrames = m_clearFrames;
  p.touchFrames = m_touchFrames;
  p.noiseLevel = m_noiseLevel;
  p.touchPeaks = m_peaks;
  std::vector<int> sorted = m_peaks;
  std::sort(sorted.begin(), sorted.end());
  const size_t rank =
      static_cast<size_t>(std::ceil(m_options.weakQuantile * static_cast<double>(sorted.size())));
  p.weakTouch = sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
  p.level = std::max(m_noiseLevel, static_cast<int>(std::floor(0.5 * p.weakTouch)));

  p.params = m_given;
  SetContactLevel(p.params, p.level);
  p.values = {{"gain", Number(p.params.gain)},
              {"threshold", Number(p.params.threshold)},
              {"threshold_mode", "\"fixed\""}};
  return p;
}

}  // namespace pg
