// Where the proxygrasp command looks for a level given by name (`proxygrasp run demo_sort`), and
// for its data: the working directory's levels/, the installed share/proxygrasp next to the
// command, and the source tree of a build folder. Paths are found from the command's own location
// (/proc/self/exe), never from a prefix fixed at build time, so a moved install still works.
#pragma once

#include "proxygrasp/core/error.h"

#include <string>
#include <vector>

namespace pg {

/// The command's data folder, share/proxygrasp beside its bin/ (<exe>/../share/proxygrasp for
/// the default layout), when it exists; "" otherwise (a build folder).
std::string InstalledDataDir();

/// The source folder of the build folder the command sits in: when <exe folder>/CMakeCache.txt
/// names a CMAKE_HOME_DIRECTORY that exists; "" otherwise (an installed command).
std::string BuildSourceDir();

/// The existing level folders, in search order: ./levels, InstalledDataDir()/levels,
/// BuildSourceDir()/levels.
std::vector<std::string> LevelSearchDirs();

/// FindLevelFile (level/find.h) over LevelSearchDirs: a path that exists, else a name there.
Result<std::string> ResolveLevel(const std::string& nameOrPath);

}  // namespace pg
