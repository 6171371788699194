#include "proxygrasp/level/find.h"

#include "proxygrasp/core/text.h"

#include <algorithm>
#include <filesystem>

namespace pg {

namespace fs = std::filesystem;

namespace {

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool EndsWithToml(const std::string& s) {
  return s.size() > 5 && s.compare(s.size() - 5, 5, ".toml") == 0;
}

}  // namespace

Result<std::string> FindLevelFile(const std::string& nameOrPath,
                                  std::span<const std::string> dirs) {
  if (nameOrPath.empty()) return MakeError({}, "no level given (a level file or a level name)");
  if (IsFile(nameOrPath)) return nameOrPath;
  std::error_code ec;
  if (fs::is_directory(nameOrPath, ec)) {
    return MakeError({}, "level " + nameOrPath + ": is a folder, not a level file");
  }
  // a path with a folder in it means that file and nothing else
  if (nameOrPath.find('/') != std::string::npos) {
    return MakeError({}, "level " + nameOrPath + ": no such file");
  }

  // a bare name: NAME.toml (or NAME as given, when it ends in .toml) in each folder in order
  const std::string file = EndsWithToml(nameOrPath) ? nameOrPath : nameOrPath + ".toml";
  for (const std::string& dir : dirs) {
    const fs::path candidate = fs::path(dir) / file;
    if (IsFile(candidate)) return candidate.lexically_normal().string();
  }

  // not found: say where it looked, and the nearest name there
  std::string searched;
  for (const std::string& dir : dirs) searched += (searched.empty() ? "" : ", ") + dir;
  if (searched.empty()) searched = "no level folders";
  std::string message = "level " + nameOrPath + ": not a file, and no " + file + " in " + searched;
  const std::vector<std::string> names = ListLevelNames(dirs);
  const std::string stem =
      EndsWithToml(nameOrPath) ? nameOrPath.substr(0, nameOrPath.size() - 5) : nameOrPath;
  message += DidYouMean(stem, names);
  return MakeError({}, message);
}

std::vector<std::string> ListLevelNames(std::span<const std::string> dirs) {
  std::vector<std::string> names;
  for (const std::string& dir : dirs) {
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->path().extension() == ".toml" && IsFile(it->path())) {
        names.push_back(it->path().stem().string());
      }
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

}  // namespace pg
