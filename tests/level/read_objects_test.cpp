#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "level/level_test_util.h"

namespace pg {
namespace {

using test::ErrorOf;
using test::kBox;

TEST(LevelErrors, UnknownObjectKey) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nfriction = 0.2\n"),
            "inline.toml:4:1: unknown key 'friction' in an object");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nresitution = 0.2\n"),
            "inline.toml:4:1: unknown key 'resitution' in an object (did you mean "
            "'restitution'?)");
}

TEST(LevelErrors, SizeKeysMustFitTheShape) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nradius = 2\n"),
            "inline.toml:4:1: 'radius' does not apply to a box (its size keys: size_x, size_y, "
            "height)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"sphere\"\nheight = 2\n"),
            "inline.toml:4:1: 'height' does not apply to a sphere (its size keys: radius, "
            "patch_radius)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"hand_five\"\nradius = 1\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:1: 'radius' does not apply to a hand_five contact (its size keys: "
            "scale)");
}

TEST(LevelErrors, PrismOutlines) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [1, 0]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points needs at least 3 points, got 2");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [4, 0], [1, 1], [0, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not convex: it turns the other way at "
            "point 3");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [4, 0], [0, 4], [4, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not a simple polygon: edge 2-3 meets "
            "edge 4-1");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [2, 0], [4, 0]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points encloses no area");
  // a vertex touching a non-neighbouring edge makes it not simple either
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\n"
                    "points = [[0, 0], [4, 0], [2, 0], [2, 2]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points is not a simple polygon: edge 1-2 meets "
            "edge 3-4");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [0, 0], [4, 0], [0, 4]]\npos = [5, 5]\n"),
            "inline.toml:4:10: object 'a': points has coincident points 1 and 2");
  // a concave L is fine as a concave prism, either winding
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\npos = [5, 5]\n"
                    "points = [[0, 0], [0, 4], [1, 4], [1, 1], [3, 1], [3, 0]]\n"),
            "(loaded)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"convex\"\n"
                    "points = [[0, 0], [4, 0], [1, 1], [0, 4]]\nkeys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:10: points of a convex contact is not convex: it turns the other way "
            "at point 3");
}

TEST(LevelErrors, ObjectConsistency) {
  EXPECT_EQ(
      ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\ntable_kinetic = 0.6\npos = [5, 5]\n"),
      "inline.toml:4:17: object 'a': table_kinetic must be <= table_static (0.6 > 0.4)");
  // a sphere's contact patch lies within it
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"sphere\"\nradius = 1\n"
                    "patch_radius = 1.5\npos = [5, 5]\n"),
            "inline.toml:5:16: object 'a': patch_radius must be at most the radius 1 (got 1.5)");
  EXPECT_EQ(
      ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = 5\ndensity = 1\npos = [5, 5]\n"),
      "inline.toml:5:1: give either mass or density, not both");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [70, 10]\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [68, 72] x [8, "
            "12] cm, the table [0, 61] x [0, 46] cm");
  // the footprint counts, not the centre: a box 4 cm wide at x = 1 overhangs the edge, a turned
  // one reaches further, a frustum's wide top overhangs even when its base fits
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [1, 10]\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [-1, 3] x [8, "
            "12] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [2.5, 10]\nangle = 45\n"),
            "inline.toml:4:7: object 'a' reaches off the table: its footprint spans [-0.328, "
            "5.328] x [7.172, 12.828] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"frustum\"\nradius = 1\ntop_radius = 3\n"
                    "pos = [2, 10]\n"),
            "inline.toml:6:7: object 'a' reaches off the table: its footprint spans [-1, 5] x [7, "
            "13] cm, the table [0, 61] x [0, 46] cm");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\npos = [59, 10]\n"
                    "points = [[0, 0], [2, 0], [0, 2]]\n"),
            "(loaded)");
  // the table's size comes from the level
  EXPECT_EQ(ErrorOf("[table]\nwidth = 80\n[[objects]]\nname = \"a\"\nshape = \"box\"\n"
                    "pos = [70, 10]\n"),
            "(loaded)");
}

TEST(LevelErrors, DuplicateNames) {
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[objects]]\nname = \"box\"\nshape = \"sphere\"\npos = [5, 5]\n"),
            "inline.toml:7:8: duplicate object name 'box' (first defined at inline.toml:2:1)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n[[script.contacts]]\nname = \"f\"\n"
                    "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:6:8: duplicate contact name 'f' (first defined at inline.toml:1:1)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[[variants]]\nname = \"v\"\n"),
            "inline.toml:4:8: duplicate variant name 'v' (first defined at inline.toml:1:1)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"\"\nshape = \"box\"\npos = [5, 5]\n"),
            "inline.toml:2:8: name must not be empty");
}

}  // namespace
}  // namespace pg
