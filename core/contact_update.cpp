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

void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     const std::vector<Fixed>& turn_speed, std::vector<Contact>& contacts,
                     std::vector<Contact>& previous, NarrowphaseCache& cache) {
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
  previous.swap(contacts);  // keeps both buffers' capacity
  contacts.clear();
  contacts.reserve(previous.size());
  // When the shape pairs are last step's, in order (a standing scene), the
  // cache's entries are rewritten where they lie, each read before it is
  // written; else they are built anew, reserved at once rather than doubled
  // up from nothing at the first step (a pair of single shapes is one entry).
  const bool in_place = cache.enabled && same_shape_pairs(bodies, pairs, cache.entries);
  if (!in_place) cache.next.reserve(std::max(cache.entries.size(), pairs.size()));
  size_t next_entry = 0;
  size_t next_old = 0;     // both lists are sorted by key: one merge walk
  size_t next_cached = 0;  // likewise through the cache
  auto keep_old_before = [&](BodyPair pair) {
    for (; next_old < previous.size() && std::tie(previous[next_old].key.body_a, previous[next_old].key.body_b) <
                                             std::tie(pair.a, pair.b);
         ++next_old) {
      if (kept(previous[next_old])) contacts.push_back(previous[next_old]);
    }
  };
  for (const BodyPair& pair : pairs) {
    const Body& a = bodies[pair.a];
    const Body& b = bodies[pair.b];
    if (a.type != BodyType::dynamic && b.type != BodyType::dynamic) continue;  // a moving kinematic body
    keep_old_before(pair);
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
        Contact contact{{pair.a, pair.b, static_cast<uint16_t>(sa), static_cast<uint16_t>(sb)}, {}};
        while (next_cached < cache.entries.size() && cache.entries[next_cached].key < contact.key) ++next_cached;
        const bool same = both_still && next_cached < cache.entries.size() &&
                          cache.entries[next_cached].key == contact.key && cache.entries[next_cached].margin == margin;
        if (same) {
          restore_found(cache.entries[next_cached].found, contact.manifold);
          ++cache.reused;
        } else {
          const WorldShape shape_a{&a.shapes[sa], compose(a.pose, a.shapes[sa].local)};
          const WorldShape shape_b{&b.shapes[sb], compose(b.pose, b.shapes[sb].local)};
          collide(shape_a, shape_b, margin, contact.manifold);  // a fresh manifold, point_count 0 when apart
          ++cache.tested;
        }
        if (in_place) {
          // A reused entry (the one this pair was restored from) would be
          // rewritten with what it holds: it is left as it is.
          if (!(same && next_entry == next_cached)) {
            cache.entries[next_entry] = {contact.key, margin, found_of(contact.manifold)};
          }
          ++next_entry;
        } else if (cache.enabled) {
          cache.next.push_back({contact.key, margin, found_of(contact.manifold)});
        }
        if (contact.manifold.point_count == 0) continue;
        while (next_old < previous.size() && previous[next_old].key < contact.key) ++next_old;
        if (settings.warm_starting && next_old < previous.size() && previous[next_old].key == contact.key) {
          inherit_impulses(previous[next_old].manifold, contact.manifold);
        }
        contacts.push_back(contact);
      }
    }
  }
  keep_old_before({UINT32_MAX, UINT32_MAX});
  if (!in_place) cache.entries.swap(cache.next);  // keeps both buffers' capacity
}

}  // namespace bitstep
