#include "proxygrasp/sensing/recorder.h"

namespace pg {

MaybeError FrameRecorder::Open(const std::string& path, cv::Size size, double fps) {
  Close();
  if (size.width <= 0 || size.height <= 0 || !(fps > 0.0)) {
    return MakeError({path}, "cannot record frames of size " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + " at " + std::to_string(fps) +
                                 " fps");
  }
  // FFV1 is lossless, so replaying gives the same contours and the same trajectories
  const int fourcc = cv::VideoWriter::fourcc('F', 'F', 'V', '1');
  if (!m_writer.open(path, cv::CAP_FFMPEG, fourcc, fps, size, false)) {
    return MakeError({path}, "cannot open the recording for writing (FFV1 through FFmpeg)");
  }
  m_path = path;
  m_size = size;
  m_frames = 0;
  return std::nullopt;
}

MaybeError FrameRecorder::Write(const cv::Mat& frame) {
  if (!m_writer.isOpened()) return MakeError({m_path}, "the recording is not open");
  if (frame.type() != CV_8UC1 || frame.size() != m_size) {
    return MakeError({m_path}, "frame " + std::to_string(m_frames) + " is " +
                                   std::to_string(frame.cols) + "x" + std::to_string(frame.rows) +
                                   " type " + std::to_string(frame.type()) + ", expected " +
                                   std::to_string(m_size.width) + "x" +
                                   std::to_string(m_size.height) + " 8-bit grey");
  }
  m_writer.write(frame);
  ++m_frames;
  return std::nullopt;
}

void FrameRecorder::Close() {
  if (m_writer.isOpened()) m_writer.release();
}

Result<int64_t> CountRecordingFrames(const std::string& path) {
  cv::VideoCapture video;
  try {
    video.open(path, cv::CAP_FFMPEG);
  } catch (const cv::Exception&) {
    video.release();
  }
  if (!video.isOpened()) return MakeError({path}, "cannot be read as a video");
  int64_t frames = 0;
  while (video.grab()) ++frames;
  return frames;
}

}  // namespace pg
