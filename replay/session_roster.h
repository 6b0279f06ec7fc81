// Who plays at which tick: a session's roster. Every player is present or
// absent at each tick; an absent player's input is empty and known (no peer
// waits for it or predicts it). The roster changes only by events that the
// host (player 0) puts in its own input stream, so every peer applies the
// same change at the same tick: no tick at or after an event's tick is
// confirmed without the host's input that carries it (replay/session.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace bitstep {

// "player is present (or absent) from tick `from` on", carried with the
// host's input for tick `at` (from <= at: a leave may reach back to the
// first tick whose input the leaver never gave).
struct RosterEvent {
  int64_t at = 0, from = 0;
  int player = 0;
  bool present = false;
  friend bool operator==(const RosterEvent&, const RosterEvent&) = default;
};

class Roster {
 public:
  // Every one of `players` present from tick 1, or those in `present_mask`
  // (bit p: player p) from the tick after `tick` (a joiner's start).
  explicit Roster(int players);
  Roster(int players, uint32_t present_mask);

  bool present(int player, int64_t tick) const;
  // Whether the player's last change made it present (it plays from then on).
  bool present_now(int player) const;
  // The tick of the player's last change (0: none).
  int64_t last_change(int player) const;
  // From `from` on the player is present or absent; a later change of the
  // same player is replaced (a leave reaching back before a join's tick).
  void set(int player, int64_t from, bool present);
  uint32_t mask_at(int64_t tick) const;
  // Changes at or before `tick` are folded into the state before it.
  void forget_before(int64_t tick);

 private:
  struct Player {
    bool initially = true;
    std::vector<std::pair<int64_t, bool>> changes;  // (from, present), ascending
  };
  std::vector<Player> players_;
};

}  // namespace bitstep
