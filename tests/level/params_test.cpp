#include "proxygrasp/level/params.h"

#include <gtest/gtest.h>

#include <set>

namespace pg {
namespace {

TEST(LevelParams, SectionsCoverEveryStage) {
  LevelParams p;
  std::set<std::string> names;
  for (const ParamSection& s : Sections(p)) {
    names.insert(s.name);
    EXPECT_FALSE(ListFields(s).empty()) << s.name;
  }
  EXPECT_EQ(names, (std::set<std::string>{"table", "physics", "proxies", "sensing", "tracking",
                                          "camera", "depth"}));
}

TEST(LevelParams, KeysAreUniqueWithinASection) {
  LevelParams p;
  for (const ParamSection& s : Sections(p)) {
    std::set<std::string> keys;
    for (const FieldInfo& f : ListFields(s)) EXPECT_TRUE(keys.insert(f.key).second) << f.key;
  }
}

TEST(LevelParams, DefaultsSuitA30InchTable) {
  // a 30" 4:3 diagonal is 76.2 cm: 61 x 45.7 cm
  LevelParams p;
  EXPECT_EQ(p.table.width, 61.0);
  EXPECT_EQ(p.table.height, 46.0);
}

TEST(LevelParams, SetParamByDottedKey) {
  LevelParams p;
  EXPECT_FALSE(SetParam(p, "physics.substeps", "8"));
  EXPECT_EQ(p.physics.substeps, 8);
  EXPECT_FALSE(SetParam(p, "proxies.placement", "ground"));
  EXPECT_EQ(p.proxies.placement, Placement::kGround);
  const MaybeError bad = SetParam(p, "physic.substeps", "8");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->message, "unknown section 'physic' (did you mean 'physics'?)");
  const MaybeError noDot = SetParam(p, "substeps", "8");
  ASSERT_TRUE(noDot);
  EXPECT_NE(noDot->message.find("section.key"), std::string::npos);
  const MaybeError range = SetParam(p, "physics.layers", "17");
  ASSERT_TRUE(range);
  EXPECT_EQ(range->message, "physics.layers: value 17 is out of range [1, 16]");
}

TEST(LevelParams, CheckParamsAcceptsTheDefaultsAndNamesTheFirstBadValue) {
  LevelParams p;
  EXPECT_FALSE(CheckParams(p));
  p.tracking.maxDistance = -1.0;
  p.physics.substeps = 0;
  // sections in their documented order: physics comes before tracking
  const MaybeError bad = CheckParams(p);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->message, "physics.substeps must be in [1, 64] (got 0)");
  p.physics.substeps = 4;
  const MaybeError tracking = CheckParams(p);
  ASSERT_TRUE(tracking);
  EXPECT_EQ(tracking->message, "tracking.max_distance must be in [0, 100] cm (got -1)");
}

}  // namespace
}  // namespace pg
