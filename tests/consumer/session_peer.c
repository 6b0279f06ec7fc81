/* A two-player rollback game in C over ENet, on the shared library's C API
 * (replay/bitstep_session.h): each player pushes its ball in an arena;
 * contacts change the game's own state (a ball that meets the other
 * scores, one that meets a wall loses 7 health), which the session saves
 * and rolls back with the physics.
 *
 *   session_peer SCENE PLAYER PORT PEER_PORT TICKS LOSS   a peer on 127.0.0.1
 *   session_peer SCENE reference TICKS                    every input known, no network
 *
 * A peer drops LOSS percent of the packets it sends unreliably (seeded by
 * its player number) and prints, once both peers confirmed every tick,
 *   tick TICKS checksum <16 hex> score A B health C D
 * the reference prints the same line from its own run: tools/check_package.sh
 * runs two peers and the reference and compares the three lines. The
 * players' inputs are a function of the tick, so the reference knows them. */
#include <enet/enet.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "replay/bitstep_session.h"

typedef struct {
  int32_t health[2];
  int32_t score[2];
  bitstep_body balls[2];
} game;

static void check(bitstep_status status, bitstep_simulation* sim, const char* what) {
  if (status == BITSTEP_OK) return;
  fprintf(stderr, "session_peer: %s: %s\n", what, sim != NULL ? bitstep_last_error(sim) : "failed");
  exit(1);
}

/* Which way a player pushes at a tick: 0 none, 1 toward +x, 2 toward -x. */
static uint8_t input_of(int player, int64_t tick) {
  const int64_t phase = (tick * (player + 2)) / (15 + 25 * player);
  return (uint8_t)((phase + player) % 3);
}

static void apply(void* user, bitstep_simulation* sim, int32_t player, const uint8_t* input, size_t size) {
  const game* g = (const game*)user;
  bitstep_pose pose;
  bitstep_vec3 push = {0, 0, 0};
  if (size != 1 || input[0] == 0) return;
  check(bitstep_get_pose(sim, g->balls[player], &pose), sim, "get_pose");
  push.x = bitstep_fixed_from_int(input[0] == 1 ? 400 : -400); /* N s: 0.76 m/s on a 524 kg ball */
  check(bitstep_apply_impulse(sim, g->balls[player], push, pose.position), sim, "apply_impulse");
}

static void advance(void* user, bitstep_simulation* sim, int64_t tick) {
  game* g = (game*)user;
  bitstep_event events[64];
  size_t count = 0, i;
  int p;
  (void)tick;
  check(bitstep_get_events(sim, events, 64, &count), sim, "get_events");
  for (i = 0; i < count; ++i) {
    const bitstep_event* e = &events[i];
    const int meet = e->body_a.index == g->balls[0].index && e->body_b.index == g->balls[1].index;
    if (e->type != BITSTEP_CONTACT_BEGIN) continue;
    for (p = 0; p < 2; ++p) {
      const uint32_t mine = g->balls[p].index;
      if (e->body_a.index != mine && e->body_b.index != mine) continue;
      if (meet) {
        g->score[p] += 1;
      } else if (e->body_a.index != 0 && e->body_b.index != 0) { /* slot 0 is the ground */
        g->health[p] -= 7;
      }
    }
  }
}

static size_t save(void* user, uint8_t* buffer, size_t capacity) {
  const game* g = (const game*)user;
  const size_t size = sizeof g->health + sizeof g->score;
  if (capacity < size) return size;
  memcpy(buffer, g->health, sizeof g->health);
  memcpy(buffer + sizeof g->health, g->score, sizeof g->score);
  return size;
}

static int32_t load(void* user, const uint8_t* state, size_t size) {
  game* g = (game*)user;
  if (size != sizeof g->health + sizeof g->score) return 0;
  memcpy(g->health, state, sizeof g->health);
  memcpy(g->score, state + sizeof g->health, sizeof g->score);
  return 1;
}

static bitstep_simulation* arena(const char* scene, game* g) {
  bitstep_simulation* sim = NULL;
  char error[256];
  if (bitstep_create_from_file(scene, &sim, error, sizeof error) != BITSTEP_OK) {
    fprintf(stderr, "session_peer: %s\n", error);
    exit(1);
  }
  check(bitstep_find_body(sim, "ball0", &g->balls[0]), sim, "find_body");
  check(bitstep_find_body(sim, "ball1", &g->balls[1]), sim, "find_body");
  check(bitstep_set_events(sim, 1), sim, "set_events");
  g->health[0] = g->health[1] = 100;
  g->score[0] = g->score[1] = 0;
  return sim;
}

static void print_result(int64_t ticks, uint64_t checksum, const game* g) {
  printf("tick %" PRId64 " checksum %016" PRIx64 " score %d %d health %d %d\n", ticks, checksum, g->score[0],
         g->score[1], g->health[0], g->health[1]);
}

static int reference(const char* scene, int64_t ticks) {
  game g;
  bitstep_simulation* sim = arena(scene, &g);
  uint8_t state[64];
  uint64_t checksum = 0;
  int64_t t;
  int p;
  for (t = 1; t <= ticks; ++t) {
    for (p = 0; p < 2; ++p) {
      const uint8_t input = input_of(p, t);
      apply(&g, sim, p, &input, 1);
    }
    check(bitstep_step(sim), sim, "step");
    advance(&g, sim, t);
    checksum = bitstep_session_tick_checksum(bitstep_checksum(sim), state, save(&g, state, sizeof state));
  }
  print_result(ticks, checksum, &g);
  bitstep_destroy(sim);
  return 0;
}

/* Every packet the session gives, to the peer (once connected), a
 * seeded share of the unreliable ones dropped. */
static void send_packets(bitstep_session* session, ENetPeer* peer, int loss, uint64_t* random) {
  static uint8_t buffer[1 << 20];
  size_t size = 0;
  int32_t reliable = 0;
  while (bitstep_session_take_packet(session, buffer, sizeof buffer, &size, &reliable) == BITSTEP_OK) {
    *random = *random * 6364136223846793005u + 1442695040888963407u; /* a 64-bit LCG: its high bits */
    if (peer == NULL || (!reliable && (int)((*random >> 33) % 100) < loss)) continue;
    enet_peer_send(peer, 0,
                   enet_packet_create(buffer, size, reliable ? ENET_PACKET_FLAG_RELIABLE : ENET_PACKET_FLAG_UNSEQUENCED));
  }
}

static int play(const char* scene, int player, int port, int peer_port, int64_t ticks, int loss) {
  game g;
  bitstep_simulation* sim = arena(scene, &g);
  bitstep_session_config config = bitstep_default_session_config();
  bitstep_game_hooks hooks;
  bitstep_session* session = NULL;
  ENetAddress bound, address;
  ENetHost* host;
  ENetPeer* peer = NULL;
  ENetEvent event;
  uint64_t random = (uint64_t)player + 1, checksum = 0;
  int64_t next_input = 1, frame, done_at = -1;
  int dialling = 0;
  enet_uint32 wait_ms;
  config.players = 2;
  config.local_player = player;
  config.mode = BITSTEP_ROLLBACK;
  hooks.user = &g;
  hooks.apply = apply;
  hooks.advance = advance;
  hooks.save = save;
  hooks.load = load;
  check(bitstep_session_create(&sim, &config, &hooks, &session), sim, "session_create");

  if (enet_initialize() != 0) return fprintf(stderr, "session_peer: enet_initialize failed\n"), 1;
  enet_address_set_host(&bound, "127.0.0.1");
  bound.port = (enet_uint16)port;
  address = bound;
  address.port = (enet_uint16)peer_port;
  host = enet_host_create(&bound, 1, 1, 0, 0);
  if (host == NULL) return fprintf(stderr, "session_peer: cannot bind 127.0.0.1:%d\n", port), 1;
  /* 1 ms frames, for at most 60 s; once every tick is confirmed, half a
   * second more of heartbeats, so the peer confirms its last ticks too. */
  for (frame = 0; frame < 60000; ++frame) {
    /* Player 1 dials, and dials again when ENet gives an attempt up (a
     * disconnect: player 0 was not listening yet). */
    if (player == 1 && !dialling && peer == NULL) dialling = enet_host_connect(host, &address, 1, 0) != NULL;
    /* Waits up to 1 ms for the first event, then takes what is there: a
     * peer sending every frame would otherwise hold us in this loop. */
    for (wait_ms = frame == 0 ? 10 : 1; enet_host_service(host, &event, wait_ms) > 0; wait_ms = 0) {
      if (event.type == ENET_EVENT_TYPE_CONNECT) peer = event.peer;
      if (event.type == ENET_EVENT_TYPE_DISCONNECT) peer = NULL, dialling = 0;
      if (event.type == ENET_EVENT_TYPE_RECEIVE) {
        bitstep_session_receive(session, event.packet->data, event.packet->dataLength); /* a refusal is counted */
        enet_packet_destroy(event.packet);
      }
    }
    if (peer == NULL) continue;
    if (next_input <= ticks) {
      const uint8_t input = input_of(player, next_input);
      if (bitstep_session_add_local_input(session, &input, 1) == BITSTEP_OK) ++next_input;
    } else {
      check(bitstep_session_heartbeat(session), NULL, "heartbeat");
    }
    while (bitstep_session_advance(session) == BITSTEP_OK && bitstep_session_tick(session) < next_input - 1) {
    }
    send_packets(session, peer, loss, &random);
    if (done_at < 0 && bitstep_session_confirmed_tick(session) >= ticks) done_at = frame;
    if (done_at >= 0 && frame - done_at > 500) break;
  }
  enet_host_flush(host);
  if (bitstep_session_confirmed_checksum(session, ticks, &checksum) != BITSTEP_OK) {
    fprintf(stderr, "session_peer: player %d: tick %" PRId64 " not confirmed (confirmed %" PRId64 ", %s)\n", player,
            ticks, bitstep_session_confirmed_tick(session), peer == NULL ? "no peer connected" : "connected");
    return 1;
  }
  {
    bitstep_session_stats stats;
    bitstep_peer_stats link;
    bitstep_session_get_stats(session, &stats);
    bitstep_session_get_peer_stats(session, 1 - player, &link);
    fprintf(stderr, "player %d: %" PRId64 " rollbacks, %" PRId64 " ticks re-run, %" PRId64 " of %" PRId64
            " packets from the peer lost, ping %d frames\n",
            player, stats.rollbacks, stats.resimulated_ticks, link.packets_lost,
            link.packets_received + link.packets_lost, link.ping_frames);
  }
  print_result(ticks, checksum, &g);
  enet_host_destroy(host);
  enet_deinitialize();
  bitstep_session_destroy(session);
  return 0;
}

int main(int argc, char** argv) {
  if (argc == 4 && strcmp(argv[2], "reference") == 0) return reference(argv[1], atoll(argv[3]));
  if (argc == 7) return play(argv[1], atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), atoll(argv[5]), atoi(argv[6]));
  fprintf(stderr, "usage: session_peer SCENE PLAYER PORT PEER_PORT TICKS LOSS | session_peer SCENE reference TICKS\n");
  return 2;
}
