#include "proxygrasp/sensing/highpass.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pg {

namespace {

// Rounds to the nearest integer, ties to even: the instruction OpenCV's vector code rounds with
// (cvtss2si), so a mean or a gained level rounds as cv::blur's and convertTo's do.
inline int RoundFloat(float x) {
#if defined(__SSE2__)
  return _mm_cvtss_si32(_mm_set_ss(x));
#else
  return static_cast<int>(std::lrintf(x));
#endif
}

}  // namespace

void SpanHighpass::Configure(int width, uint8_t cap, double gain) {
  assert(width >= 3 && width % 2 == 1 && "the box is odd and at least 3 px wide");
  assert(gain > 0.0 && "the gain is positive");
  m_width = width;
  m_radius = width / 2;
  m_cap = cap;
  // cv::blur scales the box's sum by 1 / width^2 in float (its vector code; its scalar tail in
  // double gives the same level: with an odd count no sum lies on a tie, and for boxes up to
  // 255 px the sum's distance from one is above float's error)
  m_scale = static_cast<float>(1.0 / (static_cast<double>(width) * width));
  m_gain = static_cast<float>(gain);
  m_gained = gain != 1.0;
}

void SpanHighpass::Begin(const cv::Mat& src) {
  assert(src.type() == CV_8UC1 && "the high-pass takes an 8-bit grey image");
  assert(m_width > 0 && "Configure comes first");
  m_src = src;
  m_row = -1;
  m_sums.resize(static_cast<size_t>(src.cols + 2 * m_radius));  // summed afresh at the first row
  m_prefix.resize(static_cast<size_t>(src.cols + 2 * m_radius + 1));
}

void SpanHighpass::MoveTo(int y) {
  const int rows = m_src.rows, cols = m_src.cols, r = m_radius;
  uint32_t* sums = m_sums.data() + r;
  const auto row = [&](int v) { return m_src.ptr<uint8_t>(std::clamp(v, 0, rows - 1)); };
  if (m_row < 0 || y < m_row || 2 * (y - m_row) > m_width) {
    // afresh: the box's rows summed (a roll of that many rows, two row operations each, costs more)
    std::fill(m_sums.begin(), m_sums.end(), 0u);
    for (int v = y - r; v <= y + r; ++v) {
      const uint8_t* p = row(v);
      for (int x = 0; x < cols; ++x) sums[x] += p[x];
    }
  } else {
    // rolled down a row at a time: the row entering below in, the one leaving above out
    for (int v = m_row + 1; v <= y; ++v) {
      const uint8_t* in = row(v + r);
      const uint8_t* out = row(v - r - 1);
      for (int x = 0; x < cols; ++x) sums[x] += static_cast<uint32_t>(in[x]) - out[x];
    }
  }
  // the border replicated: r columns beyond each side read the edge column
  std::fill(m_sums.begin(), m_sums.begin() + r, sums[0]);
  std::fill(m_sums.begin() + r + cols, m_sums.end(), sums[cols - 1]);
  m_row = y;
}

uint8_t SpanHighpass::Level(uint8_t s, uint32_t box) const {
  const int mean = RoundFloat(static_cast<float>(box) * m_scale);
  return static_cast<uint8_t>(std::max(0, s - std::min(mean, static_cast<int>(m_cap))));
}

uint8_t SpanHighpass::Gain(uint8_t h) const {
  if (!m_gained) return h;
  return cv::saturate_cast<uint8_t>(RoundFloat(static_cast<float>(h) * m_gain));
}

void SpanHighpass::Span(int y, int x0, int x1, cv::Mat& highpass, cv::Mat& gained) {
  assert(y >= 0 && y < m_src.rows && x0 >= 0 && x1 <= m_src.cols && "a span inside the image");
  if (x1 <= x0) return;
  if (y != m_row) MoveTo(y);
  // m_sums[x + r + d] is column x + d's sum (|d| <= r): the box of x0 + j sums the w entries
  // from m_sums[x0 + j], which is prefix[j + w] - prefix[j]
  const int n = x1 - x0, w = m_width;
  const uint32_t* sums = m_sums.data() + x0;
  uint32_t* prefix = m_prefix.data();
  uint32_t total = 0;
  prefix[0] = 0;
  for (int i = 0; i < n + w - 1; ++i) {
    total += sums[i];
    prefix[i + 1] = total;
  }
  const uint8_t* s = m_src.ptr<uint8_t>(y) + x0;
  uint8_t* h = highpass.ptr<uint8_t>(y) + x0;
  uint8_t* g = m_gained ? gained.ptr<uint8_t>(y) + x0 : nullptr;
  int j = 0;
#if defined(__SSE2__)
  // eight pixels at a time, with the scalar code's arithmetic: the sum converted to float,
  // scaled, rounded by the same instruction's rule (cvtps2dq as cvtss2si), at most the cap
  // (the means fit 16 bits), subtracted with saturation at 0
  if (!m_gained) {
    const __m128 scale = _mm_set1_ps(m_scale);
    const __m128i cap = _mm_set1_epi16(static_cast<int16_t>(m_cap));
    const __m128i zero = _mm_setzero_si128();
    const auto means = [&](int at) {
      const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(prefix + at + w));
      const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(prefix + at));
      return _mm_cvtps_epi32(_mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(hi, lo)), scale));
    };
    for (; j + 8 <= n; j += 8) {
      const __m128i mean = _mm_min_epi16(_mm_packs_epi32(means(j), means(j + 4)), cap);
      const __m128i px =
          _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(s + j)), zero);
      const __m128i out = _mm_packus_epi16(_mm_subs_epu16(px, mean), zero);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(h + j), out);
    }
  }
#endif
  for (; j < n; ++j) {
    h[j] = Level(s[j], prefix[j + w] - prefix[j]);
    if (g) g[j] = Gain(h[j]);
  }
}

uint8_t SpanHighpass::At(int x, int y) const {
  const int rows = m_src.rows, cols = m_src.cols, r = m_radius;
  uint32_t box = 0;
  for (int v = y - r; v <= y + r; ++v) {
    const uint8_t* p = m_src.ptr<uint8_t>(std::clamp(v, 0, rows - 1));
    for (int u = x - r; u <= x + r; ++u) box += p[std::clamp(u, 0, cols - 1)];
  }
  return Level(m_src.ptr<uint8_t>(y)[x], box);
}

}  // namespace pg
