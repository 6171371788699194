// The grasp sweep (issue 15; `proxygrasp bench grasp`): random grasp scenes generated from a seed,
// each classified before it runs by an analytic rule (can the grip's friction hold against table
// friction and inertia, with the grip model's bounded force?), then run through the whole pipeline
// and scored: held scenes must follow the grip's rigid motion, the others must slip, and no object
// may move much faster than the fastest contact. The rule is derived in docs/physics.md, "Grasp
// sweep".
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/physics/types.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// The object of a grasp scene.
enum class GraspShape { kBox, kCylinder, kSphere, kTriangle, kHexagon };
inline constexpr const char* kGraspShapeNames[] = {"box", "cylinder", "sphere", "triangle",
                                                   "hexagon"};

/// How the object is gripped. kOpposed: fingertips on two opposite faces, `nearCount` on the
/// near one (a thumb and one, two or three fingers); kCaged: three fingertips at 120 degrees.
enum class GraspGrip { kOpposed, kCaged };

/// What the grip does once it holds the object.
enum class GraspMotion {
  kCarry,  ///< moves rigidly along a direction
  kTurn,   ///< turns rigidly about the object's centre
  kPush,   ///< holds still while a third fingertip pushes into the object across the grip
};
inline constexpr const char* kGraspMotionNames[] = {"carry", "turn", "push"};

/// How the outlines of a scene's contacts meet (issue 42). kNone: every contour keeps 0.6 cm clear
/// of the others; kMerged: fingertips on one face touch (one outline) from the start; kMerge: two
/// fingertips on one face slide together until their outlines merge, or a third finger pushes
/// until its outline merges with the grip's; kSplit: two touching fingertips slide apart.
enum class GraspTopology { kNone, kMerged, kMerge, kSplit };
inline constexpr const char* kGraspTopologyNames[] = {"none", "merged", "merge", "split"};
inline constexpr int kGraspTopologyCount = 4;

/// How a carry or a turn (or a pusher's approach) runs: bang-bang (constant acceleration, then
/// constant deceleration), or a velocity step (constant speed, reached and left within a frame).
enum class GraspProfile { kBangBang, kStep };
inline constexpr const char* kGraspProfileNames[] = {"bang-bang", "step"};

/// Which classes of scene a sweep draws. Only none and bang-bang (`Legacy()`) draws exactly the
/// scenes of the sweep before issue 42, scene for scene.
struct GraspClasses {
  bool topology[kGraspTopologyCount] = {true, true, true, true};
  bool bangBang = true;
  bool step = true;
  static GraspClasses Legacy();
  bool IsLegacy() const;
};

/// Parses `--classes`: "all", "legacy", or a comma-separated list of topologies (none, merged,
/// merge, split) and profiles (bang-bang, step); a list that names no topology takes them all,
/// and one that names no profile takes both.
Result<GraspClasses> ParseGraspClasses(const std::string& list);

/// Another fingertip whose outline merged with a fingertip's: the contour points of the
/// fingertip inside its disc are gone from the merged outline.
struct HiddenDisc {
  Vec2 offset = Vec2::Zero();  ///< its centre, from the fingertip's centre, cm
  double radius = 0.8;         ///< cm
};

/// A fingertip of a scene: a round contact whose contour ends `depth` inside a face.
struct GraspFinger {
  Vec2 pos = Vec2::Zero();     ///< centre where it grips, object frame at the start, cm
  Vec2 inward = Vec2::Zero();  ///< unit direction it presses in (into the object), object frame
  double radius = 0.8;         ///< cm
};

/// One generated scene. Times in s from the start of the level.
struct GraspScene {
  int index = 0;
  uint64_t seed = 0;
  GraspShape shape = GraspShape::kBox;
  ObjectSpec object;  ///< pose, size, mass and frictions
  GraspGrip grip = GraspGrip::kOpposed;
  double depth = 0.5;  ///< how far each gripping contour ends inside its face, cm
  std::vector<GraspFinger> fingers;
  GraspMotion motion = GraspMotion::kCarry;
  Vec2 direction = Vec2::UnitX();  ///< carry: unit direction, table frame
  double distance = 0.0;           ///< carry: cm
  double speed = 0.0;              ///< carry: peak speed, cm/s
  double turn = 0.0;               ///< turn: signed angle, rad
  double turnRate = 0.0;           ///< turn: peak rate, rad/s
  GraspFinger pusher;              ///< push: the third fingertip at its deepest
  double pushDepth = 0.0;          ///< push: how far its contour ends inside its face, cm
  GraspTopology topology = GraspTopology::kNone;
  GraspProfile profile = GraspProfile::kBangBang;
  /// kMerge, kSplit (not a merging pusher): the fingers once they have slid (the same fingers,
  /// in order, object frame at the start); empty when nothing slides
  std::vector<GraspFinger> fingersAfter;
  double eventStart = 0.0;  ///< when the fingers start to slide, s
  double eventEnd = 0.0;    ///< when they have slid, s
  double moveStart = 0.0;   ///< when the motion (or the push's approach) starts, s
  double moveEnd = 0.0;     ///< when it ends, s
  double duration = 0.0;    ///< of the level, s
};

/// What the rule says of a scene, before it runs (docs/physics.md, "Grasp sweep").
struct GraspPrediction {
  double normalForce = 0.0;   ///< sum of the gripping fingers' normal forces at rest, dyn
  double capacity = 0.0;      ///< what the grip can supply: dyn, or dyn cm for a turn
  double requirement = 0.0;   ///< what the motion needs: dyn, or dyn cm for a turn
  double margin = 0.0;        ///< capacity / requirement (infinity when nothing is required)
  bool canHold = false;       ///< margin >= 1
  bool nearBoundary = false;  ///< margin within 20% of 1 (0.8 .. 1.2): reported apart, not scored
  /// A velocity step: the fastest step (cm/s, or rad/s for a turn) the grip catches up with
  /// within its elastic lag, starting; and stopping, the fastest it stops within that lag
  double catchUpSpeed = 0.0;
  double stopSpeed = 0.0;
  /// A velocity step: where the object comes to rest after the stop behind the grip (negative:
  /// ahead), rad for a turn (TurnStepLag; the step speeds above are then unused), cm across the
  /// axis of an opposed grip for a carry (CarryStepLag; the step speeds above are then those of
  /// the axis alone)
  double stepRest = 0.0;
  /// Fingers that slide during the motion: the largest margin of the configurations it passes
  /// through (`margin` is the smallest); the scene is scored only when they agree
  double marginMax = 0.0;
  /// Fingers that slide over a round slice: the farthest one goes round it, rad. From 5 degrees
  /// on the scene is reported with the boundary (docs/physics.md, "A slide over a round slice")
  double slideTurn = 0.0;
  /// What the sides' pushes leave along the grip's axis at rest, dyn (signed along the first
  /// fingertip's push): the table's static friction holds it (tenth revision; 0 where the sides
  /// press equally)
  double restImbalance = 0.0;
};

/// What a scene did when run.
struct GraspOutcome {
  double endError = 0.0;       ///< cm, from the pose the grip's rigid motion carries it to
  double endAngleError = 0.0;  ///< rad, absolute
  double peakSpeed = 0.0;      ///< fastest object centre of mass, cm/s
  double contactSpeed = 0.0;   ///< fastest scripted contact centre, cm/s
  bool followed = false;       ///< endError <= 1 cm and endAngleError <= 5 degrees
  bool ejected = false;        ///< peakSpeed > 1.5 contactSpeed + 5 cm/s
};

/// Scenes are generated from this seed and their index in the sweep: the scenes of the sweep
/// before issue 42 (none, bang-bang).
GraspScene GenerateGraspScene(uint64_t seed, int index);
/// The same drawing from `classes`: each scene's class comes from a stream of its own, and a scene
/// of class none and bang-bang is the scene the two-argument form draws.
GraspScene GenerateGraspScene(uint64_t seed, int index, const GraspClasses& classes);

/// Where the scene's event happens against the motion: "" (no event), "before", "during",
/// "after".
const char* GraspEventPhase(const GraspScene& scene);

/// The normal force, dyn (a vector in the object frame), of one fingertip centred at `center`
/// (object frame) pressing the object's layer-0 slice, by the grip model: each contour point
/// within the particle radius of the slice presses with k min(d + r, d_max) along the face's
/// inward normal, d its depth; averaged over where the contour's samples (every `spacing`) fall.
/// On a polygon each body presses what it meets as it comes in along `inward`: the face `inward`
/// faces, or beyond that face's ends the face beside it or the corner between them (a corner
/// along the line from where the body stopped to the vertex); a body whose target has slid off
/// the ends of the face it met presses nothing. On a round slice a body stops where its circle
/// meets the slice's as it comes in along `inward`, and presses along the normal there by its
/// target's depth along it. Contour points inside a `hidden` disc are gone (a merged outline).
Vec2 FingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                    const Vec2& center, double radius, const Vec2& inward,
                    std::span<const HiddenDisc> hidden = {});
/// The same for a fingertip that came in to `restCenter` and then moved to `center` relative to
/// the object (the object lagging): on a round slice the bodies stay where they met it.
/// `pressing`, when given, receives how many of its bodies press (averaged over the sampling
/// phases, like the force). A fingertip whose target still advances along `inward` over the
/// object (a pusher coming in) slides each pressing body over the surface along the part of
/// `inward` that lies along it; with `slideFriction` mu > 0 the result adds that body's friction,
/// mu times its normal force, along its slide.
Vec2 FingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                    const Vec2& restCenter, const Vec2& center, double radius, const Vec2& inward,
                    double* pressing = nullptr, std::span<const HiddenDisc> hidden = {},
                    double slideFriction = 0.0);
/// The force, dyn (object frame), of one fingertip that came in to `restCenter` and then moved to
/// `center` relative to a round slice (the object lagging), with each body free to slide over
/// the slice (issue 42, nineteenth revision): a body pulled along the surface by more than
/// `friction` times its press slides towards its target's radial projection until the two are
/// equal, first as the squeeze pressed it in and then as the move goes on. Each pressing body
/// gives its normal force and its pull along the surface (its friction). On a polygon it is
/// FingertipForce (bodies on a flat face keep their normal as they slide).
Vec2 RoundFingertipForce(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                         const Vec2& restCenter, const Vec2& center, double radius,
                         const Vec2& inward, double friction,
                         std::span<const HiddenDisc> hidden = {});
/// The friction force, dyn (object frame), that one fingertip's bodies give an object they grip
/// when the fingertip came in to `restCenter` (object frame), then moved to `center` (which sets
/// each body's normal force, by its target's depth, as in FingertipForce) and on by `slide` along
/// the object's surface. Each body stays where it met the object and is a spring k towards its
/// target along the surface until its friction (`friction` times its normal force) slides it.
/// At rest a body whose target lies off its normal (on a round slice, or a face met obliquely)
/// has already slid until its pull is at that limit, and the move adds to that pull: a pinch of
/// a round slice starts with half its bodies' friction pulling against any move. With
/// `peakSlide`, the fingertip slid out to `peakSlide` first and then back to `slide`: a body that
/// slid on the way out springs back from its limit.
Vec2 GripSlideFriction(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                       const Vec2& restCenter, const Vec2& center, double radius,
                       const Vec2& inward, const Vec2& slide, double friction,
                       std::span<const HiddenDisc> hidden = {},
                       std::optional<Vec2> peakSlide = std::nullopt);
/// The torque, dyn cm about the object's origin (counter-clockwise positive), that one
/// fingertip's bodies give an object they grip when the fingertip (contour centre `center`,
/// object frame) has turned by `turn` radians about the origin relative to it. Each body stays
/// where it met the object (as in FingertipForce) and is a spring k towards its target: along
/// the surface it pulls until its friction, `friction` times its normal force, slides; across it
/// presses by its target's depth. A body that slides follows its target along its face. At
/// turn 0 it is the torque the grip holds at rest (the sideways pulls of bodies on a round
/// slice, whose targets lie off their normals). With `peak`, the fingertip turned out to `peak`
/// first and then back to `turn`: a body that slid on the way out springs back from its limit.
double GripTurnTorque(const ObjectSpec& object, const PhysicsParams& physics, double spacing,
                      const Vec2& center, double radius, const Vec2& inward, double turn,
                      double friction, std::span<const HiddenDisc> hidden = {},
                      std::optional<double> peak = std::nullopt);

/// Where an object is left by a velocity step of a turn (issue 42, seventeenth revision): the
/// grip starts turning at `rate` (rad/s) within a frame while the object rests, turns on until
/// the object slides with it, and stops within a frame. `loading(lag)` is the grip's torque
/// along the turn, dyn cm, with the object lagging by `lag` (rad) from rest; `unloading(peak,
/// lag)` the torque once the lag has come back to `lag` from `peak`. Table friction holds the
/// object with up to `staticTorque` at rest and `kineticTorque` while it turns; `inertia` is its
/// moment of inertia, g cm^2. Phases (docs/physics.md, "A turn step, followed through its
/// phases"):
/// - at rest until loading(L0) = staticTorque;
/// - it then catches up: the lag grows while the grip's excess over kinetic friction takes the
///   kinetic energy 1/2 I rate^2 it has relative to the grip, to the peak Lm;
/// - it slides on with the grip where unloading(Lm, Ls) = kineticTorque;
/// - at the stop it runs on from Ls at `rate` until kinetic friction less the grip's torque has
///   taken 1/2 I rate^2, and rests there.
/// Returns the lag it rests at (rad; negative: it leads the grip), or +infinity when the grip
/// slides round it (its torque never reaches static friction) or it never catches up within
/// `maxLag`.
struct TurnStepLags {
  double breakLoose = 0.0;  ///< L0, rad
  double peak = 0.0;        ///< Lm, rad
  double sliding = 0.0;     ///< Ls, rad
  double rest = 0.0;        ///< where it rests after the stop, rad
};
TurnStepLags TurnStepLag(const std::function<double(double)>& loading,
                         const std::function<double(double, double)>& unloading,
                         double staticTorque, double kineticTorque, double inertia, double rate,
                         double maxLag);

/// Where an object is left across an opposed grip's axis by a velocity step of a carry (issue
/// 42, eighteenth revision): the grip starts moving at `speed` (cm/s) within a frame, `across`
/// the sine of the angle between the motion and the axis, moves on until the object slides
/// with it, and stops within a frame. The axis is caught up at once (its springs are the
/// normals, stiff); across only the bodies' friction and the normals of a round slice hold.
/// `loose(l)` is the magnitude of the grip's force on the resting object with the grip moved on
/// l (cm, up to `looseReach`) along the motion; `loading(x)` the force across with the object
/// lagging x (cm) from rest; `unloading(peak, x)` the same once the lag has come back to x from
/// `peak`. Table friction holds the object with up to `staticForce` at rest and `kineticForce`
/// (dyn) along its velocity while it slides; `mass` in g. Phases (docs/physics.md, "A carry
/// step, followed through its phases"):
/// - at rest until loose(L0) = staticForce: it then lags L0 `across` across;
/// - it catches up across: the lag grows while the grip's force less the table's friction across
///   (its share w / |(v cos, w)| of kinetic friction, w the object's speed across) takes the
///   kinetic energy 1/2 M (v sin)^2 it has relative to the grip, to the peak Lm;
/// - it slides on with the grip where unloading(Lm, Ls) = kineticForce sin;
/// - at the stop the axis stops first, and it runs on across from Ls until the table's whole
///   kinetic friction less the grip's force has taken 1/2 M (v sin)^2, and rests there.
/// `rest` is +infinity when it never breaks loose within `looseReach` or never catches up within
/// `maxLag` of where it broke loose, -infinity when it runs on past the grip farther than twice
/// that.
struct CarryStepLags {
  double breakLoose = 0.0;  ///< L0, cm along the motion
  double peak = 0.0;        ///< Lm, cm across
  double sliding = 0.0;     ///< Ls, cm across
  double rest = 0.0;        ///< where it rests after the stop, cm across
};
CarryStepLags CarryStepLag(const std::function<double(double)>& loose, double looseReach,
                           const std::function<double(double)>& loading,
                           const std::function<double(double, double)>& unloading,
                           double staticForce, double kineticForce, double mass, double speed,
                           double across, double maxLag);

/// The rule, evaluated at the parameters' grip stiffness, depth limit, particle radius and the
/// contour spacing.
GraspPrediction PredictGrasp(const GraspScene& scene, const PhysicsParams& physics, double spacing);

/// The scene as a level file (the fingers' keyframes every 1/30 s), with the rule's figures in
/// comments and, when it can hold, the expectations that it follows the grip.
std::string GraspSceneToml(const GraspScene& scene, const GraspPrediction& prediction);

/// Runs a scene through the whole pipeline (synthetic camera to physics) at `substeps`, with the
/// default parameters changed by `sets` ("section.key=value", as `--set` takes them).
Result<GraspOutcome> RunGraspScene(const GraspScene& scene, int substeps,
                                   const std::vector<std::string>& sets = {});

/// What a sweep does.
struct GraspSweepOptions {
  uint64_t seed = 1;
  int scenes = 300;
  std::vector<int> substeps = {2, 4, 8};
  std::string failuresDir;  ///< writes each failing scene here as a level file; "" writes none
  int threads = 1;          ///< scenes run concurrently
  bool ruleOnly = false;    ///< classify the scenes without running them
  std::vector<std::string> sets;  ///< parameter overrides "section.key=value" for rule and runs
  /// The most of the scenes the rule may call "can hold" (0.5 .. 1): the sweep draws scenes in
  /// order from the seed and skips a can-hold draw once that many are kept, so that the scenes
  /// that cannot hold are enough to measure their rate (docs/physics.md, "The scenes"). 1 keeps
  /// every draw (scenes 0 .. count - 1, as for seeds 1 to 62 in docs/physics.md).
  double holdShare = 0.6;
  GraspClasses classes;  ///< which classes of scene are drawn (`--classes`)
  /// Called after each run with the runs done and in all (from the running threads, one at a
  /// time); empty calls nothing
  std::function<void(size_t done, size_t total)> progress;
};

/// One scene's rule and its outcome at each substep count of the sweep.
struct GraspSceneResult {
  GraspScene scene;
  GraspPrediction prediction;
  std::vector<GraspOutcome> outcomes;  ///< one per GraspSweepOptions::substeps
};

/// The rates at one substep count.
struct GraspRates {
  int substeps = 0;
  int holdScenes = 0;            ///< scored scenes the rule says can hold
  int holdFollowed = 0;          ///< of those, the ones that followed the grip
  int slipScenes = 0;            ///< scored scenes the rule says cannot hold
  int slipSlipped = 0;           ///< of those, the ones that did not follow
  int boundaryScenes = 0;        ///< not scored
  int ejections = 0;             ///< every scene
  double worstHoldError = 0.0;   ///< cm, largest end error of a hold scene
  double worstSpeedRatio = 0.0;  ///< largest peakSpeed / (1.5 contactSpeed + 5)
  double HoldRate() const { return holdScenes ? double(holdFollowed) / holdScenes : 1.0; }
  double SlipRate() const { return slipScenes ? double(slipSlipped) / slipScenes : 1.0; }
};

/// The rates of one class of scenes (a shape, a motion and profile, a topology).
struct GraspClassRates {
  std::string group;  ///< "shape", "motion", "topology"
  std::string name;   ///< "box", "carry step", "merged", ...
  int scenes = 0;
  std::vector<GraspRates> rates;  ///< one per substep count
};

struct GraspSweepReport {
  GraspSweepOptions options;
  int draws = 0;  ///< scenes drawn to keep options.scenes (the rest were can-hold draws skipped)
  std::vector<GraspSceneResult> scenes;
  std::vector<GraspRates> rates;            ///< one per substep count
  std::vector<GraspClassRates> classRates;  ///< per shape, motion and profile, topology
};

/// Generates, classifies and runs the scenes. Bad options are an Error naming them as `proxygrasp
/// bench grasp` does (--count, --substeps, --threads, --hold-share).
Result<GraspSweepReport> RunGraspSweep(const GraspSweepOptions& options);

/// The rates per substep count, then the failing and worst scenes.
std::string FormatGraspSweep(const GraspSweepReport& report);

/// The report as JSON: {"seed", "scenes", "rates": [{"substeps", "hold_rate", ...}], "failures"}.
std::string GraspSweepJson(const GraspSweepReport& report);

}  // namespace pg
