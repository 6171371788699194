// The sensing view for tuning a real table: every stage of the filter chain side by side, and the
// camera image with the contacts' outlines and ids drawn on it.
#pragma once

#include "proxygrasp/sensing/sensor.h"

#include <opencv2/core.hpp>

#include <vector>

namespace pg {

/// A contact to draw on the camera image: its outline in table cm and its id (< 0: none).
struct PreviewContact {
  const Blob* blob = nullptr;
  int id = -1;
};

/// A BGR image of the sensor's last frame: the camera image with the contacts' outlines and ids,
/// then each filter stage (SensingStage order, background to binary), labelled, in a grid of
/// `columns` tiles each the camera image's size times `scale` (> 0; the outlines, ids and labels
/// are drawn at that size). The stages that hold differences from the background (subtracted,
/// smoothed, high-pass, gained) are brightened so that the last frame's threshold (over the gain
/// before the gain) shows as grey 128, by at least 1x and at most 64x, written in their labels.
/// Empty when the sensor has not run a frame.
cv::Mat SensingPreview(const Sensor& sensor, const std::vector<PreviewContact>& contacts,
                       int columns = 4, double scale = 1.0);

}  // namespace pg
