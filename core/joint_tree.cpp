#include "core/joint_tree.h"

#include <algorithm>
#include <bit>
#include <limits>

#include "core/islands.h"
#include "core/joint_solver.h"

namespace bitstep {

namespace {

constexpr uint32_t unvisited = UINT32_MAX;


// Row p of a joint on one of its bodies: the angular part.
Vec3 angular_on(const JointRow& row, int p, uint32_t body) {
  return body == row.a ? row.tree_axes[p].angular_a : row.tree_axes[p].angular_b;
}

// K_ij through one shared body B: entry (p, q) = s_i s_j l_p . l_q / m_B +
// w_p . I_B^-1 w_q, for row p of joint i and row q of joint j (i may be j),
// s = -1 on a joint's body a. Between two point blocks the linear parts are
// unit axes e_k, and angular rows have none: l_p . l_q / m_B is 1 / m_B
// where p = q < 3 and 0 elsewhere, added without the products.
Block coupling(const SolverBody& body, const JointRow& ri, const JointRow& rj, uint32_t slot) {
  Block k{};
  Vec3 turn[max_tree_axes];
  for (int q = 0; q < rj.tree_size; ++q) turn[q] = body.inverse_inertia * angular_on(rj, q, slot);
  for (int p = 0; p < ri.tree_size; ++p) {
    const Vec3 wp = angular_on(ri, p, slot);
    for (int q = 0; q < rj.tree_size; ++q) k.at[p][q] = dot(wp, turn[q]);
  }
  const bool same_side = (slot == ri.a) == (slot == rj.a);
  const Fixed mass = same_side ? body.inverse_mass : -body.inverse_mass;
  if (ri.has_point_block && rj.has_point_block) {
    for (int p = 0; p < 3; ++p) k.at[p][p] += mass;
    return k;
  }
  for (int p = 0; p < ri.tree_size; ++p) {
    const Vec3 lp = ri.tree_axes[p].linear;
    if (lp == Vec3{}) continue;
    for (int q = 0; q < rj.tree_size; ++q) {
      const Vec3 lq = rj.tree_axes[q].linear;
      if (lq != Vec3{}) k.at[p][q] += dot(lp, lq) * mass;
    }
  }
  return k;
}

// Block products over the used n x m parts (n, m <= 6), each entry a sum
// of products rounded once per three terms (dot3: one rounding for n <= 3,
// as the 3x3 point blocks have; two above).
inline Fixed dot_n(const Fixed* a, const Fixed* b, int n) {
  const Fixed low = dot(Vec3{a[0], a[1], a[2]}, Vec3{b[0], b[1], b[2]});
  if (n <= 3) return low;
  const Fixed zero;
  return low + dot(Vec3{a[3], n > 4 ? a[4] : zero, n > 5 ? a[5] : zero}, Vec3{b[3], n > 4 ? b[4] : zero, n > 5 ? b[5] : zero});
}
Block transposed(const Block& a, int n, int m) {
  Block t{};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) t.at[j][i] = a.at[i][j];
  }
  return t;
}
Mat33 mat33(const Block& a) {
  return {{Vec3{a.at[0][0], a.at[0][1], a.at[0][2]}, Vec3{a.at[1][0], a.at[1][1], a.at[1][2]},
           Vec3{a.at[2][0], a.at[2][1], a.at[2][2]}}};
}
// A 3x3 matrix as a block (the rest zero).
Block block_of(const Mat33& m) {
  Block b{};
  for (int i = 0; i < 3; ++i) {
    const Vec3 row = m.rows[static_cast<size_t>(i)];
    b.at[i][0] = row.x;
    b.at[i][1] = row.y;
    b.at[i][2] = row.z;
  }
  return b;
}
// (n x k) times (k x m).
Block product(const Block& a, const Block& b, int n, int k, int m) {
  if (n == 3 && k == 3 && m == 3) return block_of(mat33(a) * mat33(b));  // point blocks: as Mat33
  Block c{};
  const Block bt = transposed(b, k, m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) c.at[i][j] = dot_n(a.at[i], bt.at[j], k);
  }
  return c;
}
void subtract(Block& a, const Block& b, int n, int m) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) a.at[i][j] -= b.at[i][j];
  }
}
// x 2^e, rounded to nearest (ties up) where e < 0: exact where e >= 0,
// saturated past the range (the checked build aborts).
inline Fixed times_power_of_two(Fixed x, int e) {
  if (e < 0) return Fixed::from_raw((x.raw() >> -e) + ((x.raw() >> (-e - 1)) & 1));
  const int64_t room = std::numeric_limits<int64_t>::max() >> e;
  const bool saturated = x.raw() > room || x.raw() < -room;
  BITSTEP_FAULT_IF(saturated, "times_power_of_two", "result out of range, saturated", x.raw(), e);
  if (saturated) return x > Fixed{} ? Fixed::max() : -Fixed::max();
  return Fixed::from_raw(x.raw() * (int64_t{1} << e));
}
// The exponent e that brings a diagonal entry d > 0 to d 4^e in 0.5..4
// (0 where d <= 0: a row of nothing movable).
int8_t scale_exponent(Fixed diagonal) {
  if (diagonal <= Fixed{}) return 0;
  const int width = static_cast<int>(std::bit_width(static_cast<uint64_t>(diagonal.raw())));  // d in [2^(w-33), 2^(w-32))
  return static_cast<int8_t>(std::clamp((33 - width) >> 1, -24, 24));
}
// S_a K S_b of an n x m block: row i times 2^a_i, column j times 2^b_j.
void scale_block(Block& k, int n, int m, const JointTree::RowScales& a, const JointTree::RowScales& b) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) k.at[i][j] = times_power_of_two(k.at[i][j], a.exponent[i] + b.exponent[j]);
  }
}
void scale_column(Column& x, int n, const JointTree::RowScales& s) {
  for (int i = 0; i < n; ++i) x.at[i] = times_power_of_two(x.at[i], s.exponent[i]);
}

// (n x m) times a column of m, into y (its first n).
inline void product(const Block& a, const Column& x, int n, int m, Column& y) {
  const auto row = [&a](int i) { return Vec3{a.at[i][0], a.at[i][1], a.at[i][2]}; };
  if (n == 3 && m == 3) {  // two point blocks: unrolled
    const Vec3 v{x.at[0], x.at[1], x.at[2]};
    y.at[0] = dot(row(0), v);
    y.at[1] = dot(row(1), v);
    y.at[2] = dot(row(2), v);
    return;
  }
  if (m <= 3) {
    const Vec3 low{x.at[0], x.at[1], x.at[2]};
    for (int i = 0; i < n; ++i) y.at[i] = dot(row(i), low);
    return;
  }
  for (int i = 0; i < n; ++i) y.at[i] = dot_n(a.at[i], x.at, m);
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
    if (!row.is_tree_node()) continue;
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
    if (!rows[r].is_tree_node()) continue;
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
    if (rows[r].is_tree_node()) tree.row_of.push_back(r);
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
        Block block = coupling(bodies[body], ri, rj, body);  // K_ij
        const bool swapped = pj < pi;
        if (swapped) {
          std::swap(pi, pj);
          block = transposed(block, ri.tree_size, rj.tree_size);
        }
        tree.unsorted.push_back({pj, block, {}, body, tree.body_rows[x], tree.body_rows[y], swapped});
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
Block* block_between(JointTree& tree, uint32_t i, uint32_t j) {
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

Block inverse_spd(const Block& k, int n) {
  if (n == 3) return block_of(inverse_spd(mat33(k)));  // a point block: the 3x3 form
  // K^-1 = S (S K S)^-1 S, S = diag(2^e) bringing each K_ii to 0.5..4 (as
  // the tree does, JointTree::scale): a slider between bodies 1e3 apart in
  // mass has linear and angular rows 1e7 apart.
  JointTree::RowScales s{};
  for (int i = 0; i < n; ++i) s.exponent[i] = scale_exponent(k.at[i][i]);
  Block scaled = k;
  scale_block(scaled, n, n, s, s);
  Block inverse = inverse_spd(scaled, n, Column{});
  scale_block(inverse, n, n, s, s);
  return inverse;
}

Block inverse_spd(const Block& k, int n, const Column& floor) {
  // A point block outside a tree that may hold dependent rows: the 3x3
  // form at once (most of them: a chain's, a ragdoll's).
  if (n == 3 && floor.at[0] == Fixed{} && floor.at[1] == Fixed{} && floor.at[2] == Fixed{}) {
    return block_of(inverse_spd(mat33(k)));
  }
  // K = L D L^T, L unit lower triangular: d_j = k_jj - sum_{m<j} l_jm^2 d_m,
  // l_ij = (k_ij - sum_{m<j} l_im l_jm d_m) / d_j (i > j).
  Fixed l[max_tree_axes][max_tree_axes] = {};
  Fixed d[max_tree_axes] = {}, e[max_tree_axes] = {};
  bool dropped = false;
  for (int j = 0; j < n; ++j) {
    Fixed dj = k.at[j][j];
    for (int m = 0; m < j; ++m) dj -= l[j][m] * l[j][m] * d[m];
    d[j] = dj;
    if (dj <= floor.at[j]) {  // a dependent row: dropped (its l column stays 0)
      dropped = true;
      continue;
    }
    e[j] = Fixed::one() / dj;
    for (int i = j + 1; i < n; ++i) {
      Fixed kij = k.at[i][j];
      for (int m = 0; m < j; ++m) kij -= l[i][m] * l[j][m] * d[m];
      l[i][j] = kij / dj;
    }
  }
  // A point block of independent rows: the 3x3 form (the same bits).
  if (n == 3 && !dropped) return block_of(inverse_spd(mat33(k)));
  // L^-1, unit lower triangular: a_ij = -sum_{m=j}^{i-1} l_im a_mj.
  Fixed a[max_tree_axes][max_tree_axes] = {};
  for (int i = 0; i < n; ++i) {
    a[i][i] = Fixed::one();
    for (int j = 0; j < i; ++j) {
      Fixed sum;
      for (int m = j; m < i; ++m) sum = mul_add(l[i][m], a[m][j], sum);
      a[i][j] = -sum;
    }
  }
  // K^-1 = L^-T D^-1 L^-1: (K^-1)_ij = sum_{m >= max(i, j)} a_mi e_m a_mj.
  Block inverse{};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      Fixed sum;
      for (int m = i; m < n; ++m) sum = mul_add(a[m][i] * e[m], a[m][j], sum);
      inverse.at[i][j] = inverse.at[j][i] = sum;
    }
  }
  return inverse;
}

namespace {

// A row's swing (bit 1) and limit (bit 2) in the tree.
uint8_t holds_of(const JointRow& row) {
  return static_cast<uint8_t>((row.swing_in_tree ? 1 : 0) | (row.limit_in_tree ? 2 : 0));
}

void list_holds(const std::vector<JointRow>& rows, std::vector<uint8_t>& holds) {
  holds.resize(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) holds[r] = holds_of(rows[r]);
}

// Each position's tree: the lowest position it is coupled to, directly or
// through others.
void label_components(JointTree& tree) {
  const size_t n = tree.row_of.size();
  std::vector<uint32_t>& parent = tree.parent;
  parent.resize(n);
  for (uint32_t p = 0; p < n; ++p) parent[p] = p;
  for (uint32_t k = 0; k < n; ++k) {
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) unite(parent, k, tree.couplings[c].other);
  }
  tree.component.resize(n);
  for (uint32_t p = 0; p < n; ++p) tree.component[p] = find_root(parent, p);
}

// Per tree, how many of its joints hold a movable body to an immovable one.
// Only a tree held so at least twice closes a loop through the immovable
// world (a door's two pins, a plank held at both ends, the same joint
// twice), where its rows may depend on each other's; in a tree held once
// or not at all each joint's rows are independent of the others'.
void count_holds_to_immovable(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  const size_t n = tree.row_of.size();
  tree.holds_to_immovable.assign(n, 0);
  for (size_t p = 0; p < n; ++p) {
    const JointRow& row = rows[tree.row_of[p]];
    if (immovable(bodies[row.a]) || immovable(bodies[row.b])) ++tree.holds_to_immovable[tree.component[p]];
  }
}

// The numbers of the factorisation at the positions marked in `dirty` (all
// of some trees), their couplings' K blocks formed as `recouple` says:
// each pivot K_ii, then K = L D L^T in position order, leaves first.
void factor_positions(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree,
                      const std::vector<uint8_t>& dirty, bool recouple) {
  const size_t n = tree.row_of.size();
  for (size_t p = 0; p < n; ++p) {
    if (!dirty[p]) continue;
    const JointRow& row = rows[tree.row_of[p]];
    tree.size[p] = row.tree_size;
    // K_ii: the point block's K as prepare_joint_rows formed it, and the
    // other rows' entries through each movable body (all of a slider's).
    Block& pivot = tree.pivot[p];
    pivot = Block{};
    if (row.tree_size > 3 || !row.has_point_block) {
      for (const uint32_t body : {row.a, row.b}) {
        if (immovable(bodies[body])) continue;
        const Block part = coupling(bodies[body], row, row, body);
        for (int i = 0; i < row.tree_size; ++i) {
          for (int j = 0; j < row.tree_size; ++j) pivot.at[i][j] += part.at[i][j];
        }
      }
    }
    if (row.has_point_block) {
      const Block point = block_of(row.point_k);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) pivot.at[i][j] = point.at[i][j];
      }
    }
    for (int i = 0; i < max_tree_axes; ++i) {
      tree.scale[p].exponent[i] = i < row.tree_size ? scale_exponent(pivot.at[i][i]) : int8_t{0};
    }
    scale_block(pivot, row.tree_size, row.tree_size, tree.scale[p], tree.scale[p]);
    // Each row's floor: in a tree held to immovable bodies at two or more
    // joints (a loop through the world), what its pivot must keep of its
    // K_ii diagonal to be a row of its own: 2^-5 of it, and 64 raw units;
    // elsewhere 0. Such a tree may ask for what no motion gives: a beam
    // pinned to a post and to an arm that turns, whose pins' span changes.
    // Its rows along the beam then nearly depend on each other (only the
    // beam's small tilt tells them apart), and the exact answer to the
    // contradiction is a spin that grows as the tilt shrinks: 8.5e8 N s on
    // a 100 t beam in one pass, and the beam flew off at the speed cap. A
    // row that keeps less than 1/32 of its diagonal is dropped instead,
    // and holds with the other joints' impulses alone (as does an exactly
    // dependent row: two pins of a door, whose pivot rounding leaves a few
    // raw units from 0). 1/32 was measured: 1/128 and 1/64 still let such
    // beams and chains abort the checked build in 3,000 steps of 252
    // cases; the pins of a 16-plank deck hung between two posts, which
    // keep shrinking fractions of their diagonals, stay within 0.08 mm (at
    // 1/16 one of its rows went, and they parted by 0.95 mm). A tree held
    // once has no floor: a 0.01 kg link holding 1e5 kg keeps 2^-36 of its
    // diagonal, exact, as a tree held once is.
    const bool may_depend = tree.holds_to_immovable[tree.component[p]] >= 2;
    for (int i = 0; i < row.tree_size; ++i) {
      tree.floor[p].at[i] = may_depend ? Fixed::from_raw((pivot.at[i][i].raw() >> 5) + 64) : Fixed{};
    }
    if (!recouple) continue;
    for (uint32_t c = tree.couplings_begin[p]; c < tree.couplings_begin[p + 1]; ++c) {
      JointTree::Coupling& k = tree.couplings[c];
      const JointRow& first = rows[k.first];
      const JointRow& second = rows[k.second];
      k.block = coupling(bodies[k.body], first, second, k.body);
      if (k.swapped) k.block = transposed(k.block, first.tree_size, second.tree_size);
    }
  }
  // The couplings as S K S, once every scale of their trees is known.
  for (size_t p = 0; p < n; ++p) {
    if (!dirty[p]) continue;
    for (uint32_t c = tree.couplings_begin[p]; c < tree.couplings_begin[p + 1]; ++c) {
      JointTree::Coupling& k = tree.couplings[c];
      scale_block(k.block, tree.size[p], tree.size[k.other], tree.scale[p], tree.scale[k.other]);
    }
  }
  // K = L D L^T, leaves first: eliminating k subtracts K_ik D_k^-1 K_kj
  // from every pair of its later neighbours i, j (all in k's tree).
  for (uint32_t k = 0; k < n; ++k) {
    if (!dirty[k]) continue;
    const int nk = tree.size[k];
    tree.pivot_inverse[k] = inverse_spd(tree.pivot[k], nk, tree.floor[k]);
    const uint32_t begin = tree.couplings_begin[k], end = tree.couplings_begin[k + 1];
    for (uint32_t x = begin; x < end; ++x) {
      const JointTree::Coupling& ci = tree.couplings[x];
      const int ni = tree.size[ci.other];
      // K_ik D_k^-1 (ni x nk).
      const Block left = product(transposed(ci.block, nk, ni), tree.pivot_inverse[k], ni, nk, nk);
      for (uint32_t y = x; y < end; ++y) {
        const JointTree::Coupling& cj = tree.couplings[y];
        const int nj = tree.size[cj.other];
        const Block update = product(left, cj.block, ni, nk, nj);  // K_ik D_k^-1 K_kj
        if (ci.other == cj.other) {
          subtract(tree.pivot[ci.other], update, ni, nj);
          continue;
        }
        const bool i_first = ci.other < cj.other;
        Block* between = i_first ? block_between(tree, ci.other, cj.other) : block_between(tree, cj.other, ci.other);
        if (between == nullptr) {  // fill-in: the order is not a tree's
          tree.exact = false;
          return;
        }
        subtract(*between, i_first ? update : transposed(update, ni, nj), i_first ? ni : nj, i_first ? nj : ni);
      }
    }
  }
  for (uint32_t k = 0; k < n; ++k) {
    if (!dirty[k]) continue;
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) {
      JointTree::Coupling& coupling = tree.couplings[c];
      coupling.block_transposed = transposed(coupling.block, tree.size[k], tree.size[coupling.other]);
    }
  }
}

}  // namespace

void factor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  tree.exact = false;
  tree.row_of.clear();
  list_holds(rows, tree.holds);
  if (rows.empty() || !list_body_rows(bodies, rows, tree)) return;
  measure_depths(bodies, rows, tree);
  order_rows(bodies, rows, tree);
  if (tree.row_of.empty()) return;
  list_couplings(bodies, rows, tree);
  const size_t n = tree.row_of.size();
  tree.size.resize(n);
  tree.pivot.resize(n);
  tree.pivot_inverse.resize(n);
  tree.floor.resize(n);
  tree.scale.resize(n);
  tree.dirty.assign(n, 1);
  tree.exact = true;
  label_components(tree);
  count_holds_to_immovable(bodies, rows, tree);
  factor_positions(bodies, rows, tree, tree.dirty, false);
  if (!tree.exact) return;
  tree.rhs.resize(n);
}

void refactor_joint_tree(const std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows, JointTree& tree) {
  if (!tree.exact) {
    factor_joint_tree(bodies, rows, tree);
    return;
  }
  const size_t n = tree.row_of.size();
  // The trees holding a row whose swing or limit joined or left.
  std::vector<uint8_t>& dirty = tree.dirty;
  dirty.assign(n, 0);
  for (size_t p = 0; p < n; ++p) {
    const uint32_t r = tree.row_of[p];
    if (holds_of(rows[r]) != tree.holds[r]) dirty[tree.component[p]] = 1;
  }
  for (size_t p = 0; p < n; ++p) dirty[p] = dirty[tree.component[p]];
  list_holds(rows, tree.holds);
  factor_positions(bodies, rows, tree, dirty, true);
}

void solve_joint_tree(JointTree& tree, std::vector<Column>& b) {
  const size_t n = tree.row_of.size();
  for (size_t k = 0; k < n; ++k) scale_column(b[k], tree.size[k], tree.scale[k]);  // S b
  Column scaled, change;
  // Forward: b_i -= K_ik D_k^-1 b_k for each later neighbour i of k.
  for (uint32_t k = 0; k < n; ++k) {
    const int nk = tree.size[k];
    product(tree.pivot_inverse[k], b[k], nk, nk, scaled);
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) {
      const JointTree::Coupling& coupling = tree.couplings[c];
      const int ni = tree.size[coupling.other];
      product(coupling.block_transposed, scaled, ni, nk, change);
      Column& target = b[coupling.other];
      for (int i = 0; i < ni; ++i) target.at[i] -= change.at[i];
    }
  }
  // Back: x_k = D_k^-1 (b_k - sum K_ki x_i over the later neighbours i).
  for (size_t k = n; k-- > 0;) {
    const int nk = tree.size[k];
    Column& rest = b[k];
    for (uint32_t c = tree.couplings_begin[k]; c < tree.couplings_begin[k + 1]; ++c) {
      const JointTree::Coupling& coupling = tree.couplings[c];
      product(coupling.block, b[coupling.other], nk, tree.size[coupling.other], change);
      for (int i = 0; i < nk; ++i) rest.at[i] -= change.at[i];
    }
    product(tree.pivot_inverse[k], rest, nk, nk, scaled);
    rest = scaled;
  }
  for (size_t k = 0; k < n; ++k) scale_column(b[k], tree.size[k], tree.scale[k]);  // lambda = S y
}

}  // namespace bitstep
