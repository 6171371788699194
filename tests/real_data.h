// Where the tests find the footage and recorded streams from other people's tables
// (../shared/real, see its README). Tests that need them skip with kNoRealData when it is absent.
#pragma once

#include "test_paths.h"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace pg::test {

/// The real data folder: $PROXYGRASP_REAL_DATA, else ../shared/real beside the project, else
/// ../../shared/real; "" when none holds `sub`.
inline std::string RealDataDir(const std::string& sub = "touchlib") {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PROXYGRASP_REAL_DATA")) candidates.push_back(env);
  candidates.push_back(std::string(pg::test::SourceDir()) + "/../shared/real");
  candidates.push_back(std::string(pg::test::SourceDir()) + "/../../shared/real");
  for (const std::string& c : candidates)
    if (std::filesystem::is_directory(c + "/" + sub)) return c;
  return "";
}

inline constexpr const char* kNoRealData =
    "../shared/real is absent (a clone of the project alone): no recorded TUIO streams to replay; "
    "set PROXYGRASP_REAL_DATA to its folder";

}  // namespace pg::test
