// The state of a step alone, for a rollback game: saved into the caller's
// buffer without allocating, and read back into the same world in place.
//
// A snapshot (snapshot.h) carries every body's shapes, mass properties and
// material, which do not change while the body lives. A rollback state
// leaves them out: each live body is named by its serial (core/body.h,
// unique over the world object's life), and a RollbackStates keeps the
// static fields of every body it has seen once, by serial. Restoring keeps
// the static fields of a body still in its slot and brings back those of
// a body removed since (or replaced in its slot by another). Everything
// else is the state the hash covers, in the same description
// (state_description.h), so a restored world hashes and steps exactly as
// the one saved.
//
// Image: "BITSTEPR", version (u32), the world object's number (u64: a state
// restores only into the world it was saved from), the save's number (u64),
// the state's checksum (u64: XXH3-64 of the payload), the number of live
// bodies (u32), the payload's size (u64), each live body's serial (u64, in
// slot order), the payload, XXH3-64 of everything before the payload (u64).
//
// The checksum is what peers compare: the payload holds the step's state
// and nothing of one world object (no serial, world or save number), so two
// worlds in the same state, built by different peers or restored from a
// snapshot, have the same checksum; a state that differs in any field that
// steps (a pose, a velocity, a contact's impulse, a joint's) has another.
// A body's static fields are not in it: they come from the scene and the
// spawns (the state hash, state_hash.h, covers them).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/world.h"
#include "replay/state_bytes.h"
#include "replay/state_description.h"

namespace bitstep {

inline constexpr uint32_t rollback_state_version =
    6;  // 2: cars' tyre impulses; 3: sliders, joint motors; 4: the suspension's impulse, held islands' velocity passes
        // (a setting); 5: dead slots' filters; 6: the state's checksum, serials apart

class RollbackStates final : private state_bytes::BodyStatics {
 public:
  // Writes the state of `world` into `buffer` and returns its size; when
  // that is more than buffer.size(), the buffer holds nothing usable (grow
  // it to the size returned and save again). Allocates only to remember a
  // body it has not seen before.
  // With `checksum`, the state's checksum (what peers compare) there too.
  size_t save(const World& world, std::span<uint8_t> buffer, uint64_t* checksum = nullptr);
  // The same into a vector the caller keeps, grown when the state needs
  // more (then saved again) and sized to it: no allocation once it is large
  // enough.
  void save(const World& world, std::vector<uint8_t>& buffer, uint64_t* checksum = nullptr);
  // The checksum a saved image carries (not verified: restore does), or
  // nullopt when it is not a rollback state of this version.
  static std::optional<uint64_t> checksum(std::span<const uint8_t> image);

  // Reads a state this object saved from `world` back into it, or says why
  // it cannot (another world, a corrupt or truncated image) and changes
  // nothing: it is read into a copy of the world's state, swapped in only
  // when read whole (the copy's memory is kept for the next restore).
  Result<void> restore(std::span<const uint8_t> image, World& world) const;

  // Forgets the static fields of the bodies that were in none of the last
  // `saves` states saved: those states still restore; older ones are then
  // refused (whole, before anything is read). A match that keeps spawning
  // bodies calls it now and then (a session does).
  void forget_all_but_last(uint64_t saves);

  // Bodies whose static fields are kept.
  size_t remembered_bodies() const { return statics_.size(); }

 private:
  void remember(const Body& body) override;
  bool recall(uint64_t serial, Body& body) const override;

  struct Kept {
    Body body;
    uint64_t last_save;  // the number of the last save it was alive in
  };
  uint64_t instance_ = 0;             // the world object they belong to (a new one: forgotten)
  uint64_t saves_ = 0;                // saves made
  uint64_t oldest_restorable_ = 0;    // the number of the oldest save that still restores
  std::map<uint64_t, Kept> statics_;  // by serial
  mutable std::vector<uint8_t> marks_;  // the reader's scratch, kept
  // What a restore reads into (a copy of the world's state), then swaps
  // with the world's.
  mutable OwnedStateParts read_;
};

// The checksum of `world`'s state as a save carries it (what sessions'
// peers compare): saved into a scratch of this thread's, so it allocates
// while the scratch grows. A session gets it from the save it keeps anyway.
uint64_t state_checksum(const World& world);

}  // namespace bitstep
