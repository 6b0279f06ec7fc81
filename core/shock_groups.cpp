#include "core/shock_groups.h"

#include <utility>

#include "core/islands.h"
#include "core/manifold.h"
#include "core/shock.h"

namespace bitstep {

namespace {

constexpr uint8_t unconverged = 1, moving = 2;

void swap_velocities(std::vector<SolverBody>& bodies, std::vector<BodyRates>& kept) {
  for (size_t i = 0; i < bodies.size(); ++i) std::swap(bodies[i].velocity, kept[i]);
}

}  // namespace

void keep_velocities(const std::vector<SolverBody>& bodies, ShockGroups& groups) {
  groups.before_shock.resize(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) groups.before_shock[i] = bodies[i].velocity;
  groups.unconverged.clear();
}

size_t keep_iterations_where_held(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows,
                                  Fixed quiet, ShockGroups& groups, std::vector<SolverBody>& bodies) {
  if (groups.unconverged.empty()) return 0;
  const size_t n = bodies.size();
  std::vector<uint32_t>& parent = groups.parent;
  parent.resize(n);
  for (uint32_t i = 0; i < n; ++i) parent[i] = i;
  const auto movable = [&](uint32_t body) { return bodies[body].inverse_mass != Fixed{}; };
  for (const ManifoldRow& m : manifolds) {
    if (!movable(m.a) || !movable(m.b) || !touches(*m.manifold)) continue;
    unite(parent, m.a, m.b);
  }
  std::vector<uint8_t>& flags = groups.flags;
  flags.assign(n, 0);
  for (uint32_t body : groups.unconverged) flags[find_root(parent, body)] |= unconverged;
  // Judged at the iterations' velocities.
  swap_velocities(bodies, groups.before_shock);
  for (const ManifoldRow& m : manifolds) {
    if (moving_at_contact(bodies, rows, m, quiet)) flags[find_root(parent, movable(m.a) ? m.a : m.b)] |= moving;
  }
  swap_velocities(bodies, groups.before_shock);
  size_t kept = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (flags[find_root(parent, i)] != unconverged) continue;
    bodies[i].velocity = groups.before_shock[i];
    ++kept;
  }
  return kept;
}

}  // namespace bitstep
