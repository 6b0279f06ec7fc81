#include "replay/session.h"

#include <xxhash.h>

#include <algorithm>
#include <limits>
#include <utility>

#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"

namespace bitstep {

namespace {

// How far past the ticks it knows a message's tick may be: a peer runs at
// most max_prediction ahead of what it confirmed, its inputs input_delay
// ahead of that, and a burst of inputs is at most a message long.
int64_t window(const SessionConfig& c) {
  return c.max_prediction + c.input_delay + static_cast<int64_t>(max_inputs_per_message) + 2;
}

// host_asked_at_ before the host asks: long ago (frames_ minus it cannot overflow).
constexpr int64_t never_asked = std::numeric_limits<int64_t>::min() / 2;

// Confirmed hashes remembered (for confirmed_hash and late checksums).
constexpr size_t remembered_hashes = 1024;
// States at checksum ticks kept until every peer's checksum agreed.
constexpr size_t remembered_states = 8;
// Frames between the host's sends of a joiner's state while it has not
// acknowledged its first tick, and between every peer's join checks.
constexpr int64_t join_state_every = 30, join_check_every = 4;

template <class Map>
void erase_before(Map& map, int64_t tick) {
  map.erase(map.begin(), map.lower_bound(tick));
}

}  // namespace

Result<void> check_config(const SessionConfig& c) {
  if (c.players < 1 || c.players > 16) return Error{"players", "outside 1..16"};
  if (c.local_player < 0 || c.local_player >= c.players) return Error{"local player", "outside 0..players - 1"};
  if (c.input_delay < 0 || c.input_delay > 32) return Error{"input delay", "outside 0..32 ticks"};
  if (c.max_prediction < 1 || c.max_prediction > 64) return Error{"max prediction", "outside 1..64 ticks"};
  if (c.checksum_interval < 1 || c.checksum_interval > 3600) return Error{"checksum interval", "outside 1..3600 ticks"};
  if (c.leave_after != 0 && (c.leave_after < 10 || c.leave_after > 100000)) return Error{"leave after", "0 or 10..100000 frames"};
  if (c.joining && c.local_player == 0) return Error{"joining", "the host (player 0) cannot join, it starts the match"};
  if (c.watching && !c.joining) return Error{"watching", "a spectator joins a match in progress (joining)"};
  if (c.interrupt_after < 1 || c.interrupt_after > 100000) return Error{"interrupt after", "outside 1..100000 frames"};
  return {};
}

Result<void> check_hooks(const GameHooks& hooks) {
  if (!hooks.apply) return Error{"game hooks", "apply is required"};
  if (static_cast<bool>(hooks.save) != static_cast<bool>(hooks.load)) {
    return Error{"game hooks", "save and load come together (one is set, the other not)"};
  }
  return {};
}

std::string game_state_difference(std::span<const uint8_t> mine, std::span<const uint8_t> theirs) {
  if (std::equal(mine.begin(), mine.end(), theirs.begin(), theirs.end())) return "no field differs";
  size_t at = 0;
  while (at < mine.size() && at < theirs.size() && mine[at] == theirs[at]) ++at;
  if (at == mine.size() || at == theirs.size()) {
    return "the game's state: " + std::to_string(mine.size()) + " bytes vs " + std::to_string(theirs.size());
  }
  return "the game's state: byte " + std::to_string(at) + ": " + std::to_string(mine[at]) + " vs " +
         std::to_string(theirs[at]);
}

uint64_t tick_checksum(uint64_t world_checksum, std::span<const uint8_t> game_state) {
  return XXH3_64bits_withSeed(game_state.data(), game_state.size(), world_checksum);
}

Session::Session(Simulation sim, SessionConfig config, ApplyInput apply)
    : Session(std::move(sim), config, GameHooks{std::move(apply), {}, {}, {}}) {}

Session::Session(Simulation sim, SessionConfig config, GameHooks game)
    : sim_(std::move(sim)),
      config_(config),
      game_(std::move(game)),
      inputs_(static_cast<size_t>(config.players),
              PooledMap<int64_t, PlayerInput>(PoolAllocator<std::pair<const int64_t, PlayerInput>>(pool_.get()))),
      acked_(static_cast<size_t>(config.players), 0),
      confirmed_hashes_(PoolAllocator<std::pair<const int64_t, uint64_t>>(pool_.get())),
      remote_checksums_(PoolAllocator<std::pair<const std::pair<int64_t, int>, uint64_t>>(pool_.get())),
      roster_(config.players),
      start_hash_(sim_.hash()),
      joined_(!config.joining),
      heard_at_(static_cast<size_t>(config.players), 0),
      spoke_at_(static_cast<size_t>(config.players), 0),
      host_asked_at_(static_cast<size_t>(config.players), never_asked),
      wants_in_(static_cast<size_t>(config.players), Presence::absent),
      join_tick_(static_cast<size_t>(config.players), 0),
      join_state_(static_cast<size_t>(config.players)),
      links_(config.players),
      interrupted_(static_cast<size_t>(config.players), 0) {
  // Ticks 1..input_delay have no input, for every player.
  for (auto& known_inputs : inputs_) {
    for (int64_t t = 1; t <= config_.input_delay; ++t) known_inputs[t] = empty_;
  }
  next_local_ = config_.input_delay + 1;
  // Room for the states a rollback may start from: the confirmed tick's and
  // every tick run ahead of it.
  ring_.resize(static_cast<size_t>(config_.max_prediction) + 2);
  ring_tick_.assign(ring_.size(), -1);
  used_.resize(ring_.size());
  game_states_.resize(ring_.size());
  game_tick_.assign(ring_.size(), -1);
  hashes_.assign(ring_.size(), 0);
  run_tick_.assign(ring_.size(), -1);
  checked_states_.resize(remembered_states);
  events_.reserve(max_pending_events);
  // The state before tick 1, and the game's.
  uint64_t world = 0;
  save_state(0, &world);
  checksum_after(0, world);
}

// The state after `tick` (the world's now) into its place in the ring, as
// a rollback state: no allocation once the buffers are large enough.
void Session::save_state(int64_t tick, uint64_t* checksum) {
  const size_t k = static_cast<size_t>(tick) % ring_.size();
  states_.save(sim_.world(), ring_[k], checksum);
  ring_tick_[k] = tick;
  // Now and then, the bodies in none of the states a rollback or a desync
  // report may still restore are forgotten. Between a state's save and its
  // last use each of the ring's ticks may be simulated again at every
  // rollback (ring^2 saves), and checksum ticks are kept for 8 intervals:
  // four times that many saves is the margin.
  if (tick % 256 == 0) {
    const uint64_t ring = ring_.size();
    states_.forget_all_but_last(4 * (ring * ring + remembered_states * static_cast<uint64_t>(config_.checksum_interval)));
  }
}

// The input of a player who does not play (absent, watching) is known: empty.
bool Session::known(int player, int64_t tick) const {
  return !roster_.plays(player, tick) || inputs_[static_cast<size_t>(player)].count(tick) != 0;
}

// Whether this peer (not the host) must wait for the host to confirm the
// tick before it confirms it (lockstep: runs it): a player plays there
// whom the host asked for lately. The host may yet mark that player absent
// from a tick it never got the input for; a tick the host has confirmed it
// had every input for.
bool Session::awaits_host(int64_t tick) const {
  if (config_.local_player == 0 || config_.leave_after == 0 || acked_[0] >= tick) return false;
  for (int p = 1; p < config_.players; ++p) {
    const bool asked = frames_ - host_asked_at_[static_cast<size_t>(p)] < config_.leave_after;
    if (p != config_.local_player && asked && roster_.plays(p, tick)) return true;
  }
  return false;
}

// The player's input for the tick, or its last one before (the prediction).
const PlayerInput& Session::input_for(int player, int64_t tick, bool& predicted) const {
  if (!roster_.plays(player, tick)) {
    predicted = false;
    return empty_;
  }
  const auto& known_inputs = inputs_[static_cast<size_t>(player)];
  const auto at = known_inputs.lower_bound(tick);
  predicted = at == known_inputs.end() || at->first != tick;
  if (!predicted) return at->second;
  return at == known_inputs.begin() ? empty_ : std::prev(at)->second;
}

bool Session::add_local_input(PlayerInput input) {
  if (!joined_ || config_.watching) return false;  // a joiner plays from its state's next tick; a spectator never
  // Too far ahead, unless the host's roster changes must ride (a leaver
  // marked absent is what lets the confirmed tick move on).
  if (next_local_ > confirmed_ + config_.input_delay + config_.max_prediction && next_roster_.empty()) return false;
  const int64_t t = next_local_++;
  inputs_[static_cast<size_t>(config_.local_player)][t] = std::move(input);
  // The host's roster changes ride with this input: every peer applies
  // them when it learns the host's input for t.
  for (RosterEvent e : std::exchange(next_roster_, {})) {
    e.at = t;
    e.from = t;
    // A leaver's inputs count up to the first one the host never got
    // (its peers relayed to it what they held); over ticks where it does
    // not play (a spectator, a joiner not yet in) no further than t.
    if (e.presence == Presence::absent) {
      const auto& theirs = inputs_[static_cast<size_t>(e.player)];
      e.from = confirmed_ + 1;
      while (roster_.plays(e.player, e.from) ? theirs.count(e.from) != 0 : e.from < t) ++e.from;
    }
    roster_at_[t].push_back(e);
    apply_roster(e);
  }
  send_inputs();
  return true;
}

void Session::heartbeat() { send_inputs(true); }

// The lowest ack of the other players who follow the match now (present
// or watching; but `except`), or INT64_MAX when there is none.
int64_t Session::acked_by_all(int except) const {
  int64_t acked = INT64_MAX;
  for (int p = 0; p < config_.players; ++p) {
    if (p != config_.local_player && p != except && roster_.follows(p)) {
      acked = std::min(acked, acked_[static_cast<size_t>(p)]);
    }
  }
  return acked;
}

bool Session::admit(int player, bool watching) {
  if (config_.local_player != 0 || player <= 0 || player >= config_.players) return false;
  // A slot whose player is still heard from is not free.
  const bool heard = frames_ - heard_at_[static_cast<size_t>(player)] < std::max(1, config_.leave_after / 2);
  if (roster_.follows(player) && (config_.leave_after == 0 || heard)) return false;
  wants_in_[static_cast<size_t>(player)] = watching ? Presence::watching : Presence::present;
  return true;
}

// A roster change from the host's input: from `from` on, the player plays
// or not. A leaver's inputs from then on are void (a rollback mends the
// ticks run with them); a joiner's peers resend their inputs from `from` on.
void Session::apply_roster(const RosterEvent& e) {
  roster_log_.push_back(e);
  const size_t p = static_cast<size_t>(e.player);
  if (e.from <= confirmed_) {  // a leaver's input reached this peer but never the host, nor any relay
    if (!desync_) {
      desync_ = Desync{e.from, 0, 0, 0,
                       "roster: player " + std::to_string(e.player) + " changes from tick " + std::to_string(e.from) +
                           ", confirmed here already"};
    }
    return;
  }
  roster_.set(e.player, e.from, e.presence);
  if (e.presence != Presence::absent) {
    event({SessionEvent::Kind::player_joined, e.player, e.from, 0, 0, e.presence == Presence::watching});
    wants_in_[p] = Presence::absent;
    heard_at_[p] = spoke_at_[p] = frames_;
    if (e.player != config_.local_player) {
      join_tick_[p] = e.from;
      acked_[p] = e.from - 1;
      links_.reset(e.player);  // a new process: its messages are numbered from 0
    }
    return;
  }
  event({SessionEvent::Kind::player_left, e.player, e.from});
  join_tick_[p] = 0;
  join_state_[p].reset();
  auto& theirs = inputs_[p];
  theirs.erase(theirs.lower_bound(e.from), theirs.end());
  for (int64_t t = e.from; t <= tick_; ++t) {
    const std::vector<PlayerInput>* ran = used_at(t);
    if (ran != nullptr && (*ran)[p] != empty_) {
      rollback_from_ = std::min(rollback_from_, t);
      break;
    }
  }
}

// Once a frame: the host's roster decisions; a silent player's inputs
// relayed; a joiner's state (the host) and checks (everyone).
void Session::run_roster() {
  const bool host = config_.local_player == 0;
  const auto queued = [&](int p) {
    return std::any_of(next_roster_.begin(), next_roster_.end(), [&](const RosterEvent& e) { return e.player == p; });
  };
  for (int p = 0; p < config_.players; ++p) {
    const size_t k = static_cast<size_t>(p);
    if (p == config_.local_player) continue;
    const int64_t silent = frames_ - heard_at_[k];
    const int half = std::max(1, config_.leave_after / 2);
    // A joiner is silent until its state reaches it: counted from the state on.
    const bool awaits_state = join_tick_[k] != 0 && !join_state_[k];
    if (host && config_.leave_after > 0 && roster_.follows(p) && silent >= config_.leave_after && !awaits_state &&
        !queued(p)) {
      next_roster_.push_back({0, 0, p, Presence::absent});
    }
    if (host && wants_in_[k] != Presence::absent && !roster_.follows(p) && !queued(p)) {
      next_roster_.push_back({0, 0, p, wants_in_[k]});
    }
    // What a player sent to us and maybe not to others, the host above all
    // (it decides where a leaver's inputs end): relayed when the player is
    // silent to us, or when the host asked for it lately. The host asks by
    // relaying a player whose own messages it has not had for half of
    // `leave_after` (its relayed inputs count as news, not as its voice),
    // with what it holds of it or nothing: a player may be silent to the
    // host alone (it started late, its link to the host is cut).
    const bool host_asks = host && roster_.follows(p) && frames_ - spoke_at_[k] >= half;
    const bool asked = !host && frames_ - host_asked_at_[k] < config_.leave_after;
    if (config_.leave_after > 0 && (silent >= half || asked || host_asks)) {
      const int64_t acked = acked_by_all(p);
      SessionMessage m;
      m.kind = SessionMessage::Kind::relay;
      m.player = config_.local_player;
      m.subject = p;
      m.ack = confirmed_;
      m.tick = acked == INT64_MAX ? confirmed_ + 1 : std::max<int64_t>(acked + 1, 1);
      const auto& theirs = inputs_[k];
      for (auto at = theirs.lower_bound(m.tick); at != theirs.end() && m.inputs.size() < max_inputs_per_message; ++at) {
        if (at->first != m.tick + static_cast<int64_t>(m.inputs.size())) break;
        m.inputs.push_back(at->second);
      }
      if (!m.inputs.empty() || host_asks) send(std::move(m));
    }
    const int64_t joins = join_tick_[k];
    if (joins == 0) continue;
    if (acked_[k] >= joins) {  // the joiner runs
      join_tick_[k] = 0;
      join_state_[k].reset();
      continue;
    }
    if (host && join_state_[k] && frames_ % join_state_every == 0) send(*join_state_[k]);
    const auto checked = confirmed_hash(joins - 1);
    if (checked && frames_ % join_check_every == 0) {
      SessionMessage m;
      m.kind = SessionMessage::Kind::join_check;
      m.player = config_.local_player;
      m.subject = p;
      m.ack = confirmed_;
      m.tick = joins - 1;
      m.checksum = *checked;
      send(std::move(m));
    }
  }
}

// The local inputs no peer has acknowledged (at most a message of them);
// with `always`, a message even when there are none (it carries the ack).
void Session::send_inputs(bool always) {
  if (config_.players < 2 || !joined_) return;
  int64_t acked = acked_by_all();
  if (acked == INT64_MAX) acked = next_local_ - 1;  // nobody else plays now: an ack alone
  // Written in place: it is sent (counted) only when it carries something.
  SessionMessage& m = next_message(SessionMessage::Kind::inputs);
  m.player = config_.local_player;
  m.ack = confirmed_;
  m.tick = std::max<int64_t>(acked + 1, 1);
  const auto& local = inputs_[static_cast<size_t>(config_.local_player)];
  for (auto at = local.lower_bound(m.tick); at != local.end() && m.inputs.size() < max_inputs_per_message; ++at) {
    if (at->first != m.tick + static_cast<int64_t>(m.inputs.size())) break;
    m.inputs.push_back(at->second);
  }
  for (auto at = roster_at_.lower_bound(m.tick);
       at != roster_at_.end() && at->first < m.tick + static_cast<int64_t>(m.inputs.size()); ++at) {
    m.roster.insert(m.roster.end(), at->second.begin(), at->second.end());
  }
  if (always || !m.inputs.empty()) ++outgoing_count_;
}

// The next outgoing message, emptied, its vectors' memory kept; sent once
// outgoing_count_ counts it.
SessionMessage& Session::next_message(SessionMessage::Kind kind) {
  if (outgoing_count_ == outgoing_.size()) outgoing_.emplace_back();
  SessionMessage& m = outgoing_[outgoing_count_];
  m.kind = kind;
  m.player = m.subject = 0;
  m.ack = m.tick = 0;
  m.inputs.clear();
  m.checksum = 0;
  m.earlier.clear();
  m.frame = 0;
  m.echoes.clear();
  m.state.clear();
  m.game_state.clear();
  m.roster.clear();
  m.present = m.watching = 0;
  m.start_hash = 0;
  return m;
}

void Session::send(SessionMessage message) {
  next_message(message.kind) = std::move(message);
  ++outgoing_count_;
}

// The inputs a tick from the confirmed one on ran with, or nullptr.
std::vector<PlayerInput>* Session::used_at(int64_t tick) {
  const size_t k = static_cast<size_t>(tick) % used_.size();
  return tick > 0 && run_tick_[k] == tick ? &used_[k] : nullptr;
}

const Session::CheckedState* Session::checked_state(int64_t tick) const {
  for (const CheckedState& kept : checked_states_) {
    if (kept.tick == tick) return &kept;
  }
  return nullptr;
}

void Session::simulate(int64_t tick) {
  const size_t k = static_cast<size_t>(tick) % used_.size();
  std::vector<PlayerInput>& used = used_[k];  // its strings' memory kept
  used.resize(static_cast<size_t>(config_.players));
  for (int p = 0; p < config_.players; ++p) {
    bool predicted = false;
    used[static_cast<size_t>(p)] = input_for(p, tick, predicted);
    if (predicted) ++stats_.predicted_inputs;
    game_.apply(sim_, p, used[static_cast<size_t>(p)]);
  }
  sim_.step();
  if (game_.advance) game_.advance(sim_, tick);
  tick_ = tick;
  // Each tick's state is kept (a rollback's start, a checksum tick's
  // report), and its save gives the checksum peers compare.
  uint64_t world = 0;
  save_state(tick, &world);
  hashes_[k] = checksum_after(tick, world);
  run_tick_[k] = tick;
}

// The checksum after `tick`, just run (or the state a joiner starts from),
// of the world's state's checksum: with the game's state, saved into its
// place first.
uint64_t Session::checksum_after(int64_t tick, uint64_t world) {
  if (!game_.save) return world;
  const size_t k = static_cast<size_t>(tick) % game_states_.size();
  game_states_[k].clear();  // its memory kept
  game_.save(game_states_[k]);
  game_tick_[k] = tick;
  return tick_checksum(world, game_states_[k]);
}

// The game's state after a tick from the confirmed one on (empty without save).
const std::vector<uint8_t>& Session::game_after(int64_t tick) const {
  static const std::vector<uint8_t> none;
  const size_t k = static_cast<size_t>(tick) % game_states_.size();
  return game_tick_[k] == tick ? game_states_[k] : none;
}

// Back to the state before the first mispredicted tick, and forward again.
void Session::roll_back() {
  const int64_t from = rollback_from_, to = tick_;
  rollback_from_ = INT64_MAX;
  const size_t k = static_cast<size_t>(from - 1) % ring_.size();
  if (ring_tick_[k] != from - 1 || !states_.restore(ring_[k], sim_.world()).ok()) return;  // cannot happen: our own state
  if (game_.load && (game_tick_[k] != from - 1 || !game_.load(game_states_[k]))) return;   // the game's own, as saved
  // The states after `from` on are the mispredicted run's: saved again as it is run again.
  for (int64_t t = from; t <= to; ++t) ring_tick_[static_cast<size_t>(t) % ring_.size()] = -1;
  for (int64_t t = from; t <= to; ++t) simulate(t);
  event({SessionEvent::Kind::rolled_back, -1, from, to});
  ++stats_.rollbacks;
  stats_.resimulated_ticks += to - from + 1;
}

bool Session::advance() {
  ++frames_;
  if (!joined_) return false;
  run_roster();
  watch_links();
  if (config_.watching) send_inputs(true);  // a spectator's ack: it has no inputs to carry it
  const int64_t next = tick_ + 1;
  if (config_.mode == SessionMode::rollback && rollback_from_ <= tick_) roll_back();
  bool ready = known(config_.local_player, next);
  for (int p = 0; p < config_.players && ready; ++p) {
    ready = config_.mode == SessionMode::rollback || known(p, next);
  }
  if (config_.mode == SessionMode::rollback && next - confirmed_ > config_.max_prediction) ready = false;
  if (config_.mode == SessionMode::lockstep && ready && awaits_host(next)) ready = false;
  if (!ready) {
    ++stats_.stalls;
    send_inputs();  // what the peers may have lost, again
    return false;
  }
  simulate(next);
  confirm();
  return true;
}

// Every tick whose inputs are all known and were all used is confirmed: its
// hash is final; at checksum ticks it is sent and compared.
void Session::confirm() {
  while (confirmed_ < tick_ && rollback_from_ > confirmed_ + 1) {
    const int64_t c = confirmed_ + 1;
    bool all = true;
    for (int p = 0; p < config_.players && all; ++p) all = known(p, c);
    if (!all || awaits_host(c)) break;
    confirmed_ = c;
    const uint64_t hash = hashes_[static_cast<size_t>(c) % hashes_.size()];  // run_tick_ has c: not confirmed, so kept
    confirmed_hashes_[c] = hash;
    keep_join_state(c);
    if (c % config_.checksum_interval != 0) continue;
    // The state after c, kept (as a rollback state) until the peers' checksums agree.
    if (!desync_) {  // once there is one, the states around it stay for its report
      CheckedState& kept = checked_states_[static_cast<size_t>(c / config_.checksum_interval) % checked_states_.size()];
      kept.tick = c;
      const std::vector<uint8_t>& now = state_after(c);
      kept.world.assign(now.begin(), now.end());  // its memory kept
      const std::vector<uint8_t>& game = game_after(c);
      kept.game.assign(game.begin(), game.end());
    }
    SessionMessage& m = next_message(SessionMessage::Kind::checksum);
    m.player = config_.local_player;
    m.ack = confirmed_;
    m.tick = c;
    m.checksum = hash;
    for (int64_t t = c - config_.checksum_interval; m.earlier.size() < max_earlier_checksums;
         t -= config_.checksum_interval) {
      const auto earlier = confirmed_hashes_.find(t);
      if (earlier == confirmed_hashes_.end()) break;
      m.earlier.push_back(earlier->second);
    }
    ++outgoing_count_;
    for (auto remote = remote_checksums_.lower_bound(std::pair<int64_t, int>{c, 0});
         remote != remote_checksums_.end() && remote->first.first == c; ++remote) {
      check_checksum(c, remote->first.second);
    }
  }
  // Forget what no rollback or peer can need any more (a rollback starts
  // after the confirmed tick; the prediction base is the input at it).
  // Inputs stay until every player who plays acknowledged them: ours to
  // resend, a silent player's to relay.
  const int64_t acked = std::min(confirmed_, acked_by_all());
  for (auto& known_inputs : inputs_) erase_before(known_inputs, std::min(acked + 1, confirmed_));
  erase_before(roster_at_, std::min(acked + 1, confirmed_));
  roster_.forget_before(confirmed_ - static_cast<int64_t>(remembered_hashes));
  while (confirmed_hashes_.size() > remembered_hashes) confirmed_hashes_.erase(confirmed_hashes_.begin());
  remote_checksums_.erase(remote_checksums_.begin(), remote_checksums_.lower_bound(std::pair<int64_t, int>{
                                                          confirmed_ - static_cast<int64_t>(remembered_hashes), 0}));
}

// The state after a tick from the confirmed one on, as a rollback state:
// every tick's is saved as it is run (simulate), the start's and a
// joiner's first in their place.
const std::vector<uint8_t>& Session::state_after(int64_t c) { return ring_[static_cast<size_t>(c) % ring_.size()]; }

// The host, at the tick before a joiner's first: its snapshot, for the joiner.
void Session::keep_join_state(int64_t c) {
  if (config_.local_player != 0) return;
  for (int p = 1; p < config_.players; ++p) {
    if (join_tick_[static_cast<size_t>(p)] != c + 1) continue;
    SessionMessage m;
    m.kind = SessionMessage::Kind::join_state;
    m.player = 0;
    m.subject = p;
    m.ack = c;
    m.tick = c;
    m.present = roster_.mask_at(c, Presence::present);
    m.watching = roster_.mask_at(c, Presence::watching);
    m.start_hash = start_hash_;
    m.state = snapshot_of(state_after(c));
    m.game_state = game_after(c);
    send(m);
    join_state_[static_cast<size_t>(p)] = std::move(m);
    heard_at_[static_cast<size_t>(p)] = spoke_at_[static_cast<size_t>(p)] = frames_;
  }
}

void Session::check_checksum(int64_t tick, int player) {
  const auto local = confirmed_hashes_.find(tick);
  const auto theirs = remote_checksums_.find(std::pair<int64_t, int>{tick, player});
  if (desync_ || local == confirmed_hashes_.end() || theirs == remote_checksums_.end()) return;
  // A player absent at the tick is not in the match there: its hash is of
  // a run of its own (one the host gave up on while it played on unheard).
  if (roster_.at(player, tick) == Presence::absent) return;
  if (theirs->second == local->second) return;
  desync_ = Desync{tick, player, local->second, theirs->second, {}};
  event({SessionEvent::Kind::desync, player, tick});
  report_desync_at(tick, player);
}

// Our state at a desync's tick, kept for its report and sent to the peer
// (which names the first field that differs); false when not kept. A peer
// that found the desync at another tick moves ours there.
bool Session::report_desync_at(int64_t tick, int player) {
  const CheckedState* state = checked_state(tick);
  if (state == nullptr) return false;
  if (desync_->tick != tick) {
    const auto local = confirmed_hashes_.find(tick);
    const auto theirs = remote_checksums_.find(std::pair<int64_t, int>{tick, player});
    desync_->tick = tick;
    desync_->player = player;
    desync_->local = local == confirmed_hashes_.end() ? 0 : local->second;
    desync_->remote = theirs == remote_checksums_.end() ? 0 : theirs->second;
  }
  desync_snapshot_ = snapshot_of(state->world);
  desync_game_ = state->game;
  SessionMessage m;
  m.kind = SessionMessage::Kind::state;
  m.player = config_.local_player;
  m.ack = confirmed_;
  m.tick = tick;
  m.state = desync_snapshot_;
  m.game_state = desync_game_;
  send(std::move(m));
  return true;
}

// A whole snapshot of a kept rollback state: the world goes there and back.
std::vector<uint8_t> Session::snapshot_of(const std::vector<uint8_t>& state) {
  std::vector<uint8_t> now;
  states_.save(sim_.world(), now);
  if (!states_.restore(state, sim_.world()).ok()) return {};
  std::vector<uint8_t> whole = sim_.save();
  (void)states_.restore(now, sim_.world());
  return whole;
}

bool Session::receive(const SessionMessage& m) {
  const auto refuse = [&] {
    ++stats_.refused_messages;
    return false;
  };
  if (m.player < 0 || m.player >= config_.players || m.player == config_.local_player) return refuse();
  links_.received(m.player, m.sequence, frames_);
  if (!joined_) {  // the match's traffic is not ours until our state is in
    if (m.subject != config_.local_player) return true;
    if (m.kind == SessionMessage::Kind::join_check) {
      join_checks_[m.player] = {m.tick, m.checksum};
      try_join();
    } else if (m.kind == SessionMessage::Kind::join_state) {
      return receive_join_state(m);
    }
    return true;
  }
  const int64_t horizon = std::max(tick_, next_local_ - 1) + window(config_);
  const int64_t first =
      m.kind == SessionMessage::Kind::quality ? 0 : 1;  // a quality message's newest input may be none
  if (m.ack < 0 || m.ack > horizon || m.tick < first || m.tick > horizon) return refuse();
  switch (m.kind) {
    case SessionMessage::Kind::quality:
      if (m.echoes.size() != static_cast<size_t>(config_.players) || m.frame < 0) return refuse();
      links_.quality(m.player, m, config_.local_player, frames_);
      break;
    case SessionMessage::Kind::inputs:
      if (!m.roster.empty() && m.player != 0) return refuse();  // only the host changes the roster
      if (!receive_inputs(m, m.player)) return refuse();
      break;
    case SessionMessage::Kind::relay:
      if (m.subject < 0 || m.subject >= config_.players || !m.roster.empty()) return refuse();
      // Our own inputs, relayed by a peer that stopped hearing us: we have them.
      if (m.subject != config_.local_player && !receive_inputs(m, m.subject)) return refuse();
      // The host's: it does not hear the player itself, and asks for its inputs.
      if (m.player == 0 && m.subject != config_.local_player) host_asked_at_[static_cast<size_t>(m.subject)] = frames_;
      break;
    case SessionMessage::Kind::checksum: {
      if (m.earlier.size() > max_earlier_checksums) return refuse();
      // The earliest first: a desync is found at the first tick that differs.
      for (size_t i = m.earlier.size(); i-- > 0;) {
        const int64_t t = m.tick - static_cast<int64_t>(i + 1) * config_.checksum_interval;
        if (t < 1) continue;
        remote_checksums_.emplace(std::pair<int64_t, int>{t, m.player}, m.earlier[i]);
        check_checksum(t, m.player);
      }
      remote_checksums_[std::pair<int64_t, int>{m.tick, m.player}] = m.checksum;
      check_checksum(m.tick, m.player);
      break;
    }
    case SessionMessage::Kind::state: receive_desync_state(m); break;
    case SessionMessage::Kind::join_state:
      // We run already: the one we started from again (the host repeats it
      // until we acknowledge our first tick) is nothing new, any other is stale.
      if (m.subject == config_.local_player && m.tick != first_tick_) {
        ++stats_.refused_states;
        return refuse();
      }
      break;  // another joiner's
    case SessionMessage::Kind::join_check: break;
  }
  acked_[static_cast<size_t>(m.player)] = std::max(acked_[static_cast<size_t>(m.player)], m.ack);
  heard_at_[static_cast<size_t>(m.player)] = spoke_at_[static_cast<size_t>(m.player)] = frames_;
  confirm();
  return true;
}

// A peer's state at a tick of its desync: compared with ours there and the
// first differing field named. Found by it at a tick earlier than ours (a
// checksum lost on the way), ours moves there when we kept that state and
// theirs is not ours; one that agrees with ours (a third player's desync)
// explains nothing.
void Session::receive_desync_state(const SessionMessage& m) {
  if (!desync_ || !desync_->difference.empty() || m.tick > desync_->tick) return;
  World theirs;
  const Result<void> read = restore(m.state, theirs);
  if (read.ok()) {
    const uint64_t world = state_checksum(theirs);
    const uint64_t remote = game_.save ? tick_checksum(world, m.game_state) : world;
    const auto ours = confirmed_hashes_.find(m.tick);
    if (ours == confirmed_hashes_.end() || ours->second == remote) return;
    if (m.tick < desync_->tick) {
      if (!report_desync_at(m.tick, m.player)) return;
      desync_->remote = remote;
    }
  } else if (m.tick < desync_->tick) {
    return;
  }
  World mine;
  if (desync_snapshot_.empty() || !restore(desync_snapshot_, mine).ok()) return;
  desync_->difference = read.ok() ? diff_dumps(dump_state(mine), dump_state(theirs))
                                        .value()
                                        .value_or(game_state_difference(desync_game_, m.game_state))
                                  : "the peer's state cannot be read: " + read.error().message();
  event({SessionEvent::Kind::desync_explained, desync_->player, desync_->tick});
}

// A player's inputs (its own, or relayed); false, with nothing changed,
// when any is out of the window, contradicts one known, or falls where
// the player does not play; the host's roster changes are checked with them.
bool Session::receive_inputs(const SessionMessage& m, int player) {
  const int64_t horizon = std::max(tick_, next_local_ - 1) + window(config_);
  const int64_t count = static_cast<int64_t>(m.inputs.size());
  if (m.inputs.size() > max_inputs_per_message) return false;  // none: an ack alone
  if (m.tick + count - 1 > horizon) return false;
  if (m.roster.size() > max_roster_events) return false;
  for (const RosterEvent& e : m.roster) {
    if (e.at < m.tick || e.at >= m.tick + count || e.player <= 0 || e.player >= config_.players || e.from < 1 ||
        e.from > e.at + window(config_)) {
      return false;
    }
  }
  auto& theirs = inputs_[static_cast<size_t>(player)];
  // All checked before any is kept: a contradiction refuses the message.
  for (int64_t i = 0; i < count; ++i) {
    const PlayerInput& input = m.inputs[static_cast<size_t>(i)];
    const int64_t t = m.tick + i;
    if (input.size() > max_input_bytes) return false;
    if (!roster_.plays(player, t)) return false;  // a leaver's (a spectator's), for a tick it does not play
    const auto at = theirs.find(t);
    if (at != theirs.end() && at->second != input) return false;
  }
  for (int64_t i = 0; i < count; ++i) {
    const int64_t t = m.tick + i;
    const PlayerInput& input = m.inputs[static_cast<size_t>(i)];
    if (t <= confirmed_ || known(player, t)) continue;  // known already (or long confirmed)
    theirs[t] = input;
    heard_at_[static_cast<size_t>(player)] = frames_;  // news of it, if relayed
    const std::vector<PlayerInput>* ran = used_at(t);
    if (ran != nullptr && (*ran)[static_cast<size_t>(player)] != input) {
      ++stats_.mispredicted_inputs;
      rollback_from_ = std::min(rollback_from_, t);
    }
    if (player != 0) continue;
    for (const RosterEvent& e : m.roster) {
      if (e.at == t) apply_roster(e);
    }
  }
  return true;
}

// A joiner's state from the host: for our match, not older than the one
// waiting or than the host's checks; used once every check is in.
bool Session::receive_join_state(const SessionMessage& m) {
  const uint32_t everyone = config_.players >= 32 ? ~0u : (1u << config_.players) - 1;
  const auto host_check = join_checks_.find(0);
  const bool stale = (candidate_ && candidate_->tick > m.tick) ||
                     (host_check != join_checks_.end() && host_check->second.first > m.tick);
  const uint32_t local = 1u << config_.local_player;
  const bool fits = m.player == 0 && m.start_hash == start_hash_ && m.tick >= 1 &&
                    ((m.present | m.watching) & ~everyone) == 0 && (m.present & m.watching) == 0 &&
                    (m.present & 1u) != 0 && ((m.present | m.watching) & local) == 0;
  if (!fits || stale) {
    ++stats_.refused_states;
    ++stats_.refused_messages;
    return false;
  }
  candidate_ = m;
  try_join();
  return true;
}

// The waiting state, once every player present at its tick sent its check:
// used when its hash is theirs, refused when not.
void Session::try_join() {
  if (!candidate_) return;
  const SessionMessage& m = *candidate_;
  const auto refuse = [&] {
    ++stats_.refused_states;
    ++stats_.refused_messages;
    candidate_.reset();
  };
  for (int q = 0; q < config_.players; ++q) {
    if (((m.present | m.watching) & (1u << q)) == 0) continue;  // every peer that confirmed the tick checks it
    const auto check = join_checks_.find(q);
    if (check == join_checks_.end() || check->second.first < m.tick) return;  // wait for it
    if (check->second.first > m.tick) return refuse();  // a newer join: this state is stale
  }
  World candidate;
  if (!restore(m.state, candidate).ok() || candidate.step_count() != static_cast<uint64_t>(m.tick)) return refuse();
  const uint64_t world = state_checksum(candidate);
  const uint64_t hash = game_.save ? tick_checksum(world, m.game_state) : world;
  for (const auto& [q, check] : join_checks_) {
    if (((m.present | m.watching) & (1u << q)) != 0 && check.second != hash) return refuse();  // not what they confirmed
  }
  if (!sim_.load(m.state).ok()) return refuse();
  if (game_.load && !game_.load(m.game_state)) return refuse();
  // From the state on, as if the match had started there.
  const int64_t c = m.tick;
  roster_ = Roster(config_.players, m.present, m.watching);
  roster_.set(config_.local_player, c + 1, config_.watching ? Presence::watching : Presence::present);
  for (size_t p = 0; p < inputs_.size(); ++p) {
    inputs_[p].clear();
    acked_[p] = c;
    heard_at_[p] = spoke_at_[p] = frames_;
  }
  // A player's input for its first `input_delay` ticks is empty; a spectator gives none.
  const int delay = config_.watching ? 0 : config_.input_delay;
  for (int64_t t = c + 1; t <= c + delay; ++t) inputs_[static_cast<size_t>(config_.local_player)][t] = empty_;
  next_local_ = c + 1 + delay;
  tick_ = confirmed_ = first_tick_ = c;
  run_tick_.assign(run_tick_.size(), -1);
  run_tick_[static_cast<size_t>(c) % run_tick_.size()] = c;
  hashes_[static_cast<size_t>(c) % hashes_.size()] = hash;
  game_tick_.assign(game_tick_.size(), -1);
  if (game_.save) {
    game_states_[static_cast<size_t>(c) % game_states_.size()] = m.game_state;
    game_tick_[static_cast<size_t>(c) % game_tick_.size()] = c;
  }
  confirmed_hashes_.clear();
  confirmed_hashes_[c] = hash;
  for (CheckedState& checked : checked_states_) checked.tick = -1;
  remote_checksums_.clear();
  rollback_from_ = INT64_MAX;
  states_ = RollbackStates{};  // a new world: no state of the old one restores into it
  ring_tick_.assign(ring_.size(), -1);
  save_state(c);
  joined_ = true;
  candidate_.reset();
  join_checks_.clear();
  event({SessionEvent::Kind::joined, config_.local_player, c});
}

std::span<const SessionMessage> Session::take_outgoing() {
  for (size_t i = 0; i < outgoing_count_; ++i) outgoing_[i].sequence = next_sequence_++;
  return {outgoing_.data(), std::exchange(outgoing_count_, 0)};
}

std::span<const SessionEvent> Session::take_events() { return {events_.data(), std::exchange(event_count_, 0)}; }

// Kept in place, as the outgoing messages (room for them all reserved at
// the start); a game that does not take them loses the oldest.
void Session::event(const SessionEvent& e) {
  if (event_count_ == max_pending_events) {
    std::move(events_.begin() + 1, events_.end(), events_.begin());
    --event_count_;
    ++stats_.dropped_events;
  }
  if (event_count_ == events_.size()) events_.push_back(e);
  events_[event_count_++] = e;
}

PeerStats Session::peer_stats(int player) const { return links_.stats(player, frames_, next_local_ - 1); }

int Session::recommended_wait() const {
  int wait = 0;
  for (int p = 0; p < config_.players; ++p) {
    if (p != config_.local_player && roster_.plays(p, tick_ + 1)) wait = std::max(wait, peer_stats(p).frames_ahead);
  }
  return wait >= 2 ? wait : 0;
}

// Once a frame: our quality message every quality_every frames; a player
// silent for interrupt_after frames, or heard again; the time sync's advice
// (at most every 4 quality intervals, so a wait shows before the next).
void Session::watch_links() {
  if (config_.players < 2) return;
  if (frames_ % quality_every == 0) {
    SessionMessage& m = next_message(SessionMessage::Kind::quality);
    m.player = config_.local_player;
    m.ack = confirmed_;
    links_.fill_quality(m, frames_, next_local_ - 1);
    ++outgoing_count_;
  }
  if (!running_ && joined_) {
    bool heard_all = true;
    for (int p = 0; p < config_.players && heard_all; ++p) {
      if (p == config_.local_player || !roster_.follows(p)) continue;
      heard_all = links_.stats(p, frames_, next_local_ - 1).messages_received > 0;
    }
    if (heard_all) {
      running_ = true;
      event({SessionEvent::Kind::running, -1, tick_});
    }
  }
  for (int p = 0; p < config_.players; ++p) {
    const size_t k = static_cast<size_t>(p);
    if (p == config_.local_player || !roster_.follows(p)) continue;
    const int64_t silent = frames_ - heard_at_[k];
    if (interrupted_[k] == 0 && silent >= config_.interrupt_after) {
      interrupted_[k] = 1;
      event({SessionEvent::Kind::interrupted, p, tick_, 0, static_cast<int>(std::min<int64_t>(silent, INT32_MAX))});
    } else if (interrupted_[k] != 0 && silent < config_.interrupt_after) {
      interrupted_[k] = 0;
      event({SessionEvent::Kind::resumed, p, tick_});
    }
  }
  if (frames_ - last_recommendation_ >= 4 * quality_every) {
    if (const int wait = recommended_wait(); wait > 0) {
      last_recommendation_ = frames_;
      event({SessionEvent::Kind::wait_recommended, -1, tick_, 0, wait});
    }
  }
}

std::optional<uint64_t> Session::confirmed_hash(int64_t tick) const {
  const auto found = confirmed_hashes_.find(tick);
  if (found == confirmed_hashes_.end()) return std::nullopt;
  return found->second;
}

}  // namespace bitstep
