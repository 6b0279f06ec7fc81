// The joints' point blocks solved exactly, all at once, where the joints
// join the bodies in trees (chains, ragdolls, bridges anchored at both
// ends): sequential impulses on a 25-link chain holding a 100 kg ball let
// it stretch by 34 cm at 10 iterations (each pass moves an impulse one link
// further); solving K lambda = b for every joint of the tree together holds
// it exactly in one pass.
//
// K = J M^-1 J^T has a 3x3 block per pair of joints that share a movable
// body B: s_i s_j (1/m_B 1 - [r_i]x I_B^-1 [r_j]x), s = -1 where B is the
// joint's body a, +1 where it is b, r the joint's arm on B. A static,
// kinematic or sleeping body couples nothing. Eliminated leaves first (a
// body's joints before the joint that holds it, bodies deepest first in
// the tree), every joint's remaining neighbours share one body, so they
// are coupled already: the block LDL^T factorisation makes no fill-in and
// costs O(joints) 3x3 products (Baraff, "Linear-time dynamics using
// Lagrange multipliers", 1996, in joint space). Where joints close a loop
// among movable bodies there is no such order; those steps fall back to
// sequential impulses, joint by joint. Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "fixed/mat33.h"

namespace bitstep {

struct JointRow;
struct SolverBody;

struct JointTree {
  // Per point block (rows of point and hinge joints), in elimination
  // order: its row, the inverse of its pivot, and its couplings to the
  // blocks eliminated after it (K_{k,i}, row k, column i).
  struct Coupling {
    uint32_t other;  // position in the order
    Mat33 block;
  };
  std::vector<uint32_t> row_of;            // position -> joint row
  std::vector<Mat33> pivot_inverse;        // D_k^-1
  std::vector<uint32_t> couplings_begin;   // position -> its couplings; one past the last at the end
  std::vector<Coupling> couplings;
  bool exact = false;                      // false: loops, or no point blocks
  // Workspace, kept from step to step.
  std::vector<Mat33> pivot;
  std::vector<Vec3> rhs;
  struct AngularRhs {
    Fixed value[2];  // a hinge's angular rows' right-hand side (joint_solver.cpp)
  };
  std::vector<AngularRhs> angular_rhs;
  std::vector<uint32_t> parent, depth, key_order, position_of, body_rows, body_rows_begin, queue;
  std::vector<uint64_t> keys;
  std::vector<Coupling> unsorted;
  std::vector<uint32_t> owner;  // per unsorted coupling: the position it belongs to
};

// The inverse of a symmetric positive definite 3x3 block (a joint's K or a
// pivot of the tree's factorisation) by its LDL^T: six divisions and a
// few dozen products, rounded as they go. inverse() (fixed/mat33.h) is
// exact through big integers and cost ~200,000 instructions a call: 88%
// of a 26-joint chain's step. Where a pivot is not positive (a block that
// rounding left indefinite) it falls back to inverse().
Mat33 inverse_spd(const Mat33& k);

// Orders and factorises the point blocks of `rows` (the bodies' inverse
// masses and inertias, and the rows' arms, as prepare_joint_rows left them).
void factor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree);

// lambda = K^-1 b for the point blocks, b per position in tree.rhs; the
// result overwrites tree.rhs.
void solve_joint_tree(JointTree& tree);

}  // namespace bitstep
