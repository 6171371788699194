// TUIO as the pipeline's input: contacts another tracker found and tracked (run/frame_input.h
// steps the simulation with them through Simulation::StepContacts). TuioTracker is the tracking
// stage for them: session ids become contact ids, new and lifted come from the stream, outlines
// are resampled as sensing resamples its own. TuioStream is where the frames come from: a UDP
// port, live, or a recorded stream replayed on the simulation's clock.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/tracking/types.h"
#include "proxygrasp/tuio/osc.h"
#include "proxygrasp/tuio/transport.h"
#include "proxygrasp/tuio/types.h"

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// The blob of a received outline, made as sensing makes its blobs: counter-clockwise, area
/// centroid, area and bounds of the outline, contour resampled every `spacing` cm.
Blob BlobFromOutline(std::span<const Vec2> outline, double spacing);

/// Tracking for contacts that arrive tracked. A session id is the contact id when it is a valid
/// id (1 to 2^31 - 1) above every id handed out so far in the run, as TUIO senders count their
/// sessions upwards; any other session gets the next id above them, so ids are never reused.
class TuioTracker {
 public:
  /// The contacts of one simulation frame, current ones first, then those lifted this frame with
  /// their last blob (the tracking stage's order). `frame` is what arrived since the last step;
  /// nullptr when nothing did, and the live contacts continue as they were. A live contact that
  /// a frame neither lists nor lifts has lifted.
  ContactSet Step(const TuioFrame* frame, double spacing);
  /// Forgets the live contacts (a new run); ids still grow.
  void Reset() { m_live.clear(); }

  /// Live contacts now.
  int LiveCount() const { return static_cast<int>(m_live.size()); }
  /// The contact id a live session has, or kNoId.
  ContactId IdOf(TuioSessionId session) const;

 private:
  ContactId NewId(TuioSessionId session);

  struct Live {
    ContactId id = kNoId;
    Blob blob;
  };
  std::map<TuioSessionId, Live> m_live;
  ContactId m_maxId = 0;  // the largest id handed out
};

/// Where TUIO frames come from: a UDP port (live) or a recorded stream (replayed).
class TuioStream {
 public:
  /// Listens on `address`:`port` ("" is every interface). An Error when it cannot.
  static Result<std::unique_ptr<TuioStream>> Listen(const std::string& address, int port);
  /// A recorded stream, as ReadTouchlibXml gives it. It is decoded at the first step, when the
  /// table it maps onto is known; `name` is the file, for messages.
  static std::unique_ptr<TuioStream> Replay(std::vector<OscBundle> bundles, std::string name);

  /// What arrived for the simulation frame that starts at `time` s and lasts `duration` s,
  /// decoded onto params' table, all frames merged into one; nullopt when nothing did. Live: what
  /// the socket holds now, or after waiting up to wait() s for a frame. Replay: the frames whose
  /// arrival lies before the middle of the simulation frame.
  std::optional<TuioFrame> Next(double time, double duration, const TuioParams& params);

  /// Live: how long Next waits for a frame before it lets the simulation step without one, s
  /// (0: never waits; a caller that paces itself by its input sets about one frame).
  void SetWait(double seconds) { m_wait = seconds; }
  double wait() const { return m_wait; }

  bool live() const { return m_receiver != nullptr; }
  /// The port listened on (live), else 0.
  int port() const { return m_receiver ? m_receiver->port() : 0; }
  /// "tuio:ADDRESS:PORT" or "tuio file NAME".
  std::string Describe() const;
  /// What came in and what was dropped, for the status line (TuioStats::Summary).
  std::string Status() const;
  const TuioStats& stats() const;

 private:
  TuioStream() = default;

  std::unique_ptr<TuioReceiver> m_receiver;
  std::string m_address;
  double m_wait = 0.0;
  // replay
  std::string m_name;
  std::vector<OscBundle> m_bundles;
  std::vector<TuioFrame> m_frames;
  TuioStats m_replayStats;
  bool m_decoded = false;
  size_t m_next = 0;  // the first frame not yet given
};

}  // namespace pg
