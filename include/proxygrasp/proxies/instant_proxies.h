// Instant mode: the per-frame particle proxies of Wilson et al., UIST 2008 (the PARTICLE PROXIES
// section of the ITS 2009 paper), kept as a baseline. Every frame a Sobel image of the contact
// image is computed, a particle is placed at every pixel above a threshold (subsampled to a grid),
// its motion comes from optical flow, and all of last frame's particles are destroyed.
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/proxies/types.h"
#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tracking/types.h"

#include <opencv2/core.hpp>

#include <vector>

namespace pg {

/// One edge pixel chosen for a particle.
struct EdgePixel {
  cv::Point pixel;         ///< pixel (u, v) of the table image
  Vec2 pos;                ///< its centre on the table, cm
  double magnitude = 0.0;  ///< Sobel gradient magnitude, grey levels per pixel
};

/// The pixels of a table image whose Sobel gradient magnitude (the 3x3 Sobel scaled by 1/8, so a
/// ramp of g grey levels per pixel reads g) exceeds threshold, thinned to one per grid cell of
/// `spacing` cm: the strongest pixel of each cell (the first in raster order on ties).
std::vector<EdgePixel> EdgePixels(const TableImage& image, double threshold, double spacing);

/// Motion of each point from the previous image to the current one, cm: pyramidal Lucas-Kanade
/// tracks each point from the current image back to the previous one, and the motion is the
/// reverse of that. Points that cannot be tracked get zero motion. window is the LK window, px.
std::vector<Vec2> ImageMotion(const TableImage& previous, const TableImage& current,
                              const std::vector<EdgePixel>& points, int window);

/// The instant-mode particles: alive for one frame each.
class InstantProxies {
 public:
  /// Deletes every particle of the last frame and creates this frame's from the image. Each
  /// particle starts at its pixel (raycast height, or on the table outside every footprint in
  /// ground mode) and targets start + optical-flow motion. Each is tagged with the nearest
  /// current contact's id and contour index when one lies within 2 spacings, kNoId otherwise.
  void Update(const ProxyParams& params, const ContactSet& contacts, const SceneQuery& scene,
              const TableImage& image, IdCounter& ids, ParticlePlan& plan);

  /// Deletes every particle of the last frame (and forgets the last image).
  void DeleteAll(ParticlePlan& plan);

  /// Forgets particles and image without planning deletions.
  void Reset();

  /// Particles alive after the last Update.
  int LiveCount() const { return static_cast<int>(m_live.size()); }

 private:
  struct Live {
    ParticleId id = kNoId;
    ContactId contact = kNoId;
    Vec2 target = Vec2::Zero();
    double baseHeight = 0.0;
  };
  // appends a deletion to plan for every live particle
  void PlanDeletions(ParticlePlan& plan) const;

  std::vector<Live> m_live;
  TableImage m_previous;  // last frame's image (its own copy), empty before the first
};

}  // namespace pg
