// Who plays at which tick: a session's roster. Every player slot is, at
// each tick, present (it plays), watching (a spectator: it follows the
// match and acknowledges, but gives no input) or absent. The input of a
// slot that does not play is empty and known: no peer waits for it or
// predicts it. The roster changes only by events that the host (player 0)
// puts in its own input stream, so every peer applies the same change at
// the same tick: no tick at or after an event's tick is confirmed without
// the host's input that carries it (replay/session.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace bitstep {

enum class Presence : uint8_t { absent, present, watching };

// "player is present (absent, watching) from tick `from` on", carried with
// the host's input for tick `at` (from <= at: a leave may reach back to the
// first tick whose input the leaver never gave).
struct RosterEvent {
  int64_t at = 0, from = 0;
  int player = 0;
  Presence presence = Presence::absent;
  friend bool operator==(const RosterEvent&, const RosterEvent&) = default;
};

class Roster {
 public:
  // Every one of `players` present from tick 1; or, for a joiner's start,
  // those in `present` (bit p: player p) present, those in `watching`
  // watching, the others absent.
  explicit Roster(int players);
  Roster(int players, uint32_t present, uint32_t watching);

  Presence at(int player, int64_t tick) const;
  // Gives inputs at the tick.
  bool plays(int player, int64_t tick) const { return at(player, tick) == Presence::present; }
  // As of its last change: present or watching (it acknowledges ticks).
  bool follows(int player) const;
  Presence now(int player) const;
  // From `from` on; a later change of the same player is replaced (a leave
  // reaching back before a join's tick).
  void set(int player, int64_t from, Presence presence);
  // The players (bit p) in `presence` at the tick.
  uint32_t mask_at(int64_t tick, Presence presence) const;
  // Changes at or before `tick` are folded into the state before them.
  void forget_before(int64_t tick);

 private:
  struct Player {
    Presence initially = Presence::present;
    std::vector<std::pair<int64_t, Presence>> changes;  // (from, presence), ascending
  };
  std::vector<Player> players_;
};

}  // namespace bitstep
