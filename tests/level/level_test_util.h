// Shared by the level module's tests: loading a snippet and reading its first error.
#pragma once

#include "test_paths.h"

#include "proxygrasp/level/level.h"

#include <string>
#include <string_view>
#include <vector>

namespace pg::test {

inline const std::string kData = pg::test::TestDataDir();

// the formatted error of loading text as "inline.toml", or "(loaded)" when it loads
inline std::string ErrorOf(std::string_view text) {
  const Result<Level> r = ParseLevel(text, "inline.toml");
  return r.ok() ? std::string("(loaded)") : r.error().Format();
}

// a valid object to put in front of a snippet that needs one
constexpr const char* kBox = R"(
[[objects]]
name = "box"
shape = "box"
pos = [30, 20]
)";

inline std::vector<std::string> Values(const ParamSection& s) {
  std::vector<std::string> values;
  for (const FieldInfo& f : ListFields(s)) values.push_back(f.key + "=" + f.value);
  return values;
}

}  // namespace pg::test
