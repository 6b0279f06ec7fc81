// What a session tells its game (replay/session.h, session_link.h): local
// inputs refused past the prediction window; events (rolled back, a player
// left, interrupted, resumed and joined again, a desync and its report); the
// link's figures (ping, messages lost, duplicates) against the network the
// test made; and the time sync's advice to a peer that runs ahead, which,
// followed, brings it back in step and saves rollbacks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "replay/session.h"
#include "tests/replay/session_match.h"

using namespace bitstep;
using namespace bitstep::session_test;

namespace {

using Kind = SessionEvent::Kind;

std::vector<SessionEvent> of_kind(const std::vector<SessionEvent>& events, Kind kind) {
  std::vector<SessionEvent> out;
  std::copy_if(events.begin(), events.end(), std::back_inserter(out),
               [&](const SessionEvent& e) { return e.kind == kind; });
  return out;
}

}  // namespace

TEST_CASE("add_local_input refuses an input past the prediction window, and takes it once inputs arrive",
          "[session][link]") {
  SessionConfig c;
  c.players = 2;
  c.input_delay = 2;
  c.max_prediction = 5;
  Session s(arena_simulation(), c, push);
  // Nothing from player 1: inputs for ticks 3..7 (the delay's 2 after the
  // confirmed tick 0, and 5 predicted) are taken, the next is not.
  int taken = 0;
  while (s.add_local_input("1 1")) ++taken;
  CHECK(taken == 5);
  CHECK(s.local_input_tick() == 7);
  CHECK_FALSE(s.add_local_input("2 1"));
  CHECK(s.local_input_tick() == 7);  // nothing kept
  // Ticks 1 and 2 (no input from anyone) confirm; 3..7 run on predictions.
  for (int i = 0; i < 7; ++i) CHECK(s.advance());
  CHECK_FALSE(s.advance());  // no local input for tick 8 yet
  CHECK(s.confirmed_tick() == 2);
  taken = 0;
  while (s.add_local_input("1 1")) ++taken;
  CHECK(taken == 2);  // ticks 8 and 9: 2 + 2 + 5
  // Player 1's inputs for ticks 3..5, as predicted, confirm them: three more.
  SessionMessage m;
  m.player = 1;
  m.tick = 3;
  m.inputs = {"", "", ""};
  REQUIRE(s.receive(m));
  CHECK(s.confirmed_tick() == 5);
  taken = 0;
  while (s.add_local_input("1 0")) ++taken;
  CHECK(taken == 3);
  CHECK(s.local_input_tick() == 12);
  // A spectator gives no input.
  SessionConfig w = c;
  w.local_player = 1;
  w.joining = w.watching = true;
  Session spectator(arena_simulation(), w, push);
  CHECK_FALSE(spectator.add_local_input("1 1"));
}

TEST_CASE("events: rollbacks as counted, a player left, interrupted, resumed and joined, desync and its report",
          "[session][link]") {
  constexpr int64_t ticks = 500;
  Match match(3, SessionMode::rollback, 1, {10, 3, 9, 5}, 1, 60);
  match.drop_and_rejoin(2, 100, 300, ticks);

  for (size_t p = 0; p < 3; ++p) {
    INFO("peer " << p);
    const Session& s = *match.peers[p];
    const auto rolled = of_kind(match.events[p], Kind::rolled_back);
    CHECK(static_cast<int64_t>(rolled.size()) == s.stats().rollbacks);
    int64_t resimulated = 0;
    for (const SessionEvent& e : rolled) {
      CHECK(e.tick >= s.first_tick() + 1);
      CHECK(e.tick <= e.to);
      resimulated += e.to - e.tick + 1;
    }
    CHECK(resimulated == s.stats().resimulated_ticks);
    CHECK(of_kind(match.events[p], Kind::desync).empty());
  }
  // Every peer that stayed saw player 2 go silent, leave, join and speak again, in that order.
  const auto changes = match.peers[0]->roster_log();
  for (size_t p = 0; p < 2; ++p) {
    INFO("peer " << p);
    std::vector<Kind> about_2;
    for (const SessionEvent& e : match.events[p]) {
      if (e.player == 2 && e.kind != Kind::rolled_back) about_2.push_back(e.kind);
    }
    CHECK(about_2 == std::vector<Kind>{Kind::interrupted, Kind::player_left, Kind::player_joined, Kind::resumed});
    const auto left = of_kind(match.events[p], Kind::player_left);
    const auto joined = of_kind(match.events[p], Kind::player_joined);
    REQUIRE(left.size() == 1);
    REQUIRE(joined.size() == 1);
    CHECK(left[0].tick == changes[0].from);
    CHECK(joined[0].tick == changes[1].from);
    CHECK_FALSE(joined[0].watching);
    const auto silent = of_kind(match.events[p], Kind::interrupted);
    CHECK(silent[0].frames == 30);  // the default interrupt_after
  }
  // The joiner: joined at the tick it starts from.
  const auto joined = of_kind(match.events[2], Kind::joined);
  REQUIRE(joined.size() == 1);
  CHECK(joined[0].tick == match.peers[2]->first_tick());
  // Each peer said once that the match runs: the two from their first
  // frames, the joiner once in, not before.
  for (size_t p = 0; p < 3; ++p) {
    INFO("peer " << p);
    const auto running = of_kind(match.events[p], Kind::running);
    REQUIRE(running.size() == 1);
    if (p == 2) CHECK(running[0].tick >= joined[0].tick);
  }

  // A flipped bit: both peers report the desync, then its first field.
  Match broken(2, SessionMode::lockstep, 0, {});
  int64_t frame = 0;
  while (broken.peers[1]->tick() < 40) broken.frame(++frame, 300);
  Simulation& sim = broken.peers[1]->simulation();
  const BodyId ball = *sim.find_body("ball.1");
  const Body& body = sim.world().body(ball);
  Vec3 v = body.linear_velocity;
  v.x = Fixed::from_raw(v.x.raw() ^ 1);
  sim.set_velocity(ball, v, body.angular_velocity);
  while (frame < 100) broken.frame(++frame, 300);
  for (size_t p = 0; p < 2; ++p) {
    const auto found = of_kind(broken.events[p], Kind::desync);
    const auto explained = of_kind(broken.events[p], Kind::desync_explained);
    REQUIRE(found.size() == 1);
    REQUIRE(explained.size() == 1);
    CHECK(found[0].player == 1 - static_cast<int>(p));
    CHECK(explained[0].tick == found[0].tick);
    INFO(broken.peers[p]->desync()->difference);
    CHECK(broken.peers[p]->desync()->difference.rfind("$.bodies[2].", 0) == 0);  // ball.1's slot
  }
}

TEST_CASE("link figures: ping, lost messages and duplicates match the network's", "[session][link]") {
  // 4 frames each way, 20% lost, 10% duplicated.
  Match match(2, SessionMode::rollback, 2, {20, 4, 4, 10});
  match.play(900);
  for (int p = 0; p < 2; ++p) {
    INFO("peer " << p);
    const PeerStats link = match.peers[static_cast<size_t>(p)]->peer_stats(1 - p);
    // A quality message's round trip: 4 frames out, 4 back, and the frame
    // the echo waits for the next advance.
    CHECK(link.ping_frames >= 8);
    CHECK(link.ping_frames <= 10);
    // In percent of what was sent (received or lost) and of what arrived.
    const int64_t sent = link.messages_received + link.messages_lost;
    CHECK(sent > 900);
    CHECK(100 * link.messages_lost > 15 * sent);
    CHECK(100 * link.messages_lost < 25 * sent);
    CHECK(100 * link.duplicates > 5 * link.messages_received);
    CHECK(100 * link.duplicates < 15 * link.messages_received);
    CHECK(link.frames_silent <= 8);
    CHECK(std::abs(link.frames_ahead) <= 2);  // both run at one tick a frame
  }
  // Without loss nothing is counted lost.
  Match clean(2, SessionMode::lockstep, 0, {0, 2, 2, 0});
  clean.play(300);
  CHECK(clean.peers[0]->peer_stats(1).messages_lost == 0);
  CHECK(clean.peers[0]->peer_stats(1).duplicates == 0);
}

TEST_CASE("time sync: a peer that starts early is told to wait, and waiting saves rollbacks", "[session][link]") {
  // Peer 1 starts 12 frames late: peer 0 runs ahead, as far as its
  // prediction window lets it, and predicts peer 1's inputs all along.
  const auto run = [](bool honour) {
    Match match(2, SessionMode::rollback, 1, {0, 3, 3, 0});
    match.honour_waits = honour;
    match.idle_until[1] = 12;
    match.play(600);
    return match;
  };
  Match ignored = run(false), followed = run(true);
  const auto advised = of_kind(ignored.events[0], Kind::wait_recommended);
  REQUIRE_FALSE(advised.empty());
  CHECK(advised[0].frames >= 4);
  CHECK(of_kind(ignored.events[1], Kind::wait_recommended).empty());  // the late one is never told to wait
  CHECK(ignored.peers[0]->peer_stats(1).frames_ahead >= 4);
  // Followed, the advice brings peer 0 back in step: it runs within 2 frames of
  // peer 1 and rolls back less.
  CHECK(std::abs(followed.peers[0]->peer_stats(1).frames_ahead) <= 2);
  CHECK(followed.peers[0]->stats().resimulated_ticks < ignored.peers[0]->stats().resimulated_ticks);
  CHECK(followed.chains[0] == followed.chains[1]);
}

TEST_CASE("events a game does not take: the last 256 wait, the older are counted as dropped", "[session][link]") {
  SessionConfig c;
  c.players = 2;
  Session s(arena_simulation(), c, push);
  // Player 1's input changes every tick, and arrives just after the tick ran
  // on the prediction (its last input): every tick is rolled back.
  for (int64_t t = 1; t <= 300; ++t) {
    REQUIRE(s.add_local_input("1 1"));
    REQUIRE(s.advance());
    SessionMessage m;
    m.player = 1;
    m.tick = t;
    m.inputs = {t % 2 == 0 ? "2 1" : "0 1"};
    REQUIRE(s.receive(m));
  }
  REQUIRE(s.advance() == false);  // rolls back tick 300, then waits for the next local input
  CHECK(s.stats().rollbacks == 300);
  const auto events = s.take_events();
  CHECK(events.size() == max_pending_events);
  // 300 rollbacks and the running event (player 1 heard from at tick 1).
  CHECK(s.stats().dropped_events == 301 - static_cast<int64_t>(max_pending_events));
  CHECK(events.back() == SessionEvent{SessionEvent::Kind::rolled_back, -1, 300, 300});
  CHECK(s.take_events().empty());
}
