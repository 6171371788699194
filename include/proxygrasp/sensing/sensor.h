// The sensing stage: camera frame -> grey -> learned background subtracted -> smoothing ->
// high-pass -> gain -> threshold -> clean-up -> connected components -> exact outer contours
// (sub-pixel) -> table cm -> even arc-length resampling. docs/sensing.md shows each stage.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/background.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/highpass.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pg {

/// The images of the filter chain, in order, each kept for viewing after Sensor::Step.
enum class SensingStage {
  kCamera,      ///< the frame as grey (CV_8UC1)
  kBackground,  ///< the learned background (CV_8UC1)
  kSubtracted,  ///< frame minus background, negative clipped to 0 (CV_8UC1)
  kSmoothed,    ///< after the smoothing blur (CV_8UC1)
  kHighpass,    ///< after the high-pass (CV_8UC1)
  kGained,      ///< after the gain: what is thresholded (CV_8UC1)
  kBinary,      ///< after the threshold and the opening, 0/255 (CV_8UC1)
};
/// Names of SensingStage values, in enum order.
inline constexpr const char* kSensingStageNames[] = {
    "camera", "background", "subtracted", "smoothed", "highpass", "gained", "binary"};
inline constexpr int kSensingStageCount = 7;

/// Turns camera frames into contour frames. Holds the calibration, the background and scratch
/// images, so Step allocates little per frame.
class Sensor {
 public:
  /// Reads params.calibration (or uses LinearCalibration when it is ""), checks that it matches
  /// imageSize, and resets the background. Errors name the calibration file and field.
  MaybeError Configure(const SensingParams& params, const TableParams& table, cv::Size imageSize);
  /// Same, with a calibration already in memory; `source` names it in errors.
  MaybeError Configure(const SensingParams& params, const TableParams& table,
                       const Calibration& calibration, const std::string& source = "calibration");

  /// Changes the parameters of a configured sensor between frames, keeping its calibration and
  /// background: the threshold mode and levels, morphology, min_area, spacing, subpixel and
  /// table_cm_per_pixel take effect from the next frame. A change of what only Configure can
  /// apply (FixedKeysChanged) or an invalid value is an Error, and nothing changes.
  MaybeError SetParams(const SensingParams& params);
  /// The keys of the parameters that differ between `params` and those in use and that SetParams
  /// cannot change: "calibration" (read by Configure) and "background_frames" (used once, when
  /// the background is captured).
  std::vector<std::string> FixedKeysChanged(const SensingParams& params) const;

  /// One frame: processes an 8-bit frame of the configured size, grey (CV_8UC1) or colour (BGR or
  /// BGRA, converted to grey). A wrong size or type, or an empty frame, is an Error naming the
  /// frame index and what was expected. While the background is being captured
  /// (SensingParams::backgroundFrames) the frame has no blobs. `time` (s) paces the background
  /// learning: frames at the same time as the previous one do not change the background.
  Result<ContourFrame> Step(const cv::Mat& frame, int64_t index, double time,
                            bool wantTableImage = false);

  /// Uses this clear-table frame (CV_8UC1, configured size) as the background from now on.
  MaybeError SetBackground(const cv::Mat& background);
  /// True once a background is known (set, loaded, captured or estimated).
  bool HasBackground() const { return !m_background.empty(); }
  /// The background in use (empty before the first frame when none was set), CV_8UC1.
  const cv::Mat& Background() const { return m_background; }

  /// The image of one stage of the last frame (empty before the first frame; the background is
  /// the one learned so far, ready for the next frame). With SetWholeStages(false) the high-pass
  /// and gained images hold their values only along the spans of rows where a contact could be
  /// (every pixel that could pass the threshold), and 0 elsewhere.
  const cv::Mat& StageImage(SensingStage stage) const;
  /// Whether every stage image covers the whole frame (true, the default: for viewing and tuning
  /// the stages) or the high-pass and the gain are worked out only along the spans of rows round
  /// the pixels bright enough to pass the threshold (false: the pipeline, which reads only the
  /// contours).
  /// The contours are the same bits either way. Frames that ask for the table image, and the
  /// automatic threshold (which reads the whole gained image), always work on the whole frame.
  void SetWholeStages(bool whole) { m_wholeStages = whole; }
  bool WholeStages() const { return m_wholeStages; }

  /// The threshold used on the last frame, 8-bit grey above background.
  double LastThreshold() const { return m_lastThreshold; }
  /// The camera model in use (from the calibration).
  const CameraModel& model() const { return m_model; }
  /// The calibration in use.
  const Calibration& calibration() const { return m_calibration; }
  /// The parameters of the last successful Configure.
  const SensingParams& params() const { return m_params; }
  /// True after a successful Configure.
  bool configured() const { return m_configured; }

 private:
  // a new background: what was learned or measured against the old one goes (the learning, the
  // capture of clear frames, the adaptive level's noise and brightest touch)
  void ForgetLearned();
  void ExtractBlobs(std::vector<Blob>& blobs);
  // the border pixels moved onto the sub-pixel edge (a long border's thinned where straight)
  void RefineToEdge(const std::vector<cv::Point>& pixels, std::vector<Vec2>& out);
  void BuildTableMaps();
  // `level` is the threshold the tiles of HighpassWhereContactsCanBe are marked for
  void Filter(bool whole, double level);
  // the high-pass and the gain along the spans of rows where a contact can be
  // (SetWholeStages(false)), into the stage images Filter has made ready
  void HighpassWhereContactsCanBe(int width, double level);
  // the high-pass (box blur `width` px) and the gain over the whole frame
  void HighpassWhole(int width);
  // returns the time since the last frame (0 for the first frame or one at the same time)
  double LearnBackground(double time);
  // the adaptive threshold (gained grey) with this brightest touch remembered
  double AdaptiveLevel(double brightest) const;
  // the background is still being seeded or warmed up (the noise cannot be measured against it)
  bool WarmingUp() const;
  // the camera noise's deviation (grey), never below the rounding of frame and background
  double NoiseDeviation() const;
  // what is bright against the background: a hand's glow, something the warm-up took in
  double BrightMargin() const;
  // the camera noise's deviation in the frame just learned (threshold_mode "adaptive")
  void MeasureNoise(double dt);
  // the brightest fingertip-like touch above `level` (0 when none), where the filter worked
  double BrightestTipAbove(double level);
  // the highest 3x3 mean of pixels above `level` centred on `at` or one of its 8 neighbours
  double PeakAround(cv::Point at, double level) const;
  // true when a ring of a fingertip's diameter around `at` lies mostly below half of `peak`
  bool TipLike(cv::Point at, double peak) const;
  // the end of an estimated background's warm-up: its per-pixel low, floored by the spatial
  // estimate
  void FinishWarmup();
  // the first seconds after the warm-up: where the frame is darker than the background (a hand
  // that lay there at the start has moved), the band of rows r0..r1 comes down to it fast
  bool Settling() const;
  void LowerSettleFloor(double time);
  void SettleDark(int r0, int r1, double bandDt);
  // the first seconds after the warm-up: the bright regions it took in, each brought out whole
  // once part of it shows the table, and taken in again once still (background_still)
  void HoldOutHandLike();
  void TrackStillRegions(double time, double dt);
  double PixelsPerCm() const;

  SensingParams m_params;
  TableParams m_table;
  Calibration m_calibration;
  CameraModel m_model;
  bool m_configured = false;
  bool m_linear = true;  // camera -> table is affine (no distortion): map points without Newton

  cv::Mat m_background;  // CV_8UC1
  // an estimated background: the first frame's spatial estimate (CV_8UC1), and during its
  // warm-up the frames' running mean (time constant a third of the warm-up) and its per-pixel
  // lowest (CV_32F)
  cv::Mat m_spatial;
  cv::Mat m_settleFloor;     // SettleDark's floor before its noise allowance (LowerSettleFloor)
  double m_floorTime = 0.0;  // when it was last lowered
  cv::Mat m_lowMean, m_lowest;
  double m_startTime = 0.0;  // s, the time of the frame the background was estimated from
  cv::Mat m_learned;         // CV_32F, the background being learned
  // the background's long-term level: the frames learned everywhere at touch_learning (CV_32F),
  // and as whole grey levels (CV_8UC1); a glow is what is bright against a background that is
  // not below it (LearnBackground)
  cv::Mat m_reference, m_reference8;
  // after the warm-up, while it settles (TrackStillRegions), over m_brightRect: each pixel of a
  // region the warm-up found bright against the spatial estimate is kStillIn (in the background)
  // or kStillOut (held out at the spatial estimate, its running low kept); the running mean, that
  // low, when each held-out pixel's region last moved, and the offset of a running low below
  // its mean (the warm-up's)
  enum : uint8_t { kStillNone = 0, kStillIn = 1, kStillOut = 2 };
  cv::Rect m_brightRect;
  cv::Mat m_stillState;             // CV_8UC1
  cv::Mat m_stillMean, m_stillLow;  // CV_32F
  cv::Mat m_movedTime;              // CV_32F, s since m_startTime
  cv::Mat m_shown;                  // CV_8UC1 scratch: pixels that showed the table this frame
  cv::Mat m_labels, m_stats, m_centroids;  // scratch of the regions' labelling
  std::vector<uint8_t> m_regionFlags;      // per region or contact: moved, or covers clear table
  std::vector<int> m_shownCount;           // per region: pixels that showed the table
  std::vector<float> m_shownContrast;      // per region: the most they came down by, grey
  std::vector<float> m_shownTable;         // per region: the table they showed less the spatial
                                           // estimate, grey (summed, then the mean)
  std::vector<int> m_shownIn;              // per region: of them, those that were in
  bool m_stillOut = false;                 // some pixel is held out
  float m_lowOffset = 0.0f;
  float m_brightMargin = 0.0f;  // grey above the spatial estimate that makes a pixel bright
  double m_lastTime = 0.0;
  double m_learnedTime = 0.0;  // s of frames learned since the background was seeded
  bool m_warmup = false;       // the background is an estimate: warm it up
  bool m_haveTime = false;
  // the learning updates one band of rows a frame, in turn (LearnBackground)
  static constexpr int kLearnBands = 8;
  std::array<double, kLearnBands> m_bandTime{};   // s, when each band was last learned
  std::array<double, kLearnBands> m_touchTime{};  // s, when each band was last learned under
                                                  // contacts
  int m_nextBand = 0;
  bool m_bandsStarted = false;
  cv::Mat m_captureSum;  // CV_32F, while averaging the first frames
  int m_captured = 0;    // frames averaged so far
  double m_lastThreshold = 0.0;
  bool m_wholeStages = true;
  // threshold_mode "adaptive": the camera noise's deviation (grey, < 0 until measured after the
  // warm-up), the brightest touch remembered (filtered grey) and when it was last updated
  double m_noise = -1.0;
  int m_noisePhase = 0;      // the first row MeasureNoise samples, less 4
  double m_noiseSum = 0.0;   // the deviations measured in the first second, summed
  double m_noiseTime = 0.0;  // s of frames measured
  int m_noiseFrames = 0;
  double m_brightest = 0.0;
  double m_brightestTime = 0.0;
  double m_level = -1.0;  // the last adaptive level (filtered grey), < 0 before the first
  // without a touch seen: the level held at the threshold, then falling (filtered grey), since
  double m_falling = 0.0;
  double m_fallStart = 0.0;                                 // s
  std::vector<std::pair<uint8_t, cv::Point>> m_candidates;  // BrightestTipAbove's scratch

  // the stage images, reused every frame
  cv::Mat m_grey;                    // CV_8UC1
  cv::Mat m_subtracted;              // CV_8UC1 frame - background
  cv::Mat m_smoothed;                // CV_8UC1
  cv::Mat m_highpass;                // CV_8UC1
  cv::Mat m_normalized;              // CV_8UC1 after the gain: what is thresholded
  cv::Mat m_binary;                  // CV_8UC1 0/255
  cv::Mat m_wide;                    // CV_8UC1 scratch: the wide blur of a whole-frame high-pass
  cv::Mat m_still;                   // CV_8UC1 scratch: where nothing touches
  cv::Mat m_eroded;                  // CV_8UC1 scratch: the opening's first pass
  std::vector<cv::Rect> m_areas;     // the tiles round the spans worked out (m_areasOnly)
  bool m_areasOnly = false;          // the filtered image is 0 outside the spans
  SpanHighpass m_spans;              // the high-pass along the spans of rows that need it
  std::vector<uint8_t> m_tileMarks;  // per tile: some pixel there can pass the threshold
  std::vector<int> m_tileStack;      // tiles of a group still to visit
  cv::Mat m_kernel;
  std::vector<std::vector<cv::Point>> m_contours;
  std::vector<cv::Vec4i> m_hierarchy;
  std::vector<Vec2> m_refined;
  std::vector<int> m_keep;  // the border pixels RefineToEdge keeps

  // table image maps (built on first request)
  cv::Mat m_tableMapX, m_tableMapY;
};

/// The opening of radius 1 (SensingParams::morphology = 1, a 3x3 cross), in place: `image` becomes
/// what cv::morphologyEx(image, out, MORPH_OPEN, OpeningKernel(1)) gives, bit for bit, with
/// OpenCV's default border (pixels beyond the edge left out). With `areas`, the image must be 0
/// outside them, and only the areas grown by 2 px are worked (the rest stays 0, as the opening
/// leaves it). `scratch` holds the eroded image. CV_8UC1.
void OpenCross3(cv::Mat& image, cv::Mat& scratch, const std::vector<cv::Rect>* areas = nullptr);

/// The structuring element of the clean-up opening of `radius` px (SensingParams::morphology): an
/// ellipse 2 radius + 1 px across, empty for 0.
cv::Mat OpeningKernel(int radius);

}  // namespace pg
