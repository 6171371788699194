#include "proxygrasp/bench/churn.h"

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace pg {
namespace {

// Through the whole pipeline with camera noise on (default camera: noise 3 grey), one second of
// contact per scene. Issue 16's bound: a rigid contact creates and deletes at most one particle
// per second of contact after its first frame.
constexpr double kRigidChurnPerSecond = 1.0;

ChurnResult Measure(const ChurnScene& scene, int seed, MatchAlgorithm algorithm) {
  LevelParams params;
  params.camera.seed = seed;
  params.proxies.algorithm = algorithm;
  const Result<ChurnResult> r = MeasureChurn(scene, params);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().Format());
  if (!r.ok()) return {};
  const double rate = params.physics.frameRate;
  std::printf(
      "%-10s %-9s speed %4.0f cm/s turn %4.0f deg/s grow %+5.2f/s seed %d: %3d particles, "
      "%6.2f created/s %6.2f deleted/s, %3d kept, drift %.3f cm\n",
      scene.name.c_str(), kMatchAlgorithmNames[static_cast<int>(algorithm)], scene.speed,
      RadToDeg(scene.turnRate), scene.growth, seed, r.value().firstParticles,
      r.value().CreatedPerSecond(rate), r.value().DeletedPerSecond(rate), r.value().kept,
      r.value().maxDrift);
  return r.value();
}

void ExpectRigid(const ChurnScene& scene, int seed) {
  const ChurnResult r = Measure(scene, seed, MatchAlgorithm::kFast);
  const double rate = LevelParams{}.physics.frameRate;
  EXPECT_EQ(r.contactsSeen, 1) << scene.name;
  EXPECT_GE(r.frames, 50) << scene.name;
  EXPECT_LE(r.CreatedPerSecond(rate), kRigidChurnPerSecond) << scene.name << " seed " << seed;
  EXPECT_LE(r.DeletedPerSecond(rate), kRigidChurnPerSecond) << scene.name << " seed " << seed;
}

ChurnScene Moving(ChurnScene scene, double speed, double turnDegPerSecond) {
  scene.speed = speed;
  scene.turnRate = DegToRad(turnDegPerSecond);
  return scene;
}

TEST(Churn, RigidTranslationUpTo50CmPerSecondKeepsTheParticles) {
  for (const ChurnScene& base : {FingertipScene(), OvalScene(), FlatHandScene()}) {
    for (const double speed : {5.0, 20.0, 50.0}) ExpectRigid(Moving(base, speed, 0.0), 1);
  }
}

TEST(Churn, RigidTurningUpTo120DegreesPerSecondKeepsTheParticles) {
  for (const ChurnScene& base : {OvalScene(), FlatHandScene()}) {
    for (const double turn : {60.0, 120.0}) ExpectRigid(Moving(base, 10.0, turn), 1);
  }
}

TEST(Churn, OtherCameraSeeds) {
  for (int seed = 2; seed <= 6; ++seed) {
    ExpectRigid(Moving(OvalScene(), 50.0, 120.0), seed);
    ExpectRigid(Moving(FlatHandScene(), 35.0, -90.0), seed);
  }
}

TEST(Churn, TheReferenceSearchChurnsAsTheIssueMeasured) {
  // the paper's literal search on the sensed contours: an oval at 20 cm/s replaced about one
  // particle a frame in issue 16's measurement (2.00 a frame there); anything above the rigid
  // bound shows the comparison still measures what it should
  const ChurnResult r = Measure(Moving(OvalScene(), 20.0, 0.0), 1, MatchAlgorithm::kReference);
  EXPECT_GT(r.CreatedPerSecond(60.0), 10.0 * kRigidChurnPerSecond);
}

TEST(Churn, GrowingAndShrinkingContactsStillCreateAndDelete) {
  // A circle of radius r sampled every h = 0.3 cm has round(2 pi r / h) points. Growing 50% a
  // second for 59 frames takes r from 0.8 to 0.8 * (1 + 0.5 * 59/60) = 1.193 cm: 17 -> 25 points,
  // so 8 created, less up to count_hysteresis (1) not yet taken up: 7 to 8; nothing deleted but
  // for one pair where the sensed outline jitters (allowed 1). Shrinking 40% a second: r to
  // 0.8 * (1 - 0.4 * 59/60) = 0.485 cm, 10 points: 7 deleted, less up to 1.
  const double h = SensingParams{}.spacing;
  auto points = [&](double r) { return static_cast<int>(std::lround(2.0 * kPi * r / h)); };
  ChurnScene grow = FingertipScene();
  grow.growth = 0.5;
  const ChurnResult g = Measure(grow, 1, MatchAlgorithm::kFast);
  const int more = points(0.8 * (1.0 + 0.5 * 59.0 / 60.0)) - points(0.8);
  EXPECT_GE(g.created, more - 1);
  EXPECT_LE(g.created, more + 1);
  EXPECT_LE(g.deleted, 1);
  ChurnScene shrink = FingertipScene();
  shrink.growth = -0.4;
  const ChurnResult s = Measure(shrink, 1, MatchAlgorithm::kFast);
  const int fewer = points(0.8) - points(0.8 * (1.0 - 0.4 * 59.0 / 60.0));
  EXPECT_GE(s.deleted, fewer - 1);
  EXPECT_LE(s.deleted, fewer + 1);
  EXPECT_LE(s.created, 1);
}

TEST(Churn, AHandSlidingInOverTheTablesEdgeKeepsItsParticles) {
  // A five-finger hand (scale 0.7, thumb towards -x) starts with its thumb side beyond the table's
  // left edge and slides in at 10 cm/s (the churn scenes' back-and-forth path: in to x = 10 cm,
  // then back to 8, where the whole hand is on the table). Its sensed contour is the visible
  // outline plus a run along the edge (the image border), at most the hand's width there: the
  // palm and thumb, under 10 cm x 0.7 = 7 cm, 24 points at 0.3 cm. As the hand comes in, that run
  // goes (its points deleted) and the outline it hid appears (points created), so deleted <= 24 +
  // 2 (sensing jitter) and created <= the growth of the point count + deleted. Nothing else
  // changes shape.
  // (Before the contour walk was checked, the motion estimate slid the hand by a finger in such
  // frames and a hundred or more particles of the contact were replaced in one frame.)
  ChurnScene scene;
  scene.name = "hand at the edge";
  scene.shape.kind = ShapeKind::kHandFive;
  scene.shape.scale = 0.7;
  scene.shape.pose.pos = Vec2(2.0, 0.5 * TableParams{}.height);
  scene.speed = 10.0;
  scene.heading = 0.0;
  for (int seed = 1; seed <= 3; ++seed) {
    const ChurnResult r = Measure(scene, seed, MatchAlgorithm::kFast);
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    EXPECT_EQ(r.contactsSeen, 1);
    EXPECT_LE(r.deleted, 26);
    EXPECT_LE(r.created, r.lastParticles - r.firstParticles + r.deleted);
  }
}

TEST(Churn, KeptParticlesStayOnTheirPlaceOfTheContact) {
  // a translating hand's particles keep their places in the hand's frame after a second at
  // 50 cm/s: less than half the 0.3 cm spacing from where they started, so none slid to a
  // neighbouring sample (what is left is sensing's error on the outline in the two frames)
  const ChurnResult r = Measure(Moving(FlatHandScene(), 50.0, 0.0), 1, MatchAlgorithm::kFast);
  EXPECT_EQ(r.kept, r.firstParticles);
  EXPECT_LT(r.maxDrift, 0.5 * SensingParams{}.spacing);
}

TEST(Churn, KeptParticlesTurnWithAnOval) {
  // an oval fingertip (2.0 x 1.4 cm) turning in place at 60 and 120 degrees a second turns its
  // particles with it: each keeps its place in the oval's frame within half the spacing, as above.
  // (A particle that did not turn would be up to 2 * 1.0 * sin(60 deg / 2) = 1.0 cm from its place
  // after the slower second, and its sample's neighbours would take it over.)
  for (const double turn : {60.0, 120.0}) {
    for (int seed = 1; seed <= 3; ++seed) {
      const ChurnResult r = Measure(Moving(OvalScene(), 0.0, turn), seed, MatchAlgorithm::kFast);
      EXPECT_EQ(r.kept, r.firstParticles) << turn << " deg/s seed " << seed;
      EXPECT_LT(r.maxDrift, 0.5 * SensingParams{}.spacing) << turn << " deg/s seed " << seed;
    }
  }
}

}  // namespace
}  // namespace pg
