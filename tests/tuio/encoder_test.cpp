#include "proxygrasp/tuio/encoder.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/tuio/decoder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace pg {
namespace {

// what a contour may move on its way through TUIO and back (the acceptance figure)
constexpr double kRoundTripTol = 0.05;  // cm

std::vector<Vec2> Ellipse(Vec2 c, double rx, double ry, double angle, int n) {
  std::vector<Vec2> points;
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * kPi * k / n;
    const Vec2 local(rx * std::cos(t), ry * std::sin(t));
    points.push_back(c + Rotate(local, angle));
  }
  return points;
}

// a star-like concave outline, like a hand's fingers, with n points
std::vector<Vec2> Star(Vec2 c, double r, int n) {
  std::vector<Vec2> points;
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * kPi * k / n;
    const double radius = r * (0.6 + 0.4 * std::cos(5.0 * t));
    points.push_back(c + radius * Vec2(std::cos(t), std::sin(t)));
  }
  return points;
}

TuioOutContact Out(TuioSessionId id, std::vector<Vec2> contour) {
  TuioOutContact c;
  c.id = id;
  c.centroid = PolygonCentroid(ToContour(contour));
  c.contour = std::move(contour);
  return c;
}

std::vector<TuioFrame> DecodeAll(const std::vector<OscBundle>& bundles) {
  TuioDecoder d;
  for (const OscBundle& b : bundles) d.Decode(b, 0.0);
  EXPECT_EQ(d.stats().TotalDropped(), 0u) << d.stats().Summary();
  return d.TakeFrames();
}

const TuioContact* Find(const TuioFrame& f, TuioSessionId id) {
  for (const TuioContact& c : f.contacts)
    if (c.id == id) return &c;
  return nullptr;
}

TEST(SimplifyClosed, DropsCollinearPointsAndKeepsCorners) {
  std::vector<Vec2> square;
  for (int k = 0; k < 10; ++k) square.push_back(Vec2(k, 0));
  for (int k = 0; k < 10; ++k) square.push_back(Vec2(10, k));
  for (int k = 0; k < 10; ++k) square.push_back(Vec2(10 - k, 10));
  for (int k = 0; k < 10; ++k) square.push_back(Vec2(0, 10 - k));
  const std::vector<Vec2> s = SimplifyClosed(square, 0.01);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0], Vec2(0, 0));
  EXPECT_EQ(s[2], Vec2(10, 10));
}

TEST(SimplifyClosed, StaysWithinToleranceAndKeepsATriangle) {
  const std::vector<Vec2> star = Star(Vec2(10, 10), 3.0, 400);
  for (double tolerance : {0.01, 0.05, 0.2, 1.0}) {
    const std::vector<Vec2> s = SimplifyClosed(star, tolerance);
    EXPECT_LT(s.size(), star.size());
    // every dropped point lies within the tolerance of the kept outline
    EXPECT_LE(HausdorffDistance(ToContour(s), ToContour(star)), tolerance + 1e-9) << tolerance;
  }
  EXPECT_EQ(SimplifyClosed(star, 100.0).size(), 3u);
  EXPECT_EQ(SimplifyClosed(std::vector<Vec2>{Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}, 5.0).size(), 3u);
}

TEST(PrincipalBox, FindsTheAxesAndExtentsOfATurnedRectangle) {
  const double angle = 0.5;  // rad
  std::vector<Vec2> rect;
  for (const Vec2& corner : {Vec2(-3, -1), Vec2(3, -1), Vec2(3, 1), Vec2(-3, 1)})
    rect.push_back(Vec2(5, 6) + Rotate(corner, angle));
  const OrientedBox box = PrincipalBox(rect);
  EXPECT_NEAR(box.angle, angle, 1e-9);
  EXPECT_NEAR(box.width, 6.0, 1e-9);
  EXPECT_NEAR(box.height, 2.0, 1e-9);
  EXPECT_NEAR((box.centre - Vec2(5, 6)).norm(), 0.0, 1e-9);
}

TEST(TuioEncoder, OneFrameIsFrmPtrBndOcgAlv) {
  TuioEncoder e;
  const std::vector<TuioOutContact> contacts = {Out(7, Ellipse(Vec2(20, 10), 1, 1, 0, 32))};
  const std::vector<OscBundle> bundles = e.Encode(42, OscTimeTag{3, 4}, contacts);
  ASSERT_EQ(bundles.size(), 1u);
  const OscBundle& b = bundles[0];
  EXPECT_EQ(b.time, (OscTimeTag{3, 4}));
  ASSERT_EQ(b.messages.size(), 5u);
  EXPECT_EQ(b.messages[0].address, "/tuio2/frm");
  EXPECT_EQ(b.messages[0].Types(), "itis");
  EXPECT_EQ(b.messages[0].args[0].i, 42);
  EXPECT_EQ(b.messages[0].args[2].i, (640 << 16) | 480);
  EXPECT_EQ(b.messages[0].args[3].s, "proxygrasp");
  EXPECT_EQ(b.messages[1].address, "/tuio2/ptr");
  EXPECT_EQ(b.messages[1].Types(), "iiiffffff");
  EXPECT_NEAR(b.messages[1].args[3].f, 20.0 / 61.0, 1e-6);
  EXPECT_NEAR(b.messages[1].args[4].f, 1.0 - 10.0 / 46.0, 1e-6);
  EXPECT_EQ(b.messages[2].address, "/tuio2/bnd");
  EXPECT_EQ(b.messages[2].Types(), "iffffff");
  EXPECT_NEAR(b.messages[2].args[4].f, 2.0 / 61.0, 1e-3);  // width
  EXPECT_NEAR(b.messages[2].args[5].f, 2.0 / 46.0, 1e-3);  // height
  EXPECT_EQ(b.messages[3].address, "/tuio2/ocg");
  EXPECT_EQ(b.messages[3].args[0].i, 7);
  EXPECT_EQ(b.messages[3].args.size() % 2, 1u);
  EXPECT_EQ(b.messages[4].address, "/tuio2/alv");
  EXPECT_EQ(b.messages[4].Types(), "i");
  EXPECT_EQ(b.messages[4].args[0].i, 7);
}

TEST(TuioEncoder, ADepthContactAlsoSendsA3dPointerWithItsHeight) {
  TuioEncoder e;  // 61 x 46 cm
  std::vector<TuioOutContact> contacts = {Out(7, Ellipse(Vec2(20, 10), 1, 1, 0, 32)),
                                          Out(8, Ellipse(Vec2(40, 30), 1, 1, 0, 32))};
  contacts[0].height = 1.5;  // cm
  const std::vector<OscBundle> bundles = e.Encode(3, {}, contacts);
  ASSERT_EQ(bundles.size(), 1u);
  const OscBundle& b = bundles[0];
  // frm, then ptr bnd ocg p3d for the contact with a height, ptr bnd ocg for the one without
  ASSERT_EQ(b.messages.size(), 9u);
  EXPECT_EQ(b.messages[3].address, "/tuio2/ocg");
  const OscMessage& p3d = b.messages[4];
  EXPECT_EQ(p3d.address, "/tuio2/p3d");
  EXPECT_EQ(p3d.Types(), "iiifffffff");
  EXPECT_EQ(p3d.args[0].i, 7);
  // x, y as the pointer's; z = 1.5 cm / 61 cm (the table's width, the unit of x); no direction;
  // the pointer's radius
  const OscMessage& ptr = b.messages[1];
  EXPECT_EQ(p3d.args[3].f, ptr.args[3].f);
  EXPECT_EQ(p3d.args[4].f, ptr.args[4].f);
  EXPECT_NEAR(p3d.args[5].f, 1.5 / 61.0, 1e-7);
  for (int k = 6; k < 9; ++k) EXPECT_EQ(p3d.args[k].f, 0.0) << k;
  EXPECT_EQ(p3d.args[9].f, ptr.args[7].f);
  EXPECT_EQ(b.messages[5].address, "/tuio2/ptr");
  EXPECT_EQ(b.messages[7].address, "/tuio2/ocg");
  EXPECT_EQ(b.messages[8].address, "/tuio2/alv");

  // decoded: the height comes back within float32's quantisation of z (1.5 cm * 2^-24, 1e-7 cm;
  // 1e-6 allows the division and multiplication by the width), the other contact has none
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  const TuioContact* got = Find(frames[0], 7);
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(got->shape, TuioShape::kContour);
  ASSERT_TRUE(got->height);
  EXPECT_NEAR(*got->height, 1.5, 1e-6);
  ASSERT_NE(Find(frames[0], 8), nullptr);
  EXPECT_FALSE(Find(frames[0], 8)->height);

  // a client that ignores p3d sees the same contacts: the frame without its p3d decodes to the
  // same outlines
  OscBundle without = b;
  std::erase_if(without.messages, [](const OscMessage& m) { return m.address == "/tuio2/p3d"; });
  const std::vector<TuioFrame> flat = DecodeAll({without});
  ASSERT_EQ(flat.size(), 1u);
  ASSERT_EQ(flat[0].contacts.size(), 2u);
  for (const TuioContact& c : flat[0].contacts) {
    EXPECT_EQ(c.contour, Find(frames[0], c.id)->contour) << c.id;
    EXPECT_FALSE(c.height);
  }
}

TEST(TuioEncoder, HeightsFitBundlesAndRoundTripForManyContacts) {
  TuioEncoder e;
  std::vector<TuioOutContact> contacts;
  for (int k = 0; k < 60; ++k) {
    contacts.push_back(
        Out(100 + k, Ellipse(Vec2(5 + (k % 10) * 5.5, 5 + (k / 10) * 6.5), 1.2, 0.9, 0.1 * k, 48)));
    contacts.back().height = 0.05 * k;  // 0 to 2.95 cm
  }
  const std::vector<OscBundle> bundles = e.Encode(9, {}, contacts);
  EXPECT_GT(bundles.size(), 1u);
  for (size_t k = 0; k < bundles.size(); ++k) {
    EXPECT_LE(OscBundleSize(bundles[k]), 1472u) << "bundle " << k;
    // each p3d travels right after its contact's ocg
    for (size_t m = 1; m < bundles[k].messages.size(); ++m) {
      if (bundles[k].messages[m].address != "/tuio2/p3d") continue;
      EXPECT_EQ(bundles[k].messages[m - 1].address, "/tuio2/ocg");
      EXPECT_EQ(bundles[k].messages[m - 1].args[0].i, bundles[k].messages[m].args[0].i);
    }
  }
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].contacts.size(), contacts.size());
  for (const TuioOutContact& sent : contacts) {
    const TuioContact* got = Find(frames[0], sent.id);
    ASSERT_NE(got, nullptr);
    ASSERT_TRUE(got->height) << sent.id;
    // float32 z: 3 cm * 2^-24 is 2e-7 cm
    EXPECT_NEAR(*got->height, *sent.height, 1e-6) << sent.id;
  }
  EXPECT_EQ(e.stats().droppedContacts, 0u);
}

TEST(TuioEncoder, AnEmptyFrameIsFrmAndAnEmptyAlv) {
  TuioEncoder e;
  const std::vector<OscBundle> bundles = e.Encode(1, {}, {});
  ASSERT_EQ(bundles.size(), 1u);
  ASSERT_EQ(bundles[0].messages.size(), 2u);
  EXPECT_EQ(bundles[0].messages[1].address, "/tuio2/alv");
  EXPECT_TRUE(bundles[0].messages[1].args.empty());
}

TEST(TuioEncoder, RoundTripKeepsContoursWithinTolerance) {
  TuioEncoder e;
  const std::vector<TuioOutContact> contacts = {
      Out(1, Ellipse(Vec2(10, 10), 0.8, 0.8, 0.0, 24)),  // a fingertip
      Out(2, Ellipse(Vec2(30, 20), 2.0, 1.0, 0.7, 40)),  // a flat finger
      Out(3, Star(Vec2(45, 30), 4.0, 120)),              // a hand-like outline
  };
  const std::vector<OscBundle> bundles = e.Encode(5, {}, contacts);
  for (const OscBundle& b : bundles) EXPECT_LE(OscBundleSize(b), 1472u);
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].contacts.size(), 3u);
  for (const TuioOutContact& sent : contacts) {
    const TuioContact* got = Find(frames[0], sent.id);
    ASSERT_NE(got, nullptr) << sent.id;
    EXPECT_EQ(got->shape, TuioShape::kContour);
    EXPECT_LE(HausdorffDistance(ToContour(got->contour), ToContour(sent.contour)), kRoundTripTol)
        << sent.id;
    EXPECT_NEAR((got->centroid - sent.centroid).norm(), 0.0, kRoundTripTol) << sent.id;
  }
}

TEST(TuioEncoder, ALongContourIsSimplifiedToFitOneDatagram) {
  TuioEncoder e;
  // 4096 points around a wiggly hand-sized outline: far more than 1,472 bytes of floats
  std::vector<Vec2> wiggly;
  for (int k = 0; k < 4096; ++k) {
    const double t = 2.0 * kPi * k / 4096;
    const double r = 6.0 + 0.3 * std::sin(37.0 * t) + 1.5 * std::cos(5.0 * t);
    wiggly.push_back(Vec2(30, 23) + r * Vec2(std::cos(t), std::sin(t)));
  }
  const std::vector<TuioOutContact> contacts = {Out(1, wiggly)};
  const std::vector<OscBundle> bundles = e.Encode(1, {}, contacts);
  ASSERT_EQ(bundles.size(), 1u);
  EXPECT_LE(OscBundleSize(bundles[0]), 1472u);
  EXPECT_EQ(e.stats().coarsened, 1u);
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].contacts.size(), 1u);
  // coarser than the tolerance, yet still the outline: within a few millimetres
  EXPECT_LE(HausdorffDistance(ToContour(frames[0].contacts[0].contour), ToContour(wiggly)), 0.5);
}

TEST(TuioEncoder, ManyContactsAreSplitOverBundlesOfTheSameFrame) {
  TuioEncoder e;
  std::vector<TuioOutContact> contacts;
  for (int k = 0; k < 60; ++k)
    contacts.push_back(
        Out(100 + k, Ellipse(Vec2(5 + (k % 10) * 5.5, 5 + (k / 10) * 6.5), 1.2, 0.9, 0.1 * k, 48)));
  const std::vector<OscBundle> bundles = e.Encode(9, {}, contacts);
  EXPECT_GT(bundles.size(), 1u);
  std::set<int64_t> seen;
  for (size_t k = 0; k < bundles.size(); ++k) {
    const OscBundle& b = bundles[k];
    EXPECT_LE(OscBundleSize(b), 1472u) << "bundle " << k;
    ASSERT_FALSE(b.messages.empty());
    EXPECT_EQ(b.messages.front().address, "/tuio2/frm");
    EXPECT_EQ(b.messages.front().args[0].i, 9);
    EXPECT_EQ(b.messages.back().address == "/tuio2/alv", k + 1 == bundles.size());
    // a contact's ptr, bnd and ocg travel together
    for (size_t m = 1; m + 2 < b.messages.size(); m += 3) {
      EXPECT_EQ(b.messages[m].address, "/tuio2/ptr");
      EXPECT_EQ(b.messages[m + 1].address, "/tuio2/bnd");
      EXPECT_EQ(b.messages[m + 2].address, "/tuio2/ocg");
      EXPECT_EQ(b.messages[m].args[0].i, b.messages[m + 2].args[0].i);
      seen.insert(b.messages[m].args[0].i);
    }
  }
  EXPECT_EQ(seen.size(), contacts.size());
  EXPECT_EQ(bundles.back().messages.back().args.size(), contacts.size());
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].contacts.size(), contacts.size());
  for (const TuioOutContact& sent : contacts) {
    const TuioContact* got = Find(frames[0], sent.id);
    ASSERT_NE(got, nullptr);
    EXPECT_LE(HausdorffDistance(ToContour(got->contour), ToContour(sent.contour)), kRoundTripTol);
  }
  EXPECT_EQ(e.stats().droppedContacts, 0u);
}

TEST(TuioEncoder, ContactsBeyondWhatAlvCanNameAreDroppedAndCounted) {
  TuioEncoder e;
  std::vector<TuioOutContact> contacts;
  for (int k = 0; k < 400; ++k)
    contacts.push_back(
        Out(k + 1, Ellipse(Vec2(1 + (k % 20) * 3, 1 + (k / 20) * 2.2), 0.5, 0.5, 0, 8)));
  contacts.push_back(TuioOutContact{});  // no outline at all
  const std::vector<OscBundle> bundles = e.Encode(1, {}, contacts);
  for (const OscBundle& b : bundles) EXPECT_LE(OscBundleSize(b), 1472u);
  EXPECT_GT(e.stats().droppedContacts, 1u);
  const size_t named = bundles.back().messages.back().args.size();
  EXPECT_EQ(named + e.stats().droppedContacts, contacts.size());
  // bundles are filled: only the last one carries the long alv
  EXPECT_LT(bundles.size(), named / 3);
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].contacts.size(), named);
}

TEST(TuioEncoder, Tuio11CursorsForOlderClients) {
  TuioEncoderParams p;
  p.cursors11 = true;
  TuioEncoder e(p);
  const std::vector<TuioOutContact> contacts = {Out(3, Ellipse(Vec2(30.5, 23), 1, 1, 0, 16)),
                                                Out(4, Ellipse(Vec2(10, 40), 1, 1, 0, 16))};
  std::vector<OscBundle> bundles = e.Encode(1, OscTimeTag::FromSeconds(100.0), contacts);
  ASSERT_EQ(bundles.size(), 2u);
  const OscBundle& cur = bundles[1];
  ASSERT_EQ(cur.messages.size(), 5u);
  EXPECT_EQ(FormatOscMessage(cur.messages[0]), "/tuio/2Dcur ss \"source\" \"proxygrasp\"");
  EXPECT_EQ(FormatOscMessage(cur.messages[1]), "/tuio/2Dcur sii \"alive\" 3 4");
  EXPECT_EQ(cur.messages[2].Types(), "sifffff");
  EXPECT_NEAR(cur.messages[2].args[2].f, 0.5, 1e-6);
  EXPECT_NEAR(cur.messages[2].args[3].f, 0.5, 1e-6);
  EXPECT_EQ(FormatOscMessage(cur.messages[4]), "/tuio/2Dcur si \"fseq\" 1");

  // the next frame 0.1 s later has velocities in normalised units per second
  const std::vector<TuioOutContact> moved = {Out(3, Ellipse(Vec2(36.6, 23), 1, 1, 0, 16))};
  bundles = e.Encode(2, OscTimeTag::FromSeconds(100.1), moved);
  EXPECT_NEAR(bundles[1].messages[2].args[4].f, 1.0, 1e-3);

  // decoded alone, the 1.1 bundle gives fingertips at the centroids
  TuioDecoder d;
  d.Decode(bundles[1], 0.0);
  const std::vector<TuioFrame> frames = d.TakeFrames();
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].contacts.size(), 1u);
  EXPECT_EQ(frames[0].contacts[0].shape, TuioShape::kCursor);
  EXPECT_NEAR((frames[0].contacts[0].centroid - Vec2(36.6, 23)).norm(), 0.0, 1e-4);
}

TEST(TuioEncoder, ASmallerDatagramLimitIsHonoured) {
  TuioEncoderParams p;
  p.maxBundleBytes = 512;
  TuioEncoder e(p);
  std::vector<TuioOutContact> contacts;
  for (int k = 0; k < 8; ++k) contacts.push_back(Out(k + 1, Star(Vec2(8 + 6 * k, 20), 2.5, 200)));
  const std::vector<OscBundle> bundles = e.Encode(1, {}, contacts);
  for (const OscBundle& b : bundles) EXPECT_LE(OscBundleSize(b), 512u);
  const std::vector<TuioFrame> frames = DecodeAll(bundles);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].contacts.size(), contacts.size());
}

}  // namespace
}  // namespace pg
