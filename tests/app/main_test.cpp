#include "run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace pg {
namespace {

using test::RunProxygrasp;
using ::testing::HasSubstr;

TEST(Main, HelpListsSubcommands) {
  const auto r = RunProxygrasp("--help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* sub : {"params", "sense", "run", "play", "calibrate", "bench"}) {
    EXPECT_THAT(r.output, HasSubstr(sub));
  }
}

TEST(Main, UnknownSubcommandExitsTwo) {
  const auto r = RunProxygrasp("frobnicate");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("frobnicate"));
  EXPECT_THAT(r.output, HasSubstr("--help"));
}

TEST(Main, UnknownOptionExitsTwo) {
  const auto r = RunProxygrasp("--no-such-option");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("--no-such-option"));
}

TEST(Main, MissingSubcommandExitsTwo) {
  const auto r = RunProxygrasp("");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_THAT(r.output, HasSubstr("subcommand"));
}

TEST(Main, VersionPrints) {
  const auto r = RunProxygrasp("--version");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_THAT(r.output, HasSubstr("proxygrasp 0.1.0"));
}

}  // namespace
}  // namespace pg
