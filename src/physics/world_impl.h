// Private state of LayeredWorld, shared by layered_world.cpp (build, frame loop, queries),
// coupling.cpp (mass splitting, averaging, table and top friction) and particles.cpp (stacks,
// kinematic control, support).
#pragma once

#include "thread_pool.h"

#include "proxygrasp/physics/layered_world.h"
#include "proxygrasp/physics/shapes.h"

#include <box2d/b2_distance.h>
#include <box2d/box2d.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pg {

/// What a Box2D fixture belongs to; stored in the fixture's user data with an index.
enum class BodyKind : uintptr_t { kWall = 0, kObject = 1, kParticle = 2 };

inline uintptr_t MakeTag(BodyKind kind, int index) {
  return (static_cast<uintptr_t>(index) << 2) | static_cast<uintptr_t>(kind);
}
inline BodyKind TagKind(uintptr_t tag) {
  return static_cast<BodyKind>(tag & 3u);
}
inline int TagIndex(uintptr_t tag) {
  return static_cast<int>(tag >> 2);
}

// collision categories: particles and walls touch objects only
inline constexpr uint16 kObjectBit = 0x1;
inline constexpr uint16 kParticleBit = 0x2;
inline constexpr uint16 kWallBit = 0x4;
/// how much farther than its own motion at the frame's start an object may get in one frame
/// (pushes and collisions within the frame), when deciding which particles it can touch, cm:
/// 1 cm a frame is 60 cm/s gained within one frame at 60 Hz
inline constexpr double kActivityMargin = 1.0;
/// how much nearer than the distance that brings a free body back into its world it must be
/// to stay in it, cm (hysteresis, so that a body at that distance does not go in and out)
inline constexpr double kOutOfWorldHysteresis = 0.1;
/// Gauss-Seidel passes over an object's pushes in LimitRelease
inline constexpr int kReleaseIterations = 4;

inline b2Vec2 ToB2(const Vec2& v) {
  return b2Vec2(static_cast<float>(v.x()), static_cast<float>(v.y()));
}
inline Vec2 FromB2(const b2Vec2& v) {
  return Vec2(v.x, v.y);
}

/// One particle-object contact's impulses in one Box2D solve.
struct ContactRecord {
  ObjectId object = kNoObject;
  Vec2 normalIn = Vec2::Zero();   ///< unit normal pointing into the object
  Vec2 tangentIn = Vec2::Zero();  ///< unit tangent matching Box2D's tangent impulse sign
  double normalImpulse = 0.0;     ///< summed over manifold points, dyn s
  double tangentImpulse = 0.0;    ///< summed over manifold points, dyn s
  double friction = 0.0;          ///< mu used by the solver
  int points = 0;
  Vec2 point = Vec2::Zero();   ///< where it acts (the mean of its manifold points), cm
  Vec2 padVel = Vec2::Zero();  ///< the velocity of the finger's surface at the body, cm/s
};

/// Sets contact friction from object properties and records particle contact impulses. Runs on
/// the thread stepping its layer; writes only its own layer's records.
class LayerListener final : public b2ContactListener {
 public:
  const std::vector<double>* particleFriction = nullptr;  ///< per object
  const std::vector<double>* objectFriction = nullptr;    ///< per object
  std::vector<ContactRecord>* records = nullptr;

  void PreSolve(b2Contact* contact, const b2Manifold* oldManifold) override;
  void PostSolve(b2Contact* contact, const b2ContactImpulse* impulse) override;
};

/// One height layer: its Box2D world and what it recorded in the last substep.
struct Layer {
  std::unique_ptr<b2World> world;
  LayerListener listener;
  b2Body* walls = nullptr;
  std::vector<ContactRecord> records;
};

/// An object's body in one layer.
struct Slice {
  int layer = 0;
  double z = 0.0;  ///< height of the cross-section, cm
  CrossSection section;
  b2Body* body = nullptr;
  b2FrictionJoint* table = nullptr;  ///< table friction, solved with the layer's contacts
  bool touching = false;             ///< had a touching contact in the last substep
};

/// An external push waiting for the next frame.
struct Push {
  Vec2 force = Vec2::Zero();
  Vec2 point = Vec2::Zero();
  int layer = 0;
};

/// One rigid object: its slices and its coupled state (double precision, authoritative).
struct ObjectData {
  ObjectSpec spec;
  MassProps props;
  double top = 0.0;                        ///< top height, cm
  double rEff = 0.0;                       ///< table friction lever arm, cm
  std::vector<FrictionPoint> tablePoints;  ///< table friction spread over the base
  double boundRadius = 0.0;                ///< footprint radius about the local origin, cm
  CrossSection footprint;
  std::vector<Slice> slices;  ///< layers 0 .. slices.size()-1
  int splitCount = -1;        ///< n in the slices' current mass data M/n

  // coupled state: centre of mass, angle and their rates
  Vec2 center = Vec2::Zero();
  double angle = 0.0;
  Vec2 vel = Vec2::Zero();
  double omega = 0.0;
  // the same state as the slices hold it (float), the base of the next coupling
  Vec2 centerF = Vec2::Zero();
  double angleF = 0.0;
  Vec2 velF = Vec2::Zero();
  double omegaF = 0.0;

  // this frame's diagnostics (impulses until the frame's end, then forces)
  std::vector<LayerForces> forces;
  Vec2 topFriction = Vec2::Zero();
  double topNormal = 0.0;
  bool held = false;
  int particlesOnTop = 0;
  std::vector<Push> pushes;
  bool sliding = false;  ///< slid or turned on the table in the last substep (kinetic friction)
  /// the table friction's force and torque about the centre of mass in the last substep, when it
  /// slid (dyn, dyn cm): the split between resisting the slide and the turn that the layers'
  /// friction joints take up in the next substep
  Vec2 slideForce = Vec2::Zero();
  double slideTorque = 0.0;

  // the pose of the local frame, cached at every write-back
  Pose2 pose;
  double cosA = 1.0, sinA = 0.0;

  /// The pose of the local frame computed from the centre of mass and angle.
  Pose2 Pose() const;
  /// Caches pose, cosA and sinA from the coupled state.
  void CachePose();
  /// A table point in the local frame (cached pose).
  Vec2 ToLocal(const Vec2& p) const {
    const Vec2 d = p - pose.pos;
    return Vec2(cosA * d.x() + sinA * d.y(), -sinA * d.x() + cosA * d.y());
  }
  /// A local direction (or arm) turned into the table frame (cached pose).
  Vec2 ToTableDirection(const Vec2& v) const {
    return Vec2(cosA * v.x() - sinA * v.y(), sinA * v.x() + cosA * v.y());
  }
  /// The fastest any point of the footprint moves, |v| + |omega| boundRadius, cm/s.
  double FastestPointSpeed() const { return vel.norm() + std::abs(omega) * boundRadius; }
  /// Quick test that a table point may lie over the footprint (cached pose).
  bool MayHold(const Vec2& p) const {
    return (p - pose.pos).squaredNorm() <= boundRadius * boundRadius;
  }
};

/// One particle stack.
struct ParticleData {
  ParticleId id = kNoId;
  ContactId contact = kNoId;
  /// the contact it was created for: its finger. A contact that merged holds the particles of
  /// several fingers, each moving its own way; the turn and surface velocity are fitted per finger
  ContactId finger = kNoId;
  Vec2 target = Vec2::Zero();      ///< reached by the frame's end
  Vec2 prevTarget = Vec2::Zero();  ///< the target of the previous frame (or the start)
  double baseHeight = 0.0;
  int baseLayer = 0;
  ObjectId restingOn = kNoObject;
  /// measured placement: the finger's underside at the particle, as the proxies stage measured
  /// and smoothed it, cm (NaN: not measured; the stack then keeps its layer while held there and
  /// falls otherwise). See PlaceMeasured
  double measured = std::numeric_limits<double>::quiet_NaN();
  /// measured above every layer: it touches nothing and has no bodies
  bool aloft = false;
  /// created this frame: it moves from where it was placed, not with its finger (UpdateSpin)
  bool born = false;
  /// within reach of an object this frame: it has bodies in its Box2D worlds. Otherwise it has
  /// none, and pos and vel are put on its goals directly (UpdateActivity)
  bool active = false;
  Vec2 pos = Vec2::Zero();  ///< where the stack is while it has no bodies, cm
  Vec2 vel = Vec2::Zero();  ///< its velocity then, cm/s
  /// the turn rate of its contact this frame, rad/s: its bodies carry it as angular velocity so
  /// that their surfaces move with the finger's (UpdateSpin)
  double spin = 0.0;
  /// the velocity of its goal this frame, cm/s (its bodies' user data point here while they
  /// are awake, so that the contact records know it)
  Vec2 goalVel = Vec2::Zero();
  /// the velocity of its contact's surface where it is, cm/s: the contact's rigid motion this
  /// frame (its mean velocity and spin), without the slide of its particles along the contour
  Vec2 padVel = Vec2::Zero();
  std::vector<b2Body*> bodies;  ///< layers baseLayer, baseLayer + 1, ...
  /// Per body: a body that touches nothing and moves less than its radius in a substep is left
  /// asleep in its world, out of Box2D's islands, and put on its aim after the step
  /// (ApplyKinematicControl, PlaceFreeBodies). Box2D zeroes a sleeping body's velocity, so an
  /// asleep body's velocity is kept here (BodyVelocity).
  std::vector<Vec2> freeVel;
  std::vector<Vec2> freeAim;
  std::vector<char> freeNow;  ///< left asleep this substep: PlaceFreeBodies puts it on freeAim
};

struct LayeredWorld::Impl {
  PhysicsParams params;
  TableParams table;
  double dt = 0.0;        ///< substep, s
  int frameSubsteps = 1;  ///< substeps of the current frame (StableSubsteps), dt's
  std::vector<std::unique_ptr<Layer>> layers;
  std::vector<ObjectData> objects;
  std::vector<double> particleFriction;  ///< per object, for the listeners
  std::vector<double> objectFriction;    ///< per object, for the listeners
  std::vector<ParticleData> particles;
  /// per object: its origin and squared reach this frame (UpdateActivity's scratch)
  std::vector<std::pair<Vec2, double>> reaches;
  std::unordered_map<ParticleId, int> particleIndex;
  std::unique_ptr<ThreadPool> pool;
  int64_t frame = 0;
  int planErrors = 0;
  /// per object, the particles resting on its top in this substep (set by PrepareTableFriction)
  std::vector<std::vector<int>> onTop;
  std::function<void(int)> observer;
  std::optional<TimerClock> box2dClock;  ///< times StepLayers when set
  bool keepFreeBodies = false;           ///< KeepFreeBodiesInWorlds
  double box2dMs = 0.0;                  ///< time in StepLayers during the last frame, ms

  int LayerCount() const { return static_cast<int>(layers.size()); }
  /// Layer whose bodies rest on a surface at height z.
  int LayerOf(double z) const;

  // particles.cpp
  /// Creates the stack's bodies from its base layer at pos with velocity vel.
  void CreateBodies(ParticleData& p, const Vec2& pos, const Vec2& vel);
  void DestroyBodies(ParticleData& p);
  /// Layer a particle rests in on object o's surface at height h.
  int SupportLayer(int o, double h) const;
  /// The highest surface under p no higher than maxLayer: its layer, height and object (kNoObject:
  /// the table).
  void FindSupport(const Vec2& p, int maxLayer, int* layer, double* height, ObjectId* object) const;
  /// Base layer of a new particle placed at p resting at height baseHeight.
  int CreationLayer(const Vec2& p, double baseHeight) const;
  /// F = m((x* - x)/dt - v)/dt on every particle body, x* interpolated at fraction alpha.
  void ApplyKinematicControl(double alpha);
  /// Puts the bodies left asleep this substep on their aims (ApplyKinematicControl).
  void PlaceFreeBodies();
  /// A particle body's velocity, cm/s: Box2D's, or the kept one while the body is asleep.
  static Vec2 BodyVelocity(const ParticleData& p, int j);
  /// Where a stack's base is, and its velocity: its base body's, or pos and vel without bodies.
  static Vec2 BasePosition(const ParticleData& p);
  static Vec2 BaseVelocity(const ParticleData& p);
  /// Layers a stack fills from its base layer (its bodies while it has them).
  int StackLayers(const ParticleData& p) const;
  /// Adds an impulse to a particle body's velocity, asleep or not (g cm/s).
  void ApplyParticleImpulse(ParticleData& p, int j, const Vec2& impulse) const;
  /// Lets particles whose support went away fall to the highest surface below them; particles
  /// with a measured height rest or hover where it says (PlaceMeasured).
  void UpdateSupport();
  /// A stack with a measured height m at base position pos (docs/physics.md, "Measured
  /// heights"): on the object it rests on while still over it and m is at most rest_margin above
  /// its top; otherwise on the highest surface under its base when m is at most rest_margin
  /// above it, or hovering at m in the layer holding m (above that surface's slices), aloft above
  /// every layer. Moves its bodies when its layer changes.
  void PlaceMeasured(ParticleData& p, const Vec2& pos);
  /// At a frame's start: a particle is active while its path this frame passes within reach of
  /// an object (or it rests on one). A stack gets its bodies when it becomes active and loses
  /// them when it stops being so.
  void UpdateActivity();
  /// Per object, how many of the particle bodies that pressed its sides in the last frame's last
  /// substep pressed against each other: their count times the share of their normal force that
  /// cancels (read before the frame's forces are cleared).
  std::vector<double> PressingBodies() const;
  /// The substeps this frame needs: params.substeps, or more (up to max_substeps) where the
  /// opposing bodies that will press an object (as `pressed`, or those of active stacks whose
  /// targets lie within their radius of its footprint, whichever are more) weigh more than
  /// kStableMassRatio times it. After UpdateActivity.
  int StableSubsteps(const std::vector<double>& pressed) const;
  /// Makes `n` the substep count: dt, and the particle bodies' mass k dt^2 + c dt.
  void UseSubsteps(int n);

  // coupling.cpp
  /// Gives each object's slices mass M/n, inertia I/n, n = layers predicted to have contacts.
  void PrepareMassSplitting();
  /// Lists the particles resting on each object's top (onTop) and sets every slice's table
  /// friction joint to the object's Coulomb limit for this substep.
  void PrepareTableFriction();
  /// Normal force of object oi on the table: its weight plus the down force of the particles on
  /// its top, dyn.
  double TableNormal(int oi) const;
  /// Mass data of one particle body.
  /// Sets each particle's spin from its contact's rigid turn this frame.
  void UpdateSpin();
  /// Shortens a body's step from x towards *aim so that it stops where it first meets an object;
  /// returns the object fixture it meets (nullptr: none on its path).
  b2Fixture* StopAtSurface(b2Body* body, const Vec2& x, Vec2* aim,
                           const std::vector<b2Fixture*>& unpaired) const;
  /// The object fixtures in a layer near a body's path from x to aim that it has no contact
  /// with (yet): see ApplyKinematicControl.
  void FindUnpaired(int layer, const b2Body* body, const Vec2& x, const Vec2& aim,
                    std::vector<b2Fixture*>* unpaired) const;
  /// True when an object with a slice in a layer may come within reach of a body's path from x
  /// to aim this substep: its footprint (which holds every slice), moved by as much as the object
  /// travels in a substep, within the body's radius, Box2D's fattening and `extra` cm.
  bool NearSlices(int layer, const Vec2& x, const Vec2& aim, double extra) const;
  /// A body that reaches an object's surface this substep at stop (Box2D has no contact for it
  /// until the next one) presses with the grip's force law directly: the force goes to the
  /// object's slice in that layer and into the layer's contact records, with the goal's and the
  /// finger surface's velocity of particle p.
  void PressOnArrival(int layer, b2Fixture* surface, const Vec2& stop, const Vec2& goal,
                      const ParticleData& p);
  /// Mass of one particle body, k dt^2 + c dt (docs/physics.md, "Grip"), g.
  double ParticleMass() const;
  /// The grip's force law along a contact normal, dyn: k min(depth, d_max) + c goalSpeed, where
  /// depth (cm) is how far the goal lies inside the surface and goalSpeed (cm/s) how fast it
  /// moves inwards (docs/physics.md, "Grip").
  double GripPush(double depth, double goalSpeed) const;
  b2MassData ParticleMassData() const;
  /// Applies the queued external pushes for one substep.
  void ApplyPushes();
  /// Steps every layer world (concurrently when threads > 1).
  void StepLayers();
  /// Couples each object's slices into one state, applies top and table friction, writes back.
  void Couple();
  /// per object, the contact records of the particles pressing it in this substep (Couple)
  std::vector<std::vector<ContactRecord*>> releasePushes;
  /// Takes back the part of the particles' pushes on object `oi` in this substep that made one
  /// of its faces recede from a pressing body faster than grip_release_speed beyond its goal's
  /// advance into the face (a goal that withdraws counts as still), from the
  /// object's velocity and turn rate at the substep's end (`vel`, `omega`: updated).
  void LimitRelease(int oi, const std::vector<ContactRecord*>& pushes, Vec2* vel,
                    double* omega) const;
  /// The friction impulses of one object in one substep, solved together.
  struct FrictionSolve {
    Vec2 vel = Vec2::Zero();       ///< object velocity after friction, cm/s
    double omega = 0.0;            ///< object angular velocity after friction, rad/s
    std::vector<Vec2> top;         ///< impulse each resting particle gives the object, g cm/s
    std::vector<Vec2> table;       ///< impulse of each table friction point, g cm/s
    std::vector<bool> topSliding;  ///< the particle's impulse reached its limit
    bool tableSliding = false;     ///< a table friction point reached its limit: the object moves
    bool anyTopSliding = false;
  };
  /// The table friction the layer solves already applied to one object: impulse and angular
  /// impulse, summed over its slices.
  struct TableImpulse {
    Vec2 linear = Vec2::Zero();
    double angular = 0.0;
  };
  /// Projected Gauss-Seidel over the top friction of the particles resting on object oi and its
  /// table friction points, starting from velocity vel0, omega0 (which already contain the table
  /// impulse the layers applied, taken out first), and the table's normal force (dyn). With
  /// kinetic, the top contacts that slid in staticPass get kinetic limits, and the table's points
  /// all slide when the object moved: at mu_k, or at mu_s in the substep in which it breaks loose
  /// (breakingLoose; Couple() says why).
  FrictionSolve SolveFriction(int oi, const std::vector<int>& onTop, const Vec2& center,
                              const Vec2& vel0, double omega0, const TableImpulse& applied,
                              double normal, bool kinetic,
                              const FrictionSolve* staticPass = nullptr,
                              bool breakingLoose = false) const;
  /// Adds the layers' contact records to the objects' frame diagnostics.
  void CollectRecords(bool lastSubstep);
  /// Writes the object's coupled state to all its slices.
  void WriteBack(ObjectData& o);
};

}  // namespace pg
