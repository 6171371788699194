// The high-pass along spans (src/sensing/highpass.cpp) against OpenCV's whole-image chain.
#include "proxygrasp/sensing/highpass.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <random>
#include <string>
#include <vector>

namespace pg {
namespace {

// The chain the sensor runs over a whole frame: cv::blur with the border replicated, at most
// `cap`, subtracted with saturation, then the gain.
void OpenCvHighpass(const cv::Mat& src, int width, double cap, double gain, cv::Mat& highpass,
                    cv::Mat& gained) {
  cv::Mat wide;
  cv::blur(src, wide, cv::Size(width, width), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::min(wide, cap, wide);
  cv::subtract(src, wide, highpass);
  if (gain != 1.0)
    highpass.convertTo(gained, CV_8UC1, gain);
  else
    gained = highpass;
}

// Images a camera gives after the background is subtracted: mostly dark noise, with bright
// discs and wide glows, and two extremes (all 0, all 255).
std::vector<cv::Mat> TestImages(cv::Size size) {
  std::vector<cv::Mat> images;
  std::mt19937 rng(7);
  for (int k = 0; k < 4; ++k) {
    cv::Mat image(size, CV_8UC1);
    cv::randu(image, 0, 6 + 60 * k);
    std::uniform_int_distribution<int> x(-10, size.width + 10), y(-10, size.height + 10),
        radius(2, 40), level(20, 255);
    for (int d = 0; d < 12; ++d)
      cv::circle(image, {x(rng), y(rng)}, radius(rng), cv::Scalar(level(rng)), cv::FILLED);
    cv::GaussianBlur(image, image, cv::Size(), 1.0 + k);
    images.push_back(image);
  }
  images.push_back(cv::Mat::zeros(size, CV_8UC1));
  images.push_back(cv::Mat(size, CV_8UC1, cv::Scalar(255)));
  return images;
}

// Every pixel through spans that cover each row in pieces (rows in increasing order, some
// skipped and some far apart, spans of one pixel to a whole row, against the image's edges):
// bit for bit OpenCV's levels, before and after the gain, and At() for single pixels.
TEST(SpanHighpass, GivesOpenCvsLevelsBitForBit) {
  struct Setting {
    int width;
    double cap, gain;
  };
  const Setting settings[] = {{3, 40.0, 1.0},   {5, 255.0, 1.0}, {23, 40.0, 1.0},
                              {41, 40.0, 2.7},  {41, 12.0, 0.6}, {61, 255.0, 1.0},
                              {101, 40.0, 2.5}, {255, 40.0, 1.0}};
  const cv::Size size(160, 120);
  std::mt19937 rng(11);
  int compared = 0;
  for (const Setting& setting : settings) {
    for (const cv::Mat& image : TestImages(size)) {
      cv::Mat expectHigh, expectGained;
      OpenCvHighpass(image, setting.width, setting.cap, setting.gain, expectHigh, expectGained);
      SpanHighpass hp;
      hp.Configure(setting.width, cv::saturate_cast<uint8_t>(setting.cap), setting.gain);
      hp.Begin(image);
      cv::Mat high = cv::Mat::zeros(size, CV_8UC1), gained = cv::Mat::zeros(size, CV_8UC1);
      std::uniform_int_distribution<int> cut(0, size.width);
      for (int y = 0; y < size.height; ++y) {
        // a few rows left out (their pixels compared through At below)
        if (y % 17 == 5) continue;
        int a = cut(rng), b = cut(rng);
        if (a > b) std::swap(a, b);
        // the row in three spans, the middle one first
        hp.Span(y, a, b, high, gained);
        hp.Span(y, 0, a, high, gained);
        hp.Span(y, b, size.width, high, gained);
      }
      const std::string where =
          "width " + std::to_string(setting.width) + " gain " + std::to_string(setting.gain);
      for (int y = 0; y < size.height; ++y) {
        for (int x = 0; x < size.width; ++x) {
          const uint8_t want = expectHigh.at<uint8_t>(y, x);
          if (y % 17 == 5) {
            // At sums its box directly: every 8th pixel of the wide boxes
            if (setting.width > 61 && x % 8 != 0) continue;
            ASSERT_EQ(hp.At(x, y), want) << where << " at " << x << "," << y;
            ASSERT_EQ(hp.Gain(hp.At(x, y)), expectGained.at<uint8_t>(y, x)) << where;
            continue;
          }
          ASSERT_EQ(high.at<uint8_t>(y, x), want) << where << " at " << x << "," << y;
          if (setting.gain != 1.0) {
            ASSERT_EQ(gained.at<uint8_t>(y, x), expectGained.at<uint8_t>(y, x))
                << where << " at " << x << "," << y;
          }
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 500000);
}

// A single row far below the last (the column sums summed afresh) and rows one after another
// (rolled) give the same levels.
TEST(SpanHighpass, RowsFarApartAndOneAfterAnotherAgree) {
  const cv::Size size(90, 200);
  const cv::Mat image = TestImages(size)[2];
  cv::Mat expectHigh, expectGained;
  OpenCvHighpass(image, 31, 40.0, 1.0, expectHigh, expectGained);
  SpanHighpass hp;
  hp.Configure(31, 40, 1.0);
  hp.Begin(image);
  cv::Mat high = cv::Mat::zeros(size, CV_8UC1), unused;
  const int rows[] = {0, 1, 2, 40, 41, 190, 199};
  for (int y : rows) hp.Span(y, 0, size.width, high, unused);
  for (int y : rows) {
    EXPECT_EQ(cv::norm(high.row(y), expectHigh.row(y), cv::NORM_INF), 0.0) << "row " << y;
  }
}

}  // namespace
}  // namespace pg
