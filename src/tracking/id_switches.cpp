#include "proxygrasp/tracking/id_switches.h"

#include <algorithm>
#include <cmath>

namespace pg {

double IdSwitchCount::MinutesOfTouch(double fps) const {
  return fps > 0.0 ? contactFrames / fps / 60.0 : 0.0;
}

double IdSwitchCount::PerMinuteOfTouch(double fps) const {
  const double minutes = MinutesOfTouch(fps);
  return minutes > 0.0 ? switches / minutes : 0.0;
}

void IdSwitchCounter::Count(IdSwitchKind kind, const Lift& lift, const Contact& next,
                            int64_t frame) {
  ++m_count.switches;
  if (kind == IdSwitchKind::kJump) ++m_count.jumps;
  m_switches.push_back({kind, frame, lift.id, next.id, static_cast<int>(frame - lift.frame),
                        (next.blob.centroid - lift.at).norm(), lift.area});
}

void IdSwitchCounter::Add(const ContactSet& set) {
  ++m_count.frames;

  // lifts too old to be continued were real lifts: forget them
  const int64_t oldest = set.frame - m_params.maxGapFrames;
  std::erase_if(m_lifts, [&](const Lift& l) { return l.frame < oldest; });

  std::vector<Lift> lifted;
  std::vector<const Contact*> started;
  for (const Contact& c : set.contacts) {
    // a contact kept after its blob went (tracking.keep_lost) counts from the frame it was first
    // missing, as if it had lifted then, and the frames it was kept are no touch
    if (c.state == ContactState::kLifted)
      lifted.push_back({c.blob.centroid, set.frame - c.missed, c.id, c.blob.area});
    else if (c.missed == 0)
      ++m_count.contactFrames;
    if (c.state == ContactState::kNew) started.push_back(&c);
  }

  // jumps: as many new as lifted in one frame, paired globally nearest first within maxJump
  if (!lifted.empty() && lifted.size() == started.size()) {
    struct Pair {
      double d2;
      size_t lift, next;
    };
    std::vector<Pair> pairs;
    for (size_t i = 0; i < lifted.size(); ++i)
      for (size_t j = 0; j < started.size(); ++j) {
        const double d2 = (started[j]->blob.centroid - lifted[i].at).squaredNorm();
        if (d2 <= m_params.maxJump * m_params.maxJump) pairs.push_back({d2, i, j});
      }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
      if (a.d2 != b.d2) return a.d2 < b.d2;
      return a.lift != b.lift ? a.lift < b.lift : a.next < b.next;
    });
    std::vector<bool> liftTaken(lifted.size(), false), nextTaken(started.size(), false);
    for (const Pair& p : pairs) {
      if (liftTaken[p.lift] || nextTaken[p.next]) continue;
      liftTaken[p.lift] = nextTaken[p.next] = true;
      Count(IdSwitchKind::kJump, lifted[p.lift], *started[p.next], set.frame);
    }
    // what was paired is accounted for; the rest go on as flickers
    std::vector<Lift> restLifted;
    std::vector<const Contact*> restStarted;
    for (size_t i = 0; i < lifted.size(); ++i)
      if (!liftTaken[i]) restLifted.push_back(lifted[i]);
    for (size_t j = 0; j < started.size(); ++j)
      if (!nextTaken[j]) restStarted.push_back(started[j]);
    lifted = std::move(restLifted);
    started = std::move(restStarted);
  }

  // flickers: each new contact continues at most one lift, the nearest within maxDistance
  // (this frame's lifts included), and each lift is continued at most once
  for (const Lift& l : lifted)
    if (l.frame >= oldest) m_lifts.push_back(l);
  const double reach2 = m_params.maxDistance * m_params.maxDistance;
  for (const Contact* c : started) {
    auto nearest = m_lifts.end();
    double best = reach2;
    for (auto it = m_lifts.begin(); it != m_lifts.end(); ++it) {
      const double d2 = (c->blob.centroid - it->at).squaredNorm();
      if (d2 <= best) {
        best = d2;
        nearest = it;
      }
    }
    if (nearest == m_lifts.end()) continue;
    Count(IdSwitchKind::kFlicker, *nearest, *c, set.frame);
    m_lifts.erase(nearest);
  }
}

}  // namespace pg
