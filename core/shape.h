// Shapes, each with a local pose in its body's frame. A body has one or more
// shapes; more than one makes a compound (tables, chairs, ragdoll parts).
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "core/pose.h"

namespace bitstep {

enum class ShapeType : uint8_t {
  plane,    // static half-space: the local +y axis is the outward normal, the surface passes through the local origin
  box,      // half_extents along the local axes
  capsule,  // a segment from -half_height to +half_height along local y, swept by radius
  sphere,   // radius
  hull,     // a convex hull of points (core/convex_hull.h), shared and immutable
  mesh,     // static triangles, one-sided (core/triangle_mesh.h), shared and immutable; static bodies only
  heightfield,  // a grid of heights (core/height_grid.h): a mesh built from it, in `mesh`; static bodies only
};

// Each type's name in scenes, states and messages, by its value: the one
// list (shape_types.h has each type's other facts).
inline constexpr std::array<const char*, 7> shape_type_names = {"plane", "box",  "capsule",    "sphere",
                                                                "hull",  "mesh", "heightfield"};

// A mesh or a heightfield: static triangles, in `mesh`.
constexpr bool has_triangles(ShapeType type) { return type == ShapeType::mesh || type == ShapeType::heightfield; }

struct ConvexHull;
struct TriangleMesh;

struct Shape {
  ShapeType type = ShapeType::box;
  Vec3 half_extents;   // m, box
  Fixed radius;        // m, sphere and capsule
  Fixed half_height;   // m, capsule: half the length of its inner segment
  Pose local;          // in the body frame (whose origin is the centre of mass)
  std::shared_ptr<const ConvexHull> hull = nullptr;  // hull: its points, faces and mass (never null for a hull)
  std::shared_ptr<const TriangleMesh> mesh = nullptr;  // mesh, heightfield: its triangles and tree (never null)
};

struct Mat33;

// A shape placed in the world for collision: the body's pose composed with
// the shape's local pose, and, where the caller has it, the rotation matrix
// of that orientation (collide's box functions read it: the narrowphase
// computes it once per shape, not once per pair).
struct WorldShape {
  const Shape* shape;
  Pose pose;
  const Mat33* axes = nullptr;  // rotation(pose.orientation), or none
};

}  // namespace bitstep
