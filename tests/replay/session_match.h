// Peers of a session in one process (replay/session.h), over a network
// that loses, delays (so reorders) and duplicates messages: the arena they
// play in, the game and its scripted inputs, the reference chain, and the
// match loop. A peer may go offline (a crash: nothing in or out) and a new
// session may take its slot (a rejoin).
#pragma once

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fixed/splitmix64.h"
#include "replay/session.h"
#include "replay/session_roster.h"

namespace bitstep::session_test {

// Four balls on a floor with a few crates; player p pushes ball p.
inline constexpr const char* arena = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "floor", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [30, 1, 30]}]},
  {"name": "ball.0", "position": [-3, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.1", "position": [3, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.2", "position": [0, 0.5, -3], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.3", "position": [0, 0.5, 3], "shapes": [{"type": "sphere", "radius": 0.5}]}],
  "generators": [{"type": "stack", "name": "crates", "count": 3, "position": [0, 0, 0]}]})";

inline Simulation arena_simulation() {
  Result<Simulation> sim = Simulation::from_text(arena, "arena.json");
  if (!sim.ok()) FAIL(sim.error().message());
  return std::move(sim).value();
}

// The game: an input is the direction of the push held, "x z" in -1..1; a
// ball is pushed with 2000 N along it (the force held while the input is).
inline void push(Simulation& sim, int player, const PlayerInput& input) {
  if (input.empty()) return;
  const int x = input[0] - '1', z = input[2] - '1';
  const BodyId ball = *sim.find_body("ball." + std::to_string(player));
  sim.apply_force(ball, {Fixed::from_int(200 * x), Fixed{}, Fixed::from_int(200 * z)}, sim.world().body(ball).pose.position);
}

// The game's own state beside the world (GameHooks): each ball's health and
// score, changed by the contacts a step begins: a ball that begins touching
// a crate loses 7 health, two balls that meet score a point each and lose
// 3; every 30th tick a ball below 100 heals 1 (a timer). Its state is 4 +
// 4 little-endian i32s; anything it keeps outside them (`leak`, counted by
// a game that forgets to save it) does not roll back.
struct ArenaGame {
  std::array<int32_t, 4> health{100, 100, 100, 100};
  std::array<int32_t, 4> score{};
  bool leak = false;     // a buggy game: heals by the ticks it has run, a count it never saves
  int64_t advances = 0;  // ticks run, rollbacks' included (kept outside the state)

  // The game's input: ball p charges at the crates in the middle (3000 N
  // toward the origin) and steers with the input (as push, 15 times as hard).
  static void charge(Simulation& sim, int player, const PlayerInput& input) {
    const BodyId ball = *sim.find_body("ball." + std::to_string(player));
    const Vec3 at = sim.world().body(ball).pose.position;
    Vec3 force = normalize_or(Vec3{at.x, Fixed{}, at.z}, Vec3{}) * Fixed::from_int(-3000);
    if (!input.empty()) {
      force += Vec3{Fixed::from_int(3000 * (input[0] - '1')), Fixed{}, Fixed::from_int(3000 * (input[2] - '1'))};
    }
    sim.apply_force(ball, force, at);
  }
  int ball_of(const Simulation& sim, uint32_t slot) const {
    for (int p = 0; p < 4; ++p) {
      if (sim.find_body("ball." + std::to_string(p))->index == slot) return p;
    }
    return -1;
  }
  void advance(Simulation& sim, int64_t tick) {
    ++advances;
    const uint32_t floor = sim.find_body("floor")->index;
    for (const WorldEvent& e : sim.world().events()) {
      if (e.kind != EventKind::contact_begin || e.key.body_a == floor || e.key.body_b == floor) continue;
      const int a = ball_of(sim, e.key.body_a), b = ball_of(sim, e.key.body_b);
      if (a >= 0 && b >= 0) {
        for (const int p : {a, b}) {
          score[static_cast<size_t>(p)] += 1;
          health[static_cast<size_t>(p)] -= 3;
        }
      } else if (a >= 0 || b >= 0) {
        health[static_cast<size_t>(a >= 0 ? a : b)] -= 7;
      }
    }
    const bool heal = leak ? advances % 30 == 0 : tick % 30 == 0;
    for (int32_t& h : health) {
      if (heal && h < 100) ++h;
    }
  }
  void save(std::vector<uint8_t>& out) const {
    for (const auto& values : {health, score}) {
      for (const int32_t v : values) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(static_cast<uint32_t>(v) >> (8 * i)));
      }
    }
  }
  bool load(std::span<const uint8_t> in) {
    if (in.size() != 32) return false;
    for (size_t k = 0; k < 8; ++k) {
      uint32_t v = 0;
      for (size_t i = 0; i < 4; ++i) v |= uint32_t{in[4 * k + i]} << (8 * i);
      (k < 4 ? health[k] : score[k - 4]) = static_cast<int32_t>(v);
    }
    return true;
  }
  std::vector<uint8_t> state() const {
    std::vector<uint8_t> out;
    save(out);
    return out;
  }
  GameHooks hooks() {
    return {charge, [this](Simulation& sim, int64_t tick) { advance(sim, tick); },
            [this](std::vector<uint8_t>& out) { save(out); }, [this](std::span<const uint8_t> in) { return load(in); }};
  }
};

// Player p's k-th input (k from 1): a direction held for 15 ticks, then another.
inline PlayerInput script(int player, int64_t k) {
  const int64_t phase = (k / 15 + player) % 5;
  static const char* const directions[] = {"2 1", "1 2", "0 1", "1 0", "1 1"};
  return directions[phase];
}

// The chain one simulation computes when given every input in time: the
// k-th input a player gives applies at tick k + delay. With the roster
// changes a match made (its host's log): an absent player's input is
// empty, and so is a joiner's for the `delay` ticks from its first.
// The chain holds each tick's checksum (Simulation::checksum: what peers
// compare). With `game`, the arena's game plays too: the chain is of
// tick_checksum (the world's and the game's state), and `game` ends as it does.
inline std::vector<uint64_t> reference_chain(int players, int delay, int64_t ticks,
                                             const std::vector<RosterEvent>& log = {}, ArenaGame* game = nullptr) {
  Simulation sim = arena_simulation();
  sim.world().set_events(game != nullptr);
  Roster roster(players);
  std::vector<int64_t> joined(static_cast<size_t>(players), 0);
  for (const RosterEvent& e : log) {
    roster.set(e.player, e.from, e.presence);
    if (e.presence == Presence::present) joined[static_cast<size_t>(e.player)] = e.from;
  }
  std::vector<uint64_t> chain;
  for (int64_t t = 1; t <= ticks; ++t) {
    for (int p = 0; p < players; ++p) {
      const int64_t since = joined[static_cast<size_t>(p)];
      const bool silent = t <= delay || !roster.plays(p, t) || (since > 0 && t >= since && t < since + delay);
      (game != nullptr ? ArenaGame::charge : push)(sim, p, silent ? PlayerInput{} : script(p, t - delay));
    }
    sim.step();
    if (game == nullptr) {
      chain.push_back(sim.checksum());
      continue;
    }
    game->advance(sim, t);
    chain.push_back(tick_checksum(sim.checksum(), game->state()));
  }
  return chain;
}

struct Faults {
  int loss_percent = 0;
  int min_delay = 1, max_delay = 1;  // frames (16.7 ms each)
  int duplicate_percent = 0;
};

// A match's shape, for tests that play several.
struct MatchCase {
  int players;
  SessionMode mode;
  int delay;  // input delay, ticks
  Faults faults;
  const char* name;
};

// Peers exchanging messages through a queue that loses, delays (so
// reorders) and duplicates them; every frame each peer gives its input and
// advances once. Records each peer's confirmed chain (from its first tick).
struct Match {
  std::vector<std::unique_ptr<Session>> peers;
  std::vector<std::unique_ptr<ArenaGame>> games;  // with a game: each peer's
  std::vector<std::vector<uint64_t>> chains;  // chains[p][i]: the hash after tick first_tick + i + 1
  std::vector<bool> online;
  // What each peer's game saw (take_events), and the frame before which it
  // runs nothing (starts late, or waits as its session advised).
  std::vector<std::vector<SessionEvent>> events;
  std::vector<int64_t> idle_until;
  bool honour_waits = false;  // a wait_recommended event idles the peer that many frames
  struct InFlight {
    int64_t due;
    int to;
    SessionMessage message;
  };
  std::vector<InFlight> in_flight;
  SplitMix64 rng{42};
  Faults faults;
  int delay;
  SessionMode mode;
  int leave_after;
  // Sees each message as it is delivered; false holds it back for good.
  std::function<bool(int to, const SessionMessage&)> deliver;

  Match(int players, SessionMode match_mode, int input_delay, Faults f, int checksum_interval = 1, int leave_frames = 0,
        bool with_game = false)
      : faults(f), delay(input_delay), mode(match_mode), leave_after(leave_frames) {
    for (int p = 0; p < players; ++p) {
      if (with_game) games.push_back(std::make_unique<ArenaGame>());
      peers.push_back(session(config(players, p, checksum_interval), p));
    }
    chains.resize(static_cast<size_t>(players));
    online.assign(static_cast<size_t>(players), true);
    events.resize(static_cast<size_t>(players));
    idle_until.assign(static_cast<size_t>(players), 0);
  }
  SessionConfig config(int players, int p, int checksum_interval) const {
    SessionConfig c;
    c.players = players;
    c.local_player = p;
    c.mode = mode;
    c.input_delay = delay;
    c.checksum_interval = checksum_interval;
    c.leave_after = leave_after;
    REQUIRE(check_config(c).ok());
    return c;
  }
  // Player p's session, playing the game when the match has one.
  std::unique_ptr<Session> session(const SessionConfig& c, int p) {
    if (games.empty()) return std::make_unique<Session>(arena_simulation(), c, push);
    ArenaGame& game = *games[static_cast<size_t>(p)];
    Simulation sim = arena_simulation();
    sim.world().set_events(true);
    REQUIRE(check_hooks(game.hooks()).ok());
    return std::make_unique<Session>(std::move(sim), c, game.hooks());
  }
  // A new process in slot p, joining the match in progress (to play, or to watch).
  void rejoin(int p, bool watching = false) {
    SessionConfig c = config(static_cast<int>(peers.size()), p, 1);
    c.joining = true;
    c.watching = watching;
    if (!games.empty()) games[static_cast<size_t>(p)] = std::make_unique<ArenaGame>();  // a new process's
    peers[static_cast<size_t>(p)] = session(c, p);
    chains[static_cast<size_t>(p)].clear();
    events[static_cast<size_t>(p)].clear();
    online[static_cast<size_t>(p)] = true;
  }
  // Player p goes offline once its tick reaches `drop`, and a new session
  // takes its slot once the host's reaches `back` (the host admits it);
  // then the match plays to `ticks`. The frames it took.
  int64_t drop_and_rejoin(int p, int64_t drop, int64_t back, int64_t ticks) {
    int64_t now = 0;
    while (peers[static_cast<size_t>(p)]->tick() < drop && now < 10000) frame(++now, ticks);
    online[static_cast<size_t>(p)] = false;
    while (peers[0]->tick() < back && now < 20000) frame(++now, ticks);
    rejoin(p);
    REQUIRE(peers[0]->admit(p));
    return play(ticks, now);
  }
  int percent() { return static_cast<int>(rng.next() % 100); }

  void frame(int64_t now, int64_t ticks) {
    for (size_t p = 0; p < peers.size(); ++p) {
      if (!online[p]) continue;
      Session& s = *peers[p];
      // Past `ticks` too, as a game goes on: the last ticks are confirmed
      // once the inputs after them flow.
      // (local_input_tick() starts at the delay: the k-th input is for tick k + delay.)
      const bool runs = now >= idle_until[p];
      if (runs && s.joined() && s.local_input_tick() < ticks + 30) {
        s.add_local_input(script(static_cast<int>(p), s.local_input_tick() + 1 - delay));
      }
      if (runs && s.tick() < ticks + 30) s.advance();
      for (const SessionMessage& m : s.take_outgoing()) {
        // A state goes reliably, as the transport sends it.
        const bool reliable = m.kind == SessionMessage::Kind::state || m.kind == SessionMessage::Kind::join_state;
        for (size_t to = 0; to < peers.size(); ++to) {
          if (to == p || (!reliable && percent() < faults.loss_percent)) continue;
          const int copies = !reliable && percent() < faults.duplicate_percent ? 2 : 1;
          for (int k = 0; k < copies; ++k) {
            const int span = faults.max_delay - faults.min_delay + 1;
            in_flight.push_back({now + faults.min_delay + static_cast<int64_t>(rng.next() % static_cast<uint64_t>(span)),
                                 static_cast<int>(to), m});
          }
        }
      }
    }
    // Deliver what is due, in the (random) order it was sent; nothing
    // reaches a peer offline.
    std::vector<InFlight> later;
    for (InFlight& f : in_flight) {
      if (f.due > now) {
        later.push_back(std::move(f));
      } else if (online[static_cast<size_t>(f.to)] && (!deliver || deliver(f.to, f.message))) {
        peers[static_cast<size_t>(f.to)]->receive(f.message);
      }
    }
    in_flight = std::move(later);
    for (size_t p = 0; p < peers.size(); ++p) {
      for (const SessionEvent& e : peers[p]->take_events()) {
        events[p].push_back(e);
        if (honour_waits && e.kind == SessionEvent::Kind::wait_recommended) idle_until[p] = now + 1 + e.frames;
      }
    }
    // Each peer's newly confirmed hashes (confirmed by advancing or by a message).
    for (size_t p = 0; p < peers.size(); ++p) {
      const Session& s = *peers[p];
      while (s.joined() && s.first_tick() + static_cast<int64_t>(chains[p].size()) < s.confirmed_tick()) {
        chains[p].push_back(*s.confirmed_hash(s.first_tick() + static_cast<int64_t>(chains[p].size()) + 1));
      }
    }
  }

  // Frames until every peer online confirmed `ticks` (or a bound).
  int64_t play(int64_t ticks, int64_t now = 0) {
    const auto done = [&] {
      for (size_t p = 0; p < peers.size(); ++p) {
        if (online[p] && peers[p]->confirmed_tick() < ticks) return false;
      }
      return true;
    };
    const int64_t bound = now + 20 * ticks;
    while (!done() && now < bound) frame(++now, ticks);
    return now;
  }
};

}  // namespace bitstep::session_test
