#include "core/shock.h"

#include <algorithm>
#include <optional>

#include "core/islands.h"
#include "core/shock_groups.h"
#include "core/shock_levels.h"
#include "core/shock_solve.h"

namespace bitstep {

namespace {

// A rank, or an island, whose touching contacts the iterations left
// approaching, sliding and twisting no faster than this is held already
// (moving_at_contact, settle_unconverged_cluster, keep_iterations_where_held),
// m/s.
constexpr Fixed quiet_motion = 0.001_fx;

// Twice the kinetic energy per unit mass, J/kg: |v|^2 + w . (I / m) w.
// I / m is taken in the body frame, where it is at most about size^2, so
// with the envelope's speeds and sizes neither term nears the range.
Fixed energy_per_mass(const Body& body, const BodyRates& rates, Fixed inverse_mass) {
  const Vec3 w = rotate_inverse(body.pose.orientation, rates.angular);
  return dot(rates.linear, rates.linear) + dot(w, (body.inertia_local * inverse_mass) * w);
}

// Whether some touching contact of the cluster [begin, end) moves faster
// than quiet_motion (moving_at_contact) at the velocities its bodies had
// before its passes (scratch.rank_bodies), against the ranks below as the
// shock step left them: judged during or after the passes, with the same
// bits as before them. Its manifolds' rows as they were then
// (scratch.manifolds: a pass may point the order at a one-sided copy); the
// ranks below stayed frozen.
bool moving_before_passes(SolverScratch& scratch, size_t begin, size_t end) {
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  const std::vector<RankBody>& before_shock = scratch.rank_bodies;
  std::vector<BodyRates>& after = scratch.groups.after_passes;
  after.clear();
  for (const RankBody& b : before_shock) after.push_back(solver_bodies[b.body].velocity);
  for (const RankBody& b : before_shock) solver_bodies[b.body].velocity = b.velocity;
  bool moving = false;
  for (size_t i = begin; i < end && !moving; ++i) {
    moving = moving_at_contact(solver_bodies, scratch.rows, scratch.manifolds[scratch.order[i].index], quiet_motion);
  }
  for (size_t i = 0; i < before_shock.size(); ++i) solver_bodies[before_shock[i].body].velocity = after[i];
  return moving;
}

// Whether a cluster is held already: no sideways contact, and none of its
// touching contacts moving before the passes (moving_before_passes).
// Judged once, when first asked: the ranks below are frozen, so the answer
// stays.
struct HeldProbe {
  SolverScratch& scratch;
  size_t begin, end;
  bool sideways;
  std::optional<bool> answer;
  bool operator()() {
    if (!answer) answer = !sideways && !moving_before_passes(scratch, begin, end);
    return *answer;
  }
};

// One pass over the cluster's manifolds [begin, end) of scratch.shock_manifolds:
// each body held up is glued to its supports (all at once, or through one
// contact), else its rows are solved, one-sided against a lower rank.
// Settled when no velocity changed; given up (the pass left unfinished)
// when a body of a cluster held already sits on supports that part.
enum class ClusterPass { settled, changed, given_up };
ClusterPass cluster_pass(const std::vector<Body>& bodies, const std::vector<uint32_t>& level, SolverScratch& scratch,
                         size_t begin, size_t end, int pass, HeldProbe& held_already) {
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  std::vector<PointRow>& rows = scratch.rows;
  std::vector<ManifoldRow*>& shock_manifolds = scratch.shock_manifolds;
  const std::vector<ShockEntry>& order = scratch.order;
  const SupportGroups& supports = scratch.supports;
  std::vector<GlueAll>& glued_to_all = scratch.glued_to_all;
  std::vector<uint8_t>& glued_alone = scratch.glued_alone;
  std::vector<BodyRates>& glued_velocity = scratch.glued_velocity;
  bool changed = false;
  for (size_t i = begin; i < end; ++i) {
    ManifoldRow* row = shock_manifolds[i];
    const ManifoldRow& m = *row;
    const BodyRates before_a = solver_bodies[m.a].velocity, before_b = solver_bodies[m.b].velocity;
    if (level[m.a] != level[m.b]) {
      const bool mover_is_b = level[m.a] < level[m.b];
      const uint32_t mover = mover_is_b ? m.b : m.a;
      if (order[i].holds_up) {
        const BodyRates before = mover_is_b ? before_b : before_a;
        if (supports.several[mover]) {
          // Glued to all its supports at once at its first support manifold.
          const uint32_t* list = &supports.entries[supports.begin[mover]];
          const size_t count = supports.begin[mover + 1] - supports.begin[mover];
          // Glued in the last pass and not moved since: its supports are
          // frozen, so the glue would find the same again.
          const bool glued_before =
              glued_to_all[mover] == GlueAll::glued && solver_bodies[mover].velocity == glued_velocity[mover];
          if (list[0] == i && !glued_before) {
            glued_to_all[mover] =
                glue_all(solver_bodies[mover], bodies[mover], solver_bodies, bodies, list, count, level,
                         shock_manifolds, rows, scratch.glue_faces.of_body(mover), scratch.glue_faces);
            glued_velocity[mover] = solver_bodies[mover].velocity;
          }
          if (glued_to_all[mover] == GlueAll::glued) {
            changed = changed || !(solver_bodies[mover].velocity == before);
            continue;
          }
          // Supports that part cannot all hold it, and glued to one after
          // another the last wins over the others. In a cluster held already
          // the passes then trade the body between its supports without end
          // and the cluster is settled as it began (a collapsing pile would
          // run most of its clusters through every pass so): it is given up
          // at once. In motion, each support is tried.
          if (glued_to_all[mover] == GlueAll::supports_part && held_already()) return ClusterPass::given_up;
        }
        // A body on one support glued in the last pass and not moved since:
        // its support is frozen, so the glue would find the same again.
        const bool alone = !supports.several[mover];
        if (alone && glued_alone[mover] && solver_bodies[mover].velocity == glued_velocity[mover]) continue;
        const bool glued = glue(solver_bodies[mover], solver_bodies[mover_is_b ? m.a : m.b], bodies[mover],
                                mover_is_b, m, rows, scratch.glue_faces.of_manifold(i), scratch.glue_faces);
        if (alone) {
          glued_alone[mover] = glued;
          glued_velocity[mover] = solver_bodies[mover].velocity;
        }
        if (glued) {
          changed = changed || !(solver_bodies[mover].velocity == before);
          continue;
        }
        if (supports.several[mover]) continue;
      }
      if (!m.one_sided) row = &one_sided_copy(scratch, i, mover_is_b);
    }
    solve_manifold(solver_bodies, rows, *row, pass);
    changed = changed || !(solver_bodies[m.a].velocity == before_a) || !(solver_bodies[m.b].velocity == before_b);
  }
  return changed ? ClusterPass::changed : ClusterPass::settled;
}


// Solves the cluster [begin, end) of scratch.order (one rank's): passes
// until one changes no velocity (exactly: the arithmetic is fixed point),
// at most shock_iterations, the passes that would only go round a cycle
// skipped (skip_repeating_passes); a cluster that does not converge is
// settled by settle_unconverged_cluster. Then its bodies become immovable (inverse mass
// 0, listed in scratch.frozen_bodies; the one-sided rows already carry no
// turn for them).
void solve_cluster(const Settings& settings, const std::vector<Body>& bodies, const std::vector<uint32_t>& level,
                SolverScratch& scratch, size_t begin, size_t end) {
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  const std::vector<ManifoldRow*>& shock_manifolds = scratch.shock_manifolds;
  const std::vector<ShockEntry>& order = scratch.order;
  const uint32_t rank = order[begin].level;
  // The iterations' velocities of the rank's bodies (with duplicates), and
  // whether the rank has a sideways contact (a body pressed against one
  // ranked below it, not held up by it).
  std::vector<RankBody>& before_shock = scratch.rank_bodies;
  before_shock.clear();
  bool sideways = false;
  for (size_t i = begin; i < end; ++i) {
    const ManifoldRow& m = *shock_manifolds[i];
    for (uint32_t body : {m.a, m.b}) {
      if (level[body] == rank) before_shock.push_back({body, solver_bodies[body].velocity});
    }
    sideways = sideways || (level[m.a] != level[m.b] && !order[i].holds_up);
  }
  HeldProbe held_already{scratch, begin, end, sideways, {}};
  bool converged = false;
  const int last_pass = settings.shock_iterations - 1;
  bool skipped = false;  // once: the history does not follow the jump
  std::vector<BodyRates>& before_last_pass = scratch.groups.before_last_pass;
  before_last_pass.clear();
  for (int pass = 0; pass <= last_pass && !converged; ++pass) {
    before_last_pass.clear();
    for (const RankBody& b : before_shock) before_last_pass.push_back(solver_bodies[b.body].velocity);
    const ClusterPass result = cluster_pass(bodies, level, scratch, begin, end, pass, held_already);
    if (result == ClusterPass::given_up) {
      before_last_pass.clear();  // every body of the cluster counts as unconverged
      break;
    }
    converged = result == ClusterPass::settled;
    if (converged || skipped) continue;
    const int next = skip_repeating_passes(solver_bodies, before_shock, scratch.rank_history, pass, last_pass);
    skipped = next != pass;
    pass = next;
  }
  if (!converged) {
    // The bodies still changing in the last pass (shock_groups.h).
    for (size_t i = 0; i < before_shock.size(); ++i) {
      const uint32_t body = before_shock[i].body;
      if (before_last_pass.empty() || !(solver_bodies[body].velocity == before_last_pass[i])) {
        scratch.groups.unconverged.push_back(body);
      }
    }
    settle_unconverged_cluster(bodies, before_shock, held_already(), solver_bodies);
  }
  for (size_t i = begin; i < end; ++i) {
    for (uint32_t body : {shock_manifolds[i]->a, shock_manifolds[i]->b}) {
      if (level[body] != rank || solver_bodies[body].inverse_mass == Fixed{}) continue;
      scratch.frozen_bodies.push_back(body);
      scratch.saved_inverse_mass.push_back(solver_bodies[body].inverse_mass);
      solver_bodies[body].inverse_mass = Fixed{};
    }
  }
}

}  // namespace

void order_manifolds(const Settings& settings, const ShockLevels& levels, const std::vector<ManifoldRow>& manifold_rows,
                     std::vector<ShockEntry>& order, ShockOrderWorkspace& workspace) {
  const std::vector<uint32_t>& level = levels.rank;
  const std::vector<uint32_t>& height = levels.height;
  // Whether the lower-ranked body of a manifold between ranks holds the
  // other up (the normal points from a to b).
  const auto holds_up = [&](const ManifoldRow& m) {
    return is_support(level[m.a] < level[m.b] ? m.manifold->normal : -m.manifold->normal, settings.gravity);
  };
  // Manifolds between ranked bodies, by (rank of the higher body, order):
  // those within a rank (both bodies movable); between ranks, those
  // against an immovable body, those along a sideways chain within a
  // height, and those through which a lower height holds a higher one up.
  // Any other contact between heights (a tumbling body touching another
  // from below or the side) is left to the iterations: freezing the wrong
  // side would squeeze the body between two immovable ones.
  std::vector<ShockEntry>& unsorted = workspace.unsorted;
  unsorted.clear();
  for (uint32_t i = 0; i < manifold_rows.size(); ++i) {
    const ManifoldRow& m = manifold_rows[i];
    if (level[m.a] == not_supported || level[m.b] == not_supported) continue;
    const bool between_heights = level[m.a] != 0 && level[m.b] != 0 && height[m.a] != height[m.b] &&
                                 height[m.a] != not_supported && height[m.b] != not_supported;
    const bool support = level[m.a] != level[m.b] && holds_up(m);
    const bool sideways = level[m.a] != level[m.b] && !between_heights && !support;
    if (between_heights && !support) continue;
    // The higher-ranked body holds the lower-ranked one up (a body leaning
    // on one ranked after it through another chain): freezing the lower
    // would press the other down from above. Left to the iterations.
    const Vec3 from_higher = level[m.a] < level[m.b] ? -m.manifold->normal : m.manifold->normal;
    const bool lower_rests_on_higher =
        level[m.a] != level[m.b] && !support && is_support(from_higher, settings.gravity);
    if (lower_rests_on_higher) continue;
    // Apart: a speculative contact, for the iterations (gluing it would
    // stop a falling body in the air), unless sideways, where it is solved
    // one-sided up to touching and no more.
    if (!sideways && !touches(*m.manifold)) continue;
    unsorted.push_back({0, std::max(level[m.a], level[m.b]), i, support});
  }
  // Clusters: a rank's passes couple two of its bodies only through a
  // manifold between them (against the ranks below, frozen, a body is
  // solved on its own), so the rank's bodies fall into clusters joined by
  // such manifolds, each solved on its own until it converges, a manifold
  // from below going with the body it holds. Judged across the whole rank,
  // one heap that never converged would make every stack and wall at its
  // levels run all shock_iterations passes, and a box glued at rest would
  // take the iterations' sliding back because a box elsewhere in its rank
  // still rocked (settle_unconverged_cluster).
  std::vector<uint32_t>& parent = workspace.parent;
  parent.resize(level.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  uint32_t top = 0;
  for (const ShockEntry& e : unsorted) {
    const ManifoldRow& m = manifold_rows[e.index];
    if (level[m.a] == level[m.b]) unite(parent, m.a, m.b);
    top = std::max(top, e.level);
  }
  for (ShockEntry& e : unsorted) {
    const ManifoldRow& m = manifold_rows[e.index];
    e.cluster = find_root(parent, level[m.a] == e.level ? m.a : m.b);
  }
  // By level, a counting sort that keeps each level's entries in index
  // order; then by cluster within a level, sorted only where a level holds
  // more than one cluster out of order (a wall's course, a pyramid's layer:
  // one cluster, nothing to sort).
  std::vector<uint32_t>& start = workspace.level_start;
  start.assign(static_cast<size_t>(top) + 2, 0);
  for (const ShockEntry& e : unsorted) ++start[e.level + 1];
  for (size_t l = 1; l < start.size(); ++l) start[l] += start[l - 1];
  order.resize(unsorted.size());
  for (const ShockEntry& e : unsorted) order[start[e.level]++] = e;
  const auto by_cluster = [](ShockEntry x, ShockEntry y) {
    return x.cluster != y.cluster ? x.cluster < y.cluster : x.index < y.index;
  };
  for (size_t begin = 0, end = 0; begin < order.size(); begin = end) {
    while (end < order.size() && order[end].level == order[begin].level) ++end;
    const auto first = order.begin() + static_cast<std::ptrdiff_t>(begin);
    const auto last = order.begin() + static_cast<std::ptrdiff_t>(end);
    if (!std::is_sorted(first, last, by_cluster)) std::sort(first, last, by_cluster);
  }
}

void group_supports(size_t body_count, const std::vector<uint32_t>& level, const std::vector<ManifoldRow>& manifold_rows,
                    const std::vector<ShockEntry>& order, SupportGroups& groups) {
  const auto mover_of = [&](const ManifoldRow& m) { return level[m.a] < level[m.b] ? m.b : m.a; };
  // Support manifolds per body (counted in `fill`); several: more than one.
  std::vector<uint32_t>& fill = groups.fill;
  fill.assign(body_count, 0);
  for (const ShockEntry& e : order) {
    if (e.holds_up) ++fill[mover_of(manifold_rows[e.index])];
  }
  groups.several.resize(body_count);
  for (size_t body = 0; body < body_count; ++body) groups.several[body] = fill[body] > 1 ? 1 : 0;
  // Each body with several supports: its support manifolds (positions in
  // `order`), grouped by body (a counting sort: deterministic), in order.
  std::vector<uint32_t>& begin = groups.begin;
  begin.assign(body_count + 1, 0);
  for (size_t body = 0; body < body_count; ++body) {
    begin[body + 1] = begin[body] + (groups.several[body] ? fill[body] : 0);
  }
  groups.entries.resize(begin.back());
  fill.assign(begin.begin(), begin.end() - 1);
  for (uint32_t i = 0; i < order.size(); ++i) {
    const uint32_t mover = mover_of(manifold_rows[order[i].index]);
    if (order[i].holds_up && groups.several[mover]) groups.entries[fill[mover]++] = i;
  }
}

void gather_rows(std::vector<Contact>& contacts, SolverScratch& scratch) {
  // The shock step corrects this step's velocities only, and next step
  // warm-starts from what the iterations found (the shock's one-sided
  // impulses would push the supports down when applied to both bodies):
  // the impulses are saved here and put back after it. Its rows are the
  // solve's own, but for those it makes one-sided, which it copies first
  // (the position passes and next step's row reuse read the rows).
  const std::vector<ShockEntry>& order = scratch.order;
  std::vector<ManifoldRow*>& shock_manifolds = scratch.shock_manifolds;
  save_impulses(contacts, scratch.shock_saved);
  shock_manifolds.resize(order.size());
  for (size_t i = 0; i < order.size(); ++i) shock_manifolds[i] = &scratch.manifolds[order[i].index];
  scratch.one_sided.clear();
  scratch.rows_before_shock = scratch.rows.size();
}

void restore_rows(std::vector<Contact>& contacts, SolverScratch& scratch) {
  restore_impulses(scratch.shock_saved, contacts);
  scratch.rows.resize(scratch.rows_before_shock);
  scratch.one_sided.clear();
}

ManifoldRow& one_sided_copy(SolverScratch& scratch, size_t position, bool freeze_a) {
  ManifoldRow& copy = scratch.one_sided.push(*scratch.shock_manifolds[position]);
  std::vector<PointRow>& rows = scratch.rows;
  const size_t original_first = copy.first;
  copy.first = rows.size();
  // Few manifolds are made one-sided (none in a standing wall): the rows
  // grow by an eighth when they must, not to twice their size.
  if (rows.size() + copy.count > rows.capacity()) rows.reserve(rows.size() + copy.count + rows.size() / 8);
  for (size_t k = 0; k < copy.count; ++k) rows.push_back(rows[original_first + k]);
  make_one_sided(copy, rows, scratch.bodies[copy.a], scratch.bodies[copy.b], freeze_a);
  scratch.shock_manifolds[position] = &copy;
  return copy;
}

bool moving_at_contact(const std::vector<SolverBody>& solver_bodies, const std::vector<PointRow>& rows,
                       const ManifoldRow& m, Fixed speed) {
  const SolverBody& a = solver_bodies[m.a];
  const SolverBody& b = solver_bodies[m.b];
  bool touching = false;
  for (size_t k = 0; k < m.count; ++k) {
    const PointRow& row = rows[m.first + k];
    if (row.point->depth < -touch_tolerance) continue;
    touching = true;
    if (relative_velocity(a, b, row.normal) < -speed) return true;
  }
  if (!touching) return false;
  if (abs(relative_velocity(a, b, m.tangent[0])) > speed || abs(relative_velocity(a, b, m.tangent[1])) > speed) {
    return true;
  }
  return abs(relative_spin(a, b, m.twist)) * m.twist_radius > speed;
}

int skip_repeating_passes(const std::vector<SolverBody>& solver_bodies, const std::vector<RankBody>& rank,
                          std::vector<BodyRates>& history, int pass, int last_pass) {
  constexpr int longest_period = 4, window = 2 * longest_period;
  const size_t n = rank.size();
  if (pass == 0) history.resize(n * window);
  // after(p): the velocities after pass p, in a ring of `window` passes.
  const auto after = [&](int p) { return &history[n * static_cast<size_t>(p % window)]; };
  for (size_t i = 0; i < n; ++i) after(pass)[i] = solver_bodies[rank[i].body].velocity;
  for (int period = 2; period <= longest_period && 2 * period <= pass + 1; period += 2) {
    bool repeats = true;
    for (int p = pass - period + 1; p <= pass && repeats; ++p) {
      repeats = std::equal(after(p), after(p) + n, after(p - period));
    }
    if (repeats) return last_pass - (last_pass - pass) % period;
  }
  return pass;
}


void settle_unconverged_cluster(const std::vector<Body>& bodies, const std::vector<RankBody>& before_shock,
                             bool held_already, std::vector<SolverBody>& solver_bodies) {
  for (const RankBody& b : before_shock) {
    SolverBody& body = solver_bodies[b.body];
    if (held_already || energy_per_mass(bodies[b.body], b.velocity, body.inverse_mass) <
                            energy_per_mass(bodies[b.body], body.velocity, body.inverse_mass)) {
      body.velocity = b.velocity;
    }
  }
}

void propagate_shock(const Settings& settings, const std::vector<Body>& bodies, std::vector<Contact>& contacts,
                     const std::vector<JointRow>& joint_rows, SolverScratch& scratch) {
  if (scratch.manifolds.empty()) return;  // nothing awake touches anything
  shock_levels(bodies, contacts, settings.gravity, scratch.levels);
  for (const JointRow& row : joint_rows) {
    for (const uint32_t body : {row.a, row.b}) {
      if (is_awake_dynamic(bodies[body])) scratch.levels.rank[body] = not_supported;
    }
  }
  const std::vector<uint32_t>& level = scratch.levels.rank;
  order_manifolds(settings, scratch.levels, scratch.manifolds, scratch.order, scratch.order_workspace);
  group_supports(bodies.size(), level, scratch.manifolds, scratch.order, scratch.supports);
  // Per body, whether it is glued to all its supports at once in this pass.
  scratch.glued_to_all.assign(bodies.size(), GlueAll::refused);
  scratch.glued_alone.assign(bodies.size(), 0);
  scratch.glued_velocity.resize(bodies.size());  // read only where glued_to_all or glued_alone
  gather_rows(contacts, scratch);
  keep_velocities(scratch.bodies, scratch.groups);
  scratch.glue_faces.reset(bodies.size(), scratch.order.size(), scratch.solves, scratch.rows_reused_from);
  // Rank by rank, cluster by cluster, each made immovable once solved.
  scratch.saved_inverse_mass.clear();
  scratch.frozen_bodies.clear();
  const std::vector<ShockEntry>& order = scratch.order;
  const auto same_cluster = [&](size_t i, size_t j) {
    return order[i].level == order[j].level && order[i].cluster == order[j].cluster;
  };
  for (size_t begin = 0, end = 0; begin < order.size(); begin = end) {
    while (end < order.size() && same_cluster(end, begin)) ++end;
    solve_cluster(settings, bodies, level, scratch, begin, end);
  }
  for (size_t i = 0; i < scratch.frozen_bodies.size(); ++i) {
    scratch.bodies[scratch.frozen_bodies[i]].inverse_mass = scratch.saved_inverse_mass[i];
  }
  keep_iterations_where_held(scratch.manifolds, scratch.rows, quiet_motion, scratch.groups, scratch.bodies);
  restore_rows(contacts, scratch);
}

}  // namespace bitstep
