// A warm session allocates nothing per tick (replay/session.h): its maps'
// nodes come from its own pool, a tick's inputs, hash and checksum state
// go into places it keeps, and its outgoing messages are filled in place.
// Counted around each of the session's own calls (add_local_input,
// advance, take_outgoing, receive), not the test's network, for peers in
// lockstep and rollback whose messages arrive a few frames late (so
// rollbacks happen), inputs within std::string's inline size. A call that
// rolls back is left out: the world's first steps after a restore
// allocate (about 125 times for 8 ticks of this arena), which is the
// world's to mend, not the session's.
#include <catch2/catch.hpp>

#include <deque>
#include <vector>

#include "replay/session.h"
#include "tests/allocation_counter.h"
#include "tests/replay/session_match.h"

using namespace bitstep;
using namespace bitstep::session_test;
using bitstep::test::allocations;

namespace {

// Frames of a match where every message reaches every other peer `latency`
// frames later; the allocations counted inside the sessions' calls.
struct CountedMatch {
  std::vector<std::unique_ptr<Session>> peers;
  std::vector<std::unique_ptr<ArenaGame>> games;  // with_game: each peer's (GameHooks)
  struct InFlight {
    int64_t due;
    int to;
    SessionMessage message;
  };
  std::deque<InFlight> in_flight;
  int64_t now = 0;
  int latency;
  long counted = 0;
  int64_t left_out = 0;  // calls that rolled back

  CountedMatch(int players, SessionMode mode, int frames_late, bool with_game = false) : latency(frames_late) {
    for (int p = 0; p < players; ++p) {
      SessionConfig c;
      c.players = players;
      c.local_player = p;
      c.mode = mode;
      c.input_delay = 1;
      if (!with_game) {
        peers.push_back(std::make_unique<Session>(arena_simulation(), c, push));
        continue;
      }
      // The game's state saved, kept and restored with every tick, its
      // inputs the gentle pushes: the arena game's charges change the
      // contacts every tick, and the world's scratch, made anew by each
      // restore, then grows again in later steps (the world's allocations,
      // not the session's).
      games.push_back(std::make_unique<ArenaGame>());
      GameHooks hooks = games.back()->hooks();
      hooks.apply = push;
      peers.push_back(std::make_unique<Session>(arena_simulation(), c, std::move(hooks)));
    }
  }
  template <class Call>
  void count(const Session& s, Call call) {
    const long before = allocations.load();
    const int64_t rollbacks = s.stats().rollbacks;
    call();
    if (s.stats().rollbacks != rollbacks) {
      ++left_out;
      return;
    }
    counted += allocations.load() - before;
  }
  void frame() {
    ++now;
    for (size_t p = 0; p < peers.size(); ++p) {
      Session& s = *peers[p];
      const PlayerInput input = script(static_cast<int>(p), s.local_input_tick());
      count(s, [&] { s.add_local_input(input); });
      count(s, [&] { s.advance(); });
      std::span<const SessionMessage> out;
      count(s, [&] { out = s.take_outgoing(); });
      for (const SessionMessage& m : out) {
        for (size_t to = 0; to < peers.size(); ++to) {
          if (to != p) in_flight.push_back({now + latency, static_cast<int>(to), m});
        }
      }
    }
    while (!in_flight.empty() && in_flight.front().due <= now) {
      const InFlight& f = in_flight.front();
      Session& to = *peers[static_cast<size_t>(f.to)];
      count(to, [&] { to.receive(f.message); });
      in_flight.pop_front();
    }
  }
};

}  // namespace

TEST_CASE("a warm session allocates nothing per tick, with a game's own state too", "[session][allocation]") {
  for (const SessionMode mode : {SessionMode::lockstep, SessionMode::rollback}) {
    for (const int players : {2, 4}) {
      for (const bool game : {false, true}) {
        INFO((mode == SessionMode::lockstep ? "lockstep, " : "rollback, ")
             << players << " players" << (game ? ", GameHooks" : ""));
        CountedMatch match(players, mode, 3, game);
        for (int k = 0; k < 1300; ++k) match.frame();  // warm: past the 1024 confirmed hashes remembered
        match.counted = 0;
        match.left_out = 0;
        const int64_t ticks = match.peers[0]->confirmed_tick();
        const int64_t rollbacks = match.peers[0]->stats().rollbacks;
        for (int k = 0; k < 600; ++k) match.frame();
        CHECK(match.peers[0]->confirmed_tick() - ticks > 500);
        if (mode == SessionMode::rollback) CHECK(match.peers[0]->stats().rollbacks > rollbacks);
        if (mode == SessionMode::lockstep) CHECK(match.left_out == 0);
        CHECK(match.counted == 0);
      }
    }
  }
  // The counter counts: a cold session allocates.
  const long before = allocations.load();
  Session cold(arena_simulation(), SessionConfig{}, push);
  CHECK(allocations.load() - before > 0);
}
