// Finding the drawing's colours in a picture: which pixels have a colour, how many, where.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace pg::test {

/// The pixels of a BGR picture within `tolerance` (per channel) of `color`.
struct ColorPixels {
  int count = 0;
  cv::Point2d centroid;  ///< mean pixel centre, px
  cv::Rect bounds;       ///< bounding box of the pixels
};

inline ColorPixels FindColor(const cv::Mat& bgr, const cv::Scalar& color, int tolerance) {
  cv::Mat mask;
  const cv::Scalar lo(color[0] - tolerance, color[1] - tolerance, color[2] - tolerance);
  const cv::Scalar hi(color[0] + tolerance, color[1] + tolerance, color[2] + tolerance);
  cv::inRange(bgr, lo, hi, mask);
  ColorPixels out;
  out.count = cv::countNonZero(mask);
  if (out.count == 0) return out;
  const cv::Moments m = cv::moments(mask, true);
  out.centroid = {m.m10 / m.m00, m.m01 / m.m00};
  out.bounds = cv::boundingRect(mask);
  return out;
}

}  // namespace pg::test
