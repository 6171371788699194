// A run's contacts sent on as TUIO (`--tuio-out`): each frame's tracked contacts become TUIO 2.0
// bundles (tuio/encoder.h), sent over UDP to another application or written to a touchlib XML
// recording. Each bundle's time tag is the frame's simulation time, so a recording places its
// frames in time and a receiver sees the run's own clock.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/tuio/encoder.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pg {

class TuioSender;
class TouchlibXmlWriter;

/// The contacts of a frame that are still down (not lifted), as TUIO sends them: session id =
/// contact id, the contour and centroid in table cm, and a depth camera's contact's mean height
/// (the mean of Blob::heights, cm; none when it has no heights).
std::vector<TuioOutContact> ToTuioOutContacts(const ContactSet& contacts);

/// Sends the contacts of every frame a simulation steps as TUIO, to "HOST:PORT" over UDP or to a
/// touchlib XML recording ("file:PATH"). A bundle that cannot be sent is counted, never fatal:
/// the run goes on.
class TuioOutput {
 public:
  /// An output to `spec`: "HOST:PORT" (a name or an address, the port 1 to 65535) or "file:PATH"
  /// (the file is created or emptied; its folder must exist). `params` say how contacts are
  /// encoded; the table and the sensor size are the simulation's (see Send). An Error when the
  /// spec does not parse, the host does not resolve or the file cannot be created.
  static Result<std::unique_ptr<TuioOutput>> Open(const std::string& spec,
                                                  const TuioEncoderParams& params = {});
  ~TuioOutput();
  TuioOutput(const TuioOutput&) = delete;
  TuioOutput& operator=(const TuioOutput&) = delete;

  /// Sends the frame the simulation has just stepped: its contacts that have not lifted (session
  /// id = contact id, their contours and centroids), frame id = the frame's number, time tag =
  /// OscTimeTag::FromSeconds(the frame's time, s). The encoder maps [table] onto [0, 1]^2 and
  /// gives [camera] width and height as the sensor size. When the simulation was restarted (its
  /// frame number went back), the contacts of the old run are first lifted in a frame of their
  /// own, and frame ids and times continue from the old run's, so that receivers take the new
  /// run's frames as new rather than late. An Error names the first bundle of the frame that
  /// could not be sent or written; the rest are still sent, and the failures counted.
  MaybeError Send(const Simulation& sim);

  /// Ends a recording's document and closes it (UDP: nothing). Safe to call twice; the destructor
  /// calls it. An Error when the recording could not be completed.
  MaybeError Close();

  /// The spec it was opened with.
  const std::string& spec() const { return m_spec; }
  /// True for a touchlib XML recording, false for UDP.
  bool IsFile() const { return m_writer != nullptr; }
  /// Frames sent since Open.
  int64_t frames() const { return m_frames; }
  /// Bundles that could not be sent or written since Open.
  uint64_t sendErrors() const { return m_sendErrors; }
  const TuioEncodeStats& encodeStats() const { return m_encoder.stats(); }
  /// One line for a status bar or a log: "tuio out 127.0.0.1:3333: 120 frames, 0 send errors".
  std::string Status() const;

 private:
  explicit TuioOutput(const TuioEncoderParams& params);
  // encodes one frame and sends or writes its bundles
  MaybeError SendFrame(int64_t frame, double time, std::span<const TuioOutContact> contacts);

  std::string m_spec;
  TuioEncoder m_encoder;
  std::unique_ptr<TuioSender> m_sender;         // UDP
  std::unique_ptr<TouchlibXmlWriter> m_writer;  // or a recording
  int64_t m_frames = 0;
  uint64_t m_sendErrors = 0;

  // the last frame sent, as the simulation numbered it and as it went out
  bool m_anySent = false;
  int64_t m_lastSimFrame = 0;
  int64_t m_lastFrameId = 0;
  double m_lastTime = 0.0;  // s
  bool m_lastHadContacts = false;
  // added to the simulation's frame number and time after a restart
  int64_t m_frameOffset = 0;
  double m_timeOffset = 0.0;  // s
};

}  // namespace pg
