// TUIO out: a frame of contacts (contours in table cm) becomes TUIO 2.0 bundles, frm, ptr, bnd,
// ocg, p3d (a depth camera's contacts, with their heights) and alv, each small enough for one UDP
// datagram, and optionally TUIO 1.1 /tuio/2Dcur bundles for older clients. Pure: the sender
// (transport.h) puts the bundles on the wire.
#pragma once

#include "proxygrasp/tuio/osc.h"
#include "proxygrasp/tuio/types.h"

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// How contacts are encoded.
struct TuioEncoderParams {
  TableParams table;                  ///< the rectangle that maps onto normalised [0, 1]^2
  bool flipY = true;                  ///< TUIO's y runs down from the top edge; the table's runs up
  int maxBundleBytes = 1472;          ///< largest bundle, bytes (one Ethernet UDP datagram)
  double tolerance = 0.02;            ///< Douglas-Peucker tolerance of ocg outlines, cm
  bool cursors11 = false;             ///< also send TUIO 1.1 /tuio/2Dcur bundles
  std::string source = "proxygrasp";  ///< the source name in frm and 2Dcur source
  int sensorWidth = 640;              ///< sensor size given in frm's dim, pixels
  int sensorHeight = 480;             ///< sensor size given in frm's dim, pixels
};

/// A contact to send: its session id, its outline (closed, any winding) and centroid, in cm, and
/// for a depth camera's contact its mean height above the table (cm; none for the IR camera).
struct TuioOutContact {
  TuioSessionId id = 0;
  std::vector<Vec2> contour;
  Vec2 centroid = Vec2::Zero();
  std::optional<double> height;  ///< cm; sent as a /tuio2/p3d z when there is one
};

/// What the encoder had to give up, counted since the start.
struct TuioEncodeStats {
  uint64_t frames = 0;           ///< frames encoded
  uint64_t bundles = 0;          ///< bundles built
  uint64_t coarsened = 0;        ///< outlines simplified beyond `tolerance` to fit one bundle
  uint64_t droppedContacts = 0;  ///< contacts left out: too many for alv to fit, or no outline
  uint64_t droppedCursors = 0;   ///< TUIO 1.1 cursors left out of a full 2Dcur bundle
};

/// Builds the bundles of one frame. Every TUIO 2.0 bundle of a frame starts with the same frm;
/// a contact's ptr, bnd, ocg (and p3d when it has a height) always travel in the same bundle; the
/// last bundle ends with alv.
class TuioEncoder {
 public:
  explicit TuioEncoder(const TuioEncoderParams& params = {});

  void SetParams(const TuioEncoderParams& params) { m_params = params; }
  const TuioEncoderParams& params() const { return m_params; }

  /// The TUIO 2.0 bundles of one frame (frame id and time as the frm gives them), followed by one
  /// TUIO 1.1 bundle when cursors11 is set. Each is at most maxBundleBytes long.
  std::vector<OscBundle> Encode(int64_t frame, OscTimeTag time,
                                std::span<const TuioOutContact> contacts);

  const TuioEncodeStats& stats() const { return m_stats; }

 private:
  OscBundle EncodeCursors11(int64_t frame, OscTimeTag time,
                            std::span<const TuioOutContact> contacts);
  float NormX(double x) const;
  float NormY(double y) const;
  // a height above the table (cm) as a normalised z: in units of the table's width, as x
  float NormZ(double z) const;

  TuioEncoderParams m_params;
  TuioEncodeStats m_stats;
  // the last centroid and time of each cursor sent, for TUIO 1.1 velocities
  std::map<TuioSessionId, std::pair<Vec2, double>> m_lastCursor;
};

/// A closed polygon simplified by Douglas-Peucker: every dropped point lies within tolerance (cm)
/// of the kept outline. Keeps at least 3 points of a polygon that had them; the first point is
/// kept.
std::vector<Vec2> SimplifyClosed(std::span<const Vec2> points, double tolerance);

/// The oriented box around a polygon along its principal axes: centre, angle of the first axis
/// (rad, CCW from +x, in [0, pi)), and its extents along the two axes (cm).
struct OrientedBox {
  Vec2 centre = Vec2::Zero();
  double angle = 0.0;
  double width = 0.0;
  double height = 0.0;
};
OrientedBox PrincipalBox(std::span<const Vec2> points);

}  // namespace pg
