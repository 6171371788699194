// Describe(PhysicsParams) (src/physics/params.cpp): every field is listed with a unit and a
// default inside its range, and can be set by name.
#include "proxygrasp/physics/types.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace pg {
namespace {

TEST(PhysicsParams, EveryFieldHasUnitAndDefaultInRange) {
  PhysicsParams p;
  const ParamSection section{"physics", [&p](ParamVisitor& v) { Describe(p, v); }};
  const std::vector<FieldInfo> fields = ListFields(section);
  EXPECT_EQ(fields.size(), 22u);
  for (const FieldInfo& f : fields) {
    EXPECT_FALSE(f.doc.empty()) << f.key;
    if (f.type == FieldInfo::Type::kReal || f.type == FieldInfo::Type::kInteger) {
      EXPECT_FALSE(f.unit.empty()) << f.key;
      const double v = std::strtod(f.value.c_str(), nullptr);
      EXPECT_GE(v, f.min) << f.key;
      EXPECT_LE(v, f.max) << f.key;
    }
  }
}

TEST(PhysicsParams, SetByNameWithRangeCheck) {
  PhysicsParams p;
  const ParamSection section{"physics", [&p](ParamVisitor& v) { Describe(p, v); }};
  EXPECT_FALSE(SetFieldFromText(section, "top_kinetic_factor", "0.5").has_value());
  EXPECT_DOUBLE_EQ(p.topKineticFactor, 0.5);
  EXPECT_FALSE(SetFieldFromText(section, "layers", "12").has_value());
  EXPECT_EQ(p.layers, 12);
  EXPECT_TRUE(SetFieldFromText(section, "layers", "17").has_value());
  EXPECT_EQ(p.layers, 12);
}

}  // namespace
}  // namespace pg
