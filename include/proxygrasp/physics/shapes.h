// Geometry of virtual objects outside Box2D: validation, mass properties of the full 3D shape,
// cross-sections at a height (the layer slices), the footprint and the top surface height, and
// convex decomposition of prism outlines into pieces Box2D can simulate. All in the object's local
// frame, centimetres.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/physics/types.h"

#include <string>
#include <utility>
#include <vector>

namespace pg {

/// Mass properties of an object's full 3D shape.
struct MassProps {
  double volume = 0.0;           ///< cm^3
  double mass = 0.0;             ///< g
  double inertia = 0.0;          ///< about the vertical axis through the centroid, g cm^2
  Vec2 centroid = Vec2::Zero();  ///< centre of mass in the local frame, cm
};

/// A horizontal cross-section: a circle about the local origin or a polygon.
struct CrossSection {
  bool circle = false;
  double radius = 0.0;          ///< circles, cm
  Contour outline;              ///< counter-clockwise; circles as a 32-gon, cm
  std::vector<Contour> pieces;  ///< convex pieces of at most 8 vertices (empty for circles)
};

/// Checks an object spec against the physics parameters. Errors sit at spec.loc and name the
/// object and the field: "object 'cup': radius must be > 0 (got -1)"; field, when given,
/// receives the field's key ("radius"), so that a level file can point at it.
MaybeError ValidateObject(const ObjectSpec& spec, const PhysicsParams& params,
                          std::string* field = nullptr);

/// The axis-aligned bounds (low, high corners) of the object's footprint on the table at its
/// starting pose, cm.
std::pair<Vec2, Vec2> FootprintBounds(const ObjectSpec& spec);

/// The object's height (2r for spheres), cm.
double ObjectHeight(const ObjectSpec& spec);

/// Mass, inertia about the vertical axis and centroid of the full 3D shape; spec.mass > 0 overrides
/// the mass from density (the inertia scales with it).
MassProps ComputeMassProps(const ObjectSpec& spec);

/// Layers holding slices: layer k for every k < layers with (k + 0.5) h < height, and at least
/// layer 0 (a slab thinner than h/2 keeps one slice).
int SliceLayerCount(const ObjectSpec& spec, double layerHeight, int layers);

/// The height at which the slice of layer k is cut: its mid-height, or half the object's height
/// for the single slice of a slab thinner than h/2, cm.
double SliceHeight(const ObjectSpec& spec, int layer, double layerHeight);

/// The cross-section at height z (0 <= z <= height).
CrossSection SectionAt(const ObjectSpec& spec, double z);

/// The footprint: the largest cross-section, what covers the table seen from above.
CrossSection Footprint(const ObjectSpec& spec);

/// Height of the object's top surface above the local point p, or -1 when p is off it, cm.
double SurfaceHeightAt(const ObjectSpec& spec, const Vec2& p);

/// Signed distance of the local point p to the footprint's boundary: > 0 inside, cm.
double FootprintSignedDistance(const ObjectSpec& spec, const CrossSection& footprint,
                               const Vec2& p);

/// The point of the footprint's boundary nearest to the local point p, cm.
Vec2 NearestFootprintPoint(const CrossSection& footprint, const Vec2& p);

/// Mean distance of the base's area from the centroid (2R/3 for a disc), the lever arm of table
/// friction against turning; for a sphere 2a/3 of its contact patch of radius a (patch_radius;
/// 0 makes it a point that spins freely), cm.
double EffectiveFrictionRadius(const ObjectSpec& spec, const Vec2& centroid);

/// A point of an object's base and its share of the table's normal force.
struct FrictionPoint {
  Vec2 arm = Vec2::Zero();  ///< from the centroid, in the local frame, cm
  double weight = 0.0;      ///< share of the normal force; the shares sum to 1
};

/// Table friction spread over the base (uniform pressure) as about 16 points: a disc as two rings
/// of 8 at 0.431 R and 0.902 R (the radii at which equal halves reproduce the disc's first and
/// second radial moments, 2R/3 and R^2/2), a sphere's contact patch likewise, a polygon as the
/// area centroids of an even grid of cells. Their weighted arms sum to zero and their weighted
/// distances to EffectiveFrictionRadius, so a pure slide meets mu N and a pure turn mu N r_eff
/// exactly. A sphere without a patch is one point.
std::vector<FrictionPoint> TableFrictionPoints(const ObjectSpec& spec, const Vec2& centroid);

/// Splits a simple counter-clockwise polygon into convex pieces of at most maxVertices vertices
/// (ear clipping, then greedy merging across shared diagonals, Hertel-Mehlhorn style).
std::vector<Contour> ConvexDecompose(const Contour& polygon, int maxVertices = 8);

/// Area moment of inertia of a simple polygon about the point c (integral of |x - c|^2 dA), cm^4.
double PolygonPolarMoment(const Contour& polygon, const Vec2& c);

}  // namespace pg
