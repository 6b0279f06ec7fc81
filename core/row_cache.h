// Exact reuse of last step's pose-dependent row parts. A manifold's
// Jacobians (arms, d / m, I^-1 (r x d), effective masses), rocking, twist and
// rolling rows, centroid offsets and twist radius are a pure function of the
// two bodies' centres of mass, inverse masses and world inverse inertias
// (BodyRowInputs) and of the normal and the points in row order, with how
// many touch (RowInputs). Where every one of those is bit-identical to last
// step's for the same contact key, the rows are copied from last step's
// instead of built again, so a step computes the same bits with or without the cache. Only
// the velocity-dependent parts (targets, impacts, resting faces) are
// computed every step; the pair's friction coefficients come with the rows
// (the bodies' coefficients are compared too), and the tangent basis is
// found only for rows that are built. A standing structure skips the
// row setup's products and divisions. Not state: no invalidation is needed
// (the inputs are compared in full), and a restored world starts empty.
// When the contacts and their row counts are those of last step, in the same
// order, the rows are reused where they lie, so a settled scene keeps one
// set of rows, not two.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/contact.h"
#include "fixed/mat33.h"

namespace bitstep {

// A manifold's own inputs; the bodies' are compared once per body (below).
struct RowInputs {
  ContactKey key;
  Vec3 normal;
  int point_count = 0, held = 0;                    // points; of them touching (rows first)
  std::array<Vec3, max_manifold_points> points{};  // positions in row order, zero past the count
  friend bool operator==(const RowInputs&, const RowInputs&) = default;
};

// A body's inputs to its rows: centre of mass, inverse mass and world
// inverse inertia, as the solve uses them (zero mass for a sleeping body),
// and its friction coefficients (a pair's are the geometric means: two
// square roots a manifold, reused with the rows).
struct BodyRowInputs {
  Vec3 centre;
  Fixed inverse_mass;
  Mat33 inverse_inertia;
  Fixed static_friction, dynamic_friction;
  friend bool operator==(const BodyRowInputs&, const BodyRowInputs&) = default;
};

// A contact the solve takes: its position in the contact list and where
// its point rows begin (contact_rows.cpp, plan_rows).
struct SolvedContact {
  uint32_t contact;
  size_t first_row;
};

struct RowCache {
  struct Entry {
    RowInputs inputs;
    size_t first_row;     // its point rows in last step's rows
    size_t manifold_row;  // its manifold row in last step's manifold rows
  };
  std::vector<Entry> entries;  // the last cached solve's, sorted by key
  std::vector<Entry> next;     // this solve's, while its rows are built
  std::vector<BodyRowInputs> bodies;  // per slot, at the last cached solve
  std::vector<uint8_t> still;         // per slot: this solve's inputs are those, bit for bit
  bool enabled = true;         // off: every row is built (the reuse tests compare both)
  uint64_t entries_solve = 0;  // the solve (SolverScratch::solves) the entries are of; 0: none
  uint64_t reused = 0, built = 0;  // manifolds, over the world's life (figures, not state)

  // Marks each slot still or not against the last cached solve, and keeps
  // this solve's inputs for the next.
  void compare_bodies(const std::vector<BodyRowInputs>& now) {
    bodies.resize(now.size());
    still.resize(now.size());
    for (size_t i = 0; i < now.size(); ++i) {
      still[i] = bodies[i] == now[i];
      bodies[i] = now[i];
    }
  }

  // Whether `solved` lays the contacts out as the last cached solve did:
  // the same keys in the same order, each one's rows at the same place
  // (then its rows can be reused where they lie).
  bool same_layout(const std::vector<Contact>& contacts, const std::vector<SolvedContact>& solved) const {
    if (entries.size() != solved.size()) return false;
    for (size_t i = 0; i < solved.size(); ++i) {
      if (entries[i].first_row != solved[i].first_row || !(entries[i].inputs.key == contacts[solved[i].contact].key)) {
        return false;
      }
    }
    return true;
  }

  // Where the entries of keys from `key` on begin: a worker's first cursor.
  size_t cursor_at(const ContactKey& key) const {
    return static_cast<size_t>(
        std::lower_bound(entries.begin(), entries.end(), key,
                         [](const Entry& e, const ContactKey& k) { return e.inputs.key < k; }) -
        entries.begin());
  }

  // Last step's entry with exactly these inputs (both bodies still), or
  // null. Called in key order by each of the row setup's workers, each
  // walking the entries once from its own cursor (a binary search per
  // manifold probes a big scene's entries far apart, missing the cache).
  const Entry* find(const RowInputs& inputs, size_t& cursor) const {
    if (!still[inputs.key.body_a] || !still[inputs.key.body_b]) return nullptr;
    while (cursor < entries.size() && entries[cursor].inputs.key < inputs.key) ++cursor;
    if (cursor < entries.size() && entries[cursor].inputs == inputs) return &entries[cursor];
    return nullptr;
  }
};

}  // namespace bitstep
