// What the physics stage is built from: table and physics parameters and object specs.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/table.h"

#include <string>
#include <vector>

namespace pg {

/// Parameters of the layered simulation. Section [physics] of a level.
struct PhysicsParams {
  double frameRate = 60.0;          ///< camera frames per second, Hz
  int substeps = 4;                 ///< physics substeps per frame
  int velocityIterations = 8;       ///< Box2D velocity iterations per substep
  int positionIterations = 3;       ///< Box2D position iterations per substep
  int threads = 1;                  ///< threads stepping layer worlds concurrently
  double layerHeight = 1.0;         ///< height h of one layer, cm
  int layers = 8;                   ///< layer count K, at most 16
  double gravity = 981.0;           ///< cm/s^2
  double particleRadius = 0.25;     ///< radius of one particle body, cm
  double particleMass = 1.0;        ///< mass of one particle body, g
  int stackSize = 1;                ///< S, bodies per particle stack in consecutive layers
  bool capsule = false;             ///< fill every layer from the base to the top instead of S
  double particleDownForce = 2000;  ///< constant downward force per particle, dyn
  double particleFriction = 0.8;    ///< default particle-to-object friction, non-dimensional
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

void Describe(PhysicsParams& p, ParamVisitor& v);

}  // namespace pg
