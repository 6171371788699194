#include "proxygrasp/core/text.h"

#include <gtest/gtest.h>

#include <vector>

namespace pg {
namespace {

TEST(Text, EditDistance) {
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("", "abc"), 3);
  EXPECT_EQ(EditDistance("same", "same"), 0);
  EXPECT_EQ(EditDistance("substeps", "substep"), 1);
}

TEST(Text, DidYouMeanFindsCloseKeyOnly) {
  const std::vector<std::string> keys = {"substeps", "layers", "layer_height", "threads"};
  EXPECT_EQ(DidYouMean("substep", keys), " (did you mean 'substeps'?)");
  EXPECT_EQ(DidYouMean("layer_heigth", keys), " (did you mean 'layer_height'?)");
  EXPECT_EQ(DidYouMean("completely_different", keys), "");
}

TEST(Text, FormatFixedKeepsItsDecimals) {
  EXPECT_EQ(FormatFixed(0.05, 6), "0.050000");
  EXPECT_EQ(FormatFixed(-1.23456, 2), "-1.23");
  EXPECT_EQ(FormatFixed(2.5, 0), "2");  // round half to even, as printf
}

TEST(Text, FormatDoubleRoundTrips) {
  EXPECT_EQ(FormatDouble(0.3), "0.3");
  EXPECT_EQ(FormatDouble(61.0), "61");
  EXPECT_EQ(FormatDouble(-2.5), "-2.5");
}

}  // namespace
}  // namespace pg
