// Headless pictures of a level: runs it through the runner and draws its frames with the table
// view into a video and a PNG. `proxygrasp run --video` and `play` without a display use it.
#pragma once

#include "proxygrasp/app/table_view.h"
#include "proxygrasp/core/error.h"
#include "proxygrasp/run/runner.h"

#include <opencv2/core.hpp>

#include <string>

namespace pg {

/// Where and how to draw a headless run.
struct VideoOptions {
  std::string videoPath;     ///< video of the first run's frames ("" = none); .mp4 uses mp4v
  std::string pngPath;       ///< PNG of one frame of the first run ("" = none)
  double pngAt = 0.6;        ///< which frame the PNG shows, as a fraction of the run, 0..1
  cv::Size size{1024, 768};  ///< picture size, px
  ViewOptions view;          ///< what is drawn
};

/// Runs every run of the level as RunLevel does and draws the first run's frames into the video
/// and the PNG; `observer`, when given, sees each of the first run's frames after it is drawn.
/// Errors name the level or the output file that could not be written.
Result<LevelResult> RunLevelToVideo(const Level& level, const RunOptions& options,
                                    const VideoOptions& video, const FrameObserver& observer = {});

}  // namespace pg
