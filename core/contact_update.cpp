#include "core/contact_update.h"

#include <algorithm>
#include <tuple>

#include "core/collide.h"

namespace bitstep {

namespace {

// Points closer than this (m) to an old point of the same contact are the
// same point, whatever their feature ids say: clipping an incident face whose
// vertices lie exactly on the reference face's side planes (equal boxes
// stacked square) tags the same corner differently from step to step.
constexpr Fixed same_point_distance = 0.01_fx;

// Copies the manifold's friction impulses, and each point's normal impulse
// from the old point with the same feature id, else from the nearest old
// point within same_point_distance.
void inherit_impulses(const Manifold& old, Manifold& fresh) {
  fresh.friction_impulse[0] = old.friction_impulse[0];
  fresh.friction_impulse[1] = old.friction_impulse[1];
  fresh.twist_impulse = old.twist_impulse;
  fresh.rolling_impulse[0] = old.rolling_impulse[0];
  fresh.rolling_impulse[1] = old.rolling_impulse[1];
  constexpr Fixed limit_sq = same_point_distance * same_point_distance;
  for (int i = 0; i < fresh.point_count; ++i) {
    ContactPoint& p = fresh.points[static_cast<size_t>(i)];
    int nearest = -1;
    Fixed nearest_sq = limit_sq;
    for (int j = 0; j < old.point_count; ++j) {
      const ContactPoint& q = old.points[static_cast<size_t>(j)];
      if (q.feature == p.feature) {
        nearest = j;
        break;
      }
      const Vec3 d = q.position - p.position;
      // Per-axis rejection first keeps the squared length far from overflow.
      if (abs(d.x) > same_point_distance || abs(d.y) > same_point_distance || abs(d.z) > same_point_distance) continue;
      const Fixed dist_sq = length_sq(d);
      if (dist_sq < nearest_sq) {
        nearest_sq = dist_sq;
        nearest = j;
      }
    }
    if (nearest >= 0) p.normal_impulse = old.points[static_cast<size_t>(nearest)].normal_impulse;
  }
}

NarrowphaseCache::Found found_of(const Manifold& m) {
  NarrowphaseCache::Found found;
  found.normal = m.normal;
  found.point_count = m.point_count;
  for (size_t k = 0; k < found.points.size(); ++k) {
    found.points[k] = {m.points[k].position, m.points[k].depth, m.points[k].feature};
  }
  return found;
}

// A fresh manifold as collide() wrote it (its impulses zero).
void restore_found(const NarrowphaseCache::Found& found, Manifold& m) {
  m = Manifold{};
  m.normal = found.normal;
  m.point_count = found.point_count;
  for (size_t k = 0; k < found.points.size(); ++k) {
    m.points[k].position = found.points[k].position;
    m.points[k].depth = found.points[k].depth;
    m.points[k].feature = found.points[k].feature;
  }
}

// Which bodies sit exactly where they sat at last step's narrowphase; then
// this step's poses become the ones to compare with next step.
void remember_poses(const std::vector<Body>& bodies, NarrowphaseCache& cache) {
  const size_t had = cache.poses.size();
  cache.poses.resize(bodies.size());
  cache.still.resize(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    cache.still[i] = i < had && cache.poses[i] == bodies[i].pose;
    cache.poses[i] = bodies[i].pose;
  }
}

// Whether the shape pairs of `pairs` (those with a dynamic body) are the
// keys of `entries`, in the same order.
bool same_shape_pairs(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs,
                      const std::vector<NarrowphaseCache::Entry>& entries) {
  size_t i = 0;
  for (const BodyPair& pair : pairs) {
    const Body& a = bodies[pair.a];
    const Body& b = bodies[pair.b];
    if (a.type != BodyType::dynamic && b.type != BodyType::dynamic) continue;
    for (size_t sa = 0; sa < a.shapes.size(); ++sa) {
      for (size_t sb = 0; sb < b.shapes.size(); ++sb) {
        const ContactKey key{pair.a, pair.b, static_cast<uint16_t>(sa), static_cast<uint16_t>(sb)};
        if (i == entries.size() || !(entries[i].key == key)) return false;
        ++i;
      }
    }
  }
  return i == entries.size();
}

}  // namespace

namespace {

// Shape pairs per worker below which the collision tests stay on one
// thread: waking the workers costs more than they save.
constexpr size_t min_parallel_tests = 16;

// Every shape pair of the pairs with a dynamic body, in key order: its key,
// margin, and the cache entry it may be restored from (when both bodies sit
// where they sat and the margin is the same; a pure function of them).
void plan_shape_pairs(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                      const std::vector<Fixed>& turn_speed, NarrowphaseCache& cache) {
  std::vector<NarrowphaseCache::Test>& tests = cache.tests;
  tests.clear();
  size_t next_cached = 0;  // both lists are sorted by key: one merge walk
  size_t collided = 0;
  for (const BodyPair& pair : pairs) {
    const Body& a = bodies[pair.a];
    const Body& b = bodies[pair.b];
    if (a.type != BodyType::dynamic && b.type != BodyType::dynamic) continue;  // a moving kinematic body
    // Contacts are kept this far apart: the speculative distance plus how
    // far the two bodies can close in on each other this step (their
    // centres' relative motion and each one's turn at its farthest point),
    // so a fast or fast-turning body meets its contact one step early
    // instead of one step deep (a falling domino's top edge moves at w r,
    // several times its centre's speed).
    const Fixed closing = length(b.linear_velocity - a.linear_velocity) + turn_speed[pair.a] + turn_speed[pair.b];
    const Fixed margin = settings.speculative_distance + closing * settings.dt;
    const bool both_still = cache.enabled && cache.still[pair.a] && cache.still[pair.b];
    for (size_t sa = 0; sa < a.shapes.size(); ++sa) {
      for (size_t sb = 0; sb < b.shapes.size(); ++sb) {
        const ContactKey key{pair.a, pair.b, static_cast<uint16_t>(sa), static_cast<uint16_t>(sb)};
        while (next_cached < cache.entries.size() && cache.entries[next_cached].key < key) ++next_cached;
        const bool same = both_still && next_cached < cache.entries.size() &&
                          cache.entries[next_cached].key == key && cache.entries[next_cached].margin == margin;
        tests.push_back({key, margin, same ? next_cached : NarrowphaseCache::Test::none, collided});
        if (!same) ++collided;
      }
    }
  }
  cache.collided.resize(collided);
}

// The shapes whose rotation matrix the narrowphase reads (collide_internal.h axes_of).
bool has_axes(ShapeType type) { return type == ShapeType::box || type == ShapeType::hull; }

// Places the shapes of every body in a test that collide() will run
// (NarrowphaseCache::placed), each once however many pairs its body is
// in: a body's pose composed with the shape's, and a box's or hull's rotation.
void place_shapes(const std::vector<Body>& bodies, NarrowphaseCache& cache) {
  constexpr size_t none = NarrowphaseCache::Test::none;
  cache.first_placed.assign(bodies.size(), none);
  cache.placed.clear();
  cache.placed_axes.clear();
  for (const NarrowphaseCache::Test& test : cache.tests) {
    if (test.cached != none) continue;
    for (const uint32_t id : {test.key.body_a, test.key.body_b}) {
      if (cache.first_placed[id] != none) continue;
      cache.first_placed[id] = cache.placed.size();
      const Body& body = bodies[id];
      for (const Shape& shape : body.shapes) {
        const Pose pose = compose(body.pose, shape.local);
        cache.placed.push_back({&shape, pose});
        cache.placed_axes.push_back(has_axes(shape.type) ? rotation(pose.orientation) : Mat33{});
      }
    }
  }
  // The matrices are pointed at once their list stops growing.
  for (size_t k = 0; k < cache.placed.size(); ++k) {
    if (has_axes(cache.placed[k].shape->type)) cache.placed[k].axes = &cache.placed_axes[k];
  }
}

struct CollideWork {
  NarrowphaseCache& cache;
  int workers;
};

// A worker's contiguous share of the planned tests: the fresh manifold of
// each one the cache does not hold, found by collide() (a function of its
// own inputs alone, so the same bits on any number of workers).
void collide_share(void* context, int worker) {
  const CollideWork& work = *static_cast<const CollideWork*>(context);
  if (worker >= work.workers) return;
  const std::vector<NarrowphaseCache::Test>& tests = work.cache.tests;
  const size_t n = tests.size(), w = static_cast<size_t>(worker), workers = static_cast<size_t>(work.workers);
  for (size_t i = n * w / workers; i < n * (w + 1) / workers; ++i) {
    const NarrowphaseCache::Test& test = tests[i];
    if (test.cached != NarrowphaseCache::Test::none) continue;  // restored where it is merged
    const NarrowphaseCache& cache = work.cache;
    const WorldShape& shape_a = cache.placed[cache.first_placed[test.key.body_a] + test.key.shape_a];
    const WorldShape& shape_b = cache.placed[cache.first_placed[test.key.body_b] + test.key.shape_b];
    // A fresh manifold, point_count 0 when apart.
    collide(shape_a, shape_b, test.margin, work.cache.collided[test.slot]);
  }
}

}  // namespace

void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     const std::vector<Fixed>& turn_speed, std::vector<Contact>& contacts,
                     std::vector<Contact>& previous, NarrowphaseCache& cache, Executor* executor) {
  // A contact between two bodies that cannot move this step (asleep,
  // static, kinematic at rest) is kept as it is, with its impulses: the
  // broadphase reports no pair for it.
  auto kept = [&](const Contact& c) {
    return !needs_contacts(bodies[c.key.body_a]) && !needs_contacts(bodies[c.key.body_b]);
  };
  cache.next.clear();
  remember_poses(bodies, cache);
  if (pairs.empty()) {
    std::erase_if(contacts, [&](const Contact& c) { return !kept(c); });
    cache.entries.clear();
    return;
  }
  // The tests: planned here, run on the workers, merged here in order.
  plan_shape_pairs(bodies, pairs, settings, turn_speed, cache);
  place_shapes(bodies, cache);
  const size_t to_collide = cache.collided.size();
  const bool parallel = executor && executor->workers() > 1 &&
                        to_collide >= min_parallel_tests * static_cast<size_t>(executor->workers());
  CollideWork work{cache, parallel ? executor->workers() : 1};
  if (parallel) {
    executor->run(collide_share, &work);
  } else {
    collide_share(&work, 0);
  }
  cache.tested += to_collide;
  cache.reused += cache.tests.size() - to_collide;
  previous.swap(contacts);  // keeps both buffers' capacity
  contacts.clear();
  contacts.reserve(previous.size());
  // When the shape pairs are last step's, in order (a standing scene), the
  // cache's entries are rewritten where they lie (each was read by its own
  // test above); else they are built anew, reserved at once rather than
  // doubled up from nothing at the first step (a pair of single shapes is
  // one entry).
  const bool in_place = cache.enabled && same_shape_pairs(bodies, pairs, cache.entries);
  if (!in_place) cache.next.reserve(std::max(cache.entries.size(), pairs.size()));
  size_t next_old = 0;  // both lists are sorted by key: one merge walk
  auto keep_old_before = [&](uint32_t a, uint32_t b) {
    for (; next_old < previous.size() &&
           std::tie(previous[next_old].key.body_a, previous[next_old].key.body_b) < std::tie(a, b);
         ++next_old) {
      if (kept(previous[next_old])) contacts.push_back(previous[next_old]);
    }
  };
  for (size_t i = 0; i < cache.tests.size(); ++i) {
    const NarrowphaseCache::Test& test = cache.tests[i];
    keep_old_before(test.key.body_a, test.key.body_b);
    Contact contact{test.key, {}};
    if (test.cached != NarrowphaseCache::Test::none) {
      restore_found(cache.entries[test.cached].found, contact.manifold);
    } else {
      contact.manifold = cache.collided[test.slot];
    }
    if (in_place) {
      // A reused entry (the one this test was restored from) would be
      // rewritten with what it holds: it is left as it is.
      if (test.cached != i) cache.entries[i] = {test.key, test.margin, found_of(contact.manifold)};
    } else if (cache.enabled) {
      cache.next.push_back({test.key, test.margin, found_of(contact.manifold)});
    }
    if (contact.manifold.point_count == 0) continue;
    while (next_old < previous.size() && previous[next_old].key < contact.key) ++next_old;
    if (settings.warm_starting && next_old < previous.size() && previous[next_old].key == contact.key) {
      inherit_impulses(previous[next_old].manifold, contact.manifold);
    }
    contacts.push_back(contact);
  }
  keep_old_before(UINT32_MAX, UINT32_MAX);
  if (!in_place) cache.entries.swap(cache.next);  // keeps both buffers' capacity
}

}  // namespace bitstep
