// Each joint type's behaviour, one file per type, behind one checked
// switch (with_joint_type): a type is a struct of the same static
// functions, and a JointType without its case is a -Wswitch error (no
// `default:`), so a new type cannot silently act as another. A new type:
// its enum value (joint.h), its struct here and its file, its case below,
// and its keys in the scene reader and the state description
// (replay/scene.cpp, replay/state_description.h: switches of their own).
//
// The functions each type has:
//   validate(def)       the type's checks of a JointDef (World::create_joint,
//                       after the ones every type shares): refused with
//                       the field and why, or fine
//   check_motor(speed, max)
//                       the type's check of motor settings (a JointDef's,
//                       World::set_joint_motor's): refused, or fine
//   anchor_b(def)       the world point joined on b (def.anchor_a or def.anchor_b)
//   make_frames(def, a, b, joint)
//                       the type's part of a new Joint: its axes, references
//                       and limits in each body's frame
//   prepare(setup, row) the joint's rows for one solve (joint_parts.h)
//   warm_start(sa, sb, row)
//                       last step's impulses, applied to the velocities
//   solve_rows(sa, sb, a, b, row, target, impulse, in_tree)
//                       one pass of its rows on one rate (velocity or push),
//                       row by row; in_tree: without those the tree solve
//                       takes (joint_tree.h)
//   solve_friction(sa, sb, a, b, row)
//                       its friction on the velocities (where row.friction)
//   breaks(joint)       whether its impulse this step passed break_impulse
//   tree_alone(row)     whether the tree solve takes all its rows this step
//                       (an exact tree: solve_rows with in_tree does nothing;
//                       friction is the caller's test), tree_islands.h
//   position_error(joint, a, b)
//                       a bound of what its position rows would close at
//                       the bodies' poses (m or rad; Fixed::max() where the
//                       type does not measure it cheaply), joint_projection.cpp
// Internal to core/.
#pragma once

#include <cstdlib>

#include "core/joint_parts.h"

namespace bitstep {

#define BITSTEP_JOINT_TYPE_FUNCTIONS                                                                                 \
  static Result<void> validate(const JointDef& def);                                                                 \
  static Result<void> check_motor(Fixed speed, Fixed max);                                                           \
  static const Vec3& anchor_b(const JointDef& def);                                                                  \
  static void make_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint);                          \
  static void prepare(const JointSetup& setup, JointRow& row);                                                       \
  static void warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row);                                       \
  static void solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row,      \
                         const Targets& target, Impulses impulse, bool in_tree);                                     \
  static void solve_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row); \
  static bool breaks(const Joint& joint);                                                                            \
  static bool tree_alone(const JointRow& row);                                                                       \
  static Fixed position_error(const Joint& joint, const Body& a, const Body& b);

// Ball and socket (joint_point.cpp).
struct PointJoint {
  BITSTEP_JOINT_TYPE_FUNCTIONS
};
// A rope (joint_rope.cpp).
struct RopeJoint {
  BITSTEP_JOINT_TYPE_FUNCTIONS
};
// A hinge (joint_hinge.cpp).
struct HingeJoint {
  BITSTEP_JOINT_TYPE_FUNCTIONS
};
// A shoulder or hip (joint_cone.cpp).
struct ConeJoint {
  BITSTEP_JOINT_TYPE_FUNCTIONS
};
// Prismatic (joint_slider.cpp).
struct SliderJoint {
  BITSTEP_JOINT_TYPE_FUNCTIONS
};

#undef BITSTEP_JOINT_TYPE_FUNCTIONS

// Calls f with the struct of `type` (f(HingeJoint{}) for a hinge).
template <class F>
decltype(auto) with_joint_type(JointType type, F&& f) {
  switch (type) {
    case JointType::point: return f(PointJoint{});
    case JointType::max_distance: return f(RopeJoint{});
    case JointType::hinge: return f(HingeJoint{});
    case JointType::cone: return f(ConeJoint{});
    case JointType::slider: return f(SliderJoint{});
  }
  std::abort();  // never: World::create_joint and the state reader take JointType's values only
}

// Whether `type` is one of JointType's values (World::create_joint checks
// it before anything dispatches on it).
inline bool is_joint_type(JointType type) {
  switch (type) {
    case JointType::point:
    case JointType::max_distance:
    case JointType::hinge:
    case JointType::cone:
    case JointType::slider: return true;
  }
  return false;
}

// The angle limits' range check (hinges, cones; and any joint whose def
// sets `limited`): refused ("limits"), or fine.
Result<void> check_angle_limits(const JointDef& def);

}  // namespace bitstep
