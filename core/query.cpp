#include "core/query.h"

#include <algorithm>
#include <tuple>

#include "core/collide.h"
#include "core/collide_internal.h"

namespace bitstep {

namespace {

using collide_detail::get;

// Leaves per node of the tree: a few shape tests cost less than a level.
constexpr uint32_t leaf_size = 4;
// Deep enough for any tree built here (a depth of log2(leaves / 4) + 1).
constexpr int max_depth = 64;

// Twice the centre of a box along an axis (no halving: only compared).
Fixed doubled_centre(const Aabb& b, int axis) { return get(b.min, axis) + get(b.max, axis); }

// The ray of a translation: unit direction and length, or none for a zero
// translation or one beyond the casts' reach.
std::optional<Ray> ray_of(Vec3 origin, Vec3 translation) {
  if (translation == Vec3{} || !within_axes(translation, max_ray_length)) return std::nullopt;
  const Fixed length = bitstep::length(translation);
  if (length == Fixed{} || length > max_ray_length) return std::nullopt;
  return Ray{origin, normalize(translation), length};
}

// A ray or sphere cast's ray: none also for an origin beyond the casts'
// coordinates, which every shape refuses (ray_enters); refused here, before
// the tree's boxes are measured from an origin that may be any value.
std::optional<Ray> cast_ray_of(Vec3 origin, Vec3 translation) {
  if (!within_axes(origin, max_ray_coordinate)) return std::nullopt;
  return ray_of(origin, translation);
}

// The order of answers: nearest first, then by body slot and shape index.
bool before(const QueryHit& a, const QueryHit& b) {
  return std::tie(a.fraction, a.body.index, a.shape) < std::tie(b.fraction, b.body.index, b.shape);
}

}  // namespace

WorldQuery::WorldQuery(const World& world) : WorldQuery(world, std::nullopt) {}

WorldQuery::WorldQuery(const World& world, const Aabb& region) : WorldQuery(world, std::optional<Aabb>(region)) {}

WorldQuery::WorldQuery(const World& world, const std::optional<Aabb>& region) : world_(&world) {
  const std::vector<Body>& bodies = world.bodies();
  for (uint32_t slot = 0; slot < bodies.size(); ++slot) {
    const Body& body = bodies[slot];
    if (!body.alive) continue;
    for (uint32_t s = 0; s < body.shapes.size(); ++s) {
      const Leaf leaf{slot, s, shape_aabb({&body.shapes[s], compose(body.pose, body.shapes[s].local)})};
      if (body.shapes[s].type == ShapeType::plane) {
        planes_.push_back(leaf);
      } else if (!region || leaf.bounds.overlaps(*region)) {
        leaves_.push_back(leaf);
      }
    }
  }
  if (!leaves_.empty()) {
    nodes_.reserve(2 * leaves_.size() / leaf_size + 1);
    build(0, static_cast<uint32_t>(leaves_.size()));
  }
}

// Splits leaves[first, first + count) at the median of their centres along
// the widest spread of centres; ties by body slot and shape index, so the
// two halves are the same sets on every platform.
uint32_t WorldQuery::build(uint32_t first, uint32_t count) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  Aabb bounds = leaves_[first].bounds;
  Aabb centres{{doubled_centre(bounds, 0), doubled_centre(bounds, 1), doubled_centre(bounds, 2)}, {}};
  centres.max = centres.min;
  for (uint32_t i = first; i < first + count; ++i) {
    const Aabb& b = leaves_[i].bounds;
    bounds = bounds.merged(b);
    const Vec3 c{doubled_centre(b, 0), doubled_centre(b, 1), doubled_centre(b, 2)};
    centres = centres.merged({c, c});
  }
  if (count <= leaf_size) {
    nodes_[index] = {bounds, first, count, 0, 0};
    return index;
  }
  const Vec3 spread = centres.max - centres.min;
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
  const uint32_t half = count / 2;
  const auto key = [axis](const Leaf& l) { return std::tuple(doubled_centre(l.bounds, axis), l.body, l.shape); };
  const auto at = [&](uint32_t i) { return leaves_.begin() + static_cast<std::ptrdiff_t>(i); };
  std::nth_element(at(first), at(first + half), at(first + count),
                   [&](const Leaf& a, const Leaf& b) { return key(a) < key(b); });
  const uint32_t left = build(first, half);
  const uint32_t right = build(first + half, count - half);
  nodes_[index] = {bounds, 0, 0, left, right};
  return index;
}

WorldShape WorldQuery::placed(const Leaf& leaf) const {
  const Body& body = world_->bodies()[leaf.body];
  return {&body.shapes[leaf.shape], compose(body.pose, body.shapes[leaf.shape].local)};
}

QueryHit WorldQuery::hit_of(const Leaf& leaf, const Ray& ray, const ShapeEntry& entry) const {
  const Body& body = world_->bodies()[leaf.body];
  return {{leaf.body, body.generation}, leaf.shape, min(entry.distance / ray.length, Fixed::one()), entry.point,
          entry.normal};
}

// Calls visit(leaf) for every leaf of the tree whose bounds pass
// `enters`, skipping every node whose bounds do not.
template <typename Enters, typename Visit>
void WorldQuery::descend(Enters&& enters, Visit&& visit) const {
  if (nodes_.empty()) return;
  uint32_t stack[max_depth * 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!enters(node.bounds)) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (enters(leaves_[i].bounds)) visit(leaves_[i]);
      }
      continue;
    }
    stack[top++] = node.right;
    stack[top++] = node.left;
  }
}

bool WorldQuery::sees(const Leaf& leaf, const QueryFilter& filter) const {
  const Body& body = world_->bodies()[leaf.body];
  if ((body.filter.layers & filter.layers) == 0) return false;
  return !(filter.ignore.index == leaf.body && filter.ignore.generation == body.generation);
}

// Calls visit(leaf) for every plane and every leaf whose bounds, grown by
// `reach` along each axis, the ray enters within its length (which visit
// may shorten), of the bodies the filter sees.
template <typename Visit>
void WorldQuery::visit_along(const Ray& ray, Vec3 reach, const QueryFilter& filter, Visit&& visit) const {
  auto seen = [&](const Leaf& leaf) {
    if (sees(leaf, filter)) visit(leaf);
  };
  for (const Leaf& plane : planes_) seen(plane);
  Fixed distance;
  descend([&](const Aabb& bounds) { return ray_enters(Aabb{bounds.min - reach, bounds.max + reach}, ray, distance); },
          seen);
}

template <typename Enters>
std::optional<QueryHit> WorldQuery::cast_nearest(const Ray& full, Vec3 reach, const QueryFilter& filter,
                                                 Enters&& enters) const {
  Ray ray = full;  // shortened to the nearest hit so far: farther boxes are skipped
  std::optional<QueryHit> nearest;
  visit_along(ray, reach, filter, [&](const Leaf& leaf) {
    ShapeEntry entry;
    if (!enters(placed(leaf), ray, entry)) return;
    QueryHit hit = hit_of(leaf, full, entry);
    if (nearest && !before(hit, *nearest)) return;
    nearest = hit;
    ray.length = entry.distance;
  });
  return nearest;
}

template <typename Enters>
void WorldQuery::cast_all(const Ray& ray, Vec3 reach, std::vector<QueryHit>& hits, const QueryFilter& filter,
                          Enters&& enters) const {
  hits.clear();
  visit_along(ray, reach, filter, [&](const Leaf& leaf) {
    ShapeEntry entry;
    if (enters(placed(leaf), ray, entry)) hits.push_back(hit_of(leaf, ray, entry));
  });
  std::sort(hits.begin(), hits.end(), before);
}

namespace {

// A ray (radius 0) or a sphere's centre against one shape.
auto ball_enters(Fixed radius) {
  return [radius](const WorldShape& target, const Ray& ray, ShapeEntry& entry) {
    RayEntry e;
    if (!ray_enters(target, ray, radius, e)) return false;
    entry = e.distance == Fixed{} ? ShapeEntry{Fixed{}, ray.origin, -ray.direction}
                                  : ShapeEntry{e.distance, mul_add(ray.direction, e.distance, ray.origin) -
                                                               e.normal * radius,
                                               e.normal};
    return true;
  };
}

Vec3 ball_reach(Fixed radius) { return {radius, radius, radius}; }

}  // namespace

std::optional<QueryHit> WorldQuery::cast_ray(Vec3 origin, Vec3 translation, const QueryFilter& filter) const {
  const std::optional<Ray> ray = cast_ray_of(origin, translation);
  return ray ? cast_nearest(*ray, Vec3{}, filter, ball_enters(Fixed{})) : std::nullopt;
}
void WorldQuery::cast_ray_all(Vec3 origin, Vec3 translation, std::vector<QueryHit>& hits,
                              const QueryFilter& filter) const {
  hits.clear();
  const std::optional<Ray> ray = cast_ray_of(origin, translation);
  if (ray) cast_all(*ray, Vec3{}, hits, filter, ball_enters(Fixed{}));
}
std::optional<QueryHit> WorldQuery::cast_sphere(Fixed radius, Vec3 origin, Vec3 translation,
                                                const QueryFilter& filter) const {
  const std::optional<Ray> ray = cast_ray_of(origin, translation);
  if (!ray || radius < Fixed{}) return std::nullopt;
  return cast_nearest(*ray, ball_reach(radius), filter, ball_enters(radius));
}
void WorldQuery::cast_sphere_all(Fixed radius, Vec3 origin, Vec3 translation, std::vector<QueryHit>& hits,
                                 const QueryFilter& filter) const {
  hits.clear();
  const std::optional<Ray> ray = cast_ray_of(origin, translation);
  if (ray && radius >= Fixed{}) cast_all(*ray, ball_reach(radius), hits, filter, ball_enters(radius));
}

namespace {

// The tree is searched along the path of the cast shape's bounds: a ray
// from their centre, each node grown by their half size (`reach`).
std::optional<Ray> shape_path(const WorldShape& moving, Vec3 translation, Vec3& reach) {
  if (moving.shape->type == ShapeType::plane) return std::nullopt;
  const Aabb bounds = shape_aabb(moving);
  const Vec3 centre = bounds.min + (bounds.max - bounds.min) / Fixed::from_int(2);
  reach = max(bounds.max - centre, centre - bounds.min);
  return ray_of(centre, translation);
}

auto shape_enters_from(const WorldShape& moving) {
  return [moving](const WorldShape& target, const Ray& path, ShapeEntry& entry) {
    return shape_enters(moving, path, target, entry);
  };
}

}  // namespace

std::optional<QueryHit> WorldQuery::cast_shape(const Shape& shape, const Pose& pose, Vec3 translation,
                                               const QueryFilter& filter) const {
  const WorldShape moving{&shape, pose};
  Vec3 reach;
  const std::optional<Ray> ray = shape_path(moving, translation, reach);
  return ray ? cast_nearest(*ray, reach, filter, shape_enters_from(moving)) : std::nullopt;
}
void WorldQuery::cast_shape_all(const Shape& shape, const Pose& pose, Vec3 translation, std::vector<QueryHit>& hits,
                                const QueryFilter& filter) const {
  hits.clear();
  const WorldShape moving{&shape, pose};
  Vec3 reach;
  const std::optional<Ray> ray = shape_path(moving, translation, reach);
  if (ray) cast_all(*ray, reach, hits, filter, shape_enters_from(moving));
}

// Calls visit(leaf) for every plane and leaf whose bounds overlap `box`,
// of the bodies the filter sees.
template <typename Visit>
void WorldQuery::visit_overlapping(const Aabb& box, const QueryFilter& filter, Visit&& visit) const {
  auto seen = [&](const Leaf& leaf) {
    if (sees(leaf, filter)) visit(leaf);
  };
  for (const Leaf& plane : planes_) {
    if (plane.bounds.overlaps(box)) seen(plane);
  }
  descend([&](const Aabb& bounds) { return bounds.overlaps(box); }, seen);
}

void WorldQuery::overlap_box(const Aabb& box, std::vector<BodyId>& bodies, const QueryFilter& filter) const {
  bodies.clear();
  std::vector<uint32_t> slots;
  visit_overlapping(box, filter, [&](const Leaf& leaf) { slots.push_back(leaf.body); });
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
  for (const uint32_t slot : slots) bodies.push_back({slot, world_->bodies()[slot].generation});
}

void WorldQuery::overlap_shape(const Shape& shape, const Pose& pose, std::vector<ShapeOverlap>& overlaps,
                               const QueryFilter& filter) const {
  overlaps.clear();
  const WorldShape query{&shape, pose};
  visit_overlapping(shape_aabb(query), filter, [&](const Leaf& leaf) {
    Manifold m;
    if (collide(query, placed(leaf), Fixed{}, m) == 0) return;
    Fixed depth;
    for (int i = 0; i < m.point_count; ++i) depth = max(depth, m.points[static_cast<size_t>(i)].depth);
    if (depth > Fixed{}) overlaps.push_back({{leaf.body, world_->bodies()[leaf.body].generation}, leaf.shape, depth});
  });
  std::sort(overlaps.begin(), overlaps.end(), [](const ShapeOverlap& a, const ShapeOverlap& b) {
    return std::tie(a.body.index, a.shape) < std::tie(b.body.index, b.shape);
  });
}

}  // namespace bitstep
