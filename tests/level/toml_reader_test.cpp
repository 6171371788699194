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

TEST(LevelErrors, UnknownTopLevelKey) {
  EXPECT_EQ(ErrorOf("name = \"x\"\n[physic]\nlayers = 2\n"),
            "inline.toml:2:2: unknown key 'physic' (did you mean 'physics'?)");
  EXPECT_EQ(ErrorOf("\n[[object]]\nname = \"a\"\n"),
            "inline.toml:2:3: unknown key 'object' (did you mean 'objects'?)");
}

TEST(LevelErrors, UnknownParameterKey) {
  EXPECT_EQ(ErrorOf("[physics]\nlayers = 2\nsubstep = 4\n"),
            "inline.toml:3:1: unknown key 'substep' in [physics] (did you mean 'substeps'?)");
  EXPECT_EQ(ErrorOf("[camera]\nzzz = 4\n"), "inline.toml:2:1: unknown key 'zzz' in [camera]");
}

TEST(LevelErrors, WrongTypes) {
  EXPECT_EQ(ErrorOf("[physics]\nsubsteps = \"4\"\n"),
            "inline.toml:2:12: physics.substeps must be an integer, got a string");
  EXPECT_EQ(ErrorOf("[physics]\nsubsteps = 4.5\n"),
            "inline.toml:2:12: physics.substeps must be an integer, got a floating-point number");
  EXPECT_EQ(ErrorOf("[physics]\ncapsule = 1\n"),
            "inline.toml:2:11: physics.capsule must be true or false, got an integer");
  EXPECT_EQ(ErrorOf("[proxies]\nmode = 1\n"),
            "inline.toml:2:8: proxies.mode must be one of persistent, instant, got an integer");
  EXPECT_EQ(ErrorOf("[sensing]\ncalibration = 3\n"),
            "inline.toml:2:15: sensing.calibration must be a string, got an integer");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = \"heavy\"\n"),
            "inline.toml:4:8: mass must be a number, got a string");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [1, 2, 3]\n"),
            "inline.toml:4:7: pos must be an array of two numbers [x, y]");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"convex_prism\"\n"
                    "points = [[0, 0], [1, 0], 5]\n"),
            "inline.toml:4:27: points must be an array of points [[x, y], ...]");
  EXPECT_EQ(ErrorOf("physics = 3\n"),
            "inline.toml:1:11: physics must be a table [physics], got an integer");
  EXPECT_EQ(ErrorOf("name = 3\n"), "inline.toml:1:8: name must be a string, got an integer");
  EXPECT_EQ(ErrorOf("[objects]\nname = \"a\"\n"),
            "inline.toml:1:1: objects must be an array of tables [[objects]], got a table");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = [3]\n"),
            "inline.toml:4:9: a keyframe must be a table {t = ..., pos = [x, y], angle = ...}, got "
            "an integer");
}

TEST(LevelErrors, UnknownChoiceNamesTheChoices) {
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"boks\"\n"),
            "inline.toml:3:9: shape 'boks' is not one of: box, cylinder, sphere, frustum, "
            "convex_prism, concave_prism (did you mean 'box'?)");
  EXPECT_EQ(ErrorOf("[script]\ninterpolation = \"cubic\"\n"),
            "inline.toml:2:17: script.interpolation 'cubic' is not one of: linear, smooth");
}

TEST(LevelErrors, OutOfRange) {
  EXPECT_EQ(ErrorOf("[physics]\nlayers = 17\n"),
            "inline.toml:2:10: physics.layers must be in [1, 16] (got 17)");
  EXPECT_EQ(ErrorOf("[physics]\nlayer_height = 0\n"),
            "inline.toml:2:16: physics.layer_height must be in [0.05, 100] cm (got 0)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\ntable_static = -0.2\n"),
            "inline.toml:4:16: table_static must be in [0, 10] (got -0.2)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nangle = 400\n"),
            "inline.toml:4:9: angle must be in [-360, 360] deg (got 400)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nsize_x = 0\n"),
            "inline.toml:4:10: size_x must be in [0.1, 200] cm (got 0)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nheight = nan\n"),
            "inline.toml:4:10: height must be in [0.1, 100] cm (got nan)");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\npos = [2000, 1]\n"),
            "inline.toml:4:7: pos must have each coordinate in [-1000, 1000] cm (got [2000, 1])");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = -1, pos = [1, 1]}]\n"),
            "inline.toml:4:14: t must be in [0, 3600] s (got -1)");
}

TEST(LevelErrors, MissingRequiredFields) {
  EXPECT_EQ(ErrorOf("\n[[objects]]\nshape = \"box\"\n"),
            "inline.toml:2:1: object is missing required key 'name'");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\n"),
            "inline.toml:1:1: object is missing required key 'shape'");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"concave_prism\"\npos = [5, 5]\n"),
            "inline.toml:1:1: a concave_prism object needs 'points', its outline");
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\n"),
            "inline.toml:1:1: object is missing required key 'pos'");
  // a mistake in a key that is there is reported before a key left out, wherever it is
  EXPECT_EQ(ErrorOf("[[objects]]\nname = \"a\"\nshape = \"box\"\nmass = -1\n"),
            "inline.toml:4:8: mass must be in [0, 1e+06] g (got -1)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"),
            "inline.toml:1:1: contact is missing required key 'keys'");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1]}, {t = 1}]\n"),
            "inline.toml:4:32: keyframe is missing required key 'pos'");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = []\n"),
            "inline.toml:4:8: keys must be a non-empty array of keyframes [{t = 0, pos = [x, y]}, "
            "...]");
  EXPECT_EQ(ErrorOf("[[expect]]\nobject = \"box\"\n"),
            "inline.toml:1:1: expectation is missing required key 'kind'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"held\"\n"),
            "inline.toml:6:1: a held expectation is missing required key 'object'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[expect]]\nkind = \"position\"\nobject = \"box\"\n"),
            "inline.toml:6:1: a position expectation needs a region: min and max, or center and "
            "radius");
  EXPECT_EQ(ErrorOf(std::string(kBox) +
                    "[[expect]]\nkind = \"position\"\nobject = \"box\"\nmin = [0, 0]\n"),
            "inline.toml:6:1: a position expectation is missing required key 'max'");
  EXPECT_EQ(ErrorOf("[[variants]]\n[variants.physics]\nlayers = 2\n"),
            "inline.toml:1:1: variant is missing required key 'name'");
  EXPECT_EQ(ErrorOf(std::string(kBox) + "[[goals]]\nobject = \"box\"\n"),
            "inline.toml:6:1: a goal needs a zone (min and max, or center and radius), angle or "
            "both");
}

TEST(LevelErrors, FirstErrorInTheFileWins) {
  // two errors in one table: the earlier line is reported, whatever the order of the keys in code
  EXPECT_EQ(ErrorOf("[physics]\nstack_size = 0\nframe_rate = 0\n"),
            "inline.toml:2:14: physics.stack_size must be in [1, 16] (got 0)");
}

}  // namespace
}  // namespace pg
