// The joints' equality rows solved exactly, all at once, where the joints
// join the bodies in trees (chains, ragdolls, bridges anchored at both
// ends): sequential impulses on a long chain holding a heavy ball let it
// stretch (each pass moves an impulse one link further); solving
// K lambda = b for every joint of the tree together holds it exactly in one
// pass (tests/core/joint_tests.cpp: a 25-link chain holding a 100 kg ball
// stretches less than 2 cm at 10 iterations).
//
// Each joint is one node of up to six rows (JointRow::tree_axes): its point
// block (3), a hinge's two angular rows, and the swing and twist limits that
// are engaged this step; or a slider's block (two rows across its axis,
// three angular) and its limit where engaged. Each row is a Jacobian (linear and angular parts
// on each body). K = J M^-1 J^T has a block per pair of joints that share a
// movable body B, entry (p, q) = l_p . l_q / m_B + w_p . I_B^-1 w_q for
// their rows' parts l, w on B. A static, kinematic or sleeping body couples
// nothing. Eliminated leaves first (a body's joints before the joint that
// holds it, bodies deepest first in the tree), every joint's remaining
// neighbours share one body, so they are coupled already: the block LDL^T
// factorisation makes no fill-in and costs O(joints) block products
// (Baraff, "Linear-time dynamics using Lagrange multipliers", 1996, in
// joint space). Where joints close a loop among movable bodies there is no
// such order; those steps fall back to sequential impulses, joint by joint.
// Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "fixed/mat33.h"

namespace bitstep {

struct JointRow;
struct SolverBody;

// One row of a joint in the tree solve: J v = linear . (v_b - v_a) +
// angular_b . w_b + angular_a . w_a. A point block's row k has linear e_k,
// an angular row none, a slider's rows across its axis (and its limit's
// along it) a unit normal of their own.
struct TreeAxis {
  Vec3 angular_a, angular_b;
  Vec3 linear;
};

constexpr int max_tree_axes = 6;

// An n x m block (n, m <= 6) of K or of its factorisation, and a node's
// column of values.
struct Block {
  Fixed at[max_tree_axes][max_tree_axes];
};
struct Column {
  Fixed at[max_tree_axes];
};

struct JointTree {
  // Per joint (node), in elimination order: its row, its number of rows,
  // the inverse of its pivot, and its couplings to the nodes eliminated
  // after it (K_{k,i}: node k's rows by node i's).
  struct Coupling {
    uint32_t other;  // position in the order
    Block block;             // K_{k,i}
    Block block_transposed;  // K_{i,k}, for the forward pass
    // How K_{k,i} was formed, to form it again (refactor_joint_tree):
    // coupling(body, rows[first], rows[second]), transposed when swapped.
    uint32_t body, first, second;
    bool swapped;
  };
  std::vector<uint32_t> row_of;            // position -> joint row
  std::vector<uint8_t> size;               // position -> its rows
  std::vector<Block> pivot_inverse;        // D_k^-1
  std::vector<Column> floor;               // per row of D_k: the pivot at or below which it is dependent
  // Per position, each row's scale: the tree factorises S K S (S =
  // diag(2^exponent), K_ii of every row brought to 0.5..4) and solves S K S
  // y = S b, lambda = S y. Unscaled, a 1 kg, 10 cm link hinged between two
  // 1,000 kg, 10 m boxes (I^-1 600 against 6e-5) left its Schur complements
  // ~6e-5 as differences of ~600-sized products, within rounding of 0: a
  // pivot came out negative, its row was dropped and the chain flew apart.
  // Powers of two scale exactly, and every pivot is then formed
  // to ~2^-30 of its size.
  struct RowScales {
    int8_t exponent[max_tree_axes];
  };
  std::vector<RowScales> scale;
  std::vector<uint32_t> couplings_begin;   // position -> its couplings; one past the last at the end
  std::vector<Coupling> couplings;
  bool exact = false;                      // false: loops, or no joints with a point block
  // Per position, the lowest position of its tree (joints coupled through
  // movable bodies); per joint row, its swing and limit rows in the tree
  // (bit 1, bit 2) when last factorised.
  std::vector<uint32_t> component;
  std::vector<uint32_t> holds_to_immovable;  // per tree (at its lowest position): its joints to immovable bodies
  std::vector<uint8_t> holds;
  // Workspace, kept from step to step.
  std::vector<Block> pivot;
  std::vector<Column> rhs;
  std::vector<Fixed> residual;  // per tree (at its lowest position): the largest |rhs| (joint_solver.cpp)
  std::vector<uint32_t> parent, depth, position_of, body_rows, body_rows_begin, queue;
  std::vector<Coupling> unsorted;
  std::vector<uint32_t> owner;  // per unsorted coupling: the position it belongs to
  std::vector<uint8_t> dirty;   // per position, while refactoring
};

// The inverse of a symmetric positive definite 3x3 block (a joint's K) by
// its LDL^T: six divisions and a few dozen products, rounded as they go.
// inverse() (fixed/mat33.h) is exact through big integers, and so slow that
// it would take most of a chain's step. Where a pivot is not
// positive (a block that rounding left indefinite) it falls back to
// inverse().
Mat33 inverse_spd(const Mat33& k);

// The same for an n x n block (n <= 6). A pivot that is not positive (rows
// that depend on the others, as rounding may leave them) drops its row: it
// gets no impulse.
Block inverse_spd(const Block& k, int n);

// The same where row j's pivot at or below floor.at[j] drops it: the tree's
// pivots, whose rows may depend on other joints' (two joints between the
// same two bodies: two pins of a door, a pin on a hinge's axis, the same
// joint twice), their dependence left a few raw units from 0 by rounding
// (inverted, such a pivot aborted the checked build). Its rows then hold
// with the other joints' impulses alone.
Block inverse_spd(const Block& k, int n, const Column& floor);

// Orders and factorises the joints of `rows` (the bodies' inverse masses
// and inertias, and the rows' axes, as prepare_joint_rows left them).
void factor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree);

// The same within a solve after swing or limit rows joined or left the
// tree (nothing else a factorisation is made from changes in a solve: the
// bodies' inverse masses and inertias, the rows' axes, which rows have a
// point block). Only the trees holding such a row are factorised again: in
// a block LDL^T a tree's pivots and factors depend on its own joints alone,
// so the others' are the bits they were (in a scene of several ragdolls a
// refactorisation is one ragdoll's, not the whole scene's).
void refactor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree);

// lambda = K^-1 b, b per position in `b`; the result overwrites it.
void solve_joint_tree(JointTree& tree, std::vector<Column>& b);

}  // namespace bitstep
