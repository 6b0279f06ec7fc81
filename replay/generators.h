// Generators for big structures (stack, pyramid, wall, jenga, dominoes,
// tables, thrown cubes, chains, ragdolls). Each is a pure function of its parameters, using
// integer and Fixed arithmetic only, so a scene file that says "wall of 128"
// means the same bodies, bit for bit, everywhere. Bodies are named
// "<name>.<index>" with index 0, 1, ... in creation order. The parameters'
// JSON keys are the field names (replay/README.md); defaults are below.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "replay/scene.h"

namespace bitstep {

// What generated bodies are made of.
struct Substance {
  Material material;
  Fixed density = 1000.0_fx;  // kg/m^3
  Fixed mass;                 // kg per body; 0: from the density (BodyDef::mass)
  bool asleep = false;        // start asleep (when the scene's sleep is on)
};

// Which way a stack's column grows from its first box.
enum class StackDirection : uint8_t { plus_x, minus_x, plus_y, minus_y, plus_z, minus_z };

// Boxes one on another, centred over `position` (the middle of the bottom
// face of the lowest box). Each contact, the ground's included, starts
// overlapped by `overlap` (0: exactly touching; JigLib used the
// allowed penetration, i.e. Settings::penetration_slop). The column grows
// along `direction` (up by default); `half_extents` stay in world axes, so
// the boxes' half height is their half-extent along that axis, and the
// "bottom" face is the one facing against the direction.
struct StackParams {
  std::string name = "stack";
  int count = 10;
  Vec3 half_extents{0.5_fx, 0.5_fx, 0.5_fx};
  Vec3 position;
  Fixed overlap;
  StackDirection direction = StackDirection::plus_y;
  Substance substance;
};
// The boxes' half-extent along the stack's direction.
Fixed stack_half_height(const StackParams& params);
std::vector<SceneBody> generate_stack(const StackParams& params);

// A 2D pyramid in the x-y plane: rows of base, base - 1, ..., 1 boxes, each
// row centred over `position` (the middle of the bottom row's bottom face),
// neighbours `gap` apart along x. base(base + 1)/2 boxes.
struct PyramidParams {
  std::string name = "pyramid";
  int base = 10;
  Vec3 half_extents{0.5_fx, 0.5_fx, 0.5_fx};
  Vec3 position;
  Fixed gap;
  Fixed overlap;
  Substance substance;
};
std::vector<SceneBody> generate_pyramid(const PyramidParams& params);

// A brick wall in the x-y plane in running bond. A triangle wall drops one
// brick per row (rows of base, base - 1, ...: each row sits half a brick
// in from the one below, which is the running bond); `rows` defaults to
// base, base 128 gives 8,256 bricks. A rectangle wall keeps `base` bricks in
// every row and shifts odd rows by half a brick (+x).
enum class WallShape : uint8_t { triangle, rectangle };
struct WallParams {
  std::string name = "wall";
  int base = 16;
  int rows = 0;  // 0: base rows
  WallShape shape = WallShape::triangle;
  Vec3 half_extents{0.25_fx, 0.125_fx, 0.125_fx};
  Vec3 position;
  Fixed gap;
  Fixed overlap;
  Substance substance;
};
std::vector<SceneBody> generate_wall(const WallParams& params);

// A jenga tower: `levels` levels of 3 blocks side by side, alternate levels
// turned 90 degrees about y (done by swapping the x and z half-extents,
// which is exact). `half_extents` is an even level's block: long along x;
// a 3w x w x h block has half-extents [1.5w, h/2, w/2]. The default is a
// real block scaled by 10: 0.75 x 0.15 x 0.25 m.
struct JengaParams {
  std::string name = "jenga";
  int levels = 18;
  Vec3 half_extents{0.375_fx, 0.075_fx, 0.125_fx};
  Vec3 position;
  Fixed overlap;
  Substance substance;
};
std::vector<SceneBody> generate_jenga(const JengaParams& params);

// A row of dominoes standing on the ground. `half_extents` is given for a
// row along x (thin along x); for a row along z the x and z half-extents are
// swapped. `position` is the middle of the first domino's bottom face;
// `spacing` the distance between neighbours' centres. The first domino is
// tipped over its front bottom edge at `push` rad/s (0: not pushed): its
// angular and linear velocities are those of that rotation.
enum class RowDirection : uint8_t { plus_x, minus_x, plus_z, minus_z };
struct DominoParams {
  std::string name = "dominoes";
  int count = 32;
  Vec3 half_extents{0.1_fx, 1.0_fx, 0.5_fx};
  Fixed spacing = 1.0_fx;
  Vec3 position;
  RowDirection direction = RowDirection::plus_x;
  Fixed push;
  Substance substance;
};
std::vector<SceneBody> generate_dominoes(const DominoParams& params);

// Tables stacked on one another, each ONE compound body: a top box and four
// leg boxes at the corners under it, as shapes with local poses. `position`
// is the middle of the lowest table's footprint on the ground.
struct TableParams {
  std::string name = "tables";
  int count = 5;
  Vec3 top_half_extents{0.6_fx, 0.05_fx, 0.4_fx};
  Vec3 leg_half_extents{0.05_fx, 0.35_fx, 0.05_fx};
  Vec3 position;
  Substance substance;
};
std::vector<SceneBody> generate_tables(const TableParams& params);

// Bodies at seeded random positions in the box position +- spread, with
// random orientations, flying toward `target` at `speed`. SplitMix64
// (fixed/splitmix64.h) draws raw Q32.32 fractions; a draw that would
// overlap an earlier body (bounding spheres) is redrawn, up to 1000 times.
// `shapes` cycles through the given kinds (box, sphere, capsule).
struct ThrowParams {
  std::string name = "throw";
  int count = 50;
  uint64_t seed = 1;
  Vec3 position{Fixed{}, 5.0_fx, Fixed{}};
  Vec3 spread{2.0_fx, 2.0_fx, 2.0_fx};
  Vec3 target;
  Fixed speed = 10.0_fx;
  std::vector<ShapeType> shapes{ShapeType::box};
  Vec3 half_extents{0.25_fx, 0.25_fx, 0.25_fx};  // boxes
  Fixed radius = 0.25_fx;                         // spheres and capsules
  Fixed half_height = 0.25_fx;                    // capsules
  Substance substance;
};
struct ThrowResult {
  std::vector<SceneBody> bodies;
  bool placed_all = true;  // false when a body found no free spot in the region
};
ThrowResult generate_throw(const ThrowParams& params);

// A chain of `count` links, box or sphere, their centres following each
// other along `direction` (made unit) from `position` (the first link's
// centre), `gap` apart surface to surface along it. Consecutive links are
// joined at the middle of the gap between them (a point joint, or a hinge
// about `axis`, world frame). An anchored end is joined by a point joint,
// at the middle of the same gap, to a static box of half extents 0.05
// just beyond the end link: "<name>.anchor0" before the first link,
// "<name>.anchor1" after the last. Box links keep world axes; a box's
// extent along the direction is its support distance, |d.x| h.x + |d.y|
// h.y + |d.z| h.z.
//
// Bodies: the links "<name>.0" .. "<name>.<count - 1>", then the anchors.
// Joints, in creation order: "<name>.joint<k>" joins link k - 1 (anchor0
// for k = 0) to link k (anchor1 for k = count); k runs 0..count when both
// ends are anchored, 1..count - 1 when none is.
enum class ChainLink : uint8_t { box, sphere };
enum class ChainAnchoring : uint8_t { none, first, both };
struct ChainParams {
  std::string name = "chain";
  int count = 10;
  ChainLink link = ChainLink::box;
  Vec3 half_extents{0.1_fx, 0.25_fx, 0.1_fx};  // box links
  Fixed radius = 0.2_fx;                        // sphere links
  Fixed gap;                                    // m, between consecutive links' surfaces
  Vec3 position;
  Vec3 direction{Fixed{}, -Fixed::one(), Fixed{}};  // hanging down
  ChainAnchoring anchored = ChainAnchoring::first;
  JointType joint = JointType::point;  // point or hinge
  Vec3 axis{Fixed{}, Fixed{}, Fixed::one()};  // hinge
  Substance substance;
};
// A generator's bodies and the joints between them; a joint's body_a and
// body_b index `bodies` (the scene adds the index of the first body).
struct GeneratedStructure {
  std::vector<SceneBody> bodies;
  std::vector<SceneJoint> joints;
};
GeneratedStructure generate_chain(const ChainParams& params);

// N m at scale 1: enough to stop a limb swinging on its own (a head hanging
// at its swing limit circled the cone for 10 s without it), far below what
// holds a limb up against gravity (~3 N m for a forearm held level).
inline constexpr Fixed ragdoll_joint_friction = 1.0_fx;
// Solver passes of a ragdoll's island (core/island_passes.h). Its limbs'
// contacts are sequential impulses against joints solved exactly: a
// contact row sees a limb's own mass, the joints spread the push over the
// whole body, and the two converge over passes. Over 96 heaps of
// ragdolls.json (ragdolls moved by up to 3 cm), the world's 10 and 4 ->
// 30 and 12: the median heap asleep at step 423 -> 303 (14 -> 1 awake at
// 10 s), median deepest overlap at 10 s 2.7 -> 0.41 mm (before the joints'
// projection after the integration, core/joint_projection.h).
inline constexpr uint16_t ragdoll_velocity_iterations = 30;
inline constexpr uint16_t ragdoll_position_iterations = 12;

// Ragdolls: `count` humans of 11 parts joined by 10 joints, standing upright
// along +y and facing +z (their left is +x) unless `orientation` turns the
// whole body (e.g. 90 degrees about x: lying on the back). `position` is the
// first ragdoll's pelvis centre, ragdoll k's is position + k spacing (world
// frame). At scale 1 a ragdoll is 1.785 m tall (the pelvis centre 1.05 m
// above the soles) and weighs 75 kg; lengths scale with `scale`, masses
// with its cube. Proportions and masses: ragdoll_parts() in generators.cpp
// (Winter's anthropometric table). Parts are 1 cm (times the scale) apart
// where they meet, with the joint's anchor in the middle of the gap, and
// at least 1 cm apart elsewhere: nothing overlaps at creation.
//
// Bodies of ragdoll k, in creation order: "<name>.<k>.pelvis" (box),
// ".chest" (box), ".head" (sphere), ".upper_arm.l", ".forearm.l",
// ".upper_arm.r", ".forearm.r", ".thigh.l", ".shin.l", ".thigh.r",
// ".shin.r" (capsules along the limb; the forearm includes the hand, the
// shin the foot). Joints, in creation order, each from the part nearer the
// pelvis (a) to the next (b): ".waist" (pelvis-chest: cone about +y, swing
// 30, twist +-30 degrees), ".neck" (chest-head: cone about +y, 40, +-60),
// ".shoulder.l" (chest-upper arm: cone down the arm, 80, +-60), ".elbow.l"
// (hinge about -x, 0..140: the forearm bends forward only), ".shoulder.r",
// ".elbow.r", ".hip.l" (pelvis-thigh: cone down the leg, 70, +-30),
// ".knee.l" (hinge about +x, 0..140: the shin bends backward only),
// ".hip.r", ".knee.r". Axes and anchors turn with `orientation`.
struct RagdollParams {
  std::string name = "ragdoll";
  int count = 1;
  Vec3 position;                           // the first ragdoll's pelvis centre
  Vec3 spacing{Fixed{}, 2.5_fx, Fixed{}};  // from one ragdoll to the next: stacked
  Fixed scale = Fixed::one();              // 1: 1.8 m, 75 kg
  Quat orientation;                        // identity: standing upright along +y, facing +z (unit)
  Material material;
  bool asleep = true;  // as JigLib's ragdolls (when the scene's sleep is on)
  // 1/s, every part's: a limb hanging free swings on joints without
  // friction (Bullet's ragdoll demo damps its parts 0.05 and 0.85).
  Fixed linear_damping;
  Fixed angular_damping;
  // N m at scale 1 (x scale^4: torques go as mass x length): every joint's
  // friction_torque.
  Fixed joint_friction = ragdoll_joint_friction;
  // Every joint's solver passes (JointDef::velocity_iterations,
  // position_iterations): a ragdoll's island runs at least these.
  uint16_t velocity_iterations = ragdoll_velocity_iterations;
  uint16_t position_iterations = ragdoll_position_iterations;
};
inline constexpr int ragdoll_parts_count = 11;
inline constexpr int ragdoll_joints_count = 10;
// 11 count bodies and 10 count joints, joint bodies indexing `bodies`.
GeneratedStructure generate_ragdoll(const RagdollParams& params);

}  // namespace bitstep
