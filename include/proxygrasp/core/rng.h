// A small deterministic random generator: the same seed gives the same sequence on every platform
// and standard library (unlike std::normal_distribution).
#pragma once

#include <cstdint>

namespace pg {

/// xoshiro256** seeded through splitmix64.
class Rng {
 public:
  explicit Rng(uint64_t seed = 1);

  /// Next raw 64-bit value.
  uint64_t NextU64();
  /// Uniform in [0, 1).
  double Uniform();
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Standard normal (mean 0, deviation 1), Box-Muller.
  double Normal();

 private:
  uint64_t m_s[4];
  double m_spare = 0.0;
  bool m_hasSpare = false;
};

}  // namespace pg
