// The narrowphase's exact reuse (core/contact_update.h): a shape pair whose
// two poses and margin did not change by a bit gets last step's collision
// result; and the solver's (core/row_cache.h): a manifold whose rows'
// inputs did not change by a bit gets last step's Jacobians. A world stepped
// with both and one stepped without must hold the same bits after every
// step, including when a slot is reused by a body with other shapes at the
// very pose of the one removed from it.
#include <catch2/catch.hpp>

#include <functional>

#include "tests/core/test_world.h"

using namespace bitstep;
using bitstep::test::TestWorld;

namespace {

// Every pose, velocity and contact field of two worlds, bit for bit.
bool same_state(const World& x, const World& y) {
  if (x.bodies().size() != y.bodies().size() || x.contacts().size() != y.contacts().size()) return false;
  for (size_t i = 0; i < x.bodies().size(); ++i) {
    const Body& a = x.bodies()[i];
    const Body& b = y.bodies()[i];
    if (a.alive != b.alive || !(a.pose == b.pose) || a.linear_velocity != b.linear_velocity ||
        a.angular_velocity != b.angular_velocity || a.asleep != b.asleep) {
      return false;
    }
  }
  for (size_t i = 0; i < x.contacts().size(); ++i) {
    const Contact& c = x.contacts()[i];
    const Contact& d = y.contacts()[i];
    const Manifold& m = c.manifold;
    const Manifold& n = d.manifold;
    if (c.key != d.key || m.normal != n.normal || m.point_count != n.point_count) return false;
    if (m.friction_impulse[0] != n.friction_impulse[0] || m.friction_impulse[1] != n.friction_impulse[1] ||
        m.twist_impulse != n.twist_impulse) {
      return false;
    }
    for (size_t k = 0; k < static_cast<size_t>(m.point_count); ++k) {
      const ContactPoint& p = m.points[k];
      const ContactPoint& q = n.points[k];
      if (p.position != q.position || p.depth != q.depth || p.feature != q.feature ||
          p.normal_impulse != q.normal_impulse || p.split_impulse != q.split_impulse) {
        return false;
      }
    }
  }
  return true;
}

// Five boxes stacked on the ground.
void build_stack(TestWorld& t) {
  t.add_ground();
  for (int level = 0; level < 5; ++level) {
    t.add_box({Fixed{}, 0.5_fx + Fixed::from_int(level), Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  }
}

// Three courses of running bond on the ground, three bricks, two and one:
// each upper brick rests on two, and the shock step glues it to both at
// once (glue_all).
void build_wall(TestWorld& t) {
  t.add_ground();
  for (int course = 0; course < 3; ++course) {
    for (int brick = 0; brick < 3 - course; ++brick) {
      const Fixed x = Fixed::from_int(brick) + 0.5_fx * Fixed::from_int(course);
      t.add_box({x, 0.25_fx + 0.5_fx * Fixed::from_int(course), Fixed{}}, {0.5_fx, 0.25_fx, 0.25_fx});
    }
  }
}

// Steps a world with reuse and one without, `steps` times, with `between`
// applied to both before each step; the first step at which they differ (0
// when none does) and how many shape pairs the first one reused.
struct Comparison {
  int first_difference = 0;
  uint64_t reused = 0;
  uint64_t reused_rows = 0;  // manifolds whose rows were reused
};
Comparison compare(const Settings& settings, int steps, const std::function<void(TestWorld&, int)>& between,
                   const std::function<void(TestWorld&)>& build = build_stack) {
  TestWorld with(settings), without(settings);
  build(with);
  build(without);
  without.world.set_contact_reuse(false);
  Comparison result;
  for (int step = 1; step <= steps; ++step) {
    between(with, step);
    between(without, step);
    with.world.step();
    without.world.step();
    if (result.first_difference == 0 && !same_state(with.world, without.world)) result.first_difference = step;
  }
  result.reused = with.world.reused_shape_pairs();
  result.reused_rows = with.world.reused_manifold_rows();
  CHECK(without.world.reused_shape_pairs() == 0);
  CHECK(without.world.reused_manifold_rows() == 0);
  return result;
}

// Replaces `body` by an icy box (mu_s 0.05, mu 0.04) of the
// given half extents at its pose, in the same slot; its new handle.
BodyId make_icy(TestWorld& t, BodyId body, Vec3 half_extents) {
  BodyDef def;
  def.pose = t.world.body(body).pose;
  def.shapes.push_back({ShapeType::box, half_extents, {}, {}, {}});
  def.material.static_friction = 0.05_fx;
  def.material.dynamic_friction = 0.04_fx;
  REQUIRE(t.world.remove_body(body));
  const BodyId icy = t.world.create_body(def).value();
  REQUIRE(icy.index == body.index);
  return icy;
}

}  // namespace

TEST_CASE("a standing stack reuses its collision tests and keeps the same bits", "[world][reuse]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    Settings settings;
    settings.pipeline = pipeline;
    const Comparison c = compare(settings, 120, [](TestWorld&, int) {});
    INFO((pipeline == Pipeline::standard ? "standard" : "guendelman") << ": reused " << c.reused << " pairs, "
                                                                       << c.reused_rows << " manifolds' rows");
    CHECK(c.first_difference == 0);
    CHECK(c.reused > 0);  // the caches were used, or this test would prove nothing
    CHECK(c.reused_rows > 0);
  }
}

TEST_CASE("a sphere created in a removed box's slot, at its pose, is tested afresh", "[world][reuse]") {
  // The middle box goes at step 40 and a sphere takes its slot at its exact
  // pose: the same key and the same poses as the box's cached pairs, other
  // shapes. Reusing the box's results would hold the sphere on flat faces.
  Settings settings;
  const Comparison c = compare(settings, 120, [](TestWorld& t, int step) {
    if (step != 40) return;
    const BodyId middle{3, 0};
    const Pose pose = t.world.body(middle).pose;
    REQUIRE(t.world.remove_body(middle));
    BodyDef def;
    def.pose = pose;
    def.shapes.push_back({ShapeType::sphere, {}, 0.5_fx, {}, {}});
    REQUIRE(t.world.create_body(def).value().index == 3);
  });
  CHECK(c.first_difference == 0);
  CHECK(c.reused > 0);
}

TEST_CASE("a box of other friction created in a removed box's slot, at its pose, gets its own friction",
          "[world][reuse]") {
  // The same shape, pose, mass and inertia, so every Jacobian could be
  // reused: only the friction coefficients differ (the rows carry the pair's
  // geometric means, compared through the bodies' coefficients). A steady
  // sideways force of 1.2 times its weight then slides the icy box out of
  // the stack (5.9 m by step 120); with the default box's coefficients its
  // two faces (the two boxes above pressing on it) would hold it, and the
  // stack would stand and keep reusing its rows (it does when the
  // coefficients are left out of the comparison: this test then fails).
  Settings settings;
  const Comparison c = compare(settings, 120, [](TestWorld& t, int step) {
    BodyId middle{3, 0};
    if (step > 40) middle.generation = t.world.bodies()[3].generation;  // the new body's handle
    if (step == 40) make_icy(t, middle, {0.5_fx, 0.5_fx, 0.5_fx});
    if (step > 40) {
      const Fixed weight = 9.81_fx / t.world.body(middle).inverse_mass;
      t.world.apply_force(middle, {weight * 1.2_fx, Fixed{}, Fixed{}}, t.world.body(middle).pose.position);
    }
  });
  CHECK(c.first_difference == 0);
  CHECK(c.reused_rows > 0);
}

TEST_CASE("a standing wall takes its bricks' faces again and keeps the same bits", "[world][reuse]") {
  // With reuse each upper brick's glue_all face is taken again where its
  // support rows were reused (shock_solve.cpp, recall_faces: most of its
  // ~360 faces here); without, every face is measured. At step 40 the
  // middle lower brick becomes icy in its slot at its pose (its rows are
  // built again for their friction), and from step 60 the brick resting on
  // it and the first one is pushed with 0.4 times its weight, more than
  // the icy face's static cone. (The golden replays are the sharper check: a
  // recall that skips the rows' test moves jenga and tables.)
  Settings settings;
  const Comparison c = compare(
      settings, 120,
      [](TestWorld& t, int step) {
        BodyId middle{2, 0};
        if (step > 40) middle.generation = t.world.bodies()[2].generation;
        if (step == 40) make_icy(t, middle, {0.5_fx, 0.25_fx, 0.25_fx});
        if (step >= 60) {
          const BodyId pushed{4, t.world.bodies()[4].generation};
          const Fixed weight = 9.81_fx / t.world.body(pushed).inverse_mass;
          t.world.apply_force(pushed, {weight * 0.4_fx, Fixed{}, Fixed{}}, t.world.body(pushed).pose.position);
        }
      },
      build_wall);
  CHECK(c.first_difference == 0);
  CHECK(c.reused_rows > 0);
}
