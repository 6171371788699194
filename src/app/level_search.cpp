#include "proxygrasp/app/level_search.h"

#include "proxygrasp/level/find.h"

#include <filesystem>
#include <fstream>

#ifndef PROXYGRASP_DATADIR_FROM_BINDIR
#error "the build defines PROXYGRASP_DATADIR_FROM_BINDIR (src/app/CMakeLists.txt)"
#endif

namespace pg {

namespace fs = std::filesystem;

namespace {

// the folder the running command is in, "" when /proc/self/exe cannot say
fs::path ExeDir() {
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

bool IsDir(const fs::path& p) {
  std::error_code ec;
  return !p.empty() && fs::is_directory(p, ec);
}

}  // namespace

std::string InstalledDataDir() {
  const fs::path exeDir = ExeDir();
  if (exeDir.empty()) return "";
  const fs::path data = (exeDir / PROXYGRASP_DATADIR_FROM_BINDIR).lexically_normal();
  return IsDir(data) ? data.string() : "";
}

std::string BuildSourceDir() {
  const fs::path exeDir = ExeDir();
  if (exeDir.empty()) return "";
  std::ifstream cache(exeDir / "CMakeCache.txt");
  const std::string key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
  for (std::string line; std::getline(cache, line);) {
    if (line.compare(0, key.size(), key) == 0) {
      const fs::path source = line.substr(key.size());
      return IsDir(source) ? source.string() : "";
    }
  }
  return "";
}

std::vector<std::string> LevelSearchDirs() {
  std::vector<std::string> dirs;
  // an existing folder not already in the list (run from the source tree, ./levels is the
  // build's source levels)
  auto add = [&dirs](const fs::path& dir) {
    if (!IsDir(dir)) return;
    for (const std::string& d : dirs) {
      std::error_code ec;
      if (fs::equivalent(d, dir, ec)) return;
    }
    dirs.push_back(dir.string());
  };
  // the working directory's levels, then the installed ones, then the source tree's
  add("levels");
  if (const std::string data = InstalledDataDir(); !data.empty()) add(fs::path(data) / "levels");
  if (const std::string source = BuildSourceDir(); !source.empty())
    add(fs::path(source) / "levels");
  return dirs;
}

Result<std::string> ResolveLevel(const std::string& nameOrPath) {
  return FindLevelFile(nameOrPath, LevelSearchDirs());
}

}  // namespace pg
