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
};

/// The output of the tracking stage for one frame: current contacts, then those lifted this frame.
struct ContactSet {
  int64_t frame = 0;  ///< frame number from 0
  double time = 0.0;  ///< s
  std::vector<Contact> contacts;
};

/// Parameters of frame-to-frame association. Section [tracking] of a level.
struct TrackingParams {
  double maxDistance = 4.0;  ///< farthest a centroid may move between frames and keep its id, cm
};

void Describe(TrackingParams& p, ParamVisitor& v);

}  // namespace pg
