#include "core/sensor.h"

#include <algorithm>

#include "core/collide.h"

namespace bitstep {

namespace {

// Do the two shapes overlap (depth > 0 at some point)?
bool overlap(const Body& a, const Shape& shape_a, const Body& b, const Shape& shape_b) {
  Manifold m;
  const int n = collide({&shape_a, compose(a.pose, shape_a.local)}, {&shape_b, compose(b.pose, shape_b.local)}, Fixed{}, m);
  for (int i = 0; i < n; ++i) {
    if (m.points[static_cast<size_t>(i)].depth > Fixed{}) return true;
  }
  return false;
}

}  // namespace

void update_sensor_overlaps(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs,
                            std::vector<SensorOverlap>& overlaps, std::vector<SensorOverlap>& previous) {
  previous.swap(overlaps);
  overlaps.clear();
  // Pairs of two bodies that cannot move keep what they had (the broadphase
  // reports no pair for them).
  for (const SensorOverlap& o : previous) {
    const Body& a = bodies[o.key.body_a];
    const Body& b = bodies[o.key.body_b];
    if (a.alive && b.alive && !needs_contacts(a) && !needs_contacts(b)) overlaps.push_back(o);
  }
  for (const BodyPair& pair : pairs) {
    const Body& a = bodies[pair.a];
    const Body& b = bodies[pair.b];
    if (a.sensor == b.sensor) continue;  // sensors see bodies, not each other
    if (!collide_together(a.filter, b.filter)) continue;
    for (uint16_t sa = 0; sa < a.shapes.size(); ++sa) {
      for (uint16_t sb = 0; sb < b.shapes.size(); ++sb) {
        if (overlap(a, a.shapes[sa], b, b.shapes[sb])) overlaps.push_back({{pair.a, pair.b, sa, sb}});
      }
    }
  }
  std::sort(overlaps.begin(), overlaps.end());
}

void touching_keys(const std::vector<Contact>& contacts, std::vector<ContactKey>& keys) {
  keys.clear();
  for (const Contact& c : contacts) {  // sorted by key already
    if (touches(c.manifold)) keys.push_back(c.key);
  }
}

void append_changes(const std::vector<ContactKey>& before, const std::vector<ContactKey>& after, EventKind begin,
                    EventKind end, std::vector<WorldEvent>& events) {
  size_t i = 0, j = 0;
  while (i < before.size() || j < after.size()) {
    if (j == after.size() || (i < before.size() && before[i] < after[j])) {
      events.push_back({end, before[i++]});
    } else if (i == before.size() || after[j] < before[i]) {
      events.push_back({begin, after[j++]});
    } else {
      ++i, ++j;
    }
  }
}

}  // namespace bitstep
