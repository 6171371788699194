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

TEST(LevelErrors, UnknownExpectationGoalAndVariantKeys) {
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nhel = true\n"),
      "inline.toml:9:1: unknown key 'hel' in a held expectation (did you mean 'held'?)");
  // keys of earlier versions of the format name their new names
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nvalue = true\n"),
      "inline.toml:9:1: unknown key 'value' in a held expectation (did you mean 'held'? 'value' "
      "was renamed)");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\nmin_deg = 10\n"),
            "inline.toml:9:1: unknown key 'min_deg' in a rotation expectation (did you mean "
            "'above'? 'min_deg' was renamed)");
  // a key of another kind is unknown in this one
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nabove = 1\n"),
      "inline.toml:9:1: unknown key 'above' in a held expectation");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"box\"\nangle_deg = 90\n"),
            "inline.toml:8:1: unknown key 'angle_deg' in a goal (did you mean 'angle'? 'angle_deg' "
            "was renamed)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[variants.physics]\nlayer = 2\n"),
            "inline.toml:4:1: unknown key 'layer' in [variants.physics] (did you mean 'layers'?)");
  EXPECT_EQ(ErrorOf("[[variants]]\nname = \"v\"\n[variants.physic]\nlayers = 2\n"),
            "inline.toml:3:11: unknown key 'physic' in a variant (did you mean 'physics'?)");
}

TEST(LevelErrors, NamesMustExist) {
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"bx\"\n"),
            "inline.toml:8:10: unknown object 'bx' (did you mean 'box'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"ball\"\nangle = 30\n"),
            "inline.toml:7:10: unknown object 'ball'");
  const std::string finger =
      "[[script.contacts]]\nname = \"finger\"\nshape = \"circle\"\n"
      "keys = [{t = 0, pos = [1, 1]}, {t = 2, pos = [3, 1]}]\n";
  EXPECT_EQ(ErrorOf(std::string(kBox) + finger +
                    "[[expect]]\nkind = \"resting\"\ncontact = \"fingr\"\non = \"box\"\n"),
            "inline.toml:12:11: unknown contact 'fingr' (did you mean 'finger'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + finger +
                    "[[expect]]\nkind = \"resting\"\ncontact = \"finger\"\non = \"tabel\"\n"),
            "inline.toml:13:6: unknown object 'tabel' (did you mean 'table'?)");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"held\"\nobject = \"box\"\nvariant = \"single\"\n"),
            "inline.toml:9:11: unknown variant 'single'");
}

TEST(LevelErrors, ExpectationTimesAndBounds) {
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\nobject = \"box\"\nat = 5\n"),
            "inline.toml:9:6: at = 5 s is after the end of the level at 1 s");
  const std::string finger =
      "[[script.contacts]]\nname = \"finger\"\nshape = \"circle\"\n"
      "keys = [{t = 1, pos = [1, 1]}, {t = 2, pos = [3, 1]}]\n";
  EXPECT_EQ(
      ErrorOf(std::string(kBox) + finger +
              "[[expect]]\nkind = \"resting\"\ncontact = \"finger\"\non = \"box\"\nat = 0.5\n"),
      "inline.toml:14:6: at = 0.5 s is outside contact 'finger', which exists from 1 s to 2 s");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\n"),
            "inline.toml:6:1: a rotation expectation needs above, below or both");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"rotation\"\nobject = \"box\"\nabove = 10\nbelow = 5\n"),
            "inline.toml:10:9: below (5 deg) must not be less than above (10 deg)");
  EXPECT_EQ(
      ErrorOf(std::string(kBox) +
              "[[expect]]\nkind = \"displacement\"\nobject = \"box\"\nabove = 3\nbelow = 2\n"),
      "inline.toml:10:9: below (2 cm) must be greater than above (3 cm)");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"
                                        "min = [0, 0]\nmax = [10, -1]\n"),
            "inline.toml:10:7: max [10, -1] must be above min [0, 0] in both x and y");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"
                                        "min = [0, 0]\nmax = [10, 10]\nradius = 3\n"),
            "inline.toml:11:1: give a region as min and max, or as center and radius, not both");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"wobble\"\n"),
            "inline.toml:7:8: kind 'wobble' is not one of: position, rotation, displacement, "
            "held, resting, speed");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"speed\"\nobject = \"box\"\n"),
            "inline.toml:6:1: a speed expectation needs below");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"speed\"\nobject = \"box\"\nbelow = 5\nabove = 1\n"),
            "inline.toml:10:1: unknown key 'above' in a speed expectation");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[goals]]\nobject = \"box\"\ncenter = [3, 3]\nradius = 2\ntolerance = 4\n"),
            "inline.toml:10:1: tolerance needs angle");
}

TEST(Goal, MetInTheZoneAndWithinTheAngleModuloATurn) {
  Goal g;
  Region zone;
  zone.min = Vec2(0, 0);
  zone.max = Vec2(10, 10);
  g.zone = zone;
  g.angle = DegToRad(90);
  g.tolerance = DegToRad(5);
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), DegToRad(94)}));
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), DegToRad(90 + 360)})) << "a full extra turn is the same mark";
  EXPECT_FALSE(g.IsMet({Vec2(5, 5), DegToRad(96)}));
  EXPECT_FALSE(g.IsMet({Vec2(11, 5), DegToRad(90)}));
  g.angle.reset();
  EXPECT_TRUE(g.IsMet({Vec2(5, 5), 2.0}));
}

TEST(Region, ContainsRectAndCircle) {
  Region rect;
  rect.min = Vec2(0, 0);
  rect.max = Vec2(2, 1);
  EXPECT_TRUE(rect.Contains(Vec2(2, 1)));
  EXPECT_FALSE(rect.Contains(Vec2(2.01, 0.5)));
  Region circle;
  circle.kind = Region::Kind::kCircle;
  circle.center = Vec2(1, 1);
  circle.radius = 1;
  EXPECT_TRUE(circle.Contains(Vec2(1.6, 1.6)));
  EXPECT_FALSE(circle.Contains(Vec2(1.8, 1.8)));
}

}  // namespace
}  // namespace pg
