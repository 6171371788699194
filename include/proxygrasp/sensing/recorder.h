// Records raw camera frames losslessly (FFV1 in Matroska), so a recording replays bit for bit
// through `--input video:FILE` or as a level's input.
#pragma once

#include "proxygrasp/core/error.h"

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include <cstdint>
#include <string>

namespace pg {

/// The frames a recording holds, counted by decoding it (FFmpeg only, as recordings are FFV1:
/// probing every backend on a broken file would also try camera libraries). A file that is not
/// a readable video is an Error naming it.
Result<int64_t> CountRecordingFrames(const std::string& path);

/// Writes 8-bit grey frames of one size to a lossless video file.
class FrameRecorder {
 public:
  /// Opens path (".mkv" recommended) for frames of `size` at `fps` frames per second. Errors name
  /// the file.
  MaybeError Open(const std::string& path, cv::Size size, double fps);
  /// Appends one CV_8UC1 frame of the opened size; a wrong frame is an Error naming its index.
  MaybeError Write(const cv::Mat& frame);
  /// Finishes the file. Safe to call twice.
  void Close();
  bool IsOpen() const { return m_writer.isOpened(); }
  /// The file being written.
  const std::string& path() const { return m_path; }
  /// Frames written since Open.
  int64_t frames() const { return m_frames; }

 private:
  cv::VideoWriter m_writer;
  std::string m_path;
  cv::Size m_size;
  int64_t m_frames = 0;
};

}  // namespace pg
