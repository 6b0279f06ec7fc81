// A game's own state in a session (replay/session.h, GameHooks): health
// and scores that contacts change roll back with the world, every peer
// ends with the state of one run given every input, a joiner starts from
// the host's game state, and a game that keeps something outside its saved
// state is caught by the checksums, the report naming the game's byte.
#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "replay/session.h"
#include "replay/session_codec.h"
#include "replay/session_sync_test.h"
#include "tests/replay/session_match.h"

using namespace bitstep;
using namespace bitstep::session_test;

namespace {

int total_damage(const ArenaGame& game) {
  int damage = 0;
  for (const int32_t h : game.health) damage += 100 - h;
  return damage;
}

}  // namespace

TEST_CASE("a game's health and scores roll back with the world and end the same on every peer", "[session][game]") {
  constexpr int64_t ticks = 400;
  const MatchCase cases[] = {
      {2, SessionMode::rollback, 0, {10, 2, 6, 5}, "2 rollback, 10% loss, 33-100 ms, duplicates"},
      {4, SessionMode::rollback, 1, {10, 3, 9, 5}, "4 rollback, 10% loss, 50-150 ms, duplicates"},
      {4, SessionMode::lockstep, 2, {10, 3, 9, 5}, "4 lockstep, 10% loss, 50-150 ms, duplicates"},
  };
  for (const MatchCase& c : cases) {
    INFO(c.name);
    Match match(c.players, c.mode, c.delay, c.faults, 1, 0, true);
    const int64_t frames = match.play(ticks);
    ArenaGame reference;
    const std::vector<uint64_t> expected = reference_chain(c.players, c.delay, ticks, {}, &reference);
    // The game is played: the balls hit crates and each other within the match.
    CHECK(total_damage(reference) >= 20);
    if (c.players == 4) CHECK(*std::max_element(reference.score.begin(), reference.score.end()) >= 1);  // balls meet
    CHECK(expected != reference_chain(c.players, c.delay, ticks));  // the checksums cover the game
    for (size_t p = 0; p < match.peers.size(); ++p) {
      INFO("peer " << p << " after " << frames << " frames");
      const Session& s = *match.peers[p];
      REQUIRE(s.confirmed_tick() >= ticks);
      std::vector<uint64_t> chain(match.chains[p].begin(), match.chains[p].begin() + ticks);
      CHECK(chain == expected);
      CHECK_FALSE(s.desync());
      if (c.mode == SessionMode::rollback) {
        CHECK(s.stats().rollbacks > 0);  // the game's state went back with the world, and forward again
        CHECK(match.games[p]->advances > s.tick());
      }
    }
  }
}

TEST_CASE("a game that keeps state outside its save desyncs, and the report names the game's byte", "[session][game]") {
  // A heal timer counted by the ticks the game ran, rollbacks' included:
  // peers that roll back differently heal at different ticks.
  Match match(2, SessionMode::rollback, 0, {10, 2, 6, 0}, 1, 0, true);
  for (auto& game : match.games) game->leak = true;
  int64_t now = 0;
  const auto explained = [&] {
    for (const auto& peer : match.peers) {
      if (!peer->desync() || peer->desync()->difference.empty()) return false;
    }
    return true;
  };
  while (!explained() && now < 3000) match.frame(++now, 2000);
  for (const auto& peer : match.peers) {
    REQUIRE(peer->desync());
    INFO(peer->desync()->difference);
    // The worlds agree; the health of a ball (bytes 0-15) differs.
    CHECK(peer->desync()->difference.rfind("the game's state: byte ", 0) == 0);
    CHECK(peer->desync()->local != peer->desync()->remote);
  }
  // Both found it at one tick, though checksums were lost on the way.
  CHECK(match.peers[0]->desync()->tick == match.peers[1]->desync()->tick);
}

TEST_CASE("a player who rejoins starts from the host's game state and ends on the reference", "[session][game][join]") {
  constexpr int64_t ticks = 500;
  for (const SessionMode mode : {SessionMode::lockstep, SessionMode::rollback}) {
    INFO((mode == SessionMode::lockstep ? "lockstep" : "rollback"));
    Match match(3, mode, 1, {10, 3, 9, 5}, 1, 60, true);
    const int64_t now = match.drop_and_rejoin(2, 100, 300, ticks);

    const Session& joiner = *match.peers[2];
    REQUIRE(joiner.joined());
    REQUIRE(joiner.first_tick() > 300);
    ArenaGame reference;
    const std::vector<uint64_t> expected = reference_chain(3, 1, ticks, match.peers[0]->roster_log(), &reference);
    for (size_t p = 0; p < 3; ++p) {
      INFO("peer " << p << " after " << now << " frames");
      const Session& s = *match.peers[p];
      REQUIRE(s.confirmed_tick() >= ticks);
      const std::vector<uint64_t>& chain = match.chains[p];
      REQUIRE(chain.size() >= static_cast<size_t>(ticks - s.first_tick()));
      CHECK(std::vector<uint64_t>(chain.begin(), chain.begin() + (ticks - s.first_tick())) ==
            std::vector<uint64_t>(expected.begin() + s.first_tick(), expected.begin() + ticks));
      CHECK_FALSE(s.desync());
    }
    // The game the joiner took over had taken damage: a fresh one would not
    // have reached the chain above.
    ArenaGame at_join;
    reference_chain(3, 1, joiner.first_tick(), match.peers[0]->roster_log(), &at_join);
    CHECK(total_damage(at_join) > 0);
  }
}

TEST_CASE("game hooks: apply is required, save and load come together, a state packet carries the game's state",
          "[session][game][codec]") {
  ArenaGame game;
  GameHooks hooks = game.hooks();
  CHECK(check_hooks(hooks).ok());
  GameHooks no_load = hooks;
  no_load.load = nullptr;
  CHECK(check_hooks(no_load).error().message() ==
        "game hooks: save and load come together (one is set, the other not)");
  GameHooks no_apply = hooks;
  no_apply.apply = nullptr;
  CHECK(check_hooks(no_apply).error().message() == "game hooks: apply is required");

  SessionMessage m;
  m.kind = SessionMessage::Kind::state;
  m.player = 1;
  m.ack = m.tick = 30;
  m.state = {1, 2, 3};
  m.game_state = game.state();
  const Result<Packet> back = decode(encode(m));
  REQUIRE(back.ok());
  const SessionMessage& read = std::get<SessionMessage>(back.value());
  CHECK(read.state == m.state);
  CHECK(read.game_state == m.game_state);
  std::vector<uint8_t> cut = encode(m);
  cut.pop_back();
  CHECK(decode(cut).error().message() == "truncated packet");
}

TEST_CASE("the game's sync test: its own input code rolled back 8 ticks after each, every checksum the same",
          "[session][game][sync_test]") {
  const auto inputs = [](int player, int64_t tick) { return script(player, tick); };
  {
    ArenaGame game;
    Simulation sim = arena_simulation();
    sim.world().set_events(true);
    const GameSyncTestResult r = game_sync_test(sim, game.hooks(), 4, inputs, 200, 8);
    INFO(r.difference);
    CHECK(r.ok());
    CHECK(r.resimulated_ticks == 8 * (200 - 8 + 1));
    CHECK(total_damage(game) > 0);  // the game was played
    // Its chain is the one a session's peers confirm (the reference, no delay).
    ArenaGame reference;
    CHECK(r.checksums == reference_chain(4, 0, 200, {}, &reference));
  }
  {
    // The heal timer counted outside the game's state: found at the first
    // heal that differs once a ball is hurt, in the game's bytes (the
    // worlds agree).
    ArenaGame game;
    game.leak = true;
    Simulation sim = arena_simulation();
    sim.world().set_events(true);
    const GameSyncTestResult r = game_sync_test(sim, game.hooks(), 4, inputs, 200, 8);
    REQUIRE_FALSE(r.ok());
    CHECK(r.mismatch_tick > 8);  // not before the first rollback
    CHECK(r.difference.rfind("the game's state: byte ", 0) == 0);
  }
  {
    // A game that pushes a ball by a count of its own (not saved): the
    // world differs, named by its field.
    ArenaGame game;
    int64_t pushes = 0;
    GameHooks hooks = game.hooks();
    hooks.advance = [&](Simulation& s, int64_t tick) {
      game.advance(s, tick);
      if (++pushes % 50 == 0)
        s.apply_impulse(*s.find_body("ball.2"), {Fixed::from_int(100), Fixed{}, Fixed{}},
                        s.pose(*s.find_body("ball.2"))->position);
    };
    Simulation sim = arena_simulation();
    sim.world().set_events(true);
    const GameSyncTestResult r = game_sync_test(sim, hooks, 4, inputs, 200, 8);
    REQUIRE_FALSE(r.ok());
    INFO(r.difference);
    CHECK(r.difference.rfind("$.bodies[3].", 0) == 0);  // ball.2's slot
  }
}
