// Object geometry (src/physics/shapes.cpp) against closed-form values.
#include "proxygrasp/physics/shapes.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pg {
namespace {

ObjectSpec Shape(ObjectShape shape) {
  ObjectSpec s;
  s.name = "thing";
  s.shape = shape;
  s.loc = SourceLoc{"levels/t.toml", 7, 3};
  return s;
}

ObjectSpec Prism(std::vector<Vec2> points, double height, bool concave) {
  ObjectSpec s = Shape(concave ? ObjectShape::kConcavePrism : ObjectShape::kConvexPrism);
  s.points = std::move(points);
  s.height = height;
  return s;
}

// an L: the 4 x 4 square minus its top-right 2 x 2 quarter
std::vector<Vec2> LShape() {
  return {Vec2(0, 0), Vec2(4, 0), Vec2(4, 2), Vec2(2, 2), Vec2(2, 4), Vec2(0, 4)};
}

// relative tolerance for closed forms evaluated in double precision
constexpr double kRel = 1e-12;

TEST(MassProps, SolidsMatchClosedForms) {
  ObjectSpec box = Shape(ObjectShape::kBox);
  box.sizeX = 4;
  box.sizeY = 6;
  box.height = 2;
  box.density = 0.5;
  MassProps m = ComputeMassProps(box);
  EXPECT_NEAR(m.mass, 24.0, 24.0 * kRel);
  EXPECT_NEAR(m.inertia, 24.0 * (16 + 36) / 12.0, 104.0 * kRel);

  ObjectSpec cyl = Shape(ObjectShape::kCylinder);
  cyl.radius = 2;
  cyl.height = 3;
  cyl.density = 1;
  m = ComputeMassProps(cyl);
  EXPECT_NEAR(m.mass, kPi * 12, 40 * kRel);
  EXPECT_NEAR(m.inertia, 0.5 * m.mass * 4, 80 * kRel);

  ObjectSpec sph = Shape(ObjectShape::kSphere);
  sph.radius = 1.5;
  sph.density = 2;
  m = ComputeMassProps(sph);
  EXPECT_NEAR(m.mass, 2 * 4.0 / 3.0 * kPi * 1.5 * 1.5 * 1.5, 30 * kRel);
  EXPECT_NEAR(m.inertia, 0.4 * m.mass * 2.25, 30 * kRel);
  EXPECT_DOUBLE_EQ(ObjectHeight(sph), 3.0);

  // a cone: M = rho pi R^2 H / 3, I = 3/10 M R^2
  ObjectSpec cone = Shape(ObjectShape::kFrustum);
  cone.radius = 2;
  cone.topRadius = 0;
  cone.height = 3;
  cone.density = 1;
  m = ComputeMassProps(cone);
  EXPECT_NEAR(m.mass, kPi * 4, 20 * kRel);
  EXPECT_NEAR(m.inertia, 0.3 * m.mass * 4, 20 * kRel);

  // a frustum with equal radii is a cylinder
  ObjectSpec fr = cone;
  fr.topRadius = 2;
  const MassProps mc = ComputeMassProps(fr);
  fr.shape = ObjectShape::kCylinder;
  const MassProps mcyl = ComputeMassProps(fr);
  EXPECT_NEAR(mc.mass, mcyl.mass, mcyl.mass * kRel);
  EXPECT_NEAR(mc.inertia, mcyl.inertia, mcyl.inertia * kRel);
}

TEST(MassProps, PrismsMatchRectangles) {
  // the square prism equals the box
  ObjectSpec sq = Prism({Vec2(1, 1), Vec2(5, 1), Vec2(5, 5), Vec2(1, 5)}, 2, false);
  MassProps m = ComputeMassProps(sq);
  EXPECT_NEAR(m.mass, 0.5 * 32, 16 * kRel);
  EXPECT_NEAR(m.inertia, 16.0 * 32 / 12.0, 50 * kRel);
  EXPECT_NEAR((m.centroid - Vec2(3, 3)).norm(), 0.0, 1e-12);

  // the L as two rectangles, [0,4]x[0,2] and [0,2]x[2,4], by the parallel-axis theorem
  ObjectSpec l = Prism(LShape(), 1, true);
  l.density = 1;
  m = ComputeMassProps(l);
  EXPECT_NEAR(m.mass, 12.0, 12 * kRel);
  const Vec2 c1(2, 1), c2(1, 3);
  const Vec2 c = (8 * c1 + 4 * c2) / 12;
  EXPECT_NEAR((m.centroid - c).norm(), 0.0, 1e-12);
  const double i1 = 8 * (16 + 4) / 12.0 + 8 * (c1 - c).squaredNorm();
  const double i2 = 4 * (4 + 4) / 12.0 + 4 * (c2 - c).squaredNorm();
  EXPECT_NEAR(m.inertia, i1 + i2, (i1 + i2) * kRel);

  // a given mass overrides the density and scales the inertia with it
  l.mass = 24;
  const MassProps heavy = ComputeMassProps(l);
  EXPECT_DOUBLE_EQ(heavy.mass, 24);
  EXPECT_NEAR(heavy.inertia, 2 * m.inertia, 2 * m.inertia * kRel);
}

TEST(Slices, LayersAndCrossSections) {
  ObjectSpec box = Shape(ObjectShape::kBox);
  box.height = 2.0;
  EXPECT_EQ(SliceLayerCount(box, 1.0, 8), 2);
  box.height = 2.5;  // mid-height 2.5 is not below the top
  EXPECT_EQ(SliceLayerCount(box, 1.0, 8), 2);
  box.height = 2.6;
  EXPECT_EQ(SliceLayerCount(box, 1.0, 8), 3);
  EXPECT_EQ(SliceLayerCount(box, 1.0, 2), 2);  // capped by the layer count
  // a slab thinner than half a layer keeps one slice cut at half its height
  box.height = 0.3;
  EXPECT_EQ(SliceLayerCount(box, 1.0, 8), 1);
  EXPECT_DOUBLE_EQ(SliceHeight(box, 0, 1.0), 0.15);

  // sphere: r(z) = sqrt(r^2 - (z - r)^2) at the mid-heights 0.5, 1.5, 2.5, 3.5
  ObjectSpec sph = Shape(ObjectShape::kSphere);
  sph.radius = 2.0;
  ASSERT_EQ(SliceLayerCount(sph, 1.0, 8), 4);
  for (int k = 0; k < 4; ++k) {
    const double z = SliceHeight(sph, k, 1.0);
    EXPECT_DOUBLE_EQ(z, k + 0.5);
    const CrossSection s = SectionAt(sph, z);
    ASSERT_TRUE(s.circle);
    EXPECT_NEAR(s.radius, std::sqrt(4.0 - (z - 2.0) * (z - 2.0)), 1e-12);
  }
  // frustum: radius interpolated linearly
  ObjectSpec fr = Shape(ObjectShape::kFrustum);
  fr.radius = 3;
  fr.topRadius = 1;
  fr.height = 4;
  EXPECT_NEAR(SectionAt(fr, 1.0).radius, 2.5, 1e-12);
  EXPECT_NEAR(Footprint(fr).radius, 3.0, 1e-12);
}

TEST(Surface, TopHeightsOfEachShape) {
  ObjectSpec sph = Shape(ObjectShape::kSphere);
  sph.radius = 2.0;
  EXPECT_DOUBLE_EQ(SurfaceHeightAt(sph, Vec2(0, 0)), 4.0);
  EXPECT_NEAR(SurfaceHeightAt(sph, Vec2(1.2, 0)), 2.0 + std::sqrt(4 - 1.44), 1e-12);
  EXPECT_LT(SurfaceHeightAt(sph, Vec2(2.1, 0)), 0.0);

  // cone: flat nowhere, the slanted side falls linearly to the rim
  ObjectSpec cone = Shape(ObjectShape::kFrustum);
  cone.radius = 2;
  cone.topRadius = 0;
  cone.height = 4;
  EXPECT_NEAR(SurfaceHeightAt(cone, Vec2(0, 1)), 2.0, 1e-12);

  ObjectSpec l = Prism(LShape(), 1.5, true);
  EXPECT_DOUBLE_EQ(SurfaceHeightAt(l, Vec2(1, 3)), 1.5);
  EXPECT_LT(SurfaceHeightAt(l, Vec2(3, 3)), 0.0);  // the missing quarter
}

TEST(Friction, EffectiveRadiusOfDiscAndSquare) {
  ObjectSpec cyl = Shape(ObjectShape::kCylinder);
  cyl.radius = 3;
  EXPECT_DOUBLE_EQ(EffectiveFrictionRadius(cyl, Vec2::Zero()), 2.0);
  // mean distance from the centre of a square of side a: a (sqrt 2 + ln(1 + sqrt 2)) / 6
  ObjectSpec box = Shape(ObjectShape::kBox);
  box.sizeX = box.sizeY = 4;
  const double exact = 4 * (std::sqrt(2.0) + std::log(1 + std::sqrt(2.0))) / 6;
  // midpoint rule on a 160 x 160 grid: well under 0.1%
  EXPECT_NEAR(EffectiveFrictionRadius(box, Vec2::Zero()), exact, 1e-3 * exact);
}

double TotalArea(const std::vector<Contour>& pieces) {
  double a = 0;
  for (const Contour& p : pieces) a += SignedArea(p);
  return a;
}

bool Convex(const Contour& c) {
  const int n = static_cast<int>(c.cols());
  for (int i = 0; i < n; ++i) {
    if (Cross(c.col((i + 1) % n) - c.col(i), c.col((i + 2) % n) - c.col((i + 1) % n)) < -1e-9) {
      return false;
    }
  }
  return true;
}

TEST(Decompose, PiecesAreConvexSmallAndCoverThePolygon) {
  // a concave L, a convex 20-gon and a 5-point star
  std::vector<Contour> polys;
  polys.push_back(ToContour(LShape()));
  Contour ngon(2, 20), star(2, 10);
  for (int i = 0; i < 20; ++i)
    ngon.col(i) = 3.0 * Vec2(std::cos(i * kPi / 10), std::sin(i * kPi / 10));
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 == 0 ? 3.0 : 1.2;
    star.col(i) = r * Vec2(std::cos(i * kPi / 5), std::sin(i * kPi / 5));
  }
  polys.push_back(ngon);
  polys.push_back(star);
  for (const Contour& poly : polys) {
    const std::vector<Contour> pieces = ConvexDecompose(poly);
    for (const Contour& p : pieces) {
      EXPECT_GE(p.cols(), 3);
      EXPECT_LE(p.cols(), 8);
      EXPECT_TRUE(Convex(p));
      EXPECT_GT(SignedArea(p), 0.0);
    }
    EXPECT_NEAR(TotalArea(pieces), SignedArea(poly), 1e-9);
  }
  // merging keeps the count low: the L needs 2 pieces, the 20-gon 3
  EXPECT_EQ(ConvexDecompose(polys[0]).size(), 2u);
  EXPECT_EQ(ConvexDecompose(polys[1]).size(), 3u);
}

TEST(Validate, ErrorsNameObjectFieldAndPlace) {
  PhysicsParams p;
  ObjectSpec box = Shape(ObjectShape::kBox);
  box.name = "crate";
  box.sizeX = -1;
  MaybeError s = ValidateObject(box, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->Format(), "levels/t.toml:7:3: object 'crate': size_x must be > 0 (got -1)");

  box.sizeX = 4;
  box.tableKinetic = 0.5;
  box.tableStatic = 0.4;
  s = ValidateObject(box, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_NE(s->message.find("table_kinetic must be <= table_static"), std::string::npos);

  box.tableKinetic = 0.3;
  box.height = 9;  // 8 layers of 1 cm leave room for tops up to 7.5 cm
  s = ValidateObject(box, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_NE(s->message.find("height makes the object 9 cm tall, too tall"), std::string::npos);
  EXPECT_NE(s->message.find("at most 7.5 cm"), std::string::npos);

  ObjectSpec bow = Prism({Vec2(0, 0), Vec2(2, 2), Vec2(2, 0), Vec2(0, 2)}, 1, true);
  s = ValidateObject(bow, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->Format(),
            "levels/t.toml:7:3: object 'thing': points is not a simple polygon: edge 1-2 meets "
            "edge 3-4");

  ObjectSpec l = Prism(LShape(), 1, false);
  s = ValidateObject(l, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_NE(s->message.find("not convex"), std::string::npos);
  l.shape = ObjectShape::kConcavePrism;
  EXPECT_FALSE(ValidateObject(l, p).has_value());

  ObjectSpec two = Prism({Vec2(0, 0), Vec2(1, 0)}, 1, false);
  s = ValidateObject(two, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_NE(s->message.find("points needs at least 3 points, got 2"), std::string::npos);

  ObjectSpec sph = Shape(ObjectShape::kSphere);
  sph.radius = 1;
  sph.density = 0;
  s = ValidateObject(sph, p);
  ASSERT_TRUE(s.has_value());
  EXPECT_NE(s->message.find("density must be > 0 (got 0)"), std::string::npos);
  sph.mass = 10;  // a mass makes the density irrelevant
  EXPECT_FALSE(ValidateObject(sph, p).has_value());
}

TEST(Footprint, BoundsOnTheTableFollowThePose) {
  // a 4 x 2 box turned a quarter turn about (10, 10): 2 wide along x, 4 along y
  ObjectSpec box = Shape(ObjectShape::kBox);
  box.sizeX = 4;
  box.sizeY = 2;
  box.height = 1;
  box.pose = Pose2{Vec2(10, 10), kPi / 2};
  const auto [low, high] = FootprintBounds(box);
  EXPECT_NEAR(low.x(), 9.0, 1e-12);
  EXPECT_NEAR(low.y(), 8.0, 1e-12);
  EXPECT_NEAR(high.x(), 11.0, 1e-12);
  EXPECT_NEAR(high.y(), 12.0, 1e-12);
  // a frustum standing on its narrow end overhangs with its wide top
  ObjectSpec cup = Shape(ObjectShape::kFrustum);
  cup.radius = 1;
  cup.topRadius = 2;
  cup.height = 3;
  cup.pose = Pose2{Vec2(5, 6), 0.3};
  const auto [cupLow, cupHigh] = FootprintBounds(cup);
  EXPECT_NEAR(cupLow.x(), 3.0, 1e-12);
  EXPECT_NEAR(cupHigh.y(), 8.0, 1e-12);
}

}  // namespace
}  // namespace pg
