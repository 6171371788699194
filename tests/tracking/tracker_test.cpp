#include "proxygrasp/tracking/tracker.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace pg {
namespace {

Blob BlobAt(double x, double y, double area = 2.0) {
  Blob b;
  b.centroid = Vec2(x, y);
  b.area = area;
  const double r = std::sqrt(area / kPi);
  b.contour = Contour(2, 8);
  for (int i = 0; i < 8; ++i)
    b.contour.col(i) = b.centroid + r * Vec2(std::cos(i * kPi / 4), std::sin(i * kPi / 4));
  b.boundsMin = b.centroid - Vec2(r, r);
  b.boundsMax = b.centroid + Vec2(r, r);
  return b;
}

// the outline of two overlapping discs (or of one disc when r2 is 0), counter-clockwise: each
// circle's points outside the other, in angle order about the union's middle
Blob UnionBlob(Vec2 c1, double r1, Vec2 c2, double r2) {
  std::vector<std::pair<double, Vec2>> points;
  const Vec2 middle = 0.5 * (c1 + c2);
  const int kPoints = 48;
  for (int k = 0; k < kPoints; ++k) {
    const double a = 2.0 * kPi * k / kPoints;
    const Vec2 dir(std::cos(a), std::sin(a));
    const Vec2 p1 = c1 + r1 * dir;
    const Vec2 p2 = c2 + r2 * dir;
    if (r2 <= 0.0 || (p1 - c2).norm() >= r2) points.push_back({0.0, p1});
    if (r2 > 0.0 && (p2 - c1).norm() >= r1) points.push_back({0.0, p2});
  }
  for (auto& [angle, p] : points) angle = std::atan2(p.y() - middle.y(), p.x() - middle.x());
  std::sort(points.begin(), points.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Blob b;
  b.contour = Contour(2, static_cast<Eigen::Index>(points.size()));
  for (size_t k = 0; k < points.size(); ++k)
    b.contour.col(static_cast<Eigen::Index>(k)) = points[k].second;
  b.centroid = PolygonCentroid(b.contour);
  b.area = std::abs(SignedArea(b.contour));
  b.boundsMin = b.contour.rowwise().minCoeff();
  b.boundsMax = b.contour.rowwise().maxCoeff();
  return b;
}

Blob Disc(Vec2 c, double r) {
  return UnionBlob(c, r, c, 0.0);
}

ContourFrame Frame(int64_t index, std::vector<Blob> blobs) {
  ContourFrame f;
  f.index = index;
  f.time = index / 60.0;
  f.blobs = std::move(blobs);
  return f;
}

const Contact* Find(const ContactSet& set, ContactId id) {
  for (const Contact& c : set.contacts)
    if (c.id == id) return &c;
  return nullptr;
}

// one frame with these parameters: they may change from frame to frame
ContactSet StepWith(Tracker& t, const TrackingParams& p, const ContourFrame& frame) {
  EXPECT_FALSE(t.SetParams(p));
  return t.Step(frame);
}

TEST(Tracker, KeepsItsParametersAndRejectsOutOfRangeOnes) {
  TrackingParams p;
  p.maxDistance = 2.5;
  Tracker t(p);
  EXPECT_EQ(t.params().maxDistance, 2.5);
  TrackingParams bad = p;
  bad.maxDistance = -1;
  const MaybeError s = t.SetParams(bad);
  ASSERT_TRUE(s);
  EXPECT_NE(s->Format().find("tracking.max_distance"), std::string::npos) << s->Format();
  EXPECT_EQ(t.params().maxDistance, 2.5) << "a rejected change keeps the parameters";
}

TEST(Tracker, NewContinuingLifted) {
  Tracker t;
  TrackingParams p;
  p.keepLost = 0;  // lifted in the first frame without its blob
  ContactSet s0 = StepWith(t, p, Frame(0, {BlobAt(10, 10), BlobAt(30, 10)}));
  ASSERT_EQ(s0.contacts.size(), 2u);
  EXPECT_EQ(s0.frame, 0);
  EXPECT_EQ(s0.contacts[0].state, ContactState::kNew);
  EXPECT_EQ(s0.contacts[0].id, 1);
  EXPECT_EQ(s0.contacts[1].id, 2);

  // the first moves 1 cm, the second is lifted, a third appears
  ContactSet s1 = StepWith(t, p, Frame(1, {BlobAt(11, 10), BlobAt(50, 40)}));
  ASSERT_EQ(s1.contacts.size(), 3u);
  EXPECT_EQ(s1.contacts[0].id, 1);
  EXPECT_EQ(s1.contacts[0].state, ContactState::kContinuing);
  EXPECT_DOUBLE_EQ(s1.contacts[0].blob.centroid.x(), 11.0);
  EXPECT_EQ(s1.contacts[1].id, 3);
  EXPECT_EQ(s1.contacts[1].state, ContactState::kNew);
  // lifted ones come after the current ones, with their last blob
  EXPECT_EQ(s1.contacts[2].id, 2);
  EXPECT_EQ(s1.contacts[2].state, ContactState::kLifted);
  EXPECT_DOUBLE_EQ(s1.contacts[2].blob.centroid.x(), 30.0);

  // a lifted contact is reported once only
  ContactSet s2 = StepWith(t, p, Frame(2, {BlobAt(11, 10), BlobAt(50, 40)}));
  ASSERT_EQ(s2.contacts.size(), 2u);
  EXPECT_EQ(Find(s2, 2), nullptr);
}

TEST(Tracker, FartherThanMaxDistanceIsANewContact) {
  Tracker t;
  TrackingParams p;
  p.maxDistance = 2.0;
  p.maxSpeed = 0.0;  // the reach is max_distance alone
  p.keepLost = 0;    // lifted in the first frame without its blob
  StepWith(t, p, Frame(0, {BlobAt(10, 10)}));
  ContactSet s = StepWith(t, p, Frame(1, {BlobAt(12.5, 10)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].state, ContactState::kNew);
  EXPECT_EQ(s.contacts[0].id, 2);
  EXPECT_EQ(s.contacts[1].state, ContactState::kLifted);
  EXPECT_EQ(s.contacts[1].id, 1);
  // exactly at the threshold still matches
  ContactSet at = StepWith(t, p, Frame(2, {BlobAt(14.5, 10)}));
  EXPECT_EQ(at.contacts[0].id, 2);
  EXPECT_EQ(at.contacts[0].state, ContactState::kContinuing);
}

TEST(Tracker, TheReachGrowsWithTheTimeBetweenFrames) {
  // defaults: max_distance 4 cm, max_speed 150 cm/s. At 60 Hz the reach is max(4, 150/60) = 4 cm;
  // at 20 fps (a slower camera, or a recording that repeats frames) it is 150/20 = 7.5 cm
  auto at = [](int64_t index, double fps, double x) {
    ContourFrame f = Frame(index, {BlobAt(x, 10)});
    f.time = index / fps;
    return f;
  };
  Tracker fast;
  fast.Step(at(0, 60.0, 10.0));
  EXPECT_EQ(fast.Step(at(1, 60.0, 16.0)).contacts[0].state, ContactState::kNew);  // 6 > 4
  Tracker slow;
  slow.Step(at(0, 20.0, 10.0));
  ContactSet s = slow.Step(at(1, 20.0, 16.0));  // 6 <= 7.5
  EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[0].id, 1);
  EXPECT_EQ(slow.Step(at(2, 20.0, 24.0)).contacts[0].state, ContactState::kNew);  // 8 > 7.5
  // a frame that is not later than the last (a still, or a restarted clock) reaches max_distance
  Tracker still;
  still.Step(at(0, 20.0, 10.0));
  EXPECT_EQ(still.Step(at(0, 20.0, 16.0)).contacts[0].state, ContactState::kNew);
}

TEST(Tracker, ALostContactIsKeptForKeepLostFramesThenLifted) {
  // default keep_lost: 3 frames. A blob missing for 2 frames comes back under its id; one
  // missing for 4 frames is lifted in the 4th, having gone on where it was last seen for 3
  Tracker t;
  t.Step(Frame(0, {BlobAt(10, 10)}));
  for (int f = 1; f <= 2; ++f) {
    ContactSet s = t.Step(Frame(f, {}));
    ASSERT_EQ(s.contacts.size(), 1u);
    EXPECT_EQ(s.contacts[0].id, 1);
    EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
    EXPECT_EQ(s.contacts[0].missed, f);
    EXPECT_DOUBLE_EQ(s.contacts[0].blob.centroid.x(), 10.0);  // where it was last seen
  }
  ContactSet back = t.Step(Frame(3, {BlobAt(10.5, 10)}));
  ASSERT_EQ(back.contacts.size(), 1u);
  EXPECT_EQ(back.contacts[0].id, 1);
  EXPECT_EQ(back.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(back.contacts[0].missed, 0);
  for (int f = 4; f <= 6; ++f) {
    ContactSet s = t.Step(Frame(f, {}));
    ASSERT_EQ(s.contacts.size(), 1u);
    EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  }
  ContactSet gone = t.Step(Frame(7, {}));
  ASSERT_EQ(gone.contacts.size(), 1u);
  EXPECT_EQ(gone.contacts[0].id, 1);
  EXPECT_EQ(gone.contacts[0].state, ContactState::kLifted);
  EXPECT_EQ(gone.contacts[0].missed, 3);
  EXPECT_TRUE(t.Step(Frame(8, {})).contacts.empty());
  // a kept contact's reach grows with the time since it was last seen: 150 cm/s over 4 frames
  // at 20 fps is 30 cm
  Tracker slow;
  auto at = [](int64_t index, std::vector<Blob> blobs) {
    ContourFrame f = Frame(index, std::move(blobs));
    f.time = index / 20.0;
    return f;
  };
  slow.Step(at(0, {BlobAt(10, 10)}));
  for (int f = 1; f <= 3; ++f) slow.Step(at(f, {}));
  ContactSet far = slow.Step(at(4, {BlobAt(35, 10)}));
  ASSERT_EQ(far.contacts.size(), 1u);
  EXPECT_EQ(far.contacts[0].id, 1);
  EXPECT_EQ(far.contacts[0].state, ContactState::kContinuing);
}

TEST(Tracker, AContactThatRisesIntoHoverIsLiftedAtOnce) {
  // A depth camera sees a lifted fingertip as hover: its touch blob is gone and a hover region
  // (the fingertip and the finger above the band) covers where it was. It is lifted in that
  // frame, not kept for keep_lost (3) frames where it was last seen, which would leave a contact
  // (and its particles pressing) under a finger already 2 to 3 cm up at 30 cm/s.
  Tracker t;
  t.Step(Frame(0, {Disc({10, 10}, 0.8), Disc({20, 10}, 0.8)}));
  ContourFrame lifted = Frame(1, {Disc({20, 10}, 0.8)});
  lifted.hover.push_back(UnionBlob({10, 10.2}, 1.1, {10, 8.6}, 1.0));  // the pad and its finger
  ContactSet s = t.Step(lifted);
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].id, 2);
  EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[1].id, 1);
  EXPECT_EQ(s.contacts[1].state, ContactState::kLifted);
  EXPECT_TRUE(t.Step(Frame(2, {Disc({20, 10}, 0.8)})).contacts.size() == 1u);
  // a hover region beside it (its own finger rising behind a pad that dropped out of the band
  // for a frame) or elsewhere (another hand) does not lift a contact: it is kept
  Tracker beside;
  beside.Step(Frame(0, {Disc({10, 10}, 0.8)}));
  ContourFrame dropped = Frame(1, {});
  dropped.hover.push_back(UnionBlob({10, 8.2}, 0.8, {10, 7.2}, 0.8));  // 0.2 cm from the pad
  ContactSet bridged = beside.Step(dropped);
  ASSERT_EQ(bridged.contacts.size(), 1u);
  EXPECT_EQ(bridged.contacts[0].state, ContactState::kContinuing);
  Tracker u;
  u.Step(Frame(0, {Disc({10, 10}, 0.8)}));
  ContourFrame away = Frame(1, {});
  away.hover.push_back(Disc({30, 30}, 3.0));
  ContactSet kept = u.Step(away);
  ASSERT_EQ(kept.contacts.size(), 1u);
  EXPECT_EQ(kept.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(kept.contacts[0].missed, 1);
}

TEST(Tracker, GloballyNearestPairsFirst) {
  // previous A at x=0 and B at x=3; current blobs at x=2 and x=3.5. Matching blob by blob in
  // order would give the x=2 blob to its nearest, B (distance 1), and leave A and the x=3.5 blob
  // unmatched (3.5 > 2.5); the global order takes (B, 3.5) = 0.5 first, then (A, 2) = 2
  Tracker t;
  TrackingParams p;
  p.maxDistance = 2.5;
  StepWith(t, p, Frame(0, {BlobAt(0, 0), BlobAt(3, 0)}));
  ContactSet s = StepWith(t, p, Frame(1, {BlobAt(2, 0), BlobAt(3.5, 0)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].id, 1);  // the blob at x=2 continues A
  EXPECT_EQ(s.contacts[1].id, 2);  // the blob at x=3.5 continues B
  EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[1].state, ContactState::kContinuing);
}

TEST(Tracker, MergeKeepsTheNearestIdAndLiftsTheOther) {
  // two fingertips (areas 2 and 1) merge into one blob whose centroid is area-weighted
  Tracker t;
  TrackingParams p;
  p.keepLost = 0;  // lifted in the first frame without its blob
  StepWith(t, p, Frame(0, {BlobAt(10, 10, 2.0), BlobAt(12, 10, 1.0)}));
  ContactSet s = StepWith(t, p, Frame(1, {BlobAt(10.7, 10, 3.0)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].id, 1);  // the larger finger's centroid is nearer
  EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[1].id, 2);
  EXPECT_EQ(s.contacts[1].state, ContactState::kLifted);
}

TEST(Tracker, SplitKeepsTheNearestPieceAndTheOtherIsNew) {
  Tracker t;
  TrackingParams p;
  StepWith(t, p, Frame(0, {BlobAt(10.7, 10, 3.0)}));
  ContactSet s = StepWith(t, p, Frame(1, {BlobAt(10, 10, 2.0), BlobAt(12, 10, 1.0)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].id, 1);
  EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[1].id, 2);
  EXPECT_EQ(s.contacts[1].state, ContactState::kNew);
}

TEST(Tracker, IdsAreNeverReused) {
  Tracker t;
  TrackingParams p;
  p.keepLost = 0;  // lifted in the first frame without its blob
  std::set<ContactId> seen;
  for (int i = 0; i < 20; ++i) {
    // a contact appears every other frame and vanishes the next
    ContactSet s = StepWith(
        t, p, Frame(i, i % 2 == 0 ? std::vector<Blob>{BlobAt(10, 10)} : std::vector<Blob>{}));
    for (const Contact& c : s.contacts) {
      if (c.state == ContactState::kNew) {
        EXPECT_TRUE(seen.insert(c.id).second) << "id " << c.id << " reused";
      }
    }
  }
  EXPECT_EQ(seen.size(), 10u);
  t.Reset();
  ContactSet after = StepWith(t, p, Frame(20, {BlobAt(10, 10)}));
  EXPECT_EQ(after.contacts[0].state, ContactState::kNew);
  EXPECT_EQ(after.contacts[0].id, 11) << "Reset forgets contacts, not the id counter";
}

TEST(TrackerTopology, TwoFingertipsThatTouchMergeAndTheMergedContactHasBothAsParents) {
  // two fingertips 0.9 cm in radius, 2 cm apart (centres), slide together 0.1 cm per frame each
  // until their discs overlap: one blob
  Tracker t;
  StepWith(t, TrackingParams{}, Frame(0, {Disc({10, 10}, 0.9), Disc({12, 10}, 0.9)}));
  StepWith(t, TrackingParams{}, Frame(1, {Disc({10.1, 10}, 0.9), Disc({11.9, 10}, 0.9)}));
  const ContactSet s =
      StepWith(t, TrackingParams{}, Frame(2, {UnionBlob({10.2, 10}, 0.9, {11.8, 10}, 0.9)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  const Contact& merged = s.contacts[0];
  EXPECT_EQ(merged.state, ContactState::kContinuing);
  ASSERT_EQ(merged.parents.size(), 2u);
  EXPECT_EQ(merged.parents[0], merged.id) << "a continuing contact's own id comes first";
  const Contact& other = s.contacts[1];
  EXPECT_EQ(other.state, ContactState::kLifted);
  EXPECT_EQ(other.mergedInto, merged.id) << "lifted into the merged contact, not kept lost";
  EXPECT_EQ(merged.parents[1], other.id);
  EXPECT_TRUE(other.parents.empty());
  EXPECT_EQ(s.merges, 1);
  EXPECT_EQ(s.splits, 0);
}

TEST(TrackerTopology, ABlobThatPartsSplitsAndTheNewPieceHasItsParent) {
  Tracker t;
  StepWith(t, TrackingParams{}, Frame(0, {UnionBlob({10.2, 10}, 0.9, {11.8, 10}, 0.9)}));
  const ContactSet s =
      StepWith(t, TrackingParams{}, Frame(1, {Disc({10.1, 10}, 0.9), Disc({11.9, 10}, 0.9)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  // the pieces are equally near the merged centroid: either may continue it
  const int kept = s.contacts[0].state == ContactState::kContinuing ? 0 : 1;
  const Contact& continuing = s.contacts[kept];
  const Contact& piece = s.contacts[1 - kept];
  EXPECT_EQ(continuing.state, ContactState::kContinuing);
  EXPECT_EQ(piece.state, ContactState::kNew);
  ASSERT_EQ(continuing.parents.size(), 1u);
  ASSERT_EQ(piece.parents.size(), 1u);
  EXPECT_EQ(continuing.parents[0], continuing.id);
  EXPECT_EQ(piece.parents[0], continuing.id) << "split off the continuing contact";
  EXPECT_EQ(s.merges, 0);
  EXPECT_EQ(s.splits, 1);
}

TEST(TrackerTopology, APartHandedFromOneBlobToAnotherNamesBothParents) {
  // three fingertips in a row, 1.8 cm apart (radius 0.9): the middle one touches the right one
  // (one blob), then leaves it for the left one; both blobs continue their contacts by their
  // centroids, and the left one's new part came from the right one's blob
  Tracker t;
  StepWith(t, TrackingParams{},
           Frame(0, {Disc({10, 10}, 0.9), UnionBlob({11.7, 10}, 0.9, {13.4, 10}, 0.9)}));
  const ContactSet s0 =
      t.Step(Frame(1, {Disc({10, 10}, 0.9), UnionBlob({11.7, 10}, 0.9, {13.4, 10}, 0.9)}));
  const ContactSet s =
      StepWith(t, TrackingParams{},
               Frame(2, {UnionBlob({10, 10}, 0.9, {11.7, 10}, 0.9), Disc({13.4, 10}, 0.9)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  const ContactId left =
      s0.contacts[0].blob.centroid.x() < 11 ? s0.contacts[0].id : s0.contacts[1].id;
  const ContactId right = s0.contacts[0].id == left ? s0.contacts[1].id : s0.contacts[0].id;
  for (const Contact& c : s.contacts) {
    EXPECT_EQ(c.state, ContactState::kContinuing);
    if (c.id == left) {
      EXPECT_EQ(c.parents, (std::vector<ContactId>{left, right}))
          << "its new part came from the right";
    } else {
      EXPECT_EQ(c.parents, std::vector<ContactId>{right})
          << "the right one lost a part, gained none";
    }
  }
  EXPECT_EQ(s.merges, 1);
  EXPECT_EQ(s.splits, 1);
}

TEST(TrackerTopology, AFingerPutDownBesideAnotherIsNewWithNoParent) {
  // a fingertip lands 0.5 cm from another's outline: its outline is nowhere within 0.3 cm of the
  // first's, so nothing split
  Tracker t;
  StepWith(t, TrackingParams{}, Frame(0, {Disc({10, 10}, 0.9)}));
  const ContactSet s =
      StepWith(t, TrackingParams{}, Frame(1, {Disc({10, 10}, 0.9), Disc({12.3, 10}, 0.9)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[1].state, ContactState::kNew);
  EXPECT_TRUE(s.contacts[1].parents.empty());
  EXPECT_EQ(s.splits, 0);
}

TEST(TrackerTopology, AContactThatDropsOutBesideAnotherIsKeptLostNotMerged) {
  // a fingertip's blob vanishes (below the threshold) 1.5 cm from another's outline
  Tracker t;
  StepWith(t, TrackingParams{}, Frame(0, {Disc({10, 10}, 0.9), Disc({13.3, 10}, 0.9)}));
  const ContactSet s = StepWith(t, TrackingParams{}, Frame(1, {Disc({10, 10}, 0.9)}));
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[1].state, ContactState::kContinuing);
  EXPECT_EQ(s.contacts[1].missed, 1);
  EXPECT_EQ(s.contacts[0].parents.size(), 1u);
  EXPECT_EQ(s.merges, 0);
}

// Two fingertips closing at speed v each (2v together) meet within a frame at any frame rate the
// tracker supports: their last contours lie v dt behind where the merged blob has them, and are
// found inside it once moved on by their velocities.
class TrackerTopologySpeed : public ::testing::TestWithParam<std::tuple<double, double>> {};

TEST_P(TrackerTopologySpeed, MergeAndSplitAreFoundAtSpeed) {
  const auto [rate, speed] = GetParam();
  Tracker t;
  const double dt = 1.0 / rate;
  const double r = 0.9;
  // the fingertips move together (both at `speed` along y, across the line between them) while
  // the gap between them closes by 0.2 cm a frame: the merged blob appears where the contacts'
  // velocity carried them, up to v dt from their last contours
  auto centres = [&](int k) {
    const double y = 10.0 + speed * dt * k;
    const double gap = 0.4 - 0.2 * k;  // between the outlines, cm: 0.4, 0.2, 0, -0.2 ...
    return std::pair<Vec2, Vec2>{{10 - r - 0.5 * gap, y}, {10 + r + 0.5 * gap, y}};
  };
  ContactSet s;
  for (int k = 0; k < 4; ++k) {
    const auto [a, b] = centres(k);
    ContourFrame f = Frame(k, k < 3 ? std::vector<Blob>{Disc(a, r), Disc(b, r)}
                                    : std::vector<Blob>{UnionBlob(a, r, b, r)});
    f.time = k * dt;
    s = t.Step(f);
  }
  EXPECT_EQ(s.merges, 1) << rate << " fps, " << speed << " cm/s";
  // and apart again, still moving
  for (int k = 4; k < 6; ++k) {
    const double y = 10.0 + speed * dt * k;
    ContourFrame f = Frame(k, {Disc({10 - r - 0.1, y}, r), Disc({10 + r + 0.1, y}, r)});
    f.time = k * dt;
    s = t.Step(f);
    if (k == 4) {
      EXPECT_EQ(s.splits, 1) << rate << " fps, " << speed << " cm/s";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RatesAndSpeeds, TrackerTopologySpeed,
                         ::testing::Combine(::testing::Values(20.0, 30.0, 60.0),
                                            ::testing::Values(0.0, 30.0, 100.0)));

// the acceptance scenarios through the real pipeline: synthetic camera -> sensor -> tracker

struct Pipeline {
  Pipeline() : camera(Params(), table) {
    EXPECT_FALSE(sensor.Configure(SensingParams{}, table, CalibrationFromModel(camera.model())));
    EXPECT_FALSE(sensor.SetBackground(camera.Background()));
  }
  static SyntheticCameraParams Params() {
    SyntheticCameraParams p;
    p.distortion = -0.05;
    p.perspective = 0.04;
    return p;
  }
  ContactSet Step(std::span<const ContactShape> shapes) {
    Result<ContourFrame> f = sensor.Step(camera.Render(shapes), frame, frame / 60.0);
    EXPECT_TRUE(f) << f.error().Format();
    ++frame;
    return tracker.Step(f.value());
  }
  TableParams table;
  SyntheticCamera camera;
  Sensor sensor;
  Tracker tracker;
  int64_t frame = 0;
};

std::vector<ContactShape> TenFingertips(int frame) {
  // ten fingertips on two hands, each circling on its own (up to ~20 cm/s at 60 Hz, 0.35 cm per
  // frame), 3 cm apart at rest
  std::vector<ContactShape> shapes;
  const double t = frame / 60.0;
  for (int i = 0; i < 10; ++i) {
    ContactShape s;
    s.radius = 0.7 + 0.03 * (i % 5);
    const Vec2 home(12.0 + 4.0 * i, 23.0 + ((i % 5 == 0) ? -3.0 : 0.0));
    s.pose.pos = home + Vec2(1.0 * std::cos(3.0 * t + i), 4.0 * std::sin(2.0 * t + 0.5 * i));
    shapes.push_back(s);
  }
  return shapes;
}

TEST(TrackerPipeline, TenFingertipsKeepTheirIdsFor200Frames) {
  Pipeline p;
  std::map<int, ContactId> idOf;  // shape index -> id
  for (int frame = 0; frame < 200; ++frame) {
    const std::vector<ContactShape> shapes = TenFingertips(frame);
    const ContactSet set = p.Step(shapes);
    ASSERT_EQ(set.contacts.size(), 10u) << "frame " << frame;
    for (const Contact& c : set.contacts) {
      // which fingertip is this? the one whose centre is nearest the blob's centroid
      int nearest = 0;
      for (int i = 1; i < 10; ++i)
        if ((shapes[i].pose.pos - c.blob.centroid).norm() <
            (shapes[nearest].pose.pos - c.blob.centroid).norm())
          nearest = i;
      // a disc's centroid is its centre: within a tenth of a pixel or so
      EXPECT_LT((shapes[nearest].pose.pos - c.blob.centroid).norm(), 0.05);
      if (frame == 0) {
        EXPECT_EQ(c.state, ContactState::kNew);
        idOf[nearest] = c.id;
      } else {
        EXPECT_EQ(c.state, ContactState::kContinuing) << "frame " << frame;
        EXPECT_EQ(c.id, idOf[nearest])
            << "fingertip " << nearest << " changed id at frame " << frame;
      }
    }
  }
  EXPECT_EQ(idOf.size(), 10u);
}

TEST(TrackerPipeline, LiftedFingerPutDownAgainGetsANewId) {
  Pipeline p;
  ContactShape a, b;
  a.pose.pos = {20, 20};
  b.pose.pos = {35, 20};
  const ContactShape both[] = {a, b};
  const ContactShape onlyA[] = {a};
  ContactSet s = p.Step(both);
  ASSERT_EQ(s.contacts.size(), 2u);
  ContactId idB = kNoId;
  for (const Contact& c : s.contacts)
    if (c.blob.centroid.x() > 30) idB = c.id;
  ASSERT_NE(idB, kNoId);
  p.Step(both);
  // lift b: it goes on where it was for keep_lost (3) frames, then it is reported lifted once,
  // with its last blob
  for (int kept = 1; kept <= 3; ++kept) {
    s = p.Step(onlyA);
    ASSERT_EQ(s.contacts.size(), 2u);
    EXPECT_EQ(s.contacts[1].id, idB);
    EXPECT_EQ(s.contacts[1].state, ContactState::kContinuing);
    EXPECT_EQ(s.contacts[1].missed, kept);
  }
  s = p.Step(onlyA);
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[1].id, idB);
  EXPECT_EQ(s.contacts[1].state, ContactState::kLifted);
  EXPECT_NEAR(s.contacts[1].blob.centroid.x(), 35.0, 0.05);
  s = p.Step(onlyA);
  ASSERT_EQ(s.contacts.size(), 1u);
  // put it down at the same place: a new id, larger than any before
  s = p.Step(both);
  ASSERT_EQ(s.contacts.size(), 2u);
  const Contact* down = nullptr;
  for (const Contact& c : s.contacts)
    if (c.blob.centroid.x() > 30) down = &c;
  ASSERT_NE(down, nullptr);
  EXPECT_EQ(down->state, ContactState::kNew);
  EXPECT_NE(down->id, idB);
  EXPECT_GT(down->id, idB);
}

TEST(TrackerPipeline, FingersMergingAndSplitting) {
  // two fingertips slide together until they touch (one blob), then apart again
  Pipeline p;
  ContactShape left, right;
  left.radius = 0.9;
  right.radius = 0.7;
  std::vector<ContactId> idsBefore;
  ContactId mergedId = kNoId;
  bool sawMerge = false, sawSplit = false;
  for (int frame = 0; frame < 40; ++frame) {
    // gap closes from 2 cm to overlapping by 0.3 cm at frame 20, then opens again
    const double gap = 2.0 - 2.3 * (1.0 - std::abs(frame - 20) / 20.0);
    left.pose.pos = {30.0 - 0.5 * gap - left.radius, 20.0};
    right.pose.pos = {30.0 + 0.5 * gap + right.radius, 20.0};
    const ContactShape shapes[] = {left, right};
    const ContactSet s = p.Step(shapes);
    int current = 0;
    for (const Contact& c : s.contacts) current += c.state != ContactState::kLifted;
    if (frame == 0) {
      ASSERT_EQ(current, 2);
      for (const Contact& c : s.contacts) idsBefore.push_back(c.id);
    }
    if (current == 1 && !sawMerge) {
      sawMerge = true;
      // the merged blob continues the bigger finger's id (its centroid is nearer); the smaller
      // finger is lifted
      ASSERT_EQ(s.contacts.size(), 2u);
      EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
      EXPECT_EQ(s.contacts[0].id, idsBefore[0]);
      EXPECT_EQ(s.contacts[1].state, ContactState::kLifted);
      EXPECT_EQ(s.contacts[1].id, idsBefore[1]);
      EXPECT_EQ(s.contacts[1].mergedInto, s.contacts[0].id) << "the smaller merged into it";
      EXPECT_EQ(s.contacts[0].parents, (std::vector<ContactId>{idsBefore[0], idsBefore[1]}));
      EXPECT_EQ(s.merges, 1);
      mergedId = s.contacts[0].id;
    }
    if (sawMerge && current == 2 && !sawSplit) {
      sawSplit = true;
      // on the split the piece nearest the merged centroid keeps the id, the other is new
      EXPECT_EQ(s.contacts[0].id, mergedId);
      EXPECT_EQ(s.contacts[0].state, ContactState::kContinuing);
      EXPECT_EQ(s.contacts[1].state, ContactState::kNew);
      EXPECT_GT(s.contacts[1].id, idsBefore[1]);
      EXPECT_EQ(s.contacts[1].parents, std::vector<ContactId>{mergedId}) << "split off it";
      EXPECT_EQ(s.splits, 1);
    }
  }
  EXPECT_TRUE(sawMerge);
  EXPECT_TRUE(sawSplit);
}

}  // namespace
}  // namespace pg
