#include "run_command.h"
#include "test_paths.h"

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

// the text of doc between <!-- marker:begin --> and <!-- marker:end -->, or "<no markers>"
std::string Generated(const std::string& doc, const std::string& marker) {
  std::ifstream in(std::string(pg::test::SourceDir()) + "/" + doc);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const std::string begin = "<!-- " + marker + ":begin -->\n";
  const size_t b = text.find(begin);
  const size_t e = text.find("<!-- " + marker + ":end -->");
  if (b == std::string::npos || e == std::string::npos) return "<no markers>";
  return text.substr(b + begin.size(), e - b - begin.size());
}

TEST(ParamsCommand, DocsLevelsReferenceIsCurrent) {
  // docs/levels.md embeds `proxygrasp params --markdown` between two markers; keep them equal
  const auto r = RunProxygrasp("params --markdown");
  ASSERT_EQ(r.exitCode, 0);
  EXPECT_EQ(Generated("docs/levels.md", "params"), r.output)
      << "regenerate with: bash scripts/update-docs.sh";
}

TEST(ParamsCommand, DocsAppLivenessTableIsCurrent) {
  // docs/app.md embeds `proxygrasp params --liveness`: which keys apply live, which restart
  const auto r = RunProxygrasp("params --liveness");
  ASSERT_EQ(r.exitCode, 0);
  EXPECT_THAT(r.output, HasSubstr("| `[physics]` | `substeps`"));
  EXPECT_THAT(r.output, HasSubstr("`frame_rate`, `layer_height`, `layers`, `particle_radius`, "
                                  "`stack_size`, `capsule` |"));
  EXPECT_THAT(r.output, HasSubstr("| `[table]` | none | `width`, `height`, `wall_thickness` |"));
  EXPECT_EQ(Generated("docs/app.md", "liveness"), r.output)
      << "regenerate with: bash scripts/update-docs.sh";
}

}  // namespace
}  // namespace pg
