// The tracking stage: associates each frame's connected components with the contacts of the last
// frame, nearest first, and hands out ids that are never reused. Merge and split policy: see
// docs/sensing.md ("Tracking").
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tracking/types.h"

#include <vector>

namespace pg {

/// Frame-to-frame contact association with stable ids.
class Tracker {
 public:
  /// A tracker with these parameters.
  explicit Tracker(const TrackingParams& params = TrackingParams()) : m_params(params) {}

  /// Changes the parameters between frames (every tracking parameter applies live). A value out
  /// of its described range is an Error naming it, and nothing changes.
  MaybeError SetParams(const TrackingParams& params);
  const TrackingParams& params() const { return m_params; }

  /// One frame. Matches frame's blobs to the last frame's contacts (those kept without a blob
  /// included): every pair of (contact, blob) whose centroids are within
  /// max(params.maxDistance, params.maxSpeed dt) cm, dt the time since the contact was last seen
  /// (frame.time), is a candidate; candidates are taken globally nearest first, each contact and
  /// blob at most once. Matched blobs continue their contact's id; unmatched blobs are new (fresh
  /// id). An unmatched contact goes on where it was last seen, continuing with `missed` counting
  /// up, for params.keepLost frames; then it is lifted and listed once, with its last blob,
  /// after the current and kept contacts. One whose centroid, moved on by its velocity, lies
  /// inside a hover region of the frame (ContourFrame::hover: a depth camera sees the finger above
  /// the touch band) rose off the table and is lifted at once. Topology (Contact::parents,
  /// Contact::mergedInto): every contact's last blob is moved on by its centroid velocity. An
  /// unmatched contact whose moved contour lies at least half inside a blob that continues another
  /// contact (or within params.mergeMargin of it) merged into that blob: it is lifted at once, with
  /// mergedInto set, and is a parent of the blob's contact. An unmatched blob whose contour lies at
  /// least half within a previous contact's moved blob split off it: it is new, with that contact
  /// as its parent.
  ContactSet Step(const ContourFrame& frame);

  /// Forgets all contacts (the next frame's blobs are all new). Ids keep counting up.
  void Reset();

  /// The contacts currently on the table (after the last Step), lifted ones excluded.
  const std::vector<Contact>& current() const { return m_current; }

 private:
  struct Candidate {
    double distance;
    int previous;
    int blob;
  };

  TrackingParams m_params;
  std::vector<Contact> m_current;  // on the table, and those kept after they were last seen
  std::vector<double> m_seen;      // frame.time each of m_current was last seen, s
  std::vector<Vec2> m_velocity;    // each of m_current's centroid velocity, cm/s
  IdCounter m_ids;
  std::vector<Candidate> m_candidates;  // scratch
};

}  // namespace pg
