// The world's bound (core/README.md "World bounds"): World::step's last part.
#include "core/world.h"

namespace bitstep {

namespace {

bool beyond(Fixed f) { return f > envelope::world_bound || f < -envelope::world_bound; }

}  // namespace

// Raw comparisons of each live body's centre of mass: no arithmetic, the
// same answer on every build. A static body never moves (creation keeps it
// within 16 km), but one restored from a state past the bound goes too.
void World::remove_beyond_bound() {
  for (uint32_t slot = 0; slot < bodies_.size(); ++slot) {
    const Body& body = bodies_[slot];
    if (!body.alive) continue;
    const Vec3& p = body.pose.position;
    if (!beyond(p.x) && !beyond(p.y) && !beyond(p.z)) continue;
    remove_body({slot, body.generation});
    events_.push_back({EventKind::left_world, {slot, slot, 0, 0}});
  }
}

}  // namespace bitstep
