// The joints' rows in a solve (core/joint.h), made of the same constraint
// parts as the contacts' (solver_rows.h): built once per solve, warm-started
// with last step's impulses, solved after the contacts in every velocity
// iteration (before them in the soft step's passes), and their drift pushed
// out in the position passes (the split impulse: pseudo-velocities that move
// the bodies but add no momentum), or by a Baumgarte bias when the scene
// asks for it. Internal to core/.
#pragma once

#include <vector>

#include "core/joint.h"
#include "core/joint_tree.h"
#include "core/settings.h"
#include "core/solver_rows.h"

namespace bitstep {

// One joint in a solve. Point and hinge joints: a 3x3 block keeps the two
// anchors together (after Jolt's PointConstraintPart: the impulse that
// stops their relative velocity in all three directions at once, through
// K^-1, K = (1/m_a + 1/m_b) 1 - [r_a]x I_a^-1 [r_a]x - [r_b]x I_b^-1 [r_b]x).
// Hinge: two angular parts about axes normal to a's hinge axis keep b's
// axis on it, and a limit row about the axis. Rope: one axis part along the
// anchors' line, pulling only.
struct JointRow {
  uint32_t a = 0, b = 0;
  Joint* joint = nullptr;
  // The joint has a point block (point, hinge, cone: a node of the tree
  // solve), and a hinge's two angular rows go with it.
  bool has_point_block = false, hinge_rows_in_tree = false;
  // A slider's block is a node of the tree solve instead (its five rows,
  // and its limit's where engaged).
  bool slide_rows_in_tree = false;
  bool is_tree_node() const { return has_point_block || slide_rows_in_tree; }
  Vec3 ra, rb;              // m: the anchors from the centres of mass, world frame
  Mat33 point_k;            // K
  Mat33 point_mass;         // K^-1
  Vec3 point_target;        // m/s: Baumgarte's bias (zero with the split impulse)
  Vec3 point_push_target;   // m/s: the split impulse's rate toward closing the gap
  Jacobian rope;            // max_distance: along the line from a's anchor to b's
  Fixed rope_target;        // m/s: the closing rate the rope allows (its slack over dt) or asks
  Fixed rope_push_target;
  bool rope_active = false;
  // Hinge: angular rows (w_b - w_a) . p_k, p_k normal to the axis, and the
  // limit's about the axis. Each goes with the point impulse that keeps
  // the anchors' rate as it was (`anchor`, per unit of its impulse) and
  // has the effective mass of the pair (`mass`, below the part's own), so
  // turning a body about the hinge does not pull the anchors apart: an
  // arm's limit row alone would take the arm's inertia about its centre,
  // the point row then turn it about the pivot, and under a strong torque
  // the two would pass the arm back and forth degrees past its limit
  // (tests/core/joint_tests.cpp: driven by 1,000 N m it passes by at most
  // 1 degree).
  AngularPart hinge[2];
  Vec3 hinge_anchor[2];
  Fixed hinge_mass[2];
  // In the tree solve (joint_tree.h) a joint is one node of tree_size
  // rows: the point block, a hinge's two angular rows, then the swing and
  // the twist limit where they are engaged this step (swing_in_tree,
  // limit_in_tree). Row by row, the point block turns an arm back after
  // the angular rows stopped it (a blow at an arm's tip tilts its axis by
  // degrees); a ragdoll's limits, solved row by row against the tree's
  // points, are passed by tens of degrees in a pile: the twist of an upper
  // arm (0.002 kg m^2 about its axis) is tied to the forearm's swing by the
  // elbow's rows, and sequential impulses between the two converge slowly.
  TreeAxis tree_axes[max_tree_axes];
  uint8_t tree_size = 0;
  bool swing_in_tree = false, limit_in_tree = false;
  bool released = false;  // a row left the tree this step (joint_solver.cpp: release_pulling_rows)
  Fixed hinge_target[2], hinge_push_target[2];
  bool swing_active = false;  // cone: hinge[0] is the swing row (one-sided), the limit the twist's
  AngularPart limit;        // (w_b - w_a) . axis
  Vec3 limit_anchor;
  Fixed limit_mass;
  Fixed limit_target, limit_push_target;
  int limit_side = 0;       // +1: at the lower limit (impulse >= 0), -1: at the upper (<= 0), 0: none
  // Friction against b turning relative to a (Joint::friction_torque),
  // solved in the velocity iterations only, from zero each step (not
  // warm-started: no state): a hinge's about its axis (friction_hinge),
  // a point or cone joint's about every axis at once, M = (I_a^-1 +
  // I_b^-1)^-1, its impulse's length at most friction_torque dt.
  bool friction = false;
  Fixed friction_max;  // N m s: friction_torque dt
  AngularPart friction_hinge;
  Mat33 friction_mass;
  Vec3 friction_impulse;  // a hinge's in x
  // A motor (Joint::motor_speed, motor_max): a hinge's row about its axis,
  // paired with the point impulse (motor_turn, motor_anchor, motor_mass),
  // a slider's its axis row (slide_axis); its impulse within motor_limit
  // (motor_max dt) either way. Velocity only, row by row.
  bool motor = false;
  Fixed motor_limit;  // N m s or N s
  AngularPart motor_turn;
  Vec3 motor_anchor;
  Fixed motor_mass;
  // Slider (joint_slider.cpp): one block of five rows solved at once,
  // lambda = K^-1 (target - J v): two linear rows across the axis (n_k .
  // the anchors' gap) and three angular rows (w_b - w_a) . e_k about the
  // world axes, K = J M^-1 J^T (5x5, slide_mass its inverse); and its axis
  // row (the translation's rate: the limit, the motor and friction),
  // paired with the block impulse that keeps the block's rates
  // (slide_axis_anchor per unit of its impulse; slide_axis_mass the
  // pair's effective mass, the Schur complement).
  Jacobian slide[5];
  Block slide_mass;
  Fixed slide_target[5], slide_push_target[5];
  Jacobian slide_axis;
  Fixed slide_axis_anchor[5];
  Fixed slide_axis_mass;
  // The passes its island runs beyond the world's (island_passes.h).
  uint16_t extra_velocity_passes = 0, extra_position_passes = 0;
  // The tree alone holds its island (tree_islands.h): once a pass finds
  // its tree's residual within tree_residual_tolerance on a rate, it takes
  // part in no later pass on that rate (velocity_held, push_held).
  bool tree_island = false;
  bool velocity_held = false, push_held = false;
  // Split impulses, this solve's only.
  Vec3 point_push_impulse;
  Fixed rope_push_impulse, hinge_push_impulse[2], limit_push_impulse;
  Vec3 angular_push_impulse;
  Fixed motor_push_impulse;  // always 0: a motor pushes nothing
};

// Rows for every live joint with an awake dynamic body, in joint order.
void build_joint_rows(const Settings& settings, const std::vector<Body>& bodies, std::vector<Joint>& joints,
                      const std::vector<SolverBody>& solver_bodies, std::vector<JointRow>& rows);
// The same, and their point blocks' tree factorised (joint_tree.h).
void prepare_joint_rows(const Settings& settings, const std::vector<Body>& bodies, std::vector<Joint>& joints,
                        const std::vector<SolverBody>& solver_bodies, std::vector<JointRow>& rows, JointTree& tree);
void warm_start_joints(std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows);
// One velocity iteration over the joints: ropes, limits and hinge axes
// row by row, then every point block at once (the tree solve), or block by
// block where the joints close a loop. extra_pass >= 0: one of the passes
// beyond the world's (core/island_passes.h), over the joints whose island
// runs more than extra_pass of them; the others are left as they are.
// A held row (velocity_held) takes part in no pass.
void solve_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass = -1);
// One position pass over the joints (on the push rates), likewise. Whether
// any row has something to push.
void push_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass = -1);
bool joints_to_push(const std::vector<JointRow>& rows);

// The angle of b's reference vector about the hinge axis, from a's (rad,
// -pi..pi): 0 at creation. For a cone, the twist: b's reference projected
// onto the plane normal to a's axis first.
Fixed hinge_angle(const Joint& joint, const Body& a, const Body& b);
// A cone's twist (joint_cone.cpp).
Fixed twist_angle(const Joint& joint, const Body& a, const Body& b);
// A slider's translation: b's anchor from a's along a's axis (m), 0 at
// creation (joint_slider.cpp).
Fixed slider_translation(const Joint& joint, const Body& a, const Body& b);
// A cone's swing: the angle between its two bodies' copies of the axis (rad, 0..pi).
Fixed swing_angle(const Joint& joint, const Body& a, const Body& b);

// Whether the joint's impulse this step went past its break_impulse.
bool over_break_impulse(const Joint& joint);

}  // namespace bitstep
