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
  // between two frames: the reach grows with the time since the contact was last seen
  for (int i = 0; i < nPrev; ++i) {
    const double interval = frame.time - m_seen[i];
    const double reach =
        std::max(params.maxDistance, interval > 0.0 ? params.maxSpeed * interval : 0.0);
    const double reach2 = reach * reach;
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
  std::vector<double> seen;
  next.reserve(nBlobs);
  seen.reserve(nBlobs);
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
    seen.push_back(frame.time);
  }
  // unmatched contacts continue where they were last seen for keep_lost frames (a blob that
  // drops out for a frame or two keeps its id and its particles); then they are lifted
  std::vector<Contact> lifted;
  for (int i = 0; i < nPrev; ++i) {
    if (prevTaken[i]) continue;
    Contact c = std::move(m_current[i]);
    if (c.missed < params.keepLost) {
      c.state = ContactState::kContinuing;
      ++c.missed;
      next.push_back(std::move(c));
      seen.push_back(m_seen[i]);
    } else {
      c.state = ContactState::kLifted;
      lifted.push_back(std::move(c));
    }
  }
  out.contacts = next;
  // lifted contacts once, with their last blob, after the current ones
  for (Contact& c : lifted) out.contacts.push_back(std::move(c));
  m_current = std::move(next);
  m_seen = std::move(seen);
  return out;
}

void Tracker::Reset() {
  m_current.clear();
  m_seen.clear();
}

}  // namespace pg
