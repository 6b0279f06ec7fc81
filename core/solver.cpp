#include "core/solver.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include "core/islands.h"
#include "core/shock.h"
#include "core/solver_rows.h"

namespace bitstep {

namespace {

// Manifolds per worker below which the sweeps stay on one thread: waking the
// workers costs more than they save.
constexpr size_t min_parallel_manifolds = 32;
// The same for the row setup, whose work per manifold is a tenth of the
// iterations': shared among two workers, thrown's ~150 settled manifolds
// took 5% longer.
constexpr size_t min_parallel_row_setups = 128;

// An orthonormal pair perpendicular to the unit vector n (fixed choice, so
// warm-started friction impulses keep their meaning between steps).
void tangent_basis(Vec3 n, Vec3& t1, Vec3& t2) {
  const Vec3 axis = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  t1 = normalize(cross(n, axis));
  t2 = cross(n, t1);
}

// A rocking row about the in-plane axis e of a manifold with centroid c: the
// point impulses lambda alpha_i n, alpha_i = ((d_i x n) . e) / S with
// d_i = p_i - c and S = sum ((d_i x n) . e)^2, add up to no force (sum d_i = 0)
// and to the angular impulse lambda u, u = sum alpha_i (d_i x n); the row
// measures (w_b - w_a) . u. Solving it resolves a face's tilt in one step
// where the point rows alone need many passes (a tall stack's rocking mode).
// `arms`: the first `count` points' d_i x n, the same for both axes.
ManifoldRow::Rocking make_rocking(const SolverBody& a, const SolverBody& b, const Vec3 (&arms)[max_manifold_points],
                                  int count, Vec3 e) {
  ManifoldRow::Rocking r;
  Fixed along[max_manifold_points];  // (d_i x n) . e
  Fixed s;
  for (int i = 0; i < count; ++i) {
    along[i] = dot(arms[i], e);
    s += along[i] * along[i];
  }
  if (s < 0.0001_fx) return r;  // the points lie on a line along e: no lever about it
  Vec3 u;
  for (int i = 0; i < count; ++i) {
    r.alpha[i] = along[i] / s;
    u += arms[i] * r.alpha[i];
  }
  r.row = make_twist(a, b, u);
  r.active = r.row.mass > Fixed{};
  return r;
}

// A point at `depth` (m, < 0: a gap) approaching at `speed` (m/s) meets
// its surface within the step dt: it overlaps already, or covers the gap.
bool meets_at(Fixed depth, Fixed speed, Fixed dt) { return depth >= Fixed{} || speed * dt >= -depth; }

// The collision pass solves only the manifolds where something hits: a
// point that meets this step approaching faster than the restitution
// threshold. Resting contacts wait for the contact pass.
bool impacts(const Settings& settings, const Body& body_a, const Body& body_b, const SolverBody& a,
             const SolverBody& b, const Manifold& m) {
  for (int i = 0; i < m.point_count; ++i) {
    const ContactPoint& p = m.points[static_cast<size_t>(i)];
    const Vec3 ra = p.position - body_a.pose.position, rb = p.position - body_b.pose.position;
    const Vec3 relative = b.velocity.linear + cross(b.velocity.angular, rb) - a.velocity.linear -
                          cross(a.velocity.angular, ra);
    const Fixed approach = -dot(relative, m.normal);
    if (meets_at(p.depth, approach, settings.dt) && approach > settings.restitution_threshold) return true;
  }
  return false;
}

// Orders a manifold's points so that those that touch come first and
// returns how many: the manifold's own rows (centroid, rocking, friction,
// the shock step's block) stand on these alone. A point still apart is a
// speculative row of its own: shared into the centroid row it was pushed
// where nothing touches, and the rows that then took the push back from it
// tilted the body (a leaning plate's foot: the point pairs of its two bottom
// edges, one touching, one 7 mm up). All of them when none touches.
// A stable partition through a copy on the stack (std::stable_partition
// takes a heap buffer: a settled step allocates nothing).
int hold_touching_first(Manifold& m) {
  const auto touches = [](const ContactPoint& p) { return p.depth >= -touch_tolerance; };
  const size_t count = static_cast<size_t>(m.point_count);
  // Already in order (no touching point after one apart: every point of a
  // resting face), the partition would copy each point onto itself.
  const auto first = m.points.begin(), last = first + static_cast<std::ptrdiff_t>(count);
  if (std::is_partitioned(first, last, touches)) {
    const auto held = std::partition_point(first, last, touches) - first;
    return held > 0 ? static_cast<int>(held) : m.point_count;
  }
  std::array<ContactPoint, max_manifold_points> ordered;
  size_t held = 0;
  for (size_t i = 0; i < count; ++i) {
    if (touches(m.points[i])) ordered[held++] = m.points[i];
  }
  for (size_t i = 0, k = held; i < count; ++i) {
    if (!touches(m.points[i])) ordered[k++] = m.points[i];
  }
  std::copy_n(ordered.begin(), count, m.points.begin());
  return held > 0 ? static_cast<int>(held) : m.point_count;
}

// The radius a shape rolls on (m): a sphere's or a capsule's; a box does
// not roll.
Fixed rolling_radius(const Shape& shape) { return shape.type == ShapeType::box ? Fixed{} : shape.radius; }

void gather_bodies(const std::vector<Body>& bodies, std::vector<SolverBody>& out) {
  out.assign(bodies.size(), SolverBody{});
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& body = bodies[i];
    if (!body.alive || body.asleep) continue;  // a sleeping body is immovable: zero inverse mass
    out[i] = {{body.linear_velocity, body.angular_velocity}, {}, body.inverse_mass, body.inverse_inertia_world};
  }
  for (SolverBody& body : out) body.still = immovable(body) && body.velocity == BodyRates{};
}

// A worker's last pair friction and tangent basis in the row setup, each a
// function of its inputs alone (the two bodies' coefficients; the normal):
// consecutive contacts of a pile often share their materials, or their
// normal (bodies on the ground), and take the square roots and the
// normalisation found for the contact before.
class RowMemo {
 public:
  // The pair's static and dynamic friction: the geometric means.
  void friction(const Material& a, const Material& b, Fixed& mu_s, Fixed& mu_d) {
    if (!mixed_ || !(a.static_friction == static_a_ && b.static_friction == static_b_ &&
                     a.dynamic_friction == dynamic_a_ && b.dynamic_friction == dynamic_b_)) {
      mixed_ = true;
      static_a_ = a.static_friction;
      static_b_ = b.static_friction;
      dynamic_a_ = a.dynamic_friction;
      dynamic_b_ = b.dynamic_friction;
      mu_s_ = sqrt(static_a_ * static_b_);
      mu_d_ = sqrt(dynamic_a_ * dynamic_b_);
    }
    mu_s = mu_s_;
    mu_d = mu_d_;
  }
  void tangents(Vec3 n, Vec3& t1, Vec3& t2) {
    if (!based_ || !(n == normal_)) {
      based_ = true;
      normal_ = n;
      tangent_basis(n, t1_, t2_);
    }
    t1 = t1_;
    t2 = t2_;
  }

 private:
  bool mixed_ = false, based_ = false;
  Fixed static_a_, static_b_, dynamic_a_, dynamic_b_, mu_s_, mu_d_;
  Vec3 normal_, t1_, t2_;
};

// What a manifold's pose-dependent rows are computed from (row_cache.h),
// its points already in row order.
RowInputs row_inputs(const Contact& contact, int held) {
  const Manifold& m = contact.manifold;
  RowInputs in{contact.key, m.normal, m.point_count, held, {}};
  for (int i = 0; i < m.point_count; ++i) in.points[static_cast<size_t>(i)] = m.points[static_cast<size_t>(i)].position;
  return in;
}

// What every solved contact's row setup reads and writes: manifold
// `slot`'s rows are built into place.
struct RowSetup {
  const Settings& settings;
  const std::vector<Body>& bodies;
  const std::vector<SolverBody>& solver_bodies;
  const std::vector<BodyRates>& start_velocities;
  std::vector<Contact>& contacts;
  SolvePass pass;
  std::vector<PointRow>& rows;
  std::vector<ManifoldRow>& manifold_rows;
  RowCache* cache;  // null: build every row
  const std::vector<PointRow>& last_rows;
  const std::vector<ManifoldRow>& last_manifolds;
  const std::vector<SolvedContact>& solved;
  Fixed inverse_dt;
  int workers;
  uint64_t* reused;  // per worker: manifolds whose rows were reused
  bool in_place;     // last_rows, last_manifolds and the cache's entries are this solve's own
};

// The rows of the solved contact `slot`: its point rows at rows[first ..)
// and its manifold row at manifold_rows[slot]; with a cache, last step's
// pose-dependent parts where its RowInputs did not change by a bit (found
// from `cursor`, which walks the cache's entries in key order). Whether
// they were reused.
bool build_rows(const RowSetup& setup, size_t slot, size_t& cursor, RowMemo& memo) {
  const Settings& settings = setup.settings;
  const std::vector<Body>& bodies = setup.bodies;
  const std::vector<SolverBody>& solver_bodies = setup.solver_bodies;
  const std::vector<BodyRates>& start_velocities = setup.start_velocities;
  const SolvePass pass = setup.pass;
  std::vector<PointRow>& rows = setup.rows;
  std::vector<ManifoldRow>& manifold_rows = setup.manifold_rows;
  RowCache* cache = setup.cache;
  const std::vector<PointRow>& last_rows = setup.last_rows;
  const std::vector<ManifoldRow>& last_manifolds = setup.last_manifolds;
  const Fixed inverse_dt = setup.inverse_dt;
  Contact& contact = setup.contacts[setup.solved[slot].contact];
  const size_t first = setup.solved[slot].first_row;
  const uint32_t ia = contact.key.body_a, ib = contact.key.body_b;
  const Body& body_a = bodies[ia];
  const Body& body_b = bodies[ib];
  const SolverBody& a = solver_bodies[ia];
  const SolverBody& b = solver_bodies[ib];
  Manifold& m = contact.manifold;
  // Pair mixing: the larger restitution; friction below.
  const Fixed restitution = max(body_a.material.restitution, body_b.material.restitution);
  // Box pairs roll on nothing: no square root for them.
  const Fixed roll_radius =
      max(rolling_radius(body_a.shapes[contact.key.shape_a]), rolling_radius(body_b.shapes[contact.key.shape_b]));
  const Fixed rolling_limit =
      roll_radius > Fixed{}
          ? sqrt(body_a.material.rolling_resistance * body_b.material.rolling_resistance) * roll_radius
          : Fixed{};
  const int held = hold_touching_first(m);
  const RowCache::Entry* reuse = nullptr;
  if (cache) {
    const RowInputs inputs = row_inputs(contact, held);
    reuse = cache->find(inputs, cursor);
    // In place, this slot's entry was last step's for the same key and
    // rows, read just now by find and by no other slot; found there, it
    // holds these inputs, rows and slot already.
    if (!(setup.in_place && reuse == &cache->entries[slot])) {
      (setup.in_place ? cache->entries : cache->next)[slot] = {inputs, first, slot};
    }
  }
  // Friction: the geometric means of the bodies' coefficients, as last
  // step's rows hold them where they are reused (their bodies' are equal).
  Fixed mu_s, mu_d;
  if (reuse) {
    mu_s = last_manifolds[reuse->manifold_row].static_friction;
    mu_d = last_manifolds[reuse->manifold_row].dynamic_friction;
  } else {
    memo.friction(body_a.material, body_b.material, mu_s, mu_d);
  }
  // The tangents (a fixed choice per normal, so warm-started friction
  // keeps its meaning), for the rows that are built.
  Vec3 t1, t2;
  if (!reuse || (rolling_limit > Fixed{} && last_manifolds[reuse->manifold_row].rolling_limit == Fixed{})) {
    memo.tangents(m.normal, t1, t2);
  }
  Vec3 centroid;
  Fixed target;
  for (int i = 0; i < m.point_count; ++i) {
    ContactPoint& p = m.points[static_cast<size_t>(i)];
    const Vec3 ra = p.position - body_a.pose.position, rb = p.position - body_b.pose.position;
    // Built where it lies (in place, a reused Jacobian is there already).
    PointRow& row = rows[first + static_cast<size_t>(i)];
    if (!reuse) {
      row.normal = make_jacobian(a, b, ra, rb, m.normal);
    } else {
      const Jacobian& last = last_rows[reuse->first_row + static_cast<size_t>(i)].normal;
      if (&last != &row.normal) row.normal = last;
    }
    row.a = ia;
    row.b = ib;
    row.push_target = Fixed{};
    row.point = &p;
    row.in_resting_face = row.impact = false;
    const Fixed approach = relative_velocity(a, b, row.normal);
    // A gap (depth < 0) may close by depth / dt this step: speculative contact.
    row.velocity_target = p.depth < Fixed{} ? p.depth * inverse_dt : Fixed{};
    // An impact: the surfaces meet this step (or already overlap) faster
    // than the restitution threshold. The bounce is placed at the moment
    // of impact. With s the approach speed before this step's forces and
    // a the relative normal acceleration they give (gravity), the impact
    // time from the start of the step is t = -depth / s (< 0 when the
    // shapes already overlap), the approach speed then s - a t, and the
    // point leaves at e (s - a t). By the end of the step, tau = dt - t
    // after the impact, it is e (s - a t) tau + a tau^2 / 2 above the
    // surface moving at e (s - a t) + a tau. The velocity row asks for that
    // speed; the rest of the displacement goes through the split-impulse
    // channel as an exact pseudo-velocity (a pull when the gap was still
    // open), so the rebound height does not depend on where in the step
    // the impact fell.
    const bool meets = meets_at(p.depth, -approach, settings.dt);
    // The approach speed before this step's forces (nine products) is read
    // only by the two bounces below, each of which also asks what may_bounce
    // does: where it is false, neither reads the 0 in its place.
    const bool may_bounce = (pass == SolvePass::standard && meets && approach < Fixed{}) ||
                            (pass == SolvePass::contact && p.depth < Fixed{} && restitution > Fixed{});
    const Fixed start_speed =
        may_bounce ? -relative_rate(start_velocities[ia], start_velocities[ib], row.normal) : Fixed{};
    if (pass == SolvePass::collision) {
      // JigLib's collision pass: a point that meets this step
      // leaves at e times its approach speed (the velocities have no
      // forces yet); nothing is pushed apart. With e = 0 it only arrives:
      // a gap closes by depth / dt, as in the iterations.
      if (meets && -approach > settings.restitution_threshold && restitution > Fixed{}) {
        row.velocity_target = -approach * restitution;
      }
      centroid += p.position;
      target += row.velocity_target;
      continue;
    }
    if (pass == SolvePass::standard && meets && start_speed > settings.restitution_threshold &&
        approach < Fixed{}) {
      const Fixed acceleration = (approach + start_speed) * inverse_dt;
      const Fixed impact_time = -min(p.depth / start_speed, settings.dt);  // t, at least -dt
      const Fixed after = settings.dt - impact_time;                          // tau
      const Fixed leave = restitution * (start_speed - acceleration * impact_time);
      const Fixed bounce = leave + acceleration * after;
      if (bounce > Fixed{}) {
        row.velocity_target = bounce;
        row.impact = true;
        // (depth + leave tau + a tau^2 / 2 - bounce dt) / dt
        const Fixed rest = p.depth + leave * (after - settings.dt) + acceleration * after * (after / 2.0_fx - settings.dt);
        row.push_target = rest * inverse_dt;
      }
    }
    if (pass == SolvePass::contact && p.depth < Fixed{} && meets_at(p.depth, start_speed, settings.dt) &&
        start_speed > settings.restitution_threshold && restitution > Fixed{}) {
      // The collision pass bounced this point from a gap, as if the
      // surfaces had met at the start of the step: it leaves at
      // e s from where it is. The bounce belongs to the moment of impact,
      // t = -depth / s, and by the end of the step the point should be
      // e s (dt - t) from the surface, not -depth + e s dt: the difference
      // goes through the split-impulse channel as an exact pull (depth -
      // e s t) / dt, so the body reaches the surface however fast it came
      // (it stopped in mid-air up to a step's travel short).
      // The velocity row holds what the bounce left (no further approach).
      const Fixed leave = restitution * start_speed;
      row.velocity_target = Fixed{};
      row.impact = true;
      row.push_target = (p.depth - leave * (-p.depth / start_speed)) * inverse_dt;
    }
    const Fixed excess = p.depth - settings.penetration_slop;
    if (excess > Fixed{} && !row.impact) {
      const Fixed factor = settings.baumgarte ? settings.baumgarte_factor : settings.split_impulse_factor;
      const Fixed recovery = min(factor * excess * inverse_dt, settings.max_push_out_speed);
      if (settings.baumgarte) {
        row.velocity_target = max(row.velocity_target, recovery);
      } else {
        row.push_target = recovery;
      }
    }
    p.split_impulse = Fixed{};
    if (i < held) {
      centroid += p.position;
      target += row.velocity_target;
    }
  }
  const Fixed count = Fixed::from_int(held);
  if (reuse) {
    // The same Jacobians, offsets, twist radius and rocking rows as last
    // step's (rolling rows too where last step built them).
    // In place they are this slot's own row already (a settled scene's
    // every row: a kilobyte each not copied onto itself).
    const ManifoldRow& last = last_manifolds[reuse->manifold_row];
    if (&last != &manifold_rows[slot]) manifold_rows[slot] = last;
    ManifoldRow& face = manifold_rows[slot];
    face.first = first;
    face.velocity_target = target / count;
    face.static_friction = mu_s;
    face.dynamic_friction = mu_d;
    face.manifold = &m;
    face.one_sided = false;
  } else {
    centroid = centroid / count;
    Fixed radius;
    for (int i = 0; i < held; ++i) radius += length(m.points[static_cast<size_t>(i)].position - centroid);
    const Vec3 ra = centroid - body_a.pose.position, rb = centroid - body_b.pose.position;
    Vec3 arms[max_manifold_points];  // (p_i - c) x n, for both rocking rows
    for (int i = 0; i < held; ++i) arms[i] = cross(m.points[static_cast<size_t>(i)].position - centroid, m.normal);
    manifold_rows[slot] = {ia, ib, first, static_cast<size_t>(held), make_jacobian(a, b, ra, rb, m.normal),
                             {make_jacobian(a, b, ra, rb, t1), make_jacobian(a, b, ra, rb, t2)},
                             make_twist(a, b, m.normal), ra, rb, target / count, radius / count, mu_s, mu_d, &m,
                             {make_rocking(a, b, arms, held, t1), make_rocking(a, b, arms, held, t2)},
                             {}, false, {}, Fixed{}};
    ManifoldRow& face = manifold_rows[slot];
    face.share_mass = face.normal.mass / count;
  }
  manifold_rows[slot].index = static_cast<uint32_t>(slot);
  manifold_rows[slot].reused_from = reuse ? static_cast<uint32_t>(reuse->manifold_row) : ManifoldRow::none;
  // A resting face (3 or more touching points asking for no relative
  // speed) has three normal degrees of freedom, its centroid row and two
  // rocking rows, which keep every point pushing: its point rows would only
  // redistribute impulse between the points, so the iterations skip them.
  ManifoldRow& face = manifold_rows[slot];
  if (rolling_limit > Fixed{}) {
    if (!reuse || face.rolling_limit == Fixed{}) {
      face.rolling[0] = make_twist(a, b, t1);
      face.rolling[1] = make_twist(a, b, t2);
    }
    face.rolling_limit = rolling_limit;
  } else {
    face.rolling[0] = face.rolling[1] = AngularPart{};
    face.rolling_limit = Fixed{};
    m.rolling_impulse[0] = m.rolling_impulse[1] = Fixed{};
  }
  const size_t held_end = first + static_cast<size_t>(held);
  bool resting = held >= 3 && face.rocking[0].active && face.rocking[1].active;
  for (size_t k = first; k < held_end; ++k) {
    resting = resting && rows[k].velocity_target == Fixed{} && rows[k].point->depth >= Fixed{};
  }
  for (size_t k = first; k < held_end; ++k) rows[k].in_resting_face = resting;
  return reuse != nullptr;
}

// Worker w builds the w-th contiguous share of the solved contacts.
void build_rows_of_worker(void* context, int worker) {
  const RowSetup& setup = *static_cast<const RowSetup*>(context);
  if (worker >= setup.workers) return;
  const size_t n = setup.solved.size(), w = static_cast<size_t>(worker), workers = static_cast<size_t>(setup.workers);
  const size_t begin = n * w / workers, end = n * (w + 1) / workers;
  if (begin == end) return;
  size_t cursor = !setup.cache     ? 0
                  : setup.in_place ? begin  // the entries lie as the contacts do
                                   : setup.cache->cursor_at(setup.contacts[setup.solved[begin].contact].key);
  uint64_t reused = 0;
  RowMemo memo;
  for (size_t slot = begin; slot < end; ++slot) reused += build_rows(setup, slot, cursor, memo) ? 1u : 0u;
  setup.reused[w] = reused;
}

// The contacts this solve takes (an awake body; in the collision pass, only
// those that hit), in order, and where each one's point rows begin
// (`solved`); the number of point rows.
size_t plan_rows(const Settings& settings, const std::vector<Body>& bodies, const std::vector<SolverBody>& solver_bodies,
                 const std::vector<Contact>& contacts, SolvePass pass, std::vector<SolvedContact>& solved) {
  solved.clear();
  size_t row_count = 0;
  for (uint32_t c = 0; c < contacts.size(); ++c) {
    const Contact& contact = contacts[c];
    const Body& body_a = bodies[contact.key.body_a];
    const Body& body_b = bodies[contact.key.body_b];
    if (!is_awake_dynamic(body_a) && !is_awake_dynamic(body_b)) continue;  // asleep: kept, not solved
    if (pass == SolvePass::collision && !impacts(settings, body_a, body_b, solver_bodies[contact.key.body_a],
                                                 solver_bodies[contact.key.body_b], contact.manifold)) {
      continue;
    }
    solved.push_back({c, row_count});
    row_count += static_cast<size_t>(contact.manifold.point_count);
  }
  return row_count;
}

// Sizes the rows and builds every planned contact's (plan_rows, build_rows)
// into rows and manifold_rows, on the executor's workers when there are
// enough: each contact's rows are a function of its own inputs, written
// into their own places, so the same bits on any number. Last step's parts
// come from last_rows and last_manifolds where the cache finds them. Those may be rows and manifold_rows themselves when the plan lays
// every contact where the last cached solve did (in_place; the cache's
// entries are then rewritten where they lie too): each slot then reads only
// its own last contents, before it writes them.
void prepare_rows(const Settings& settings, const std::vector<Body>& bodies,
                  const std::vector<SolverBody>& solver_bodies, const std::vector<BodyRates>& start_velocities,
                  std::vector<Contact>& contacts, SolvePass pass, size_t row_count, std::vector<PointRow>& rows,
                  std::vector<ManifoldRow>& manifold_rows, RowCache* cache, const std::vector<PointRow>& last_rows,
                  const std::vector<ManifoldRow>& last_manifolds, const std::vector<SolvedContact>& solved,
                  bool in_place, Executor* executor) {
  // Resized, not cleared: in a steady scene the sizes stay and nothing is
  // written twice.
  rows.resize(row_count);
  manifold_rows.resize(solved.size());
  if (cache && !in_place) cache->next.resize(solved.size());
  const bool parallel =
      executor && executor->workers() > 1 && solved.size() >= min_parallel_row_setups * static_cast<size_t>(executor->workers());
  const int workers = parallel ? std::min(executor->workers(), max_workers) : 1;
  uint64_t reused[max_workers] = {};
  RowSetup setup{settings,       bodies, solver_bodies, start_velocities,          contacts, pass,    rows,
                       manifold_rows,  cache,  last_rows,     last_manifolds,            solved,   Fixed::one() / settings.dt,
                       workers,        reused,        in_place};
  if (parallel) {
    executor->run(build_rows_of_worker, &setup);
  } else {
    build_rows_of_worker(&setup, 0);
  }
  if (cache) {
    uint64_t total = 0;
    for (int w = 0; w < workers; ++w) total += reused[w];
    cache->reused += total;
    cache->built += solved.size() - total;
  }
}

void warm_start(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                const std::vector<ManifoldRow>& manifold_rows) {
  for (const PointRow& row : rows) warm_start_point(bodies[row.a], bodies[row.b], row);
  for (const ManifoldRow& m : manifold_rows) warm_start_manifold(bodies[m.a], bodies[m.b], m);
}

// The iterations' point rows: those outside a resting face, whose rows the
// manifold's centroid and rocking rows stand for (build_rows), in order. A
// standing wall's are almost none: listed once, the ~220-byte rows are not
// loaded again in every pass only to be skipped.
void sweep_free_rows(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows, const std::vector<uint32_t>& free_rows,
                     int pass) {
  const size_t n = free_rows.size();
  for (size_t k = 0; k < n; ++k) {
    PointRow& row = rows[free_rows[pass % 2 == 0 ? k : n - 1 - k]];
    solve_normal(bodies[row.a], bodies[row.b], row);
  }
}

// One sweep of the iterations over manifolds (rows or their sweep copies),
// in order.
template <class Row, class Solve>
void sweep_manifolds(std::vector<SolverBody>& bodies, const std::vector<Row>& rows, Solve solve) {
  for (const Row& m : rows) solve(bodies[m.a], bodies[m.b], m);
}

// The same over their copies (SweepRows::free).
void sweep_free_rows(std::vector<SolverBody>& bodies, const std::vector<FreeRow>& free, int pass) {
  const size_t n = free.size();
  for (size_t k = 0; k < n; ++k) {
    const FreeRow& row = free[pass % 2 == 0 ? k : n - 1 - k];
    solve_normal(bodies[row.a], bodies[row.b], row);
  }
}

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
// into a box, or a box lying on a limb, was pushed apart at the mass ratio
// and pulled back by its joints in every pass: ragdoll heaps kept limbs
// 4.5 mm deep in boxes and each other (median over 96 heaps at 10 s; 34 mm
// at worst). The shock step, which settles such mass ratios for the
// velocities, leaves jointed bodies alone (shock.h). Here, as in its
// passes (after Guendelman, Bridson and Fedkiw, whose shock propagation is
// their last pass), a contact between two movable bodies, at least one of
// them jointed and not both of one joint tree, whose normal lies within 60
// degrees of up has the lower body stand still for the upper one, which is
// pushed out alone: 2.7 mm (34 at worst, a forearm between a box and a
// thigh). In every pass it was 2.0 mm, but 20 of the 96 heaps were still
// awake at 10 s (14 so). Rows of bodies no joint holds are pushed as
// before.
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
    // its joints' exact push undid the one-way push each step, and the
    // forearm stayed 14 mm inside.
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

void write_velocities(const std::vector<SolverBody>& solver_bodies, std::vector<Body>& bodies) {
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body& body = bodies[i];
    if (!is_awake_dynamic(body)) continue;
    body.linear_velocity = solver_bodies[i].velocity.linear;
    body.angular_velocity = solver_bodies[i].velocity.angular;
  }
}

}  // namespace

void solve_contacts(const SolveContext& context, SolvePass kind) {
  const Settings& settings = context.settings;
  std::vector<Body>& bodies = context.bodies;
  std::vector<Contact>& contacts = context.contacts;
  const JointSet& joints = context.joints;
  PushVelocities& push = context.push;
  SolverScratch& scratch = context.scratch;
  Executor* executor = context.executor;
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  gather_bodies(bodies, solver_bodies);
  if (kind == SolvePass::collision) save_impulses(contacts, scratch.saved_impulses);
  RowCache& cache = scratch.row_cache;
  const bool cached = cache.enabled && kind != SolvePass::collision;
  if (cached) {
    std::vector<BodyRowInputs>& now = scratch.body_row_inputs;
    now.resize(bodies.size());
    for (size_t i = 0; i < bodies.size(); ++i) {
      now[i] = {bodies[i].pose.position, solver_bodies[i].inverse_mass, solver_bodies[i].inverse_inertia,
                bodies[i].material.static_friction, bodies[i].material.dynamic_friction};
    }
    cache.compare_bodies(now);
  }
  if (kind != SolvePass::collision) {
    ++scratch.solves;
    scratch.rows_reused_from = cached ? cache.entries_solve : 0;
    if (cached) cache.entries_solve = scratch.solves;
  }
  const size_t row_count = plan_rows(settings, bodies, solver_bodies, contacts, kind, scratch.solved);
  // The collision pass (its manifolds are those that hit) builds every row,
  // into rows of its own. A cached solve reuses the last cached solve's
  // rows where it can: in place when it lays its contacts out as that solve
  // did (a settled scene: one set of rows, not two), else from the other
  // buffer, into which that solve's rows move aside.
  std::vector<PointRow>& rows = kind == SolvePass::collision ? scratch.collision_rows : scratch.rows;
  std::vector<ManifoldRow>& manifold_rows = kind == SolvePass::collision ? scratch.collision_manifolds : scratch.manifolds;
  const bool in_place = cached && scratch.rows_from_cached_solve && cache.same_layout(contacts, scratch.solved);
  if (kind != SolvePass::collision) {
    if (scratch.rows_from_cached_solve && !in_place) {
      std::swap(rows, scratch.last_rows);
      std::swap(manifold_rows, scratch.last_manifolds);
    }
    scratch.rows_from_cached_solve = false;
  }
  // The joints' rows first (they read no contact row). With joints the
  // sweeps stay on this thread, and so do the rows and their copies: made
  // on other workers they would only have to move here (the playground ran
  // 5-8% slower on two workers than on one).
  std::vector<JointRow>& joint_rows = joints.rows;
  joint_rows.clear();
  if (kind != SolvePass::collision) prepare_joint_rows(settings, bodies, joints.joints, solver_bodies, joint_rows, joints.tree);
  std::vector<TyreRow>& tyre_rows = context.tyres.rows;
  tyre_rows.clear();
  if (kind != SolvePass::collision) prepare_tyre_rows(bodies, solver_bodies, context.tyres.contacts, tyre_rows);
  Executor* row_executor = joint_rows.empty() ? executor : nullptr;
  prepare_rows(settings, bodies, solver_bodies, scratch.start_velocities, contacts, kind, row_count, rows,
               manifold_rows, cached ? &cache : nullptr, in_place ? rows : scratch.last_rows,
               in_place ? manifold_rows : scratch.last_manifolds, scratch.solved, in_place, row_executor);
  if (cached) {
    if (!in_place) std::swap(cache.entries, cache.next);
    scratch.rows_from_cached_solve = true;
  }
  const bool warm = settings.warm_starting && kind != SolvePass::collision;
  if (!warm) {
    for (JointRow& row : joint_rows) {
      Joint& joint = *row.joint;
      joint.point_impulse = Vec3{};
      joint.distance_impulse = joint.limit_impulse = joint.hinge_impulse[0] = joint.hinge_impulse[1] = Fixed{};
      joint.angular_impulse = Vec3{};
      joint.motor_impulse = Fixed{};
    }
    for (const PointRow& row : rows) row.point->normal_impulse = Fixed{};
    for (const ManifoldRow& m : manifold_rows) {
      m.manifold->friction_impulse[0] = m.manifold->friction_impulse[1] = m.manifold->twist_impulse = Fixed{};
      m.manifold->rolling_impulse[0] = m.manifold->rolling_impulse[1] = Fixed{};
    }
  }
  // The warm start and the iterations: the same sweeps, in the same order
  // for every body, on the executor's workers (ordered_sweeps.h) where there
  // is enough to share.
  bool parallel = executor && executor->workers() > 1 && joint_rows.empty() && tyre_rows.empty() &&
                  manifold_rows.size() >= min_parallel_manifolds * static_cast<size_t>(executor->workers());
  SweepRows& sweep_rows = scratch.sweep_rows;
  const bool copies = manifold_rows.size() >= scratch.sweep_copies_from;
  if (copies) split_sweep_rows(manifold_rows, rows, sweep_rows, row_executor);
  if (parallel) {
    std::vector<SweepStep>& steps = scratch.sweeps.steps;
    steps.clear();
    if (warm) steps.insert(steps.end(), {{SweepKind::warm_point, false}, {SweepKind::warm_manifold, false}});
    for (int pass = 0; pass < settings.velocity_iterations; ++pass) {
      steps.insert(steps.end(), {{SweepKind::friction, false},
                                 {SweepKind::manifold_normal, false},
                                 {SweepKind::rocking, false},
                                 {SweepKind::point_normal, pass % 2 == 1}});
    }
    std::vector<uint8_t>& movable = scratch.sweeps.movable;
    movable.resize(bodies.size());
    for (size_t i = 0; i < bodies.size(); ++i) movable[i] = is_awake_dynamic(bodies[i]) ? 1 : 0;
    parallel = run_ordered_sweeps(*executor, steps, movable, solver_bodies, rows, manifold_rows,
                                  copies ? &sweep_rows : nullptr, scratch.sweeps);
  }
  if (!parallel) {
    if (warm) warm_start_joints(solver_bodies, joint_rows);
    if (warm) warm_start(solver_bodies, rows, manifold_rows);
    warm_start_tyres(solver_bodies, tyre_rows, warm);
    std::vector<uint32_t>& free_rows = scratch.free_rows;  // the copies list their own
    free_rows.clear();
    if (!copies) {
      for (uint32_t i = 0; i < rows.size(); ++i) {
        if (is_free_row(rows[i])) free_rows.push_back(i);
      }
    }
    for (int pass = 0; pass < settings.velocity_iterations; ++pass) {
      if (copies) {
        sweep_manifolds(solver_bodies, sweep_rows.friction, solve_friction<FrictionRow>);
        sweep_manifolds(solver_bodies, sweep_rows.centroids, solve_manifold_normal<CentroidRow>);
        sweep_manifolds(solver_bodies, sweep_rows.rocking, solve_rocking<RockingRow>);
        sweep_free_rows(solver_bodies, sweep_rows.free, pass);
      } else {
        sweep_manifolds(solver_bodies, manifold_rows, solve_friction<ManifoldRow>);
        sweep_manifolds(solver_bodies, manifold_rows, solve_manifold_normal<ManifoldRow>);
        sweep_manifolds(solver_bodies, manifold_rows, solve_rocking<ManifoldRow>);
        sweep_free_rows(solver_bodies, rows, free_rows, pass);
      }
      solve_joints(solver_bodies, joint_rows, joints.tree);
      solve_tyres(solver_bodies, tyre_rows);
    }
    store_tyre_impulses(tyre_rows, context.tyres.contacts);
  }
  if (copies) write_back_impulses(manifold_rows, rows, sweep_rows, row_executor);
  // Islands whose joints ask for more passes than the world's run them
  // here, over their own rows (island_passes.h; with joints the sweeps
  // above ran on this thread).
  IslandPasses& island_passes = scratch.island_passes;
  plan_island_passes(settings, solver_bodies, rows, manifold_rows, joint_rows, island_passes);
  run_extra_velocity_passes(solver_bodies, rows, manifold_rows, joint_rows, joints.tree, island_passes);
  if (kind == SolvePass::collision) {
    restore_impulses(scratch.saved_impulses, contacts);
    write_velocities(solver_bodies, bodies);
    return;
  }
  if (settings.shock_propagation) propagate_shock(settings, bodies, contacts, joint_rows, scratch);
  // Position passes. When no row asks for a push (no overlap beyond the
  // slop, no impact's displacement), every row computes a zero impulse from
  // zero push velocities: skipping the passes gives the same bits.
  const bool anything_to_push =
      std::any_of(rows.begin(), rows.end(), [](const PointRow& row) { return row.push_target != Fixed{}; }) ||
      joints_to_push(joint_rows);
  if (!settings.baumgarte && anything_to_push) {
    std::vector<SweepStep>& steps = scratch.sweeps.steps;
    steps.clear();
    for (int pass = 0; pass < settings.position_iterations; ++pass) steps.push_back({SweepKind::point_push, pass % 2 == 1});
    if (!parallel ||
        !run_ordered_sweeps(*executor, steps, scratch.sweeps.movable, solver_bodies, rows, manifold_rows,
                            copies ? &sweep_rows : nullptr, scratch.sweeps)) {
      one_way_pushes(settings, solver_bodies, rows, joint_rows, scratch.jointed, scratch.joint_trees, scratch.one_way);
      run_extra_position_passes(solver_bodies, rows, joint_rows, joints.tree, island_passes);
      for (int pass = 0; pass < settings.position_iterations; ++pass) {
        // The joints last: contacts pushed after them pressed ragdoll
        // limbs past their limits (an elbow 20 degrees for a second in a
        // pile; in 12 piles of ragdolls.json, 263 joint-steps of 60,000
        // more than 2 degrees past, 71 with the joints last) and left
        // deeper overlaps at 10 s (4.7 mm on average, 3.9 mm).
        if (pass + 1 == settings.position_iterations && !scratch.one_way.empty()) {
          sweep_last_push(solver_bodies, rows, scratch.one_way, pass);
        } else {
          sweep(solver_bodies, rows, pass, solve_push);
        }
        push_joints(solver_bodies, joint_rows, joints.tree);
      }
    }
  }
  push.linear.assign(bodies.size(), Vec3{});
  push.angular.assign(bodies.size(), Vec3{});
  write_velocities(solver_bodies, bodies);
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (!is_awake_dynamic(bodies[i])) continue;
    push.linear[i] = solver_bodies[i].push.linear;
    push.angular[i] = solver_bodies[i].push.angular;
  }
}

}  // namespace bitstep
