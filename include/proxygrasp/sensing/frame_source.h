// Where camera frames come from: a camera (index or V4L2 device path), a video file, a folder of
// numbered images, the synthetic table camera, or a depth camera (sensing/depth_source.h). Every
// source delivers 8-bit grey frames, or depth sources 16-bit depth in mm, and says clearly when it
// cannot open or stops delivering; a lost camera is a status, never a crash.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/sensing/synthetic_camera.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pg {

/// The outcome of reading one frame.
enum class FrameStatus {
  kOk,     ///< a frame was delivered
  kEnd,    ///< a finite source (video, folder, script) has no more frames
  kLost,   ///< a live source stopped delivering (camera unplugged); Reopen() may bring it back
  kError,  ///< this frame could not be read (a broken image file); LastError() says why
};

/// Names of FrameStatus values, in enum order.
inline constexpr const char* kFrameStatusNames[] = {"ok", "end", "lost", "error"};

/// A stream of 8-bit grey (CV_8UC1) frames, or of depth (CV_16UC1, mm, 0 = no reading) for the
/// depth sources. Other modules may implement it (a level's script
/// rendered through the synthetic camera, say).
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// Reads the next frame into `frame` (CV_8UC1, or CV_16UC1 depth in mm, when kOk).
  virtual FrameStatus Read(cv::Mat& frame) = 0;
  /// What this source is, for messages: "camera 0", "video clip.mp4", ...
  virtual std::string Describe() const = 0;
  /// Why the last Read did not deliver, or "" after a good frame.
  virtual std::string LastError() const { return m_lastError; }
  /// Tries to open the source again after kLost. The default cannot reopen.
  virtual MaybeError Reopen() { return MakeError({Describe()}, "this source cannot be reopened"); }
  /// Frames per second the source runs at, or 0 when unknown.
  virtual double FrameRate() const { return 0.0; }

 protected:
  std::string m_lastError;
};

/// Opens a source from a spec: "camera:N", a "/dev/video*" path, "video:FILE" or a video file,
/// an image file (one frame), "folder:DIR" or a directory, "synthetic:fingers" or "synthetic:hands"
/// (built-in demo scenes), or a depth source: depth:DIR, fakenect:DIR, oni:FILE, openni[:URI],
/// kinect[:N] (OpenDepthSource). Errors name the spec and say what went wrong.
Result<std::unique_ptr<FrameSource>> OpenFrameSource(const std::string& spec);

/// A script for SyntheticSource: the shapes on the table at a frame; false ends the script.
using ShapeScript = std::function<bool(int64_t frame, std::vector<ContactShape>& shapes)>;

/// Renders a shape script through the synthetic table camera, one frame per Read.
class SyntheticSource : public FrameSource {
 public:
  /// `frameCount` < 0 runs until the script returns false.
  SyntheticSource(std::string name, const SyntheticCameraParams& camera, const TableParams& table,
                  ShapeScript script, int64_t frameCount, double frameRate = 60.0);
  /// Renders the script's next frame; kEnd when the script or the frame count ends.
  FrameStatus Read(cv::Mat& frame) override;
  std::string Describe() const override { return m_name; }
  double FrameRate() const override { return m_frameRate; }
  /// The shapes of the last frame read (truth for tests and overlays).
  const std::vector<ContactShape>& shapes() const { return m_shapes; }
  /// The camera that renders the frames (its model() is the true calibration).
  SyntheticCamera& camera() { return m_camera; }

 private:
  std::string m_name;
  SyntheticCamera m_camera;
  ShapeScript m_script;
  int64_t m_frameCount;
  double m_frameRate;
  int64_t m_next = 0;
  std::vector<ContactShape> m_shapes;
};

/// True when the path names an image file by its extension (png, jpg, jpeg, bmp, tif, tiff, pgm,
/// ppm; any case).
bool IsImageFile(const std::string& path);

/// Image files of a folder in numeric order: "frame_2.png" before "frame_10.png" (the last run of
/// digits in the name decides; ties fall back to the name). Only common image extensions count.
std::vector<std::string> NumberedImages(const std::string& dir);

}  // namespace pg
