// The physics stage: one Box2D world per height layer. Objects are rigid bodies with one slice
// (a Box2D body) per layer they occupy; after every substep the slices are coupled back into one
// pose and velocity by mass splitting, and table friction, top friction and particle support are
// applied. Particles are stacks of circle bodies driven by kinematic control (Wilson, ITS 2009).
// See docs/physics.md.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/table.h"
#include "proxygrasp/core/timer.h"
#include "proxygrasp/physics/types.h"
#include "proxygrasp/proxies/types.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// The layered simulation. Answers the proxies' SceneQuery from its state after the last frame.
class LayeredWorld : public SceneQuery {
 public:
  LayeredWorld();
  ~LayeredWorld() override;
  LayeredWorld(LayeredWorld&&) noexcept;
  LayeredWorld& operator=(LayeredWorld&&) noexcept;

  /// Validates the parameters and objects and builds the K layer worlds, walls and slices,
  /// replacing anything built before. Bad specs give an Error at spec.loc naming object and field;
  /// on error the world is left empty.
  MaybeError Build(const PhysicsParams& physics, const TableParams& table,
                   std::span<const ObjectSpec> objects);

  /// Changes the parameters of a built world between frames, keeping every object and particle
  /// where it is: frame_rate, substeps, iterations, threads, gravity, particle_mass (applied to
  /// the existing bodies), particle_down_force, particle_friction (for objects that use it),
  /// top_kinetic_factor and the held thresholds take effect from the next StepFrame. A change of
  /// what only Build can apply (FixedKeysChanged) or an invalid value is an Error naming the key,
  /// and nothing changes.
  MaybeError SetParams(const PhysicsParams& physics);
  /// The keys of the parameters that differ between `physics` and those in use and that
  /// SetParams cannot change: "layer_height", "layers" (the layer worlds and slices),
  /// "particle_radius", "stack_size" and "capsule" (the particle bodies).
  std::vector<std::string> FixedKeysChanged(const PhysicsParams& physics) const;

  /// One frame: ApplyPlan(plan), then StepFrame().
  void Step(const ParticlePlan& plan);

  /// The first half of Step, for tests that look between the halves. Applies one frame's
  /// particle plan: creates stacks (at start, base layer from baseHeight),
  /// deletes stacks, sets the targets the next StepFrame drives particles to. Entries naming
  /// unknown particles are skipped and counted (PlanErrors).
  void ApplyPlan(const ParticlePlan& plan);

  /// The second half of Step. Advances one camera frame: substeps of dt = 1 / (frameRate *
  /// substeps), each with kinematic control, the layer worlds' steps (in parallel when threads >
  /// 1), coupling, top and table friction and particle support; then the frame's diagnostics.
  void StepFrame();

  /// An external force, dyn, at a table point, cm, acting through the object's slice in `layer`
  /// for every substep of the next frame. Layers the object does not occupy are clamped to its
  /// top slice; an unknown object or a non-finite value is counted (PlanErrors) and dropped.
  void ApplyForce(ObjectId object, const Vec2& force, const Vec2& worldPoint, int layer);

  // SceneQuery, answered from the state after the last frame.
  double TopHeightAt(const Vec2& p) const override;
  double FootprintDepth(const Vec2& p, double* topHeight) const override;
  Vec2 NearestOutside(const Vec2& p) const override;
  ObjectId ObjectAt(const Vec2& p) const override;

  /// Where every particle is after the last frame, in creation order.
  std::vector<ParticleFeedback> Feedback() const;
  /// Number of objects.
  int ObjectCount() const;
  /// The state of object i after the last frame.
  ObjectState Object(ObjectId i) const;
  /// The forces object i received from particles during the last frame.
  ObjectForces Forces(ObjectId i) const;
  /// The slices of object i, lowest layer first, in its local frame.
  std::vector<SliceOutline> Slices(ObjectId i) const;
  /// Every particle stack, in creation order.
  std::vector<ParticleState> Particles() const;
  /// Number of particle stacks.
  int ParticleCount() const;
  /// Particle stacks whose bodies took part in the Box2D worlds in the last frame: those whose
  /// path came within reach of an object, or that rest on one. The others were put on their
  /// targets directly (docs/physics.md, Particles far from objects).
  int ActiveParticleCount() const;
  /// Particle bodies that Box2D's solver stepped in the last substep: those of active stacks that
  /// pressed on an object, came near one they had no contact with yet, or moved more than their
  /// radius. The others touched nothing; they were left asleep in their worlds and put on their
  /// aims directly (docs/physics.md, Particles far from objects).
  int SolvedBodyCount() const;
  /// Particle bodies in the layers' Box2D worlds (their broad-phase) after the last substep: those
  /// of active stacks within reach of an object's footprint in their layer. The others left their
  /// worlds until an object comes within reach (docs/physics.md, Particles far from objects).
  int InWorldBodyCount() const;
  /// Box2D bodies in all layers: object slices plus particle bodies (walls not counted).
  int BodyCount() const;
  /// Frames stepped since Build.
  int64_t Frame() const;
  /// Substeps the last frame took: `substeps`, or more when a light object was pressed by many
  /// bodies (docs/physics.md, "Substeps that keep a grip stable").
  int FrameSubsteps() const;
  /// Inputs that were skipped: plan entries naming unknown or duplicate particles or holding
  /// non-finite positions, and pushes on unknown objects or with non-finite values.
  int PlanErrors() const;
  /// The parameters in use.
  const PhysicsParams& params() const;

  /// Hash (FNV-1a) of the exact simulation state: object poses and velocities, every particle
  /// body's position and velocity, bit for bit. Equal hashes mean identical runs.
  uint64_t StateHash() const;

  /// Test hook: true when every object's slices share one pose bit for bit right now.
  bool SlicesAgree() const;

  /// Times each frame's Box2D stepping (the layers' b2World::Step calls, contact listeners
  /// included) with this clock; nullopt, the default, times nothing. With the thread CPU clock and
  /// physics.threads > 1, only the calling thread's share is counted. For `proxygrasp bench`.
  void SetBox2DClock(std::optional<TimerClock> clock);
  /// Milliseconds the last frame spent in b2World::Step, by the clock set (0 when none is).
  double Box2DMs() const;

  /// Test hook: called after every substep (coupling included) with the substep index.
  void SetSubstepObserver(std::function<void(int)> observer);
  /// Test hook: with true, free bodies that no object can reach stay asleep in their worlds
  /// instead of leaving them (the behaviour before they left, for comparison); default false.
  void KeepFreeBodiesInWorlds(bool keep);

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace pg
