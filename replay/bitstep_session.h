/* bitstep's C API for a networked game's ticks (the C++ Session of
 * replay/session.h): N players' inputs applied to every peer's simulation
 * in the same order, in lockstep (a tick runs when every input is here) or
 * with rollback (a tick runs at once on predicted inputs and is run again
 * when a real one differs), the game's own state (a score, a health bar)
 * saved and restored with the physics, and peers comparing checksums.
 *
 * No transport: the session gives the packets to send to every other peer
 * (bitstep_session_take_packet) and takes the packets that arrive
 * (bitstep_session_receive); the game carries them over UDP, ENet or
 * anything else. A lost, repeated or reordered packet costs only time:
 * every input packet repeats what the peers have not acknowledged. A
 * packet marked reliable (a state sent after a desync, or to a joiner)
 * must arrive whole. Peers must start from the same scene and settings:
 * nothing here compares them before the first checksum does.
 *
 * Errors follow bitstep.h: a status, and after every failure on a session
 * bitstep_session_last_error(session) holds the message, valid until the
 * next call on that session. BITSTEP_NOT_READY is no error: the session
 * cannot take this input or run this tick yet. A session is used by one
 * thread at a time; its hooks run inside its calls, on that thread. */
#ifndef BITSTEP_REPLAY_BITSTEP_SESSION_H
#define BITSTEP_REPLAY_BITSTEP_SESSION_H

#include "replay/bitstep.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bitstep_session bitstep_session;

typedef enum { BITSTEP_LOCKSTEP = 0, BITSTEP_ROLLBACK = 1 } bitstep_session_mode;
typedef struct {
  int32_t players;           /* 1..16 */
  int32_t local_player;      /* 0..players - 1 */
  int32_t mode;              /* bitstep_session_mode */
  int32_t input_delay;       /* ticks, 0..32: a local input applies this many ticks later */
  int32_t max_prediction;    /* rollback: ticks ahead of the last confirmed one, 1..64 */
  int32_t checksum_interval; /* every k-th confirmed tick is compared, 1..3600 */
  int32_t leave_after;       /* frames of silence before the host (player 0) drops a player, 0 (never) or 10..100000 */
  int32_t joining;           /* joins a match in progress: waits for the host's state */
  int32_t watching;          /* joins as a spectator */
  int32_t interrupt_after;   /* frames of silence before an INTERRUPTED event, 1..100000 */
} bitstep_session_config;
bitstep_session_config bitstep_default_session_config(void);

/* The game's side of every tick (GGRS's advance, save and load). A tick:
 * apply(player, input) for each player in player order, the world's step,
 * advance(tick), the game's own logic (it may read the step's events).
 * Then the session keeps save's bytes beside the world's state, restores
 * both on a rollback (load), and the checksums peers compare cover both.
 * `sim` is the session's simulation (bitstep_session_simulation): apply
 * inputs to it with bitstep_apply_impulse and the like. save writes the
 * game's state into the buffer and returns its size; when that is more
 * than capacity it is called again with a buffer that large. load returns
 * 0 when it cannot read a state (a joiner then refuses it). save and load
 * both NULL: the game keeps no state beside the world; advance may be
 * NULL. Everything of the game its future depends on belongs in save:
 * what is left out does not roll back, and the peers desync. A hook must
 * not call the session's own functions (it runs inside one of them). */
typedef struct {
  void* user; /* passed to every hook */
  void (*apply)(void* user, bitstep_simulation* sim, int32_t player, const uint8_t* input, size_t size);
  void (*advance)(void* user, bitstep_simulation* sim, int64_t tick);
  size_t (*save)(void* user, uint8_t* buffer, size_t capacity);
  int32_t (*load)(void* user, const uint8_t* state, size_t size);
} bitstep_game_hooks;

/* A session over *sim, which it takes: on success *sim is NULL and the
 * simulation lives in the session (bitstep_session_simulation); on failure
 * *sim is kept, *out is NULL and the message is bitstep_last_error(*sim)
 * (INVALID: "session: input delay: outside 0..32 ticks"). save runs here
 * once, for the state before tick 1. */
bitstep_status bitstep_session_create(bitstep_simulation** sim, const bitstep_session_config* config,
                                      const bitstep_game_hooks* hooks, bitstep_session** out);
void bitstep_session_destroy(bitstep_session* session);
const char* bitstep_session_last_error(const bitstep_session* session);
/* The session's simulation, to read (poses, events) and to apply inputs
 * to inside the hooks; valid until the session is destroyed (destroying
 * it does nothing). Change it only inside apply: anything else is not in
 * every peer's ticks. */
bitstep_simulation* bitstep_session_simulation(bitstep_session* session);

/* The local player's input for its next tick (input_delay after the last
 * one given), up to 1024 bytes. NOT_READY, nothing kept, when that tick
 * is more than max_prediction past the last confirmed one: the game runs
 * too far ahead of its peers and gives this frame's input again next
 * frame; so too for a spectator, and a joiner not yet running. */
bitstep_status bitstep_session_add_local_input(bitstep_session* session, const uint8_t* input, size_t size);
/* Runs the next tick (rolling back first when a known input differs from
 * the one predicted): OK; NOT_READY when it must wait for inputs. */
bitstep_status bitstep_session_advance(bitstep_session* session);
/* A packet from a peer: OK; INVALID when it is not a session packet of
 * this version or the session refused it (counted in the stats: a
 * message out of the window, a forged state). */
bitstep_status bitstep_session_receive(bitstep_session* session, const uint8_t* packet, size_t size);
/* The next packet to send to every other peer, in order: OK with its
 * bytes and *reliable (0 or 1); NOT_FOUND when none waits;
 * BUFFER_TOO_SMALL, *size the bytes needed, the packet kept. */
bitstep_status bitstep_session_take_packet(bitstep_session* session, uint8_t* buffer, size_t capacity, size_t* size,
                                           int32_t* reliable);
/* An inputs packet even when every local input is acknowledged (call it
 * now and then once the match is over, so peers still waiting learn that
 * their last inputs arrived). */
bitstep_status bitstep_session_heartbeat(bitstep_session* session);
/* The host (player 0) lets `player`, an absent slot, play again (or watch)
 * from its next input on: NOT_FOUND for any other peer or slot. */
bitstep_status bitstep_session_admit(bitstep_session* session, int32_t player, int32_t watching);

int64_t bitstep_session_tick(const bitstep_session* session);           /* ticks simulated */
int64_t bitstep_session_confirmed_tick(const bitstep_session* session); /* every input up to it known and used */
int32_t bitstep_session_joined(const bitstep_session* session);         /* 0 while a joiner waits for its state */
/* The checksum (world and game state) after a confirmed tick of the last
 * 1,024: what every peer computed, and what a replay of the match gives. */
bitstep_status bitstep_session_confirmed_checksum(bitstep_session* session, int64_t tick, uint64_t* out);
/* The checksum of a tick as sessions compare it, from the world's
 * (bitstep_checksum) and the game's saved state (save's bytes; NULL for a
 * game without save and load: the world's checksum alone): so a game checks a match's record or its
 * own reference run against what the peers confirmed. */
uint64_t bitstep_session_tick_checksum(uint64_t world_checksum, const uint8_t* game_state, size_t size);
/* Frames this peer runs ahead of the slowest player it follows: skipping
 * that many frames lets the others catch up (GGPO's time sync). */
int32_t bitstep_session_recommended_wait(const bitstep_session* session);

/* What happened, in order: OK with the next event, NOT_FOUND when none
 * waits. At most 256 wait; past that the oldest go (counted). */
typedef enum {
  BITSTEP_SESSION_JOINED = 0,           /* this joiner took the host's state: it runs from tick + 1 */
  BITSTEP_SESSION_PLAYER_JOINED = 1,    /* player plays (or, watching, watches) from tick */
  BITSTEP_SESSION_PLAYER_LEFT = 2,      /* player is absent from tick: the host gave it up */
  BITSTEP_SESSION_INTERRUPTED = 3,      /* nothing heard from player for frames frames */
  BITSTEP_SESSION_RESUMED = 4,          /* player is heard again */
  BITSTEP_SESSION_ROLLED_BACK = 5,      /* ticks tick..to were run again: a prediction was wrong */
  BITSTEP_SESSION_DESYNC = 6,           /* the checksums of tick differ with player's */
  BITSTEP_SESSION_DESYNC_EXPLAINED = 7, /* the first differing field is known (bitstep_session_get_desync) */
  BITSTEP_SESSION_WAIT_RECOMMENDED = 8, /* this peer runs frames frames ahead: skip that many */
  BITSTEP_SESSION_RUNNING = 9           /* every other player has been heard from: the match is under way (once) */
} bitstep_session_event_type;
typedef struct {
  int32_t type; /* bitstep_session_event_type */
  int32_t player;
  int64_t tick, to;
  int32_t frames;
  int32_t watching;
} bitstep_session_event;
bitstep_status bitstep_session_next_event(bitstep_session* session, bitstep_session_event* out);

/* The first desync: its tick, the player whose checksum differed, both
 * checksums, and the first field that differs once the peer's state came
 * ("" until then; "ball.2: linear_velocity.y: ..." or "the game's state:
 * byte 0: 94 vs 93"), valid until the next call on the session. NOT_FOUND
 * while the peers agree. */
typedef struct {
  int64_t tick;
  int32_t player;
  uint64_t local, remote;
  const char* difference;
} bitstep_session_desync;
bitstep_status bitstep_session_get_desync(bitstep_session* session, bitstep_session_desync* out);

typedef struct {
  int64_t rollbacks, resimulated_ticks, stalls;
  int64_t predicted_inputs, mispredicted_inputs;
  int64_t refused_messages, refused_states, dropped_events;
} bitstep_session_stats;
bitstep_status bitstep_session_get_stats(bitstep_session* session, bitstep_session_stats* out);
/* The link to another player, measured from the packets themselves. */
typedef struct {
  int32_t ping_frames;      /* round trip in frames, -1 until measured */
  int32_t frames_ahead;     /* our newest input tick minus the peer's now (negative: behind) */
  int64_t frames_silent;    /* frames since its last packet */
  int64_t packets_received; /* distinct ones */
  int64_t packets_lost;     /* numbers below its highest that never came */
  int64_t duplicates;
} bitstep_peer_stats;
bitstep_status bitstep_session_get_peer_stats(bitstep_session* session, int32_t player, bitstep_peer_stats* out);

#ifdef __cplusplus
}
#endif

#endif
