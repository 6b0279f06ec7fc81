// Sensors and the step's events. A sensor body's shapes report what
// overlaps them and push nothing (a trigger volume, a pickup, a goal line);
// each step the world lists what began and ended touching or overlapping,
// in a defined order, so a lockstep game can react to them.
#pragma once

#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/broadphase.h"
#include "core/contact.h"

namespace bitstep {

// A shape of a sensor body overlapping a shape of another (non-sensor)
// body, keyed as contacts are (body_a < body_b). State: an overlap that
// ends is an event, also after a restore.
struct SensorOverlap {
  ContactKey key;
  friend auto operator<=>(const SensorOverlap&, const SensorOverlap&) = default;
};

enum class EventKind : uint8_t {
  contact_begin,  // two shapes began touching (a contact point within the touch tolerance)
  contact_end,
  sensor_begin,  // a shape began overlapping a sensor's shape
  sensor_end,
  left_world,    // a body crossed the world's bound and was removed (key: its slot twice, shapes 0)
  joint_broken,  // a joint's impulse passed its break_impulse and it was removed (key: its bodies' slots, shapes 0)
};

// One event of a step: what began or ended between the two shapes of `key`.
struct WorldEvent {
  EventKind kind;
  ContactKey key;
  uint32_t joint = 0;  // joint_broken: the joint's slot (its dead slot keeps the generation its handle had)
  friend auto operator<=>(const WorldEvent&, const WorldEvent&) = default;
};

// This step's overlaps: for every broadphase pair of a sensor and a body
// that is not one (and that the collision filters allow), every pair of
// their shapes that overlaps (the narrowphase's exact test, depth > 0);
// where neither body can move this step (core/body.h needs_contacts), last
// step's overlaps of the pair are kept, as contacts are. Sorted by key.
void update_sensor_overlaps(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs,
                            std::vector<SensorOverlap>& overlaps, std::vector<SensorOverlap>& previous);

// The keys of the contacts that touch, in the contacts' (key) order.
void touching_keys(const std::vector<Contact>& contacts, std::vector<ContactKey>& keys);

// What began and ended between two sorted key lists, appended to `events`
// as `begin` / `end` events in key order.
void append_changes(const std::vector<ContactKey>& before, const std::vector<ContactKey>& after, EventKind begin,
                    EventKind end, std::vector<WorldEvent>& events);

}  // namespace bitstep
