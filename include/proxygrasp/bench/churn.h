// Particle churn: how many particles a contact creates and deletes while it moves over an empty
// table, measured through the whole pipeline (synthetic camera with its noise, sensing, tracking,
// proxies, physics). Persistence exists so that a particle keeps its state (pressed against a
// side, resting on a top) while its contact moves: a rigid contact should keep its particles after
// its first frame. Shape change is what creation and deletion are for.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/level/params.h"
#include "proxygrasp/sensing/types.h"

#include <string>

namespace pg {

/// One churn scene: a contact that translates, turns and grows at constant rates.
struct ChurnScene {
  std::string name;       ///< for tables and messages
  ContactShape shape;     ///< its kind and size; its pose is the start pose
  double speed = 0.0;     ///< cm/s, along `heading`
  double heading = 0.5;   ///< direction of travel, rad from +x
  double turnRate = 0.0;  ///< rad/s, counter-clockwise about the shape's origin
  double growth = 0.0;    ///< relative size change per second (circles, ellipses, hands)
  double duration = 1.0;  ///< s of contact
};

/// A round fingertip (circle of radius 0.8 cm), an oval fingertip (a 2.0 x 1.4 cm ellipse) and a
/// flat hand (scale 1, about 19 cm long), each at rest in the middle of the default table.
ChurnScene FingertipScene();
ChurnScene OvalScene();
ChurnScene FlatHandScene();

/// What a churn run counted after the contact's first frame.
struct ChurnResult {
  int frames = 0;          ///< frames counted after the contact's first
  int created = 0;         ///< particles created in them
  int deleted = 0;         ///< particles deleted in them
  int firstParticles = 0;  ///< particles in the contact's first frame
  int lastParticles = 0;   ///< particles in its last frame
  int contactsSeen = 0;    ///< most contacts tracked in one frame (1 for a clean run)
  int kept = 0;            ///< particles alive from the first frame to the last
  double maxDrift = 0.0;   ///< largest move of a kept particle's target in the contact's own
                           ///< frame (the scripted pose) between the first frame and the last, cm
  /// Created and deleted per second of contact after its first frame (frames at frameRate Hz).
  double CreatedPerSecond(double frameRate) const;
  double DeletedPerSecond(double frameRate) const;
};

/// Runs the scene through the whole pipeline with these parameters on an empty table and counts
/// the churn. An Error when the parameters do not start a simulation.
Result<ChurnResult> MeasureChurn(const ChurnScene& scene, const LevelParams& params);

}  // namespace pg
