#include "proxygrasp/sensing/preview.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace pg {

namespace {

// one labelled BGR tile of `size` from a grey stage image, its levels multiplied by `stretch`
cv::Mat Tile(const cv::Mat& grey, cv::Size size, const std::string& label, double stretch = 1.0) {
  cv::Mat tile;
  if (grey.empty()) {
    tile = cv::Mat::zeros(size, CV_8UC3);
  } else {
    cv::Mat scaled = grey;
    if (grey.size() != size)
      cv::resize(grey, scaled, size, 0, 0,
                 size.width < grey.cols ? cv::INTER_AREA : cv::INTER_LINEAR);
    if (stretch != 1.0) {
      // into a new image: `scaled` may still share the sensor's stage image
      cv::Mat bright;
      scaled.convertTo(bright, CV_8UC1, stretch);  // saturating
      scaled = bright;
    }
    cv::cvtColor(scaled, tile, cv::COLOR_GRAY2BGR);
  }
  // the label at the bottom left: the app's heads-up lines cover the top of the first tiles
  const double scale = std::max(0.4, size.width / 640.0);
  cv::putText(tile, label, cv::Point(6, size.height - static_cast<int>(8 * scale)),
              cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  return tile;
}

}  // namespace

cv::Mat SensingPreview(const Sensor& sensor, const std::vector<PreviewContact>& contacts,
                       int columns, double scale) {
  const cv::Mat& camera = sensor.StageImage(SensingStage::kCamera);
  if (camera.empty() || columns < 1 || !(scale > 0.0)) return cv::Mat();
  // tiles are scaled before the outlines and labels go on, so those stay sharp at any size
  const cv::Size size(std::max(1, static_cast<int>(camera.cols * scale)),
                      std::max(1, static_cast<int>(camera.rows * scale)));

  // the camera image with each contact's outline (green) and id (red) in camera pixels
  cv::Mat first = Tile(camera, size, "camera + contacts");
  for (const PreviewContact& c : contacts) {
    if (c.blob == nullptr || c.blob->contour.cols() < 3) continue;
    std::vector<cv::Point> outline;
    for (Eigen::Index k = 0; k < c.blob->contour.cols(); ++k) {
      const Vec2 px = scale * sensor.model().TableToCamera(c.blob->contour.col(k));
      outline.emplace_back(static_cast<int>(std::lround(px.x())),
                           static_cast<int>(std::lround(px.y())));
    }
    cv::polylines(first, outline, true, cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
    if (c.id >= 0) {
      const Vec2 at = scale * sensor.model().TableToCamera(c.blob->centroid);
      cv::putText(first, std::to_string(c.id),
                  cv::Point(static_cast<int>(at.x()) + 6, static_cast<int>(at.y()) - 6),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    }
  }

  // then every stage after the camera, in chain order. The differences from the background
  // (subtracted to gained) are shown brightened so that the threshold shows as mid grey
  // (kThresholdGrey): on a dim table, whose touches are a few grey levels above it, they would
  // be black; on any table, what is grey or brighter in them is what can pass the threshold
  // (before the high-pass and the gain, the threshold over the gain). Never darkened, at most
  // kMostStretch times; the factor is in the label.
  constexpr double kThresholdGrey = 128.0;
  constexpr double kMostStretch = 64.0;
  const double gain = sensor.params().gain;
  std::vector<cv::Mat> tiles{first};
  for (int k = 1; k < kSensingStageCount; ++k) {
    const SensingStage stage = static_cast<SensingStage>(k);
    std::string label = kSensingStageNames[k];
    double stretch = 1.0;
    if (stage == SensingStage::kSubtracted || stage == SensingStage::kSmoothed ||
        stage == SensingStage::kHighpass || stage == SensingStage::kGained) {
      const double level = stage == SensingStage::kGained || !(gain > 0.0)
                               ? sensor.LastThreshold()
                               : sensor.LastThreshold() / gain;
      if (level > 0.0) stretch = std::clamp(kThresholdGrey / level, 1.0, kMostStretch);
      if (stretch > 1.0) {
        char times[32];
        std::snprintf(times, sizeof(times), " (x%.1f)", stretch);
        label += times;
      }
    }
    if (stage == SensingStage::kBinary) {
      // the level the gained image was thresholded at (it adapts: docs/sensing.md, step 7)
      char level[32];
      std::snprintf(level, sizeof(level), " (above %.1f)", sensor.LastThreshold());
      label += level;
    }
    tiles.push_back(Tile(sensor.StageImage(stage), size, label, stretch));
  }
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  cv::Mat out = cv::Mat::zeros(size.height * rows, size.width * columns, CV_8UC3);
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    tiles[i].copyTo(out(cv::Rect(col * size.width, row * size.height, size.width, size.height)));
  }
  return out;
}

}  // namespace pg
