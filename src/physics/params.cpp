#include "proxygrasp/physics/types.h"

namespace pg {

void Describe(PhysicsParams& p, ParamVisitor& v) {
  v.Real("frame_rate", p.frameRate, 1, 1000, "Hz", {"camera frames per second", Apply::kRestart});
  v.Integer("substeps", p.substeps, 1, 64, "1",
            "physics substeps per frame: the least; a frame takes more when a light object is "
            "pressed by many bodies (max_substeps)");
  v.Integer("max_substeps", p.maxSubsteps, 1, 64, "1",
            "most substeps a frame takes so that the opposing bodies pressing an object weigh at "
            "most twice the object (stability; a value at or below substeps adds none)");
  v.Integer("velocity_iterations", p.velocityIterations, 1, 100, "1",
            "Box2D velocity iterations per substep");
  v.Integer("position_iterations", p.positionIterations, 1, 100, "1",
            "Box2D position iterations per substep");
  v.Integer("threads", p.threads, 1, 16, "1", "threads stepping the layer worlds concurrently");
  v.Real("layer_height", p.layerHeight, 0.05, 100, "cm",
         {"height h of one layer", Apply::kRestart});
  v.Integer("layers", p.layers, 1, 16, "1", {"layer count K", Apply::kRestart});
  v.Real("gravity", p.gravity, 0, 10000, "cm/s^2", "gravity for table friction");
  v.Real("particle_radius", p.particleRadius, 0.01, 5, "cm",
         {"radius of one particle body", Apply::kRestart});
  v.Real("grip_stiffness", p.gripStiffness, 1, 1e8, "dyn/cm",
         "normal force of a particle body per cm its target lies inside an object");
  v.Real("grip_damping", p.gripDamping, 0, 1e6, "dyn s/cm",
         "normal force of a particle body per cm/s its target moves into an object");
  v.Real("grip_release_speed", p.gripReleaseSpeed, 0, 1e6, "cm/s",
         "fastest a particle body pushes an object's face away beyond its target's own advance, "
         "as a finger pad springs back; u^2/s where the face slides across the finger at s > u "
         "(0 = no limit)");
  v.Real("grip_max_depth", p.gripMaxDepth, 0.001, 100, "cm",
         "target depth inside an object beyond which a particle presses no harder");
  v.Integer("stack_size", p.stackSize, 1, 16, "1",
            {"S, bodies per particle stack", Apply::kRestart});
  v.Boolean("capsule", p.capsule,
            {"fill every layer from a particle's base to the top", Apply::kRestart});
  v.Real("particle_down_force", p.particleDownForce, 0, 1e7, "dyn",
         "constant downward force per particle");
  v.Real("rest_margin", p.restMargin, 0, 10, "cm",
         "measured heights: a particle rests on the surface below it while its measured "
         "underside is at most this above it, and hovers when higher");
  v.Real("particle_friction", p.particleFriction, 0, 10, "1",
         "default friction between particles and objects");
  v.Real("top_kinetic_factor", p.topKineticFactor, 0, 1, "1",
         "top friction: kinetic coefficient as a fraction of the static one");
  v.Real("held_opposing_dot", p.heldOpposingDot, -1, 0, "1",
         "held: contact normals with a dot product below this oppose");
  v.Real("held_friction_margin", p.heldFrictionMargin, 0, 1, "1",
         "held: friction below this fraction of its limit is not slipping");
}

}  // namespace pg
