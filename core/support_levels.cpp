#include "core/support_levels.h"

namespace bitstep {

bool is_support(Vec3 normal, Vec3 gravity) {
  // n . up > cos 60 deg with up = -g / |g|, as n . (-g) > |g| / 2.
  return dot(normal, -gravity) > length(gravity) / 2.0_fx;
}

void support_levels(const std::vector<Body>& bodies, const std::vector<Contact>& contacts, Vec3 gravity,
                    Fixed touch_distance, std::vector<uint32_t>& level) {
  level.assign(bodies.size(), not_supported);
  if (gravity == Vec3{}) return;

  // Support edges supporter -> supported, grouped by supporter (counting
  // sort over the contacts, which are in (a, b) order: deterministic).
  struct Edge {
    uint32_t from, to;
  };
  std::vector<Edge> edges;
  for (const Contact& c : contacts) {
    if (!touches(c.manifold, touch_distance)) continue;
    // The normal points from a to b.
    if (is_support(c.manifold.normal, gravity)) edges.push_back({c.key.body_a, c.key.body_b});
    if (is_support(-c.manifold.normal, gravity)) edges.push_back({c.key.body_b, c.key.body_a});
  }
  std::vector<uint32_t> first(bodies.size() + 1, 0);
  for (const Edge& e : edges) ++first[e.from + 1];
  for (size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
  std::vector<uint32_t> supported(edges.size());
  std::vector<uint32_t> fill(first.begin(), first.end() - 1);
  for (const Edge& e : edges) supported[fill[e.from]++] = e.to;

  std::vector<uint32_t> queue;
  for (uint32_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].alive && !is_awake_dynamic(bodies[i])) {  // static, kinematic or asleep
      level[i] = 0;
      queue.push_back(i);
    }
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const uint32_t from = queue[head];
    for (uint32_t k = first[from]; k < first[from + 1]; ++k) {
      const uint32_t to = supported[k];
      if (level[to] != not_supported || !is_awake_dynamic(bodies[to])) continue;
      level[to] = level[from] + 1;
      queue.push_back(to);
    }
  }
}

}  // namespace bitstep
