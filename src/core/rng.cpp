#include "proxygrasp/core/rng.h"

#include "proxygrasp/core/units.h"

#include <cmath>

namespace pg {

namespace {

uint64_t SplitMix64(uint64_t& x) {
  uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

uint64_t Rotl(uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

}  // namespace

Rng::Rng(uint64_t seed) {
  for (uint64_t& s : m_s) s = SplitMix64(seed);
}

uint64_t Rng::NextU64() {
  const uint64_t result = Rotl(m_s[1] * 5, 7) * 9;
  const uint64_t t = m_s[1] << 17;
  m_s[2] ^= m_s[0];
  m_s[3] ^= m_s[1];
  m_s[1] ^= m_s[2];
  m_s[0] ^= m_s[3];
  m_s[2] ^= t;
  m_s[3] = Rotl(m_s[3], 45);
  return result;
}

double Rng::Uniform() {
  return static_cast<double>(NextU64() >> 11) * 0x1.0p-53;
}

double Rng::Normal() {
  if (m_hasSpare) {
    m_hasSpare = false;
    return m_spare;
  }
  // Box-Muller on (0, 1] so the log is finite
  const double u1 = 1.0 - Uniform();
  const double u2 = Uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  m_spare = r * std::sin(2.0 * kPi * u2);
  m_hasSpare = true;
  return r * std::cos(2.0 * kPi * u2);
}

}  // namespace pg
