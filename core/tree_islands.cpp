#include "core/tree_islands.h"

#include "core/joint_types.h"
#include "core/row_islands.h"

namespace bitstep {

void mark_tree_islands(const std::vector<SolverBody>& bodies, const std::vector<ManifoldRow>& manifold_rows,
                       const std::vector<TyreRow>& tyre_rows, const JointTree& tree, std::vector<JointRow>& joint_rows,
                       TreeIslands& scratch) {
  for (JointRow& row : joint_rows) row.tree_island = false;
  if (!tree.exact || joint_rows.empty()) return;
  std::vector<uint32_t>& parent = scratch.parent;
  unite_rows(bodies, manifold_rows, joint_rows, &tyre_rows, parent);
  std::vector<uint8_t>& more = scratch.more_than_tree;
  more.assign(bodies.size(), 0);
  const auto mark = [&](uint32_t a, uint32_t b) { more[row_island(bodies, parent, a, b)] = 1; };
  for (const ManifoldRow& m : manifold_rows) mark(m.a, m.b);  // its point rows join the same two bodies
  for (const TyreRow& row : tyre_rows) mark(row.a, row.b);
  for (const JointRow& row : joint_rows) {
    const bool alone =
        !row.friction && with_joint_type(row.joint->type, [&](auto type) { return decltype(type)::tree_alone(row); });
    if (!alone) mark(row.a, row.b);
  }
  for (JointRow& row : joint_rows) row.tree_island = more[row_island(bodies, parent, row.a, row.b)] == 0;
}

}  // namespace bitstep
