// The sensor's capped high-pass worked out along spans of rows: the pixels that can pass the
// threshold, not the rectangles round them (docs/sensing.md, "High-pass").
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace pg {

/// The capped high-pass of an 8-bit image s: h = s - min(m, cap), saturated at 0, where m is the
/// mean of s over a `width` x `width` box centred on the pixel (the image's border replicated),
/// rounded to the nearest grey level; then, with a gain other than 1, g = h * gain rounded to
/// the nearest level (ties to even) and saturated. Bit for bit what cv::blur (BORDER_REPLICATE),
/// cv::min, cv::subtract and Mat::convertTo give over the whole image, but worked out only over
/// the spans of rows it is asked for: a box's sum is kept per column as the rows go down (one add
/// and one subtract of a row each) and run along each span.
///
/// A frame: Begin, then Span for rows in increasing order (any number of spans per row, any
/// order within a row).
class SpanHighpass {
 public:
  /// `width` odd and at least 3; `cap` the most the high-pass subtracts; `gain` > 0.
  void Configure(int width, uint8_t cap, double gain);
  /// Starts a frame on `src` (CV_8UC1), which must stay unchanged until the frame's last Span.
  void Begin(const cv::Mat& src);
  /// Works out row `y`, columns [x0, x1), into `highpass` and, with a gain other than 1,
  /// `gained` (both CV_8UC1, the size of src).
  void Span(int y, int x0, int x1, cv::Mat& highpass, cv::Mat& gained);
  /// One pixel's high-pass (before the gain), summed directly: for the few pixels read outside
  /// the spans.
  uint8_t At(int x, int y) const;
  /// One level through the gain, as Span applies it.
  uint8_t Gain(uint8_t h) const;

 private:
  // the column sums of the rows [y - r, y + r] (border replicated), row m_row, with r
  // replicated entries on each side: m_sums[r + x] is column x's
  void MoveTo(int y);
  // the high-pass of level s whose box sums to `box`
  uint8_t Level(uint8_t s, uint32_t box) const;

  int m_width = 0, m_radius = 0;
  uint8_t m_cap = 0;
  float m_scale = 0.0f;  // 1 / width^2
  float m_gain = 1.0f;
  bool m_gained = false;
  cv::Mat m_src;
  int m_row = -1;  // the row m_sums is for, -1 before the first Span
  std::vector<uint32_t> m_sums;
  std::vector<uint32_t> m_prefix;  // a span's running sum of m_sums
};

}  // namespace pg
