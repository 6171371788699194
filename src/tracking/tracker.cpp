#include "proxygrasp/tracking/tracker.h"

#include "proxygrasp/core/params.h"

#include <algorithm>

namespace pg {

MaybeError Tracker::SetParams(const TrackingParams& params) {
  if (MaybeError s = CheckDescribed("tracking", params)) return s;
  m_params = params;
  return std::nullopt;
}

ContactSet Tracker::Step(const ContourFrame& frame) {
  const TrackingParams& params = m_params;
  ContactSet out;
  out.frame = frame.index;
  out.time = frame.time;
  const int nPrev = static_cast<int>(m_current.size());
  const int nBlobs = static_cast<int>(frame.blobs.size());

  // every (previous contact, blob) pair within reach, nearest first; ties by blob then contact
  // order so the result does not depend on the sort implementation
  m_candidates.clear();
  // a camera slower than 60 Hz (or a recording that repeats frames) shows a finger farther on
  // between two frames: the reach grows with the time between them
  const double interval = nPrev > 0 ? frame.time - m_lastTime : 0.0;
  const double reach =
      std::max(params.maxDistance, interval > 0.0 ? params.maxSpeed * interval : 0.0);
  const double reach2 = reach * reach;
  m_lastTime = frame.time;
  for (int i = 0; i < nPrev; ++i) {
    for (int j = 0; j < nBlobs; ++j) {
      const double d2 = (frame.blobs[j].centroid - m_current[i].blob.centroid).squaredNorm();
      if (d2 <= reach2) m_candidates.push_back({d2, i, j});
    }
  }
  std::sort(m_candidates.begin(), m_candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.distance != b.distance) return a.distance < b.distance;
    if (a.blob != b.blob) return a.blob < b.blob;
    return a.previous < b.previous;
  });

  // greedy one-to-one assignment, globally nearest pairs first
  std::vector<int> blobToPrev(nBlobs, -1);
  std::vector<bool> prevTaken(nPrev, false);
  for (const Candidate& c : m_candidates) {
    if (prevTaken[c.previous] || blobToPrev[c.blob] >= 0) continue;
    prevTaken[c.previous] = true;
    blobToPrev[c.blob] = c.previous;
  }

  // current contacts in blob order (largest first), continuing or new
  std::vector<Contact> next;
  next.reserve(nBlobs);
  for (int j = 0; j < nBlobs; ++j) {
    Contact c;
    if (blobToPrev[j] >= 0) {
      c.id = m_current[blobToPrev[j]].id;
      c.state = ContactState::kContinuing;
    } else {
      c.id = m_ids.Next();
      c.state = ContactState::kNew;
    }
    c.blob = frame.blobs[j];
    next.push_back(std::move(c));
  }
  out.contacts = next;

  // lifted contacts once, with their last blob, after the current ones
  for (int i = 0; i < nPrev; ++i) {
    if (prevTaken[i]) continue;
    Contact lifted = std::move(m_current[i]);
    lifted.state = ContactState::kLifted;
    out.contacts.push_back(std::move(lifted));
  }
  m_current = std::move(next);
  return out;
}

void Tracker::Reset() {
  m_current.clear();
}

}  // namespace pg
