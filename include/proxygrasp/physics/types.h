// What the physics stage is built from: table and physics parameters and object specs.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/table.h"

#include <limits>
#include <string>
#include <vector>

namespace pg {

/// Parameters of the layered simulation. Section [physics] of a level.
struct PhysicsParams {
  double frameRate = 60.0;          ///< camera frames per second, Hz
  int substeps = 4;                 ///< physics substeps per frame (the least)
  int maxSubsteps = 4;              ///< most substeps a frame takes to keep a light object that
                                    ///< many opposing bodies press stable (at most `substeps`: no
                                    ///< more)
  int velocityIterations = 8;       ///< Box2D velocity iterations per substep
  int positionIterations = 3;       ///< Box2D position iterations per substep
  int threads = 1;                  ///< threads stepping layer worlds concurrently
  double layerHeight = 1.0;         ///< height h of one layer, cm
  int layers = 8;                   ///< layer count K, at most 16
  double gravity = 981.0;           ///< cm/s^2
  double particleRadius = 0.25;     ///< radius of one particle body, cm
  double gripStiffness = 57600;     ///< grip spring: normal force on an object per cm a particle
                                    ///< body's target lies inside it, dyn/cm
  double gripDamping = 0.0;         ///< grip dashpot: normal force per cm/s the target moves into
                                    ///< the object relative to its surface, dyn s/cm
  double gripReleaseSpeed = 5.0;    ///< fastest a particle body pushes a face away beyond its
                                    ///< target's advance, cm/s: a finger pad springs back (u^2 / s
                                    ///< where the face slides across the finger at s > u; 0: no
                                    ///< limit)
  double gripMaxDepth = 1.0;        ///< depth beyond which pressing deeper adds no force, cm
  int stackSize = 1;                ///< S, bodies per particle stack in consecutive layers
  bool capsule = false;             ///< fill every layer from the base to the top instead of S
  double particleDownForce = 2000;  ///< constant downward force per particle, dyn
  double restMargin = 0.5;          ///< measured heights: a stack rests on the surface below it
                                    ///< while its measured underside is at most this above it,
                                    ///< and hovers higher, cm
  double particleFriction = 0.8;    ///< default particle-to-object friction, non-dimensional
  double topKineticFactor = 0.75;   ///< top friction: kinetic / static coefficient, non-dimensional
  double heldOpposingDot = -0.5;    ///< held: contact normals whose dot product is below this
                                    ///< oppose, non-dimensional
  double heldFrictionMargin = 0.99;  ///< held: a contact whose friction is below this fraction of
                                     ///< mu * normal is not sliding, non-dimensional
};

/// Shapes of virtual objects. All are prisms or solids of revolution about the vertical axis.
enum class ObjectShape { kBox, kCylinder, kSphere, kFrustum, kConvexPrism, kConcavePrism };
inline constexpr const char* kObjectShapeNames[] = {"box",     "cylinder",     "sphere",
                                                    "frustum", "convex_prism", "concave_prism"};

/// A virtual object as a level describes it. Mass and inertia are those of the full 3D shape.
struct ObjectSpec {
  std::string name;
  ObjectShape shape = ObjectShape::kBox;
  double sizeX = 4.0;              ///< box width along local x, cm
  double sizeY = 4.0;              ///< box depth along local y, cm
  double radius = 2.0;             ///< cylinder, sphere, frustum bottom radius, cm
  double topRadius = 0.0;          ///< frustum top radius (0 makes a cone), cm
  double patchRadius = 0.05;       ///< sphere: radius of its flat contact patch on the table, cm
                                   ///< (table friction resists its spin over the patch)
  double height = 2.0;             ///< box, cylinder, frustum and prism height, cm (sphere: 2r)
  std::vector<Vec2> points;        ///< prism outline in the local frame, cm
  double mass = 0.0;               ///< g; when > 0 it overrides density
  double density = 0.5;            ///< g/cm^3
  double particleFriction = -1.0;  ///< against particles; < 0 uses PhysicsParams::particleFriction
  double tableStatic = 0.4;        ///< static friction against the table, non-dimensional
  double tableKinetic = 0.3;       ///< kinetic friction against the table, non-dimensional
  double objectFriction = 0.4;     ///< against other objects and walls, non-dimensional
  double restitution = 0.1;        ///< non-dimensional
  Pose2 pose;                      ///< starting pose
  Vec2 velocity = Vec2::Zero();    ///< starting velocity, cm/s
  double angularVelocity = 0.0;    ///< starting angular velocity, rad/s
  SourceLoc loc;                   ///< where the level defines it, for messages
};

/// Forces an object received from particles in one layer, averaged over the last frame.
struct LayerForces {
  Vec2 normal = Vec2::Zero();      ///< vector sum of the normal forces, dyn
  Vec2 friction = Vec2::Zero();    ///< vector sum of the friction forces, dyn
  double normalMagnitude = 0.0;    ///< sum of the normal force magnitudes, dyn
  double frictionMagnitude = 0.0;  ///< sum of the friction force magnitudes, dyn
  int contacts = 0;                ///< particle contact points in the frame's last substep
};

/// Forces an object received from particles over the last frame, by layer and in total.
struct ObjectForces {
  std::vector<LayerForces> layers;  ///< one entry per layer (K), from the side contacts
  LayerForces total;                ///< the sum over layers
  Vec2 topFriction = Vec2::Zero();  ///< friction from particles resting on its top, dyn
  double topNormal = 0.0;           ///< downward force of particles resting on its top, dyn
};

/// The state of one object after the last frame.
struct ObjectState {
  std::string name;
  Pose2 pose;                        ///< pose of the object's local frame, cm and rad
  Vec2 velocity = Vec2::Zero();      ///< velocity of the centre of mass, cm/s
  double angularVelocity = 0.0;      ///< rad/s, counter-clockwise
  Vec2 centerOfMass = Vec2::Zero();  ///< in the table frame, cm
  bool held = false;                 ///< held by opposing particle contacts without slipping
  double topHeight = 0.0;            ///< height of its top, cm
  double mass = 0.0;                 ///< of the full 3D shape, g
  double inertia = 0.0;              ///< about the vertical axis through the centre, g cm^2
  int layerCount = 0;                ///< layers 0 .. layerCount-1 hold its slices
  int particlesOnTop = 0;            ///< particles resting on its top
};

/// The cross-section of an object in one layer, in the object's local frame, for drawing.
struct SliceOutline {
  int layer = 0;
  double z = 0.0;               ///< height of the cross-section, cm
  Contour outline;              ///< counter-clockwise (circles as a 32-gon), cm
  std::vector<Contour> pieces;  ///< the convex pieces Box2D simulates (circles: the outline)
};

/// The state of one particle stack after the last frame.
struct ParticleState {
  ParticleId id = kNoId;
  ContactId contact = kNoId;
  Vec2 pos = Vec2::Zero();         ///< base position (its base body's while it has bodies), cm
  Vec2 target = Vec2::Zero();      ///< where kinematic control drives it this frame, cm
  double baseHeight = 0.0;         ///< height of the surface it rests on, cm
  int baseLayer = 0;               ///< layer of its lowest body
  int layerCount = 0;              ///< layers the stack fills, consecutive from the base
  ObjectId restingOn = kNoObject;  ///< the object it rests on; kNoObject: the table (or
                                   ///< hovering, when baseHeight is above every top under it)
  /// measured placement: the finger's underside measured at it, cm (NaN when not measured)
  double measured = std::numeric_limits<double>::quiet_NaN();
  bool aloft = false;  ///< measured above every layer: it has no bodies and touches nothing
  /// within reach of an object in the last frame: it has one Box2D body per layer it fills.
  /// Otherwise it has none and is put on its target directly (docs/physics.md)
  bool active = false;
};

void Describe(PhysicsParams& p, ParamVisitor& v);

}  // namespace pg
