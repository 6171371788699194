// What the sensing stage takes and hands on: contact shapes for the synthetic table camera, the
// sensing parameters, and the contour frame (one Blob per connected component, in table cm).
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/table.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pg {

/// Kinds of contact shape the synthetic table camera can draw.
enum class ShapeKind {
  kCircle,          ///< a fingertip: radius
  kEllipse,         ///< radiusX, radiusY
  kCapsule,         ///< a segment of `length` swept by `radius` (a finger lying flat)
  kConvexPolygon,   ///< points (local cm, any winding)
  kConcavePolygon,  ///< points (local cm, any winding, simple)
  kHandFive,        ///< a palm with five fingers spread, scaled by `scale`
  kHandFlat,        ///< a flat hand, fingers together, scaled by `scale`
  kHandCupped,      ///< the edge of a cupped hand: a C-shaped arc, scaled by `scale`
};

/// Names of ShapeKind values as used in level files, in enum order.
inline constexpr const char* kShapeKindNames[] = {
    "circle", "ellipse", "capsule", "convex", "concave", "hand_five", "hand_flat", "hand_cupped"};

/// A contact shape placed on the table. Sizes in cm, angle in radians CCW. The local frame of a
/// hand has the fingers pointing along +y and the palm centre at the origin.
struct ContactShape {
  ShapeKind kind = ShapeKind::kCircle;
  double radius = 0.8;       ///< circle and capsule radius, cm
  double radiusX = 1.2;      ///< ellipse semi-axis along local x, cm
  double radiusY = 0.8;      ///< ellipse semi-axis along local y, cm
  double length = 3.0;       ///< capsule length between the cap centres, along local x, cm
  double scale = 1.0;        ///< hand size, non-dimensional; 1 is an adult hand about 19 cm long
  std::vector<Vec2> points;  ///< polygon vertices in the local frame, cm
  Pose2 pose;                ///< where the shape sits on the table
  double pressure = 1.0;     ///< brightness of the contact, 0..1 of full contact, non-dimensional
  double height = 0.0;       ///< from the table to the contact's underside, cm (0 = touching)
};

/// What the synthetic table camera is.
enum class CameraKind {
  kIr,     ///< an IR camera under a diffuse-illumination table: 8-bit grey frames
  kDepth,  ///< a Kinect v1-like depth camera above the table: 16-bit depth frames, mm
};
inline constexpr const char* kCameraKindNames[] = {"ir", "depth"};

/// Parameters of the synthetic table camera. Section [camera] of a level.
struct SyntheticCameraParams {
  CameraKind kind = CameraKind::kIr;  ///< IR frames from below or depth frames from above
  int width = 640;                    ///< image width, pixels
  int height = 480;                   ///< image height, pixels
  double background = 40.0;           ///< mean background level, 8-bit grey
  double contactLevel = 220.0;        ///< level of full contact, 8-bit grey
  double haloLevel = 45.0;            ///< extra brightness of a hovering hand's halo, 8-bit grey
  double haloWidth = 1.5;             ///< how far the halo reaches beyond a hand, cm
  double vignetting = 0.25;           ///< brightness lost at the corners, fraction of background
  double gradient = 12.0;             ///< slow left-to-right background ramp, 8-bit grey
  double noise = 3.0;                 ///< Gaussian sensor noise deviation, 8-bit grey
  double distortion = 0.0;            ///< radial lens distortion k1, non-dimensional (0 = none)
  double perspective = 0.0;  ///< camera-to-table keystone, fraction of the width (0 = none)
  int seed = 1;              ///< noise seed; the same seed gives the same frames
  // the depth camera (kind = kDepth); docs/sensing.md, "The synthetic depth camera"
  double cameraHeight = 0.0;  ///< depth camera above the table, cm (0 = derived from the table)
  double projectorBaseline = 7.5;  ///< IR projector's offset from the camera along image x, cm
  double disparityNoise = 0.5;     ///< per-pixel noise deviation, Kinect raw disparity steps
  bool disparitySteps = true;      ///< depth rounded to Kinect v1's 11-bit disparity steps
  double edgeHoles = 0.5;          ///< chance that a pixel at a depth edge reads 0, 0..1
  double edgeJump = 10.0;          ///< depth step that makes an edge, mm
  double fingerThickness = 1.2;    ///< a finger's (and a fingertip pad's) thickness, cm
  double fingerRise = 25.0;        ///< a fingertip's finger rising toward the arm, deg
  double fingerLength = 6.0;       ///< the finger's reach from the pad's centre, cm
  double palmThickness = 2.5;      ///< a hand's palm thickness (scale 1), cm
  double armRise = 20.0;           ///< a hand's forearm rising from the wrist, deg
};

/// Threshold modes.
enum class ThresholdMode {
  kFixed,     ///< the fixed `threshold`
  kAuto,      ///< Otsu's method on each frame, never below `auto_floor`
  kAdaptive,  ///< a fraction of the table's brightest recent touch, above its noise, at most
              ///< `threshold`
};
inline constexpr const char* kThresholdModeNames[] = {"fixed", "auto", "adaptive"};

/// Parameters of preprocessing and contour extraction. Section [sensing] of a level.
struct SensingParams {
  std::string calibration;        ///< calibration YAML file, "" maps the image linearly
  int backgroundFrames = 0;       ///< frames averaged into the background at start (0 = estimate)
  double backgroundWarmup = 0.2;  ///< time an estimated background takes its per-pixel low, s
  bool stills = false;  ///< each frame on its own: spatial background, level from the frame
  double backgroundSettle = 5.0;  ///< time after the warm-up a darker frame is learned fast, s
  double backgroundStill =
      0.5;  ///< a region there from the start that moved: held out until still, s
  double backgroundLearning = 10.0;  ///< learned background's time constant, s (0 = frozen)
  double touchLearning = 300.0;  ///< the background's time constant under contacts, s (0 = never)
  double smooth = 0.0;           ///< Gaussian smoothing deviation, cm (0 = none)
  double highpassWidth = 4.0;    ///< width of the blur the high-pass subtracts, cm (0 = none)
  double highpassCap = 40.0;     ///< most slow brightness the high-pass removes, 8-bit grey
  double gain = 1.0;             ///< amplification after the high-pass, non-dimensional
  ThresholdMode thresholdMode = ThresholdMode::kAdaptive;  ///< how the threshold is set
  double threshold = 30.0;  ///< fixed threshold on the filtered image (adaptive: the highest), grey
  double autoFloor = 30.0;  ///< lowest threshold the automatic mode may pick, 8-bit grey
  double noiseFactor = 5.0;       ///< adaptive: lowest level, in camera noise deviations, 1
  double contrastFraction = 0.3;  ///< adaptive: level as a fraction of the brightest touch, 1
  double contrastMemory = 60.0;   ///< adaptive: how long the brightest touch is remembered, s
  int morphology = 1;             ///< radius of the clean-up opening, pixels (0 = none)
  double minArea = 0.5;           ///< smallest contact kept, cm^2
  double spacing = 0.3;           ///< arc-length spacing of resampled contours, cm
  bool subpixel = true;           ///< move contour points onto the half-contrast edge, sub-pixel
  double tableCmPerPixel = 0.1;   ///< pixel size of the table-aligned image (when asked), cm
};

/// One connected component: an evenly resampled outer contour and its summary, in table cm.
struct Blob {
  Contour contour;                ///< CCW, implicitly closed, spacing ~SensingParams::spacing
  Vec2 centroid = Vec2::Zero();   ///< area centroid, cm
  double area = 0.0;              ///< cm^2
  Vec2 boundsMin = Vec2::Zero();  ///< bounding box corner, cm
  Vec2 boundsMax = Vec2::Zero();  ///< bounding box corner, cm
  /// Depth cameras: the height measured above the surface at each contour point, cm (one per
  /// column of `contour`); empty for the IR camera.
  std::vector<double> heights;
  /// Depth cameras: a region above the touch band (ContourFrame::hover), not a touch. The
  /// simulation tracks such regions with the touches for measured placement (docs/proxies.md).
  bool hover = false;

  /// The mean of `heights`, cm: the contact's height as `sense`, the traces, TUIO and the
  /// preview give it. Nothing without heights (the IR camera).
  std::optional<double> MeanHeight() const {
    if (heights.empty()) return std::nullopt;
    double sum = 0.0;
    for (const double h : heights) sum += h;
    return sum / static_cast<double>(heights.size());
  }
};

/// A table-aligned image: pixel (u, v) covers table point origin + (u + 0.5, v + 0.5) * cmPerPixel.
struct TableImage {
  cv::Mat image;               ///< 8-bit level-normalized contact image (CV_8UC1)
  double cmPerPixel = 0.1;     ///< cm
  Vec2 origin = Vec2::Zero();  ///< table position of the image's top-left corner, cm
};

/// The output of the sensing stage for one camera frame.
struct ContourFrame {
  int64_t index = 0;        ///< frame number from 0
  double time = 0.0;        ///< s
  std::vector<Blob> blobs;  ///< one per connected component, largest first
  std::vector<Blob> hover;  ///< depth cameras: regions above the touch band (hands over the
                            ///< table), with heights, largest first; empty for the IR camera
  TableImage tableImage;    ///< the contact image on the table grid (instant mode, drawing)
};

void Describe(SyntheticCameraParams& p, ParamVisitor& v);
void Describe(SensingParams& p, ParamVisitor& v);

}  // namespace pg
