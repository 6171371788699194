// What the proxies stage takes and hands on: its parameters, the scene query it asks the physics
// (answered from the previous frame), the particle feedback from the physics, and the particle
// plan.
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/core/params.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace pg {

/// Persistent particle proxies (ITS 2009) or the per-frame baseline of Wilson et al. (UIST 2008).
enum class ProxyMode { kPersistent, kInstant };
inline constexpr const char* kProxyModeNames[] = {"persistent", "instant"};

/// How successors are searched: the paper's exhaustive search on the contours as sensed
/// (reference), or on the previous contour moved by the contact's rigid motion and the current one
/// resampled in phase with it, by exact running sums (fast) or in a predicted window (windowed).
enum class MatchAlgorithm { kReference, kFast, kWindowed };
inline constexpr const char* kMatchAlgorithmNames[] = {"reference", "fast", "windowed"};

/// Where new particles go: by raycast onto the highest surface, always on the table, at the height
/// the depth camera measured (issue 44), or measured where the contact has heights and by raycast
/// where it has none (auto).
enum class Placement { kRaycast, kGround, kMeasured, kAuto };
inline constexpr const char* kPlacementNames[] = {"raycast", "ground", "measured", "auto"};

/// Whether a placement takes a contact's heights where it has them (measured and auto).
inline bool MeasuresHeights(Placement p) {
  return p == Placement::kMeasured || p == Placement::kAuto;
}

/// Parameters of the proxies stage. Section [proxies] of a level.
struct ProxyParams {
  ProxyMode mode = ProxyMode::kPersistent;
  MatchAlgorithm algorithm = MatchAlgorithm::kWindowed;
  int window = 8;              ///< n: the window sum runs over i = -n/2..n/2 around each match
                               ///< (integer halves: an odd n sums as n - 1 does), points
  int countHysteresis = 1;     ///< fast and windowed: a continuing contact keeps its point
                               ///< count while sensing's differs by at most this, points
  int searchRadius = 12;       ///< w, half-width of the windowed search, points
  bool subsample = true;       ///< refine reused targets between contour samples (parabola
                               ///< through the window scores of the successor's neighbours)
  double fallbackScore = 0.5;  ///< windowed search falls back to the full search where its
                               ///< best exceeds a lower bound on the exact score by more than
                               ///< this per window term, cm^2
  Placement placement = Placement::kAuto;
  double heightOffset = 0.8;       ///< measured: a contour point's height (the top of what the
                                   ///< depth camera sees near the outline) less this is the
                                   ///< underside of the finger there, cm
  int heightSpan = 2;              ///< measured: a particle's height is the median over the
                                   ///< contour points this many either side of its own, points
  double heightSmoothing = 0.015;  ///< measured: time constant of the per-particle filter that
                                   ///< follows the measured height, s (0: none)
  double penetrationLimit = 1.5;   ///< ground mode: a new contact whose deepest contour point
                                   ///< lies deeper than this inside an object's footprint goes
                                   ///< on its top (by raycast) instead of the table, cm
  double instantThreshold = 40.0;  ///< instant mode: Sobel magnitude that makes a particle, grey/px
  double instantSpacing = 0.3;     ///< instant mode: spacing of the subsampled particles, cm
  int instantFlowWindow = 21;      ///< instant mode: Lucas-Kanade optical flow window, pixels
};

/// The scene as the proxies stage sees it (answered by the physics from the previous frame).
class SceneQuery {
 public:
  virtual ~SceneQuery() = default;
  /// Height of the top surface of the highest object whose footprint holds p, or 0 (the table), cm.
  virtual double TopHeightAt(const Vec2& p) const = 0;
  /// How deep p lies inside the footprint of the object it is in (the highest), or <= 0 when in
  /// none; topHeight receives that object's top height (0 when in none). cm.
  virtual double FootprintDepth(const Vec2& p, double* topHeight) const = 0;
  /// The nearest point to p that lies outside every object's footprint (p itself when outside).
  virtual Vec2 NearestOutside(const Vec2& p) const = 0;
  /// The highest object whose footprint holds p, or kNoObject.
  virtual ObjectId ObjectAt(const Vec2& p) const = 0;
};

/// Where a particle really is after the last physics step, fed back to the proxies stage.
struct ParticleFeedback {
  ParticleId id = kNoId;
  Vec2 pos = Vec2::Zero();  ///< base body position, cm
  double baseHeight = 0.0;  ///< height of the surface the stack rests on, cm
};

/// What happens to a particle this frame.
enum class ParticleAction { kReused, kCreated, kDeleted };
inline constexpr const char* kParticleActionNames[] = {"reused", "created", "deleted"};

/// One particle in the plan.
struct PlannedParticle {
  ParticleId id = kNoId;
  ContactId contact = kNoId;
  int index = -1;  ///< contour point it follows this frame (-1 when deleted): of the sensed
                   ///< contour, or with the fast and windowed searches of a continuing contact,
                   ///< of that contour resampled in phase with the last frame's (its count
                   ///< within count_hysteresis of the sensed count)
  ParticleAction action = ParticleAction::kReused;
  Vec2 target = Vec2::Zero();  ///< where kinematic control drives it by the frame's end, cm
  Vec2 start = Vec2::Zero();   ///< created: where it is placed; otherwise unused, cm
  double baseHeight = 0.0;     ///< created: height it rests at; reused: unchanged, cm
  /// measured placement (a contact with heights): the underside of the finger at the particle,
  /// measured and smoothed, cm; NaN when not measured. The physics rests the stack on the
  /// surface below it or lets it hover at this height (docs/physics.md, "Measured heights")
  double measured = std::numeric_limits<double>::quiet_NaN();
};

/// The output of the proxies stage for one frame; the physics applies it.
struct ParticlePlan {
  int64_t frame = 0;
  std::vector<PlannedParticle> particles;
  int reused = 0;
  int created = 0;
  int deleted = 0;
};

void Describe(ProxyParams& p, ParamVisitor& v);

}  // namespace pg
