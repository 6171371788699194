// Where a level named on a command line is: a path, or a name looked up in level folders (the
// working directory's levels/, an installed share/proxygrasp/levels). The proxygrasp command
// searches its own folders (app/level_search.h); an embedding program passes its own, such as
// the proxygrasp_LEVELS_DIR its CMake package gives (docs/embedding.md).
#pragma once

#include "proxygrasp/core/error.h"

#include <span>
#include <string>
#include <vector>

namespace pg {

/// The level file `nameOrPath` means: itself when it is an existing file; else, when it is a bare
/// name (no '/'), the first of `dirs` holding NAME.toml, or NAME when it already ends in .toml.
/// Not found, the Error says what was tried, lists the folders searched and suggests the
/// closest level name found there ("did you mean 'demo_sort'?"). An existing folder, or a path
/// with a '/' that is not a file, is an Error naming the path.
Result<std::string> FindLevelFile(const std::string& nameOrPath, std::span<const std::string> dirs);

/// The level names (file stems of *.toml, sorted, without duplicates) in these folders; missing
/// folders are skipped.
std::vector<std::string> ListLevelNames(std::span<const std::string> dirs);

}  // namespace pg
