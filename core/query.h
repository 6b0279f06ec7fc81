// Questions a game asks the world between steps: what a ray or a moving
// sphere hits first (or everything it hits), which bodies' bounds overlap a
// box, which shapes a shape overlaps. As deterministic as the step: the
// answers are computed in fixed point and come in a defined order (distance,
// then body slot, then shape index), so in a lockstep game they can steer
// the simulation.
//
// A WorldQuery is built over the world as it is (every live body's shapes,
// static, sleeping and awake, in a tree of bounding boxes: O(n log n)) and
// answers from that snapshot until it is built again: build one after each
// step and ask it as much as needed (a ray over 10,000 bodies visits a few
// dozen boxes).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/ray_cast.h"
#include "core/shape_cast.h"
#include "core/world.h"

namespace bitstep {

struct QueryHit {
  BodyId body;
  uint32_t shape = 0;  // its index in the body's shapes
  Fixed fraction;      // of the translation at which it is met, 0..1
  Vec3 point;          // where the ray (or the cast shape's surface) first touches the shape
  Vec3 normal;         // the shape's outward unit normal there (-direction when starting inside)
  // Starting inside (or touching): fraction 0, the normal -direction, the
  // point the ray's origin (the cast shape's centre).
};

// Which bodies a query sees: those on any of `layers` (their
// CollisionFilter::layers, core/body.h), but not `ignore` (a car's rays
// skip the car). By default every body.
struct QueryFilter {
  uint32_t layers = UINT32_MAX;
  BodyId ignore;
};

struct ShapeOverlap {
  BodyId body;
  uint32_t shape = 0;
  Fixed depth;  // m, the deepest overlap between the two shapes (> 0)
};

class WorldQuery {
 public:
  explicit WorldQuery(const World& world);
  // Only the shapes whose bounds overlap `region` (and every plane): exact
  // for questions that stay inside it (a car's wheel rays), and cheaper to
  // build in a large world.
  WorldQuery(const World& world, const Aabb& region);

  // A ray from `origin` along `translation` (its length is the ray's): the
  // first shape it meets, or every shape it meets, nearest first. Shapes are
  // solid: a ray starting inside one meets it at fraction 0. A zero
  // translation, an origin beyond 65,536 m or a translation longer than
  // 131,072 m meets nothing.
  std::optional<QueryHit> cast_ray(Vec3 origin, Vec3 translation, const QueryFilter& filter = {}) const;
  void cast_ray_all(Vec3 origin, Vec3 translation, std::vector<QueryHit>& hits, const QueryFilter& filter = {}) const;

  // A sphere of `radius` moved from `origin` along `translation`: where its
  // surface first touches each shape (`point`), the fraction of the move at
  // which it does.
  std::optional<QueryHit> cast_sphere(Fixed radius, Vec3 origin, Vec3 translation,
                                      const QueryFilter& filter = {}) const;
  void cast_sphere_all(Fixed radius, Vec3 origin, Vec3 translation, std::vector<QueryHit>& hits,
                       const QueryFilter& filter = {}) const;

  // A shape (a sphere, capsule or box; its `local` pose is not used) moved
  // from `pose` along `translation` without turning: where it first touches
  // each shape (core/shape_cast.h says how each pair is solved). A capsule
  // cast is a character's sweep, a box cast a crate's.
  std::optional<QueryHit> cast_shape(const Shape& shape, const Pose& pose, Vec3 translation,
                                     const QueryFilter& filter = {}) const;
  void cast_shape_all(const Shape& shape, const Pose& pose, Vec3 translation, std::vector<QueryHit>& hits,
                      const QueryFilter& filter = {}) const;

  // Bodies with a shape whose bounds overlap `box`, by slot.
  void overlap_box(const Aabb& box, std::vector<BodyId>& bodies, const QueryFilter& filter = {}) const;

  // Shapes that `shape` placed at `pose` overlaps (the narrowphase's exact
  // test, touching not counted), by body slot and shape index.
  void overlap_shape(const Shape& shape, const Pose& pose, std::vector<ShapeOverlap>& overlaps,
                     const QueryFilter& filter = {}) const;

 private:
  struct Leaf {
    uint32_t body, shape;
    Aabb bounds;
  };
  struct Node {
    Aabb bounds;
    uint32_t first, count;   // leaves[first, first + count) when a leaf node (count > 0)
    uint32_t left, right;    // children otherwise
  };

  WorldQuery(const World& world, const std::optional<Aabb>& region);
  uint32_t build(uint32_t first, uint32_t count);
  WorldShape placed(const Leaf& leaf) const;
  QueryHit hit_of(const Leaf& leaf, const Ray& ray, const ShapeEntry& entry) const;
  template <typename Enters, typename Visit>
  void descend(Enters&& enters, Visit&& visit) const;
  bool sees(const Leaf& leaf, const QueryFilter& filter) const;
  template <typename Visit>
  void visit_along(const Ray& ray, Vec3 reach, const QueryFilter& filter, Visit&& visit) const;
  template <typename Visit>
  void visit_overlapping(const Aabb& box, const QueryFilter& filter, Visit&& visit) const;
  // `enters(placed shape, ray, entry)` is the exact test of one shape; `reach`
  // grows the tree's boxes by the cast shape's half size.
  template <typename Enters>
  std::optional<QueryHit> cast_nearest(const Ray& ray, Vec3 reach, const QueryFilter& filter, Enters&& enters) const;
  template <typename Enters>
  void cast_all(const Ray& ray, Vec3 reach, std::vector<QueryHit>& hits, const QueryFilter& filter,
                Enters&& enters) const;

  const World* world_;
  std::vector<Leaf> leaves_;
  std::vector<Leaf> planes_;  // bounds the whole world: tested on every query, not in the tree
  std::vector<Node> nodes_;   // nodes_[0] is the root when there are leaves
};

}  // namespace bitstep
