#include "proxygrasp/proxies/instant_proxies.h"

#include "proxygrasp/proxies/proxy_stage.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <set>

#include "proxies/test_scene.h"
#include "proxies/test_shapes.h"

namespace pg {
namespace {

// one frame with these parameters: they may change from frame to frame
ParticlePlan StepWith(ProxyStage& stage, const ProxyParams& params, const ContactSet& contacts,
                      const SceneQuery& scene, std::span<const ParticleFeedback> feedback,
                      const TableImage* image) {
  EXPECT_FALSE(stage.SetParams(params));
  return stage.Step(contacts, scene, feedback, image);
}

using testing::Box;
using testing::BoxScene;
using testing::CircleOutline;
using testing::Moved;
using testing::Sensed;

constexpr double kCmPerPixel = 0.1;
const Vec2 kOrigin(5.0, 3.0);

// a 30 x 20 cm table image with bright discs (centre in pixels, radius in pixels)
TableImage Discs(const std::vector<std::pair<cv::Point, int>>& discs) {
  TableImage t;
  t.image = cv::Mat(200, 300, CV_8UC1, cv::Scalar(40));
  for (const auto& [centre, radius] : discs) cv::circle(t.image, centre, radius, 220, cv::FILLED);
  // the optics blur contact edges over a pixel or two
  cv::GaussianBlur(t.image, t.image, cv::Size(5, 5), 1.0);
  t.cmPerPixel = kCmPerPixel;
  t.origin = kOrigin;
  return t;
}

// the table position of a pixel-space point (pixel centres sit at +0.5)
Vec2 Table(double u, double v) {
  return kOrigin + Vec2(u + 0.5, v + 0.5) * kCmPerPixel;
}

TEST(InstantProxies, SobelMagnitudeIsGreyLevelsPerPixel) {
  // a ramp rising 2 grey levels per pixel along u reads exactly 2 everywhere
  TableImage t;
  t.image = cv::Mat(40, 60, CV_8UC1);
  for (int v = 0; v < 40; ++v) {
    for (int u = 0; u < 60; ++u)
      t.image.at<unsigned char>(v, u) = static_cast<unsigned char>(2 * u);
  }
  t.cmPerPixel = kCmPerPixel;
  // the border columns mirror the image, so their gradient is zero: interior cells only
  const std::vector<EdgePixel> above = EdgePixels(t, 1.9, 0.1);
  EXPECT_EQ(above.size(), static_cast<size_t>(40 * 58));
  for (const EdgePixel& e : above) EXPECT_FLOAT_EQ(e.magnitude, 2.0);
  EXPECT_TRUE(EdgePixels(t, 2.1, 0.1).empty());
}

TEST(InstantProxies, EdgePixelsOutlineADisc) {
  const TableImage t = Discs({{cv::Point(150, 100), 20}});
  const std::vector<EdgePixel> edges = EdgePixels(t, 40.0, 0.3);
  // one per 3 x 3 pixel cell that the edge ring (2 cm radius) crosses: 2 pi 20 / 3 ~ 42 cells
  // and more where the ring clips cell corners
  EXPECT_GT(edges.size(), 35u);
  EXPECT_LT(edges.size(), 100u);
  for (const EdgePixel& e : edges) {
    const double r = std::hypot(e.pixel.x - 150.0, e.pixel.y - 100.0);
    // the blurred step is steepest at the drawn radius; 40 grey/px is reached within 2 px of it
    EXPECT_NEAR(r, 20.0, 2.5) << "pixel " << e.pixel.x << "," << e.pixel.y;
    EXPECT_NEAR((e.pos - Table(e.pixel.x, e.pixel.y)).norm(), 0.0, 1e-12);
    EXPECT_GT(e.magnitude, 40.0);
  }
  // nothing passes a threshold above the steepest edge (180 grey levels over a blurred step)
  EXPECT_TRUE(EdgePixels(t, 500.0, 0.3).empty());
  // no particles where there is no image
  EXPECT_TRUE(EdgePixels(TableImage{}, 40.0, 0.3).empty());
}

TEST(InstantProxies, OpticalFlowGivesTheDiscsMotion) {
  const TableImage a = Discs({{cv::Point(150, 100), 20}});
  const TableImage b = Discs({{cv::Point(156, 96), 20}});
  const std::vector<EdgePixel> edges = EdgePixels(b, 40.0, 0.3);
  const std::vector<Vec2> motion = ImageMotion(a, b, edges, 21);
  ASSERT_EQ(motion.size(), edges.size());
  // the disc moved (6, -4) px = (0.6, -0.4) cm; LK on a blurred edge is accurate to a fraction of
  // a pixel, so allow 0.1 cm (1 px) at 90% of the points
  int close = 0;
  for (const Vec2& m : motion) close += (m - Vec2(0.6, -0.4)).norm() < 0.1;
  EXPECT_GE(close, 0.9 * motion.size()) << close << " of " << motion.size();
  // no previous image, or a different grid: no motion
  for (const Vec2& m : ImageMotion(TableImage{}, b, edges, 21)) EXPECT_EQ(m, Vec2::Zero());
}

ContactSet DiscContacts(int64_t frame, const std::vector<std::pair<cv::Point, int>>& discs) {
  ContactSet set;
  set.frame = frame;
  ContactId id = 1;
  for (const auto& [centre, radius] : discs) {
    Contact c;
    c.id = id++;
    c.state = frame == 0 ? ContactState::kNew : ContactState::kContinuing;
    c.blob.contour =
        Sensed(Moved(CircleOutline(radius * kCmPerPixel), {Table(centre.x - 0.5, centre.y - 0.5)}));
    set.contacts.push_back(c);
  }
  return set;
}

TEST(InstantProxies, EveryFrameReplacesEveryParticle) {
  ProxyParams params;
  params.mode = ProxyMode::kInstant;
  BoxScene scene;
  ProxyStage stage;
  std::vector<ParticleId> alive;
  std::set<ParticleId> ever;
  for (int frame = 0; frame < 4; ++frame) {
    const std::vector<std::pair<cv::Point, int>> discs = {{cv::Point(80 + 6 * frame, 100), 15},
                                                          {cv::Point(200, 60 - 4 * frame), 18}};
    const TableImage image = Discs(discs);
    const ParticlePlan plan =
        StepWith(stage, params, DiscContacts(frame, discs), scene, {}, &image);
    ASSERT_EQ(CheckPlan(plan, alive), "");
    // last frame's particles all end, none is reused
    EXPECT_EQ(plan.deleted, static_cast<int>(alive.size()));
    EXPECT_EQ(plan.reused, 0);
    EXPECT_GT(plan.created, 40);
    alive.clear();
    int moving = 0;
    for (const PlannedParticle& p : plan.particles) {
      if (p.action != ParticleAction::kCreated) continue;
      EXPECT_TRUE(ever.insert(p.id).second);
      alive.push_back(p.id);
      // every edge particle is near one of the two contacts' contours
      EXPECT_NE(p.contact, kNoId);
      // from the second frame on each disc's particles move with it: (0.6, 0) or (0, -0.4) cm
      if (frame > 0) {
        const Vec2 expected = p.contact == 1 ? Vec2(0.6, 0.0) : Vec2(0.0, -0.4);
        moving += ((p.target - p.start) - expected).norm() < 0.1;
      }
    }
    if (frame > 0) {
      EXPECT_GE(moving, 0.9 * plan.created) << "frame " << frame;
    }
    EXPECT_EQ(stage.LiveCount(), plan.created);
  }
}

TEST(InstantProxies, ParticlesOverAnObjectLandOnItsTopEveryFrame) {
  // a fingertip pushing into a box from the left. Instant particles are placed afresh by raycast
  // each frame, so those over the footprint sit on the top: the finger slides onto the object
  // (the paper's argument that per-frame particles cannot hold a grasp). Persistent particles
  // keep their table height.
  BoxScene scene;
  scene.boxes = {{Table(100, 50), Table(200, 150), 4.0}};
  ProxyParams instant;
  instant.mode = ProxyMode::kInstant;
  ProxyParams persistent;
  ProxyStage a;
  ProxyStage b;
  int onTopInstant = 0;
  int onTopPersistent = 0;
  for (int frame = 0; frame < 8; ++frame) {
    const std::vector<std::pair<cv::Point, int>> discs = {{cv::Point(80 + 4 * frame, 100), 12}};
    const TableImage image = Discs(discs);
    const ContactSet set = DiscContacts(frame, discs);
    for (const PlannedParticle& p : StepWith(a, instant, set, scene, {}, &image).particles) {
      if (p.action != ParticleAction::kDeleted && p.baseHeight == 4.0) ++onTopInstant;
    }
    for (const PlannedParticle& p : StepWith(b, persistent, set, scene, {}, nullptr).particles) {
      if (p.action != ParticleAction::kDeleted && p.baseHeight == 4.0) ++onTopPersistent;
    }
  }
  EXPECT_GT(onTopInstant, 20);
  EXPECT_EQ(onTopPersistent, 0);
}

TEST(InstantProxies, GroundModeStartsOutsideEveryFootprint) {
  BoxScene scene;
  scene.boxes = {{Table(140, 90), Table(200, 150), 4.0}};
  ProxyParams params;
  params.mode = ProxyMode::kInstant;
  params.placement = Placement::kGround;
  ProxyStage stage;
  const std::vector<std::pair<cv::Point, int>> discs = {{cv::Point(150, 100), 20}};
  const TableImage image = Discs(discs);
  const ParticlePlan plan = StepWith(stage, params, DiscContacts(0, discs), scene, {}, &image);
  for (const PlannedParticle& p : plan.particles) {
    EXPECT_EQ(p.baseHeight, 0.0);
    EXPECT_FALSE(BoxScene::Inside(scene.boxes[0], p.start));
  }
  // a quarter of the disc's edge lies over the box: those particles were moved out of it
  int inside = 0;
  for (const EdgePixel& e : EdgePixels(image, params.instantThreshold, params.instantSpacing)) {
    inside += BoxScene::Inside(scene.boxes[0], e.pos);
  }
  EXPECT_GT(inside, 5);
}

}  // namespace
}  // namespace pg
