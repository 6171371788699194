// TUIO in: OSC messages from another tracker become frames of contacts with contours in table cm.
// Pure: no sockets, no clock of its own (the caller passes the time of arrival), so a recording,
// a test or the receiver (transport.h) can feed it alike.
#pragma once

#include "proxygrasp/tuio/osc.h"
#include "proxygrasp/tuio/types.h"

#include <map>
#include <optional>
#include <span>
#include <vector>

namespace pg {

/// Assembles TUIO 2.0 (frm, ptr, p3d, bnd, ocg, alv) and TUIO 1.1 (2Dcur, 2Dblb) messages into
/// frames. A TUIO 2.0 frame runs from /tuio2/frm to /tuio2/alv (a frame split over several bundles
/// repeats its frm); a TUIO 1.1 frame ends at its profile's fseq. A session that is alive but sent
/// no shape this frame keeps its last shape; a session missing from alive lifts. Malformed
/// messages are counted in stats() by reason and dropped; nothing here throws or asserts on input.
class TuioDecoder {
 public:
  explicit TuioDecoder(const TuioParams& params = {});

  /// Replaces the parameters; they apply from the next message on.
  void SetParams(const TuioParams& params) { m_params = params; }
  const TuioParams& params() const { return m_params; }

  /// Decodes one bundle (or one message sent alone) that arrived at `now`, receiver clock in s.
  void Decode(const OscBundle& bundle, double now) { Decode(bundle.messages, now); }
  void Decode(std::span<const OscMessage> messages, double now);
  /// Counts a datagram that was not OSC at all (it does not count as a sign of life).
  void CountBadPacket() { ++m_stats[TuioDrop::kBadPacket]; }

  /// When nothing arrived for params().timeout before `now` (s), lifts every live contact in a
  /// frame of its own (frame id -1) and forgets partial frames. True when it lifted any.
  bool Expire(double now);

  /// The frames completed since the last call, oldest first. When more than maxQueuedFrames
  /// waited, the oldest were merged (MergeTuioFrames), so the queue never grows without bound.
  std::vector<TuioFrame> TakeFrames();
  /// True when a completed frame waits to be taken.
  bool HasFrames() const { return !m_frames.empty(); }

  /// Forgets every contact and partial frame; keeps the parameters and the counts.
  void Reset();

  const TuioStats& stats() const { return m_stats; }
  /// Sessions live now.
  int LiveCount() const { return static_cast<int>(m_live.size()); }

 private:
  // the TUIO profiles, each with its own frame sequence and alive list
  enum Profile { kTuio2, kCursor11, kBlob11, kProfileCount };

  struct Shape {
    TuioShape kind = TuioShape::kContour;
    std::vector<Vec2> contour;
  };
  struct Track {
    Profile profile = kTuio2;
    TuioShape kind = TuioShape::kContour;
    std::vector<Vec2> contour;
    Vec2 centroid = Vec2::Zero();
    std::optional<double> height;  // cm, from the last frame that gave a shape
    bool isNew = true;
  };
  struct Pending {
    bool open = false;  // a frame has started and not ended
    bool late = false;  // its frame id is older than the last one taken: drop it at its end
    int64_t frame = -1;
    bool haveAlive = false;
    std::vector<TuioSessionId> alive;
    std::map<TuioSessionId, Shape> shapes;
    std::map<TuioSessionId, double> heights;  // cm, from p3d
  };

  void DecodeTuio2(const OscMessage& m);
  void DecodeTuio11(Profile profile, const OscMessage& m);
  // reads a TUIO 1.1 set message into a shape; false (counted) when it is malformed
  bool ReadSet11(Profile profile, const OscMessage& m);
  /// True when the message starts with an int (a frame or session id); otherwise counts the drop.
  bool StartsWithInt(const std::vector<OscArg>& a);
  bool ReadAlive(const OscMessage& m, size_t first, std::vector<TuioSessionId>& ids);
  void AddShape(Pending& p, TuioSessionId id, Shape shape);
  // checks a normalised coordinate; false (counted) when it is not finite or out of range
  bool CheckCoord(double v);
  Vec2 ToTable(double u, double v) const;
  bool AcceptFrameId(Profile profile, int64_t frame) const;
  void Complete(Profile profile);
  void Push(TuioFrame frame);
  std::vector<Vec2> Ellipse(Vec2 centre, double rx, double ry, double angle) const;

  TuioParams m_params;
  TuioStats m_stats;
  std::map<TuioSessionId, Track> m_live;  // ordered by id, so frames list contacts by id
  Pending m_pending[kProfileCount];
  int64_t m_lastFrame[kProfileCount];
  bool m_haveLastFrame[kProfileCount] = {};
  double m_lastPacket = 0.0;  // s, when the last packet arrived
  double m_now = 0.0;         // s, when the packet being decoded arrived
  bool m_anyPacket = false;
  std::vector<TuioFrame> m_frames;
};

/// Several frames as one, for a caller that polls less often than frames arrive: the contacts
/// of the last frame (new when new in any of them), and every session lifted in any of them that
/// is not live at the end. A lifted id may be one the caller never saw as new. Empty in, a frame
/// with nothing in it out.
TuioFrame MergeTuioFrames(std::span<const TuioFrame> frames);

/// Decodes a recorded stream as if bundle k arrived at k * interval s (a recording's time tags
/// are often "immediately"), and returns every frame it made, in order.
std::vector<TuioFrame> ReplayTuio(std::span<const OscBundle> bundles, const TuioParams& params,
                                  double interval = 1.0 / 60.0);

/// Where a recorded bundle arrives, s from the first: its time tag less the first's when every
/// tag is a time (not "immediately") and they never run backwards; else k * interval.
std::vector<double> ReplayArrivals(std::span<const OscBundle> bundles, double interval);

/// Decodes a recorded stream with ReplayArrivals' times, then lets the decoder's timeout expire
/// after the last bundle so that contacts still live at the end lift. The decoder's counts go to
/// `stats` when given.
std::vector<TuioFrame> ReplayRecording(std::span<const OscBundle> bundles, const TuioParams& params,
                                       double interval, TuioStats* stats = nullptr);

}  // namespace pg
