#include "proxygrasp/proxies/proxy_stage.h"

#include "proxygrasp/core/params.h"
#include "proxygrasp/proxies/matching.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <unordered_set>

namespace pg {
namespace {

// the contour point nearest j (by index distance, the preceding one first on equal distance)
// whose predecessor is known; -1 when there is none. With `labels` (the finger of each point),
// the nearest among the points of j's own finger first, any kept point when that finger has none
int NearestKept(const std::vector<int>& pred, int j, const std::vector<ContactId>& labels = {}) {
  const int m = static_cast<int>(pred.size());
  auto search = [&](bool sameFinger) {
    auto fits = [&](int i) { return pred[i] >= 0 && (!sameFinger || labels[i] == labels[j]); };
    for (int d = 1; d <= m / 2; ++d) {
      const int before = WrapIndex(j - d, m);
      if (fits(before)) return before;
      const int after = WrapIndex(j + d, m);
      if (fits(after)) return after;
    }
    return -1;
  };
  const int own = labels.empty() ? -1 : search(true);
  return own >= 0 ? own : search(false);
}

// whether a contact's particles take their heights from its measurements
bool Measures(const ProxyParams& params, const Blob& blob) {
  const bool any = !blob.heights.empty() && blob.heights.size() == size_t(blob.contour.cols());
  return any && MeasuresHeights(params.placement);
}

// the underside of the finger at contour point j of a blob with heights: the median of the
// measured heights over the points `span` either side of j, less the offset, never below the
// table, cm
double MeasuredUnderside(const ProxyParams& params, const Blob& blob, int j,
                         std::vector<double>& scratch) {
  const int n = static_cast<int>(blob.heights.size());
  const int span = std::min(params.heightSpan, (n - 1) / 2);
  scratch.clear();
  for (int d = -span; d <= span; ++d) scratch.push_back(blob.heights[size_t(WrapIndex(j + d, n))]);
  const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  return std::max(0.0, *mid - params.heightOffset);
}

// the contour point of `contour` nearest p, searched from `hint` outwards while the distance
// falls, then over the whole contour when the local search ends far from p (further than
// `near`); contours are walked in order, so the hint of the last particle is nearly always right
int NearestPoint(const Contour& contour, const Vec2& p, int hint, double near) {
  const int n = static_cast<int>(contour.cols());
  auto d2 = [&](int i) { return (Vec2(contour.col(i)) - p).squaredNorm(); };
  int best = WrapIndex(hint, n);
  double bestD = d2(best);
  for (const int step : {1, -1}) {
    for (int i = WrapIndex(best + step, n), tries = 0; tries < n;
         i = WrapIndex(i + step, n), ++tries) {
      const double d = d2(i);
      if (d >= bestD) break;
      best = i;
      bestD = d;
    }
  }
  if (bestD <= near * near) return best;
  for (int i = 0; i < n; ++i) {
    const double d = d2(i);
    if (d < bestD) {
      best = i;
      bestD = d;
    }
  }
  return best;
}

// the principal axis of a contour's points, rad, and its elongation sqrt(l1 / l2) >= 1
double PrincipalAxis(const Contour& c, const Vec2& centre, double* elongation) {
  double xx = 0.0, yy = 0.0, xy = 0.0;
  for (Eigen::Index i = 0; i < c.cols(); ++i) {
    const Vec2 d = c.col(i) - centre;
    xx += d.x() * d.x();
    yy += d.y() * d.y();
    xy += d.x() * d.y();
  }
  const double mean = 0.5 * (xx + yy);
  const double spread = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
  *elongation = mean - spread > 0.0 ? std::sqrt((mean + spread) / (mean - spread))
                                    : std::numeric_limits<double>::infinity();
  return 0.5 * std::atan2(2.0 * xy, xx - yy);
}

// below this elongation a contact's turning is not observable from its outline (a round
// fingertip looks the same at every angle, and the sensor's sampling jitter would pass for it)
constexpr double kMinElongationForTurning = 1.3;

// The contact's rigid motion from the previous contour to the current one: the translation of its
// area centroid, and for elongated contacts the turning of its principal axis. Sub-sample motion
// is invisible to each point's own match where the contour runs along the motion (the aperture
// problem); the whole contour's motion is not.
Pose2 RigidMotion(const Contour& prev, const Contour& cur) {
  const Vec2 centroidPrev = PolygonCentroid(prev);
  const Vec2 centroidCur = PolygonCentroid(cur);
  double elongationPrev = 1.0, elongationCur = 1.0;
  const double axisPrev = PrincipalAxis(prev, centroidPrev, &elongationPrev);
  const double axisCur = PrincipalAxis(cur, centroidCur, &elongationCur);
  double angle = 0.0;
  if (std::min(elongationPrev, elongationCur) >= kMinElongationForTurning) {
    // an axis has no direction: the turn is taken modulo half a turn
    angle = WrapAngle(2.0 * (axisCur - axisPrev)) / 2.0;
  }
  return Pose2{centroidCur - Rotate(centroidPrev, angle), angle};
}

// how many contour samples on either side of its match a reused particle's target may move to:
// a match lags sub-sample motion by up to a sample or two where the contour runs along the motion
constexpr int kSubsampleReach = 3;

// The reused particle's target: its last target moved by the contact's rigid motion, then put
// back on the current contour at the nearest point of the segments within kSubsampleReach samples
// of its match j (so it stays near its match and on the contour).
// With `labels` (the finger of each point of a merged outline), only along the outline of the
// particle's own finger: a target near where two fingers' outlines meet does not slide onto the
// other's.
Vec2 SubsampleTarget(const Contour& cur, int j, const Vec2& lastTarget, const Pose2& motion,
                     const std::vector<ContactId>& labels = {}, ContactId finger = kNoId) {
  const int m = static_cast<int>(cur.cols());
  const Vec2 predicted = motion.Apply(lastTarget);
  if (m < 3) return cur.col(j);
  Vec2 best = cur.col(j);
  double bestDistance = (predicted - best).squaredNorm();
  const int reach = std::min(kSubsampleReach, (m - 1) / 2);
  for (int i = -reach; i < reach; ++i) {
    const int ia = WrapIndex(j + i, m), ib = WrapIndex(j + i + 1, m);
    if (!labels.empty() && (labels[ia] != finger || labels[ib] != finger)) continue;
    const Vec2 a = cur.col(ia);
    const Vec2 b = cur.col(ib);
    if ((b - a).squaredNorm() <= 0.0) continue;
    const Vec2 q = ClosestPointOnSegment(predicted, a, b);
    const double d = (predicted - q).squaredNorm();
    if (d < bestDistance) {
      bestDistance = d;
      best = q;
    }
  }
  return best;
}

// The successors chain integer matches frame after frame and each match drops the sub-sample
// shift of the contour's sampling, so a contact's indices can creep round its contour away from
// its particles' (sub-sample) targets; over a few dozen frames of a turning grip they creep several
// samples and the reach above starts dragging the targets round the contact. The creep is common to
// the whole contour: the median, over the reused particles, of the offset from a particle's index
// to the current point nearest its target. 0 when the indices still sit on their targets.
int IndexCreep(const Contour& cur, const Contour& targets, const std::vector<bool>& reused) {
  const int m = static_cast<int>(cur.cols());
  const int reach = std::min(kSubsampleReach + 1, (m - 1) / 2);
  std::vector<int> offsets;
  for (int j = 0; j < m; ++j) {
    if (!reused[j]) continue;
    int best = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (int i = -reach; i <= reach; ++i) {
      const double d = (cur.col(WrapIndex(j + i, m)) - targets.col(j)).squaredNorm();
      if (d < bestDistance) {
        bestDistance = d;
        best = i;
      }
    }
    offsets.push_back(best);
  }
  if (offsets.empty()) return 0;
  auto mid = offsets.begin() + static_cast<std::ptrdiff_t>(offsets.size() / 2);
  std::nth_element(offsets.begin(), mid, offsets.end());
  return *mid;
}

// The motion of each previous point of a contact whose points belong to several fingers (a
// merge): each finger's points move by that finger's own motion, fitted from `seed` (the whole
// outline's). Empty when every point is one finger's, which then moves with the outline.
std::vector<Pose2> FingerMotions(const Contour& prev, const Contour& cur,
                                 const std::vector<ContactId>& fingers, const Pose2& seed) {
  const int n = static_cast<int>(prev.cols());
  if (static_cast<int>(fingers.size()) != n ||
      std::all_of(fingers.begin(), fingers.end(),
                  [&](ContactId f) { return f == fingers.front(); })) {
    return {};
  }
  std::vector<Pose2> motions(static_cast<size_t>(n), seed);
  std::vector<ContactId> done;
  std::vector<int> members;
  for (int k = 0; k < n; ++k) {
    const ContactId f = fingers[k];
    if (std::find(done.begin(), done.end(), f) != done.end()) continue;
    done.push_back(f);
    members.clear();
    for (int i = k; i < n; ++i) {
      if (fingers[i] == f) members.push_back(i);
    }
    Contour piece(2, static_cast<Eigen::Index>(members.size()));
    for (size_t i = 0; i < members.size(); ++i) piece.col(i) = prev.col(members[i]);
    const Pose2 motion = EstimatePieceMotion(piece, cur, seed);
    for (const int i : members) motions[i] = motion;
  }
  return motions;
}

// a merged contact keeps the whole outlines of the fingers it still holds points of; with one
// finger left it is that finger's contact again
template <class Track>
void KeepHeldGhosts(Track& track) {
  std::erase_if(track.ghosts, [&](const auto& g) {
    return std::find(track.fingers.begin(), track.fingers.end(), g.finger) == track.fingers.end();
  });
  if (track.ghosts.size() < 2) track.ghosts.clear();
}

void Count(ParticlePlan& plan) {
  plan.reused = plan.created = plan.deleted = 0;
  for (const PlannedParticle& p : plan.particles) {
    switch (p.action) {
      case ParticleAction::kReused:
        ++plan.reused;
        break;
      case ParticleAction::kCreated:
        ++plan.created;
        break;
      case ParticleAction::kDeleted:
        ++plan.deleted;
        break;
    }
  }
}

}  // namespace

MatchResult MatchSuccessors(const ProxyParams& params, const Contour& prev, const Contour& cur,
                            int* fallbacks) {
  const int window = std::clamp(params.window, 0, kMaxMatchWindow);
  switch (params.algorithm) {
    case MatchAlgorithm::kReference:
      return MatchReference(prev, cur, window);
    case MatchAlgorithm::kWindowed: {
      // a band as wide as the contour is the full search: no prediction to work out
      if (cur.cols() > 0 && BandSpansContour(params.searchRadius, static_cast<int>(cur.cols()))) {
        if (fallbacks) *fallbacks += static_cast<int>(prev.cols());
        return MatchFast(prev, cur, window);
      }
      const std::vector<int> predicted = PredictSuccessors(prev, cur);
      MatchResult r =
          MatchWindowed(prev, cur, window, predicted, params.searchRadius, params.fallbackScore);
      if (fallbacks) *fallbacks += r.fallbacks;
      return r;
    }
    case MatchAlgorithm::kFast:
      break;
  }
  return MatchFast(prev, cur, window);
}

MaybeError ProxyStage::SetParams(const ProxyParams& params) {
  if (MaybeError s = CheckDescribed("proxies", params)) return s;
  m_params = params;
  return std::nullopt;
}

ParticlePlan ProxyStage::Step(const ContactSet& contacts, const SceneQuery& scene,
                              std::span<const ParticleFeedback> feedback, const TableImage* image) {
  const ProxyParams& params = m_params;
  ParticlePlan plan;
  plan.frame = contacts.frame;
  m_feedback.clear();
  for (const ParticleFeedback& f : feedback) m_feedback[f.id] = f;

  // a change of mode ends every particle of the other mode
  if (params.mode != m_lastMode) {
    if (params.mode == ProxyMode::kInstant) {
      for (const auto& [id, track] : m_tracks) DeleteTrack(id, track, plan);
      m_tracks.clear();
      m_measured.clear();
    } else {
      m_instant.DeleteAll(plan);
    }
    m_lastMode = params.mode;
  }

  if (params.mode == ProxyMode::kPersistent) {
    Persistent(params, contacts, scene, plan);
    MeasureHeights(params, contacts, plan);
  } else if (image == nullptr || image->image.empty()) {
    // instant mode sees nothing without an image: last frame's particles still end
    ++m_stats.missingImage;
    m_instant.DeleteAll(plan);
  } else {
    m_instant.Update(params, contacts, scene, *image, m_ids, plan);
  }
  Count(plan);
  return plan;
}

void ProxyStage::MeasureHeights(const ProxyParams& params, const ContactSet& contacts,
                                ParticlePlan& plan) {
  // Each particle of a contact with heights reads the finger's underside at the contour point
  // nearest its target, and follows it through a first-order filter that goes a = 1 - exp(-T /
  // tau) of the way to each reading, frames T apart: a ramp is followed T (1 - a) / a late, and
  // noise is cut to sqrt(a / (2 - a)) of itself (docs/proxies.md, "Measured heights").
  const double frame = contacts.time - m_measuredTime;
  const double a = params.heightSmoothing > 0.0 && frame > 0.0 && m_measuredTime >= 0.0
                       ? 1.0 - std::exp(-frame / params.heightSmoothing)
                       : 1.0;
  m_measuredTime = contacts.time;
  std::unordered_map<ContactId, const Blob*> blobs;
  for (const Contact& c : contacts.contacts) {
    if (c.state != ContactState::kLifted && Measures(params, c.blob)) blobs.emplace(c.id, &c.blob);
  }
  if (blobs.empty() && m_measured.empty()) return;  // nothing measured (the IR camera)
  ContactId last = kNoId;
  const Blob* blob = nullptr;
  int hint = 0;
  for (PlannedParticle& p : plan.particles) {
    if (p.action == ParticleAction::kDeleted) {
      m_measured.erase(p.id);
      continue;
    }
    if (p.contact != last) {
      last = p.contact;
      const auto it = blobs.find(p.contact);
      blob = it != blobs.end() ? it->second : nullptr;
      hint = 0;
    }
    if (blob == nullptr) {  // Measures: a measured blob has a point per height, and some
      m_measured.erase(p.id);
      continue;
    }
    hint = NearestPoint(blob->contour, p.target, hint, 1.0);
    const double now = MeasuredUnderside(params, *blob, hint, m_scratch);
    const auto it = m_measured.find(p.id);
    if (p.action == ParticleAction::kCreated || it == m_measured.end()) {
      p.measured = now;
      m_measured[p.id] = now;
    } else {
      it->second += a * (now - it->second);
      p.measured = it->second;
    }
  }
}

void ProxyStage::Reset() {
  m_measured.clear();
  m_measuredTime = -1.0;
  m_tracks.clear();
  m_feedback.clear();
  m_instant.Reset();
  m_lastMode = ProxyMode::kPersistent;
  m_stats = {};
}

int ProxyStage::LiveCount() const {
  int n = m_instant.LiveCount();
  for (const auto& [id, track] : m_tracks) n += static_cast<int>(track.ids.size());
  return n;
}

void ProxyStage::FindGripTurns(const ContactSet& contacts, const SceneQuery& scene) {
  // a grip: continuing contacts whose outlines reach into the same object's footprint
  struct Member {
    Vec2 from;
    Vec2 to;
    ContactId id;
  };
  std::map<ObjectId, std::vector<Member>> grips;
  m_gripTurn.clear();
  // a contact in a merge or split jumps with its outline: its centroid shows no motion of the
  // hand (its parents and children are the ones with more than one relative)
  std::unordered_map<ContactId, int> relatives;
  for (const Contact& contact : contacts.contacts) {
    if (contact.state == ContactState::kLifted) continue;
    for (const ContactId p : contact.parents) ++relatives[p];
    if (contact.parents.size() > 1) relatives[contact.id] += 2;
  }
  for (const Contact& contact : contacts.contacts) {
    if (contact.state != ContactState::kContinuing) continue;
    if (const auto r = relatives.find(contact.id); r != relatives.end() && r->second > 1) continue;
    const auto it = m_tracks.find(contact.id);
    const Contour& cur = contact.blob.contour;
    if (it == m_tracks.end() || it->second.contour.cols() == 0 || cur.cols() == 0) continue;
    ObjectId touched = kNoObject;
    for (Eigen::Index j = 0; j < cur.cols() && touched == kNoObject; ++j) {
      touched = scene.ObjectAt(cur.col(j));
    }
    if (touched == kNoObject) continue;
    grips[touched].push_back(
        {it->second.contour.rowwise().mean(), cur.rowwise().mean(), contact.id});
  }
  // the grip's turn: the rotation that best carries its contacts' centroids from the last frame
  // to this one (least squares about their means)
  for (const auto& [object, members] : grips) {
    if (members.size() < 2) continue;
    Vec2 meanFrom = Vec2::Zero(), meanTo = Vec2::Zero();
    for (const Member& m : members) {
      meanFrom += m.from;
      meanTo += m.to;
    }
    meanFrom /= static_cast<double>(members.size());
    meanTo /= static_cast<double>(members.size());
    double cross = 0.0, dot = 0.0;
    for (const Member& m : members) {
      const Vec2 a = m.from - meanFrom;
      const Vec2 b = m.to - meanTo;
      cross += a.x() * b.y() - a.y() * b.x();
      dot += a.dot(b);
    }
    if (cross == 0.0 && dot <= 0.0) continue;
    const double turn = std::atan2(cross, dot);
    for (const Member& m : members) m_gripTurn[m.id] = turn;
  }
}

void ProxyStage::Persistent(const ProxyParams& params, const ContactSet& contacts,
                            const SceneQuery& scene, ParticlePlan& plan) {
  if (params.algorithm != MatchAlgorithm::kReference) FindGripTurns(contacts, scene);
  // ids on the table this frame; a lifted entry for one of them is contradictory and ignored
  std::unordered_set<ContactId> current;
  for (const Contact& contact : contacts.contacts) {
    if (contact.state != ContactState::kLifted) current.insert(contact.id);
  }
  // merges and splits first: their contacts take over the particles of every contact they came
  // from, which are then no longer there to be lifted
  std::unordered_set<ContactId> handed;
  HandOver(params, contacts, scene, plan, handed);
  std::unordered_set<ContactId> seen;
  for (const Contact& contact : contacts.contacts) {
    if (contact.state != ContactState::kLifted && handed.count(contact.id) > 0) {
      if (!seen.insert(contact.id).second) ++m_stats.duplicateContacts;
      continue;
    }
    // one entry per id and frame: a repeated id is bad input, the first current entry wins
    const bool lifted = contact.state == ContactState::kLifted;
    if ((lifted && current.count(contact.id) > 0) || !seen.insert(contact.id).second) {
      ++m_stats.duplicateContacts;
      continue;
    }
    auto it = m_tracks.find(contact.id);
    switch (contact.state) {
      case ContactState::kLifted:
        // a lifted contact takes all its particles with it
        if (it != m_tracks.end()) {
          DeleteTrack(it->first, it->second, plan);
          m_tracks.erase(it);
        }
        break;
      case ContactState::kNew:
        // an id that is new again (tracker restart): its old particles go first
        if (it != m_tracks.end()) {
          ++m_stats.restartedNew;
          DeleteTrack(it->first, it->second, plan);
          m_tracks.erase(it);
        }
        Seed(params, contact, scene, plan);
        break;
      case ContactState::kContinuing:
        if (it == m_tracks.end()) {
          ++m_stats.unknownContinuing;
          Seed(params, contact, scene, plan);
        } else {
          Continue(params, contact, scene, it->second, plan);
        }
        break;
    }
  }
  // contacts that disappeared without being reported lifted are lifted now
  for (auto it = m_tracks.begin(); it != m_tracks.end();) {
    if (current.count(it->first) == 0) {
      ++m_stats.vanishedContacts;
      DeleteTrack(it->first, it->second, plan);
      it = m_tracks.erase(it);
    } else {
      ++it;
    }
  }
}

void ProxyStage::HandOver(const ProxyParams& params, const ContactSet& contacts,
                          const SceneQuery& scene, ParticlePlan& plan,
                          std::unordered_set<ContactId>& handled) {
  // each current contact (its first entry) and the last frame's contacts with particles it
  // names as parents; families join contacts that share a parent
  std::vector<const Contact*> targets;
  std::unordered_set<ContactId> listed;
  std::map<ContactId, std::vector<int>> childrenOf;  // parent id -> indices into targets
  for (const Contact& c : contacts.contacts) {
    if (c.state == ContactState::kLifted || !listed.insert(c.id).second) continue;
    bool any = false;
    for (const ContactId p : c.parents) {
      if (m_tracks.count(p) == 0) continue;
      auto& children = childrenOf[p];
      if (!children.empty() && children.back() == static_cast<int>(targets.size())) continue;
      children.push_back(static_cast<int>(targets.size()));
      any = true;
    }
    if (any) targets.push_back(&c);
  }
  if (childrenOf.empty()) return;
  // union-find over the targets: two that share a parent are one family
  std::vector<int> root(targets.size());
  for (size_t i = 0; i < root.size(); ++i) root[i] = static_cast<int>(i);
  auto find = [&](int i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (const auto& [parent, children] : childrenOf) {
    for (size_t k = 1; k < children.size(); ++k) root[find(children[k])] = find(children[0]);
  }
  std::map<int, std::pair<std::vector<ContactId>, std::vector<const Contact*>>> families;
  for (const auto& [parent, children] : childrenOf)
    families[find(children[0])].first.push_back(parent);
  for (size_t i = 0; i < targets.size(); ++i) {
    families[find(static_cast<int>(i))].second.push_back(targets[i]);
  }
  for (const auto& [key, family] : families) {
    const auto& [sources, members] = family;
    // one contact continuing itself alone is the ordinary case
    if (sources.size() == 1 && members.size() == 1 && members[0]->id == sources[0] &&
        members[0]->state == ContactState::kContinuing) {
      continue;
    }
    HandOverFamily(params, sources, members, scene, plan);
    for (const Contact* c : members) handled.insert(c->id);
    ++m_stats.handovers;
  }
}

void ProxyStage::HandOverFamily(const ProxyParams& params, const std::vector<ContactId>& sources,
                                const std::vector<const Contact*>& targets, const SceneQuery& scene,
                                ParticlePlan& plan) {
  // The paper's successor search, run from every source contour to every target contour: each
  // source point takes the target point whose window matches best over all targets, and each
  // target point takes the best-scoring source point that chose it as its predecessor. A merged
  // contact so inherits the particles of all its parents (the union of their contours matched to
  // its one), and the pieces of a split each take their parent's particles that fall on their
  // outlines. Each source contour is first moved on by its contact's last rigid motion (each
  // has its own, and the merged outline shows none of them), so that the sum of squared
  // distances sees the change of shape rather than the motion.
  std::vector<Track> from;
  std::vector<Contour> moved;
  from.reserve(sources.size());
  moved.reserve(sources.size());
  for (const ContactId id : sources) {
    auto it = m_tracks.find(id);
    from.push_back(std::move(it->second));
    m_tracks.erase(it);
    moved.push_back(Transformed(from.back().contour, from.back().motion));
  }
  const int window = std::clamp(params.window, 0, kMaxMatchWindow);
  struct Choice {
    int target = -1;
    int index = -1;
    double score = std::numeric_limits<double>::infinity();
  };
  std::vector<std::vector<Choice>> choice(from.size());
  auto fingerOf = [&](int i, int k) {
    return from[i].fingers.size() == from[i].ids.size() ? from[i].fingers[k] : sources[i];
  };
  // In a merge, a particle that lost its successor walks on only over points whose finger is its
  // own: points that its finger's whole outline (Track::ghosts, or the source's outline) passes
  // within half a spacing as near as any other's (where the fingers meet, either), or that no
  // whole outline passes near (the neck the camera fills between them). Elsewhere the point is
  // another finger's skin, and Continue would take it back the next frame. The successors the
  // search chose are not filtered: at a merge right after a split (outlines that flicker as they
  // touch) that deleted and created 10 particles of merge_grip at one camera seed, where the
  // outline's change requires 3. open[f][j]: whether finger f's particles may walk onto point j of
  // the one target.
  // each source's fingers' whole outlines, moved on one frame: its ghosts, or its own outline
  std::vector<std::vector<Track::Ghost>> whole(from.size());
  for (size_t i = 0; i < from.size(); ++i) {
    if (from[i].ghosts.empty()) {
      whole[i].push_back({sources[i], moved[i]});
    } else {
      for (const Track::Ghost& g : from[i].ghosts) {
        whole[i].push_back({g.finger, Transformed(g.outline, from[i].motion)});
      }
    }
  }
  std::map<ContactId, std::vector<bool>> open;
  if (from.size() > 1 && targets.size() == 1 && targets[0]->blob.contour.cols() > 0) {
    const Contour& cur = targets[0]->blob.contour;
    const int m = static_cast<int>(cur.cols());
    const double spacing = Perimeter(cur) / m;
    std::vector<const Track::Ghost*> outlines;
    for (const std::vector<Track::Ghost>& w : whole) {
      for (const Track::Ghost& g : w) {
        outlines.push_back(&g);
        open[g.finger].assign(static_cast<size_t>(m), false);
      }
    }
    std::vector<double> distance(outlines.size());
    for (int j = 0; j < m; ++j) {
      double best = std::numeric_limits<double>::infinity();
      for (size_t o = 0; o < outlines.size(); ++o) {
        distance[o] = DistanceToBoundary(outlines[o]->outline, cur.col(j));
        best = std::min(best, distance[o]);
      }
      for (size_t o = 0; o < outlines.size(); ++o) {
        if (best > 0.25 * spacing || distance[o] <= best + 0.5 * spacing)
          open[outlines[o]->finger][j] = true;
      }
    }
  }
  auto mayTake = [&](int i, int k, int j) {
    if (open.empty()) return true;
    const auto f = open.find(fingerOf(i, k));
    return f == open.end() || f->second[j];
  };
  for (size_t i = 0; i < from.size(); ++i) {
    choice[i].resize(static_cast<size_t>(from[i].contour.cols()));
    if (from[i].contour.cols() == 0) continue;
    for (size_t t = 0; t < targets.size(); ++t) {
      const Contour& cur = targets[t]->blob.contour;
      if (cur.cols() == 0) continue;
      const MatchResult r = MatchFast(moved[i], cur, window);
      for (size_t k = 0; k < choice[i].size(); ++k) {
        if (r.score[k] < choice[i][k].score) {
          choice[i][k] = {static_cast<int>(t), r.successor[k], r.score[k]};
        }
      }
    }
  }
  // predecessors: per target point, the (source, point) with the lowest score
  struct Pred {
    int source = -1;
    int point = -1;
    double score = std::numeric_limits<double>::infinity();
  };
  std::vector<std::vector<Pred>> pred(targets.size());
  for (size_t t = 0; t < targets.size(); ++t) {
    pred[t].resize(static_cast<size_t>(targets[t]->blob.contour.cols()));
  }
  for (size_t i = 0; i < from.size(); ++i) {
    for (size_t k = 0; k < choice[i].size(); ++k) {
      const Choice& c = choice[i][k];
      if (c.target < 0) continue;
      Pred& p = pred[c.target][c.index];
      if (c.score < p.score) p = {static_cast<int>(i), static_cast<int>(k), c.score};
    }
  }
  // A source point whose successor went to a better-scoring one moves to the nearest free point
  // next to it, on the side where it lies from the winner along its own contour: the contours
  // are sampled at independent phases and lengths, so several points of an outline that only
  // moved often choose one successor while its neighbour goes free, which would delete and
  // create a particle for nothing. A point moves to the nearest free point that way, never across
  // another outline's particle: an outline that shrank still deletes, one that grew still
  // creates.
  std::vector<std::tuple<double, int, int>> losers;  // score, source, point
  for (size_t i = 0; i < from.size(); ++i) {
    for (size_t k = 0; k < choice[i].size(); ++k) {
      const Choice& c = choice[i][k];
      if (c.target < 0) continue;
      const Pred& p = pred[c.target][c.index];
      if (p.source != static_cast<int>(i) || p.point != static_cast<int>(k)) {
        losers.emplace_back(c.score, static_cast<int>(i), static_cast<int>(k));
      }
    }
  }
  std::sort(losers.begin(), losers.end());
  for (const auto& [score, i, k] : losers) {
    const Choice& c = choice[i][k];
    std::vector<Pred>& line = pred[c.target];
    const int m = static_cast<int>(line.size());
    const Pred& winner = line[c.index];
    // which way along the target: the same way k lies from the winner along their contour
    int direction = 1;
    if (winner.source == i) {
      const int n = static_cast<int>(choice[i].size());
      direction = WrapIndex(k - winner.point, n) <= n / 2 ? 1 : -1;
    }
    for (int step = 1; step < m; ++step) {
      const int j = WrapIndex(c.index + direction * step, m);
      if (!mayTake(i, k, j)) break;  // another finger's skin: not across it
      if (line[j].source < 0) {
        line[j] = {i, k, score};
        break;
      }
      if (line[j].source != i) break;  // another outline's particle: not across it
    }
  }
  auto heightOf = [&](int i, int k) {
    const auto f = m_feedback.find(from[i].ids[k]);
    return f != m_feedback.end() ? f->second.baseHeight : from[i].baseHeights[k];
  };
  auto lastTarget = [&](int i, int k) -> Vec2 {
    return from[i].targets.cols() == from[i].contour.cols() ? Vec2(from[i].targets.col(k))
                                                            : Vec2(from[i].contour.col(k));
  };
  auto positionOf = [&](int i, int k) -> Vec2 {
    const auto f = m_feedback.find(from[i].ids[k]);
    return f != m_feedback.end() ? f->second.pos : lastTarget(i, k);
  };
  // A particle that presses an object keeps pressing it through the merge (issue 42): where the
  // merged outline is shorter than its parents' (the camera fills the neck where two fingers
  // meet), a finger loses points, and the particle that gives way should be one that presses
  // nothing. So a loser left without a point whose last target lies inside an object's footprint,
  // below its top, takes the next point along its own finger's outline, and that finger's
  // particles there move on by one point each, up to the first that presses nothing (or a free
  // point); that one gives way instead.
  auto presses = [&](int i, int k) {
    double top = 0.0;
    return scene.FootprintDepth(lastTarget(i, k), &top) > 0.0 && heightOf(i, k) < top;
  };
  {
    std::vector<std::vector<bool>> placed(from.size());
    for (size_t i = 0; i < from.size(); ++i) placed[i].assign(from[i].ids.size(), false);
    for (const std::vector<Pred>& line : pred) {
      for (const Pred& q : line) {
        if (q.source >= 0) placed[q.source][q.point] = true;
      }
    }
    for (const auto& [score, i, k] : losers) {
      if (placed[i][k] || !presses(i, k)) continue;
      const Choice& c = choice[i][k];
      std::vector<Pred>& line = pred[c.target];
      const int m = static_cast<int>(line.size());
      for (const int direction : {1, -1}) {
        std::vector<int> chain;
        bool room = false;
        for (int step = 1; step < m && !room; ++step) {
          const int j = WrapIndex(c.index + direction * step, m);
          if (!mayTake(i, k, j)) break;
          const Pred& q = line[j];
          if (q.source >= 0 && fingerOf(q.source, q.point) != fingerOf(i, k)) break;
          chain.push_back(j);
          room = q.source < 0 || !presses(q.source, q.point);
        }
        if (!room) continue;
        const Pred& last = line[chain.back()];
        if (last.source >= 0) placed[last.source][last.point] = false;
        for (size_t s = chain.size() - 1; s > 0; --s) line[chain[s]] = line[chain[s - 1]];
        line[chain.front()] = {i, k, score};
        placed[i][k] = true;
        break;
      }
    }
  }
  std::vector<std::vector<bool>> kept(from.size());
  for (size_t i = 0; i < from.size(); ++i) kept[i].assign(from[i].ids.size(), false);
  for (size_t t = 0; t < targets.size(); ++t) {
    const Contact& contact = *targets[t];
    const Contour& cur = contact.blob.contour;
    const int m = static_cast<int>(cur.cols());
    std::vector<int> has(m, -1);
    for (int j = 0; j < m; ++j) has[j] = pred[t][j].source >= 0 ? j : -1;
    Track track;
    track.contour = cur;
    track.targets = cur;
    // its motion goes on as that of the source most of its particles came from
    std::vector<int> votes(from.size(), 0);
    for (const Pred& q : pred[t]) {
      if (q.source >= 0) ++votes[q.source];
    }
    track.motion = from[std::max_element(votes.begin(), votes.end()) - votes.begin()].motion;
    // each finger's whole outline, as its source last saw it apart, moved on one frame
    for (size_t i = 0; i < from.size(); ++i) {
      if (votes[i] > 0) track.ghosts.insert(track.ghosts.end(), whole[i].begin(), whole[i].end());
    }
    // each point's finger: its particle's, or for a point without one, after a merge, the
    // finger's whose whole outline passes nearest
    std::vector<ContactId> labels;
    if (track.ghosts.size() >= 2) {
      labels.resize(m);
      for (int j = 0; j < m; ++j) {
        const Pred& q = pred[t][j];
        if (q.source >= 0) {
          labels[j] = fingerOf(q.source, q.point);
          continue;
        }
        double best = std::numeric_limits<double>::infinity();
        for (const Track::Ghost& g : track.ghosts) {
          const double d = DistanceToBoundary(g.outline, cur.col(j));
          if (d < best) {
            best = d;
            labels[j] = g.finger;
          }
        }
      }
    }
    track.ids.resize(m);
    track.baseHeights.resize(m);
    track.fingers.resize(m);
    // a target no source point chose starts over: seeded as a new contact is
    if (m > 0 && std::none_of(has.begin(), has.end(), [](int h) { return h >= 0; })) {
      Seed(params, contact, scene, plan);
      continue;
    }
    for (int j = 0; j < m; ++j) {
      PlannedParticle p;
      p.contact = contact.id;
      p.index = j;
      p.target = cur.col(j);
      const Pred& q = pred[t][j];
      if (q.source >= 0) {
        p.id = from[q.source].ids[q.point];
        p.action = ParticleAction::kReused;
        p.baseHeight = heightOf(q.source, q.point);
        // its last target moved on with its contact, on this outline near its point
        if (params.subsample) {
          p.target = SubsampleTarget(cur, j, lastTarget(q.source, q.point), from[q.source].motion);
        }
        kept[q.source][q.point] = true;
        track.fingers[j] = fingerOf(q.source, q.point);
      } else {
        // created where the nearest handed-over neighbour on this outline sits, at its height:
        // beside a gripped face, never on the object's top. After a merge, the point is the
        // finger's whose whole outline passes nearest, and its neighbour is one of that
        // finger's where there is one
        const Pred& nb = pred[t][NearestKept(has, j, labels)];
        p.id = m_ids.Next();
        p.action = ParticleAction::kCreated;
        p.start = positionOf(nb.source, nb.point);
        p.baseHeight = heightOf(nb.source, nb.point);
        track.fingers[j] = labels.empty() ? fingerOf(nb.source, nb.point) : labels[j];
        if (params.placement == Placement::kGround && p.baseHeight <= 0.0) {
          p.start = scene.NearestOutside(p.start);
          p.baseHeight = 0.0;
        }
      }
      track.ids[j] = p.id;
      track.baseHeights[j] = p.baseHeight;
      track.targets.col(j) = p.target;
      plan.particles.push_back(p);
    }
    KeepHeldGhosts(track);
    m_tracks[contact.id] = std::move(track);
  }
  // the source particles no target point took
  int sourcePoints = 0, targetPoints = 0;
  for (const Track& track : from) sourcePoints += static_cast<int>(track.ids.size());
  for (const Contact* c : targets) targetPoints += static_cast<int>(c->blob.contour.cols());
  const size_t before = plan.particles.size();
  for (size_t i = 0; i < from.size(); ++i) {
    for (size_t k = 0; k < from[i].ids.size(); ++k) {
      if (kept[i][k]) continue;
      PlannedParticle p;
      p.id = from[i].ids[k];
      p.contact = sources[i];
      p.index = -1;
      p.action = ParticleAction::kDeleted;
      p.target = from[i].contour.col(static_cast<Eigen::Index>(k));
      p.baseHeight = heightOf(static_cast<int>(i), static_cast<int>(k));
      plan.particles.push_back(p);
    }
  }
  const int deleted = static_cast<int>(plan.particles.size() - before);
  const int created = targetPoints - (sourcePoints - deleted);
  m_stats.handoverCreated += created;
  m_stats.handoverDeleted += deleted;
  m_stats.handoverKept += sourcePoints - deleted;
  m_stats.handoverExcessMax =
      std::max(m_stats.handoverExcessMax, created - std::max(0, targetPoints - sourcePoints));
}

void ProxyStage::Seed(const ProxyParams& params, const Contact& contact, const SceneQuery& scene,
                      ParticlePlan& plan) {
  const Contour& cur = contact.blob.contour;
  const int m = static_cast<int>(cur.cols());
  Track track;
  track.contour = cur;
  track.ids.resize(m);
  track.baseHeights.resize(m);

  // ground mode keeps a contact on the table unless its deepest contour point lies deeper than
  // the penetration limit inside a footprint; raycast mode (and such a deep contact) places every
  // point on the highest surface under it
  const bool measured = Measures(params, contact.blob);
  // a contact without heights cannot be measured: auto and measured raycast it
  bool raycast = params.placement != Placement::kGround && !measured;
  if (!raycast && !measured) {
    double deepest = 0.0;
    for (int j = 0; j < m; ++j) {
      double top = 0.0;
      deepest = std::max(deepest, scene.FootprintDepth(cur.col(j), &top));
    }
    raycast = deepest > params.penetrationLimit;
  }

  for (int j = 0; j < m; ++j) {
    PlannedParticle p;
    p.id = m_ids.Next();
    p.contact = contact.id;
    p.index = j;
    p.action = ParticleAction::kCreated;
    p.target = cur.col(j);
    if (measured) {
      // at the measured height; a point measured inside an object's volume (below its top,
      // within its footprint) starts where it is freed by the shorter move: up onto the top or
      // out through the side
      const double under = MeasuredUnderside(params, contact.blob, j, m_scratch);
      double top = 0.0;
      const double depth = scene.FootprintDepth(p.target, &top);
      if (depth <= 0.0 || under >= top) {
        p.start = p.target;
        p.baseHeight = under;
      } else if (top - under <= depth) {
        p.start = p.target;
        p.baseHeight = top;
      } else {
        p.start = scene.NearestOutside(p.target);
        p.baseHeight = under;
      }
    } else if (raycast) {
      p.start = p.target;
      p.baseHeight = scene.TopHeightAt(p.target);
    } else {
      p.start = scene.NearestOutside(p.target);
      p.baseHeight = 0.0;
    }
    track.ids[j] = p.id;
    track.baseHeights[j] = p.baseHeight;
    plan.particles.push_back(p);
  }
  track.fingers.assign(static_cast<size_t>(m), contact.id);
  m_tracks[contact.id] = std::move(track);
}

void ProxyStage::Continue(const ProxyParams& params, const Contact& contact,
                          const SceneQuery& scene, Track& track, ParticlePlan& plan) {
  const Contour& prev = track.contour;
  const int n = static_cast<int>(prev.cols());
  // nothing to match from: the contact starts over as if new
  if (n == 0) {
    Seed(params, contact, scene, plan);
    return;
  }

  // Motion compensation (fast and windowed searches): the previous contour moved by the
  // contact's rigid motion, and the current one resampled in phase with it, keeping its point
  // count within the hysteresis. A rigid contact then matches point for point, and the sum of
  // squared distances sees only what changed shape. The reference search matches the contours as
  // sensed, as the paper does.
  const bool compensate = params.algorithm != MatchAlgorithm::kReference;
  Contour cur = contact.blob.contour;
  Contour prevMatched;
  ContourMotion contourMotion;
  std::vector<Pose2> pointMotion;  // per previous point, when it holds several fingers
  if (compensate && cur.cols() > 0) {
    contourMotion = EstimateMotion(prev, cur);
    // a round contact shows no turn of its own: in a grip it turns with the grip, about its
    // centroid, so its particles keep their places on the face it presses
    const auto grip = m_gripTurn.find(contact.id);
    if (!contourMotion.turnObservable && grip != m_gripTurn.end()) {
      const Vec2 centre = prev.rowwise().mean();
      const Vec2 movedCentre = contourMotion.motion.Apply(centre);
      contourMotion.motion.angle = grip->second;
      contourMotion.motion.pos = movedCentre - Rotate(centre, grip->second);
    }
    prevMatched = Transformed(prev, contourMotion.motion);
    // a merged contact's fingers each move their own way: a finger that pushes on while the
    // others hold still keeps its particles, and those of the others that went inside the
    // outline (where the fingers now touch) are the ones that go
    pointMotion = FingerMotions(prev, cur, track.fingers, contourMotion.motion);
    for (size_t k = 0; k < pointMotion.size(); ++k) {
      prevMatched.col(static_cast<Eigen::Index>(k)) = pointMotion[k].Apply(prev.col(k));
    }
    const int sensed = static_cast<int>(cur.cols());
    const int count = std::abs(sensed - n) <= params.countHysteresis ? n : sensed;
    cur = ResampleInPhase(cur, prevMatched, count);
  }
  const int m = static_cast<int>(cur.cols());

  // successors of the previous points, predecessors of the current ones
  const MatchResult match = m > 0 ? MatchSuccessors(params, compensate ? prevMatched : prev, cur,
                                                    &m_stats.windowedFallbacks)
                                  : MatchResult{std::vector<int>(n, -1), {}, 0};
  std::vector<int> pred = m > 0 ? Predecessors(match, m) : std::vector<int>{};

  auto fingerOf = [&](int k) {
    return track.fingers.size() == static_cast<size_t>(n) ? track.fingers[k] : contact.id;
  };
  // A merged contact's current points belong to the finger whose moved points lie nearest. A
  // particle follows its own finger's skin: matched to another finger's point (where the fingers
  // meet, one finger's outline goes inside as the other's moves on), it moves to a free point of
  // its own finger next to its match, or is deleted; a point left without a particle takes one
  // created beside its own finger's nearest (docs/proxies.md, "After the merge").
  // A point is its finger's whose moved points lie nearest; but where a finger moves on into the
  // others (a pusher between two pinching fingertips), the points of the others it has just
  // covered lie within one frame's move of its new points, nearer than its own moved points, and
  // a point once labelled another's stays so: the pusher's tip creeps to the fingertips. So each
  // finger's whole outline as it was seen apart (Track::ghosts) moves on with the finger too, and
  // a point goes to the finger whose whole outline passes nearest. A whole outline is kept only
  // while it describes its finger: while the points of its finger lie within half the outline's
  // point spacing of it (the median). The parts of a real hand change shape as they move, and
  // their outlines of a few frames before soon do not.
  std::vector<ContactId> labels;
  if (!pointMotion.empty() && m > 0) {
    labels.resize(m);
    for (Track::Ghost& g : track.ghosts) {
      Pose2 own = contourMotion.motion;
      for (int k = 0; k < n; ++k) {
        if (fingerOf(k) == g.finger) {
          own = pointMotion[k];
          break;
        }
      }
      g.outline = Transformed(g.outline, own);
    }
    for (int j = 0; j < m; ++j) {
      int nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (int k = 0; k < n; ++k) {
        const double d = (prevMatched.col(k) - cur.col(j)).squaredNorm();
        if (d < best) {
          best = d;
          nearest = k;
        }
      }
      labels[j] = fingerOf(nearest);
    }
    const double spacing = Perimeter(cur) / m;
    if (!track.ghosts.empty()) {
      std::vector<double> off;
      std::erase_if(track.ghosts, [&](Track::Ghost& g) {
        // the finger's fitted motion leaves a little error every frame; laid back onto the
        // finger's points it does not add up
        std::vector<int> members;
        for (int j = 0; j < m; ++j) {
          if (labels[j] == g.finger) members.push_back(j);
        }
        if (members.empty()) return true;
        Contour piece(2, static_cast<Eigen::Index>(members.size()));
        for (size_t i = 0; i < members.size(); ++i) piece.col(i) = cur.col(members[i]);
        const Vec2 onto = EstimatePieceMotion(piece, g.outline, Pose2{}).pos;
        g.outline.colwise() -= onto;
        off.clear();
        for (const int j : members) off.push_back(DistanceToBoundary(g.outline, cur.col(j)));
        auto mid = off.begin() + static_cast<std::ptrdiff_t>(off.size() / 2);
        std::nth_element(off.begin(), mid, off.end());
        return *mid > 0.5 * spacing;
      });
    }
    if (track.ghosts.size() >= 2) {
      for (int j = 0; j < m; ++j) {
        // a finger whose whole outline no longer describes it keeps its points, and so does
        // one whose outline passes within half a spacing as near as another's (where two
        // fingers' outlines meet)
        double ownDistance = std::numeric_limits<double>::infinity();
        double best = std::numeric_limits<double>::infinity();
        ContactId nearest = kNoId;
        // A point starts as its particle's finger where that finger still has its whole
        // outline: where two outlines meet, the nearest moved point is often the other's, and
        // the particle, pressing an object with its own finger's skin, would be deleted
        if (pred[j] >= 0) {
          const ContactId held = fingerOf(pred[j]);
          for (const Track::Ghost& g : track.ghosts) {
            if (g.finger == held) labels[j] = held;
          }
        }
        for (const Track::Ghost& g : track.ghosts) {
          const double d = DistanceToBoundary(g.outline, cur.col(j));
          if (g.finger == labels[j]) ownDistance = d;
          if (d < best) {
            best = d;
            nearest = g.finger;
          }
        }
        if (best <= 0.25 * spacing && best + 0.5 * spacing < ownDistance) labels[j] = nearest;
      }
    }
    std::vector<int> own = pred;
    std::vector<bool> placed(n, false);
    for (int j = 0; j < m; ++j) {
      if (own[j] >= 0 && fingerOf(own[j]) != labels[j]) own[j] = -1;
      if (own[j] >= 0) placed[own[j]] = true;
    }
    // a previous point left without a point of its own finger (matched to another finger's, or
    // its match taken by a better one) moves to the nearest free point of its finger next to
    // its match: the outlines are sampled at independent phases where they meet, as in a
    // hand-over
    for (int k = 0; k < n; ++k) {
      const int j = match.successor[k];
      if (placed[k] || j < 0) continue;
      for (int d = 0; d <= kSubsampleReach; ++d) {
        const int before = WrapIndex(j - d, m), after = WrapIndex(j + d, m);
        const int free = own[before] < 0 && labels[before] == fingerOf(k) ? before
                         : own[after] < 0 && labels[after] == fingerOf(k) ? after
                                                                          : -1;
        if (free >= 0) {
          own[free] = k;
          break;
        }
      }
    }
    if (std::any_of(own.begin(), own.end(), [](int k) { return k >= 0; })) pred = std::move(own);
  }

  // the particle's known base height and position: feedback first, its own record otherwise
  auto heightOf = [&](int k) {
    const auto f = m_feedback.find(track.ids[k]);
    return f != m_feedback.end() ? f->second.baseHeight : track.baseHeights[k];
  };

  // the last target of previous point k's particle (its contour point when none was stored)
  auto lastTarget = [&](int k) -> Vec2 {
    return track.targets.cols() == n ? Vec2(track.targets.col(k)) : Vec2(prev.col(k));
  };
  auto positionOf = [&](int k) -> Vec2 {
    const auto f = m_feedback.find(track.ids[k]);
    return f != m_feedback.end() ? f->second.pos : lastTarget(k);
  };
  const Pose2 motion = !params.subsample || m == 0 ? Pose2{}
                       : compensate                ? contourMotion.motion
                                                   : RigidMotion(prev, cur);

  std::vector<ParticleId> ids(m, kNoId);
  std::vector<double> heights(m, 0.0);
  std::vector<ContactId> fingers(m, contact.id);
  std::vector<bool> reused(m, false);
  Contour targets(2, m);
  const size_t first = plan.particles.size();
  for (int j = 0; j < m; ++j) {
    PlannedParticle p;
    p.contact = contact.id;
    p.index = j;
    p.target = cur.col(j);
    if (pred[j] >= 0) {
      // reuse: the predecessor's particle now follows this point
      p.id = track.ids[pred[j]];
      p.action = ParticleAction::kReused;
      reused[j] = true;
      if (params.subsample) {
        p.target = SubsampleTarget(cur, j, lastTarget(pred[j]), motion, labels, fingerOf(pred[j]));
      }
      p.baseHeight = heightOf(pred[j]);
      fingers[j] = fingerOf(pred[j]);
    } else {
      // create: where the nearest kept neighbour's particle sits, at its height
      const int nb = NearestKept(pred, j, labels);
      assert(nb >= 0 && "a continuing contact keeps at least one point");
      p.id = m_ids.Next();
      p.action = ParticleAction::kCreated;
      p.start = positionOf(pred[nb]);
      p.baseHeight = heightOf(pred[nb]);
      fingers[j] = labels.empty() ? fingerOf(pred[nb]) : labels[j];
      // in ground mode a particle on the table never starts inside a footprint
      if (params.placement == Placement::kGround && p.baseHeight <= 0.0) {
        p.start = scene.NearestOutside(p.start);
        p.baseHeight = 0.0;
      }
    }
    ids[j] = p.id;
    heights[j] = p.baseHeight;
    targets.col(j) = p.target;
    plan.particles.push_back(p);
  }

  // the particles keep their targets; their indices move back under them when they crept
  const int creep = params.subsample ? IndexCreep(cur, targets, reused) : 0;
  if (creep != 0) {
    std::vector<ParticleId> shiftedIds(m);
    std::vector<double> shiftedHeights(m);
    std::vector<ContactId> shiftedFingers(m);
    Contour shiftedTargets(2, m);
    for (int j = 0; j < m; ++j) {
      const int to = WrapIndex(j + creep, m);
      shiftedIds[to] = ids[j];
      shiftedHeights[to] = heights[j];
      shiftedFingers[to] = fingers[j];
      shiftedTargets.col(to) = targets.col(j);
      plan.particles[first + j].index = to;
    }
    ids = std::move(shiftedIds);
    heights = std::move(shiftedHeights);
    fingers = std::move(shiftedFingers);
    targets = std::move(shiftedTargets);
    ++m_stats.indexShifts;
  }

  // delete: previous points that no current point took as predecessor
  std::vector<bool> kept(n, false);
  for (const int k : pred) {
    if (k >= 0) kept[k] = true;
  }
  for (int k = 0; k < n; ++k) {
    if (kept[k]) continue;
    PlannedParticle p;
    p.id = track.ids[k];
    p.contact = contact.id;
    p.index = -1;
    p.action = ParticleAction::kDeleted;
    p.target = prev.col(k);
    p.baseHeight = heightOf(k);
    plan.particles.push_back(p);
  }

  track.contour = cur;
  track.ids = std::move(ids);
  track.baseHeights = std::move(heights);
  track.fingers = std::move(fingers);
  track.targets = std::move(targets);
  track.motion = compensate ? contourMotion.motion : motion;
  KeepHeldGhosts(track);
}

void ProxyStage::DeleteTrack(ContactId id, const Track& track, ParticlePlan& plan) {
  for (size_t k = 0; k < track.ids.size(); ++k) {
    PlannedParticle p;
    p.id = track.ids[k];
    p.contact = id;
    p.index = -1;
    p.action = ParticleAction::kDeleted;
    p.target = track.contour.col(static_cast<Eigen::Index>(k));
    p.baseHeight = track.baseHeights[k];
    plan.particles.push_back(p);
  }
}

std::string CheckPlan(const ParticlePlan& plan, std::span<const ParticleId> aliveBefore) {
  const std::set<ParticleId> alive(aliveBefore.begin(), aliveBefore.end());
  std::set<ParticleId> seen;
  int reused = 0, created = 0, deleted = 0;
  for (const PlannedParticle& p : plan.particles) {
    const std::string who = "particle " + std::to_string(p.id);
    if (p.id == kNoId) return "a particle has no id";
    if (!seen.insert(p.id).second) return who + " appears twice";
    const bool wasAlive = alive.count(p.id) > 0;
    switch (p.action) {
      case ParticleAction::kReused:
        if (!wasAlive) return who + " is reused but was not alive";
        ++reused;
        break;
      case ParticleAction::kCreated:
        if (wasAlive) return who + " is created but was alive";
        ++created;
        break;
      case ParticleAction::kDeleted:
        if (!wasAlive) return who + " is deleted but was not alive";
        ++deleted;
        break;
    }
  }
  if (reused != plan.reused || created != plan.created || deleted != plan.deleted) {
    return "counts " + std::to_string(plan.reused) + "/" + std::to_string(plan.created) + "/" +
           std::to_string(plan.deleted) + " differ from the entries " + std::to_string(reused) +
           "/" + std::to_string(created) + "/" + std::to_string(deleted);
  }
  // every particle alive before and not in the plan would be silently kept
  for (const ParticleId id : alive) {
    if (seen.count(id) == 0) return "particle " + std::to_string(id) + " alive but not planned";
  }
  return "";
}

}  // namespace pg
