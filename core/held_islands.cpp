#include "core/held_islands.h"

#include <algorithm>

#include "core/islands.h"
#include "core/row_islands.h"
#include "core/settings.h"

namespace bitstep {

void plan_held_islands(const Settings& settings, const std::vector<SolverBody>& bodies,
                       const std::vector<BodyRates>& start, const std::vector<PointRow>& rows,
                       const std::vector<ManifoldRow>& manifold_rows, const std::vector<JointRow>& joint_rows,
                       const std::vector<TyreRow>& tyre_rows, HeldIslands& out) {
  out.all_passes = settings.velocity_iterations;
  out.more_passes = 0;
  out.manifolds.clear();
  out.free_rows.clear();
  const int held_passes = std::min(settings.held_velocity_iterations, settings.velocity_iterations);
  if (!settings.shock_propagation || held_passes == settings.velocity_iterations || manifold_rows.empty()) return;
  // Where no movable body starts still, every island moves: a world in
  // motion finds no islands.
  const auto movable = [&](uint32_t i) { return !immovable(bodies[i]); };
  bool any_still = false;
  for (uint32_t i = 0; i < bodies.size() && !any_still; ++i) any_still = movable(i) && start[i] == BodyRates{};
  if (!any_still) return;
  std::vector<uint32_t>& parent = out.parent;
  unite_rows(bodies, manifold_rows, joint_rows, &tyre_rows, parent);
  // An island moves if a body of it does, or it has an impact, a contact
  // other than a resting face, a joint or a tyre (every row touches a
  // movable body: contact_rows.cpp builds no other).
  const auto root_of = [&](uint32_t a, uint32_t b) { return row_island(bodies, parent, a, b); };
  std::vector<uint8_t>& moving = out.moving;
  moving.assign(bodies.size(), 0);
  for (uint32_t i = 0; i < bodies.size(); ++i) {
    if (movable(i) && start[i] != BodyRates{}) moving[find_root(parent, i)] = 1;
  }
  for (const PointRow& row : rows) {
    if (row.impact) moving[root_of(row.a, row.b)] = 1;
  }
  for (const ManifoldRow& m : manifold_rows) {
    if (!rows[m.first].in_resting_face) moving[root_of(m.a, m.b)] = 1;
  }
  for (const JointRow& row : joint_rows) moving[root_of(row.a, row.b)] = 1;
  for (const TyreRow& row : tyre_rows) moving[root_of(row.a, row.b)] = 1;
  bool any_held = false;
  for (uint32_t i = 0; i < manifold_rows.size(); ++i) {
    const ManifoldRow& m = manifold_rows[i];
    if (moving[root_of(m.a, m.b)]) {
      out.manifolds.push_back(i);
    } else {
      any_held = true;
    }
  }
  if (!any_held) {
    out.manifolds.clear();
    return;
  }
  for (uint32_t i = 0; i < rows.size(); ++i) {
    if (is_free_row(rows[i]) && moving[root_of(rows[i].a, rows[i].b)]) out.free_rows.push_back(i);
  }
  out.held_rows += manifold_rows.size() - out.manifolds.size();
  out.all_passes = held_passes;
  out.more_passes = settings.velocity_iterations - held_passes;
}

void run_moving_passes(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows,
                       const std::vector<ManifoldRow>& manifold_rows, std::vector<JointRow>& joint_rows,
                       JointTree& tree, std::vector<TyreRow>& tyre_rows, const HeldIslands& plan) {
  for (int k = 0; k < plan.more_passes; ++k) {
    const int pass = plan.all_passes + k;  // the world's pass: the free rows' direction
    const auto sweep = [&](auto solve) {
      for (const uint32_t i : plan.manifolds) {
        const ManifoldRow& m = manifold_rows[i];
        solve(bodies[m.a], bodies[m.b], m);
      }
    };
    sweep(solve_friction<ManifoldRow>);
    sweep(solve_manifold_normal<ManifoldRow>);
    sweep(solve_rocking<ManifoldRow>);
    const size_t n = plan.free_rows.size();
    for (size_t j = 0; j < n; ++j) {
      PointRow& row = rows[plan.free_rows[pass % 2 == 0 ? j : n - 1 - j]];
      solve_normal(bodies[row.a], bodies[row.b], row);
    }
    solve_joints(bodies, joint_rows, tree);
    solve_tyres(bodies, tyre_rows);
  }
}

}  // namespace bitstep
