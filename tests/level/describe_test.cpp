#include "test_paths.h"

#include "proxygrasp/level/level.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
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
  EXPECT_EQ(keys.size(), 20u) << "every ObjectSpec field but loc is a key";
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

TEST(Describe, SizeKeysOfAShapeComeFromTheDescription) {
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kBox), "size_x, size_y, height");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kSphere), "radius, patch_radius");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kFrustum), "radius, top_radius, height");
  EXPECT_EQ(ObjectSizeKeys(ObjectShape::kConcavePrism), "height, points");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kEllipse), "radius_x, radius_y");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kCapsule), "radius, length");
  EXPECT_EQ(ContactSizeKeys(ShapeKind::kHandFlat), "scale");
}

// docs/levels.md, or "" when it cannot be read
std::string LevelsDoc() {
  std::ifstream in(std::string(pg::test::SourceDir()) + "/docs/levels.md");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// the part of doc under heading, up to the next heading of the same or a higher level
std::string DocSection(const std::string& doc, const std::string& heading) {
  const size_t b = doc.find("\n" + heading + "\n");
  if (b == std::string::npos) return "";
  const std::string level = "\n" + heading.substr(0, heading.find(' ') + 1);
  size_t e = doc.find(level, b + 1);
  if (heading.starts_with("### ")) e = std::min(e, doc.find("\n## ", b + 1));
  return doc.substr(b, e == std::string::npos ? std::string::npos : e - b);
}

// the table rows of section that name `key`
std::vector<std::string> RowsOf(const std::string& section, const std::string& key) {
  std::vector<std::string> rows;
  std::istringstream lines(section);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("|") && line.find("`" + key + "`") != std::string::npos) {
      rows.push_back(line);
    }
  }
  return rows;
}

// docs/levels.md is written by hand around these keys; every key must appear in a table row with
// its default, so the reference cannot drift from the code
TEST(Describe, DocsListEveryObjectAndContactKeyWithItsDefault) {
  const std::string doc = LevelsDoc();
  ASSERT_FALSE(doc.empty()) << "docs/levels.md is missing";
  auto section = [&doc](const std::string& heading) {
    const std::string text = DocSection(doc, heading);
    EXPECT_FALSE(text.empty()) << heading;
    return text;
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

TEST(Describe, FileKeysAreDocumented) {
  std::set<std::string> names;
  for (const ParamSection& section : FileSections()) {
    names.insert(section.name);
    std::set<std::string> keys;
    for (const FieldInfo& f : ListFields(section)) {
      EXPECT_TRUE(keys.insert(f.key).second) << section.name << "." << f.key;
      EXPECT_FALSE(f.doc.empty()) << section.name << "." << f.key;
      EXPECT_FALSE(f.unit.empty() &&
                   (f.type == FieldInfo::Type::kReal || f.type == FieldInfo::Type::kVector))
          << section.name << "." << f.key << " has no unit";
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"script", "script.contacts", "keys", "variants", "region",
                                          "expect", "expect.rotation", "goals"}));
}

// every key of the file's own tables has a row in its docs/levels.md section that gives its unit,
// and a row that starts with the key alone gives its default (or says it is required)
TEST(Describe, DocsListEveryFileKeyWithItsUnitAndDefault) {
  const std::string doc = LevelsDoc();
  ASSERT_FALSE(doc.empty()) << "docs/levels.md is missing";
  const std::vector<std::pair<std::string, std::vector<std::string>>> headings = {
      {"script", {"### [script]"}},
      {"script.contacts", {"### [[script.contacts]]"}},
      {"keys", {"### keys"}},
      {"variants", {"## [[variants]]"}},
      {"region", {"## [[expect]]", "## [[goals]]"}},
      {"expect", {"## [[expect]]"}},
      {"expect.rotation", {"## [[expect]]"}},
      {"goals", {"## [[goals]]"}},
  };
  // defaults the docs give otherwise than the description's value
  const std::map<std::string, std::string> defaults = {
      {"script.contacts.name", "required"},
      {"script.contacts.shape", "required"},
      {"script.contacts.interpolation", "[script] interpolation"},
      {"keys.t", "required"},
      {"keys.pos", "required"},
      {"expect.kind", "required"},
      {"expect.rotation.kind", "required"},
      {"variants.name", "required"},
      {"goals.object", "required"}};
  for (const ParamSection& section : FileSections()) {
    std::vector<std::string> docs;
    for (const auto& [name, list] : headings) {
      if (name == section.name) docs = list;
    }
    ASSERT_FALSE(docs.empty()) << section.name << " has no docs/levels.md heading";
    for (const std::string& heading : docs) {
      const std::string text = DocSection(doc, heading);
      ASSERT_FALSE(text.empty()) << "docs/levels.md lacks " << heading;
      for (const FieldInfo& f : ListFields(section)) {
        const std::string where = heading + " `" + f.key + "`";
        const std::vector<std::string> rows = RowsOf(text, f.key);
        ASSERT_FALSE(rows.empty()) << "docs/levels.md " << where << " has no row";
        const std::string unit = "| " + f.unit + " |";
        EXPECT_TRUE(f.unit.empty() ||
                    std::any_of(rows.begin(), rows.end(),
                                [&](const auto& r) { return r.find(unit) != std::string::npos; }))
            << "docs/levels.md " << where << " lacks its unit " << f.unit;
        // a key given a default in one row must give the described one
        const std::string cell = "`" + f.key + "` | `";
        const bool given = std::any_of(rows.begin(), rows.end(), [&](const std::string& r) {
          return r.find(cell) != std::string::npos;
        });
        const auto special = defaults.find(section.name + "." + f.key);
        const std::string value = special != defaults.end() ? special->second : f.value;
        EXPECT_TRUE(!given || std::any_of(rows.begin(), rows.end(),
                                          [&](const std::string& r) {
                                            return r.find(cell + value + "` |") !=
                                                   std::string::npos;
                                          }))
            << "docs/levels.md " << where << " should have the default " << value;
      }
    }
  }
}

}  // namespace
}  // namespace pg
