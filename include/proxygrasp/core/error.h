// Errors that name where the problem is: file:line:col for level files, the argument for the
// command line, the frame for sensing. A Result<T> carries either a value or an Error.
#pragma once

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace pg {

/// A place in a source file; line and col are 1-based, 0 when unknown.
struct SourceLoc {
  std::string file;
  int line = 0;
  int col = 0;

  /// "file:line:col", "file:line", "file", or "" depending on what is known.
  std::string Format() const;
};

/// An error with an optional location.
struct Error {
  SourceLoc loc;
  std::string message;

  /// "file:line:col: message", or just the message when there is no location.
  std::string Format() const;
};

/// Builds an Error at a location.
Error MakeError(SourceLoc loc, std::string message);

/// Either a value or an Error.
template <typename T>
class Result {
 public:
  Result(T value) : m_data(std::move(value)) {}      // NOLINT(google-explicit-constructor)
  Result(Error error) : m_data(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return m_data.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() {
    assert(ok() && "Result holds an error, not a value");
    return std::get<0>(m_data);
  }
  const T& value() const {
    assert(ok() && "Result holds an error, not a value");
    return std::get<0>(m_data);
  }
  const Error& error() const {
    assert(!ok() && "Result holds a value, not an error");
    return std::get<1>(m_data);
  }

 private:
  std::variant<T, Error> m_data;
};

/// Nothing when all went well, or the Error. Unlike Result, a MaybeError that converts to true
/// holds a failure: `if (MaybeError e = Start()) return e;`.
using MaybeError = std::optional<Error>;

}  // namespace pg
