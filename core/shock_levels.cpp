#include "core/shock_levels.h"

#include <algorithm>

namespace bitstep {

// n . up > cos 60 deg with up = -g / |g|, as n . (-g) > |g| / 2.
bool is_support(Vec3 normal, Vec3 gravity) { return SupportTest(gravity)(normal); }

namespace {

using Edge = ShockLevels::Edge;
using Adjacency = ShockLevels::Adjacency;

// Groups the edges by `from` (a counting sort, stable: deterministic).
void build_adjacency(const std::vector<Edge>& edges, size_t body_count, Adjacency& adjacency) {
  std::vector<uint32_t>& first = adjacency.first;
  first.assign(body_count + 1, 0);
  adjacency.to.resize(edges.size());
  for (const Edge& e : edges) ++first[e.from + 1];
  for (size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
  adjacency.fill.assign(first.begin(), first.end() - 1);
  for (const Edge& e : edges) adjacency.to[adjacency.fill[e.from]++] = e.to;
}

// Breadth-first distances from the bodies already in `queue` (distance set)
// along the edges, to bodies `reachable` allows.
template <typename Reachable>
void breadth_first(const Adjacency& adjacency, std::vector<uint32_t>& queue, std::vector<uint32_t>& distance,
                   Reachable reachable) {
  for (size_t head = 0; head < queue.size(); ++head) {
    const uint32_t from = queue[head];
    for (uint32_t k = adjacency.first[from]; k < adjacency.first[from + 1]; ++k) {
      const uint32_t to = adjacency.to[k];
      if (distance[to] != not_supported || !reachable(to)) continue;
      distance[to] = distance[from] + 1;
      queue.push_back(to);
    }
  }
}

// Heights: breadth first up the supporter -> supported edges (the normal
// points from a to b) from the immovable bodies (height 0).
void heights(const std::vector<Body>& bodies, const std::vector<Contact>& contacts, const SupportTest& holds_up,
             bool gravity, ShockLevels& levels) {
  const size_t count = bodies.size();
  std::vector<uint32_t>& height = levels.height;
  height.assign(count, not_supported);
  std::vector<Edge>& supports = levels.supports;
  supports.clear();
  if (gravity) {
    for (const Contact& c : contacts) {
      if (!touches(c.manifold)) continue;
      if (holds_up(c.manifold.normal)) supports.push_back({c.key.body_a, c.key.body_b});
      if (holds_up(-c.manifold.normal)) supports.push_back({c.key.body_b, c.key.body_a});
    }
  }
  std::vector<uint32_t>& queue = levels.queue;
  queue.clear();
  for (uint32_t i = 0; i < count; ++i) {
    if (!bodies[i].alive || is_awake_dynamic(bodies[i])) continue;
    height[i] = 0;
    queue.push_back(i);
  }
  build_adjacency(supports, count, levels.adjacency);
  breadth_first(levels.adjacency, queue, height, [&](uint32_t i) { return is_awake_dynamic(bodies[i]); });
}

// Sideways: seeds are movable bodies in contact with an immovable one
// through a contact that does not hold them up; the chains run through
// contacts between movable bodies of the same height (never from a body
// to one that holds it up), and on into bodies of no height (a car that
// hops on hitting the pinned box stays pinned). Speculative contacts
// count: a body closing in on a pinned one this step is solved against it
// (only up to touching: nothing is glued sideways).
void sideways_distances(const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                        const SupportTest& holds_up, ShockLevels& levels) {
  const size_t count = bodies.size();
  const std::vector<uint32_t>& height = levels.height;
  const auto immovable = [&](uint32_t i) { return bodies[i].alive && !is_awake_dynamic(bodies[i]); };
  const auto movable = [&](uint32_t i) { return is_awake_dynamic(bodies[i]); };
  std::vector<Edge>& sideways = levels.sideways;
  sideways.clear();
  std::vector<uint8_t>& seed = levels.seed;
  seed.assign(count, 0);
  for (const Contact& c : contacts) {
    const uint32_t a = c.key.body_a, b = c.key.body_b;
    if (movable(a) && movable(b)) {
      if (height[a] != height[b] && height[a] != not_supported && height[b] != not_supported) continue;
      // A chain does not run down from a body to the one holding it up: it
      // ranked a box below the one leaning on it, and the shock step then
      // froze the leaning box and pressed the other out from under it.
      if (!holds_up(-c.manifold.normal)) sideways.push_back({a, b});
      if (!holds_up(c.manifold.normal)) sideways.push_back({b, a});
    } else if (immovable(a) && movable(b) && !holds_up(c.manifold.normal)) {
      seed[b] = 1;
    } else if (immovable(b) && movable(a) && !holds_up(-c.manifold.normal)) {
      seed[a] = 1;
    }
  }
  std::vector<uint32_t>& sideways_distance = levels.sideways_distance;
  sideways_distance.assign(count, not_supported);
  std::vector<uint32_t>& queue = levels.queue;
  queue.clear();
  for (uint32_t i = 0; i < count; ++i) {
    if (!seed[i]) continue;
    sideways_distance[i] = 0;
    queue.push_back(i);
  }
  build_adjacency(sideways, count, levels.adjacency);
  breadth_first(levels.adjacency, queue, sideways_distance, movable);
}

// Ranks: (height, sideways distance) in lexicographic order, numbered
// consecutively from 1 for height 1; "no height" comes after the highest.
void ranks(ShockLevels& levels) {
  const std::vector<uint32_t>& height = levels.height;
  const std::vector<uint32_t>& sideways_distance = levels.sideways_distance;
  std::vector<uint32_t>& rank = levels.rank;
  const size_t count = height.size();
  rank.assign(count, not_supported);
  uint32_t top = 0;
  for (uint32_t h : height) {
    if (h != not_supported) top = std::max(top, h);
  }
  std::vector<uint32_t>& deepest = levels.deepest;  // per height, the longest sideways chain
  deepest.assign(size_t{top} + 1, 0);
  for (uint32_t i = 0; i < count; ++i) {
    if (height[i] == not_supported || sideways_distance[i] == not_supported) continue;
    deepest[height[i]] = std::max(deepest[height[i]], sideways_distance[i]);
  }
  std::vector<uint32_t>& first = levels.first_rank;  // the rank of (height h, distance 0)
  first.assign(size_t{top} + 2, 0);
  first[1] = 1;
  for (uint32_t h = 1; h <= top; ++h) first[h + 1] = first[h] + deepest[h] + 1;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t distance = sideways_distance[i] == not_supported ? 0 : sideways_distance[i];
    if (height[i] != not_supported) {
      rank[i] = height[i] == 0 ? 0 : first[height[i]] + distance;
    } else if (sideways_distance[i] != not_supported) {
      rank[i] = first[top + 1] + distance;
    }
  }
}

}  // namespace

void shock_levels(const std::vector<Body>& bodies, const std::vector<Contact>& contacts, Vec3 gravity,
                  ShockLevels& levels) {
  const SupportTest holds_up(gravity);
  heights(bodies, contacts, holds_up, gravity != Vec3{}, levels);
  sideways_distances(bodies, contacts, holds_up, levels);
  ranks(levels);
}

}  // namespace bitstep
