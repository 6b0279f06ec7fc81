#include "core/row_islands.h"

#include "core/islands.h"

namespace bitstep {

void unite_rows(const std::vector<SolverBody>& bodies, const std::vector<ManifoldRow>& manifold_rows,
                const std::vector<JointRow>& joint_rows, const std::vector<TyreRow>* tyre_rows,
                std::vector<uint32_t>& parent) {
  parent.resize(bodies.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto join = [&](uint32_t a, uint32_t b) {
    if (!immovable(bodies[a]) && !immovable(bodies[b])) unite(parent, a, b);
  };
  for (const ManifoldRow& m : manifold_rows) join(m.a, m.b);
  for (const JointRow& row : joint_rows) join(row.a, row.b);
  if (tyre_rows != nullptr) {
    for (const TyreRow& row : *tyre_rows) join(row.a, row.b);
  }
}

uint32_t row_island(const std::vector<SolverBody>& bodies, std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
  return find_root(parent, immovable(bodies[a]) ? b : a);
}

}  // namespace bitstep
