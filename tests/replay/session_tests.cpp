// Sessions (replay/session.h) over an in-process network that loses,
// delays, reorders and duplicates messages: 2 and 4 peers in lockstep and
// rollback end with the hash chain of one simulation given every input;
// a flipped bit is caught within a checksum interval, naming the field;
// hostile messages are refused and counted.
#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "fixed/splitmix64.h"
#include "replay/session.h"
#include "replay/session_codec.h"

using namespace bitstep;

namespace {

// Four balls on a floor with a few crates; player p pushes ball p.
const char* const arena = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "floor", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [30, 1, 30]}]},
  {"name": "ball.0", "position": [-3, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.1", "position": [3, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.2", "position": [0, 0.5, -3], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "ball.3", "position": [0, 0.5, 3], "shapes": [{"type": "sphere", "radius": 0.5}]}],
  "generators": [{"type": "stack", "name": "crates", "count": 3, "position": [0, 0, 0]}]})";

Simulation arena_simulation() {
  std::string error;
  auto sim = Simulation::from_text(arena, "arena.json", error);
  INFO(error);
  REQUIRE(sim);
  return std::move(*sim);
}

// The game: an input is the direction of the push held, "x z" in -1..1; a
// ball is pushed with 2000 N along it (the force held while the input is).
void push(Simulation& sim, int player, const PlayerInput& input) {
  if (input.empty()) return;
  const int x = input[0] - '1', z = input[2] - '1';
  const BodyId ball = *sim.find_body("ball." + std::to_string(player));
  sim.apply_force(ball, {Fixed::from_int(200 * x), Fixed{}, Fixed::from_int(200 * z)}, sim.world().body(ball).pose.position);
}

// Player p's k-th input (k from 1): a direction held for 15 ticks, then another.
PlayerInput script(int player, int64_t k) {
  const int64_t phase = (k / 15 + player) % 5;
  static const char* const directions[] = {"2 1", "1 2", "0 1", "1 0", "1 1"};
  return directions[phase];
}

// The chain one simulation computes when given every input in time: the
// k-th input a player gives applies at tick k + delay.
std::vector<uint64_t> reference_chain(int players, int delay, int64_t ticks) {
  Simulation sim = arena_simulation();
  std::vector<uint64_t> chain;
  for (int64_t t = 1; t <= ticks; ++t) {
    for (int p = 0; p < players; ++p) push(sim, p, t <= delay ? PlayerInput{} : script(p, t - delay));
    sim.step();
    chain.push_back(sim.hash());
  }
  return chain;
}

struct Faults {
  int loss_percent = 0;
  int min_delay = 1, max_delay = 1;  // frames (16.7 ms each)
  int duplicate_percent = 0;
};

// Peers exchanging messages through a queue that loses, delays (so
// reorders) and duplicates them; every frame each peer gives its input and
// advances once. Records each peer's confirmed chain.
struct Match {
  std::vector<std::unique_ptr<Session>> peers;
  std::vector<std::vector<uint64_t>> chains;
  struct InFlight {
    int64_t due;
    int to;
    SessionMessage message;
  };
  std::vector<InFlight> in_flight;
  SplitMix64 rng{42};
  Faults faults;
  int delay;

  Match(int players, SessionMode mode, int input_delay, Faults f, int checksum_interval = 1)
      : faults(f), delay(input_delay) {
    for (int p = 0; p < players; ++p) {
      SessionConfig c;
      c.players = players;
      c.local_player = p;
      c.mode = mode;
      c.input_delay = input_delay;
      c.checksum_interval = checksum_interval;
      REQUIRE(config_error(c).empty());
      peers.push_back(std::make_unique<Session>(arena_simulation(), c, push));
    }
    chains.resize(static_cast<size_t>(players));
  }
  int percent() { return static_cast<int>(rng.next() % 100); }

  void frame(int64_t now, int64_t ticks) {
    for (size_t p = 0; p < peers.size(); ++p) {
      Session& s = *peers[p];
      // Past `ticks` too, as a game goes on: the last ticks are confirmed
      // once the inputs after them flow.
      // (local_input_tick() starts at the delay: the k-th input is for tick k + delay.)
      if (s.local_input_tick() < ticks + 30) {
        s.add_local_input(script(static_cast<int>(p), s.local_input_tick() + 1 - delay));
      }
      if (s.tick() < ticks + 30) s.advance();
      for (SessionMessage& m : s.take_outgoing()) {
        for (size_t to = 0; to < peers.size(); ++to) {
          if (to == p || percent() < faults.loss_percent) continue;
          const int copies = percent() < faults.duplicate_percent ? 2 : 1;
          for (int k = 0; k < copies; ++k) {
            const int span = faults.max_delay - faults.min_delay + 1;
            in_flight.push_back({now + faults.min_delay + static_cast<int64_t>(rng.next() % static_cast<uint64_t>(span)),
                                 static_cast<int>(to), m});
          }
        }
      }
    }
    // Deliver what is due, in the (random) order it was sent.
    std::vector<InFlight> later;
    for (InFlight& f : in_flight) {
      if (f.due <= now) {
        peers[static_cast<size_t>(f.to)]->receive(f.message);
      } else {
        later.push_back(std::move(f));
      }
    }
    in_flight = std::move(later);
    // Each peer's newly confirmed hashes (confirmed by advancing or by a message).
    for (size_t p = 0; p < peers.size(); ++p) {
      while (static_cast<int64_t>(chains[p].size()) < peers[p]->confirmed_tick()) {
        chains[p].push_back(*peers[p]->confirmed_hash(static_cast<int64_t>(chains[p].size()) + 1));
      }
    }
  }

  // Frames until every peer confirmed `ticks` (or a bound).
  int64_t play(int64_t ticks) {
    int64_t now = 0;
    const auto done = [&] {
      return std::all_of(peers.begin(), peers.end(), [&](const auto& s) { return s->confirmed_tick() >= ticks; });
    };
    while (!done() && now < 20 * ticks) frame(++now, ticks);
    return now;
  }
};

// What the input given in frame k means: the script's k-th, at tick k + delay.
}  // namespace

TEST_CASE("2 and 4 peers in lockstep and in rollback end with one simulation's chain", "[session]") {
  constexpr int64_t ticks = 300;
  struct Case {
    int players;
    SessionMode mode;
    int delay;
    Faults faults;
    const char* name;
  };
  const Case cases[] = {
      {2, SessionMode::lockstep, 0, {}, "2 lockstep"},
      {2, SessionMode::rollback, 0, {0, 2, 2, 0}, "2 rollback, 2 frames of latency"},
      {4, SessionMode::lockstep, 2, {10, 3, 9, 5}, "4 lockstep, 10% loss, 50-150 ms, duplicates"},
      {4, SessionMode::rollback, 1, {10, 3, 9, 5}, "4 rollback, 10% loss, 50-150 ms, duplicates"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    Match match(c.players, c.mode, c.delay, c.faults);
    const int64_t frames = match.play(ticks);
    const std::vector<uint64_t> expected = reference_chain(c.players, c.delay, ticks);
    for (size_t p = 0; p < match.peers.size(); ++p) {
      INFO("peer " << p << " after " << frames << " frames");
      const Session& s = *match.peers[p];
      REQUIRE(s.confirmed_tick() >= ticks);
      REQUIRE(match.chains[p].size() >= static_cast<size_t>(ticks));
      std::vector<uint64_t> chain(match.chains[p].begin(), match.chains[p].begin() + ticks);
      CHECK(chain == expected);
      CHECK_FALSE(s.desync());
      CHECK(s.stats().refused_messages == 0);
      if (c.mode == SessionMode::rollback && c.faults.max_delay > 1) {
        CHECK(s.stats().rollbacks > 0);  // the predictions were wrong at times, and mended
        CHECK(s.stats().mispredicted_inputs > 0);
      }
      if (c.mode == SessionMode::lockstep) CHECK(s.stats().rollbacks == 0);
    }
  }
}

TEST_CASE("a flipped bit in one peer is reported within a checksum interval, naming the body and field", "[session]") {
  Match match(2, SessionMode::lockstep, 0, {}, 10);
  bool flipped = false;
  int64_t now = 0;
  while (now < 1000 && !(match.peers[0]->desync() && !match.peers[0]->desync()->difference.empty() &&
                         match.peers[1]->desync() && !match.peers[1]->desync()->difference.empty())) {
    Session& cheat = *match.peers[1];
    if (!flipped && cheat.tick() == 199) {
      // One bit of ball.1's velocity, before tick 200.
      Simulation& sim = cheat.simulation();
      const BodyId ball = *sim.find_body("ball.1");
      const Body& body = sim.world().body(ball);
      Vec3 v = body.linear_velocity;
      v.x = Fixed::from_raw(v.x.raw() ^ 1);
      sim.set_velocity(ball, v, body.angular_velocity);
      flipped = true;
    }
    match.frame(++now, 400);
  }
  for (const auto& peer : match.peers) {
    REQUIRE(peer->desync());
    CHECK(peer->desync()->tick == 200);
    INFO(peer->desync()->difference);
    CHECK(peer->desync()->difference.rfind("$.bodies[2].", 0) == 0);  // ball.1's slot
  }
}

TEST_CASE("a session refuses hostile messages and counts them", "[session]") {
  SessionConfig c;
  c.players = 2;
  Session s(arena_simulation(), c, push);
  SessionMessage m;
  m.player = 1;
  m.tick = 1;
  m.inputs = {"1 1"};
  REQUIRE(s.receive(m));
  SessionMessage bad = m;
  bad.player = 0;  // our own player
  CHECK_FALSE(s.receive(bad));
  bad.player = 7;  // no such player
  CHECK_FALSE(s.receive(bad));
  bad = m;
  bad.inputs = {"2 1"};  // contradicts the input for tick 1
  CHECK_FALSE(s.receive(bad));
  bad = m;
  bad.tick = 100000;  // far beyond the window
  CHECK_FALSE(s.receive(bad));
  bad = m;
  bad.inputs = {std::string(max_input_bytes + 1, 'x')};
  bad.tick = 2;
  CHECK_FALSE(s.receive(bad));
  bad = m;
  bad.inputs.assign(max_inputs_per_message + 1, "1 1");
  CHECK_FALSE(s.receive(bad));
  bad = m;
  bad.kind = SessionMessage::Kind::state;
  bad.state = {1, 2, 3};  // no desync to explain: ignored
  CHECK(s.receive(bad));
  CHECK(s.stats().refused_messages == 6);
  CHECK(m.inputs == std::vector<PlayerInput>{"1 1"});
  // The refused input never reached the world: tick 1 runs with "1 1".
  s.add_local_input("1 1");
  REQUIRE(s.advance());
  CHECK(s.confirmed_tick() == 1);
  CHECK(config_error({3, 3, SessionMode::rollback, 0, 8, 1}) == "local player: outside 0..players - 1");
  CHECK(config_error({2, 0, SessionMode::rollback, 0, 65, 1}) == "max prediction: outside 1..64 ticks");
}

TEST_CASE("packets: messages and hellos round-trip, malformed ones are refused with a reason", "[session][codec]") {
  SessionMessage inputs;
  inputs.player = 3;
  inputs.ack = 41;
  inputs.tick = 40;
  inputs.inputs = {"1 1", "", std::string(max_input_bytes, 'z')};
  SessionMessage checksum;
  checksum.kind = SessionMessage::Kind::checksum;
  checksum.player = 1;
  checksum.ack = 9;
  checksum.tick = 10;
  checksum.checksum = 0x0123456789abcdefu;
  SessionMessage state = checksum;
  state.kind = SessionMessage::Kind::state;
  state.checksum = 0;  // a state carries none
  state.state = {1, 2, 3, 4, 5};
  for (const SessionMessage& m : {inputs, checksum, state}) {
    const auto decoded = decode(encode(m));
    REQUIRE(std::holds_alternative<SessionMessage>(decoded));
    const SessionMessage& d = std::get<SessionMessage>(decoded);
    CHECK(d.kind == m.kind);
    CHECK(d.player == m.player);
    CHECK(d.ack == m.ack);
    CHECK(d.tick == m.tick);
    CHECK(d.inputs == m.inputs);
    CHECK(d.checksum == m.checksum);
    CHECK(d.state == m.state);
  }
  const Hello hello{2, 4, SessionMode::lockstep, 3, 0xfeedu};
  const auto decoded_hello = decode(encode(hello));
  REQUIRE(std::holds_alternative<Hello>(decoded_hello));
  CHECK(std::get<Hello>(decoded_hello) == hello);

  const auto reason = [](std::vector<uint8_t> bytes) {
    const auto d = decode(bytes);
    return std::holds_alternative<PacketError>(d) ? std::get<PacketError>(d).reason : std::string("accepted");
  };
  std::vector<uint8_t> good = encode(inputs);
  CHECK(reason({}) == "not a bitstep packet (bad magic)");
  std::vector<uint8_t> bad = good;
  bad[0] = 'x';
  CHECK(reason(bad) == "not a bitstep packet (bad magic)");
  bad = good;
  bad[2] = 9;
  CHECK(reason(bad) == "packet version 9");
  bad = good;
  bad[3] = 7;
  CHECK(reason(bad) == "packet type 7");
  bad = good;
  bad.pop_back();
  CHECK(reason(bad) == "truncated packet");
  bad = good;
  bad.push_back(0);
  CHECK(reason(bad) == "bytes left after the packet");
  bad = good;
  bad[21] = 200;  // the count
  CHECK(reason(bad) == "inputs: more than 128");
  SessionMessage long_input = inputs;
  long_input.inputs = {std::string(max_input_bytes + 1, 'z')};
  CHECK(reason(encode(long_input)) == "inputs: an input longer than 1024 bytes");
  bad = encode(hello);
  bad[6] = 2;  // the mode
  CHECK(reason(bad) == "hello: mode out of range");
  // Every truncation of every packet is refused, none crashes.
  for (const auto& packet : {encode(inputs), encode(checksum), encode(state), encode(hello)}) {
    for (size_t n = 0; n < packet.size(); ++n) {
      CHECK(std::holds_alternative<PacketError>(decode(std::span<const uint8_t>(packet.data(), n))));
    }
  }
}
