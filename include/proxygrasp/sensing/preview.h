// The sensing view for tuning a real table: every stage of the filter chain side by side, and the
// camera image with the contacts' outlines and ids drawn on it; for a depth camera, the depth
// chain's stages (depth, surface, height above it, touch and hover) in false colour.
#pragma once

#include "proxygrasp/sensing/depth_sensor.h"
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

/// Colours of the depth tiles (BGR), shared with tests that look for them.
namespace depth_colors {
/// no reading (depth 0): in the depth, surface and height tiles
inline const cv::Vec3b kNoReading(255, 0, 255);
/// no reading in the touch and hover tiles (their masks are white)
inline const cv::Vec3b kNoReadingMask(128, 0, 128);
/// the height tile: grey below the band (the surface and its noise), green in the band (darkest
/// at touch_low, brightest at touch_high), blue to light blue above it up to the hover ceiling,
/// white above the ceiling
inline constexpr int kBelowDarkest = 60, kBelowBrightest = 120;
inline constexpr int kBandDarkest = 140;
inline const cv::Vec3b kAboveCeiling(255, 255, 255);
}  // namespace depth_colors

/// The height tile's colour of `heightMm` above the surface at a pixel whose touch band starts at
/// `bandLowMm` (DepthSensor::BandLow: touch_low, higher where the pixel is noisy) and ends at
/// touch_high (an empty band where it starts above that), hover up to hover_ceiling (`p`).
/// depth_colors gives the scheme.
cv::Vec3b HeightColour(float heightMm, float bandLowMm, const DepthParams& p);

/// The depth chain's view of the sensor's last frame, BGR, in a grid of `columns` tiles each the
/// depth image's size times `scale` (> 0), each labelled:
/// - depth (false colour, near red, far blue) with the contacts' outlines (green) and ids (red);
/// - surface, on the same colour scale: the surface model's range widened by twice touch_high
///   towards the camera and touch_high away from it, so that a touching finger shows a colour of
///   its own while everything higher saturates (before the surface is learned, the frame's range);
/// - height above the surface (HeightColour, each pixel with its own band), a legend strip of the
///   colours with the band's nominal edges (touch_low, touch_high, hover_ceiling) at its foot;
/// - touch: the band's mask with the contacts' outlines and ids;
/// - hover: its mask with each hover region's outline (yellow) and mean height in cm.
/// No reading is depth_colors::kNoReading (kNoReadingMask on the masks). Tiles of stages not
/// run yet (the surface is still being learned) are black and say so. Empty when the sensor has
/// not taken a frame, or `columns` < 1 or `scale` <= 0.
cv::Mat DepthPreview(const DepthSensor& sensor, const std::vector<PreviewContact>& contacts,
                     const std::vector<Blob>& hover, int columns = 3, double scale = 1.0);

}  // namespace pg
