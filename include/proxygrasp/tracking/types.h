// What the tracking stage hands on: the contact set, each connected component with a stable id.
#pragma once

#include "proxygrasp/core/ids.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/sensing/types.h"

#include <cstdint>
#include <vector>

namespace pg {

/// How a contact relates to the last frame.
enum class ContactState { kNew, kContinuing, kLifted };
inline constexpr const char* kContactStateNames[] = {"new", "continuing", "lifted"};

/// A tracked contact. A lifted contact carries its last blob.
struct Contact {
  ContactId id = kNoId;
  ContactState state = ContactState::kNew;
  Blob blob;
  /// frames the contact has gone on without a blob of its own (tracking.keep_lost), its blob
  /// being the last one seen; for a lifted contact, the frames it went on so before it lifted
  int missed = 0;
  /// The last frame's contacts this one came from (topology): a continuing contact's own id
  /// first, then those that merged into it this frame; a piece split off another contact this
  /// frame (state new) has that contact's id; empty for a contact that is new on the table. A
  /// lifted contact has none.
  std::vector<ContactId> parents;
  /// lifted: the contact it merged into this frame (its blob joined that one's), or kNoId when it
  /// left the table
  ContactId mergedInto = kNoId;
};

/// The output of the tracking stage for one frame: current contacts, then those lifted this frame.
struct ContactSet {
  int64_t frame = 0;  ///< frame number from 0
  double time = 0.0;  ///< s
  std::vector<Contact> contacts;
  int merges = 0;  ///< current contacts with more than one parent (several blobs became one)
  int splits = 0;  ///< last frame's contacts that are the parent of more than one current one
};

/// Parameters of frame-to-frame association. Section [tracking] of a level.
struct TrackingParams {
  /// farthest a centroid may move between two frames and keep its id at any frame rate, cm
  double maxDistance = 4.0;
  /// fastest a centroid may move and keep its id, cm/s: between frames dt apart the reach is
  /// max(maxDistance, maxSpeed dt), so a slower camera (or a recording that repeats frames)
  /// reaches as far in time as a faster one
  double maxSpeed = 150.0;
  /// frames a contact whose blob is gone continues where it was last seen before it is lifted
  /// (0: lifted in the first frame without it): a blob that drops out for a frame or two, below
  /// the threshold or min_area, keeps its id and its particles; a lift is reported this late
  int keepLost = 3;
  /// Topology: a contact of the last frame whose blob is not matched this frame merged into a
  /// blob when at least half its last contour, moved on by its last velocity, lies inside that
  /// blob or within this margin of it; a new blob split off a contact of the last frame when at
  /// least half its contour lies so within that contact's moved blob. The margin grows by a
  /// quarter of the distance the contact's velocity carries it between the frames (its
  /// uncertainty), cm
  double mergeMargin = 0.3;
};

void Describe(TrackingParams& p, ParamVisitor& v);

}  // namespace pg
