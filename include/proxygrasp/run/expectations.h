// A level's expectations checked against a run as it goes: each is checked on the first frame at
// or after its time (or at the end of the run), against the state after that frame.
#pragma once

#include "proxygrasp/level/level.h"
#include "proxygrasp/run/plan.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pg {

class Simulation;

/// The outcome of one expectation in one run.
struct ExpectationResult {
  const Expectation* expectation = nullptr;
  std::string text;      ///< what it checks, for the report
  std::string measured;  ///< the value measured, with its unit
  bool passed = false;
};

/// A one-line description of what e checks, for reports: "box held at 2 s (instant)".
std::string ExpectationText(const Expectation& e);

/// How many recent frames decide whether an object is held (0.1 s at 60 Hz): the held flag of a
/// single frame flickers when one contact point slips for a substep.
inline constexpr int kHeldFrames = 6;

/// Checks the expectations of one run of a level. It keeps a fixed amount of state per object
/// (start, unwrapped rotation, the last kHeldFrames held flags), whatever the run's length.
class Evaluator {
 public:
  /// Picks the expectations that apply to run and records the objects' starting poses.
  Evaluator(const Level& level, const LevelRun& run, const Simulation& sim);

  /// After each frame: updates the object tracks, then appends to results every expectation due
  /// by time t (s, the end of the frame).
  void AfterFrame(const Simulation& sim, double t, std::vector<ExpectationResult>& results);

  /// At the end of the run (t, s): checks everything still pending, or fails it as not reached,
  /// and sorts results into file order.
  void Finish(const Simulation& sim, double t, std::vector<ExpectationResult>& results);

 private:
  // what the evaluator remembers of each object across a run
  struct ObjectTrack {
    Vec2 start = Vec2::Zero();
    double lastAngle = 0.0;
    double rotation = 0.0;                 // unwrapped signed rotation since the start, rad
    std::array<bool, kHeldFrames> held{};  // the last frames' held flags, a ring
    int64_t frames = 0;                    // frames seen
    double peakSpeed = 0.0;                // fastest centre of mass at a frame's end, cm/s
  };

  double DefaultTime(const Expectation& e) const;
  ObjectId ObjectIndex(const std::string& name) const;
  ExpectationResult Check(const Expectation& e, const Simulation& sim) const;

  const Level& m_level;
  std::vector<const Expectation*> m_pending;
  std::vector<ObjectTrack> m_objects;
};

}  // namespace pg
