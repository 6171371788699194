// Stable integer ids. Ids start at 1, grow by one, and are never reused within a run.
#pragma once

#include <cstdint>

namespace pg {

/// Id of a tracked contact (finger, hand, thing on the table).
using ContactId = int32_t;
/// Id of a particle proxy (a stack of bodies in the physics).
using ParticleId = int32_t;
/// A virtual object: its index in the level's object list, from 0 (unlike the ids above, which
/// are counted from 1).
using ObjectId = int32_t;
/// The ObjectId that names no object: what a particle resting on the bare table rests on.
inline constexpr ObjectId kNoObject = -1;

/// The contact or particle id that names nothing.
inline constexpr int32_t kNoId = 0;

/// Hands out ids 1, 2, 3, ... and never reuses one.
class IdCounter {
 public:
  int32_t Next() { return m_next++; }
  /// The id the next call to Next() returns.
  int32_t Peek() const { return m_next; }

 private:
  int32_t m_next = 1;
};

}  // namespace pg
