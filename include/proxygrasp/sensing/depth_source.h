// Depth cameras as frame sources: 16-bit PNG folders (depth:DIR), libfreenect's recordings
// (fakenect:DIR), OpenNI2 devices and ONI recordings (openni[:URI], oni:FILE), and a live Kinect v1
// through libfreenect (kinect[:N]). Every depth source delivers CV_16UC1 frames of depth in
// millimetres along the camera's axis, 0 where the camera has no reading. The touch-from-depth
// chain that turns them into contacts is not built yet: the IR sensor refuses such frames by name
// (counted and skipped). docs/sensing.md, "Depth cameras".
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/sensing/frame_source.h"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pg {

/// Kinect v1's "no reading" raw disparity.
inline constexpr int kKinectNoReading = 2047;

/// OpenKinect's fit of Kinect v1's depth to its raw disparity: z = kKinectFitScale mm x
/// tan(raw / kKinectFitSpan + kKinectFitOffset).
inline constexpr double kKinectFitScale = 123.6;
inline constexpr double kKinectFitSpan = 2842.5;
inline constexpr double kKinectFitOffset = 1.1863;

/// Kinect v1 raw 11-bit disparity to depth, mm (OpenKinect's fit: z = 0.1236 m x tan(raw / 2842.5
/// + 1.1863)); 0 for kKinectNoReading and for raw values whose fit is not a depth in front of the
/// camera (the fit's tangent passes pi/2 at raw 1084, about 10 m).
double KinectRawToMm(int raw);

/// The raw disparity whose depth is nearest `mm` (the inverse of KinectRawToMm), or
/// kKinectNoReading when no raw value in 0..2046 gives a depth within a step of it.
int KinectMmToRaw(double mm);

/// Kinect v1's raw disparity for a depth in mm as a real number (the inverse of the fit), and the
/// depth one raw step spans there, mm (dz/draw: 2.89 mm at 1 m, growing with the distance squared).
double KinectDisparity(double mm);
double KinectStepMm(double mm);

/// KinectRawToMm rounded to whole mm for every 11-bit raw value, as the depth sources deliver it
/// (0 = no reading): a table, since the tangent per pixel is slow.
const std::array<uint16_t, 2048>& KinectRawToMmTable();

/// Converts a raw disparity image (CV_16UC1, 11-bit) to depth in mm (CV_16UC1, 0 = no reading).
void KinectRawToMmImage(const cv::Mat& raw, cv::Mat& mm);

/// Reads one fakenect depth frame (d-*.pgm: a binary PGM of 640x480 16-bit raw disparity stored
/// little-endian, whatever its header's maximum says) into CV_16UC1 raw disparity. An Error names
/// the file and what is wrong with it (not a PGM, truncated, not 16-bit).
Result<cv::Mat> ReadFakenectDepth(const std::string& path);

/// Writes depth frames (CV_16UC1, mm, 0 = no reading) as a recording the depth sources read back:
/// `depth:` (a folder of 16-bit PNGs, depth_000000.png, ...) or `fakenect:` (INDEX.txt and
/// d-TIME-STAMP.pgm frames of raw disparity, as fakenect-record writes them).
class DepthRecordingWriter {
 public:
  enum class Format { kDepthPng, kFakenect };
  /// Creates the folder (it may exist; existing frames are not removed). Errors name it.
  static Result<DepthRecordingWriter> Create(const std::string& dir, Format format);
  /// Writes one frame taken at `time` (s from the start). Errors name the file.
  MaybeError Write(const cv::Mat& depthMm, double time);
  int64_t frames() const { return m_frames; }

 private:
  std::string m_dir;
  Format m_format = Format::kDepthPng;
  int64_t m_frames = 0;
};

/// True when `spec` names a depth source: depth:DIR, fakenect:DIR, oni:FILE, openni[:URI],
/// kinect[:N].
bool IsDepthSourceSpec(const std::string& spec);

/// True when `spec` names a live depth device (kinect[:N], openni[:URI]), which may be lost and
/// come back, rather than a recording.
bool IsLiveDepthSourceSpec(const std::string& spec);

/// Opens the depth source a spec names (IsDepthSourceSpec). A missing folder, file or device, a
/// folder whose first image is not 16-bit, an INDEX.txt naming a file that is not there, an ONI
/// file without a depth stream, or a build without the library a device needs, is an Error naming
/// what and where.
Result<std::unique_ptr<FrameSource>> OpenDepthSource(const std::string& spec);

/// The few things a live Kinect source asks of its device: libfreenect's (OpenDepthSource's
/// kinect[:N]), or a stand-in that tests unplug and plug back in.
class KinectDevice {
 public:
  virtual ~KinectDevice() = default;
  /// Opens Kinect number `index` and starts its depth stream (mm); "" when it did, else why not.
  virtual std::string Open(int index) = 0;
  /// The next depth frame (CV_16UC1, mm), waiting up to `seconds`; false when none came.
  virtual bool NextFrame(double seconds, cv::Mat& depthMm) = 0;
  /// Stops the stream and closes the device (nothing when it is not open).
  virtual void Close() = 0;
};

/// A live Kinect source on a device layer: Read is kLost when no frame comes within a second,
/// Reopen opens the device anew. An Error (naming `spec`) when the device does not open.
Result<std::unique_ptr<FrameSource>> OpenKinect(std::unique_ptr<KinectDevice> device, int index,
                                                const std::string& spec);

/// Whether this build reads OpenNI2 devices and ONI files, and live Kinects through libfreenect.
bool HaveOpenNi2();
bool HaveFreenect();

}  // namespace pg
