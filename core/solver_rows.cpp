#include "core/solver_rows.h"

#include "core/mass.h"

namespace bitstep {

namespace {

template <class Row>
Fixed total_normal_impulse(const Row& m) {
  Fixed total;
  for (size_t i = 0; i < m.count; ++i) total += normal_impulse(m, i);
  return total;
}

// Whether no point of m pulls (every accumulated normal impulse >= 0).
template <class Row>
bool none_pull(const Row& m) {
  for (size_t i = 0; i < m.count; ++i) {
    if (normal_impulse(m, i) < Fixed{}) return false;
  }
  return true;
}

// Two rows along an orthonormal pair (friction's tangents, rolling
// resistance's axes) solved as one: the impulse j that stops the relative
// rate along both is kept while |j| <= hold j_n, else scaled onto the disc
// |j| = slide j_n. Inside needs no square root: |j| <= |j0| + |j1| bounds
// it, and length_exceeds compares squares.
// Returns the disc's radius hold j_n.
template <class Part>
Fixed solve_disc(SolverBody& a, SolverBody& b, const Part* rows, Fixed (&impulse)[2], Fixed hold, Fixed slide,
                 Fixed normal) {
  const Fixed old0 = impulse[0], old1 = impulse[1];
  Fixed new0 = old0 - mul_in_range(rows[0].mass, relative_velocity(a, b, rows[0]));
  Fixed new1 = old1 - mul_in_range(rows[1].mass, relative_velocity(a, b, rows[1]));
  const Fixed limit = mul_in_range(hold, normal);
  const Vec3 both{new0, new1, Fixed{}};
  if (abs(new0) + abs(new1) > limit && length_exceeds(both, limit)) {
    const Fixed magnitude = length(both);
    const Fixed onto = slide * normal;
    new0 = mul_div(new0, onto, magnitude);
    new1 = mul_div(new1, onto, magnitude);
  }
  impulse[0] = new0;
  impulse[1] = new1;
  apply_impulse(a, b, rows[0], new0 - old0);
  apply_impulse(a, b, rows[1], new1 - old1);
  return limit;
}

// d / m, I^-1 (r x d) and (r x d) . I^-1 (r x d) of one body: zero products
// for an immovable one, not formed.
struct BodyPart {
  Vec3 linear, turn;
  Fixed angular_mass;
};
BodyPart body_part(const SolverBody& body, Vec3 arm, Vec3 d) {
  if (body.inverse_mass == Fixed{} && body.inverse_inertia == Mat33{}) return {};
  const Vec3 turn = body.inverse_inertia * arm;
  return {d * body.inverse_mass, turn, dot(arm, turn)};
}

}  // namespace

// Whether a body does not move in the solve (static, kinematic, asleep):
// zero inverse mass and inertia, so its products in a row are all zero.
bool immovable(const SolverBody& body) { return body.inverse_mass == Fixed{} && body.inverse_inertia == Mat33{}; }

Jacobian make_jacobian(const SolverBody& a, const SolverBody& b, Vec3 ra, Vec3 rb, Vec3 d) {
  const Vec3 arm_a = cross(ra, d), arm_b = cross(rb, d);
  const BodyPart part_a = body_part(a, arm_a, d), part_b = body_part(b, arm_b, d);
  Jacobian j{d, arm_a, arm_b, part_a.linear, part_b.linear, part_a.turn, part_b.turn, {}};
  // J M^-1 J^T = 1/m_a + 1/m_b + (r_a x d) . I_a^-1 (r_a x d) + (r_b x d) . I_b^-1 (r_b x d)
  const Fixed k = a.inverse_mass + b.inverse_mass + part_a.angular_mass + part_b.angular_mass;
  j.mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
  return j;
}

// The angular row (w_b - w_a) . n.
AngularPart make_twist(const SolverBody& a, const SolverBody& b, Vec3 n) {
  AngularPart j{n, a.inverse_inertia * n, b.inverse_inertia * n, {}};
  const Fixed k = dot(n, j.turn_a) + dot(n, j.turn_b);
  j.mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
  return j;
}


// Friction at the centroid: the impulse that stops sliding is kept while
// within the static cone |j_t| <= mu_s j_n (j_n the manifold's total normal
// impulse), else scaled onto the dynamic cone mu_d j_n; the twist likewise
// with the cone scaled by the points' mean radius; then rolling resistance.
template <class Row>
void solve_friction(SolverBody& a, SolverBody& b, const Row& m) {
  const Fixed normal = total_normal_impulse(m);
  Fixed (&friction)[2] = friction_impulse(m);
  Fixed& twist_total = twist_impulse(m);
  Fixed (&rolling)[2] = rolling_impulse(m);
  if (normal == Fixed{}) {
    // No normal impulse (a speculative contact, bricks side by side): every
    // cone below has radius 0, so each row's new impulse is 0 whatever the
    // relative rates (kept at 0, or scaled onto the zero disc): the same
    // bits without their products, square root and divisions.
    const Fixed old[5] = {friction[0], friction[1], twist_total, rolling[0], rolling[1]};
    friction[0] = friction[1] = twist_total = Fixed{};
    apply_impulse(a, b, m.tangent[0], -old[0]);
    apply_impulse(a, b, m.tangent[1], -old[1]);
    apply_spin(a, b, m.twist, -old[2]);
    if (m.rolling_limit > Fixed{}) {
      rolling[0] = rolling[1] = Fixed{};
      apply_spin(a, b, m.rolling[0], -old[3]);
      apply_spin(a, b, m.rolling[1], -old[4]);
    }
    return;
  }

  // mu_s j_n: the tangents' disc radius, the product mu_s * j_n in range.
  const Fixed static_limit =
      solve_disc(a, b, m.tangent, friction, m.static_friction, m.dynamic_friction, normal);

  const Fixed old_twist = twist_total;
  Fixed twist = old_twist - mul_in_range(m.twist.mass, relative_spin(a, b, m.twist));
  const Fixed twist_limit = static_limit * m.twist_radius;
  if (abs(twist) > twist_limit) {
    const Fixed slide = m.dynamic_friction * normal * m.twist_radius;
    twist = twist < Fixed{} ? -slide : slide;
  }
  twist_total = twist;
  apply_spin(a, b, m.twist, twist - old_twist);

  // Rolling resistance: the angular impulse that stops the relative rotation
  // in the contact plane, within the disc |j_r| <= c r j_n (Box2D v3's, about
  // two axes in 3D). Warm-started like friction: started from zero every step
  // it lagged the normal and friction rows it balances, and the lag drove a
  // steady creep in proportion to c.
  if (m.rolling_limit > Fixed{}) {
    solve_disc(a, b, m.rolling, rolling, m.rolling_limit, m.rolling_limit, normal);
  }
}


template <class Row>
void solve_manifold_normal(SolverBody& a, SolverBody& b, const Row& m) {
  if (m.count < 2) return;  // a single point is its own centroid
  const Fixed vn = relative_velocity(a, b, m.normal);
  Fixed share = mul_in_range(m.share_mass, m.velocity_target - vn);
  // Each point's accumulated impulse stays >= 0.
  for (size_t i = 0; i < m.count; ++i) share = max(share, -normal_impulse(m, i));
  for (size_t i = 0; i < m.count; ++i) normal_impulse(m, i) += share;
  // The solver's in-range form (an impulse times 2..4): the bits of *, and
  // an impulse gcc multiplies with one instruction a product (from *'s
  // saturated result it took three).
  apply_impulse(a, b, m.normal, mul_in_range(share, Fixed::from_int(static_cast<int32_t>(m.count))));
}

// Drives the relative rocking rate to zero, keeping every point's
// accumulated normal impulse >= 0 (contacts push, never pull).
namespace {

// lambda held to what a face's points can take: |lambda alpha_i| <= 2^29
// N s. A face too small for the moment it is asked (a 1e5 kg box spinning
// on a 1 cm die: alpha ~ 1 / 1 cm) would otherwise ask point impulses
// past the range. Decided on the exact product; within it, lambda itself.
// |alpha_i| <= 1 / sqrt(S) <= 100 (make_rocking keeps S >= 1e-4), so
// below 2^22 lambda needs no check.
constexpr Fixed unchecked_rocking = Fixed::from_raw(int64_t{1} << 54);  // 2^22

[[gnu::noinline]] Fixed within_points_range(Fixed lambda, const ManifoldRow::Rocking& r, size_t count) {
  constexpr Fixed most = Fixed::from_raw(int64_t{1} << 61);  // 2^29
  Fixed largest;
  for (size_t i = 0; i < count; ++i) largest = max(largest, abs(r.alpha[i]));
  if (!product_exceeds(abs(lambda), largest, most)) return lambda;
  const Fixed cap = most / largest;
  return lambda < Fixed{} ? -cap : cap;
}

}  // namespace

template <class Row>
void solve_rocking(SolverBody& a, SolverBody& b, const Row& m) {
  for (const ManifoldRow::Rocking& r : m.rocking) {
    if (!r.active) continue;
    Fixed lambda = -mul_in_range(r.row.mass, relative_spin(a, b, r.row));
    if (abs(lambda) >= unchecked_rocking) lambda = within_points_range(lambda, r, m.count);
    // lambda = 0 changes nothing (each lambda alpha_i rounds to 0) unless a
    // point pulls already, which the bound below would correct.
    if (lambda == Fixed{} && none_pull(m)) continue;
    // jn_i + lambda alpha_i >= 0 for every point; the bound -jn_i / alpha_i
    // is divided out only for a point that would pull. Unclamped (the
    // usual case), the sums checked are the new impulses as they are.
    Fixed next[max_manifold_points];
    bool clamped = false;
    for (size_t i = 0; i < m.count; ++i) {
      const Fixed alpha = r.alpha[i];
      const Fixed jn = normal_impulse(m, i);
      next[i] = jn + mul_in_range(lambda, alpha);
      if (next[i] >= Fixed{}) continue;
      clamped = true;
      if (alpha > Fixed{}) lambda = max(lambda, -jn / alpha);
      if (alpha < Fixed{}) lambda = min(lambda, jn / -alpha);
    }
    for (size_t i = 0; i < m.count; ++i) {
      Fixed& jn = normal_impulse(m, i);
      jn = clamped ? max(jn + mul_in_range(lambda, r.alpha[i]), Fixed{}) : next[i];
    }
    apply_spin(a, b, r.row, lambda);
  }
}

template void solve_friction(SolverBody&, SolverBody&, const ManifoldRow&);
template void solve_friction(SolverBody&, SolverBody&, const FrictionRow&);
template void solve_manifold_normal(SolverBody&, SolverBody&, const ManifoldRow&);
template void solve_manifold_normal(SolverBody&, SolverBody&, const CentroidRow&);
template void solve_rocking(SolverBody&, SolverBody&, const ManifoldRow&);
template void solve_rocking(SolverBody&, SolverBody&, const RockingRow&);

namespace {

// The point rows of manifold row i: from its first to the next one's
// (every point of the manifold, in point order; count are those held).
size_t rows_end(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows, size_t i) {
  return i + 1 < manifolds.size() ? manifolds[i + 1].first : rows.size();
}

struct CopyRun {
  const std::vector<ManifoldRow>& manifolds;
  const std::vector<PointRow>& rows;
  SweepRows* out;            // the copies being made
  const SweepRows* copies;   // the copies written back
  size_t workers;
  // Manifolds [begin, end) of worker w's share.
  size_t begin(size_t w) const { return manifolds.size() * w / workers; }
  size_t end(size_t w) const { return manifolds.size() * (w + 1) / workers; }
};

// What each list takes from one worker's share.
void count_copies(void* context, int worker) {
  CopyRun& run = *static_cast<CopyRun*>(context);
  const size_t w = static_cast<size_t>(worker);
  SweepRows::Starts counts{};
  for (size_t i = run.begin(w); i < run.end(w); ++i) {
    const ManifoldRow& m = run.manifolds[i];
    if (has_centroid_row(m)) ++counts.centroids;
    if (has_rocking_rows(m)) ++counts.rocking;
    const size_t end = rows_end(run.manifolds, run.rows, i);
    for (size_t r = m.first; r < end; ++r) {
      if (is_free_row(run.rows[r])) ++counts.free;
    }
  }
  run.out->starts[w] = counts;
}

void fill_copies(void* context, int worker) {
  CopyRun& run = *static_cast<CopyRun*>(context);
  const size_t w = static_cast<size_t>(worker);
  SweepRows& out = *run.out;
  const std::vector<PointRow>& rows = run.rows;
  SweepRows::Starts at = out.starts[w];
  for (size_t i = run.begin(w); i < run.end(w); ++i) {
    const ManifoldRow& m = run.manifolds[i];
    const Manifold& manifold = *m.manifold;
    ManifoldImpulses& impulses = out.impulses[i];
    impulses = {{},
                {manifold.friction_impulse[0], manifold.friction_impulse[1]},
                manifold.twist_impulse,
                {manifold.rolling_impulse[0], manifold.rolling_impulse[1]}};
    const size_t end = rows_end(run.manifolds, rows, i);
    for (size_t r = m.first; r < end; ++r) {
      const PointRow& row = rows[r];
      Fixed& jn = impulses.normal[r - m.first];
      jn = row.point->normal_impulse;
      if (is_free_row(row)) out.free[at.free++] = {row.a, row.b, row.normal, row.velocity_target, &jn};
    }
    out.friction[i] = {m.a,     m.b,     m.count,           &impulses,          {m.tangent[0], m.tangent[1]},
                       m.twist, m.static_friction, m.dynamic_friction, m.twist_radius, m.rolling_limit,
                       m.rolling};
    if (has_centroid_row(m)) {
      out.centroids[at.centroids++] = {m.a, m.b, m.count, &impulses, m.normal, m.share_mass, m.velocity_target};
    }
    if (has_rocking_rows(m)) out.rocking[at.rocking++] = {m.a, m.b, m.count, &impulses, {m.rocking[0], m.rocking[1]}};
  }
}

void write_back(void* context, int worker) {
  const CopyRun& run = *static_cast<CopyRun*>(context);
  const size_t w = static_cast<size_t>(worker);
  for (size_t i = run.begin(w); i < run.end(w); ++i) {
    const ManifoldRow& m = run.manifolds[i];
    Manifold& manifold = *m.manifold;
    const ManifoldImpulses& impulses = run.copies->impulses[i];
    const size_t end = rows_end(run.manifolds, run.rows, i);
    for (size_t r = m.first; r < end; ++r) run.rows[r].point->normal_impulse = impulses.normal[r - m.first];
    manifold.friction_impulse[0] = impulses.friction[0];
    manifold.friction_impulse[1] = impulses.friction[1];
    manifold.twist_impulse = impulses.twist;
    manifold.rolling_impulse[0] = impulses.rolling[0];
    manifold.rolling_impulse[1] = impulses.rolling[1];
  }
}

void run_on(Executor* executor, Executor::Task task, CopyRun& run) {
  if (run.workers > 1) {
    executor->run(task, &run);
  } else {
    task(&run, 0);
  }
}

}  // namespace

void split_sweep_rows(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows, SweepRows& out,
                      Executor* executor) {
  const size_t workers = executor ? static_cast<size_t>(executor->workers()) : 1;
  CopyRun run{manifolds, rows, &out, &out, workers};
  out.starts.resize(workers);
  run_on(executor, count_copies, run);
  SweepRows::Starts total{};
  for (SweepRows::Starts& s : out.starts) {
    const SweepRows::Starts counts = s;
    s = total;
    total.centroids += counts.centroids;
    total.rocking += counts.rocking;
    total.free += counts.free;
  }
  out.impulses.resize(manifolds.size());
  out.friction.resize(manifolds.size());
  out.centroids.resize(total.centroids);
  out.rocking.resize(total.rocking);
  out.free.resize(total.free);
  run_on(executor, fill_copies, run);
}

void write_back_impulses(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows,
                         const SweepRows& copies, Executor* executor) {
  const size_t workers = executor ? static_cast<size_t>(executor->workers()) : 1;
  CopyRun run{manifolds, rows, nullptr, &copies, workers};
  run_on(executor, write_back, run);
}

// One pass over a manifold: friction, the centroid row, rocking, then its
// points (in alternating direction).
void solve_manifold(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows, const ManifoldRow& m, int pass) {
  SolverBody& a = bodies[m.a];
  SolverBody& b = bodies[m.b];
  solve_friction(a, b, m);
  solve_manifold_normal(a, b, m);
  solve_rocking(a, b, m);
  for (size_t k = 0; k < m.count; ++k) {
    const PointRow& row = rows[m.first + (pass % 2 == 0 ? k : m.count - 1 - k)];
    solve_normal(a, b, row);
  }
}

void save_impulses(const std::vector<Contact>& contacts, std::vector<Fixed>& out) {
  out.clear();
  for (const Contact& c : contacts) {
    const Manifold& m = c.manifold;
    out.insert(out.end(),
               {m.friction_impulse[0], m.friction_impulse[1], m.twist_impulse, m.rolling_impulse[0], m.rolling_impulse[1]});
    for (int i = 0; i < m.point_count; ++i) out.push_back(m.points[static_cast<size_t>(i)].normal_impulse);
  }
}

void restore_impulses(const std::vector<Fixed>& saved, std::vector<Contact>& contacts) {
  size_t k = 0;
  for (Contact& c : contacts) {
    Manifold& m = c.manifold;
    m.friction_impulse[0] = saved[k++];
    m.friction_impulse[1] = saved[k++];
    m.twist_impulse = saved[k++];
    m.rolling_impulse[0] = saved[k++];
    m.rolling_impulse[1] = saved[k++];
    for (int i = 0; i < m.point_count; ++i) m.points[static_cast<size_t>(i)].normal_impulse = saved[k++];
  }
}

}  // namespace bitstep
