// `proxygrasp bench` (issue 17): the standard scenes through the whole pipeline on frames rendered
// beforehand, so that the pipeline is timed alone and the synthetic camera's rendering apart; each
// stage's CPU time per frame (median and p99); and in the same run the baselines: bare OpenCV
// sensing of the same frames, the Box2D stepping inside the physics stage, and the paper's
// exhaustive contour matching. See docs/performance.md.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/core/timer.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pg {

/// The sensing chain written as bare OpenCV calls ending at findContours: background subtraction,
/// smoothing, capped high-pass, gain, threshold, opening and contours, with the same sizes in
/// pixels as the sensing stage (issue 14). No sub-pixel edges, table mapping, resampling or
/// background learning: the baseline the sensing stage is compared with.
class BareSensingChain {
 public:
  /// Sizes from `params` for frames as wide as `background` over the table's width.
  BareSensingChain(const SensingParams& params, const TableParams& table,
                   const cv::Mat& background);

  /// Runs the chain on one CV_8UC1 frame of the background's size; returns the contours found.
  size_t Step(const cv::Mat& frame);

 private:
  SensingParams m_params;
  cv::Mat m_background;
  double m_sigma = 0.0;     // Gaussian deviation, pixels (0 = no smoothing)
  int m_highpassWidth = 0;  // box width of the high-pass, pixels, odd (0 = no high-pass)
  cv::Mat m_kernel;         // opening's structuring element (empty = no opening)
  cv::Mat m_diff, m_smooth, m_wide, m_high, m_gained, m_binary;
  std::vector<cv::Vec4i> m_hierarchy;
  std::vector<std::vector<cv::Point>> m_contours;
};

/// The depth chain as bare OpenCV calls (issue 43): the frame less the surface, the touch band
/// thresholded between a lower edge per pixel (DepthSensor's noise edge) and touch_high, the
/// opening and findContours; no learning, hover, heights or table mapping. The baseline
/// DepthSensor is compared with.
class BareDepthChain {
 public:
  /// surfaceMm: CV_32F, mm; the band's lower edge per pixel (CV_32F, mm above the surface) and
  /// its upper edge, mm; the opening's radius in pixels.
  BareDepthChain(const cv::Mat& surfaceMm, const cv::Mat& lowMm, double highMm, int morphology);
  /// Runs the chain on one CV_16UC1 frame (mm) of the surface's size; returns the contours found.
  size_t Step(const cv::Mat& depthMm);

 private:
  cv::Mat m_surface;
  cv::Mat m_low, m_high;  // CV_32F, mm
  cv::Mat m_kernel;
  cv::Mat m_float, m_height, m_binary;
  std::vector<std::vector<cv::Point>> m_contours;
};

/// The depth scene, run after the standard ones unless --scenes leaves it out: 640x480 depth
/// frames of a table 1 m away (1.5 mm noise), 10 fingertips touching and 2 palms hovering 4 cm
/// above it, all sweeping; only its sensing is timed, against BareDepthChain.
inline constexpr const char* kDepthBenchScene = "depth_touch";

/// The standard scenes, in the order a bench runs them: "fingertips10_s3", "flat_hands2_s3_k8",
/// "five_hands4_s3", "flat_hands8".
std::vector<std::string> BenchSceneNames();

/// What a bench run does.
struct BenchOptions {
  int frames = 120;                 ///< timed frames per scene and repeat (60 Hz: 2 s of motion)
  int repeat = 1;                   ///< runs of each scene; the figures pool every run's frames
  std::vector<std::string> scenes;  ///< names from BenchSceneNames(); empty runs them all
  std::vector<std::string> sets;    ///< parameter overrides "section.key=value" for every scene
  /// What the stage times measure: the stepping thread's CPU time (default: comparable on a loaded
  /// machine), or wall time (physics.threads > 1, whose worker threads the CPU clock misses).
  TimerClock clock = TimerClock::kThreadCpu;
};

/// The nearest-rank percentile of the values, p in (0, 1]; 0 for none.
double Percentile(std::vector<double> values, double p);

/// The median and 99th percentile (nearest rank) of a per-frame time, ms.
struct BenchFigure {
  std::string name;
  double p50 = 0.0;  ///< ms
  double p99 = 0.0;  ///< ms
};

/// One scene's pipeline figures: CPU ms per frame of the thread stepping it.
struct BenchScene {
  std::string name;
  std::string description;
  int frames = 0;                   ///< timed frames, every repeat together
  double contacts = 0.0;            ///< mean current contacts per frame
  double particles = 0.0;           ///< mean live particle stacks after a frame
  double bodies = 0.0;              ///< mean Box2D bodies after a frame
  std::vector<BenchFigure> stages;  ///< "sense", "track", "proxies", "physics", "total"
  BenchFigure total;                ///< the "total" stage again, sensing to physics
  /// FNV-1a of every object's pose and velocity bits after the first repeat's last frame: equal
  /// hashes mean bit-identical runs (physics.threads must not change them).
  uint64_t stateHash = 0;
};

/// A baseline beside the stage it is compared with, on the same frames: medians per frame, ms.
struct BenchBaseline {
  std::string name;   ///< "sensing_vs_bare_opencv", "physics_vs_box2d", "matching_vs_exhaustive",
                      ///< "depth_vs_bare_opencv"
  std::string scene;  ///< the scene whose frames both ran on
  double oursMs = 0.0;
  double bareMs = 0.0;
  double ratio = 0.0;  ///< oursMs / bareMs
};

/// Where the figures were taken.
struct BenchMachine {
  std::string cpu;         ///< `model name` of /proc/cpuinfo ("unknown" when absent)
  int cores = 0;           ///< hardware threads
  std::string compiler;    ///< the compiler's name and __VERSION__
  std::string buildType;   ///< CMAKE_BUILD_TYPE of this build
  std::string opencv;      ///< OpenCV version
  double loadStart = 0.0;  ///< 1-minute load average when the run started (-1 when unknown)
  double loadEnd = 0.0;    ///< and when it ended
};

/// Everything one bench run measured.
struct BenchReport {
  BenchMachine machine;
  int frames = 0;                             ///< BenchOptions::frames
  int repeat = 0;                             ///< BenchOptions::repeat
  TimerClock clock = TimerClock::kThreadCpu;  ///< BenchOptions::clock
  std::vector<std::string> sets;              ///< BenchOptions::sets
  std::vector<BenchScene> scenes;
  std::vector<BenchFigure> render;  ///< per scene (name = scene), one synthetic camera frame
  std::vector<BenchBaseline> baselines;
};

/// The machine this process runs on; loadStart and loadEnd both the load average now.
BenchMachine DescribeBenchMachine();

/// Runs the bench. Bad options (frames or repeat below 1, an unknown scene) are an Error naming
/// them; the option names are those of `proxygrasp bench`.
Result<BenchReport> RunBench(const BenchOptions& options);

/// The report as JSON: {"machine", "frames", "repeat", "scenes": [{"name", "p50_ms", "p99_ms",
/// "stages": {"sense": {"p50_ms", "p99_ms"}, ...}, ...}], "render": [...], "baselines": [...]}.
std::string BenchJson(const BenchReport& report);

/// The report as readable tables, baselines with their ratios.
std::string FormatBench(const BenchReport& report);

}  // namespace pg
