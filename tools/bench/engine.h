// What a benchmark experiment needs from a physics engine, in doubles, so
// that bitstep and a peer (Bullet) are built, stepped and measured by the
// same experiment code (tools/bench/experiments.cpp). Reports may use
// floating point; bitstep's simulation behind this interface never does.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace bitstep::bench {

using V3 = std::array<double, 3>;
using Q4 = std::array<double, 4>;  // w, x, y, z

enum class ShapeKind { box, sphere, capsule, hull, mesh, heightfield };

struct ShapeSpec {
  ShapeKind kind = ShapeKind::box;
  V3 half_extents{0.5, 0.5, 0.5};  // m, box
  double radius = 0.5;             // m, sphere and capsule
  double half_height = 0.5;        // m, capsule: half its inner segment, along local y
  V3 local_position{0, 0, 0};      // in the body frame
  Q4 local_orientation{1, 0, 0, 0};
  // A hull: its corners (the shape's frame), and the mass properties
  // bitstep's builder found for them (each engine's body is then the same).
  std::vector<V3> points{};
  double volume = 0;                   // m^3
  V3 centroid{0, 0, 0};                // m, the shape's frame
  std::array<V3, 3> inertia_per_kg{};  // m^2, about the centroid, the shape's axes (full)
  // A static mesh: `points` are its vertices, three indices per triangle.
  std::vector<uint32_t> indices{};
  // A static heightfield: sample (i, j) at (i spacing_x, heights[j columns
  // + i], j spacing_z) in the shape's frame, each cell split along its
  // (i, j)-(i + 1, j + 1) diagonal (bitstep's core/height_grid.h; Bullet's
  // btHeightfieldTerrainShape splits the same way by default).
  uint32_t columns = 0, rows = 0;
  double spacing_x = 1, spacing_z = 1;  // m
  std::vector<double> heights{};        // m, row by row
};

struct BodySpec {
  bool is_static = false;
  std::vector<ShapeSpec> shapes;
  double mass = 1.0;  // kg (dynamic); inertia from the shapes at uniform density
  V3 position{0, 0, 0};              // of the body frame the shapes are given in
  Q4 orientation{1, 0, 0, 0};
  V3 linear_velocity{0, 0, 0};       // m/s
  V3 angular_velocity{0, 0, 0};      // rad/s, world frame
  double static_friction = 0.5;      // pairs combine by sqrt(mu_a mu_b)
  double dynamic_friction = 0.5;     // (an engine with one coefficient uses this one)
  double restitution = 0.0;          // pairs combine by max(e_a, e_b)
};

// Of the centre of mass (which for a compound body is not the body frame).
struct BodyState {
  V3 position{0, 0, 0};
  Q4 orientation{1, 0, 0, 0};
  V3 linear_velocity{0, 0, 0};
  V3 angular_velocity{0, 0, 0};
};

enum class JointKind { point, hinge, cone };

// A joint between two bodies (indices from add_body), in the world frame at
// the moment of creation. The joined bodies do not collide with each other.
struct JointSpec {
  JointKind kind = JointKind::point;
  int body_a = 0, body_b = 0;
  V3 anchor{0, 0, 0};  // m, world: the point both bodies share
  V3 axis{0, 0, 1};    // hinge: the axis; cone: the twist axis (world, unit)
  bool limited = false;  // hinge: b's turn about the axis relative to a kept in [lower, upper]; a cone's always is
  double lower = 0;      // rad, <= 0
  double upper = 0;      // rad, >= 0
  double swing = 0;      // rad: cone: how far b's twist axis may swing from a's
  double friction = 0;   // N m against b turning relative to a (Bullet: hinges only)
};

// A character controller: a kinematic upright capsule that walks at a
// desired level velocity, slides along walls, steps up and down to
// step_height and does not walk up slopes steeper than max_slope.
struct CharacterSpec {
  V3 position{0, 0, 0};                   // m, the capsule's centre
  double radius = 0.3;                    // m
  double half_height = 0.6;               // m, of the inner segment, along y
  double max_slope = 0.7853981633974483;  // rad (45 degrees)
  double step_height = 0.3;               // m
};

// The step every engine is given: the same dt, iteration count and gravity.
struct StepConfig {
  double dt = 1.0 / 60.0;  // s
  int iterations = 10;     // velocity iterations
  V3 gravity{0, -9.81, 0};
  int threads = 1;  // workers stepping a bitstep world (the same bits for any count); peers use one
};

class Engine {
 public:
  virtual ~Engine() = default;
  // Index of the new body, 0, 1, ... in creation order.
  virtual int add_body(const BodySpec& spec) = 0;
  virtual void step() = 0;
  virtual BodyState state(int body) const = 0;
  // Index of the new joint, 0, 1, ... in creation order; -1: the engine has no joints.
  virtual int add_joint(const JointSpec& spec) {
    (void)spec;
    return -1;
  }
  // Index of the new character, 0, 1, ... in creation order; -1: the
  // engine has no character controller.
  virtual int add_character(const CharacterSpec& spec) {
    (void)spec;
    return -1;
  }
  // The level velocity (m/s) it walks at from the next step on.
  virtual void walk(int character, const V3& velocity) {
    (void)character;
    (void)velocity;
  }
  // Its capsule's centre, m.
  virtual V3 character_position(int character) const {
    (void)character;
    return {0, 0, 0};
  }
  // The deepest overlap among the engine's current contact points, m (>= 0).
  virtual double max_penetration() const = 0;
  // A 64-bit hash over the exact bits of every body's state (determinism check).
  virtual uint64_t state_hash() const = 0;
};

// A named way to build an engine: "standard", "standard+shock", "guendelman",
// "guendelman+shock" (bitstep), "bullet" (the peer program).
struct Variant {
  std::string name;
  std::unique_ptr<Engine> (*make)(const StepConfig& config);
};

}  // namespace bitstep::bench
