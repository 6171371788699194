#include "proxygrasp/app/video.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <filesystem>
#include <optional>

namespace pg {

namespace {

// creates the folder a file goes into
void MakeParent(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
}

}  // namespace

Result<LevelResult> RunLevelToVideo(const Level& level, const RunOptions& options,
                                    const VideoOptions& video, const FrameObserver& observer) {
  // the frame the PNG shows, counted from 1 like Simulation::Frame after a step
  const double frameRate = level.params.physics.frameRate;
  const int64_t total =
      options.frames >= 0
          ? options.frames
          : static_cast<int64_t>(std::ceil(level.script.duration * frameRate - 1e-9));
  const int64_t pngFrame =
      std::max<int64_t>(1, static_cast<int64_t>(std::lround(static_cast<double>(total) *
                                                            std::clamp(video.pngAt, 0.0, 1.0))));

  std::string firstRun;
  std::optional<DisplayMap> map;
  TableView view;
  cv::VideoWriter writer;
  MaybeError failure;
  bool pngWritten = false;
  cv::Mat lastPicture;
  auto draw = [&](const RunResult& run, const Simulation& sim) {
    // only the first run is drawn: variants and other modes replay the same script
    if (firstRun.empty()) firstRun = run.name;
    if (run.name != firstRun || failure) return;
    if (!map) {
      Result<DisplayMap> m = LevelDisplayMap(sim.params(), video.size);
      if (!m.ok()) {
        failure = m.error();
        return;
      }
      map = m.value();
      if (!video.videoPath.empty()) {
        MakeParent(video.videoPath);
        writer.open(video.videoPath, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), frameRate,
                    video.size, true);
        if (!writer.isOpened()) {
          failure = MakeError({video.videoPath}, "cannot open the video for writing (mp4v)");
          return;
        }
      }
    }
    const cv::Mat picture = view.Draw(sim, *map, video.size, video.view);
    if (writer.isOpened()) writer.write(picture);
    lastPicture = picture;
    if (!video.pngPath.empty() && sim.Frame() == pngFrame) {
      MakeParent(video.pngPath);
      if (!cv::imwrite(video.pngPath, picture)) {
        failure = MakeError({video.pngPath}, "cannot write the PNG");
        return;
      }
      pngWritten = true;
    }
    if (observer) observer(run, sim);
  };

  Result<LevelResult> result = RunLevel(level, options, draw);
  writer.release();
  if (!result.ok()) return result;
  if (failure) return *failure;
  // a run shorter than the PNG's frame still leaves a picture: its last frame
  if (!video.pngPath.empty() && !pngWritten) {
    if (lastPicture.empty()) return MakeError({video.pngPath}, "the run drew no frame");
    MakeParent(video.pngPath);
    if (!cv::imwrite(video.pngPath, lastPicture))
      return MakeError({video.pngPath}, "cannot write the PNG");
  }
  return result;
}

}  // namespace pg
