// TestWorld: a world with helpers that read like the physics, so the tests
// do too.
#pragma once

#include <vector>

#include "core/convex_hull.h"
#include "core/world.h"

namespace bitstep::test {

// A rotation of `degrees` about the unit vector `axis`.
inline Quat about_degrees(Vec3 axis, Fixed degrees) {
  return from_axis_angle(axis, degrees * "3.14159265358979/180"_fx);
}

// A box of half extents h made as a hull of its eight corners (the
// generic path's shape, to set beside the box's own routines).
inline Shape box_hull(Vec3 h) {
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k) {
    corners.push_back({(k & 1) != 0 ? h.x : -h.x, (k & 2) != 0 ? h.y : -h.y, (k & 4) != 0 ? h.z : -h.z});
  }
  Shape s;
  s.type = ShapeType::hull;
  s.hull = build_convex_hull(corners).value();
  return s;
}

// A die: a cube of half size a with its corners cut to b (six octagons,
// eight triangles, 24 corners).
inline Shape die_hull(Fixed a, Fixed b) {
  std::vector<Vec3> points;
  for (int k = 0; k < 8; ++k) {
    const Fixed x = (k & 1) != 0 ? Fixed::one() : -Fixed::one(), y = (k & 2) != 0 ? Fixed::one() : -Fixed::one(),
                z = (k & 4) != 0 ? Fixed::one() : -Fixed::one();
    points.push_back({x * a, y * a, z * b});
    points.push_back({x * a, y * b, z * a});
    points.push_back({x * b, y * a, z * a});
  }
  Shape s;
  s.type = ShapeType::hull;
  s.hull = build_convex_hull(points).value();
  return s;
}

struct TestWorld {
  World world;

  explicit TestWorld(const Settings& settings = {}) : world(settings) {}

  // A static ground box whose top face is at y = 0.
  BodyId add_ground(Material material = {}) {
    BodyDef def;
    def.type = BodyType::static_body;
    def.pose.position = {Fixed{}, -1.0_fx, Fixed{}};
    def.shapes.push_back({ShapeType::box, {50.0_fx, 1.0_fx, 50.0_fx}, {}, {}, {}});
    def.material = material;
    return world.create_body(def).value();
  }

  // A static ramp 20 x 1 x 6 m, its centre at the origin, tilted by `tilt`:
  // its top face passes through tilt applied to (0, 0.5, 0).
  BodyId add_ramp(Quat tilt, Material material = {}) {
    BodyDef def;
    def.type = BodyType::static_body;
    def.pose = {{}, tilt};
    def.shapes.push_back({ShapeType::box, {10.0_fx, 0.5_fx, 3.0_fx}, {}, {}, {}});
    def.material = material;
    return world.create_body(def).value();
  }

  BodyId add_box(Vec3 position, Vec3 half_extents, Material material = {}) {
    BodyDef def;
    def.pose.position = position;
    def.shapes.push_back({ShapeType::box, half_extents, {}, {}, {}});
    def.material = material;
    return world.create_body(def).value();
  }

  BodyId add_sphere(Vec3 position, Fixed radius, Material material = {}) {
    BodyDef def;
    def.pose.position = position;
    def.shapes.push_back({ShapeType::sphere, {}, radius, {}, {}});
    def.material = material;
    return world.create_body(def).value();
  }

  BodyId add_capsule(Pose pose, Fixed radius, Fixed half_height, Material material = {}) {
    BodyDef def;
    def.pose = pose;
    def.shapes.push_back({ShapeType::capsule, {}, radius, half_height, {}});
    def.material = material;
    return world.create_body(def).value();
  }

  // A small static block at `position` to join things to (it touches nothing).
  BodyId add_anchor(Vec3 position) {
    BodyDef def;
    def.type = BodyType::static_body;
    def.pose.position = position;
    def.shapes.push_back({ShapeType::box, {0.05_fx, 0.05_fx, 0.05_fx}, {}, {}, {}});
    return world.create_body(def).value();
  }

  // A joint of `type` between a and b at the world point `anchor`, about
  // z where the type has an axis.
  Result<JointId> join(JointType type, BodyId a, BodyId b, Vec3 anchor) {
    JointDef def;
    def.type = type;
    def.body_a = a;
    def.body_b = b;
    def.anchor_a = anchor;
    def.axis = {Fixed{}, Fixed{}, Fixed::one()};
    return world.create_joint(def);
  }

  void simulate_steps(int steps) {
    for (int i = 0; i < steps; ++i) world.step();
  }
  // Whole steps covering `seconds` (rounded down).
  void simulate(Fixed seconds) { simulate_steps(static_cast<int>((seconds / world.settings().dt).raw() >> 32)); }

  const Body& body(BodyId id) const { return world.body(id); }
};

}  // namespace bitstep::test
