#include "core/contact_rows.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include "core/ordered_sweeps.h"

namespace bitstep {

namespace {

// The row setup's work per manifold is a fraction of the iterations': below
// this many a worker, sharing it among two workers costs more in waking and
// waiting than it saves.
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
// A worker's share of the row setup: the setup, 1 / dt, and where each
// worker counts the manifolds whose rows it reused.
struct RowBuild {
  const RowSetup& setup;
  Fixed inverse_dt;
  int workers;
  uint64_t* reused;  // per worker
};

// One solved contact's rows while they are built: its bodies, its pair's
// mixed materials, how many of its points touch (the rows first), the
// cache entry of last step's rows it reuses (or null), and its tangents.
struct ContactRows {
  Contact& contact;
  Manifold& m;
  size_t slot, first;
  uint32_t ia, ib;
  const Body& body_a;
  const Body& body_b;
  const SolverBody& a;
  const SolverBody& b;
  Fixed restitution;    // the pair's: the larger
  Fixed rolling_limit;  // m: 0 where nothing rolls
  int held = 0;
  const RowCache::Entry* reuse = nullptr;
  Fixed mu_s, mu_d;
  Vec3 t1, t2;
};

ContactRows contact_rows(const RowSetup& setup, size_t slot) {
  Contact& contact = setup.contacts[setup.solved[slot].contact];
  const uint32_t ia = contact.key.body_a, ib = contact.key.body_b;
  const Body& body_a = setup.bodies[ia];
  const Body& body_b = setup.bodies[ib];
  // Pair mixing: the larger restitution; friction below.
  const Fixed restitution = max(body_a.material.restitution, body_b.material.restitution);
  // Box pairs roll on nothing: no square root for them.
  const Fixed roll_radius =
      max(rolling_radius(body_a.shapes[contact.key.shape_a]), rolling_radius(body_b.shapes[contact.key.shape_b]));
  const Fixed rolling_limit =
      roll_radius > Fixed{}
          ? sqrt(body_a.material.rolling_resistance * body_b.material.rolling_resistance) * roll_radius
          : Fixed{};
  return {contact,         contact.manifold,         slot,   setup.solved[slot].first_row, ia, ib, body_a, body_b,
          setup.solver_bodies[ia], setup.solver_bodies[ib], restitution, rolling_limit, 0, nullptr, {}, {}, {}, {}};
}

// Last step's rows for this contact, where the cache holds them for the
// same inputs (found from `cursor`, which walks the cache's entries in key
// order), and this solve's entry for it; then the pair's friction and the
// tangents for the rows that are built.
void find_reusable(const RowSetup& setup, ContactRows& c, size_t& cursor, RowMemo& memo) {
  if (RowCache* cache = setup.cache) {
    const RowInputs inputs = row_inputs(c.contact, c.held);
    c.reuse = cache->find(inputs, cursor);
    // In place, this slot's entry was last step's for the same key and
    // rows, read just now by find and by no other slot; found there, it
    // holds these inputs, rows and slot already.
    if (!(setup.in_place && c.reuse == &cache->entries[c.slot])) {
      (setup.in_place ? cache->entries : cache->next)[c.slot] = {inputs, c.first, c.slot};
    }
  }
  // Friction: the geometric means of the bodies' coefficients, as last
  // step's rows hold them where they are reused (their bodies' are equal).
  if (c.reuse) {
    c.mu_s = setup.last_manifolds[c.reuse->manifold_row].static_friction;
    c.mu_d = setup.last_manifolds[c.reuse->manifold_row].dynamic_friction;
  } else {
    memo.friction(c.body_a.material, c.body_b.material, c.mu_s, c.mu_d);
  }
  // The tangents (a fixed choice per normal, so warm-started friction
  // keeps its meaning), for the rows that are built.
  if (!c.reuse ||
      (c.rolling_limit > Fixed{} && setup.last_manifolds[c.reuse->manifold_row].rolling_limit == Fixed{})) {
    memo.tangents(c.m.normal, c.t1, c.t2);
  }
}

// A point row's targets in the standard and contact passes: the velocity
// it asks for (speculative approach, bounce, Baumgarte bias) and its
// split-impulse push. `approach` is J v now; `meets`: it touches this step.
void set_point_targets(const RowBuild& build, const ContactRows& c, PointRow& row, const ContactPoint& p,
                       Fixed approach, Fixed start_speed, bool meets) {
  const Settings& settings = build.setup.settings;
  const SolvePass pass = build.setup.pass;
  const Fixed inverse_dt = build.inverse_dt;
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
  if (pass == SolvePass::standard && meets && start_speed > settings.restitution_threshold &&
      approach < Fixed{}) {
    const Fixed acceleration = (approach + start_speed) * inverse_dt;
    const Fixed impact_time = -min(p.depth / start_speed, settings.dt);  // t, at least -dt
    const Fixed after = settings.dt - impact_time;                          // tau
    const Fixed leave = c.restitution * (start_speed - acceleration * impact_time);
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
      start_speed > settings.restitution_threshold && c.restitution > Fixed{}) {
    // The collision pass bounced this point from a gap, as if the
    // surfaces had met at the start of the step: it leaves at
    // e s from where it is. The bounce belongs to the moment of impact,
    // t = -depth / s, and by the end of the step the point should be
    // e s (dt - t) from the surface, not -depth + e s dt: the difference
    // goes through the split-impulse channel as an exact pull (depth -
    // e s t) / dt, so the body reaches the surface however fast it came
    // (it stopped in mid-air up to a step's travel short).
    // The velocity row holds what the bounce left (no further approach).
    const Fixed leave = c.restitution * start_speed;
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
}

// Point i's row, built where it lies (in place, a reused Jacobian is there
// already). Whether it counts towards the manifold's centroid row.
bool build_point_row(const RowBuild& build, const ContactRows& c, int i) {
  const RowSetup& setup = build.setup;
  const Settings& settings = setup.settings;
  const SolvePass pass = setup.pass;
  ContactPoint& p = c.m.points[static_cast<size_t>(i)];
  const Vec3 ra = p.position - c.body_a.pose.position, rb = p.position - c.body_b.pose.position;
  PointRow& row = setup.rows[c.first + static_cast<size_t>(i)];
  if (!c.reuse) {
    row.normal = make_jacobian(c.a, c.b, ra, rb, c.m.normal);
  } else {
    const Jacobian& last = setup.last_rows[c.reuse->first_row + static_cast<size_t>(i)].normal;
    if (&last != &row.normal) row.normal = last;
  }
  row.a = c.ia;
  row.b = c.ib;
  row.push_target = Fixed{};
  row.point = &p;
  row.in_resting_face = row.impact = false;
  const Fixed approach = relative_velocity(c.a, c.b, row.normal);
  // A gap (depth < 0) may close by depth / dt this step: speculative contact.
  row.velocity_target = p.depth < Fixed{} ? p.depth * build.inverse_dt : Fixed{};
  const bool meets = meets_at(p.depth, -approach, settings.dt);
  if (pass == SolvePass::collision) {
    // JigLib's collision pass: a point that meets this step
    // leaves at e times its approach speed (the velocities have no
    // forces yet); nothing is pushed apart. With e = 0 it only arrives:
    // a gap closes by depth / dt, as in the iterations.
    if (meets && -approach > settings.restitution_threshold && c.restitution > Fixed{}) {
      row.velocity_target = -approach * c.restitution;
    }
    return true;
  }
  // The approach speed before this step's forces (nine products) is read
  // only by the two bounces, each of which also asks what may_bounce
  // does: where it is false, neither reads the 0 in its place.
  const bool may_bounce = (pass == SolvePass::standard && meets && approach < Fixed{}) ||
                          (pass == SolvePass::contact && p.depth < Fixed{} && c.restitution > Fixed{});
  const Fixed start_speed =
      may_bounce ? -relative_rate(setup.start_velocities[c.ia], setup.start_velocities[c.ib], row.normal) : Fixed{};
  set_point_targets(build, c, row, p, approach, start_speed, meets);
  p.split_impulse = Fixed{};
  return i < c.held;
}

// The manifold row at `slot`: the centroid of its counted points and their
// mean velocity target; the same Jacobians, offsets, twist radius and
// rocking rows as last step's where they are reused.
void build_manifold_row(const RowSetup& setup, const ContactRows& c, Vec3 centroid, Fixed target) {
  const Fixed count = Fixed::from_int(c.held);
  std::vector<ManifoldRow>& manifold_rows = setup.manifold_rows;
  const Manifold& m = c.m;
  if (c.reuse) {
    // In place they are this slot's own row already (a settled scene's
    // every row: a kilobyte each not copied onto itself). Rolling rows
    // come along where last step built them.
    const ManifoldRow& last = setup.last_manifolds[c.reuse->manifold_row];
    if (&last != &manifold_rows[c.slot]) manifold_rows[c.slot] = last;
    ManifoldRow& face = manifold_rows[c.slot];
    face.first = c.first;
    face.velocity_target = target / count;
    face.static_friction = c.mu_s;
    face.dynamic_friction = c.mu_d;
    face.manifold = &c.m;
    face.one_sided = false;
  } else {
    centroid = centroid / count;
    Fixed radius;
    for (int i = 0; i < c.held; ++i) radius += length(m.points[static_cast<size_t>(i)].position - centroid);
    const Vec3 ra = centroid - c.body_a.pose.position, rb = centroid - c.body_b.pose.position;
    Vec3 arms[max_manifold_points];  // (p_i - c) x n, for both rocking rows
    for (int i = 0; i < c.held; ++i) arms[i] = cross(m.points[static_cast<size_t>(i)].position - centroid, m.normal);
    const SolverBody& a = c.a;
    const SolverBody& b = c.b;
    manifold_rows[c.slot] = {c.ia, c.ib, c.first, static_cast<size_t>(c.held), make_jacobian(a, b, ra, rb, m.normal),
                             {make_jacobian(a, b, ra, rb, c.t1), make_jacobian(a, b, ra, rb, c.t2)},
                             make_twist(a, b, m.normal), ra, rb, target / count, radius / count, c.mu_s, c.mu_d, &c.m,
                             {make_rocking(a, b, arms, c.held, c.t1), make_rocking(a, b, arms, c.held, c.t2)},
                             {}, false, {}, Fixed{}};
    ManifoldRow& face = manifold_rows[c.slot];
    face.share_mass = face.normal.mass / count;
  }
  manifold_rows[c.slot].index = static_cast<uint32_t>(c.slot);
  manifold_rows[c.slot].reused_from = c.reuse ? static_cast<uint32_t>(c.reuse->manifold_row) : ManifoldRow::none;
}

// The manifold's rolling rows (where the pair rolls), and whether its
// point rows make a resting face. A resting face (3 or more touching
// points asking for no relative speed) has three normal degrees of
// freedom, its centroid row and two rocking rows, which keep every point
// pushing: its point rows would only redistribute impulse between the
// points, so the iterations skip them.
void finish_manifold_row(const RowSetup& setup, const ContactRows& c) {
  ManifoldRow& face = setup.manifold_rows[c.slot];
  if (c.rolling_limit > Fixed{}) {
    if (!c.reuse || face.rolling_limit == Fixed{}) {
      face.rolling[0] = make_twist(c.a, c.b, c.t1);
      face.rolling[1] = make_twist(c.a, c.b, c.t2);
    }
    face.rolling_limit = c.rolling_limit;
  } else {
    face.rolling[0] = face.rolling[1] = AngularPart{};
    face.rolling_limit = Fixed{};
    c.m.rolling_impulse[0] = c.m.rolling_impulse[1] = Fixed{};
  }
  std::vector<PointRow>& rows = setup.rows;
  const size_t held_end = c.first + static_cast<size_t>(c.held);
  bool resting = c.held >= 3 && face.rocking[0].active && face.rocking[1].active;
  for (size_t k = c.first; k < held_end; ++k) {
    resting = resting && rows[k].velocity_target == Fixed{} && rows[k].point->depth >= Fixed{};
  }
  for (size_t k = c.first; k < held_end; ++k) rows[k].in_resting_face = resting;
}

// The rows of the solved contact `slot`. Whether they were reused.
bool build_rows(const RowBuild& build, size_t slot, size_t& cursor, RowMemo& memo) {
  ContactRows c = contact_rows(build.setup, slot);
  c.held = hold_touching_first(c.m);
  find_reusable(build.setup, c, cursor, memo);
  Vec3 centroid;
  Fixed target;
  for (int i = 0; i < c.m.point_count; ++i) {
    if (!build_point_row(build, c, i)) continue;
    centroid += c.m.points[static_cast<size_t>(i)].position;
    target += build.setup.rows[c.first + static_cast<size_t>(i)].velocity_target;
  }
  build_manifold_row(build.setup, c, centroid, target);
  finish_manifold_row(build.setup, c);
  return c.reuse != nullptr;
}

// Worker w builds the w-th contiguous share of the solved contacts.
void build_rows_of_worker(void* context, int worker) {
  const RowBuild& build = *static_cast<const RowBuild*>(context);
  const RowSetup& setup = build.setup;
  if (worker >= build.workers) return;
  const size_t n = setup.solved.size(), w = static_cast<size_t>(worker), workers = static_cast<size_t>(build.workers);
  const size_t begin = n * w / workers, end = n * (w + 1) / workers;
  if (begin == end) return;
  size_t cursor = !setup.cache     ? 0
                  : setup.in_place ? begin  // the entries lie as the contacts do
                                   : setup.cache->cursor_at(setup.contacts[setup.solved[begin].contact].key);
  uint64_t reused = 0;
  RowMemo memo;
  for (size_t slot = begin; slot < end; ++slot) reused += build_rows(build, slot, cursor, memo) ? 1u : 0u;
  build.reused[w] = reused;
}

}  // namespace

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

void prepare_rows(const RowSetup& setup, Executor* executor) {
  // Resized, not cleared: in a steady scene the sizes stay and nothing is
  // written twice.
  setup.rows.resize(setup.row_count);
  setup.manifold_rows.resize(setup.solved.size());
  if (setup.cache && !setup.in_place) setup.cache->next.resize(setup.solved.size());
  const bool parallel = executor && executor->workers() > 1 &&
                        setup.solved.size() >= min_parallel_row_setups * static_cast<size_t>(executor->workers());
  const int workers = parallel ? std::min(executor->workers(), max_workers) : 1;
  uint64_t reused[max_workers] = {};
  RowBuild build{setup, Fixed::one() / setup.settings.dt, workers, reused};
  if (parallel) {
    executor->run(build_rows_of_worker, &build);
  } else {
    build_rows_of_worker(&build, 0);
  }
  if (setup.cache) {
    uint64_t total = 0;
    for (int w = 0; w < workers; ++w) total += reused[w];
    setup.cache->reused += total;
    setup.cache->built += setup.solved.size() - total;
  }
}

}  // namespace bitstep
