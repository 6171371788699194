// The synthetic table camera: renders contact shapes placed in table cm into 8-bit frames that look
// like a diffuse-illumination table seen from below (bright contacts, a dim halo around hands,
// vignetting, a background gradient, Gaussian noise, optional lens distortion and perspective), and
// reports the true outlines so tests can measure the sensing pipeline against them. With
// `kind = depth` it is a Kinect v1-like depth camera above the table instead: 16-bit depth frames
// (mm, 0 = no reading) of the contacts as fingers and hands with thickness (synthetic_depth.cpp;
// docs/sensing.md, "The synthetic depth camera").
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/rng.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <span>
#include <string>
#include <vector>

namespace pg {

/// Signed distance from a table point to the shape's boundary, cm: negative inside. Exact for
/// circles, capsules and polygons; a close approximation near the boundary of ellipses; hands are
/// smooth unions of a palm and finger capsules (their zero level is exact).
double ShapeDistance(const ContactShape& shape, const Vec2& tablePoint);

/// A hand's distance as the renderer reads it for the halo outside the outline: bilinear between
/// exact values on a 0.05 cm grid in the hand's unscaled frame, within `error` cm (scale x 0.05 cm)
/// of ShapeDistance. False for shapes other than hands and where the point is off the grid (more
/// than 2.5 cm, unscaled, beyond the hand's bounds); there the renderer takes the exact distance.
bool SampledHandDistance(const ContactShape& shape, const Vec2& tablePoint, double& distance,
                         double& error);

/// A circle in table cm.
struct Circle {
  Vec2 centre = Vec2::Zero();
  double radius = 0.0;  ///< cm
};

/// The fingertips of a hand (hand_five, hand_flat; none for other shapes), thumb first: the
/// centre of each finger's round end and its radius, table cm, at the shape's pose and scale.
std::vector<Circle> HandFingertips(const ContactShape& shape);

/// The true outline of a shape in table cm, counter-clockwise, densely sampled (<= 0.05 cm apart
/// on curves; polygons keep their exact vertices).
Contour ShapeOutline(const ContactShape& shape);

/// Axis-aligned bounds of a shape's outline in table cm: {min, max}.
std::pair<Vec2, Vec2> ShapeBounds(const ContactShape& shape);

/// A ten-fingertip or a two-hand demo scene at a frame, as the `synthetic:` sources show them.
/// `name` is "fingers" or "hands"; returns false for an unknown name.
bool DemoScene(const std::string& name, int64_t frame, const TableParams& table,
               std::vector<ContactShape>& shapes);

/// The depth camera's height above the table, cm: params.cameraHeight, or when that is 0 the
/// least height at which a Kinect v1 (field of view 57 x 43 deg, nearest reading 80 cm) sees the
/// whole table and a body up to kDepthTallestBody above it: max(width / (2 tan 28.5 deg),
/// height / (2 tan 21.5 deg), 80 cm + kDepthTallestBody); 100 cm for the default 61 x 46 cm table.
double DepthCameraHeight(const SyntheticCameraParams& params, const TableParams& table);

/// The tallest a body the depth camera draws rises above the table at `height` 0 (a hand's
/// forearm at scale 1), cm.
inline constexpr double kDepthTallestBody = 20.0;

/// The top of a contact's body above the table at a table point, cm, as the depth camera draws it
/// (fingertips with their finger, hands with their forearm, at the contact's `height`); negative
/// where the body is not.
double BodyTopHeight(const ContactShape& shape, const SyntheticCameraParams& params,
                     const Vec2& tablePoint);

/// The underside of a contact's body above the table at a table point, cm: the contact's
/// `height`, more where a fingertip's finger or a hand's forearm rises; the body is solid from
/// there to its top, with air below (a hovering fingertip's side is seen from its underside up).
/// Negative where the body is not.
double BodyUnderside(const ContactShape& shape, const SyntheticCameraParams& params,
                     const Vec2& tablePoint);

/// How much an IR camera under the table dims a contact `height` cm above the surface: exp(-height
/// / 0.5 cm), so 1 at 0 (touching) and 0.14 at 1 cm. Until hovering is modelled (issue 44) this is
/// all the IR camera does with a keyframe's height.
double IrHoverDimming(double height);

/// Renders contact shapes as a camera under the table would see them. Deterministic: the same
/// params (seed included) and the same calls give the same frames.
class SyntheticCamera {
 public:
  SyntheticCamera(const SyntheticCameraParams& params, const TableParams& table);

  /// Renders one frame of params.width x params.height: CV_8UC1 for the IR camera (each shape at
  /// its pose, dimmed by its height, hands with a halo), CV_16UC1 depth in mm (0 = no reading) for
  /// the depth camera (RenderDepth). Advances the noise generator.
  cv::Mat Render(std::span<const ContactShape> shapes);

  /// The depth camera's frame (whatever the kind): the bodies seen in perspective from
  /// cameraHeight() above the table's centre, the projector's shadow, holes at depth edges, noise
  /// and disparity steps as the params say. CV_16UC1, mm, 0 = no reading.
  cv::Mat RenderDepth(std::span<const ContactShape> shapes);

  /// What the camera is (params.kind).
  CameraKind kind() const { return m_params.kind; }
  /// The depth camera's height above the table, cm (DepthCameraHeight).
  double cameraHeight() const { return m_cameraHeight; }

  /// The true outlines of the shapes, one per shape, in table cm (see ShapeOutline).
  std::vector<Contour> TrueOutlines(std::span<const ContactShape> shapes) const;

  /// Renders an arbitrary table-space image through the same camera model (perspective,
  /// distortion, vignetting, background, noise). tableImage covers the whole table: its top-left
  /// corner is table point (0, height) and its bottom-right (width, 0). Its grey levels are
  /// reflectances: 0 shows the background, full scale (255 for 8 bits, 1 for float) full contact
  /// level. Grey, BGR or BGRA; 8-bit, 16-bit or float.
  cv::Mat RenderTableImage(const cv::Mat& tableImage);

  /// The clear-table image without noise (what averaging many empty frames gives): CV_8UC1 for
  /// the IR camera; for the depth camera CV_16UC1, the table plane's depth in mm everywhere
  /// (on a disparity step when disparity_steps is on).
  cv::Mat Background() const;

  /// Changes the lighting and noise between frames: background, contact_level, halo_level,
  /// halo_width, vignetting, gradient and noise (and the depth camera's live keys) take effect
  /// from the next Render (and Background).
  /// A change of what fixes the image or the noise stream (FixedKeysChanged) is an Error and
  /// nothing changes.
  MaybeError SetParams(const SyntheticCameraParams& params);
  /// The keys of the parameters that differ between `params` and those in use and that SetParams
  /// cannot change: "kind", "width", "height", "distortion", "perspective" (the camera model),
  /// "seed" and "camera_height".
  std::vector<std::string> FixedKeysChanged(const SyntheticCameraParams& params) const;

  /// The true camera model: intrinsics, distortion and the camera -> table homography.
  const CameraModel& model() const { return m_model; }
  /// The parameters in use.
  const SyntheticCameraParams& params() const { return m_params; }

 private:
  // the vignetting gain and background level of every pixel, from m_params
  void BuildIllumination();
  // fills the noise bank from the generator
  void DrawNoiseBank();
  // composes contact coverage c and halo h (both CV_32F, 0..1) into a noisy 8-bit frame; c and h
  // are zero outside the `drawn` rectangles
  cv::Mat Compose(const cv::Mat& contact, const cv::Mat& halo, std::span<const cv::Rect> drawn);

  // whether the noise bank is needed for the current params
  bool WantsNoiseBank() const;
  // the depth camera's clear table without noise (Background for kind = kDepth)
  cv::Mat DepthBackground() const;

  SyntheticCameraParams m_params;
  TableParams m_table;
  CameraModel m_model;
  Rng m_rng;
  double m_cameraHeight = 0.0;     // the depth camera's height above the table, cm
  cv::Mat m_tableX, m_tableY;      // CV_32F: the table point each pixel sees, cm
  cv::Mat m_cmPerPixel;            // CV_32F: local pixel size, cm
  cv::Mat m_gain;                  // CV_32F: vignetting gain, 0..1
  cv::Mat m_background;            // CV_32F: background level before vignetting, grey
  cv::Mat m_litBackground;         // CV_32F: m_gain * m_background, the noiseless clear table
  std::vector<float> m_noiseBank;  // standard normal samples, drawn once from the seed
  float m_noiseMax = 0.0f;         // the largest |sample| in the bank

  // Render's coverage and halo images (CV_32F), kept between frames: only the rectangles the last
  // frame drew into are cleared. A copy of the camera starts with its own (empty) scratch, so two
  // copies never draw into one buffer.
  struct Scratch {
    cv::Mat contact, halo;
    std::vector<cv::Rect> drawn;      // pixel rectangles written since the last clear
    std::vector<uint8_t> blockCodes;  // one shape's 4 px blocks: skip, fill or shade
    Scratch() = default;
    Scratch(const Scratch&) {}
    Scratch& operator=(const Scratch&) {
      contact.release();
      halo.release();
      drawn.clear();
      return *this;
    }
  };
  Scratch m_scratch;

  // RenderDepth's working images, kept between frames (fresh ones a frame were page faults); a
  // copy of the camera starts with its own
  struct DepthScratch {
    cv::Mat top, bottom, tileMax, seen, lit, hole, depth;
    DepthScratch() = default;
    DepthScratch(const DepthScratch&) {}
    DepthScratch& operator=(const DepthScratch&) {
      for (cv::Mat* m : {&top, &bottom, &tileMax, &seen, &lit, &hole, &depth}) m->release();
      return *this;
    }
  };
  DepthScratch m_depthScratch;
};

/// The camera model a SyntheticCamera with these params uses (the depth camera's maps the image
/// linearly onto the table: its distortion and perspective are ignored).
CameraModel SyntheticCameraModel(const SyntheticCameraParams& params, const TableParams& table);

}  // namespace pg
