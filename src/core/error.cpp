#include "proxygrasp/core/error.h"

namespace pg {

std::string SourceLoc::Format() const {
  if (file.empty()) return {};
  std::string s = file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (col > 0) s += ":" + std::to_string(col);
  }
  return s;
}

std::string Error::Format() const {
  const std::string where = loc.Format();
  return where.empty() ? message : where + ": " + message;
}

Error MakeError(SourceLoc loc, std::string message) {
  return Error{std::move(loc), std::move(message)};
}

}  // namespace pg
