// Mapping a fresh image's pages at once (synthetic_camera.cpp), for the synthetic cameras.
#pragma once

#include <opencv2/core.hpp>

namespace pg {

/// Maps every whole page of the image's memory in one call (MADV_POPULATE_WRITE) instead of one
/// page fault per 4 KB page as it is first written; nothing where the call is missing or fails.
void PrefaultPages(const cv::Mat& image);

}  // namespace pg
