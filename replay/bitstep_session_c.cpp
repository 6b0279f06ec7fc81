// The C API of sessions (replay/bitstep_session.h) over the C++ Session
// (replay/session.h) and its packet codec (replay/session_codec.h). No
// exception crosses into C; the game's C hooks run inside the session's
// calls, wrapped as GameHooks.
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "replay/bitstep_handle.h"
#include "replay/bitstep_session.h"
#include "replay/session.h"
#include "replay/session_codec.h"

struct bitstep_session {
  std::unique_ptr<bitstep::Session> session;
  bitstep_game_hooks hooks{};
  int players = 0;
  bitstep_simulation sim{static_cast<bitstep::Simulation*>(nullptr)};  // the session's world, borrowed
  std::string last_error;
  struct Packet {
    std::vector<uint8_t> bytes;
    bool reliable = false;
  };
  std::deque<Packet> packets;  // to send, oldest first
  std::deque<bitstep::SessionEvent> events;
  std::string difference;  // the desync's, for bitstep_session_get_desync
};

namespace {

using bitstep::c_api::first_null;
using bitstep::c_api::guarded;

bitstep_status fail(bitstep_session* s, bitstep_status status, std::string message) {
  return bitstep::c_api::fail(s->last_error, status, std::move(message));
}

bitstep_status null_argument(bitstep_session* s, const char* call, const char* argument) {
  return bitstep::c_api::null_argument(s->last_error, call, argument);
}

// What the last call gave to send and to tell, moved into the handle's
// queues (the session's own are valid only until its next call).
bitstep_status collected(bitstep_session* s, bitstep_status status) {
  for (const bitstep::SessionMessage& m : s->session->take_outgoing()) {
    const bool reliable =
        m.kind == bitstep::SessionMessage::Kind::state || m.kind == bitstep::SessionMessage::Kind::join_state;
    s->packets.push_back({bitstep::encode(m), reliable});
  }
  for (const bitstep::SessionEvent& e : s->session->take_events()) s->events.push_back(e);
  while (s->events.size() > bitstep::max_pending_events) s->events.pop_front();
  return status;
}

// The C hooks as the session's: the simulation handle passed to them is
// the session's world, borrowed.
bitstep::GameHooks hooks_of(bitstep_session* s) {
  bitstep::GameHooks game;
  game.apply = [s](bitstep::Simulation& sim, int player, const bitstep::PlayerInput& input) {
    s->sim.sim = &sim;
    s->hooks.apply(s->hooks.user, &s->sim, player, reinterpret_cast<const uint8_t*>(input.data()), input.size());
  };
  if (s->hooks.advance != nullptr) {
    game.advance = [s](bitstep::Simulation& sim, int64_t tick) {
      s->sim.sim = &sim;
      s->hooks.advance(s->hooks.user, &s->sim, tick);
    };
  }
  if (s->hooks.save != nullptr && s->hooks.load != nullptr) {
    // save into the vector's kept memory; once more when it needs more.
    game.save = [s](std::vector<uint8_t>& out) {
      out.resize(out.capacity());
      size_t size = s->hooks.save(s->hooks.user, out.data(), out.size());
      if (size > out.size()) {
        out.resize(size);
        size = s->hooks.save(s->hooks.user, out.data(), out.size());
      }
      out.resize(size <= out.size() ? size : 0);
    };
    game.load = [s](std::span<const uint8_t> state) {
      return s->hooks.load(s->hooks.user, state.data(), state.size()) != 0;
    };
  } else if (s->hooks.save != nullptr || s->hooks.load != nullptr) {
    game.save = [](std::vector<uint8_t>&) {};  // one without the other: check_hooks says so
  }
  return game;
}

bitstep::SessionConfig config_of(const bitstep_session_config& c) {
  bitstep::SessionConfig config;
  config.players = c.players;
  config.local_player = c.local_player;
  config.mode = c.mode == BITSTEP_LOCKSTEP ? bitstep::SessionMode::lockstep : bitstep::SessionMode::rollback;
  config.input_delay = c.input_delay;
  config.max_prediction = c.max_prediction;
  config.checksum_interval = c.checksum_interval;
  config.leave_after = c.leave_after;
  config.joining = c.joining != 0;
  config.watching = c.watching != 0;
  config.interrupt_after = c.interrupt_after;
  return config;
}

}  // namespace

extern "C" {

bitstep_session_config bitstep_default_session_config(void) {
  const bitstep::SessionConfig d;
  return {d.players,           d.local_player, BITSTEP_ROLLBACK,  d.input_delay,      d.max_prediction,
          d.checksum_interval, d.leave_after,  d.joining ? 1 : 0, d.watching ? 1 : 0, d.interrupt_after};
}

bitstep_status bitstep_session_create(bitstep_simulation** sim, const bitstep_session_config* config,
                                      const bitstep_game_hooks* hooks, bitstep_session** out) {
  if (out != nullptr) *out = nullptr;
  if (sim == nullptr || *sim == nullptr) return BITSTEP_NULL_ARGUMENT;
  bitstep_simulation* handle = *sim;
  return guarded(handle, [&] {
    if (const char* null = first_null({{config, "config"}, {hooks, "hooks"}, {out, "out"}})) {
      return bitstep::c_api::null_argument(handle->last_error, "session_create", null);
    }
    if (!handle->owned) {
      return bitstep::c_api::fail(handle->last_error, BITSTEP_INVALID,
                                  "session_create: the simulation is a session's already");
    }
    if (config->mode != BITSTEP_LOCKSTEP && config->mode != BITSTEP_ROLLBACK) {
      return bitstep::c_api::fail(handle->last_error, BITSTEP_INVALID,
                                  "session_create: mode: not a bitstep_session_mode");
    }
    if (hooks->apply == nullptr) {
      return bitstep::c_api::fail(handle->last_error, BITSTEP_INVALID, "session_create: game hooks: apply is required");
    }
    const bitstep::SessionConfig c = config_of(*config);
    if (const bitstep::Result<void> checked = bitstep::check_config(c); !checked.ok()) {
      return bitstep::c_api::fail(handle->last_error, checked.error().within("session_create"));
    }
    auto made = std::make_unique<bitstep_session>();
    made->hooks = *hooks;
    made->players = c.players;
    bitstep::GameHooks game = hooks_of(made.get());
    if (const bitstep::Result<void> checked = bitstep::check_hooks(game); !checked.ok()) {
      return bitstep::c_api::fail(handle->last_error, checked.error().within("session_create"));
    }
    made->session = std::make_unique<bitstep::Session>(std::move(*handle->owned), c, std::move(game));
    made->sim.sim = &made->session->simulation();
    collected(made.get(), BITSTEP_OK);
    delete handle;
    *sim = nullptr;
    *out = made.release();
    return BITSTEP_OK;
  });
}

void bitstep_session_destroy(bitstep_session* session) { delete session; }

const char* bitstep_session_last_error(const bitstep_session* session) {
  return session == nullptr ? "" : session->last_error.c_str();
}

bitstep_simulation* bitstep_session_simulation(bitstep_session* session) {
  return session == nullptr ? nullptr : &session->sim;
}

bitstep_status bitstep_session_add_local_input(bitstep_session* session, const uint8_t* input, size_t size) {
  return guarded(session, [&] {
    if (input == nullptr && size > 0) return null_argument(session, "session_add_local_input", "input (of size > 0)");
    if (size > bitstep::max_input_bytes) {
      return fail(session, BITSTEP_INVALID,
                  "session_add_local_input: " + std::to_string(size) + " bytes, more than 1024");
    }
    const bitstep::PlayerInput bytes(reinterpret_cast<const char*>(input), size);
    if (session->session->add_local_input(bytes)) return collected(session, BITSTEP_OK);
    return collected(session, fail(session, BITSTEP_NOT_READY,
                                   "session_add_local_input: not now (too far ahead of the peers, watching, or "
                                   "not joined yet): give it again next frame"));
  });
}

bitstep_status bitstep_session_advance(bitstep_session* session) {
  return guarded(session, [&] {
    if (session->session->advance()) return collected(session, BITSTEP_OK);
    return collected(session, fail(session, BITSTEP_NOT_READY, "session_advance: waiting for inputs"));
  });
}

bitstep_status bitstep_session_receive(bitstep_session* session, const uint8_t* packet, size_t size) {
  return guarded(session, [&] {
    if (packet == nullptr) return null_argument(session, "session_receive", "packet");
    const bitstep::Result<bitstep::Packet> decoded = bitstep::decode({packet, size});
    if (!decoded.ok()) return bitstep::c_api::fail(session->last_error, decoded.error().within("session_receive"));
    const auto* message = std::get_if<bitstep::SessionMessage>(&decoded.value());
    if (message == nullptr) return fail(session, BITSTEP_INVALID, "session_receive: not a session message");
    if (session->session->receive(*message)) return collected(session, BITSTEP_OK);
    return collected(session, fail(session, BITSTEP_INVALID, "session_receive: refused (counted in the stats)"));
  });
}

bitstep_status bitstep_session_take_packet(bitstep_session* session, uint8_t* buffer, size_t capacity, size_t* size,
                                           int32_t* reliable) {
  return guarded(session, [&] {
    if (const char* null = first_null({{size, "size"}, {reliable, "reliable"}})) {
      return null_argument(session, "session_take_packet", null);
    }
    if (buffer == nullptr && capacity > 0)
      return null_argument(session, "session_take_packet", "buffer (of capacity > 0)");
    if (session->packets.empty()) return fail(session, BITSTEP_NOT_FOUND, "session_take_packet: none waits");
    const bitstep_session::Packet& next = session->packets.front();
    *size = next.bytes.size();
    *reliable = next.reliable ? 1 : 0;
    if (next.bytes.size() > capacity) {
      return fail(session, BITSTEP_BUFFER_TOO_SMALL,
                  "session_take_packet: " + std::to_string(next.bytes.size()) + " bytes needed, " +
                      std::to_string(capacity) + " given");
    }
    std::memcpy(buffer, next.bytes.data(), next.bytes.size());
    session->packets.pop_front();
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_session_heartbeat(bitstep_session* session) {
  return guarded(session, [&] {
    session->session->heartbeat();
    return collected(session, BITSTEP_OK);
  });
}

bitstep_status bitstep_session_admit(bitstep_session* session, int32_t player, int32_t watching) {
  return guarded(session, [&] {
    if (session->session->admit(player, watching != 0)) return collected(session, BITSTEP_OK);
    return fail(session, BITSTEP_NOT_FOUND,
                "session_admit: player " + std::to_string(player) + ": not the host, or not a slot it can admit");
  });
}

int64_t bitstep_session_tick(const bitstep_session* session) {
  return session == nullptr ? 0 : session->session->tick();
}

int64_t bitstep_session_confirmed_tick(const bitstep_session* session) {
  return session == nullptr ? 0 : session->session->confirmed_tick();
}

int32_t bitstep_session_joined(const bitstep_session* session) {
  return session != nullptr && session->session->joined() ? 1 : 0;
}

bitstep_status bitstep_session_confirmed_checksum(bitstep_session* session, int64_t tick, uint64_t* out) {
  return guarded(session, [&] {
    if (out == nullptr) return null_argument(session, "session_confirmed_checksum", "out");
    const std::optional<uint64_t> checksum = session->session->confirmed_hash(tick);
    if (!checksum) {
      return fail(session, BITSTEP_NOT_FOUND,
                  "session_confirmed_checksum: tick " + std::to_string(tick) + " is not confirmed or not remembered");
    }
    *out = *checksum;
    return BITSTEP_OK;
  });
}

uint64_t bitstep_session_tick_checksum(uint64_t world_checksum, const uint8_t* game_state, size_t size) {
  if (game_state == nullptr) return world_checksum;  // a game without save and load
  return bitstep::tick_checksum(world_checksum, {game_state, size});
}

int32_t bitstep_session_recommended_wait(const bitstep_session* session) {
  return session == nullptr ? 0 : session->session->recommended_wait();
}

bitstep_status bitstep_session_next_event(bitstep_session* session, bitstep_session_event* out) {
  return guarded(session, [&] {
    if (out == nullptr) return null_argument(session, "session_next_event", "out");
    if (session->events.empty()) return fail(session, BITSTEP_NOT_FOUND, "session_next_event: none waits");
    const bitstep::SessionEvent& e = session->events.front();
    *out = {static_cast<int32_t>(e.kind), e.player, e.tick, e.to, e.frames, e.watching ? 1 : 0};
    session->events.pop_front();
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_session_get_desync(bitstep_session* session, bitstep_session_desync* out) {
  return guarded(session, [&] {
    if (out == nullptr) return null_argument(session, "session_get_desync", "out");
    const std::optional<bitstep::Desync>& desync = session->session->desync();
    if (!desync) return fail(session, BITSTEP_NOT_FOUND, "session_get_desync: the peers agree");
    session->difference = desync->difference;
    *out = {desync->tick, desync->player, desync->local, desync->remote, session->difference.c_str()};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_session_get_stats(bitstep_session* session, bitstep_session_stats* out) {
  return guarded(session, [&] {
    if (out == nullptr) return null_argument(session, "session_get_stats", "out");
    const bitstep::SessionStats& s = session->session->stats();
    const int64_t dropped = s.dropped_events;
    *out = {s.rollbacks,           s.resimulated_ticks, s.stalls,         s.predicted_inputs,
            s.mispredicted_inputs, s.refused_messages,  s.refused_states, dropped};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_session_get_peer_stats(bitstep_session* session, int32_t player, bitstep_peer_stats* out) {
  return guarded(session, [&] {
    if (out == nullptr) return null_argument(session, "session_get_peer_stats", "out");
    if (player < 0 || player >= session->players) {
      return fail(session, BITSTEP_NOT_FOUND, "session_get_peer_stats: no player " + std::to_string(player));
    }
    const bitstep::PeerStats p = session->session->peer_stats(player);
    *out = {p.ping_frames, p.frames_ahead, p.frames_silent, p.messages_received, p.messages_lost, p.duplicates};
    return BITSTEP_OK;
  });
}

}  // extern "C"

static_assert(BITSTEP_SESSION_WAIT_RECOMMENDED == static_cast<int>(bitstep::SessionEvent::Kind::wait_recommended));
static_assert(BITSTEP_SESSION_RUNNING == static_cast<int>(bitstep::SessionEvent::Kind::running));
static_assert(BITSTEP_SESSION_ROLLED_BACK == static_cast<int>(bitstep::SessionEvent::Kind::rolled_back));
