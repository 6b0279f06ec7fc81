#include "core/island_passes.h"

#include <algorithm>

#include "core/row_islands.h"
#include "core/joint_solver.h"
#include "core/settings.h"
#include "core/solver_rows.h"

namespace bitstep {

namespace {

// A joint's ask beyond the world's count (0 asks nothing).
uint16_t beyond(uint16_t asked, int world) {
  return asked > world ? static_cast<uint16_t>(asked - world) : uint16_t{0};
}

}  // namespace

void plan_island_passes(const Settings& settings, const std::vector<SolverBody>& bodies,
                        const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifold_rows,
                        std::vector<JointRow>& joint_rows, IslandPasses& out) {
  out.manifolds.clear();
  out.free_rows.clear();
  out.push_rows.clear();
  out.most_velocity = out.most_position = 0;
  bool asks = false;
  for (JointRow& row : joint_rows) {
    row.extra_velocity_passes = row.extra_position_passes = 0;
    asks = asks || beyond(row.joint->velocity_iterations, settings.velocity_iterations) > 0 ||
           beyond(row.joint->position_iterations, settings.position_iterations) > 0;
  }
  if (!asks) return;
  // The islands, through every contact row and joint between two movable
  // bodies (not the tyres).
  std::vector<uint32_t>& parent = out.parent;
  unite_rows(bodies, manifold_rows, joint_rows, nullptr, parent);
  // Each island's extras: the most any of its joints asks.
  out.root_velocity.assign(bodies.size(), 0);
  out.root_position.assign(bodies.size(), 0);
  const auto root_of = [&](uint32_t a, uint32_t b) { return row_island(bodies, parent, a, b); };
  for (const JointRow& row : joint_rows) {
    const uint32_t root = root_of(row.a, row.b);
    out.root_velocity[root] =
        std::max(out.root_velocity[root], beyond(row.joint->velocity_iterations, settings.velocity_iterations));
    out.root_position[root] =
        std::max(out.root_position[root], beyond(row.joint->position_iterations, settings.position_iterations));
  }
  for (JointRow& row : joint_rows) {
    const uint32_t root = root_of(row.a, row.b);
    row.extra_velocity_passes = out.root_velocity[root];
    row.extra_position_passes = out.root_position[root];
    out.most_velocity = std::max<int>(out.most_velocity, row.extra_velocity_passes);
    out.most_position = std::max<int>(out.most_position, row.extra_position_passes);
  }
  // Every row touches a movable body (contact_rows.cpp builds no other).
  for (uint32_t i = 0; i < manifold_rows.size(); ++i) {
    const uint16_t extra = out.root_velocity[root_of(manifold_rows[i].a, manifold_rows[i].b)];
    if (extra > 0) out.manifolds.push_back({i, extra});
  }
  for (uint32_t i = 0; i < rows.size(); ++i) {
    const uint32_t root = root_of(rows[i].a, rows[i].b);
    if (out.root_velocity[root] > 0 && is_free_row(rows[i])) out.free_rows.push_back({i, out.root_velocity[root]});
    if (out.root_position[root] > 0) out.push_rows.push_back({i, out.root_position[root]});
  }
}

void run_extra_velocity_passes(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows,
                               const std::vector<ManifoldRow>& manifold_rows, std::vector<JointRow>& joint_rows,
                               JointTree& tree, const IslandPasses& plan) {
  for (int pass = 0; pass < plan.most_velocity; ++pass) {
    // As a world's pass (solver.cpp): each sweep over the manifolds, the
    // free point rows in alternating direction, then the joints.
    const auto sweep = [&](auto solve) {
      for (const IslandPasses::Entry& e : plan.manifolds) {
        if (e.extra <= pass) continue;
        const ManifoldRow& m = manifold_rows[e.index];
        solve(bodies[m.a], bodies[m.b], m);
      }
    };
    sweep(solve_friction<ManifoldRow>);
    sweep(solve_manifold_normal<ManifoldRow>);
    sweep(solve_rocking<ManifoldRow>);
    const size_t n = plan.free_rows.size();
    for (size_t k = 0; k < n; ++k) {
      const IslandPasses::Entry& e = plan.free_rows[pass % 2 == 0 ? k : n - 1 - k];
      if (e.extra <= pass) continue;
      PointRow& row = rows[e.index];
      solve_normal(bodies[row.a], bodies[row.b], row);
    }
    solve_joints(bodies, joint_rows, tree, pass);
  }
}

void run_extra_position_passes(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                               std::vector<JointRow>& joint_rows, JointTree& tree, const IslandPasses& plan) {
  for (int pass = 0; pass < plan.most_position; ++pass) {
    const size_t n = plan.push_rows.size();
    for (size_t k = 0; k < n; ++k) {
      const IslandPasses::Entry& e = plan.push_rows[pass % 2 == 0 ? k : n - 1 - k];
      if (e.extra <= pass) continue;
      const PointRow& row = rows[e.index];
      solve_push(bodies[row.a], bodies[row.b], row);
    }
    push_joints(bodies, joint_rows, tree, pass);
  }
}

}  // namespace bitstep
