// Joints between bodies 1e2 to 1e7 apart in mass, swung: two heavy boxes
// joined through a light link and flung apart. Point joints: the impulses
// on the link's faces nearly cancel in sum, but last step's, applied one
// joint at a time in the warm start, turned a 10 g die past 2^31 rad/s and
// the checked build aborted (issue 48's sweep: 24 of 32 such cases); the
// warm start is now scaled into range (core/joint_solver.cpp,
// keep_warm_start_in_range). Hinges: the joint tree's pivots came out
// negative from rounding and the chain flew apart at 2 m/s; the tree now
// factorises a scaled K (JointTree::scale). Sliders: block by block a
// light link between two of them slid off along its axis; their blocks are
// now nodes of the tree. These run in both builds; in
// the checked one any overflow aborts. Still open (core/README.md): hinges
// and sliders near their speed limits, and a small body anchored far from
// its joint (a die whose anchor lies 50 of its sizes away); none of these
// cases is run here.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/joint_parts.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

constexpr double g = 9.81;

// x rounded to the nearest Q32.32 value (a test's own numbers).
Fixed fixed_of(double x) { return Fixed::from_raw(std::llround(std::ldexp(x, 32))); }

double energy(const Body& body) {
  if (body.inverse_mass == Fixed{}) return 0;
  const double m = 1.0 / to_double(body.inverse_mass);
  const Vec3 v = body.linear_velocity;
  const Vec3 w = rotate_inverse(body.pose.orientation, body.angular_velocity);
  return 0.5 * m * to_double(dot(v, v)) + 0.5 * to_double(dot(w, body.inertia_local * w)) +
         m * g * to_double(body.pose.position.y);
}

double total_energy(const World& world) {
  double sum = 0;
  for (const Body& body : world.bodies()) sum += energy(body);
  return sum;
}

// A static post; a heavy 10 m box hinged to it about z, flung at `speed`
// (a share across the hinge, which it stops); a die joined under it by
// `type`, and a second heavy box joined under the die, flung the other way.
struct Rig {
  TestWorld t;
  BodyId upper, die, lower;
};

void build_rig(Rig& rig, JointType type, double die_mass, double die_half, double heavy_mass, double speed) {
  TestWorld& t = rig.t;
  BodyDef post;
  post.type = BodyType::static_body;
  post.pose.position = {Fixed{}, 20.0_fx, Fixed{}};
  post.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  const BodyId post_id = t.world.create_body(post).value();
  const Fixed half = fixed_of(die_half);
  const auto box = [&](Fixed y, Fixed h, double mass, Vec3 velocity) {
    BodyDef def;
    def.pose.position = {Fixed{}, y, Fixed{}};
    def.shapes.push_back({ShapeType::box, {h, h, h}, {}, {}, {}});
    def.mass = fixed_of(mass);
    def.linear_velocity = velocity;
    return t.world.create_body(def).value();
  };
  const Fixed v = fixed_of(speed);
  rig.upper = box(14.5_fx, 5.0_fx, heavy_mass, {v * 0.9487_fx, Fixed{}, v * 0.3162_fx});
  rig.die = box(9.5_fx - half, half, die_mass, {});
  rig.lower = box(4.5_fx - half * 2.0_fx, 5.0_fx, heavy_mass, {-v * 0.9806_fx, v * 0.1961_fx, Fixed{}});
  REQUIRE(t.join(JointType::hinge, post_id, rig.upper, {Fixed{}, 19.5_fx, Fixed{}}).ok());
  REQUIRE(t.join(type, rig.upper, rig.die, {Fixed{}, 9.5_fx, Fixed{}}).ok());
  REQUIRE(t.join(type, rig.die, rig.lower, {Fixed{}, 9.5_fx - half * 2.0_fx, Fixed{}}).ok());
}

// The largest gap between any joint's two anchors (m).
double largest_gap(const World& world) {
  double gap = 0;
  for (const Joint& joint : world.joints()) {
    const Vec3 on_a = world.bodies()[joint.body_a].pose.apply(joint.local_anchor_a);
    const Vec3 on_b = world.bodies()[joint.body_b].pose.apply(joint.local_anchor_b);
    gap = std::max(gap, to_double(length(on_b - on_a)));
  }
  return gap;
}

}  // namespace

TEST_CASE("two heavy boxes joined through a light die and flung apart run in range and gain no energy",
          "[joint][range]") {
  for (const double die_mass : {0.01, 0.1}) {
    for (const double die_half : {0.01, 0.05}) {
      for (const double heavy_mass : {1000.0, 100000.0}) {
        for (const double speed_share : {0.5, 0.99}) {
          // 10 m boxes: reach 8.66 m; the speed of each within its limit
          // min(500, 2^28 / (m R)) (core/envelope.h).
          const double speed = speed_share * std::min(500.0, std::ldexp(1.0, 28) / (heavy_mass * 8.67));
          INFO("die " << die_mass << " kg, " << 2 * die_half << " m; boxes " << heavy_mass << " kg at " << speed
                      << " m/s");
          Rig rig;
          build_rig(rig, JointType::point, die_mass, die_half, heavy_mass, speed);
          // The first step takes the blow the joints cannot allow (the
          // boxes' speeds across their joints); from then on the energy
          // may only fall (gravity's work is in it).
          rig.t.world.step();
          const double start = total_energy(rig.t.world);
          double peak = start;
          for (int i = 0; i < 90; ++i) {
            rig.t.world.step();
            peak = std::max(peak, total_energy(rig.t.world));
          }
          INFO("energy after the first step " << start << " J, largest after " << peak << " J");
          CHECK(peak <= start * 1.01);
        }
      }
    }
  }
}

// The joint tree's pivots, formed unscaled, were differences of products
// ~1e7 apart in size: a 1 kg, 10 cm link hinged between two 1,000 kg, 10 m
// boxes got a negative pivot within 14 steps at 2 m/s, its row was dropped
// and the chain flew apart (Release; the checked build aborted). The tree
// now factorises S K S with every diagonal near 1 (JointTree::scale).
TEST_CASE("a light link hinged between two heavy boxes swinging holds them together", "[joint][range][tree]") {
  for (const double die_mass : {10.0, 1.0, 0.1}) {
    for (const double speed : {2.0, 10.0, 50.0}) {
      INFO("link " << die_mass << " kg, 10 cm, between 1,000 kg boxes at " << speed << " m/s");
      Rig rig;
      build_rig(rig, JointType::hinge, die_mass, 0.05, 1000.0, speed);
      rig.t.world.step();
      const double start = total_energy(rig.t.world);
      double peak = start, gap = 0;
      for (int i = 0; i < 300; ++i) {
        rig.t.world.step();
        peak = std::max(peak, total_energy(rig.t.world));
        gap = std::max(gap, largest_gap(rig.t.world));
      }
      INFO("largest anchor gap " << gap * 1000 << " mm; energy after the first step " << start << " J, largest after "
                                 << peak << " J");
      CHECK(gap < 0.002);
      CHECK(peak <= start * 1.01);
    }
  }
}

// How far any slider's b anchor is off a's axis (m).
double largest_off_axis(const World& world) {
  double off = 0;
  for (const Joint& joint : world.joints()) {
    if (!joint.alive || joint.type != JointType::slider) continue;
    const Body& a = world.bodies()[joint.body_a];
    const Body& b = world.bodies()[joint.body_b];
    const Vec3 gap = b.pose.apply(joint.local_anchor_b) - a.pose.apply(joint.local_anchor_a);
    const Vec3 axis = rotate(a.pose.orientation, joint.local_axis_a);
    off = std::max(off, to_double(length(gap - axis * dot(gap, axis))));
  }
  return off;
}

// Sliders solved block by block left a light link between two of them
// converging by ~1% a pass under a 1:100 load: the link turned though
// its slider held it to the post's frame, and pumped by that turn it slid
// off along its free axis (10 kg: 42 m/s within ten seconds of a 0.5 m/s
// nudge; 1 kg: the speed limit). The blocks are now nodes of the joint
// tree, solved with the hinges and points in one exact pass.
TEST_CASE("a light link between two sliders under heavy boxes swinging stays on its axes, gaining no energy",
          "[joint][range][tree][slider]") {
  for (const double die_mass : {10.0, 1.0}) {
    for (const double speed : {0.5, 2.0, 10.0}) {
      INFO("link " << die_mass << " kg, 10 cm, between 1,000 kg boxes at " << speed << " m/s");
      Rig rig;
      build_rig(rig, JointType::slider, die_mass, 0.05, 1000.0, speed);
      rig.t.world.step();
      const double start = total_energy(rig.t.world);
      double peak = start, off = 0, link_speed = 0;
      for (int i = 0; i < 600; ++i) {
        rig.t.world.step();
        peak = std::max(peak, total_energy(rig.t.world));
        off = std::max(off, largest_off_axis(rig.t.world));
        link_speed = std::max(link_speed, to_double(length(rig.t.body(rig.die).linear_velocity)));
      }
      INFO("largest off-axis gap " << off * 1000 << " mm; link's top speed " << link_speed
                                   << " m/s; energy after the first step " << start << " J, largest after " << peak
                                   << " J");
      CHECK(off < 0.002);
      CHECK(link_speed < 2 * speed);
      CHECK(peak <= start * 1.01);
    }
  }
}

TEST_CASE("a joint row's accumulated impulse stays within the bound, bit for bit below it", "[joint][range]") {
  const Fixed bound = max_joint_impulse;
  // Below the bound: the plain sum, and the change made is the change asked.
  Fixed total = 1000.5_fx;
  CHECK(accumulate(total, -250.25_fx) == -250.25_fx);
  CHECK(total == 750.25_fx);
  CHECK(bounded_total(-bound + 1.0_fx, -0.5_fx) == -bound + 0.5_fx);
  // At it: held there, whatever the change, and only what fits is made.
  total = bound - 1.0_fx;
  CHECK(accumulate(total, 5.0_fx) == 1.0_fx);
  CHECK(total == bound);
  for (const Fixed change : {Fixed::max(), Fixed::lowest(), Fixed::from_raw(bound.raw() * 3)}) {
    for (const Fixed start : {bound, -bound, Fixed{}}) {
      const Fixed next = bounded_total(start, change);
      CHECK(next >= -bound);
      CHECK(next <= bound);
      CHECK((change >= Fixed{} ? next >= start : next <= start));  // never against the change
    }
  }
  Vec3 point{bound, -bound, Fixed{}};
  const Vec3 made = accumulate(point, Vec3{Fixed::max(), Fixed::lowest(), 2.0_fx});
  CHECK(made == Vec3{Fixed{}, Fixed{}, 2.0_fx});
  CHECK(point == Vec3{bound, -bound, 2.0_fx});
}
