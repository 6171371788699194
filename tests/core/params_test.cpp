#include "proxygrasp/core/params.h"

#include <gtest/gtest.h>

namespace pg {
namespace {

enum class Color { kRed, kGreen };
constexpr const char* kColorNames[] = {"red", "green"};

struct Sample {
  double length = 2.5;
  int count = 3;
  bool enabled = false;
  Color color = Color::kRed;
  std::string path = "a.yaml";
};

void Describe(Sample& s, ParamVisitor& v) {
  v.Real("length", s.length, 0, 10, "cm", "a length");
  v.Integer("count", s.count, 1, 5, "1", "a count");
  v.Boolean("enabled", s.enabled, "a flag");
  VisitEnum(v, "color", s.color, kColorNames, "a colour");
  v.Text("path", s.path, "a file");
}

ParamSection SectionOf(Sample& s) {
  return {"sample", [&s](ParamVisitor& v) { Describe(s, v); }};
}

TEST(Params, ListsFieldsWithValues) {
  Sample s;
  const auto fields = ListFields(SectionOf(s));
  ASSERT_EQ(fields.size(), 5u);
  EXPECT_EQ(fields[0].key, "length");
  EXPECT_EQ(fields[0].value, "2.5");
  EXPECT_EQ(fields[0].unit, "cm");
  EXPECT_EQ(fields[1].value, "3");
  EXPECT_EQ(fields[2].value, "false");
  EXPECT_EQ(fields[3].value, "\"red\"");
  ASSERT_EQ(fields[3].choices.size(), 2u);
  EXPECT_EQ(fields[4].value, "\"a.yaml\"");
}

TEST(Params, SetsEachType) {
  Sample s;
  const ParamSection section = SectionOf(s);
  EXPECT_FALSE(SetFieldFromText(section, "length", "7.25"));
  EXPECT_FALSE(SetFieldFromText(section, "count", "5"));
  EXPECT_FALSE(SetFieldFromText(section, "enabled", "true"));
  EXPECT_FALSE(SetFieldFromText(section, "color", "green"));
  EXPECT_FALSE(SetFieldFromText(section, "path", "\"b.yaml\""));
  EXPECT_EQ(s.length, 7.25);
  EXPECT_EQ(s.count, 5);
  EXPECT_TRUE(s.enabled);
  EXPECT_EQ(s.color, Color::kGreen);
  EXPECT_EQ(s.path, "b.yaml");
}

TEST(Params, RejectsBadValuesAndKeepsOldOnes) {
  Sample s;
  const ParamSection section = SectionOf(s);
  const Status range = SetFieldFromText(section, "length", "11");
  ASSERT_TRUE(range);
  EXPECT_EQ(range->message, "sample.length: value 11 is out of range [0, 10] cm");
  const Status type = SetFieldFromText(section, "count", "2.5");
  ASSERT_TRUE(type);
  EXPECT_EQ(type->message, "sample.count: expected an integer, got '2.5'");
  const Status choice = SetFieldFromText(section, "color", "blue");
  ASSERT_TRUE(choice);
  EXPECT_EQ(choice->message, "sample.color: 'blue' is not one of: red, green");
  const Status unknown = SetFieldFromText(section, "lenght", "1");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->message, "unknown key 'sample.lenght' (did you mean 'length'?)");
  EXPECT_EQ(s.length, 2.5);
  EXPECT_EQ(s.count, 3);
  EXPECT_EQ(s.color, Color::kRed);
}

TEST(Params, ChangedFieldsAsToml) {
  Sample s, defaults;
  EXPECT_EQ(ChangedFieldsAsToml(SectionOf(s), SectionOf(defaults)), "");
  s.length = 4.0;
  s.color = Color::kGreen;
  EXPECT_EQ(ChangedFieldsAsToml(SectionOf(s), SectionOf(defaults)),
            "[sample]\nlength = 4\ncolor = \"green\"\n");
}

}  // namespace
}  // namespace pg
