// Wall-clock timing for per-stage milliseconds.
#pragma once

#include <chrono>

namespace pg {

/// Measures elapsed wall time from construction or the last Restart().
class Stopwatch {
 public:
  Stopwatch() : m_start(std::chrono::steady_clock::now()) {}
  void Restart() { m_start = std::chrono::steady_clock::now(); }
  /// Milliseconds since the start.
  double Ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace pg
