#include "proxygrasp/tuio/decoder.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pg {
namespace {

// float32 normalised coordinates on a 61 cm table are good to about 4e-6 cm
constexpr double kFloatTol = 1e-4;  // cm

OscMessage Msg(std::string address, std::vector<OscArg> args) {
  return OscMessage{std::move(address), std::move(args)};
}
OscArg I(int32_t v) {
  return OscArg::Int(v);
}
OscArg F(double v) {
  return OscArg::Float(static_cast<float>(v));
}
OscArg S(std::string v) {
  return OscArg::String(std::move(v));
}

OscMessage Frm(int32_t id) {
  return Msg("/tuio2/frm", {I(id), OscArg::Time({}), I((640 << 16) | 480), S("test")});
}
OscMessage Alv(std::vector<int32_t> ids) {
  OscMessage m = Msg("/tuio2/alv", {});
  for (int32_t id : ids) m.args.push_back(I(id));
  return m;
}
// a square outline of side s (normalised) with its lower-left TUIO corner at (u, v)
OscMessage Square(int32_t id, double u, double v, double s) {
  return Msg("/tuio2/ocg", {I(id), F(u), F(v), F(u + s), F(v), F(u + s), F(v + s), F(u), F(v + s)});
}
OscMessage Ptr(int32_t id, double u, double v) {
  return Msg("/tuio2/ptr", {I(id), I(0), I(0), F(u), F(v), F(0), F(0), F(0.01), F(1)});
}
OscMessage CurSet(int32_t id, double u, double v) {
  return Msg("/tuio/2Dcur", {S("set"), I(id), F(u), F(v), F(0), F(0), F(0)});
}
OscMessage CurAlive(std::vector<int32_t> ids) {
  OscMessage m = Msg("/tuio/2Dcur", {S("alive")});
  for (int32_t id : ids) m.args.push_back(I(id));
  return m;
}
OscMessage CurFseq(int32_t f) {
  return Msg("/tuio/2Dcur", {S("fseq"), I(f)});
}

OscBundle B(std::vector<OscMessage> messages) {
  return OscBundle{{}, std::move(messages)};
}

// decodes one bundle and returns the single frame it completed
TuioFrame One(TuioDecoder& d, const OscBundle& b, double now = 0.0) {
  d.Decode(b, now);
  std::vector<TuioFrame> frames = d.TakeFrames();
  EXPECT_EQ(frames.size(), 1u);
  return frames.empty() ? TuioFrame() : frames.back();
}

const TuioContact* Find(const TuioFrame& f, TuioSessionId id) {
  for (const TuioContact& c : f.contacts)
    if (c.id == id) return &c;
  return nullptr;
}

double SignedAreaOf(const std::vector<Vec2>& p) {
  return SignedArea(ToContour(p));
}

TEST(TuioDecoder, Tuio2ContourMapsOntoTheTableInCentimetres) {
  TuioDecoder d;  // 61 x 46 cm, y flipped
  const TuioFrame f = One(d, B({Frm(7), Square(3, 0.25, 0.5, 0.1), Alv({3})}));
  EXPECT_EQ(f.frame, 7);
  ASSERT_EQ(f.contacts.size(), 1u);
  const TuioContact& c = f.contacts[0];
  EXPECT_EQ(c.id, 3);
  EXPECT_TRUE(c.isNew);
  EXPECT_EQ(c.shape, TuioShape::kContour);
  ASSERT_EQ(c.contour.size(), 4u);
  // TUIO (0.25, 0.5)..(0.35, 0.6) with y down is x 15.25..21.35 cm, y 18.4..23 cm on the table
  double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
  for (const Vec2& p : c.contour) {
    minX = std::min(minX, p.x());
    maxX = std::max(maxX, p.x());
    minY = std::min(minY, p.y());
    maxY = std::max(maxY, p.y());
  }
  EXPECT_NEAR(minX, 0.25 * 61.0, kFloatTol);
  EXPECT_NEAR(maxX, 0.35 * 61.0, kFloatTol);
  EXPECT_NEAR(minY, 0.4 * 46.0, kFloatTol);
  EXPECT_NEAR(maxY, 0.5 * 46.0, kFloatTol);
  EXPECT_GT(SignedAreaOf(c.contour), 0.0) << "contours come out counter-clockwise";
  EXPECT_NEAR(c.centroid.x(), 0.3 * 61.0, kFloatTol);
  EXPECT_NEAR(c.centroid.y(), 0.45 * 46.0, kFloatTol);
}

TEST(TuioDecoder, FlipYOffKeepsTuioY) {
  TuioParams p;
  p.flipY = false;
  TuioDecoder d(p);
  const TuioFrame f = One(d, B({Frm(1), Ptr(1, 0.5, 0.25), Alv({1})}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_NEAR(f.contacts[0].centroid.y(), 0.25 * 46.0, kFloatTol);
}

TEST(TuioDecoder, SessionsContinueKeepTheirShapeAndLiftWhenMissingFromAlive) {
  TuioDecoder d;
  TuioFrame f =
      One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Square(2, 0.5, 0.5, 0.1), Alv({1, 2})}));
  ASSERT_EQ(f.contacts.size(), 2u);
  EXPECT_TRUE(f.contacts[0].isNew && f.contacts[1].isNew);
  EXPECT_TRUE(f.lifted.empty());

  // 1 moves, 2 sends nothing but stays alive: it keeps its last outline
  const Vec2 before = Find(f, 2)->centroid;
  f = One(d, B({Frm(2), Square(1, 0.2, 0.1, 0.1), Alv({1, 2})}));
  ASSERT_EQ(f.contacts.size(), 2u);
  EXPECT_FALSE(Find(f, 1)->isNew);
  EXPECT_FALSE(Find(f, 2)->isNew);
  EXPECT_NEAR(Find(f, 1)->centroid.x(), 0.25 * 61.0, kFloatTol);
  EXPECT_NEAR((Find(f, 2)->centroid - before).norm(), 0.0, 1e-12);

  // 2 leaves alive: lifted; 3 arrives
  f = One(d, B({Frm(3), Square(3, 0.7, 0.7, 0.1), Alv({1, 3})}));
  EXPECT_EQ(f.lifted, std::vector<TuioSessionId>{2});
  ASSERT_EQ(f.contacts.size(), 2u);
  EXPECT_TRUE(Find(f, 3)->isNew);
  EXPECT_EQ(Find(f, 2), nullptr);
  EXPECT_EQ(d.LiveCount(), 2);
  EXPECT_EQ(d.stats().TotalDropped(), 0u);
}

TEST(TuioDecoder, ContourBeatsBoundsBeatsPointer) {
  TuioDecoder d;
  OscMessage bnd = Msg("/tuio2/bnd", {I(5), F(0.5), F(0.5), F(0.0), F(0.2), F(0.1), F(0.01)});
  TuioFrame f = One(d, B({Frm(1), Ptr(5, 0.5, 0.5), bnd, Alv({5})}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_EQ(f.contacts[0].shape, TuioShape::kBounds);
  f = One(d, B({Frm(2), Square(5, 0.4, 0.4, 0.2), Ptr(5, 0.5, 0.5), Alv({5})}));
  EXPECT_EQ(f.contacts[0].shape, TuioShape::kContour);
}

// a 3D pointer: x, y and z normalised, z in units of the table's width (docs/tuio.md)
OscMessage P3d(int32_t id, double u, double v, double z) {
  return Msg("/tuio2/p3d", {I(id), I(0), I(0), F(u), F(v), F(z), F(0), F(0), F(0), F(0.01)});
}

TEST(TuioDecoder, A3dPointerGivesItsContactAHeight) {
  TuioDecoder d;  // 61 x 46 cm
  // alone, p3d is a fingertip circle like ptr, at z 0.02 table widths: 0.02 * 61 = 1.22 cm;
  // float32 z keeps it to 1.22 * 2^-24, far inside kFloatTol
  TuioFrame f = One(d, B({Frm(1), P3d(4, 0.5, 0.25, 0.02), Alv({4})}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_EQ(f.contacts[0].shape, TuioShape::kPointer);
  ASSERT_TRUE(f.contacts[0].height);
  EXPECT_NEAR(*f.contacts[0].height, 0.02 * 61.0, kFloatTol);
  EXPECT_NEAR(f.contacts[0].centroid.x(), 0.5 * 61.0, kFloatTol);
  EXPECT_NEAR(f.contacts[0].centroid.y(), 0.75 * 46.0, kFloatTol);
  // with an outline the outline is the shape, the height still comes from p3d, in either order
  f = One(d, B({Frm(2), P3d(4, 0.5, 0.25, 0.01), Square(4, 0.45, 0.2, 0.1), Alv({4})}));
  EXPECT_EQ(f.contacts[0].shape, TuioShape::kContour);
  ASSERT_TRUE(f.contacts[0].height);
  EXPECT_NEAR(*f.contacts[0].height, 0.01 * 61.0, kFloatTol);
  // a frame without shapes keeps the last shape and height
  f = One(d, B({Frm(3), Alv({4})}));
  ASSERT_TRUE(f.contacts[0].height);
  EXPECT_NEAR(*f.contacts[0].height, 0.01 * 61.0, kFloatTol);
  // a new shape without p3d: the sender no longer gives a height
  f = One(d, B({Frm(4), Square(4, 0.45, 0.2, 0.1), Alv({4})}));
  EXPECT_FALSE(f.contacts[0].height);
  // 2D messages and TUIO 1.1 cursors never carry one
  f = One(d, B({CurAlive({9}), CurSet(9, 0.2, 0.2), CurFseq(1)}));
  ASSERT_NE(Find(f, 9), nullptr);
  EXPECT_FALSE(Find(f, 9)->height);
  EXPECT_EQ(d.stats().TotalDropped(), 0u) << d.stats().Summary();
  EXPECT_EQ(d.stats().ignored, 0u);
}

TEST(TuioDecoder, BoundsBecomeAnEllipseOfTheirSize) {
  TuioDecoder d;
  // width 0.2 of 61 cm, height 0.1 of 46 cm, turned a quarter turn (clockwise in TUIO's y-down
  // frame is counter-clockwise on the table)
  OscMessage bnd = Msg("/tuio2/bnd", {I(5), F(0.5), F(0.5), F(kPi / 2), F(0.2), F(0.1), F(0)});
  const TuioFrame f = One(d, B({Frm(1), bnd, Alv({5})}));
  const std::vector<Vec2>& c = f.contacts.at(0).contour;
  ASSERT_EQ(static_cast<int>(c.size()), TuioParams().circlePoints);
  double extentX = 0.0, extentY = 0.0;
  for (const Vec2& p : c) {
    extentX = std::max(extentX, std::abs(p.x() - 30.5));
    extentY = std::max(extentY, std::abs(p.y() - 23.0));
  }
  EXPECT_NEAR(extentX, 0.05 * 46.0, 1e-3) << "the short axis lies along x after the turn";
  EXPECT_NEAR(extentY, 0.1 * 61.0, 1e-3);
}

TEST(TuioDecoder, Tuio11CursorsBecomeFingertipCircles) {
  TuioParams p;
  p.cursorRadius = 1.0;
  TuioDecoder d(p);
  TuioFrame f = One(d, B({CurAlive({4}), CurSet(4, 0.5, 0.5), CurFseq(10)}));
  EXPECT_EQ(f.frame, 10);
  ASSERT_EQ(f.contacts.size(), 1u);
  const TuioContact& c = f.contacts[0];
  EXPECT_EQ(c.shape, TuioShape::kCursor);
  EXPECT_EQ(static_cast<int>(c.contour.size()), p.circlePoints);
  for (const Vec2& q : c.contour) EXPECT_NEAR((q - Vec2(30.5, 23.0)).norm(), 1.0, 1e-9);
  EXPECT_NEAR(c.centroid.x(), 30.5, kFloatTol);

  // set and alive in either order; fseq ends the frame
  f = One(d, B({CurSet(4, 0.6, 0.5), CurAlive({4}), CurFseq(11)}));
  EXPECT_FALSE(f.contacts.at(0).isNew);
  EXPECT_NEAR(f.contacts[0].centroid.x(), 0.6 * 61.0, kFloatTol);
  f = One(d, B({CurAlive({}), CurFseq(12)}));
  EXPECT_TRUE(f.contacts.empty());
  EXPECT_EQ(f.lifted, std::vector<TuioSessionId>{4});
}

TEST(TuioDecoder, Tuio11BlobsBecomeEllipsesOfTheirSize) {
  TuioDecoder d;
  OscMessage set = Msg("/tuio/2Dblb", {S("set"), I(9), F(0.5), F(0.5), F(0.0), F(0.1), F(0.2),
                                       F(0.02), F(0), F(0), F(0), F(0), F(0)});
  const TuioFrame f = One(
      d, B({Msg("/tuio/2Dblb", {S("alive"), I(9)}), set, Msg("/tuio/2Dblb", {S("fseq"), I(1)})}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_EQ(f.contacts[0].shape, TuioShape::kBlob);
  double extentX = 0.0, extentY = 0.0;
  for (const Vec2& p : f.contacts[0].contour) {
    extentX = std::max(extentX, std::abs(p.x() - 30.5));
    extentY = std::max(extentY, std::abs(p.y() - 23.0));
  }
  EXPECT_NEAR(extentX, 0.05 * 61.0, 1e-3);
  EXPECT_NEAR(extentY, 0.1 * 46.0, 1e-3);
}

TEST(TuioDecoder, ProfilesLiftOnlyTheirOwnSessions) {
  TuioDecoder d;
  One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})}));
  TuioFrame f = One(d, B({CurAlive({50}), CurSet(50, 0.5, 0.5), CurFseq(1)}));
  EXPECT_EQ(f.contacts.size(), 2u) << "a cursor frame keeps the TUIO 2.0 contact";
  f = One(d, B({Frm(2), Alv({})}));
  EXPECT_EQ(f.lifted, std::vector<TuioSessionId>{1});
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_EQ(f.contacts[0].id, 50);
}

TEST(TuioDecoder, AFrameSplitOverBundlesRepeatsItsFrm) {
  TuioDecoder d;
  d.Decode(B({Frm(4), Square(1, 0.1, 0.1, 0.1)}), 0.0);
  EXPECT_TRUE(d.TakeFrames().empty());
  const TuioFrame f = One(d, B({Frm(4), Square(2, 0.5, 0.5, 0.1), Alv({1, 2})}));
  EXPECT_EQ(f.contacts.size(), 2u);
  EXPECT_EQ(d.stats()[TuioDrop::kIncompleteFrame], 0u);
}

TEST(TuioDecoder, MessagesSentAloneStillMakeFrames) {
  TuioDecoder d;
  const std::vector<OscMessage> stream = {Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})};
  for (const OscMessage& m : stream) d.Decode(std::span(&m, 1), 0.0);
  const std::vector<TuioFrame> frames = d.TakeFrames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].contacts.size(), 1u);
  EXPECT_EQ(d.stats().packets, 3u);
}

TEST(TuioDecoder, LateFramesAreDroppedButARestartIsTaken) {
  TuioDecoder d;
  One(d, B({Frm(500), Square(1, 0.1, 0.1, 0.1), Alv({1})}));
  d.Decode(B({Frm(499), Alv({})}), 0.0);
  EXPECT_TRUE(d.TakeFrames().empty());
  EXPECT_EQ(d.stats()[TuioDrop::kLateFrame], 1u);
  EXPECT_EQ(d.LiveCount(), 1) << "the late frame lifted nothing";
  // far below the last id: the sender restarted
  const TuioFrame f = One(d, B({Frm(1), Alv({})}));
  EXPECT_EQ(f.lifted, std::vector<TuioSessionId>{1});
  // TUIO 1.1 fseq -1 is always taken
  One(d, B({CurAlive({2}), CurSet(2, 0.5, 0.5), CurFseq(100)}));
  One(d, B({CurAlive({2}), CurSet(2, 0.5, 0.5), CurFseq(-1)}));
  One(d, B({CurAlive({2}), CurSet(2, 0.5, 0.5), CurFseq(-1)}));
}

TEST(TuioDecoder, ANewFrmBeforeAlvDropsTheIncompleteFrame) {
  TuioDecoder d;
  d.Decode(B({Frm(1), Square(1, 0.1, 0.1, 0.1)}), 0.0);
  const TuioFrame f = One(d, B({Frm(2), Square(2, 0.5, 0.5, 0.1), Alv({2})}));
  EXPECT_EQ(d.stats()[TuioDrop::kIncompleteFrame], 1u);
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_EQ(f.contacts[0].id, 2);
}

TEST(TuioDecoder, AMalformedShapeOpensNoFrame) {
  TuioDecoder d;
  // a NaN outline sent alone, then a proper frame: one drop, and no incomplete frame
  const OscMessage bad =
      Msg("/tuio2/ocg", {I(1), F(0.1), F(std::nan("")), F(0.2), F(0.1), F(0.2), F(0.2)});
  d.Decode(std::span(&bad, 1), 0.0);
  One(d, B({Frm(1), Square(2, 0.5, 0.5, 0.1), Alv({2})}));
  EXPECT_EQ(d.stats()[TuioDrop::kNonFinite], 1u);
  EXPECT_EQ(d.stats().TotalDropped(), 1u) << d.stats().Summary();
}

TEST(TuioDecoder, AliveWithoutAShapeWaitsForOne) {
  TuioDecoder d;
  TuioFrame f = One(d, B({Frm(1), Alv({8})}));
  EXPECT_TRUE(f.contacts.empty());
  f = One(d, B({Frm(2), Square(8, 0.1, 0.1, 0.1), Alv({8})}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_TRUE(f.contacts[0].isNew);
}

// ---- malformed input: each class is counted under its reason and dropped ----

struct BadCase {
  const char* name;
  OscMessage message;
  TuioDrop reason;
};

std::vector<BadCase> BadCases() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  OscMessage tooManyPoints = Msg("/tuio2/ocg", {I(1)});
  for (int k = 0; k < 10000; ++k) {
    const double t = 2.0 * kPi * k / 10000;
    tooManyPoints.args.push_back(F(0.5 + 0.1 * std::cos(t)));
    tooManyPoints.args.push_back(F(0.5 + 0.1 * std::sin(t)));
  }
  return {
      {"unknown address", Msg("/foo/bar", {I(1)}), TuioDrop::kUnknownAddress},
      {"unknown 2Dcur command", Msg("/tuio/2Dcur", {S("jump"), I(1)}), TuioDrop::kUnknownCommand},
      {"2Dcur without args", Msg("/tuio/2Dcur", {}), TuioDrop::kTooFewArgs},
      {"2Dcur command not a string", Msg("/tuio/2Dcur", {I(1)}), TuioDrop::kWrongType},
      {"2Dcur set too short", Msg("/tuio/2Dcur", {S("set"), I(1), F(0.5)}), TuioDrop::kTooFewArgs},
      {"2Dcur set id a float", Msg("/tuio/2Dcur", {S("set"), F(1), F(0.5), F(0.5)}),
       TuioDrop::kWrongType},
      {"2Dcur set x a string", Msg("/tuio/2Dcur", {S("set"), I(1), S("x"), F(0.5)}),
       TuioDrop::kWrongType},
      {"2Dcur set NaN", Msg("/tuio/2Dcur", {S("set"), I(1), F(nan), F(0.5)}), TuioDrop::kNonFinite},
      {"2Dcur set inf", Msg("/tuio/2Dcur", {S("set"), I(1), F(0.5), F(inf)}), TuioDrop::kNonFinite},
      {"2Dcur set out of range", Msg("/tuio/2Dcur", {S("set"), I(1), F(1.2), F(0.5)}),
       TuioDrop::kOutOfRange},
      {"2Dcur set below range", Msg("/tuio/2Dcur", {S("set"), I(1), F(0.5), F(-0.1)}),
       TuioDrop::kOutOfRange},
      {"2Dcur alive a string", Msg("/tuio/2Dcur", {S("alive"), I(1), S("2")}),
       TuioDrop::kWrongType},
      {"2Dcur fseq without id", Msg("/tuio/2Dcur", {S("fseq")}), TuioDrop::kTooFewArgs},
      {"2Dcur fseq a float", Msg("/tuio/2Dcur", {S("fseq"), F(3)}), TuioDrop::kWrongType},
      {"2Dblb set too short", Msg("/tuio/2Dblb", {S("set"), I(1), F(0.5), F(0.5), F(0)}),
       TuioDrop::kTooFewArgs},
      {"2Dblb set NaN angle",
       Msg("/tuio/2Dblb", {S("set"), I(1), F(0.5), F(0.5), F(nan), F(0.1), F(0.1)}),
       TuioDrop::kNonFinite},
      {"2Dblb set huge width",
       Msg("/tuio/2Dblb", {S("set"), I(1), F(0.5), F(0.5), F(0), F(5), F(0.1)}),
       TuioDrop::kOutOfRange},
      {"frm without id", Msg("/tuio2/frm", {}), TuioDrop::kTooFewArgs},
      {"frm id a string", Msg("/tuio2/frm", {S("1")}), TuioDrop::kWrongType},
      {"ocg without args", Msg("/tuio2/ocg", {}), TuioDrop::kTooFewArgs},
      {"ocg id a float", Msg("/tuio2/ocg", {F(1), F(0.1), F(0.1), F(0.2), F(0.1), F(0.2), F(0.2)}),
       TuioDrop::kWrongType},
      {"ocg odd coordinates", Msg("/tuio2/ocg", {I(1), F(0.1), F(0.1), F(0.2), F(0.1), F(0.2)}),
       TuioDrop::kTooFewArgs},
      {"ocg two points", Msg("/tuio2/ocg", {I(1), F(0.1), F(0.1), F(0.2), F(0.1)}),
       TuioDrop::kTooFewArgs},
      {"ocg three equal points",
       Msg("/tuio2/ocg", {I(1), F(0.1), F(0.1), F(0.1), F(0.1), F(0.1), F(0.1)}),
       TuioDrop::kTooFewArgs},
      {"ocg a string coordinate",
       Msg("/tuio2/ocg", {I(1), F(0.1), F(0.1), S("0.2"), F(0.1), F(0.2), F(0.2)}),
       TuioDrop::kWrongType},
      {"ocg NaN", Msg("/tuio2/ocg", {I(1), F(0.1), F(nan), F(0.2), F(0.1), F(0.2), F(0.2)}),
       TuioDrop::kNonFinite},
      {"ocg out of range",
       Msg("/tuio2/ocg", {I(1), F(0.1), F(0.1), F(3.0), F(0.1), F(0.2), F(0.2)}),
       TuioDrop::kOutOfRange},
      {"ocg of 10000 points", tooManyPoints, TuioDrop::kTooManyPoints},
      {"ptr too short", Msg("/tuio2/ptr", {I(1), I(0), I(0), F(0.5)}), TuioDrop::kTooFewArgs},
      {"ptr x an int", Msg("/tuio2/ptr", {I(1), I(0), I(0), I(0), F(0.5)}), TuioDrop::kWrongType},
      {"ptr blob argument", Msg("/tuio2/ptr", {I(1), I(0), I(0), OscArg::Other('b'), F(0.5)}),
       TuioDrop::kWrongType},
      {"ptr inf", Msg("/tuio2/ptr", {I(1), I(0), I(0), F(inf), F(0.5)}), TuioDrop::kNonFinite},
      {"p3d too short", Msg("/tuio2/p3d", {I(1), I(0), I(0), F(0.5), F(0.5)}),
       TuioDrop::kTooFewArgs},
      {"p3d z a string", Msg("/tuio2/p3d", {I(1), I(0), I(0), F(0.5), F(0.5), S("0.1")}),
       TuioDrop::kWrongType},
      {"p3d NaN z", Msg("/tuio2/p3d", {I(1), I(0), I(0), F(0.5), F(0.5), F(nan)}),
       TuioDrop::kNonFinite},
      {"p3d z out of range", Msg("/tuio2/p3d", {I(1), I(0), I(0), F(0.5), F(0.5), F(2.0)}),
       TuioDrop::kOutOfRange},
      {"bnd too short", Msg("/tuio2/bnd", {I(1), F(0.5), F(0.5), F(0)}), TuioDrop::kTooFewArgs},
      {"bnd negative height",
       Msg("/tuio2/bnd", {I(1), F(0.5), F(0.5), F(0), F(0.1), F(-0.5), F(0)}),
       TuioDrop::kOutOfRange},
      {"alv a float", Msg("/tuio2/alv", {I(1), F(2)}), TuioDrop::kWrongType},
  };
}

TEST(TuioDecoder, EveryKindOfMalformedMessageIsCountedAndDropped) {
  for (const BadCase& bad : BadCases()) {
    SCOPED_TRACE(bad.name);
    TuioDecoder d;
    // a good frame first, so that a bad message cannot hide by lifting or adding a contact
    One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})}));
    d.Decode(B({Frm(2), bad.message, Alv({1})}), 0.0);
    for (size_t r = 0; r < static_cast<size_t>(TuioDrop::kCount); ++r) {
      const TuioDrop reason = static_cast<TuioDrop>(r);
      EXPECT_EQ(d.stats()[reason], reason == bad.reason ? 1u : 0u) << kTuioDropNames[r];
    }
    EXPECT_EQ(d.stats().TotalDropped(), 1u);
    // the frame around it still completes with the good contact unchanged
    const std::vector<TuioFrame> frames = d.TakeFrames();
    ASSERT_FALSE(frames.empty());
    ASSERT_EQ(frames.back().contacts.size(), 1u);
    EXPECT_EQ(frames.back().contacts[0].id, 1);
    EXPECT_NEAR(frames.back().contacts[0].centroid.x(), 0.15 * 61.0, kFloatTol);
  }
}

TEST(TuioDecoder, CoordinatesWithinTheMarginAreTaken) {
  TuioDecoder d;  // margin 0.05
  const TuioFrame f = One(d, B({CurAlive({1}), CurSet(1, 1.04, -0.04), CurFseq(1)}));
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_NEAR(f.contacts[0].centroid.x(), 1.04 * 61.0, kFloatTol);
  EXPECT_EQ(d.stats().TotalDropped(), 0u);
}

TEST(TuioDecoder, OtherTuioProfilesAreIgnoredNotErrors) {
  TuioDecoder d;
  d.Decode(B({Msg("/tuio/2Dobj", {S("alive")}), Msg("/tuio2/tok", {I(1), I(0), I(3), F(0.5)}),
              Msg("/tuio2/icg", {I(1), F(0.1), F(0.1)})}),
           0.0);
  EXPECT_EQ(d.stats().ignored, 3u);
  EXPECT_EQ(d.stats().TotalDropped(), 0u);
}

TEST(TuioDecoder, TooManyContactsAreCappedAndCounted) {
  TuioParams p;
  p.maxContacts = 4;
  TuioDecoder d(p);
  OscBundle b = B({CurAlive({})});
  for (int id = 1; id <= 10; ++id) {
    b.messages[0].args.push_back(I(id));
    b.messages.push_back(CurSet(id, 0.05 * id, 0.5));
  }
  b.messages.push_back(CurFseq(1));
  const TuioFrame f = One(d, b);
  EXPECT_EQ(f.contacts.size(), 4u);
  EXPECT_GT(d.stats()[TuioDrop::kTooManyContacts], 0u);
}

TEST(TuioDecoder, ExpireLiftsEverythingAfterTheTimeout) {
  TuioDecoder d;  // timeout 0.5 s
  One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Square(2, 0.5, 0.5, 0.1), Alv({1, 2})}), 10.0);
  EXPECT_FALSE(d.Expire(10.4));
  EXPECT_TRUE(d.TakeFrames().empty());
  EXPECT_TRUE(d.Expire(10.6));
  const std::vector<TuioFrame> frames = d.TakeFrames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].frame, -1);
  EXPECT_EQ(frames[0].lifted, (std::vector<TuioSessionId>{1, 2}));
  EXPECT_TRUE(frames[0].contacts.empty());
  EXPECT_EQ(d.LiveCount(), 0);
  EXPECT_EQ(d.stats().expired, 1u);
  EXPECT_FALSE(d.Expire(20.0)) << "nothing left to lift";
  // the stream comes back, even with lower frame ids
  const TuioFrame f = One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})}), 21.0);
  ASSERT_EQ(f.contacts.size(), 1u);
  EXPECT_TRUE(f.contacts[0].isNew);
}

TEST(TuioDecoder, BadPacketsDoNotKeepTheStreamAlive) {
  TuioDecoder d;
  One(d, B({Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})}), 0.0);
  d.CountBadPacket();
  EXPECT_TRUE(d.Expire(1.0));
  EXPECT_EQ(d.stats()[TuioDrop::kBadPacket], 1u);
}

TEST(TuioDecoder, TheQueueOfUntakenFramesStaysBounded) {
  TuioParams p;
  p.maxQueuedFrames = 8;
  TuioDecoder d(p);
  d.Decode(B({Frm(1), Square(1, 0.1, 0.1, 0.1), Alv({1})}), 0.0);
  d.Decode(B({Frm(2), Square(2, 0.5, 0.1, 0.1), Alv({1, 2})}), 0.0);
  d.Decode(B({Frm(3), Alv({2})}), 0.0);
  for (int f = 4; f < 1000; ++f) d.Decode(B({Frm(f), Square(2, 0.5, 0.1, 0.1), Alv({2})}), 0.0);
  const std::vector<TuioFrame> frames = d.TakeFrames();
  EXPECT_LE(frames.size(), 8u);
  // what the merged frames said is not lost
  const TuioFrame all = MergeTuioFrames(frames);
  EXPECT_EQ(all.frame, 999);
  EXPECT_EQ(all.lifted, std::vector<TuioSessionId>{1});
  ASSERT_EQ(all.contacts.size(), 1u);
  EXPECT_TRUE(all.contacts[0].isNew) << "the caller has not seen session 2 yet";
}

TEST(TuioDecoder, MergeKeepsTheLastContactsAndEveryLift) {
  auto contact = [](TuioSessionId id, bool isNew) {
    TuioContact c;
    c.id = id;
    c.isNew = isNew;
    return c;
  };
  TuioFrame a, b;
  a.frame = 1;
  a.contacts = {contact(1, true), contact(2, true)};
  b.frame = 2;
  b.contacts = {contact(2, false), contact(3, true)};
  b.lifted = {1};
  const std::vector<TuioFrame> frames = {a, b};
  const TuioFrame m = MergeTuioFrames(frames);
  EXPECT_EQ(m.frame, 2);
  ASSERT_EQ(m.contacts.size(), 2u);
  EXPECT_TRUE(m.contacts[0].isNew);
  EXPECT_TRUE(m.contacts[1].isNew);
  EXPECT_EQ(m.lifted, std::vector<TuioSessionId>{1});
}

TEST(TuioStats, SummaryNamesEachReason) {
  TuioStats s;
  EXPECT_EQ(s.Summary(), "");
  s[TuioDrop::kNonFinite] = 10;
  s[TuioDrop::kUnknownAddress] = 2;
  EXPECT_EQ(s.TotalDropped(), 12u);
  EXPECT_EQ(s.Summary(), "12 dropped: 2 unknown address, 10 non-finite");
}

}  // namespace
}  // namespace pg
