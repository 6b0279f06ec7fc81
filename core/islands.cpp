#include "core/islands.h"

namespace bitstep {

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];  // path halving
    i = parent[i];
  }
  return i;
}

void unite(std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b) {
    parent[b] = a;
  } else {
    parent[a] = b;
  }
}

void build_islands(const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                   const std::vector<Joint>& joints, Islands& islands) {
  const auto n = static_cast<uint32_t>(bodies.size());
  auto dynamic = [&](uint32_t i) { return bodies[i].alive && bodies[i].type == BodyType::dynamic; };
  std::vector<uint32_t>& parent = islands.parent;
  parent.resize(n);
  for (uint32_t i = 0; i < n; ++i) parent[i] = i;
  for (const Contact& c : contacts) {
    if (dynamic(c.key.body_a) && dynamic(c.key.body_b) && touches(c.manifold)) {
      unite(parent, c.key.body_a, c.key.body_b);
    }
  }
  for (const Joint& j : joints) {
    if (j.alive && dynamic(j.body_a) && dynamic(j.body_b)) unite(parent, j.body_a, j.body_b);
  }
  // Number the islands by their root (lowest slot), then list members by
  // counting sort: both in slot order.
  islands.island_of.assign(n, no_island);
  std::vector<uint32_t>& island_of_root = islands.island_of_root;
  island_of_root.assign(n, no_island);
  uint32_t count = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (!dynamic(i)) continue;
    const uint32_t root = find_root(parent, i);
    if (island_of_root[root] == no_island) island_of_root[root] = count++;
    islands.island_of[i] = island_of_root[root];
  }
  islands.first.assign(count + 1, 0);
  for (uint32_t i = 0; i < n; ++i) {
    if (islands.island_of[i] != no_island) ++islands.first[islands.island_of[i] + 1];
  }
  for (uint32_t k = 1; k <= count; ++k) islands.first[k] += islands.first[k - 1];
  islands.members.assign(islands.first[count], 0);
  std::vector<uint32_t>& fill = islands.fill;
  fill.assign(islands.first.begin(), islands.first.end() - 1);
  for (uint32_t i = 0; i < n; ++i) {
    if (islands.island_of[i] != no_island) islands.members[fill[islands.island_of[i]]++] = i;
  }
}

}  // namespace bitstep
