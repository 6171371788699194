#include "proxygrasp/proxies/matching.h"
#include "proxygrasp/proxies/types.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace pg {
namespace {

ParamSection Section(ProxyParams& p) {
  return {"proxies", [&p](ParamVisitor& v) { Describe(p, v); }};
}

TEST(ProxyParams, EveryFieldIsDescribedOnce) {
  ProxyParams p;
  std::set<std::string> keys;
  for (const FieldInfo& f : ListFields(Section(p))) {
    EXPECT_TRUE(keys.insert(f.key).second) << f.key;
    EXPECT_FALSE(f.doc.empty()) << f.key;
  }
  EXPECT_EQ(keys, (std::set<std::string>{"mode", "algorithm", "window", "search_radius",
                                         "fallback_score", "placement", "penetration_limit",
                                         "instant_threshold", "instant_spacing",
                                         "instant_flow_window", "subsample", "count_hysteresis",
                                         "height_offset", "height_span", "height_smoothing"}));
}

TEST(ProxyParams, SetByName) {
  ProxyParams p;
  const ParamSection s = Section(p);
  EXPECT_FALSE(SetFieldFromText(s, "algorithm", "windowed"));
  EXPECT_EQ(p.algorithm, MatchAlgorithm::kWindowed);
  EXPECT_FALSE(SetFieldFromText(s, "mode", "instant"));
  EXPECT_EQ(p.mode, ProxyMode::kInstant);
  EXPECT_FALSE(SetFieldFromText(s, "instant_flow_window", "15"));
  EXPECT_EQ(p.instantFlowWindow, 15);
}

TEST(ProxyParams, WindowRangeMatchesTheMatchingLimit) {
  // the matching sums stay exact in int64 only up to kMaxMatchWindow; the level range says so too
  ProxyParams p;
  const ParamSection s = Section(p);
  const MaybeError tooWide = SetFieldFromText(s, "window", std::to_string(kMaxMatchWindow + 1));
  ASSERT_TRUE(tooWide);
  EXPECT_NE(tooWide->message.find("out of range"), std::string::npos) << tooWide->message;
  EXPECT_FALSE(SetFieldFromText(s, "window", std::to_string(kMaxMatchWindow)));
}

}  // namespace
}  // namespace pg
