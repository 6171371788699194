// The proxies stage: turns each frame's contact set into a particle plan. In persistent mode
// (ITS 2009) every contour point of every contact owns one particle that lives as long as the point
// has a predecessor; in instant mode (UIST 2008) every particle lives one frame.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/proxies/instant_proxies.h"
#include "proxygrasp/proxies/matching.h"
#include "proxygrasp/proxies/types.h"
#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tracking/types.h"

#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace pg {

/// Counts of unusual input the stage survived, since the last Reset().
struct ProxyStageStats {
  int duplicateContacts = 0;  ///< repeated ids in one set (the first current entry wins)
  int unknownContinuing = 0;  ///< continuing contacts with no state, seeded as new
  int restartedNew = 0;       ///< new contacts whose id already had state (old particles deleted)
  int vanishedContacts = 0;   ///< contacts with state missing from the set (particles deleted)
  int windowedFallbacks = 0;  ///< points the windowed search handed to the full search
  int indexShifts = 0;      ///< contours whose indices crept off their targets and were moved back
  int missingImage = 0;     ///< instant-mode frames without a table image (no particles)
  int handovers = 0;        ///< merges and splits whose particles were handed over
  int handoverCreated = 0;  ///< particles created at hand-overs
  int handoverDeleted = 0;  ///< particles deleted at hand-overs
  int handoverKept = 0;     ///< parents' particles that went on with a child at hand-overs
  /// The most particles a hand-over created beyond what its change of outline requires:
  /// created - max(0, M - N), M the children's and N the parents' contour points (equal to
  /// deleted - max(0, N - M)). docs/proxies.md, "Merges and splits".
  int handoverExcessMax = 0;
};

/// The successors of a contact's previous contour points on its current contour, by the search
/// `params.algorithm` names (window `params.window`; the windowed search with
/// `params.search_radius` and `params.fallback_score`), as the stage matches. Points the windowed
/// search handed to the exact search are added to `*fallbacks` when it is given.
MatchResult MatchSuccessors(const ProxyParams& params, const Contour& prev, const Contour& cur,
                            int* fallbacks = nullptr);

/// The proxies stage and its state across frames.
class ProxyStage {
 public:
  /// A stage with these parameters.
  explicit ProxyStage(const ProxyParams& params = ProxyParams()) : m_params(params) {}

  /// Changes the parameters between frames (every proxies parameter applies live, the mode
  /// included). A value out of its described range is an Error naming it, and nothing changes.
  MaybeError SetParams(const ProxyParams& params);
  const ProxyParams& params() const { return m_params; }

  /// One frame: the plan for every particle. feedback holds where the physics put the particles
  /// of the last plan; image is the table image (needed in instant mode, may be null otherwise).
  ParticlePlan Step(const ContactSet& contacts, const SceneQuery& scene,
                    std::span<const ParticleFeedback> feedback, const TableImage* image);

  /// Forgets every contact and particle (ids keep counting up: they are never reused).
  void Reset();

  /// Number of particles alive after the last Step.
  int LiveCount() const;
  /// Unusual input seen since the last Reset.
  const ProxyStageStats& Stats() const { return m_stats; }

 private:
  // what the stage remembers of a contact between frames
  struct Track {
    Contour contour;                  // last contour, cm
    std::vector<ParticleId> ids;      // particle of each contour point
    std::vector<double> baseHeights;  // last known base height of each point's particle, cm
    Contour targets;                  // last target of each point's particle (subsample), cm
    Pose2 motion;                     // the contact's last rigid motion, from the contour before
    // the contact each point's particle was first created for: its finger. A merged contact
    // holds several, each moving its own way (empty: every point is the contact's own)
    std::vector<ContactId> fingers;
    // A merged contact's fingers as they were seen apart: each one's last whole outline before
    // the merge, moved on by that finger's own motion every frame. A point of the outline
    // belongs to the finger whose whole outline passes nearest (empty: one finger)
    struct Ghost {
      ContactId finger = kNoId;
      Contour outline;  // cm
    };
    std::vector<Ghost> ghosts;
  };

  void Persistent(const ProxyParams& params, const ContactSet& contacts, const SceneQuery& scene,
                  ParticlePlan& plan);
  void Seed(const ProxyParams& params, const Contact& contact, const SceneQuery& scene,
            ParticlePlan& plan);
  void Continue(const ProxyParams& params, const Contact& contact, const SceneQuery& scene,
                Track& track, ParticlePlan& plan);
  void DeleteTrack(ContactId id, const Track& track, ParticlePlan& plan);
  // merges and splits (Contact::parents): the contacts of this frame that take over particles of
  // other contacts of the last frame; handed over, and their ids added to `handled`
  void HandOver(const ProxyParams& params, const ContactSet& contacts, const SceneQuery& scene,
                ParticlePlan& plan, std::unordered_set<ContactId>& handled);
  void HandOverFamily(const ProxyParams& params, const std::vector<ContactId>& sources,
                      const std::vector<const Contact*>& targets, const SceneQuery& scene,
                      ParticlePlan& plan);
  void FindGripTurns(const ContactSet& contacts, const SceneQuery& scene);
  // measured placement: each planned particle of a contact with heights gets its smoothed
  // measured underside (PlannedParticle::measured)
  void MeasureHeights(const ProxyParams& params, const ContactSet& contacts, ParticlePlan& plan);

  ProxyParams m_params;
  std::map<ContactId, Track> m_tracks;  // ordered: plans come out in the same order every run
  std::unordered_map<ParticleId, ParticleFeedback> m_feedback;  // this frame's feedback by id
  std::unordered_map<ContactId, double>
      m_gripTurn;  // this frame's turn of each contact's grip, rad
  std::unordered_map<ParticleId, double> m_measured;  // each particle's filtered height, cm
  double m_measuredTime = -1.0;  // time of the last frame measured, s (< 0: none yet)
  std::vector<double> m_scratch;
  InstantProxies m_instant;
  IdCounter m_ids;
  ProxyMode m_lastMode = ProxyMode::kPersistent;
  ProxyStageStats m_stats;
};

/// Checks a plan's invariants: unique ids, counts that match the entries, created ids not alive
/// before, reused and deleted ids alive before. alive is the set of ids alive before the plan;
/// returns "" when the plan is sound, otherwise what is wrong.
std::string CheckPlan(const ParticlePlan& plan, std::span<const ParticleId> aliveBefore);

}  // namespace pg
