#include "proxygrasp/core/params.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>

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
  v.Integer("count", s.count, 1, 5, "1", {"a count", Apply::kRestart});
  v.Boolean("enabled", s.enabled, "a flag");
  VisitEnum(v, "color", s.color, kColorNames, "a colour");
  v.Text("path", s.path, {"a file", Apply::kRestart});
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
  const MaybeError range = SetFieldFromText(section, "length", "11");
  ASSERT_TRUE(range);
  EXPECT_EQ(range->message, "sample.length: value 11 is out of range [0, 10] cm");
  const MaybeError type = SetFieldFromText(section, "count", "2.5");
  ASSERT_TRUE(type);
  EXPECT_EQ(type->message, "sample.count: expected an integer, got '2.5'");
  const MaybeError choice = SetFieldFromText(section, "color", "blue");
  ASSERT_TRUE(choice);
  EXPECT_EQ(choice->message, "sample.color: 'blue' is not one of: red, green");
  const MaybeError unknown = SetFieldFromText(section, "lenght", "1");
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

TEST(Params, CheckFieldsNamesTheFirstValueOutOfItsRange) {
  Sample s;
  EXPECT_FALSE(CheckFields(SectionOf(s)));
  // values set in code, not through text, are checked against the same ranges
  s.count = 0;
  s.length = 12.0;
  const MaybeError both = CheckFields(SectionOf(s));
  ASSERT_TRUE(both);
  EXPECT_EQ(both->message, "sample.length must be in [0, 10] cm (got 12)");
  s.length = std::nan("");
  const MaybeError nan = CheckFields(SectionOf(s));
  ASSERT_TRUE(nan);
  EXPECT_EQ(nan->message, "sample.length must be in [0, 10] cm (got nan)");
  s.length = 1.0;
  const MaybeError count = CheckFields(SectionOf(s));
  ASSERT_TRUE(count);
  EXPECT_EQ(count->message, "sample.count must be in [1, 5] (got 0)");
  s.count = 1;
  s.color = static_cast<Color>(2);
  const MaybeError choice = CheckFields(SectionOf(s));
  ASSERT_TRUE(choice);
  EXPECT_EQ(choice->message, "sample.color must be one of red, green (got index 2)");
}

TEST(Params, ChangedKeysListsExactlyTheFieldsThatDiffer) {
  Sample a, b;
  EXPECT_TRUE(ChangedKeys(SectionOf(a), SectionOf(b)).empty());
  // the smallest change of a double counts
  b.length = std::nextafter(a.length, 10.0);
  b.path = "c.yaml";
  EXPECT_EQ(ChangedKeys(SectionOf(a), SectionOf(b)), (std::vector<std::string>{"length", "path"}));
}

// a struct with the geometric field kinds: an angle, a vector and a point list
struct Shape {
  double heading = 0.5 * kPi;  // rad
  Vec2 pos = Vec2(1.0, 2.0);
  std::vector<Vec2> outline = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
};

void Describe(Shape& s, ParamVisitor& v) {
  v.Angle("heading", s.heading, -360, 360, "deg", "a heading");
  v.Vector("pos", s.pos, -10, 10, "cm", "a position");
  v.Points("outline", s.outline, -5, 5, "cm", "an outline");
}

ParamSection SectionOf(Shape& s) {
  return {"shape", [&s](ParamVisitor& v) { Describe(s, v); }};
}

TEST(Params, EachFieldSaysWhenAChangeTakesEffect) {
  Sample s;
  const std::vector<FieldInfo> fields = ListFields(SectionOf(s));
  EXPECT_EQ(fields[0].apply, Apply::kLive) << "a plain doc is a live field";
  EXPECT_EQ(fields[1].apply, Apply::kRestart);
  EXPECT_EQ(fields[1].doc, "a count");
  Sample next;
  next.length = 3;
  next.count = 4;
  next.path = "b.yaml";
  EXPECT_EQ(RestartKeysChanged("sample", s, next), (std::vector<std::string>{"count", "path"}));
  EXPECT_EQ(ChangedKeys(SectionOf(s), SectionOf(next)),
            (std::vector<std::string>{"length", "count", "path"}));
  EXPECT_TRUE(RestartKeysChanged("sample", s, s).empty());
  next.count = 9;
  const MaybeError bad = CheckDescribed("sample", next);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->Format(), "sample.count must be in [1, 5] (got 9)");
  EXPECT_FALSE(CheckDescribed("sample", s));
}

TEST(Params, ListsAnglesInDegreesAndVectorsAsArrays) {
  Shape s;
  const auto fields = ListFields(SectionOf(s));
  ASSERT_EQ(fields.size(), 3u);
  EXPECT_EQ(fields[0].type, FieldInfo::Type::kReal);
  EXPECT_EQ(fields[0].value, "90");
  EXPECT_EQ(fields[0].unit, "deg");
  EXPECT_EQ(fields[1].type, FieldInfo::Type::kVector);
  EXPECT_EQ(fields[1].value, "[1, 2]");
  EXPECT_EQ(fields[1].min, -10);
  EXPECT_EQ(fields[2].type, FieldInfo::Type::kPoints);
  EXPECT_EQ(fields[2].value, "[[0, 0], [1, 0], [0, 1]]");
}

TEST(Params, SetsAnglesVectorsAndPoints) {
  Shape s;
  const ParamSection section = SectionOf(s);
  EXPECT_FALSE(SetFieldFromText(section, "heading", "-45"));
  EXPECT_DOUBLE_EQ(s.heading, -0.25 * kPi);
  EXPECT_FALSE(SetFieldFromText(section, "pos", "[3.5, -4]"));
  EXPECT_EQ(s.pos, Vec2(3.5, -4));
  EXPECT_FALSE(SetFieldFromText(section, "outline", "[[0, 0], [2, 0], [2, 2], [0, 2]]"));
  ASSERT_EQ(s.outline.size(), 4u);
  EXPECT_EQ(s.outline[2], Vec2(2, 2));
  EXPECT_FALSE(SetFieldFromText(section, "outline", "[]"));
  EXPECT_TRUE(s.outline.empty());
}

TEST(Params, RejectsBadVectorsAndPointsAndKeepsOldOnes) {
  Shape s;
  const ParamSection section = SectionOf(s);
  const MaybeError angle = SetFieldFromText(section, "heading", "400");
  ASSERT_TRUE(angle);
  EXPECT_EQ(angle->message, "shape.heading: value 400 is out of range [-360, 360] deg");
  const MaybeError three = SetFieldFromText(section, "pos", "[1, 2, 3]");
  ASSERT_TRUE(three);
  EXPECT_EQ(three->message, "shape.pos: expected [x, y], got '[1, 2, 3]'");
  const MaybeError far = SetFieldFromText(section, "pos", "[1, 20]");
  ASSERT_TRUE(far);
  EXPECT_EQ(far->message, "shape.pos: value [1, 20] is out of range [-10, 10] cm");
  const MaybeError flat = SetFieldFromText(section, "outline", "[0, 1]");
  ASSERT_TRUE(flat);
  EXPECT_EQ(flat->message, "shape.outline: expected [[x, y], ...], got '[0, 1]'");
  const MaybeError outside = SetFieldFromText(section, "outline", "[[0, 0], [6, 0]]");
  ASSERT_TRUE(outside);
  EXPECT_EQ(outside->message, "shape.outline: point [6, 0] is out of range [-5, 5] cm");
  const MaybeError open = SetFieldFromText(section, "outline", "[[0, 0], [1, 0]");
  ASSERT_TRUE(open);
  EXPECT_DOUBLE_EQ(s.heading, 0.5 * kPi);
  EXPECT_EQ(s.pos, Vec2(1, 2));
  EXPECT_EQ(s.outline.size(), 3u);
}

TEST(Params, AngleVisitedButUnchangedKeepsItsExactRadians) {
  // degrees -> radians -> degrees need not round-trip bit for bit; an unset angle must not drift
  Shape s;
  s.heading = 0.1;
  EXPECT_FALSE(SetFieldFromText(SectionOf(s), "pos", "[0, 0]"));
  EXPECT_EQ(s.heading, 0.1);
}

TEST(Params, CheckFieldsCoversAnglesVectorsAndPoints) {
  Shape s;
  EXPECT_FALSE(CheckFields(SectionOf(s)));
  s.outline[1] = Vec2(6, 0);
  const MaybeError point = CheckFields(SectionOf(s));
  ASSERT_TRUE(point);
  EXPECT_EQ(point->message, "shape.outline must have each coordinate in [-5, 5] cm (got [6, 0])");
  s.pos = Vec2(0, -11);
  const MaybeError pos = CheckFields(SectionOf(s));
  ASSERT_TRUE(pos);
  EXPECT_EQ(pos->message, "shape.pos must have each coordinate in [-10, 10] cm (got [0, -11])");
  // angles are checked in degrees, as they are written
  s.heading = DegToRad(400);
  const MaybeError angle = CheckFields(SectionOf(s));
  ASSERT_TRUE(angle);
  EXPECT_EQ(angle->message.rfind("shape.heading must be in [-360, 360] deg (got 4", 0), 0u)
      << angle->message;
}

TEST(Params, TypeNamesCoverEveryKind) {
  EXPECT_STREQ(TypeName(FieldInfo::Type::kVector), "an array [x, y]");
  EXPECT_STREQ(TypeName(FieldInfo::Type::kPoints), "an array of points [[x, y], ...]");
}

}  // namespace
}  // namespace pg
