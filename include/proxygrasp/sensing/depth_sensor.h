// Touch from depth (A. Wilson, "Using a Depth Camera as a Touch Sensor", ITS 2010): a depth camera
// above the table; a per-pixel model of the surface learned from the frames; a pixel touches when
// it lies within a band above the surface, and hovers above the band up to a ceiling. Touch regions
// become the same ContourFrame as the IR chain's (contours in table cm), each contour point with
// the height measured there; hover regions come with theirs. docs/sensing.md, "Depth cameras".
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pg {

/// Parameters of touch from depth. Section [depth] of a level. The derivations of the defaults are
/// in docs/sensing.md, "Depth cameras".
struct DepthParams {
  int surfaceFrames = 15;         ///< frames averaged into the surface model at start, frames
  double surfaceLearning = 10.0;  ///< surface's time constant where nothing is near, s (0 = fixed)
  double surfaceRecovery = 1.0;   ///< time constant where the surface reads farther than learned
                                  ///< (something left that was there at the start), s
  double touchLow = 0.5;          ///< lower edge of the touch band above the surface, cm
  double touchHigh = 2.0;         ///< upper edge of the touch band (finger thickness + noise), cm
  double hoverCeiling = 30.0;     ///< highest hover above the surface, cm
  double noiseFactor = 4.0;       ///< a pixel touches only this many of its noise deviations up, 1
  double noiseFloor = 1.5;        ///< least noise deviation at 1 m, mm (grows with distance^2)
  double hoverMinArea = 1.0;      ///< smallest hover region kept, cm^2
  double heightRadius = 0.5;      ///< a contour point's height: the median within this, cm
  double minWidth = 0.6;          ///< a touch region narrower than this everywhere and lying
                                  ///< along hover is the side of a body above the band, cm
};

void Describe(DepthParams& p, ParamVisitor& v);

/// The images of the depth chain, each kept for viewing after DepthSensor::Step.
enum class DepthStage {
  kDepth,    ///< the frame, mm (CV_16UC1)
  kSurface,  ///< the surface model, mm (CV_32F)
  kHeight,   ///< height above the surface, mm (CV_32F; the surface's distance where no reading)
  kTouch,    ///< the touch band, after the opening, 0/255 (CV_8UC1)
  kHover,    ///< above the band up to the ceiling, 0/255 (CV_8UC1)
};
inline constexpr const char* kDepthStageNames[] = {"depth", "surface", "height", "touch", "hover"};
inline constexpr int kDepthStageCount = 5;

/// Turns depth frames (CV_16UC1, mm, 0 = no reading) into contour frames with heights.
class DepthSensor {
 public:
  /// Reads sensing.calibration (or maps the image linearly onto the table), checks the
  /// parameters. The sensing parameters give the opening, min_area and spacing, as for the IR
  /// chain. Errors name the calibration file or the parameter.
  MaybeError Configure(const DepthParams& depth, const SensingParams& sensing,
                       const TableParams& table, cv::Size imageSize);
  /// Changes the parameters between frames; surface_frames and the calibration need Configure.
  MaybeError SetParams(const DepthParams& depth, const SensingParams& sensing);

  /// One depth frame of the configured size. While the surface is being learned
  /// (DepthParams::surfaceFrames) the frame has no blobs. A wrong size or type is an Error naming
  /// the frame. `time` (s) paces the learning.
  Result<ContourFrame> Step(const cv::Mat& depthMm, int64_t index, double time);

  /// True once the surface model is learned.
  bool HasSurface() const { return m_seeded; }
  /// The surface model, mm (CV_32F), and its per-pixel noise deviation as measured, mm (CV_32F;
  /// the band uses at least DepthParams::noiseFloor scaled to the distance).
  const cv::Mat& Surface() const { return m_surface; }
  const cv::Mat& SurfaceNoise() const { return m_noise; }
  /// The touch band's lower edge per pixel, mm (CV_32F; empty before the surface is learned):
  /// touch_low, or noise_factor deviations of the pixel's noise when that is higher.
  const cv::Mat& BandLow() const { return m_threshold; }
  /// Uses this surface (CV_32F mm, holes as 0 filled from neighbours) with `noise` mm everywhere.
  MaybeError SetSurface(const cv::Mat& surfaceMm, double noiseMm);

  /// The image of one stage of the last frame (empty before the first).
  const cv::Mat& StageImage(DepthStage stage) const;
  const DepthParams& params() const { return m_depth; }
  const CameraModel& model() const { return m_model; }
  bool configured() const { return m_configured; }

 private:
  // the band's lower edge per pixel, from the noise and the parameters
  void UpdateBand();
  void Seed(const cv::Mat& depthMm);
  void Classify(const cv::Mat& depthMm);
  // the opening; true when only `areas` (rows) of the mask can hold pixels after it
  bool Open(cv::Mat& mask, std::vector<uint8_t>& rows, std::vector<cv::Rect>& areas);
  void Learn(const cv::Mat& depthMm, double dt);
  // the regions of `mask` (in `areas` only, when given), without the strips along the side of
  // a body above the band: narrower than `minWidth` cm everywhere and lying along hover (0: all)
  void Extract(const cv::Mat& mask, const std::vector<cv::Rect>* areas, double minArea,
               double minWidth, std::vector<Blob>& blobs);
  // the widest disk within the outer border `pixels` of a region, diameter in px
  double InscribedWidth(const std::vector<cv::Point>& pixels);
  // the share of border pixels `pixels` with a hover pixel within `reach` px
  double HoverShare(const std::vector<cv::Point>& pixels, int reach) const;

  DepthParams m_depth;
  SensingParams m_sensing;
  TableParams m_table;
  CameraModel m_model;
  cv::Matx33d m_tableToCamera = cv::Matx33d::eye();
  cv::Size m_size;
  bool m_configured = false;

  // the surface model: mean and deviation, mm
  cv::Mat m_sum, m_sumSq, m_count;  // CV_64F / CV_32S while seeding
  int m_seedFrames = 0;
  bool m_seeded = false;
  cv::Mat m_surface, m_noise;  // CV_32F
  cv::Mat m_threshold;         // CV_32F: the band's lower edge per pixel, mm
  // CV_32F: with the calibration's table plane, the height along its normal of an axial mm
  // (PlaneHeightScale); empty without one (heights along the camera's axis)
  cv::Mat m_heightScale;
  double m_lastTime = 0.0;
  bool m_haveTime = false;
  static constexpr int kLearnBands = 8;
  int m_nextBand = 0;
  double m_bandTime[kLearnBands] = {};

  // stage images, reused
  cv::Mat m_frame;   // CV_16UC1
  cv::Mat m_height;  // CV_32F, mm
  cv::Mat m_touch, m_hover, m_near, m_scratch, m_eroded, m_region, m_distance;
  // per row of the touch and hover masks: 1 where the row holds a pixel; the rows' areas where
  // the opened masks can hold any (empty: the whole image)
  std::vector<uint8_t> m_touchRows, m_hoverRows;
  std::vector<cv::Rect> m_touchAreas, m_hoverAreas;
  cv::Mat m_kernel;
  std::vector<std::vector<cv::Point>> m_contours, m_areaContours;
  std::vector<float> m_values;  // heights around one contour point
};

/// Fills pixels of `image` (CV_32F) where `valid` is 0 from their valid neighbours, at growing
/// scales (normalized convolution): every pixel gets a value when any is valid.
void FillHoles(cv::Mat& image, const cv::Mat& valid);

}  // namespace pg
