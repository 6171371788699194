#include "proxygrasp/level/level.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

namespace pg {
namespace {

std::vector<FieldInfo> ObjectFields() {
  ObjectSpec o;
  return ListFields({"objects", [&o](ParamVisitor& v) { DescribeObject(o, v); }});
}

std::vector<FieldInfo> ContactFields() {
  ContactShape c;
  return ListFields({"contacts", [&c](ParamVisitor& v) { DescribeContactShape(c, v); }});
}

TEST(Describe, ObjectKeysAreUniqueAndDocumented) {
  std::set<std::string> keys;
  for (const FieldInfo& f : ObjectFields()) {
    EXPECT_TRUE(keys.insert(f.key).second) << f.key;
    EXPECT_FALSE(f.doc.empty()) << f.key;
  }
  EXPECT_EQ(keys.size(), 19u) << "every ObjectSpec field but loc is a key";
}

TEST(Describe, AnglesAreListedInDegrees) {
  ObjectSpec o;
  o.pose.angle = 0.5 * 3.14159265358979323846;
  const auto fields = ListFields({"objects", [&o](ParamVisitor& v) { DescribeObject(o, v); }});
  for (const FieldInfo& f : fields) {
    if (f.key == "angle") {
      EXPECT_EQ(f.value, "90");
      EXPECT_EQ(f.unit, "deg");
    }
  }
}

TEST(Describe, SizeKeysApplyToTheirShapes) {
  EXPECT_TRUE(ObjectKeyApplies(ObjectShape::kBox, "size_x"));
  EXPECT_FALSE(ObjectKeyApplies(ObjectShape::kCylinder, "size_x"));
  EXPECT_FALSE(ObjectKeyApplies(ObjectShape::kSphere, "height"));
  EXPECT_TRUE(ObjectKeyApplies(ObjectShape::kFrustum, "top_radius"));
  EXPECT_TRUE(ObjectKeyApplies(ObjectShape::kConcavePrism, "points"));
  EXPECT_TRUE(ObjectKeyApplies(ObjectShape::kSphere, "mass"));
  EXPECT_TRUE(ContactKeyApplies(ShapeKind::kCapsule, "length"));
  EXPECT_FALSE(ContactKeyApplies(ShapeKind::kCircle, "length"));
  EXPECT_TRUE(ContactKeyApplies(ShapeKind::kHandCupped, "scale"));
  EXPECT_FALSE(ContactKeyApplies(ShapeKind::kHandCupped, "radius"));
  EXPECT_TRUE(ContactKeyApplies(ShapeKind::kEllipse, "pressure"));
}

// docs/levels.md is written by hand around these keys; every key must appear in a table row with
// its default, so the reference cannot drift from the code
TEST(Describe, SizeKeysOfAShapeComeFromTheDescription) {
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kBox), "size_x, size_y, height");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kSphere), "radius");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kFrustum), "radius, top_radius, height");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kConcavePrism), "height, points");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kEllipse), "radius_x, radius_y");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kCapsule), "radius, length");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kHandFlat), "scale");
}

TEST(Describe, DocsListEveryObjectAndContactKeyWithItsDefault) {
  std::ifstream in(std::string(PROXYGRASP_SOURCE_DIR) + "/docs/levels.md");
  ASSERT_TRUE(in) << "docs/levels.md is missing";
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string doc = buffer.str();
  auto section = [&doc](const std::string& heading) {
    const size_t b = doc.find(heading);
    EXPECT_NE(b, std::string::npos) << heading;
    if (b == std::string::npos) return std::string();
    const size_t e = doc.find("\n### ", b + 1);
    return doc.substr(b, e == std::string::npos ? std::string::npos : e - b);
  };
  const std::string objects = section("### [[objects]]");
  for (const FieldInfo& f : ObjectFields()) {
    const bool required = f.key == "name" || f.key == "shape" || f.key == "pos";
    const std::string value = required ? "required" : f.value;
    EXPECT_NE(objects.find("| `" + f.key + "` | `" + value + "` |"), std::string::npos)
        << "docs/levels.md [[objects]] lacks a row for " << f.key << " with default " << value;
  }
  const std::string contacts = section("### [[script.contacts]]");
  for (const FieldInfo& f : ContactFields()) {
    const std::string value = f.key == "shape" ? "required" : f.value;
    EXPECT_NE(contacts.find("| `" + f.key + "` | `" + value + "` |"), std::string::npos)
        << "docs/levels.md [[script.contacts]] lacks a row for " << f.key << " with default "
        << value;
  }
}

}  // namespace
}  // namespace pg
