// Islands: the groups of dynamic bodies joined by touching contacts and
// joints. An island sleeps and wakes as one. Static
// bodies never join: two stacks on one ground are two islands.
#pragma once

#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/contact.h"
#include "core/joint.h"

namespace bitstep {

inline constexpr uint32_t no_island = UINT32_MAX;

struct Islands {
  // Per body slot: the island index, or no_island for static, kinematic and
  // dead slots. Islands are numbered in the order of their lowest slot.
  std::vector<uint32_t> island_of;
  // The bodies of island i are members[first[i] .. first[i + 1]), in slot order.
  std::vector<uint32_t> first;
  std::vector<uint32_t> members;

  size_t count() const { return first.empty() ? 0 : first.size() - 1; }

  // Workspace of build_islands, reused so that a settled step allocates
  // nothing (the union-find parents, each root's island, the fill cursors).
  std::vector<uint32_t> parent, island_of_root, fill;
};

// Union-find over body slots with the smaller slot as the root, so a set's
// root is its lowest slot whatever order the unions come in (deterministic);
// find_root halves the path on the way. Also used by the shock step's
// islands (shock_groups.cpp).
uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i);
void unite(std::vector<uint32_t>& parent, uint32_t a, uint32_t b);

// Builds the islands: a contact that touches (manifold.h: a point within
// touch_tolerance), or a live joint, joins its two bodies when both are
// dynamic (waking one link of a chain wakes the chain).
// Deterministic: the result depends on slots and contacts only, never on
// memory addresses or iteration over unordered containers.
void build_islands(const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                   const std::vector<Joint>& joints, Islands& islands);

}  // namespace bitstep
