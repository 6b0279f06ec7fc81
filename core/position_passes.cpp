#include "core/position_passes.h"

#include "core/islands.h"
#include "core/settings.h"
#include "core/shock_levels.h"

namespace bitstep {

namespace {

// Sweeps alternate direction every pass, so no point of a symmetric stack
// is always solved last (a remedy against drift from the engines bitstep
// follows: Kenwright's simple impulse engine, JigLib).
template <class Solve>
void sweep(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows, int pass, Solve solve) {
  if (pass % 2 == 0) {
    for (const PointRow& row : rows) solve(bodies[row.a], bodies[row.b], row);
  } else {
    for (auto it = rows.rbegin(); it != rows.rend(); ++it) solve(bodies[it->a], bodies[it->b], *it);
  }
}


// The last position pass pushes the contacts of jointed bodies one way.
// The position passes end with the joints' exact push, so a limb pressed
// into a box, or a box lying on a limb, would be pushed apart at the mass
// ratio and pulled back by its joints in every pass, and ragdoll heaps
// would keep limbs millimetres deep in boxes and each other. The shock
// step, which settles such mass ratios for the velocities, leaves jointed
// bodies alone (shock.h). Here, as in its passes (after Guendelman, Bridson
// and Fedkiw, whose shock propagation is their last pass), a contact
// between two movable bodies, at least one of them jointed and not both of
// one joint tree, whose normal lies within 60 degrees of up has the lower
// body stand still for the upper one, which is pushed out alone. Only in
// the last pass: one-way pushes in every pass leave shallower overlaps but
// keep more heaps awake. Rows of bodies no joint holds are pushed both
// ways, as in the other passes.
void one_way_pushes(const Settings& settings, const std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                    const std::vector<JointRow>& joint_rows, std::vector<uint8_t>& jointed,
                    std::vector<uint32_t>& tree, std::vector<OneWayPush>& out) {
  out.clear();
  if (joint_rows.empty() || settings.gravity == Vec3{}) return;
  // Which movable bodies a joint holds, and their trees: joined through
  // movable bodies (an immovable body joins no two trees).
  jointed.assign(bodies.size(), 0);
  tree.resize(bodies.size());
  for (uint32_t i = 0; i < tree.size(); ++i) tree[i] = i;
  for (const JointRow& row : joint_rows) {
    const bool a = !immovable(bodies[row.a]), b = !immovable(bodies[row.b]);
    jointed[row.a] |= a ? 1 : 0;
    jointed[row.b] |= b ? 1 : 0;
    if (a && b) unite(tree, row.a, row.b);
  }
  const SupportTest holds_up(settings.gravity);
  // 1 / (d . d / m + (r x d) . I^-1 (r x d)) for one side of row j.
  const auto one_side_mass = [](const Vec3& direction, const Vec3& linear, const Vec3& arm, const Vec3& turn) {
    const Fixed k = dot(direction, linear) + dot(arm, turn);
    return k > Fixed{} ? Fixed::one() / k : Fixed{};
  };
  for (uint32_t r = 0; r < rows.size(); ++r) {
    const PointRow& row = rows[r];
    if (immovable(bodies[row.a]) || immovable(bodies[row.b])) continue;  // one way already
    if (!jointed[row.a] && !jointed[row.b]) continue;
    // Two bodies of one tree (a ragdoll's forearm under its own pelvis):
    // its joints' exact push would undo the one-way push each step, and the
    // forearm would stay inside.
    if (jointed[row.a] && jointed[row.b] && find_root(tree, row.a) == find_root(tree, row.b)) continue;
    const Jacobian& j = row.normal;
    if (holds_up(j.direction)) {
      out.push_back({r, true, one_side_mass(j.direction, j.linear_b, j.arm_b, j.turn_b)});
    } else if (holds_up(-j.direction)) {
      out.push_back({r, false, one_side_mass(j.direction, j.linear_a, j.arm_a, j.turn_a)});
    }
  }
}

// The last position pass: every row, the one-way ones (by row, in
// `one_way`) pushing the upper body alone, in the pass's direction.
void sweep_last_push(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                     const std::vector<OneWayPush>& one_way, int pass) {
  const size_t n = rows.size();
  size_t next = pass % 2 == 0 ? 0 : one_way.size();  // one_way is in row order
  for (size_t k = 0; k < n; ++k) {
    const size_t i = pass % 2 == 0 ? k : n - 1 - k;
    const PointRow& row = rows[i];
    if (pass % 2 == 0 && next < one_way.size() && one_way[next].row == i) {
      solve_push_one_way(bodies[row.a], bodies[row.b], row, one_way[next++]);
    } else if (pass % 2 != 0 && next > 0 && one_way[next - 1].row == i) {
      solve_push_one_way(bodies[row.a], bodies[row.b], row, one_way[--next]);
    } else {
      solve_push(bodies[row.a], bodies[row.b], row);
    }
  }
}

}  // namespace

void push_apart(const Settings& settings, std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                std::vector<JointRow>& joint_rows, JointTree& tree, const IslandPasses& island_passes,
                PositionScratch& scratch) {
  one_way_pushes(settings, bodies, rows, joint_rows, scratch.jointed, scratch.joint_trees, scratch.one_way);
  run_extra_position_passes(bodies, rows, joint_rows, tree, island_passes);
  for (int pass = 0; pass < settings.position_iterations; ++pass) {
    // The joints last: contacts pushed after them press ragdoll limbs
    // past their limits (an elbow held degrees past for a second in a
    // pile) and leave deeper overlaps.
    if (pass + 1 == settings.position_iterations && !scratch.one_way.empty()) {
      sweep_last_push(bodies, rows, scratch.one_way, pass);
    } else {
      sweep(bodies, rows, pass, solve_push);
    }
    push_joints(bodies, joint_rows, tree);
  }
}

}  // namespace bitstep
