// Shock levels (JigLib's, after Guendelman, Bridson and Fedkiw 2003):
// the order in which the shock step makes bodies immovable. Upward from
// the static, kinematic and sleeping bodies along the direction opposite
// gravity, and sideways from anything immovable a body is pressed against,
// so that bodies "stack in any direction": a light box between a wall and
// a car is held by the wall for the car.
#pragma once

#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/contact.h"

namespace bitstep {

inline constexpr uint32_t not_supported = UINT32_MAX;

// Whether a contact normal, pointing from one body to the other, makes the
// first hold the second up: within 60 degrees of up = -gravity.
bool is_support(Vec3 normal, Vec3 gravity);

// is_support for one gravity and many normals: its threshold |g| / 2 (a
// square root and a division) taken once, the same bits.
class SupportTest {
 public:
  explicit SupportTest(Vec3 gravity) : up_(-gravity), threshold_(length(gravity) / 2.0_fx) {}
  bool operator()(Vec3 normal) const { return dot(normal, up_) > threshold_; }

 private:
  Vec3 up_;
  Fixed threshold_;
};

struct ShockLevels {
  // Per body slot. Height: 0 for static, kinematic and sleeping bodies; an
  // awake body resting on a body of height k is at most k + 1 ("resting
  // on": a contact whose normal, from the supporter to it, lies within 60
  // degrees of up). Breadth-first from height 0 (ties by slot order), so a
  // height is the fewest supports between a body and the ground.
  // not_supported: no such path (falling, leaning sideways on others, a
  // dead slot, or any body when gravity is zero).
  std::vector<uint32_t> height;
  // The shock step's order: 0 for height 0, then by height, and within a
  // height by the fewest contacts to a body of that height in contact with
  // an immovable one sideways (a contact that is not a support; a body
  // with none counts as 0). Bodies of no height come last, ranked the same
  // way when such a chain reaches them (from any height), else
  // not_supported (left out).
  std::vector<uint32_t> rank;

  // Workspace, reused from step to step so that a settled step allocates
  // nothing; not state (rebuilt from the contacts every step).
  struct Edge {
    uint32_t from, to;
  };
  // Edges grouped by `from`: the neighbours of body i are to[first[i] ..
  // first[i + 1]).
  struct Adjacency {
    std::vector<uint32_t> first, to, fill;
  };
  std::vector<Edge> supports, sideways;
  Adjacency adjacency;
  std::vector<uint32_t> queue, sideways_distance, deepest, first_rank;
  std::vector<uint8_t> seed;
};

// Only contacts that touch (manifold.h: within touch_tolerance) hold a body
// up; a speculative contact further apart holds nothing yet. Sideways
// chains run through speculative contacts too.
void shock_levels(const std::vector<Body>& bodies, const std::vector<Contact>& contacts, Vec3 gravity,
                  ShockLevels& levels);

}  // namespace bitstep
