// The one frame input of the pipeline: where each frame of a run comes from. The headless runner,
// `sense` and the app all step their simulation through it:
// - the level's script, drawn by the synthetic camera;
// - contact shapes given each frame (the app's mouse and touch hands), drawn the same way;
// - a frame source: a camera, a video or recording, a folder of images, a synthetic scene;
// - contours given each frame, which skip the camera and sensing;
// - TUIO from another tracker, live on a UDP port or recorded: contacts that skip the camera,
//   sensing and tracking (run/tuio_input.h).
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/run/tuio_input.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/types.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pg {

class Simulation;
struct Level;

/// Where a run's frames come from, and how one frame steps the simulation.
class FrameInput {
 public:
  /// The kinds of input.
  enum class Kind {
    kScript,    ///< the level's script through the synthetic camera
    kShapes,    ///< shapes set before each step, through the synthetic camera
    kSource,    ///< images from a FrameSource
    kContours,  ///< contours set before each step; no camera, no sensing
    kTuio,      ///< tracked contacts from a TUIO stream; no camera, sensing or tracking
  };

  /// The level's script.
  static FrameInput Script();
  /// What a level's [script] names as its input: its video recording, its recorded TUIO stream,
  /// else its contacts (Script). An Error names the recording that does not open.
  static Result<FrameInput> ForLevel(const Level& level);
  /// Shapes set with SetShapes before each Step.
  static FrameInput Shapes();
  /// Contour frames set with SetContours before each Step.
  static FrameInput Contours();
  /// Frames from the source a spec names (OpenFrameSource: camera:N, /dev/videoN, video:FILE, a
  /// video file, folder:DIR, synthetic:NAME), or TUIO received on a UDP port: tuio:PORT (every
  /// interface) or tuio:ADDRESS:PORT (one loopback or LAN address, or a name such as localhost). A
  /// camera that does not open is an Error unless keepMissing, which keeps the spec so that
  /// Reconnect can open it later (a camera plugged in after the start); LastError then says why it
  /// is missing.
  static Result<FrameInput> Open(const std::string& spec, bool keepMissing = false);
  /// Contacts from a TUIO stream (TuioStream::Listen or TuioStream::Replay).
  static FrameInput Tuio(std::unique_ptr<TuioStream> stream);
  /// Frames from an open source; spec is what Reconnect opens when the source cannot reopen.
  static FrameInput FromSource(std::unique_ptr<FrameSource> source, std::string spec);

  /// The shapes of the next frame (kShapes).
  void SetShapes(std::span<const ContactShape> shapes);
  /// The contours of the next frame (kContours), in table cm.
  void SetContours(ContourFrame contours);

  /// Steps sim by one frame from this input. kOk when the simulation stepped; kEnd when a finite
  /// source has no more frames; kLost when a live source stopped (or never opened), kError when a
  /// frame could not be read or does not fit the run's camera size: LastError says why and the
  /// simulation did not step. An Error is the pipeline rejecting the frame.
  Result<FrameStatus> Step(Simulation& sim);

  /// Reads a source's next frame ahead, so that its size is known before the run starts; the
  /// next Step delivers it. The status is Read's; PeekedSize is the frame's size after kOk.
  FrameStatus Peek();
  cv::Size PeekedSize() const { return m_frame.size(); }

  /// Opens a lost, ended or missing source again: the source's own Reopen, else its spec anew.
  MaybeError Reconnect();

  Kind kind() const { return m_kind; }
  /// True for kSource with an open source.
  bool HasSource() const { return m_source != nullptr; }
  /// True for the inputs that bring no camera images (kContours, kTuio).
  bool Imageless() const { return m_kind == Kind::kContours || m_kind == Kind::kTuio; }
  /// The TUIO stream of kTuio, else nullptr.
  TuioStream* tuio() const { return m_tuio.get(); }
  /// What the input is, for messages: "script", "shapes", "contours", the TUIO stream's or the
  /// source's description.
  std::string Describe() const;
  /// Why the last Step did not step the simulation, or "".
  const std::string& LastError() const { return m_lastError; }
  /// Frames skipped since this input was made: a source's frame that could not be read (a corrupt
  /// image or PGM), one of the wrong size, or one the pipeline rejected (kError or an Error from
  /// Step). A lost source is not counted: it delivers no frames.
  int64_t skippedFrames() const { return m_skippedFrames; }

 private:
  explicit FrameInput(Kind kind) : m_kind(kind) {}

  Kind m_kind;
  std::string m_spec;
  std::unique_ptr<FrameSource> m_source;
  std::unique_ptr<TuioStream> m_tuio;
  TuioTracker m_tuioTracker;
  std::vector<ContactShape> m_shapes;
  ContourFrame m_contours;
  cv::Mat m_frame;
  bool m_peeked = false;     // m_frame holds a frame read ahead by Peek
  int64_t m_framesRead = 0;  // frames read, good or not, since the source was opened
  int64_t m_skippedFrames = 0;
  std::string m_lastError;
};

}  // namespace pg
