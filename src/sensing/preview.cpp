#include "proxygrasp/sensing/preview.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace pg {

namespace {

// a label at the bottom left of a tile: the app's heads-up lines cover the top of the first tiles
void Label(cv::Mat& tile, const std::string& label) {
  const double scale = std::max(0.4, tile.cols / 640.0);
  cv::putText(tile, label, cv::Point(6, tile.rows - static_cast<int>(8 * scale)),
              cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
}

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
  Label(tile, label);
  return tile;
}

// a BGR image at the tile's size: areas averaged when shrinking, pixels kept when enlarging (so a
// mask's or a colour's pixels stay what they are)
cv::Mat Fit(const cv::Mat& bgr, cv::Size size) {
  if (bgr.size() == size) return bgr;
  cv::Mat out;
  cv::resize(bgr, out, size, 0, 0, size.width < bgr.cols ? cv::INTER_AREA : cv::INTER_NEAREST);
  return out;
}

// a black tile that says why it is empty
cv::Mat Missing(cv::Size size, const std::string& label) {
  cv::Mat tile = cv::Mat::zeros(size, CV_8UC3);
  Label(tile, label);
  return tile;
}

// depth (mm, CV_16UC1 or CV_32F) in false colour between `nearMm` (red) and `farMm` (blue); where
// `frame` (CV_16UC1, when given) reads 0: no reading
cv::Mat DepthColour(const cv::Mat& mm, const cv::Mat& frame, double nearMm, double farMm) {
  const double span = std::max(1.0, farMm - nearMm);
  cv::Mat grey;
  // level 255 at the near end, 0 at the far end, saturating outside
  mm.convertTo(grey, CV_8UC1, -255.0 / span, 255.0 * farMm / span);
  cv::Mat bgr;
  cv::applyColorMap(grey, bgr, cv::COLORMAP_TURBO);
  if (!frame.empty() && frame.size() == bgr.size())
    bgr.setTo(cv::Scalar(depth_colors::kNoReading), frame == 0);
  return bgr;
}

// each contact's outline (green) and id (red), from table cm to the tile's pixels
void DrawContacts(cv::Mat& tile, const CameraModel& model, double scale,
                  const std::vector<PreviewContact>& contacts) {
  for (const PreviewContact& c : contacts) {
    if (c.blob == nullptr || c.blob->contour.cols() < 3) continue;
    std::vector<cv::Point> outline;
    for (Eigen::Index k = 0; k < c.blob->contour.cols(); ++k) {
      const Vec2 px = scale * model.TableToCamera(c.blob->contour.col(k));
      outline.emplace_back(static_cast<int>(std::lround(px.x())),
                           static_cast<int>(std::lround(px.y())));
    }
    cv::polylines(tile, outline, true, cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
    if (c.id >= 0) {
      const Vec2 at = scale * model.TableToCamera(c.blob->centroid);
      cv::putText(tile, std::to_string(c.id),
                  cv::Point(static_cast<int>(at.x()) + 6, static_cast<int>(at.y()) - 6),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    }
  }
}

// a 0/255 mask as a white-on-black tile, no reading in dark magenta
cv::Mat MaskTile(const cv::Mat& mask, const cv::Mat& frame, cv::Size size) {
  cv::Mat bgr;
  cv::cvtColor(mask, bgr, cv::COLOR_GRAY2BGR);
  if (!frame.empty() && frame.size() == bgr.size())
    bgr.setTo(cv::Scalar(depth_colors::kNoReadingMask), frame == 0);
  return Fit(bgr, size).clone();
}

}  // namespace

cv::Vec3b HeightColour(float heightMm, float bandLowMm, const DepthParams& p) {
  namespace dc = depth_colors;
  // the sensor's edges: touch from the pixel's lower edge to touch_high, hover above both
  const float low = std::max(bandLowMm, static_cast<float>(10.0 * p.touchLow));
  const float high = std::max(low, static_cast<float>(10.0 * p.touchHigh));
  const float ceiling = std::max(high, static_cast<float>(10.0 * p.hoverCeiling));
  if (!(heightMm >= low)) {
    // below the band: grey, from kBelowDarkest a band's lower edge below the surface (or 1 mm
    // when the edge is 0) to kBelowBrightest at the edge
    const float span = std::max(1.0f, low);
    const float t = std::clamp((heightMm + span) / (2.0f * span), 0.0f, 1.0f);
    const auto g =
        static_cast<uint8_t>(dc::kBelowDarkest + t * (dc::kBelowBrightest - dc::kBelowDarkest));
    return {g, g, g};
  }
  if (heightMm <= high && high > low) {
    const float t = (heightMm - low) / (high - low);
    return {0, static_cast<uint8_t>(dc::kBandDarkest + t * (255 - dc::kBandDarkest)), 0};
  }
  if (heightMm <= ceiling) {
    // hover: blue just above the band to light blue at the ceiling
    const float t = ceiling > high ? (heightMm - high) / (ceiling - high) : 1.0f;
    return {255, static_cast<uint8_t>(200.0f * t), 0};
  }
  return dc::kAboveCeiling;
}

namespace {

// Tiles of one size laid out `columns` to a row, left to right and top to bottom.
cv::Mat Grid(const std::vector<cv::Mat>& tiles, cv::Size size, int columns) {
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  cv::Mat out = cv::Mat::zeros(size.height * rows, size.width * columns, CV_8UC3);
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    tiles[i].copyTo(out(cv::Rect(col * size.width, row * size.height, size.width, size.height)));
  }
  return out;
}

}  // namespace

cv::Mat DepthPreview(const DepthSensor& sensor, const std::vector<PreviewContact>& contacts,
                     const std::vector<Blob>& hover, int columns, double scale) {
  const cv::Mat& frame = sensor.StageImage(DepthStage::kDepth);
  if (frame.empty() || columns < 1 || !(scale > 0.0)) return cv::Mat();
  const cv::Size size(std::max(1, static_cast<int>(frame.cols * scale)),
                      std::max(1, static_cast<int>(frame.rows * scale)));
  const DepthParams& p = sensor.params();
  const cv::Mat& surface = sensor.StageImage(DepthStage::kSurface);
  const cv::Mat& height = sensor.StageImage(DepthStage::kHeight);
  const cv::Mat& touch = sensor.StageImage(DepthStage::kTouch);
  const cv::Mat& over = sensor.StageImage(DepthStage::kHover);
  const bool learned = sensor.HasSurface() && !surface.empty() && !height.empty();

  // the colour scale of depth and surface. Over the whole frame's range (a table a metre away, a
  // hand 30 cm over it) a touching finger, 0.5 to 2 cm over the table, would be a few per cent of
  // the scale and share the table's colour; so the scale is the surface's own range widened by
  // twice touch_high towards the camera and touch_high away from it: on a flat table the band
  // takes a third of the colours, and everything higher than twice the band saturates red.
  double nearMm = 0.0, farMm = 0.0;
  if (learned) {
    cv::minMaxLoc(surface, &nearMm, &farMm);
    nearMm -= 2.0 * 10.0 * p.touchHigh;
    farMm += 10.0 * p.touchHigh;
  } else {
    cv::minMaxLoc(frame, &nearMm, &farMm, nullptr, nullptr, frame != 0);
  }
  char range[64];
  std::snprintf(range, sizeof range, " (%.0f-%.0f mm)", nearMm, farMm);

  std::vector<cv::Mat> tiles;
  // depth, with the contacts
  {
    cv::Mat tile = Fit(DepthColour(frame, frame, nearMm, farMm), size).clone();
    DrawContacts(tile, sensor.model(), scale, contacts);
    Label(tile, std::string("depth + contacts") + range);
    tiles.push_back(tile);
  }
  if (!learned) {
    for (int k = 1; k < kDepthStageCount; ++k)
      tiles.push_back(Missing(size, std::string(kDepthStageNames[k]) + " (learning the surface)"));
  } else {
    // the surface, on the depth's scale (it has no holes: they are filled from their neighbours)
    cv::Mat tile = Fit(DepthColour(surface, cv::Mat(), nearMm, farMm), size).clone();
    Label(tile, std::string("surface") + range);
    tiles.push_back(tile);

    // height above the surface, by the band's colours, and a legend strip of them at its foot
    const cv::Mat& bandLow = sensor.BandLow();
    const float nominalLow = static_cast<float>(10.0 * p.touchLow);
    cv::Mat bgr(height.size(), CV_8UC3);
    for (int y = 0; y < height.rows; ++y) {
      const float* h = height.ptr<float>(y);
      const float* b = bandLow.empty() ? nullptr : bandLow.ptr<float>(y);
      const uint16_t* d = frame.ptr<uint16_t>(y);
      cv::Vec3b* o = bgr.ptr<cv::Vec3b>(y);
      for (int x = 0; x < height.cols; ++x)
        o[x] = d[x] == 0 ? depth_colors::kNoReading : HeightColour(h[x], b ? b[x] : nominalLow, p);
    }
    tile = Fit(bgr, size).clone();
    // the legend: from a band's lower edge below the surface to above the ceiling, the band's
    // part widened to a third of the strip so that its edges show; ticks at its edges
    const double textScale = std::max(0.4, size.width / 640.0);
    const int strip = std::max(6, static_cast<int>(10 * textScale));
    const int foot = size.height - static_cast<int>(24 * textScale);
    const int x0 = size.width / 2, x1 = size.width - 8;
    if (x1 - x0 >= 12 && foot - strip > 0) {
      const double low = 10.0 * p.touchLow, high = std::max(low, 10.0 * p.touchHigh);
      const double ceiling = std::max(high, 10.0 * p.hoverCeiling);
      const int w = x1 - x0, a = x0 + w / 6, b = x0 + w / 2, c = x1 - w / 12;
      auto heightAt = [&](int x) {
        const double below = std::max(1.0, low);
        if (x < a) return -below + (low + below) * (x - x0) / std::max(1, a - x0);
        if (x < b) return low + (high - low) * (x - a) / std::max(1, b - a);
        if (x < c) return high + (ceiling - high) * (x - b) / std::max(1, c - b);
        return ceiling + 1.0;
      };
      for (int x = x0; x < x1; ++x)
        cv::line(
            tile, {x, foot - strip}, {x, foot},
            cv::Scalar(HeightColour(static_cast<float>(heightAt(x)), static_cast<float>(low), p)));
      for (int x : {a, b, c})
        cv::line(tile, {x, foot - strip - 3}, {x, foot + 2}, cv::Scalar(0, 255, 255));
    }
    char band[96];
    std::snprintf(band, sizeof band, "height (band %.1f-%.1f cm, ceiling %.0f cm)", p.touchLow,
                  p.touchHigh, p.hoverCeiling);
    Label(tile, band);
    tiles.push_back(tile);

    // touch, with the contacts
    tile = MaskTile(touch, frame, size);
    DrawContacts(tile, sensor.model(), scale, contacts);
    Label(tile, "touch + contacts");
    tiles.push_back(tile);

    // hover, each region's outline and mean height
    tile = MaskTile(over, frame, size);
    for (const Blob& b : hover) {
      if (b.contour.cols() < 3) continue;
      std::vector<cv::Point> outline;
      for (Eigen::Index k = 0; k < b.contour.cols(); ++k) {
        const Vec2 px = scale * sensor.model().TableToCamera(b.contour.col(k));
        outline.emplace_back(static_cast<int>(std::lround(px.x())),
                             static_cast<int>(std::lround(px.y())));
      }
      cv::polylines(tile, outline, true, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
      const std::optional<double> mean = b.MeanHeight();
      if (!mean) continue;
      char text[32];
      std::snprintf(text, sizeof text, "%.1f cm", *mean);
      const Vec2 at = scale * sensor.model().TableToCamera(b.centroid);
      cv::putText(tile, text, cv::Point(static_cast<int>(at.x()) + 6, static_cast<int>(at.y())),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 200, 255), 1, cv::LINE_AA);
    }
    Label(tile, "hover + heights");
    tiles.push_back(tile);
  }

  return Grid(tiles, size, columns);
}

cv::Mat SensingPreview(const Sensor& sensor, const std::vector<PreviewContact>& contacts,
                       int columns, double scale) {
  const cv::Mat& camera = sensor.StageImage(SensingStage::kCamera);
  if (camera.empty() || columns < 1 || !(scale > 0.0)) return cv::Mat();
  // tiles are scaled before the outlines and labels go on, so those stay sharp at any size
  const cv::Size size(std::max(1, static_cast<int>(camera.cols * scale)),
                      std::max(1, static_cast<int>(camera.rows * scale)));

  // the camera image with each contact's outline (green) and id (red) in camera pixels
  cv::Mat first = Tile(camera, size, "camera + contacts");
  DrawContacts(first, sensor.model(), scale, contacts);

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
  return Grid(tiles, size, columns);
}

}  // namespace pg
