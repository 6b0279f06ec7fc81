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
#include "tests/replay/session_match.h"

using namespace bitstep;
using namespace bitstep::session_test;

TEST_CASE("2 and 4 peers in lockstep and in rollback end with one simulation's chain", "[session]") {
  constexpr int64_t ticks = 300;
  const MatchCase cases[] = {
      {2, SessionMode::lockstep, 0, {}, "2 lockstep"},
      {2, SessionMode::rollback, 0, {0, 2, 2, 0}, "2 rollback, 2 frames of latency"},
      {4, SessionMode::lockstep, 2, {10, 3, 9, 5}, "4 lockstep, 10% loss, 50-150 ms, duplicates"},
      {4, SessionMode::rollback, 1, {10, 3, 9, 5}, "4 rollback, 10% loss, 50-150 ms, duplicates"},
  };
  for (const MatchCase& c : cases) {
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
  CHECK(check_config({3, 3, SessionMode::rollback, 0, 8, 1}).error().message() == "local player: outside 0..players - 1");
  CHECK(check_config({2, 0, SessionMode::rollback, 0, 65, 1}).error().message() == "max prediction: outside 1..64 ticks");
}

TEST_CASE("packets: messages and hellos round-trip, malformed ones are refused with a reason", "[session][codec]") {
  SessionMessage inputs;
  inputs.player = 3;
  inputs.ack = 41;
  inputs.tick = 40;
  inputs.inputs = {"1 1", "", std::string(max_input_bytes, 'z')};
  inputs.sequence = 0xfedcba98u;
  SessionMessage checksum;
  checksum.kind = SessionMessage::Kind::checksum;
  checksum.player = 1;
  checksum.ack = 9;
  checksum.tick = 10;
  checksum.checksum = 0x0123456789abcdefu;
  checksum.earlier = {7, 8, 9};
  SessionMessage state = checksum;
  state.kind = SessionMessage::Kind::state;
  state.checksum = 0;  // a state carries none
  state.earlier.clear();
  state.state = {1, 2, 3, 4, 5};
  state.game_state = {100, 90};
  SessionMessage quality = state;
  quality.kind = SessionMessage::Kind::quality;
  quality.state.clear();
  quality.game_state.clear();
  quality.frame = 600;
  quality.echoes = {{570, 3}, {-1, 0}, {585, 1}};
  // Leaving and joining: the host's roster changes, a relay, a joiner's state and check.
  SessionMessage host_inputs = inputs;
  host_inputs.player = 0;
  host_inputs.roster = {{41, 38, 2, Presence::absent}, {41, 41, 3, Presence::present}, {41, 41, 1, Presence::watching}};
  SessionMessage relay = inputs;
  relay.kind = SessionMessage::Kind::relay;
  relay.subject = 2;
  SessionMessage join_state = state;
  join_state.kind = SessionMessage::Kind::join_state;
  join_state.subject = 1;
  join_state.present = 0b1001;
  join_state.watching = 0b0100;
  join_state.start_hash = 0xabcdefu;
  SessionMessage join_check = checksum;
  join_check.kind = SessionMessage::Kind::join_check;
  join_check.subject = 1;
  join_check.earlier.clear();  // a checksum's alone
  for (const SessionMessage& m : {inputs, checksum, state, host_inputs, relay, join_state, join_check, quality}) {
    const auto decoded = decode(encode(m));
    REQUIRE(decoded.ok());
    REQUIRE(std::holds_alternative<SessionMessage>(decoded.value()));
    const SessionMessage& d = std::get<SessionMessage>(decoded.value());
    CHECK(d.kind == m.kind);
    CHECK(d.sequence == m.sequence);
    CHECK(d.player == m.player);
    CHECK(d.ack == m.ack);
    CHECK(d.tick == m.tick);
    CHECK(d.inputs == m.inputs);
    CHECK(d.checksum == m.checksum);
    CHECK(d.earlier == m.earlier);
    CHECK(d.state == m.state);
    CHECK(d.game_state == m.game_state);
    CHECK(d.frame == m.frame);
    CHECK(d.echoes.size() == m.echoes.size());
    for (size_t i = 0; i < d.echoes.size() && i < m.echoes.size(); ++i) {
      CHECK(d.echoes[i].frame == m.echoes[i].frame);
      CHECK(d.echoes[i].held == m.echoes[i].held);
    }
    CHECK(d.subject == m.subject);
    CHECK(d.roster == m.roster);
    CHECK(d.present == m.present);
    CHECK(d.watching == m.watching);
    CHECK(d.start_hash == m.start_hash);
  }
  const Hello hello{2, 4, SessionMode::lockstep, 3, 0xfeedu};
  const auto decoded_hello = decode(encode(hello));
  REQUIRE(decoded_hello.ok());
  REQUIRE(std::holds_alternative<Hello>(decoded_hello.value()));
  CHECK(std::get<Hello>(decoded_hello.value()) == hello);

  const auto reason = [](std::vector<uint8_t> bytes) {
    const auto d = decode(bytes);
    return !d.ok() ? d.error().message() : std::string("accepted");
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
  bad = encode(checksum);
  bad[33] = 4;  // the earlier checksums' count
  CHECK(reason(bad) == "checksum: more than 3 earlier checksums");
  bad = encode(quality);
  bad[33] = 17;  // the echoes' count
  CHECK(reason(bad) == "quality: more than 16 players");
  bad = good;
  bad.pop_back();
  CHECK(reason(bad) == "truncated packet");
  bad = good;
  bad.push_back(0);
  CHECK(reason(bad) == "bytes left after the packet");
  bad = good;
  bad[25] = 200;  // the count (after magic 2, version, type, sequence 4, player, ack 8, tick 8)
  CHECK(reason(bad) == "inputs: more than 128");
  SessionMessage long_input = inputs;
  long_input.inputs = {std::string(max_input_bytes + 1, 'z')};
  CHECK(reason(encode(long_input)) == "inputs: an input longer than 1024 bytes");
  bad = encode(hello);
  bad[6] = 2;  // the mode
  CHECK(reason(bad) == "hello: mode out of range");
  // Every truncation of every packet is refused, none crashes.
  for (const auto& packet : {encode(inputs), encode(checksum), encode(state), encode(hello), encode(host_inputs),
                             encode(relay), encode(join_state), encode(join_check), encode(quality)}) {
    for (size_t n = 0; n < packet.size(); ++n) {
      CHECK_FALSE(decode(std::span<const uint8_t>(packet.data(), n)).ok());
    }
  }
}

TEST_CASE("a hello that does not fit is refused with its reason, which both sides word alike", "[session][codec]") {
  const Hello match{0, 2, SessionMode::rollback, 1, 0x3c0e9c78ac0b4f0fu};
  Hello hello{1, 2, SessionMode::rollback, 1, 0x3c0e9c78ac0b4f0fu};
  CHECK_FALSE(refusal_of(match, hello, false).has_value());  // it fits
  const auto why = [&](Hello h, bool said_hello = false) { return refusal_of(match, h, said_hello); };
  Hello h = hello;
  h.start_hash = 1;
  CHECK(why(h) == HelloRefused::another_scene);
  h = hello;
  h.players = 3;
  CHECK(why(h) == HelloRefused::player_count);
  h = hello;
  h.mode = SessionMode::lockstep;
  CHECK(why(h) == HelloRefused::mode);
  h = hello;
  h.input_delay = 0;
  CHECK(why(h) == HelloRefused::input_delay);
  h = hello;
  h.player = 2;
  CHECK(why(h) == HelloRefused::no_such_player);
  h.player = 0;
  CHECK(why(h) == HelloRefused::our_player);
  CHECK(why(hello, true) == HelloRefused::player_taken);
  h = hello;
  h.joining = true;
  CHECK_FALSE(why(h, true).has_value());  // a joiner takes a slot that was played
  h.player = 0;
  CHECK(why(h) == HelloRefused::our_player);  // the host is player 0
  Hello player_1 = match;
  player_1.player = 1;
  CHECK(refusal_of(player_1, h, true) == HelloRefused::not_joinable);  // the host's slot, at another peer
  Hello joining_match = match;
  joining_match.players = h.players = 3;
  joining_match.player = 1;
  joining_match.joining = true;
  h.player = 2;
  CHECK(refusal_of(joining_match, h, false) == HelloRefused::not_joinable);  // a joiner is no door

  // The words, from the match's hello and the refused one.
  h = hello;
  h.players = 3;
  CHECK(describe(HelloRefused::player_count, match, 3, h, 3) == "another player count: 2 in the match, 3 in the hello");
  h = hello;
  h.start_hash = 0x10d880ea6600fc89u;
  CHECK(describe(HelloRefused::another_scene, match, 3, h, 3) ==
        "another scene or settings: start state hash 3c0e9c78ac0b4f0f in the match, 10d880ea6600fc89 in the hello");
  CHECK(describe(HelloRefused::version, match, 3, hello, 2) ==
        "another build: packet version 3 in the match, 2 in the hello");
  CHECK(describe(HelloRefused::player_taken, match, 3, hello, 3) == "player 1 said hello already");

  // A refusal round-trips; one of a later version (same layout) still reads.
  const Refusal refusal{HelloRefused::input_delay, match, packet_version()};
  std::vector<uint8_t> bytes = encode(refusal);
  const Result<Packet> back = decode(bytes);
  REQUIRE(back.ok());
  CHECK(std::get<Refusal>(back.value()) == refusal);
  bytes[2] = 9;
  REQUIRE(decode(bytes).ok());
  CHECK(std::get<Refusal>(decode(bytes).value()).version == 9);
  bytes[4] = 0;  // no such reason
  CHECK(decode(bytes).error().message() == "refused: reason out of range");
  // A hello of another build is known as one, to be answered.
  std::vector<uint8_t> old_hello = encode(hello);
  old_hello[2] = 2;
  CHECK_FALSE(decode(old_hello).ok());
  CHECK(looks_like_hello(old_hello));
  CHECK(packet_version(old_hello) == 2);
}
