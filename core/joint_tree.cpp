#include "core/joint_tree.h"

#include <algorithm>

#include "core/islands.h"
#include "core/joint_solver.h"

namespace bitstep {

namespace {

constexpr uint32_t unvisited = UINT32_MAX;

Mat33 skew(Vec3 r) { return {{Vec3{Fixed{}, -r.z, r.y}, Vec3{r.z, Fixed{}, -r.x}, Vec3{-r.y, r.x, Fixed{}}}}; }

bool has_point_block(const JointRow& row) { return row.joint->type != JointType::max_distance; }

// The joint's arm on `body` and the sign of its impulse there (-1 on a, +1 on b).
Vec3 arm_on(const JointRow& row, uint32_t body) { return body == row.a ? row.ra : row.rb; }
Fixed sign_on(const JointRow& row, uint32_t body) { return body == row.a ? -Fixed::one() : Fixed::one(); }

// K_ij through one shared body: s_i s_j (1/m 1 - [r_i]x I^-1 [r_j]x).
Mat33 coupling(const SolverBody& body, Vec3 ri, Vec3 rj, Fixed sign) {
  const Fixed m = body.inverse_mass;
  const Mat33 linear{{Vec3{m, Fixed{}, Fixed{}}, Vec3{Fixed{}, m, Fixed{}}, Vec3{Fixed{}, Fixed{}, m}}};
  const Mat33 k = linear - skew(ri) * (body.inverse_inertia * skew(rj));
  return sign < Fixed{} ? Mat33{} - k : k;
}

// Lists, per movable body, the point-block rows on it (a counting sort:
// in row order). Returns false when the rows close a loop among movable
// bodies.
bool list_body_rows(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  const size_t count = bodies.size();
  std::vector<uint32_t>& parent = tree.parent;
  parent.resize(count);
  for (uint32_t i = 0; i < count; ++i) parent[i] = i;
  std::vector<uint32_t>& begin = tree.body_rows_begin;
  begin.assign(count + 1, 0);
  for (const JointRow& row : rows) {
    if (!has_point_block(row)) continue;
    const bool movable_a = !immovable(bodies[row.a]), movable_b = !immovable(bodies[row.b]);
    if (movable_a && movable_b) {
      if (find_root(parent, row.a) == find_root(parent, row.b)) return false;
      unite(parent, row.a, row.b);
    }
    if (movable_a) ++begin[row.a + 1];
    if (movable_b) ++begin[row.b + 1];
  }
  for (size_t i = 1; i <= count; ++i) begin[i] += begin[i - 1];
  tree.body_rows.resize(begin[count]);
  std::vector<uint32_t>& fill = tree.queue;
  fill.assign(begin.begin(), begin.end() - 1);
  for (uint32_t r = 0; r < rows.size(); ++r) {
    if (!has_point_block(rows[r])) continue;
    for (const uint32_t body : {rows[r].a, rows[r].b}) {
      if (!immovable(bodies[body])) tree.body_rows[fill[body]++] = r;
    }
  }
  return true;
}

// Each movable body's depth in its tree, breadth-first from the tree's
// lowest slot.
void measure_depths(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  std::vector<uint32_t>& depth = tree.depth;
  depth.assign(bodies.size(), unvisited);
  std::vector<uint32_t>& queue = tree.queue;
  for (uint32_t root = 0; root < bodies.size(); ++root) {
    if (depth[root] != unvisited || tree.body_rows_begin[root] == tree.body_rows_begin[root + 1]) continue;
    depth[root] = 0;
    queue.assign(1, root);
    for (size_t q = 0; q < queue.size(); ++q) {
      const uint32_t body = queue[q];
      for (uint32_t k = tree.body_rows_begin[body]; k < tree.body_rows_begin[body + 1]; ++k) {
        const JointRow& row = rows[tree.body_rows[k]];
        const uint32_t other = row.a == body ? row.b : row.a;
        if (immovable(bodies[other]) || depth[other] != unvisited) continue;
        depth[other] = depth[body] + 1;
        queue.push_back(other);
      }
    }
  }
}

// The elimination order: deepest bodies first; at a body, the rows that
// hold it to immovable ones, then the row that joins it to its parent.
void order_rows(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  struct Key {
    uint32_t depth, body, joins_parent, row;
  };
  const auto key_of = [&](uint32_t r) {
    const JointRow& row = rows[r];
    const bool movable_a = !immovable(bodies[row.a]), movable_b = !immovable(bodies[row.b]);
    uint32_t body = movable_a ? row.a : row.b;
    if (movable_a && movable_b && tree.depth[row.b] > tree.depth[row.a]) body = row.b;
    return Key{tree.depth[body], body, movable_a && movable_b ? 1u : 0u, r};
  };
  tree.row_of.clear();
  for (uint32_t r = 0; r < rows.size(); ++r) {
    if (has_point_block(rows[r])) tree.row_of.push_back(r);
  }
  std::sort(tree.row_of.begin(), tree.row_of.end(), [&](uint32_t x, uint32_t y) {
    const Key a = key_of(x), b = key_of(y);
    if (a.depth != b.depth) return a.depth > b.depth;
    if (a.body != b.body) return a.body < b.body;
    if (a.joins_parent != b.joins_parent) return a.joins_parent < b.joins_parent;
    return a.row < b.row;
  });
  tree.position_of.assign(rows.size(), unvisited);
  for (uint32_t p = 0; p < tree.row_of.size(); ++p) tree.position_of[tree.row_of[p]] = p;
}

// The couplings through every movable body, each kept by the earlier of
// its two positions (a counting sort by that position: deterministic).
void list_couplings(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  tree.unsorted.clear();
  tree.owner.clear();
  for (uint32_t body = 0; body < bodies.size(); ++body) {
    for (uint32_t x = tree.body_rows_begin[body]; x < tree.body_rows_begin[body + 1]; ++x) {
      for (uint32_t y = x + 1; y < tree.body_rows_begin[body + 1]; ++y) {
        const JointRow& ri = rows[tree.body_rows[x]];
        const JointRow& rj = rows[tree.body_rows[y]];
        uint32_t pi = tree.position_of[tree.body_rows[x]], pj = tree.position_of[tree.body_rows[y]];
        const Fixed sign = sign_on(ri, body) * sign_on(rj, body);
        Mat33 block = coupling(bodies[body], arm_on(ri, body), arm_on(rj, body), sign);  // K_ij
        if (pj < pi) {
          std::swap(pi, pj);
          block = transpose(block);
        }
        tree.unsorted.push_back({pj, block});
        tree.owner.push_back(pi);
      }
    }
  }
  const size_t n = tree.row_of.size();
  tree.couplings_begin.assign(n + 1, 0);
  for (const uint32_t p : tree.owner) ++tree.couplings_begin[p + 1];
  for (size_t p = 1; p <= n; ++p) tree.couplings_begin[p] += tree.couplings_begin[p - 1];
  tree.couplings.resize(tree.unsorted.size());
  std::vector<uint32_t>& fill = tree.queue;
  fill.assign(tree.couplings_begin.begin(), tree.couplings_begin.end() - 1);
  for (size_t c = 0; c < tree.unsorted.size(); ++c) tree.couplings[fill[tree.owner[c]]++] = tree.unsorted[c];
}

// The block stored between positions i < j, or null (fill-in: not a tree).
Mat33* block_between(JointTree& tree, uint32_t i, uint32_t j) {
  for (uint32_t c = tree.couplings_begin[i]; c < tree.couplings_begin[i + 1]; ++c) {
    if (tree.couplings[c].other == j) return &tree.couplings[c].block;
  }
  return nullptr;
}

}  // namespace

Mat33 inverse_spd(const Mat33& k) {
  // K = L D L^T, L unit lower triangular: d0 = k00, l10 = k10 / d0,
  // l20 = k20 / d0, d1 = k11 - l10 k10, l21 = (k21 - l20 k10) / d1,
  // d2 = k22 - l20 k20 - l21 (k21 - l20 k10).
  const Fixed k00 = k.rows[0].x, k10 = k.rows[1].x, k11 = k.rows[1].y, k20 = k.rows[2].x, k21 = k.rows[2].y,
              k22 = k.rows[2].z;
  const Fixed d0 = k00;
  if (d0 <= Fixed{}) return inverse(k);
  const Fixed l10 = k10 / d0, l20 = k20 / d0;
  const Fixed d1 = k11 - l10 * k10;
  if (d1 <= Fixed{}) return inverse(k);
  const Fixed m21 = k21 - l20 * k10;
  const Fixed l21 = m21 / d1;
  const Fixed d2 = k22 - l20 * k20 - l21 * m21;
  if (d2 <= Fixed{}) return inverse(k);
  // K^-1 = L^-T D^-1 L^-1. L^-1 = [[1, 0, 0], [-l10, 1, 0], [l10 l21 - l20, -l21, 1]].
  const Fixed a10 = -l10, a21 = -l21, a20 = l10 * l21 - l20;
  const Fixed e0 = Fixed::one() / d0, e1 = Fixed::one() / d1, e2 = Fixed::one() / d2;
  // (K^-1)_ij = sum_k (L^-1)_ki e_k (L^-1)_kj over k >= max(i, j).
  const Fixed i22 = e2;
  const Fixed i21 = a21 * e2;
  const Fixed i20 = a20 * e2;
  const Fixed i11 = e1 + a21 * i21;
  const Fixed i10 = a10 * e1 + a21 * i20;
  const Fixed i00 = e0 + a10 * a10 * e1 + a20 * i20;
  return {{Vec3{i00, i10, i20}, Vec3{i10, i11, i21}, Vec3{i20, i21, i22}}};
}

void factor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  tree.exact = false;
  tree.row_of.clear();
  if (rows.empty() || !list_body_rows(bodies, rows, tree)) return;
  measure_depths(bodies, rows, tree);
  order_rows(bodies, rows, tree);
  if (tree.row_of.empty()) return;
  list_couplings(bodies, rows, tree);
  const size_t n = tree.row_of.size();
  tree.pivot.resize(n);
  tree.pivot_inverse.resize(n);
  for (size_t p = 0; p < n; ++p) tree.pivot[p] = rows[tree.row_of[p]].point_k;
  // K = L D L^T, leaves first: eliminating k subtracts K_ik D_k^-1 K_kj
  // from every pair of its later neighbours i, j.
  for (uint32_t k = 0; k < n; ++k) {
    const Mat33 inverse_pivot = inverse_spd(tree.pivot[k]);
    tree.pivot_inverse[k] = inverse_pivot;
    const uint32_t begin = tree.couplings_begin[k], end = tree.couplings_begin[k + 1];
    for (uint32_t x = begin; x < end; ++x) {
      const JointTree::Coupling ci = tree.couplings[x];
      const Mat33 left = transpose(ci.block) * inverse_pivot;  // K_ik D_k^-1
      for (uint32_t y = x; y < end; ++y) {
        const JointTree::Coupling cj = tree.couplings[y];
        const Mat33 update = left * cj.block;  // K_ik D_k^-1 K_kj
        if (ci.other == cj.other) {
          tree.pivot[ci.other] = tree.pivot[ci.other] - update;
          continue;
        }
        const bool i_first = ci.other < cj.other;
        Mat33* between = i_first ? block_between(tree, ci.other, cj.other) : block_between(tree, cj.other, ci.other);
        if (between == nullptr) return;  // fill-in: the order is not a tree's
        *between = *between - (i_first ? update : transpose(update));
      }
    }
  }
  tree.rhs.resize(n);
  tree.angular_rhs.resize(n);
  tree.exact = true;
}

void solve_joint_tree(JointTree& tree) {
  const size_t n = tree.row_of.size();
  std::vector<Vec3>& b = tree.rhs;
  // Forward: b_i -= K_ik D_k^-1 b_k for each later neighbour i of k.
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 scaled = tree.pivot_inverse[k] * b[k];
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) {
      const JointTree::Coupling& coupling = tree.couplings[c];
      b[coupling.other] -= transpose(coupling.block) * scaled;
    }
  }
  // Back: x_k = D_k^-1 (b_k - sum K_ki x_i over the later neighbours i).
  for (size_t k = n; k-- > 0;) {
    Vec3 rest = b[k];
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) {
      rest -= tree.couplings[c].block * b[tree.couplings[c].other];
    }
    b[k] = tree.pivot_inverse[k] * rest;
  }
}

}  // namespace bitstep
