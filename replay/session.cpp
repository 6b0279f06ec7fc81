#include "replay/session.h"

#include <algorithm>
#include <utility>

#include "replay/snapshot.h"
#include "replay/state_dump.h"

namespace bitstep {

namespace {

// How far past the ticks it knows a message's tick may be: a peer runs at
// most max_prediction ahead of what it confirmed, its inputs input_delay
// ahead of that, and a burst of inputs is at most a message long.
int64_t window(const SessionConfig& c) {
  return c.max_prediction + c.input_delay + static_cast<int64_t>(max_inputs_per_message) + 2;
}

// Confirmed hashes remembered (for confirmed_hash and late checksums).
constexpr size_t remembered_hashes = 1024;
// States at checksum ticks kept until every peer's checksum agreed.
constexpr size_t remembered_states = 8;

template <class Map>
void erase_before(Map& map, int64_t tick) {
  map.erase(map.begin(), map.lower_bound(tick));
}

}  // namespace

std::string config_error(const SessionConfig& c) {
  if (c.players < 1 || c.players > 16) return "players: outside 1..16";
  if (c.local_player < 0 || c.local_player >= c.players) return "local player: outside 0..players - 1";
  if (c.input_delay < 0 || c.input_delay > 32) return "input delay: outside 0..32 ticks";
  if (c.max_prediction < 1 || c.max_prediction > 64) return "max prediction: outside 1..64 ticks";
  if (c.checksum_interval < 1 || c.checksum_interval > 3600) return "checksum interval: outside 1..3600 ticks";
  return {};
}

Session::Session(Simulation sim, SessionConfig config, ApplyInput apply)
    : sim_(std::move(sim)),
      config_(config),
      apply_(std::move(apply)),
      inputs_(static_cast<size_t>(config.players)),
      acked_(static_cast<size_t>(config.players), 0) {
  // Ticks 1..input_delay have no input, for every player.
  for (auto& known_inputs : inputs_) {
    for (int64_t t = 1; t <= config_.input_delay; ++t) known_inputs[t] = empty_;
  }
  next_local_ = config_.input_delay + 1;
  // Room for the states a rollback may start from: the confirmed tick's and
  // every tick run ahead of it.
  ring_.resize(static_cast<size_t>(config_.max_prediction) + 2);
  ring_tick_.assign(ring_.size(), -1);
  if (config_.mode == SessionMode::rollback) save_state(0);
}

// The state after `tick` (the world's now) into its place in the ring, as
// a rollback state: no allocation once the buffers are large enough.
void Session::save_state(int64_t tick) {
  const size_t k = static_cast<size_t>(tick) % ring_.size();
  states_.save(sim_.world(), ring_[k]);
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

bool Session::known(int player, int64_t tick) const {
  return inputs_[static_cast<size_t>(player)].count(tick) != 0;
}

// The player's input for the tick, or its last one before (the prediction).
const PlayerInput& Session::input_for(int player, int64_t tick, bool& predicted) const {
  const auto& known_inputs = inputs_[static_cast<size_t>(player)];
  const auto at = known_inputs.lower_bound(tick);
  predicted = at == known_inputs.end() || at->first != tick;
  if (!predicted) return at->second;
  return at == known_inputs.begin() ? empty_ : std::prev(at)->second;
}

void Session::add_local_input(PlayerInput input) {
  inputs_[static_cast<size_t>(config_.local_player)][next_local_++] = std::move(input);
  send_inputs();
}

void Session::heartbeat() { send_inputs(true); }

// The local inputs no peer has acknowledged (at most a message of them);
// with `always`, a message even when there are none (it carries the ack).
void Session::send_inputs(bool always) {
  if (config_.players < 2) return;
  int64_t acked = INT64_MAX;
  for (int p = 0; p < config_.players; ++p) {
    if (p != config_.local_player) acked = std::min(acked, acked_[static_cast<size_t>(p)]);
  }
  SessionMessage m;
  m.kind = SessionMessage::Kind::inputs;
  m.player = config_.local_player;
  m.ack = confirmed_;
  m.tick = std::max<int64_t>(acked + 1, 1);
  const auto& local = inputs_[static_cast<size_t>(config_.local_player)];
  for (auto at = local.lower_bound(m.tick); at != local.end() && m.inputs.size() < max_inputs_per_message; ++at) {
    if (at->first != m.tick + static_cast<int64_t>(m.inputs.size())) break;
    m.inputs.push_back(at->second);
  }
  if (always || !m.inputs.empty()) outgoing_.push_back(std::move(m));
}

void Session::simulate(int64_t tick) {
  if (config_.mode == SessionMode::rollback) save_state(tick - 1);  // the state this tick starts from
  std::vector<PlayerInput> used(static_cast<size_t>(config_.players));
  for (int p = 0; p < config_.players; ++p) {
    bool predicted = false;
    used[static_cast<size_t>(p)] = input_for(p, tick, predicted);
    if (predicted) ++stats_.predicted_inputs;
    apply_(sim_, p, used[static_cast<size_t>(p)]);
  }
  sim_.step();
  tick_ = tick;
  hashes_[tick] = sim_.hash();
  used_[tick] = std::move(used);
}

// Back to the state before the first mispredicted tick, and forward again.
void Session::roll_back() {
  const int64_t from = rollback_from_, to = tick_;
  rollback_from_ = INT64_MAX;
  const size_t k = static_cast<size_t>(from - 1) % ring_.size();
  if (ring_tick_[k] != from - 1 || states_.restore(ring_[k], sim_.world())) return;  // cannot happen: our own state
  for (int64_t t = from; t <= to; ++t) simulate(t);
  ++stats_.rollbacks;
  stats_.resimulated_ticks += to - from + 1;
}

bool Session::advance() {
  const int64_t next = tick_ + 1;
  if (config_.mode == SessionMode::rollback && rollback_from_ <= tick_) roll_back();
  bool ready = known(config_.local_player, next);
  for (int p = 0; p < config_.players && ready; ++p) {
    ready = config_.mode == SessionMode::rollback || known(p, next);
  }
  if (config_.mode == SessionMode::rollback && next - confirmed_ > config_.max_prediction) ready = false;
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
    if (!all) break;
    confirmed_ = c;
    confirmed_hashes_[c] = hashes_.at(c);
    if (c % config_.checksum_interval != 0) continue;
    // The state after c, kept (as a rollback state) until the peers' checksums agree.
    const size_t k = static_cast<size_t>(c) % ring_.size();
    if (ring_tick_[k] != c) save_state(c);  // c is the tick just run
    checked_states_[c] = ring_[k];
    if (checked_states_.size() > remembered_states) checked_states_.erase(checked_states_.begin());
    SessionMessage m;
    m.kind = SessionMessage::Kind::checksum;
    m.player = config_.local_player;
    m.ack = confirmed_;
    m.tick = c;
    m.checksum = hashes_.at(c);
    outgoing_.push_back(std::move(m));
    const auto remote = remote_checksums_.find(c);
    if (remote != remote_checksums_.end()) {
      for (const auto& [player, checksum] : remote->second) check_checksum(c, player);
    }
  }
  // Forget what no rollback or peer can need any more (a rollback starts
  // after the confirmed tick; the prediction base is the input at it).
  int64_t acked = confirmed_;
  for (int p = 0; p < config_.players; ++p) {
    if (p != config_.local_player) acked = std::min(acked, acked_[static_cast<size_t>(p)]);
  }
  erase_before(used_, confirmed_);
  erase_before(hashes_, confirmed_);
  for (int p = 0; p < config_.players; ++p) {
    erase_before(inputs_[static_cast<size_t>(p)], p == config_.local_player ? std::min(acked + 1, confirmed_) : confirmed_);
  }
  while (confirmed_hashes_.size() > remembered_hashes) confirmed_hashes_.erase(confirmed_hashes_.begin());
  erase_before(remote_checksums_, confirmed_ - static_cast<int64_t>(remembered_hashes));
}

void Session::check_checksum(int64_t tick, int player) {
  const auto local = confirmed_hashes_.find(tick);
  const auto remote = remote_checksums_.find(tick);
  if (desync_ || local == confirmed_hashes_.end() || remote == remote_checksums_.end()) return;
  const auto theirs = remote->second.find(player);
  if (theirs == remote->second.end() || theirs->second == local->second) return;
  desync_ = Desync{tick, player, local->second, theirs->second, {}};
  const auto state = checked_states_.find(tick);
  if (state == checked_states_.end()) return;
  desync_snapshot_ = snapshot_of(state->second);
  SessionMessage m;
  m.kind = SessionMessage::Kind::state;
  m.player = config_.local_player;
  m.ack = confirmed_;
  m.tick = tick;
  m.state = desync_snapshot_;
  outgoing_.push_back(std::move(m));
}

// A whole snapshot of a kept rollback state: the world goes there and back.
std::vector<uint8_t> Session::snapshot_of(const std::vector<uint8_t>& state) {
  std::vector<uint8_t> now;
  states_.save(sim_.world(), now);
  if (states_.restore(state, sim_.world())) return {};
  std::vector<uint8_t> whole = sim_.save();
  (void)states_.restore(now, sim_.world());
  return whole;
}

bool Session::receive(const SessionMessage& m) {
  const auto refuse = [&] {
    ++stats_.refused_messages;
    return false;
  };
  const int64_t horizon = std::max(tick_, next_local_ - 1) + window(config_);
  if (m.player < 0 || m.player >= config_.players || m.player == config_.local_player) return refuse();
  if (m.ack < 0 || m.ack > next_local_ - 1 + window(config_) || m.tick < 1 || m.tick > horizon) return refuse();
  switch (m.kind) {
    case SessionMessage::Kind::inputs: {
      if (m.inputs.size() > max_inputs_per_message) return refuse();  // none: an ack alone
      if (m.tick + static_cast<int64_t>(m.inputs.size()) - 1 > horizon) return refuse();
      auto& theirs = inputs_[static_cast<size_t>(m.player)];
      // All checked before any is kept: a contradiction refuses the message.
      for (size_t i = 0; i < m.inputs.size(); ++i) {
        if (m.inputs[i].size() > max_input_bytes) return refuse();
        const auto at = theirs.find(m.tick + static_cast<int64_t>(i));
        if (at != theirs.end() && at->second != m.inputs[i]) return refuse();
      }
      for (size_t i = 0; i < m.inputs.size(); ++i) {
        const int64_t t = m.tick + static_cast<int64_t>(i);
        if (t <= confirmed_ || known(m.player, t)) continue;  // known already (or long confirmed)
        theirs[t] = m.inputs[i];
        const auto ran = used_.find(t);
        if (ran != used_.end() && ran->second[static_cast<size_t>(m.player)] != m.inputs[i]) {
          ++stats_.mispredicted_inputs;
          rollback_from_ = std::min(rollback_from_, t);
        }
      }
      break;
    }
    case SessionMessage::Kind::checksum:
      remote_checksums_[m.tick][m.player] = m.checksum;
      check_checksum(m.tick, m.player);
      break;
    case SessionMessage::Kind::state: {
      if (!desync_ || desync_->tick != m.tick || !desync_->difference.empty()) break;
      if (desync_snapshot_.empty()) break;
      World mine, theirs;
      if (const auto why = restore(m.state, theirs)) {
        desync_->difference = "the peer's state cannot be read: " + *why;
      } else if (!restore(desync_snapshot_, mine)) {
        desync_->difference = diff_dumps(dump_state(mine), dump_state(theirs)).first.value_or("no field differs");
      }
      break;
    }
  }
  acked_[static_cast<size_t>(m.player)] = std::max(acked_[static_cast<size_t>(m.player)], m.ack);
  confirm();
  return true;
}

std::vector<SessionMessage> Session::take_outgoing() { return std::exchange(outgoing_, {}); }

std::optional<uint64_t> Session::confirmed_hash(int64_t tick) const {
  const auto found = confirmed_hashes_.find(tick);
  if (found == confirmed_hashes_.end()) return std::nullopt;
  return found->second;
}

}  // namespace bitstep
