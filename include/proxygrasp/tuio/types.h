// What the TUIO module takes and hands on: contacts received from (or sent to) another tracker as
// contours in table cm, the frames they come in, the decoder's parameters and its drop counts.
// See docs/tuio.md for the messages and the coordinate mapping.
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/table.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pg {

/// A TUIO session id: one touch from the moment it appears until it lifts.
using TuioSessionId = int64_t;

/// Which TUIO message a received contact's shape came from.
enum class TuioShape {
  kContour,  ///< TUIO 2.0 /tuio2/ocg: the outline itself
  kBounds,   ///< TUIO 2.0 /tuio2/bnd: an ellipse of the bounds' size
  kPointer,  ///< TUIO 2.0 /tuio2/ptr: a fingertip circle
  kCursor,   ///< TUIO 1.1 /tuio/2Dcur: a fingertip circle
  kBlob,     ///< TUIO 1.1 /tuio/2Dblb: an ellipse of the blob's size
};
inline constexpr const char* kTuioShapeNames[] = {"contour", "bounds", "pointer", "cursor", "blob"};

/// A contact as TUIO carries it, in table cm.
struct TuioContact {
  TuioSessionId id = 0;
  bool isNew = true;  ///< first frame of this session (else continuing)
  TuioShape shape = TuioShape::kContour;
  std::vector<Vec2> contour;     ///< closed, counter-clockwise, at least 3 distinct points, cm
  Vec2 centroid = Vec2::Zero();  ///< area centroid of the contour, cm
  /// height above the table, cm, when the sender gave one (a /tuio2/p3d z); none otherwise
  std::optional<double> height;
};

/// One frame of contacts: every live contact, and the sessions that ended since the last frame.
struct TuioFrame {
  int64_t frame = 0;  ///< the sender's frame id (TUIO 2.0 frm, TUIO 1.1 fseq); -1 when expired
  double time = 0.0;  ///< receiver clock when the frame completed, s
  std::vector<TuioContact> contacts;
  std::vector<TuioSessionId> lifted;
};

/// How TUIO maps onto the table and what the decoder accepts.
struct TuioParams {
  TableParams table;            ///< the rectangle normalised [0, 1]^2 maps onto
  bool flipY = true;            ///< TUIO's y runs down from the top edge; the table's runs up
  double cursorRadius = 0.8;    ///< radius of the circle a cursor or pointer becomes, cm
  int circlePoints = 16;        ///< points of a cursor's circle or a blob's ellipse
  double margin = 0.05;         ///< coordinates may lie this far outside [0, 1], normalised
  int maxContourPoints = 4096;  ///< a longer /tuio2/ocg is dropped, points
  int maxContacts = 256;        ///< live sessions beyond this many are dropped, contacts
  double timeout = 0.5;         ///< with no bundle for this long, every contact lifts, s
  int maxQueuedFrames = 64;     ///< frames not yet taken beyond this are merged, frames
};

/// Why a message (or a whole packet) was dropped.
enum class TuioDrop {
  kBadPacket,        ///< the datagram is not OSC (truncated, bad padding, bad bundle)
  kUnknownAddress,   ///< not a TUIO address
  kUnknownCommand,   ///< a TUIO 1.1 message whose first argument is not set, alive, fseq, source
  kWrongType,        ///< an argument of the wrong type
  kTooFewArgs,       ///< fewer arguments than the message needs (or an odd coordinate count)
  kNonFinite,        ///< a NaN or infinite number
  kOutOfRange,       ///< a coordinate or size beyond [0, 1] by more than the margin
  kTooManyPoints,    ///< a contour of more than maxContourPoints points
  kTooManyContacts,  ///< more than maxContacts live sessions
  kLateFrame,        ///< a frame id older than the last one taken (reordered UDP)
  kIncompleteFrame,  ///< a TUIO 2.0 frame that a new frm replaced before its alv
  kCount
};
inline constexpr const char* kTuioDropNames[] = {
    "bad packet",        "unknown address", "unknown command", "wrong type",
    "too few args",      "non-finite",      "out of range",    "too many points",
    "too many contacts", "late frame",      "incomplete frame"};
static_assert(std::size(kTuioDropNames) == static_cast<size_t>(TuioDrop::kCount));

/// What came in and what was dropped, counted since the start.
struct TuioStats {
  uint64_t packets = 0;   ///< bundles (or lone messages) received
  uint64_t messages = 0;  ///< messages received
  uint64_t frames = 0;    ///< frames completed
  uint64_t ignored = 0;   ///< TUIO messages of profiles not used here (2Dobj, tok, icg, ...)
  uint64_t expired = 0;   ///< times the stream timed out with contacts live
  std::array<uint64_t, static_cast<size_t>(TuioDrop::kCount)> dropped{};

  uint64_t& operator[](TuioDrop d) { return dropped[static_cast<size_t>(d)]; }
  uint64_t operator[](TuioDrop d) const { return dropped[static_cast<size_t>(d)]; }
  /// Every drop, whatever the reason.
  uint64_t TotalDropped() const;
  /// For a status line: "" when nothing was dropped, else "12 dropped: 10 non-finite, 2 unknown
  /// address".
  std::string Summary() const;
};

}  // namespace pg
