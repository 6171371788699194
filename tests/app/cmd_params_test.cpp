#include "run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace pg {
namespace {

using test::RunProxygrasp;
using ::testing::HasSubstr;

TEST(ParamsCommand, ListsDefaultsWithUnits) {
  const auto r = RunProxygrasp("params --section physics");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_THAT(r.output, HasSubstr("[physics]"));
  EXPECT_THAT(r.output, HasSubstr("layer_height = 1"));
  EXPECT_THAT(r.output, HasSubstr("cm"));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("[table]")));
}

TEST(ParamsCommand, UnknownSectionExitsTwo) {
  const auto r = RunProxygrasp("params --section nope");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("unknown section 'nope'"));
}

TEST(ParamsCommand, DocsLevelsReferenceIsCurrent) {
  // docs/levels.md embeds `proxygrasp params --markdown` between two markers; keep them equal
  const auto r = RunProxygrasp("params --markdown");
  ASSERT_EQ(r.exitCode, 0);
  std::ifstream in(std::string(PROXYGRASP_SOURCE_DIR) + "/docs/levels.md");
  ASSERT_TRUE(in) << "docs/levels.md is missing";
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const std::string begin = "<!-- params:begin -->\n";
  const std::string end = "<!-- params:end -->";
  const size_t b = text.find(begin);
  const size_t e = text.find(end);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(text.substr(b + begin.size(), e - b - begin.size()), r.output)
      << "regenerate with: bash scripts/update-docs.sh";
}

}  // namespace
}  // namespace pg
