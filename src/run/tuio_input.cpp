#include "proxygrasp/run/tuio_input.h"

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/tuio/decoder.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>

namespace pg {

Blob BlobFromOutline(std::span<const Vec2> outline, double spacing) {
  Contour dense(2, static_cast<Eigen::Index>(outline.size()));
  for (size_t k = 0; k < outline.size(); ++k) dense.col(static_cast<Eigen::Index>(k)) = outline[k];
  Blob blob;
  if (dense.cols() == 0) return blob;
  const Contour ccw = MakeCounterClockwise(dense);
  blob.area = std::abs(SignedArea(ccw));
  blob.centroid = PolygonCentroid(ccw);
  blob.boundsMin = ccw.rowwise().minCoeff();
  blob.boundsMax = ccw.rowwise().maxCoeff();
  blob.contour = ResampleClosed(ccw, spacing, 3);
  return blob;
}

// ---- tracking ----

ContactId TuioTracker::NewId(TuioSessionId session) {
  constexpr TuioSessionId kMaxId = std::numeric_limits<ContactId>::max();
  ContactId id = 0;
  if (session > m_maxId && session <= kMaxId) {
    id = static_cast<ContactId>(session);
  } else {
    // a session id below one already used, or none a contact id can hold: the next free id
    // (after 2^31 - 1 ids there is none left; the last one is then shared)
    id = m_maxId < std::numeric_limits<ContactId>::max() ? m_maxId + 1 : m_maxId;
  }
  m_maxId = std::max(m_maxId, id);
  return id;
}

ContactId TuioTracker::IdOf(TuioSessionId session) const {
  const auto it = m_live.find(session);
  return it == m_live.end() ? kNoId : it->second.id;
}

ContactSet TuioTracker::Step(const TuioFrame* frame, double spacing) {
  ContactSet out;
  if (!frame) {
    // nothing arrived: every live contact holds its last shape
    for (const auto& [session, live] : m_live)
      out.contacts.push_back({live.id, ContactState::kContinuing, live.blob, 0, {live.id}});
    return out;
  }

  std::set<TuioSessionId> listed;
  for (const TuioContact& c : frame->contacts) {
    if (!listed.insert(c.id).second) continue;  // a session listed twice: the first counts
    auto it = m_live.find(c.id);
    const bool fresh = it == m_live.end();
    if (fresh) it = m_live.emplace(c.id, Live{NewId(c.id), Blob()}).first;
    it->second.blob = BlobFromOutline(c.contour, spacing);
    // a height sent with the contact (/tuio2/p3d): TUIO carries one per contact, so every point
    // of the outline takes it
    if (c.height)
      it->second.blob.heights.assign(static_cast<size_t>(it->second.blob.contour.cols()),
                                     *c.height);
    // TUIO says nothing of merges and splits: a session continues itself or is new
    Contact contact{it->second.id,
                    fresh ? ContactState::kNew : ContactState::kContinuing,
                    it->second.blob,
                    0,
                    {}};
    if (!fresh) contact.parents.push_back(contact.id);
    out.contacts.push_back(std::move(contact));
  }
  // lifted: named in the frame's lifted list, or simply no longer listed
  for (auto it = m_live.begin(); it != m_live.end();) {
    if (listed.contains(it->first)) {
      ++it;
      continue;
    }
    out.contacts.push_back(
        {it->second.id, ContactState::kLifted, std::move(it->second.blob), 0, {}});
    it = m_live.erase(it);
  }
  return out;
}

// ---- streams ----

Result<std::unique_ptr<TuioStream>> TuioStream::Listen(const std::string& address, int port) {
  Result<std::unique_ptr<TuioReceiver>> opened = TuioReceiver::Open(address, port);
  if (!opened.ok()) return opened.error();
  std::unique_ptr<TuioStream> s(new TuioStream());
  s->m_receiver = std::move(opened.value());
  s->m_address = address;
  return s;
}

std::unique_ptr<TuioStream> TuioStream::Replay(std::vector<OscBundle> bundles, std::string name) {
  std::unique_ptr<TuioStream> s(new TuioStream());
  s->m_bundles = std::move(bundles);
  s->m_name = std::move(name);
  return s;
}

std::optional<TuioFrame> TuioStream::Next(double time, double duration, const TuioParams& params) {
  if (m_receiver) {
    const TableParams& now = m_receiver->decoder().params().table;
    if (now.width != params.table.width || now.height != params.table.height)
      m_receiver->decoder().SetParams(params);
    if (m_wait > 0.0) return m_receiver->WaitFrame(m_wait);
    return m_receiver->PollFrame(TuioClock());
  }
  if (!m_decoded) {
    m_frames = ReplayRecording(m_bundles, params, duration, &m_replayStats);
    m_bundles.clear();
    m_bundles.shrink_to_fit();
    m_decoded = true;
  }
  // a frame that arrived before the middle of this simulation frame applies to it
  const double until = time + 0.5 * duration;
  const size_t first = m_next;
  while (m_next < m_frames.size() && m_frames[m_next].time <= until) ++m_next;
  if (m_next == first) return std::nullopt;
  if (m_next == first + 1) return m_frames[first];
  return MergeTuioFrames(std::span<const TuioFrame>(m_frames).subspan(first, m_next - first));
}

std::string TuioStream::Describe() const {
  if (m_receiver)
    return "tuio:" + (m_address.empty() ? std::string() : m_address + ":") +
           std::to_string(m_receiver->port());
  return "tuio file " + m_name;
}

const TuioStats& TuioStream::stats() const {
  return m_receiver ? m_receiver->stats() : m_replayStats;
}

std::string TuioStream::Status() const {
  const TuioStats& s = stats();
  const std::string dropped = s.Summary();
  return Describe() + ": " + std::to_string(s.packets) + " packets, " + std::to_string(s.frames) +
         " frames, " + (dropped.empty() ? std::string("none dropped") : dropped);
}

}  // namespace pg
