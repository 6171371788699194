#include "proxygrasp/core/error.h"

#include <gtest/gtest.h>

namespace pg {
namespace {

TEST(Error, FormatsFileLineCol) {
  EXPECT_EQ(MakeError({"levels/a.toml", 12, 5}, "friction must be >= 0").Format(),
            "levels/a.toml:12:5: friction must be >= 0");
  EXPECT_EQ(MakeError({"a.toml", 3, 0}, "bad").Format(), "a.toml:3: bad");
  EXPECT_EQ(MakeError({"a.toml", 0, 0}, "missing").Format(), "a.toml: missing");
  EXPECT_EQ(MakeError({}, "plain").Format(), "plain");
}

TEST(Error, ResultHoldsValueOrError) {
  Result<int> good(7);
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(good.value(), 7);
  Result<int> bad(MakeError({"f", 1, 2}, "no"));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().Format(), "f:1:2: no");
}

}  // namespace
}  // namespace pg
