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

TEST(LevelErrors, UnknownScriptContactAndKeyframeKeys) {
  EXPECT_EQ(ErrorOf("[script]\nduraton = 3\n"),
            "inline.toml:2:1: unknown key 'duraton' in [script] (did you mean 'duration'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nradus = 1\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:1: unknown key 'radus' in a contact (did you mean 'radius'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1], angel = 3}]\n"),
            "inline.toml:4:31: unknown key 'angel' in a keyframe (did you mean 'angle'?)");
}

TEST(LevelErrors, KeyframeOutOfOrder) {
  EXPECT_EQ(
      ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = [\n"
              "  {t = 0, pos = [1, 1]},\n  {t = 1, pos = [2, 1]},\n  {t = 0.5, pos = [3, 1]},\n"
              "]\n"),
      "inline.toml:7:3: keyframe out of order: t = 0.5 s is not after the previous "
      "keyframe's t = 1 s");
  // equal times are out of order too: a contact cannot be in two places at once
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 1, pos = [1, 1]}, {t = 1, pos = [2, 1]}]\n"),
            "inline.toml:4:32: keyframe out of order: t = 1 s is not after the previous "
            "keyframe's t = 1 s");
}

TEST(LevelErrors, DurationBeforeTheLastKeyframe) {
  EXPECT_EQ(ErrorOf("[script]\nduration = 1\n[[script.contacts]]\nname = \"f\"\n"
                    "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}, {t = 2, pos = [2, 1]}]\n"),
            "inline.toml:2:12: duration 1 s ends before the last keyframe at 2 s");
}

}  // namespace
}  // namespace pg
