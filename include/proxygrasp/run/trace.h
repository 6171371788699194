// The one trace writer: a run's per-frame rows streamed to disk as the run goes (objects.csv,
// frames.csv, contacts.csv) and, when asked, its camera frames recorded losslessly beside them (a
// video, or for a depth camera a depth:DIR or fakenect:DIR recording). The runner, the app's
// recording and `run --record` all write through it, so every trace has the same columns.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/sensing/recorder.h"

#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

namespace pg {

class DepthRecordingWriter;
class Simulation;
struct FrameStats;

/// The objects.csv header line (without newline).
inline constexpr const char* kObjectsCsvHeader =
    "frame,t,object,x,y,angle_deg,vx,vy,omega_deg_s,held";
/// The frames.csv header line (without newline). height: the mean of the down contacts' mean
/// heights, cm (empty when no contact has heights: the IR camera); hover: the depth camera's hover
/// regions; hover_height: the mean of their mean heights, cm (empty when there are none).
inline constexpr const char* kFramesCsvHeader =
    "frame,t,contacts,merges,splits,particles,created,deleted,bodies,height,hover,hover_height,"
    "sense_ms,track_ms,proxy_ms,physics_ms,total_ms";
/// The contacts.csv header line (without newline): one row per contact per frame, lifted ones
/// included; height is the contact's mean height, cm (empty when it has none: the IR camera).
inline constexpr const char* kContactsCsvHeader = "frame,t,id,state,x,y,area,height";

/// Where a recording's trace goes: the file's path without its extension plus "_trace"
/// ("runs/push.mkv" -> "runs/push_trace"); for a depth recording its folder's path plus "_trace"
/// ("depth:runs/push" -> "runs/push_trace").
std::string RecordingTraceDir(const std::string& recordingPath);

/// One objects.csv row per object after a frame: frame, t (s, the end of the frame), name,
/// x, y (cm), angle (deg), vx, vy (cm/s), angular velocity (deg/s), held (0 or 1).
std::string ObjectRows(const Simulation& sim);

/// The frames.csv row of the frame the simulation has just stepped: its stats at time t (s, the
/// end of the frame), its contacts' and hover regions' heights.
std::string FrameRow(const Simulation& sim);

/// The contacts.csv rows of the frame the simulation has just stepped: frame, t (s, the end of
/// the frame), id, state (new, continuing, lifted), centroid x, y (cm), area (cm^2), mean height
/// (cm, empty without heights).
std::string ContactRows(const Simulation& sim);

/// Streams one run's traces. Rows go to disk as they are written; nothing of the run is kept in
/// memory, whatever its length.
class TraceWriter {
 public:
  TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;
  ~TraceWriter();

  /// Creates dir (and its parents) and starts objects.csv, frames.csv and contacts.csv there with
  /// their headers. When videoPath is not empty, the camera frames (size, at frameRate) are
  /// recorded there too (FFV1); its folder must exist, and it is opened first, so that a video that
  /// cannot be written leaves no trace folder behind. A videoPath "depth:DIR" or "fakenect:DIR"
  /// records a depth camera's frames (CV_16UC1, mm) as that recording instead
  /// (DepthRecordingWriter; the folder is made). Errors name the folder or file; on error nothing
  /// stays open.
  MaybeError Open(const std::string& dir, const std::string& videoPath = "",
                  cv::Size size = cv::Size(), double frameRate = 0.0);

  /// Appends the rows of the frame the simulation has just stepped, and its camera image when
  /// recording. A failed write is an Error naming the file.
  MaybeError Write(const Simulation& sim);

  /// Records one camera image taken at `time` (s) when recording (nothing otherwise): 8-bit grey
  /// to a video, 16-bit depth to a depth recording; the other kind is an Error saying which
  /// recording takes it.
  MaybeError WriteCamera(const cv::Mat& image, double time);

  /// Flushes and closes every file. Safe to call twice. An Error when the files could not be
  /// completed.
  MaybeError Close();

  bool IsOpen() const { return m_objects.is_open(); }
  /// The folder of the CSV files.
  const std::string& dir() const { return m_dir; }
  /// Frames written since Open.
  int64_t frames() const { return m_frames; }

 private:
  std::string m_dir;
  std::ofstream m_objects;
  std::ofstream m_frameRows;
  std::ofstream m_contactRows;
  FrameRecorder m_recorder;
  std::unique_ptr<DepthRecordingWriter> m_depth;  // a depth recording, when recording one
  std::string m_depthSpec;                        // its depth:DIR or fakenect:DIR
  int64_t m_frames = 0;
};

}  // namespace pg
