// Timing for per-stage milliseconds: wall time, or the calling thread's CPU time.
#pragma once

#include <chrono>
#include <ctime>

namespace pg {

/// What a Stopwatch measures.
enum class TimerClock {
  kWall,       ///< elapsed wall time (steady clock)
  kThreadCpu,  ///< CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID)
};

/// Measures elapsed time from construction or the last Restart().
class Stopwatch {
 public:
  explicit Stopwatch(TimerClock clock = TimerClock::kWall) : m_clock(clock), m_start(Now()) {}
  void Restart() { m_start = Now(); }
  /// Milliseconds since the start.
  double Ms() const { return Now() - m_start; }

 private:
  // the clock's reading, ms
  double Now() const {
    if (m_clock == TimerClock::kThreadCpu) {
      timespec t{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
      return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
    }
    return std::chrono::duration<double, std::milli>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  TimerClock m_clock;
  double m_start;
};

}  // namespace pg
