// The C API's sessions (replay/bitstep_session.h): two peers in rollback
// over a channel that loses, delays and reorders packets play a game whose
// own state (health and score, changed by the step's contact events) rolls
// back with the physics, and both confirm the reference's checksum at every
// tick; a game that leaves part of its state out of save is caught as a
// desync; misuse gets the documented statuses and messages.
#include <catch2/catch.hpp>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "replay/bitstep_session.h"
#include "replay/session.h"
#include "tests/replay/c_api_support.h"

namespace {

// Two balls on a floor between walls, pushed at each other by their players.
const char* const arena_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [10, 1, 10]}]},
  {"name": "west", "type": "static", "position": [-6, 1, 0], "shapes": [{"type": "box", "half_extents": [0.5, 1, 10]}]},
  {"name": "east", "type": "static", "position": [6, 1, 0], "shapes": [{"type": "box", "half_extents": [0.5, 1, 10]}]},
  {"name": "ball0", "position": [-2, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball1", "position": [2, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})";

// The game beside the world: each ball's health and score. A ball that
// meets the other scores; one that meets a wall loses health.
struct Game {
  int32_t health[2] = {100, 100};
  int32_t score[2] = {0, 0};
  bool leaky = false;  // load forgets the score: a rollback keeps the mispredicted one
};

bitstep_body ball(bitstep_simulation* sim, int player) {
  bitstep_body b{};
  REQUIRE(bitstep_find_body(sim, player == 0 ? "ball0" : "ball1", &b) == BITSTEP_OK);
  return b;
}

// A player's input at a tick: which way to push (0 none, 1 toward +x, 2 toward -x), changing every 15-40 ticks.
uint8_t input_of(int player, int64_t tick) {
  const int64_t phase = (tick * (player + 2)) / (15 + 25 * player);
  return static_cast<uint8_t>((phase + player) % 3);
}

void apply(void*, bitstep_simulation* sim, int32_t player, const uint8_t* input, size_t size) {
  if (size != 1 || input[0] == 0) return;
  const bitstep_body b = ball(sim, player);
  bitstep_pose pose{};
  REQUIRE(bitstep_get_pose(sim, b, &pose) == BITSTEP_OK);
  const bitstep_fixed push = input[0] == 1 ? units(400) : units(-400);  // 0.76 m/s on 524 kg
  REQUIRE(bitstep_apply_impulse(sim, b, {push, 0, 0}, pose.position) == BITSTEP_OK);
}

void advance(void* user, bitstep_simulation* sim, int64_t) {
  Game& game = *static_cast<Game*>(user);
  bitstep_event events[64];
  size_t count = 0;
  REQUIRE(bitstep_get_events(sim, events, 64, &count) == BITSTEP_OK);
  const uint32_t ball0 = ball(sim, 0).index, ball1 = ball(sim, 1).index;
  for (size_t i = 0; i < count; ++i) {
    const bitstep_event& e = events[i];
    if (e.type != BITSTEP_CONTACT_BEGIN) continue;
    const bool meet = (e.body_a.index == ball0 && e.body_b.index == ball1);
    for (int p = 0; p < 2; ++p) {
      const uint32_t mine = p == 0 ? ball0 : ball1;
      if (e.body_a.index != mine && e.body_b.index != mine) continue;
      if (meet) {
        game.score[p] += 1;
      } else if (e.body_a.index != 0 && e.body_b.index != 0) {  // not the ground: a wall
        game.health[p] -= 7;
      }
    }
  }
}

size_t save(void* user, uint8_t* buffer, size_t capacity) {
  const Game& game = *static_cast<Game*>(user);
  constexpr size_t size = sizeof game.health + sizeof game.score;
  if (capacity < size) return size;
  std::memcpy(buffer, game.health, sizeof game.health);
  std::memcpy(buffer + sizeof game.health, game.score, sizeof game.score);
  return size;
}

int32_t load(void* user, const uint8_t* state, size_t size) {
  Game& game = *static_cast<Game*>(user);
  if (size != sizeof game.health + sizeof game.score) return 0;
  std::memcpy(game.health, state, sizeof game.health);
  if (!game.leaky) std::memcpy(game.score, state + sizeof game.health, sizeof game.score);
  return 1;
}

bitstep_simulation* arena() {
  bitstep_simulation* sim = simulation_of(arena_scene, "arena.json");
  REQUIRE(bitstep_set_events(sim, 1) == BITSTEP_OK);
  return sim;
}

bitstep_session* peer(int player, Game& game, int max_prediction = 8) {
  bitstep_simulation* sim = arena();
  bitstep_session_config config = bitstep_default_session_config();
  config.players = 2;
  config.local_player = player;
  config.mode = BITSTEP_ROLLBACK;
  config.max_prediction = max_prediction;
  const bitstep_game_hooks hooks{&game, apply, advance, save, load};
  bitstep_session* session = nullptr;
  REQUIRE(bitstep_session_create(&sim, &config, &hooks, &session) == BITSTEP_OK);
  CHECK(sim == nullptr);  // the session took it
  return session;
}

// The reference: every input known, the ticks in order, the checksum a
// session confirms (the world's rollback checksum and the game's bytes).
std::vector<uint64_t> reference(int64_t ticks, Game& game) {
  bitstep_simulation* sim = arena();
  std::vector<uint64_t> checksums;
  for (int64_t t = 1; t <= ticks; ++t) {
    for (int p = 0; p < 2; ++p) {
      const uint8_t input = input_of(p, t);
      apply(&game, sim, p, &input, 1);
    }
    REQUIRE(bitstep_step(sim) == BITSTEP_OK);
    advance(&game, sim, t);
    uint8_t bytes[64];
    const size_t size = save(&game, bytes, sizeof bytes);
    checksums.push_back(bitstep::tick_checksum(bitstep_checksum(sim), {bytes, size}));
  }
  bitstep_destroy(sim);
  return checksums;
}

// Packets between the two peers: each lost with 10%, delayed 1-4 frames
// (so reordered), from a seeded generator.
struct Channel {
  struct InFlight {
    int64_t due;
    int to;
    std::vector<uint8_t> bytes;
  };
  std::mt19937 random{7};
  std::vector<InFlight> flying;
  int64_t sent = 0, lost = 0;

  void take(bitstep_session* from, int to, int64_t frame) {
    uint8_t buffer[65536];
    size_t size = 0;
    int32_t reliable = 0;
    while (bitstep_session_take_packet(from, buffer, sizeof buffer, &size, &reliable) == BITSTEP_OK) {
      ++sent;
      if (!reliable && random() % 10 == 0) {
        ++lost;
        continue;
      }
      flying.push_back({frame + 1 + static_cast<int64_t>(random() % 4), to, {buffer, buffer + size}});
    }
  }
  void deliver(bitstep_session* peers[2], int64_t frame) {
    for (size_t i = 0; i < flying.size();) {
      if (flying[i].due > frame) {
        ++i;
        continue;
      }
      bitstep_session_receive(peers[flying[i].to], flying[i].bytes.data(), flying[i].bytes.size());
      flying.erase(flying.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
};

// Plays `ticks` ticks, then lets every input through until both confirm them.
void play(bitstep_session* peers[2], int64_t ticks, Channel& channel) {
  int64_t next_input[2] = {1, 1};
  for (int64_t frame = 0; frame < 40 * ticks; ++frame) {
    for (int p = 0; p < 2; ++p) {
      if (next_input[p] <= ticks) {
        const uint8_t input = input_of(p, next_input[p]);
        if (bitstep_session_add_local_input(peers[p], &input, 1) == BITSTEP_OK) ++next_input[p];
      } else {
        REQUIRE(bitstep_session_heartbeat(peers[p]) == BITSTEP_OK);
      }
      // Once a frame at least: a rollback and the confirmation of what
      // arrived happen in advance, also when no new tick can run.
      while (bitstep_session_advance(peers[p]) == BITSTEP_OK && bitstep_session_tick(peers[p]) < next_input[p] - 1) {
      }
      channel.take(peers[p], 1 - p, frame);
    }
    channel.deliver(peers, frame);
    if (bitstep_session_confirmed_tick(peers[0]) >= ticks && bitstep_session_confirmed_tick(peers[1]) >= ticks) return;
  }
  bitstep_session_stats a{}, b{};
  bitstep_session_get_stats(peers[0], &a);
  bitstep_session_get_stats(peers[1], &b);
  FAIL("the peers did not confirm every tick: confirmed "
       << bitstep_session_confirmed_tick(peers[0]) << " and " << bitstep_session_confirmed_tick(peers[1]) << ", ticks "
       << bitstep_session_tick(peers[0]) << " and " << bitstep_session_tick(peers[1]) << ", refused "
       << a.refused_messages << " and " << b.refused_messages);
}

}  // namespace

TEST_CASE("C API sessions: two peers under loss roll back the game with the physics and end on the reference",
          "[c_api][session]") {
  constexpr int64_t ticks = 300;
  Game reference_game;
  const std::vector<uint64_t> expected = reference(ticks, reference_game);
  // The game happened: the balls met and hit the walls.
  INFO("reference: scores " << reference_game.score[0] << ", " << reference_game.score[1] << "; health "
                            << reference_game.health[0] << ", " << reference_game.health[1]);
  CHECK(reference_game.score[0] >= 2);
  CHECK(reference_game.health[0] + reference_game.health[1] < 200);

  Game games[2];
  bitstep_session* peers[2] = {peer(0, games[0]), peer(1, games[1])};
  Channel channel;
  play(peers, ticks, channel);
  for (int p = 0; p < 2; ++p) {
    INFO("peer " << p);
    for (int64_t t = 1; t <= ticks; ++t) {
      uint64_t checksum = 0;
      REQUIRE(bitstep_session_confirmed_checksum(peers[p], t, &checksum) == BITSTEP_OK);
      REQUIRE(checksum == expected[static_cast<size_t>(t - 1)]);
    }
    bitstep_session_stats stats{};
    REQUIRE(bitstep_session_get_stats(peers[p], &stats) == BITSTEP_OK);
    CHECK(stats.rollbacks > 0);  // predictions were wrong, and taken back
    int rolled_back = 0, running = 0;
    bitstep_session_event e{};
    while (bitstep_session_next_event(peers[p], &e) == BITSTEP_OK) {
      CHECK(e.type != BITSTEP_SESSION_DESYNC);
      rolled_back += e.type == BITSTEP_SESSION_ROLLED_BACK ? 1 : 0;
      running += e.type == BITSTEP_SESSION_RUNNING ? 1 : 0;
    }
    CHECK(rolled_back == stats.rollbacks);
    CHECK(running == 1);
    bitstep_peer_stats link{};
    REQUIRE(bitstep_session_get_peer_stats(peers[p], 1 - p, &link) == BITSTEP_OK);
    CHECK(link.packets_lost > 0);
    CHECK(link.ping_frames >= 2);
    bitstep_session_desync desync{};
    CHECK(bitstep_session_get_desync(peers[p], &desync) == BITSTEP_NOT_FOUND);
  }
  // The game's state on both is the reference's at the last tick... once
  // they ran it on confirmed inputs (a peer may have run past it: no).
  for (int p = 0; p < 2; ++p) {
    CHECK(std::memcmp(games[p].score, reference_game.score, sizeof reference_game.score) == 0);
    CHECK(std::memcmp(games[p].health, reference_game.health, sizeof reference_game.health) == 0);
  }
  INFO("sent " << channel.sent << ", lost " << channel.lost);
  CHECK(channel.lost > channel.sent / 20);
  bitstep_session_destroy(peers[0]);
  bitstep_session_destroy(peers[1]);
}

TEST_CASE("C API sessions: a score left out of the rollback is a desync, found and explained", "[c_api][session]") {
  Game games[2];
  games[0].leaky = games[1].leaky = true;
  bitstep_session* peers[2] = {peer(0, games[0]), peer(1, games[1])};
  Channel channel;
  play(peers, 300, channel);
  bool found = false;
  for (int p = 0; p < 2; ++p) {
    bitstep_session_desync desync{};
    if (bitstep_session_get_desync(peers[p], &desync) != BITSTEP_OK) continue;
    found = true;
    CHECK(desync.local != desync.remote);
  }
  CHECK(found);
  bitstep_session_destroy(peers[0]);
  bitstep_session_destroy(peers[1]);
}

TEST_CASE("C API sessions: misuse gets the documented statuses and messages", "[c_api][session]") {
  Game game;
  bitstep_simulation* sim = arena();
  bitstep_session_config config = bitstep_default_session_config();
  const bitstep_game_hooks hooks{&game, apply, advance, save, load};
  bitstep_session* session = nullptr;
  CHECK(bitstep_session_create(nullptr, &config, &hooks, &session) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_session_create(&sim, nullptr, &hooks, &session) == BITSTEP_NULL_ARGUMENT);
  CHECK(std::string(bitstep_last_error(sim)) == "session_create: config is NULL");
  config.input_delay = 40;
  CHECK(bitstep_session_create(&sim, &config, &hooks, &session) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)) == "session_create: input delay: outside 0..32 ticks");
  CHECK(session == nullptr);
  CHECK(sim != nullptr);  // kept on failure
  config = bitstep_default_session_config();
  const bitstep_game_hooks half{&game, apply, advance, save, nullptr};
  CHECK(bitstep_session_create(&sim, &config, &half, &session) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)) ==
        "session_create: game hooks: save and load come together (one is set, the other not)");
  const bitstep_game_hooks none{&game, nullptr, nullptr, nullptr, nullptr};
  CHECK(bitstep_session_create(&sim, &config, &none, &session) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)) == "session_create: game hooks: apply is required");
  config.mode = 5;
  CHECK(bitstep_session_create(&sim, &config, &hooks, &session) == BITSTEP_INVALID);
  config = bitstep_default_session_config();
  config.max_prediction = 2;
  REQUIRE(bitstep_session_create(&sim, &config, &hooks, &session) == BITSTEP_OK);

  // The session's world is borrowed: destroying it does nothing; a
  // session cannot be made over it again.
  bitstep_simulation* world = bitstep_session_simulation(session);
  bitstep_destroy(world);
  CHECK(bitstep_slot_count(world) == 5);
  bitstep_session* second = session;
  CHECK(bitstep_session_create(&world, &config, &hooks, &second) == BITSTEP_INVALID);
  CHECK(second == nullptr);
  CHECK(std::string(bitstep_last_error(world)) == "session_create: the simulation is a session's already");

  const uint8_t input = 1;
  CHECK(bitstep_session_add_local_input(session, nullptr, 1) == BITSTEP_NULL_ARGUMENT);
  CHECK(std::string(bitstep_session_last_error(session)) == "session_add_local_input: input (of size > 0) is NULL");
  std::vector<uint8_t> long_input(1025);
  CHECK(bitstep_session_add_local_input(session, long_input.data(), long_input.size()) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_session_last_error(session)) == "session_add_local_input: 1025 bytes, more than 1024");
  // No peer answers: two ticks of prediction, then NOT_READY.
  for (int i = 0; i < 2; ++i) {
    REQUIRE(bitstep_session_add_local_input(session, &input, 1) == BITSTEP_OK);
    REQUIRE(bitstep_session_advance(session) == BITSTEP_OK);
  }
  CHECK(bitstep_session_add_local_input(session, &input, 1) == BITSTEP_NOT_READY);
  CHECK(bitstep_session_advance(session) == BITSTEP_NOT_READY);
  CHECK(std::string(bitstep_session_last_error(session)) == "session_advance: waiting for inputs");
  uint8_t byte = 0;
  size_t size = 0;
  int32_t reliable = 0;
  CHECK(bitstep_session_take_packet(session, &byte, 1, &size, &reliable) == BITSTEP_BUFFER_TOO_SMALL);
  CHECK(size > 1);
  CHECK(bitstep_session_take_packet(session, nullptr, 0, nullptr, &reliable) == BITSTEP_NULL_ARGUMENT);
  const uint8_t garbage[] = {0xde, 0xad, 0xbe, 0xef};
  CHECK(bitstep_session_receive(session, garbage, sizeof garbage) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_session_last_error(session)).rfind("session_receive: ", 0) == 0);
  CHECK(bitstep_session_receive(session, nullptr, 0) == BITSTEP_NULL_ARGUMENT);
  uint64_t checksum = 0;
  CHECK(bitstep_session_confirmed_checksum(session, 50, &checksum) == BITSTEP_NOT_FOUND);
  bitstep_peer_stats link{};
  CHECK(bitstep_session_get_peer_stats(session, 2, &link) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_session_admit(session, 1, 0) == BITSTEP_NOT_FOUND);  // player 1 plays: nothing to admit
  CHECK(bitstep_session_advance(nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_session_next_event(nullptr, nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(std::string(bitstep_session_last_error(nullptr)).empty());
  bitstep_session_destroy(session);
  bitstep_session_destroy(nullptr);
}
