#include "proxygrasp/sensing/background.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace pg {

cv::Mat EstimateBackground(const cv::Mat& frame, double pxPerCm,
                           const SpatialBackgroundScales& scales) {
  assert(frame.type() == CV_8UC1 && "background estimate needs an 8-bit grey frame");
  assert(pxPerCm > 0.0 && "the camera's scale must be positive");
  // blocks a fingertip wide (at least 4 px): their median is the table's level unless a contact
  // covers half the block or more, and it averages the noise of a few hundred pixels away
  const int block = std::max(4, static_cast<int>(std::lround(scales.block * pxPerCm)));
  const double blockCm = block / pxPerCm;
  const int bw = (frame.cols + block - 1) / block;
  const int bh = (frame.rows + block - 1) / block;
  cv::Mat level(bh, bw, CV_32F);
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      const cv::Rect r(bx * block, by * block, std::min(block, frame.cols - bx * block),
                       std::min(block, frame.rows - by * block));
      std::array<int, 256> hist{};
      for (int y = r.y; y < r.y + r.height; ++y) {
        const uint8_t* row = frame.ptr<uint8_t>(y);
        for (int x = r.x; x < r.x + r.width; ++x) ++hist[row[x]];
      }
      const int half = r.area() / 2;
      int seen = 0, value = 0;
      while (value < 255 && seen + hist[value] <= half) seen += hist[value++];
      level.at<float>(by, bx) = static_cast<float>(value);
    }
  }
  // Bright regions narrower than a hand go: the opening (the minimum over a disc, then the
  // maximum over it) keeps a level only where a whole disc a hand across lies at or above it.
  // Then dark spots narrower than a fingertip's shadow go (the closing). Beyond the grid's edge
  // neither reads anything (OpenCV's default morphology border).
  const auto disc = [&](double cm) {
    const int r = std::max(1, static_cast<int>(std::lround(0.5 * cm / blockCm)));
    return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  };
  cv::morphologyEx(level, level, cv::MORPH_OPEN, disc(scales.hand));
  cv::morphologyEx(level, level, cv::MORPH_CLOSE, disc(scales.shadow));

  // block centres to pixels, bilinearly
  cv::Mat full;
  cv::resize(level, full, cv::Size(bw * block, bh * block), 0, 0, cv::INTER_LINEAR);
  cv::Mat out;
  full(cv::Rect(0, 0, frame.cols, frame.rows)).convertTo(out, CV_8UC1);
  return out;
}

}  // namespace pg
