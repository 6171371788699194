// The clear table seen through contacts: a background estimated from one frame that may show
// fingertips and hands (docs/sensing.md, "Background", "From the first frame").
#pragma once

#include <opencv2/core.hpp>

namespace pg {

/// Scales of the spatial estimate, cm on the table.
struct SpatialBackgroundScales {
  double block = 1.5;   ///< blocks whose median is taken (a fingertip's width)
  double hand = 10.0;   ///< bright regions narrower than this are left out (a palm is 8 to 9 cm)
  double shadow = 3.0;  ///< dark regions narrower than this are left out (a fingertip's shadow)
};

/// Estimates the clear table from one frame that may show contacts: the median of blocks of
/// `scales.block` cm, a grey opening of that grid by a disc `scales.hand` cm across (bright
/// regions narrower than a hand, fingertips and hands, are left out), a closing by a disc
/// `scales.shadow` cm across (dark spots such as a fingertip's shadow are left out), then
/// interpolated bilinearly to full size. `pxPerCm` is the camera's scale. What is static and
/// narrower than a hand but not a contact (an illuminator's hot spot) is left out too: only time
/// tells it from a hand (Sensor's warm-up). CV_8UC1 in, CV_8UC1 out.
cv::Mat EstimateBackground(const cv::Mat& frame, double pxPerCm,
                           const SpatialBackgroundScales& scales = SpatialBackgroundScales());

}  // namespace pg
