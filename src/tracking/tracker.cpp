#include "proxygrasp/tracking/tracker.h"

#include "proxygrasp/core/params.h"

#include <algorithm>
#include <optional>

namespace pg {
namespace {

// a contour that lies at least this much within a blob (as a fraction of its points) came from it
// or went into it
constexpr double kMinCoverage = 0.5;
// a continuing blob at least this much within its own contact's moved blob is that contact alone
constexpr double kOwnCoverage = 0.9;
// a part of a continuing blob that came from another contact covers at least this of it
constexpr double kMinPartCoverage = 0.25;
// how much of the distance a contact's last velocity carries it between frames is uncertain
constexpr double kVelocityUncertainty = 0.25;

// the fraction of the points of `points`, moved by `shift`, that lie inside the blob's outline or
// within `margin` of it
double Coverage(const Contour& points, const Vec2& shift, const Blob& blob, double margin) {
  const Eigen::Index n = points.cols();
  if (n == 0 || blob.contour.cols() < 3) return 0.0;
  // the bounds from the outline itself: a blob made by hand may not carry them
  const Vec2 lo = Vec2(blob.contour.rowwise().minCoeff()) - Vec2(margin, margin);
  const Vec2 hi = Vec2(blob.contour.rowwise().maxCoeff()) + Vec2(margin, margin);
  // PolygonBands: Coverage asks about most points of every continuing contact's outline each
  // frame, and asked of whole outlines (PointInPolygon, DistanceToBoundary) that took 1 ms a
  // frame of four spread hands. Made when a first point lies within the bounds: most pairs of
  // contacts lie apart.
  std::optional<PolygonBands> outline;
  int covered = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Vec2 p = points.col(k) + shift;
    if (p.x() < lo.x() || p.y() < lo.y() || p.x() > hi.x() || p.y() > hi.y()) continue;
    if (!outline) outline.emplace(blob.contour);
    if (outline->Inside(p) || outline->Within(p, margin)) ++covered;
  }
  return static_cast<double>(covered) / static_cast<double>(n);
}

}  // namespace

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

  // Topology. Each previous contact's last blob is moved on by its velocity to where it should be
  // now; an unmatched previous contact whose moved contour lies mostly within a blob merged into
  // it, and an unmatched blob whose contour lies mostly within a previous contact's moved blob
  // split off it.
  std::vector<Vec2> shift(nPrev, Vec2::Zero());
  std::vector<double> margin(nPrev, params.mergeMargin);
  for (int i = 0; i < nPrev; ++i) {
    const double interval = std::max(0.0, frame.time - m_seen[i]);
    shift[i] = m_velocity[i] * interval;
    margin[i] += kVelocityUncertainty * shift[i].norm();
  }
  std::vector<int> mergedTo(nPrev, -1);
  for (int i = 0; i < nPrev; ++i) {
    if (prevTaken[i]) continue;
    double best = kMinCoverage;
    for (int j = 0; j < nBlobs; ++j) {
      // a blob no contact continues is farther than the reach from this one (they would have
      // been paired): a new contact, not a merge
      if (blobToPrev[j] < 0) continue;
      const double c = Coverage(m_current[i].blob.contour, shift[i], frame.blobs[j], margin[i]);
      if (c >= best) {
        best = c;
        mergedTo[i] = j;
      }
    }
  }
  // A depth camera sees a finger that rises out of the touch band as hover (ContourFrame::hover):
  // an unmatched contact whose centroid, moved on by its velocity, lies inside a hover region
  // rose into it and is lifted at once, not kept where it was last seen (keep_lost is for blobs
  // that drop out of the camera's view, and a finger in the air is in view). Inside, with no
  // margin: a fingertip's pad that drops out of the band for a frame lies beside the hover of its
  // own finger rising behind it, not within it. IR frames have no hover.
  std::vector<bool> rose(nPrev, false);
  for (int i = 0; i < nPrev; ++i) {
    if (prevTaken[i] || mergedTo[i] >= 0) continue;
    const Vec2 at = m_current[i].blob.centroid + shift[i];
    for (const Blob& hover : frame.hover) {
      if (hover.contour.cols() >= 3 && PointInPolygon(hover.contour, at)) {
        rose[i] = true;
        break;
      }
    }
  }
  std::vector<int> splitFrom(nBlobs, -1);
  for (int j = 0; j < nBlobs; ++j) {
    if (blobToPrev[j] >= 0) continue;
    double best = kMinCoverage;
    for (int i = 0; i < nPrev; ++i) {
      const double c = Coverage(frame.blobs[j].contour, -shift[i], m_current[i].blob, margin[i]);
      if (c >= best) {
        best = c;
        splitFrom[j] = i;
      }
    }
  }

  // current contacts in blob order (largest first), continuing or new
  std::vector<Contact> next;
  std::vector<double> seen;
  std::vector<Vec2> velocity;
  next.reserve(nBlobs);
  seen.reserve(nBlobs);
  velocity.reserve(nBlobs);
  std::vector<int> children(nPrev, 0);
  for (int j = 0; j < nBlobs; ++j) {
    Contact c;
    Vec2 v = Vec2::Zero();
    if (blobToPrev[j] >= 0) {
      const int i = blobToPrev[j];
      c.id = m_current[i].id;
      c.state = ContactState::kContinuing;
      c.parents.push_back(c.id);
      ++children[i];
      const double interval = frame.time - m_seen[i];
      v = interval > 0.0 ? Vec2((frame.blobs[j].centroid - m_current[i].blob.centroid) / interval)
                         : m_velocity[i];
    } else {
      c.id = m_ids.Next();
      c.state = ContactState::kNew;
      if (splitFrom[j] >= 0) {
        c.parents.push_back(m_current[splitFrom[j]].id);
        ++children[splitFrom[j]];
        v = m_velocity[splitFrom[j]];
      }
    }
    c.blob = frame.blobs[j];
    next.push_back(std::move(c));
    seen.push_back(frame.time);
    velocity.push_back(v);
  }
  for (int i = 0; i < nPrev; ++i) {
    if (mergedTo[i] >= 0) next[mergedTo[i]].parents.push_back(m_current[i].id);
  }
  // A part handed from one blob to another in one frame (a finger that leaves one neighbour for
  // another, the two blobs each continuing a contact): a continuing blob that its own contact's
  // moved blob does not cover grew a part, and every other contact of the last frame that
  // covers at least kMinPartCoverage of it is a parent too (its blob split, and the part merged
  // here). A blob that its own contact covers, a fingertip beside another, gets no such parent.
  for (int j = 0; j < nBlobs; ++j) {
    const int own = blobToPrev[j];
    if (own < 0) continue;
    const Contour& contour = frame.blobs[j].contour;
    if (Coverage(contour, -shift[own], m_current[own].blob, margin[own]) >= kOwnCoverage) continue;
    for (int i = 0; i < nPrev; ++i) {
      if (i == own || mergedTo[i] >= 0) continue;
      const ContactId id = m_current[i].id;
      std::vector<ContactId>& parents = next[j].parents;
      if (std::find(parents.begin(), parents.end(), id) != parents.end()) continue;
      if (Coverage(contour, -shift[i], m_current[i].blob, margin[i]) < kMinPartCoverage) continue;
      parents.push_back(id);
      ++children[i];
    }
  }
  // a centroid jumps when blobs join or part: the contacts of such an event keep the velocity
  // of the contact they continue rather than the jump
  for (int j = 0; j < nBlobs; ++j) {
    Contact& c = next[j];
    if (c.parents.size() > 1) ++out.merges;
    const int i = blobToPrev[j];
    if (i >= 0 && (c.parents.size() > 1 || children[i] > 1)) velocity[j] = m_velocity[i];
  }
  for (int i = 0; i < nPrev; ++i) {
    if (children[i] > 1) ++out.splits;
  }
  // unmatched contacts continue where they were last seen for keep_lost frames (a blob that
  // drops out for a frame or two keeps its id and its particles); then they are lifted. A
  // contact that merged into a blob is lifted at once, into it.
  std::vector<Contact> lifted;
  for (int i = 0; i < nPrev; ++i) {
    if (prevTaken[i]) continue;
    Contact c = std::move(m_current[i]);
    c.parents.clear();
    if (mergedTo[i] >= 0) {
      c.state = ContactState::kLifted;
      c.mergedInto = next[mergedTo[i]].id;
      lifted.push_back(std::move(c));
    } else if (c.missed < params.keepLost && !rose[i]) {
      c.state = ContactState::kContinuing;
      c.parents.push_back(c.id);
      ++c.missed;
      next.push_back(std::move(c));
      seen.push_back(m_seen[i]);
      velocity.push_back(m_velocity[i]);
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
  m_velocity = std::move(velocity);
  return out;
}

void Tracker::Reset() {
  m_current.clear();
  m_seen.clear();
  m_velocity.clear();
}

}  // namespace pg
