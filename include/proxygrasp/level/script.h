// A level's script: contacts with a shape and keyframed poses over time, played into the synthetic
// table camera. A contact exists from its first keyframe to its last, inclusive.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tuio/osc.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pg {

/// How a contact moves between two keyframes.
enum class Interpolation {
  kLinear,  ///< constant velocity within a segment
  kSmooth,  ///< smoothstep ease in and out: zero velocity at every keyframe
};
inline constexpr const char* kInterpolationNames[] = {"linear", "smooth"};

/// Time a script runs on after its last keyframe when it names no duration, s.
inline constexpr double kScriptSettleTime = 1.0;

/// One keyframe of a contact: where it is at time t. Angles in radians (degrees in the file).
struct Keyframe {
  double t = 0.0;       ///< s from the start of the level
  Pose2 pose;           ///< position cm, angle rad CCW
  double height = 0.0;  ///< from the table to the contact's underside, cm (0 = touching)
  SourceLoc loc;        ///< where the level defines it
};

/// A scripted contact: a synthetic-camera shape moved through its keyframes.
struct ScriptContact {
  std::string name;
  ContactShape shape;  ///< size and kind; its pose is set by the keyframes
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<Keyframe> keys;  ///< at least one, t strictly increasing
  SourceLoc loc;

  /// Time of the first keyframe, s.
  double Start() const { return keys.front().t; }
  /// Time of the last keyframe, s.
  double End() const { return keys.back().t; }
};

/// The [script] of a level.
struct Script {
  double duration = kScriptSettleTime;  ///< s; default: the last keyframe + kScriptSettleTime
  Interpolation interpolation = Interpolation::kLinear;  ///< default for contacts naming none
  std::vector<ScriptContact> contacts;
  /// A recorded video (`proxygrasp run --record`) whose frames replace the rendered contacts, as
  /// an absolute or level-relative path resolved by the loader; "" renders the contacts.
  std::string recording;
  int64_t recordingFrames = 0;  ///< frames in the recording, counted by the loader
  /// A recorded TUIO stream (touchlib XML: proxygrasp's own `--tuio-out file:PATH` or a real
  /// table's) whose contacts replace the script's, as an absolute or level-relative path resolved
  /// by the loader; "" when there is none.
  std::string tuio;
  /// Its packets, read by the loader; shared, as the level is copied into each run.
  std::shared_ptr<const std::vector<OscBundle>> tuioBundles;
  SourceLoc loc;
};

/// The contact's pose at time t (s), or nullopt when t is before its first or after its last
/// keyframe.
std::optional<Pose2> PoseAt(const ScriptContact& contact, double t);

/// The contact's height above the table at time t (cm, from the table to its underside),
/// interpolated as its pose is, or nullopt when t is before its first or after its last keyframe.
std::optional<double> HeightAt(const ScriptContact& contact, double t);

/// The contacts present at time t (s), in script order, each with its interpolated pose (radians)
/// and height (cm).
/// When contactIndices is given it receives the index into script.contacts of each shape.
std::vector<ContactShape> ShapesAt(const Script& script, double t,
                                   std::vector<int>* contactIndices = nullptr);

/// Time of the last keyframe of any contact, s; 0 when there are none.
double LastKeyframeTime(const Script& script);

}  // namespace pg
