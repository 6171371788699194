// Proposing sensing values for a real table from a capture: a clear table first, then a few seconds
// of touches (`proxygrasp tune`). The rule and its derivation are in docs/sensing.md ("Tuning a
// table").
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <string>
#include <utility>
#include <vector>

namespace pg {

/// How a capture is read.
struct TuneOptions {
  double clearSeconds = 1.0;  ///< the capture's first seconds show the clear table, s
  double weakQuantile = 0.1;  ///< share of touches at or below the weak touch's peak, 0..1
  int minTouches = 5;         ///< fewest touch components the proposal needs
};

/// What a capture showed and the values proposed from it.
struct TuneProposal {
  cv::Mat background;   ///< mean of the clear-table frames, CV_8UC1
  int clearFrames = 0;  ///< frames in the clear part
  int touchFrames = 0;  ///< frames after it
  /// N: the lowest high-pass level (8-bit grey) above which no clear-table frame shows a contact
  /// (after the opening and min_area). 0 when the clear table shows none even above 0.
  int noiseLevel = 0;
  std::vector<int> touchPeaks;  ///< every touch component's peak (highest 3x3 mean) above N
  double weakTouch = 0.0;       ///< W: the weakQuantile of touchPeaks, grey
  /// T = max(N, floor(W / 2)): the proposed values make "high-pass level above T" what is
  /// thresholded, so the clear table shows no contact and a weak touch's outline lies at half
  /// its peak.
  int level = 0;
  SensingParams params;  ///< the parameters given to Configure with the proposed values set
  /// The proposed values as [sensing] keys and TOML text, for Calibration::sensing.
  std::vector<std::pair<std::string, std::string>> values;
};

/// Sets the gain and the fixed threshold so that exactly the high-pass levels (8-bit grey) above
/// `level` (0..254) are thresholded; the threshold is kept where it can be.
void SetContactLevel(SensingParams& params, int level);

/// Reads a capture frame by frame and proposes sensing values for it. Frames of the clear part are
/// kept until it ends (about 18 MB a second at 640x480 and 60 Hz); touch frames are not kept.
class SensingTuner {
 public:
  /// The parameters (everything but the gain and the threshold is kept as given), the table and
  /// the calibration the capture is seen through (its background is not used: the clear part
  /// gives one). Errors name the bad parameter or calibration field.
  MaybeError Configure(const SensingParams& params, const TableParams& table,
                       const Calibration& calibration, const TuneOptions& options = {});
  /// One frame of the capture, 8-bit grey or colour, at `time` s (increasing). A frame of the
  /// wrong size or type is an Error naming it; nothing is lost and later frames still count.
  MaybeError AddFrame(const cv::Mat& frame, int64_t index, double time);
  /// The proposal, once the capture has had its clear part and touches. Errors say what the
  /// capture lacked (no frame after the clear part, no touch brighter than the clear table).
  Result<TuneProposal> Propose() const;

 private:
  MaybeError StartTouches();
  // true when the high-pass image shows a contact above `level` (opening and min_area applied)
  bool ShowsContact(const cv::Mat& highpass, int level);
  void CollectTouchPeaks(const cv::Mat& highpass);

  SensingParams m_given;
  TuneOptions m_options;
  bool m_configured = false;
  double m_startTime = 0.0;
  bool m_haveStart = false;
  std::vector<std::pair<cv::Mat, double>> m_clear;  // grey frames and times of the clear part
  bool m_touching = false;                          // the clear part is over
  Sensor m_sensor;  // gain 1 and a fixed threshold: the tuner reads its high-pass stage
  cv::Mat m_background;
  cv::Mat m_kernel;
  double m_minPixels = 1.0;  // min_area in camera pixels
  int m_clearFrames = 0;
  int m_touchFrames = 0;
  int m_noiseLevel = 0;
  std::vector<int> m_peaks;
  cv::Mat m_mean, m_binary, m_labels, m_stats, m_centroids;
};

}  // namespace pg
