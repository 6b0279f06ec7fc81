// Each shape type's facts, one file per type, behind one checked switch
// (with_shape_type), as joint_types.h does for joints: a type is a struct
// of the same static functions, and a ShapeType without its case is a
// -Wswitch error (no `default:`), so a new shape cannot silently act as a
// box or a sphere. A new shape: its enum value (shape.h), its struct here
// and its file, its case below, its row and column of collide.cpp's pair
// table, its name (shape.h), and its keys in the scene reader
// (replay/scene.cpp) and the state description (replay/state_description.h).
//
// The functions each type has:
//   volume(shape)       m^3 (a plane's: 0)
//   mass(shape, density)
//                       its solid mass, and the diagonal of its inertia
//                       tensor about its own centre in its own axes
//   check(shape)        the envelope's checks of its sizes: refused with
//                       the field ("radius") and why, or fine
//   extent(shape)       how far its farthest point lies from its origin
//                       (the body's reach, core/envelope.h; a plane's: 0)
//   bounds(placed)      its world box (a plane's: the whole envelope)
//   ray(placed, ray, radius, entry)
//                       where a ray first enters the shape grown by
//                       `radius` (core/ray_cast.h's rules)
//   core_radius(shape)  the shape is its core (a point, a segment or a
//                       box) grown by this radius (a sphere's radius, a
//                       box's 0), as Box2D's and Jolt's convex radius
//   core_support(placed, d)
//                       the core's farthest point along world direction d
//                       (any length; ties take the + side), for GJK
//                       (gjk.h). Exact: corners and ends, no square root. A
//                       plane is unbounded: it has none (its origin), and
//                       the generic path never takes one
// Internal to core/.
#pragma once

#include <cstdlib>

#include "core/aabb.h"
#include "core/error.h"
#include "core/ray_cast.h"
#include "core/settings.h"
#include "core/shape.h"
#include "fixed/mat33.h"

namespace bitstep {

// A shape's solid mass, its inertia tensor about its centre of mass in its
// own axes (diagonal for the primitives), and that centre in its own frame
// (the origin for the primitives; a hull's centroid) (kg, kg m^2, m).
struct ShapeMass {
  Fixed mass;
  Mat33 inertia;
  Vec3 center;
};

#define BITSTEP_SHAPE_TYPE_FUNCTIONS                                                        \
  static Fixed volume(const Shape& shape);                                                  \
  static ShapeMass mass(const Shape& shape, Fixed density);                                 \
  static Result<void> check(const Shape& shape);                                            \
  static Fixed extent(const Shape& shape);                                                  \
  static Aabb bounds(const WorldShape& placed);                                             \
  static bool ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry); \
  static Fixed core_radius(const Shape& shape);                                             \
  static Vec3 core_support(const WorldShape& placed, Vec3 direction);

// A static half-space (shape_plane.cpp).
struct PlaneShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A box (shape_box.cpp).
struct BoxShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A capsule along its local y (shape_capsule.cpp).
struct CapsuleShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A sphere (shape_sphere.cpp).
struct SphereShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A convex hull (shape_hull.cpp, core/convex_hull.h).
struct HullShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A static triangle mesh (shape_mesh.cpp, core/triangle_mesh.h).
struct MeshShape {
  BITSTEP_SHAPE_TYPE_FUNCTIONS
};
// A heightfield: a mesh built from a grid (core/height_grid.h), every fact
// a mesh's.
struct HeightfieldShape : MeshShape {};

#undef BITSTEP_SHAPE_TYPE_FUNCTIONS

// Calls f with the struct of `type` (f(BoxShape{}) for a box).
template <class F>
decltype(auto) with_shape_type(ShapeType type, F&& f) {
  switch (type) {
    case ShapeType::plane: return f(PlaneShape{});
    case ShapeType::box: return f(BoxShape{});
    case ShapeType::capsule: return f(CapsuleShape{});
    case ShapeType::sphere: return f(SphereShape{});
    case ShapeType::hull: return f(HullShape{});
    case ShapeType::mesh: return f(MeshShape{});
    case ShapeType::heightfield: return f(HeightfieldShape{});
  }
  std::abort();  // never: World::create_body and the state reader take ShapeType's values only
}

// Whether `type` is one of ShapeType's values.
inline bool is_shape_type(ShapeType type) {
  switch (type) {
    case ShapeType::plane:
    case ShapeType::box:
    case ShapeType::capsule:
    case ShapeType::sphere:
    case ShapeType::hull:
    case ShapeType::mesh:
    case ShapeType::heightfield: return true;
  }
  return false;
}

// Its name (shape.h's list).
inline const char* shape_name(ShapeType type) { return shape_type_names[static_cast<size_t>(type)]; }

// A size the envelope admits: 0.01..50 m (core/settings.h).
inline bool size_in_envelope(Fixed s) { return s >= envelope::min_size && s <= envelope::max_size; }

// pi and 4 pi / 3 rounded to Q32.32 (the volumes' and inertias').
inline constexpr Fixed volume_pi = "raw:3243f6a89"_fx;
inline constexpr Fixed volume_four_thirds_pi = "raw:430548e0b"_fx;

}  // namespace bitstep
