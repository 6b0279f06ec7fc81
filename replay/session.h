// A game's ticks for N players, as GGPO and GGRS run them. Every tick
// each player gives an input (the game's bytes: which buttons are held,
// where the stick points); every peer applies all of them, in player order,
// to its own simulation, so every peer computes the same bits.
//
// - lockstep: a tick runs when every player's input for it is here;
// - rollback: a tick runs at once on predicted inputs (a player's last
//   known input, repeated); when the real one arrives and differs, the
//   simulation goes back to the tick before it (a snapshot) and runs those
//   ticks again; at most `max_prediction` ticks ahead of the last tick whose
//   inputs are all known.
// A local input applies `input_delay` ticks later (ticks 1..delay have no
// input): a little delay hides the network's and saves rollbacks.
//
// Peers compare a checksum (the rollback state's, RollbackStates::save: it
// names nothing of one world object; with the game's state: see GameHooks) of every `checksum_interval`-th confirmed
// tick, each message repeating the last three (a lost one costs no comparison); on a mismatch each sends the other its
// state at that tick and both name the first field that differs (the dump's diff). From a desync on, the states kept
// for it are no longer replaced: a peer told of a desync at another of
// the kept ticks answers with its own state there.
//
// No transport here: the session says what to send (take_outgoing) and is
// told what arrived (receive). Every input message carries all the local
// inputs the peers have not acknowledged, so a lost packet costs nothing
// but time; a message that makes no sense (a player out of range, a tick
// out of the window, an input that contradicts one already known) is
// refused and counted, never applied.
//
// Memory: a warm session (its maps at their size, about 1,100 ticks in:
// 1,024 confirmed hashes are remembered) allocates nothing in its own
// calls per tick; map nodes come from its NodePool (replay/node_pool.h),
// a tick's inputs and hash go to places it keeps, and take_outgoing hands
// out messages filled in place. Inputs longer than std::string's inline
// capacity (15 bytes here) allocate their copies, and the world's first
// steps after a rollback's restore allocate (the world's, not ours).
//
// Leaving and joining (replay/session_roster.h): the host (player 0)
// decides who plays, and its decisions travel in its own input stream, so
// every peer applies them at the same tick. A player the host has heard
// nothing from for `leave_after` frames is marked absent from the first
// tick whose input the host never got (the others first relay to it every
// input of the silent player they hold, once it asks; a player silent to
// the host alone plays on through those relays); its inputs from then on
// are empty, and its own inputs for those ticks are refused. A player may join
// (or rejoin) a slot that is absent: the host announces it present from
// its next input's tick T, and once it has confirmed T - 1 sends the joiner
// its snapshot after T - 1; every peer sends the joiner the hash it
// confirmed for T - 1 (a join check). The joiner uses the snapshot only
// when its hash is the one every player present at T - 1 checked, for its
// own match (the start hash): a forged or stale state is refused and
// counted. A spectator joins the same way into a slot where it watches:
// it acknowledges ticks (its peers resend to it) but gives no input. The
// host must stay for the whole match (no host migration).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "replay/node_pool.h"
#include "replay/rollback_state.h"
#include "replay/session_link.h"
#include "replay/session_roster.h"
#include "replay/simulation.h"

namespace bitstep {

using PlayerInput = std::string;  // the game's bytes for one player's tick

enum class SessionMode : uint8_t { lockstep, rollback };

struct SessionConfig {
  int players = 2;
  int local_player = 0;
  SessionMode mode = SessionMode::rollback;
  int input_delay = 0;         // ticks, 0..32
  int max_prediction = 8;      // ticks ahead of the last confirmed one (rollback), 1..64
  int checksum_interval = 1;   // every k-th confirmed tick, 1..3600
  int leave_after = 0;         // frames of silence before the host marks a player absent, 0 (never) or 10..100000
  bool joining = false;        // joins a match in progress: waits for the host's state
  bool watching = false;       // joins as a spectator: follows the match, gives no input
  int interrupt_after = 30;    // frames of a player's silence before an `interrupted` event, 1..100000
};

// What is wrong with a config: the field ("input delay") and the bound.
Result<void> check_config(const SessionConfig& config);

struct SessionMessage {
  enum class Kind : uint8_t { inputs, checksum, state, relay, join_state, join_check, quality };
  // quality: a player's frame, and the frame of each player's last quality message it heard
  // and the frames it held it since (replay/session_link.h: the round trip).
  struct Echo {
    int64_t frame = -1;  // -1: none heard
    int64_t held = 0;
  };
  Kind kind = Kind::inputs;
  uint32_t sequence = 0;            // the sender's count of its messages (take_outgoing numbers them)
  int player = 0;                   // the sender
  int subject = 0;                  // relay: whose inputs; join_state, join_check: the joiner
  int64_t ack = 0;                  // the sender has every player's input up to this tick
  int64_t tick = 0;                 // inputs: of inputs[0]; checksum, state: the tick; quality: the newest input's
  int64_t frame = 0;                // quality: the sender's frame
  std::vector<Echo> echoes;         // quality: per player
  std::vector<PlayerInput> inputs;  // inputs: the sender's for ticks tick, tick + 1, ...
  uint64_t checksum = 0;            // checksum, join_check: the tick's checksum (tick_checksum)
  std::vector<uint64_t> earlier;    // checksum: those of the checksum ticks before `tick`, latest first (<= 3)
  std::vector<uint8_t> state;       // state: the snapshot after `tick` (after a mismatch); join_state: the joiner's start
  std::vector<uint8_t> game_state;  // state, join_state: the game's state after `tick` (GameHooks::save)
  std::vector<RosterEvent> roster;  // inputs (the host's only): the roster changes its inputs carry
  uint32_t present = 0;             // join_state: who plays at `tick` (bit p: player p)
  uint32_t watching = 0;            // join_state: who watches at `tick`
  uint64_t start_hash = 0;          // join_state: the match's (the state hash before tick 1)
};

inline constexpr size_t max_roster_events = 16;
inline constexpr size_t max_earlier_checksums = 3;

inline constexpr size_t max_input_bytes = 1024;
inline constexpr size_t max_inputs_per_message = 128;

struct Desync {
  int64_t tick = 0;
  int player = 0;  // whose checksum differed
  uint64_t local = 0, remote = 0;
  std::string difference;  // the first differing field, once the peer's state arrived
};

// What happened in a session, for the game to show or act on, in the order
// it happened (take_events).
struct SessionEvent {
  enum class Kind : uint8_t {
    joined,            // this peer (a joiner) took the host's state: it runs from `tick` + 1
    player_joined,     // `player` plays (or, `watching`, watches) from `tick`
    player_left,       // `player` is absent from `tick`: the host gave it up
    interrupted,       // nothing heard from `player` for `frames` frames
    resumed,           // `player` is heard again
    rolled_back,       // ticks `tick`..`to` were run again: a prediction was wrong
    desync,            // the checksums of `tick` differ with `player`'s (desync() has both)
    desync_explained,  // the first field that differs is known (desync()->difference)
    wait_recommended,  // this peer runs `frames` frames ahead of the slowest peer: skip that many frames
    running,           // every other player it follows has been heard from: the match is under way (once)
  };
  Kind kind = Kind::joined;
  int player = -1;
  int64_t tick = 0, to = 0;
  int frames = 0;
  bool watching = false;
  friend bool operator==(const SessionEvent&, const SessionEvent&) = default;
};

struct SessionStats {
  int64_t rollbacks = 0, resimulated_ticks = 0, stalls = 0;
  int64_t predicted_inputs = 0, mispredicted_inputs = 0;
  int64_t refused_messages = 0;
  int64_t refused_states = 0;  // join states refused (another match, stale, or not the checked hash)
  int64_t dropped_events = 0;  // events not taken before max_pending_events more came
};

inline constexpr size_t max_pending_events = 256;

// Applies one player's input to the simulation, before a tick.
using ApplyInput = std::function<void(Simulation& sim, int player, const PlayerInput& input)>;

// The game's side of every tick (GGRS's advance, save and load requests).
// A tick runs: `apply` for each player's input, in player order; the
// world's step; `advance`, the game's own logic of the tick (scores,
// health, timers, AI; it may read the step's events and contacts). Then
// the session keeps the game's state (`save`) beside the world's, a
// rollback restores both (`load`), and the checksums peers compare cover
// both (tick_checksum). The game's state is everything of the game its
// future depends on: what save leaves out a rollback does not take back,
// and the peers desync. Without save and load the session rolls back the
// world alone and the checksum is the world's (Simulation::checksum).
struct GameHooks {
  ApplyInput apply;
  std::function<void(Simulation& sim, int64_t tick)> advance;
  // Writes the game's state into `out`, which is empty (its memory is kept
  // from call to call: a game state of steady size allocates nothing).
  std::function<void(std::vector<uint8_t>& out)> save;
  // Makes the game's state what `state` (written by save) says; false when
  // it cannot read it (a joiner then refuses the state it was sent).
  std::function<bool(std::span<const uint8_t> state)> load;
};

// What is wrong with the hooks: apply is required, save and load come together.
Result<void> check_hooks(const GameHooks& hooks);

// The checksum of a tick that peers compare: the world's
// (Simulation::checksum, the rollback state's) alone when the game keeps no
// state, else XXH3-64 of the game's saved state seeded with it.
uint64_t tick_checksum(uint64_t world_checksum, std::span<const uint8_t> game_state);
// Where two game states first differ: "the game's state: byte N: a vs b"
// (or their sizes), "no field differs" when they do not.
std::string game_state_difference(std::span<const uint8_t> mine, std::span<const uint8_t> theirs);

class Session {
 public:
  // `config` must pass check_config, `game` check_hooks. The game's save
  // is called here for its state before tick 1.
  Session(Simulation sim, SessionConfig config, GameHooks game);
  // A game that keeps no state of its own beside the world.
  Session(Simulation sim, SessionConfig config, ApplyInput apply);

  // The local player's next input (for the tick input_delay after the last
  // one given). Then advance. False, and nothing kept, when that tick is
  // more than max_prediction ticks past the last confirmed one (plus the
  // delay; GGRS's prediction threshold): the game runs too far ahead of
  // its peers and gives this frame's input again next frame. False too
  // for a spectator and for a joiner not yet running.
  bool add_local_input(PlayerInput input);
  // Runs the next tick if it can (rolling back first when a known input
  // differs from the one predicted); false when it must wait for inputs.
  bool advance();
  // A peer's message; false (and counted) when refused.
  bool receive(const SessionMessage& message);
  // An inputs message even when every local input is acknowledged: it
  // carries this peer's ack (call it now and then once the match is over,
  // so peers still waiting learn that their last inputs arrived).
  void heartbeat();
  // The host: let `player` (an absent slot, or one the host will mark
  // absent) play again, or watch, from the host's next input on; false for
  // any other peer or slot.
  bool admit(int player, bool watching = false);
  // The host has roster changes for its next input: a game that gives its
  // inputs no further ahead than the simulation gives one more now.
  bool roster_waits() const { return !next_roster_.empty(); }
  // False while a joining session waits for its state.
  bool joined() const { return joined_; }
  // The tick this session started from (0, or the joiner's state's).
  int64_t first_tick() const { return first_tick_; }
  const Roster& roster() const { return roster_; }
  // The roster changes this peer applied, in order (for a game's record).
  const std::vector<RosterEvent>& roster_log() const { return roster_log_; }
  uint64_t start_hash() const { return start_hash_; }
  // What to send to every peer since the last call; valid until the next
  // call of any of this session's functions (the messages' memory is kept
  // and filled again: no allocation per tick once warm).
  std::span<const SessionMessage> take_outgoing();

  int64_t tick() const { return tick_; }                // ticks simulated
  int64_t confirmed_tick() const { return confirmed_; }  // every input up to it known and used
  int64_t local_input_tick() const { return next_local_ - 1; }
  // The last tick up to which `player` said it has every input.
  int64_t peer_ack(int player) const { return acked_[static_cast<size_t>(player)]; }
  const std::optional<Desync>& desync() const { return desync_; }
  const SessionStats& stats() const { return stats_; }
  // What happened since the last call (valid until the next call of any of
  // this session's functions; no allocation). At most max_pending_events
  // wait: past that the oldest go (counted in stats().dropped_events).
  std::span<const SessionEvent> take_events();
  // The link to another player (replay/session_link.h): ping, frames
  // ahead, silence, messages received and lost.
  PeerStats peer_stats(int player) const;
  // Frames this peer runs ahead of the slowest player it follows, when two
  // or more (else 0): skipping that many advances lets the others catch up.
  int recommended_wait() const;
  const Simulation& simulation() const { return sim_; }
  Simulation& simulation() { return sim_; }
  // The checksum after a confirmed tick still remembered (the last 1,024),
  // or nullopt.
  std::optional<uint64_t> confirmed_hash(int64_t tick) const;

 private:
  // The states at a checksum tick, until compared (rollback states).
  struct CheckedState {
    int64_t tick = -1;
    std::vector<uint8_t> world, game;
  };

  bool known(int player, int64_t tick) const;
  bool awaits_host(int64_t tick) const;
  const PlayerInput& input_for(int player, int64_t tick, bool& predicted) const;
  void save_state(int64_t tick, uint64_t* checksum = nullptr);
  std::vector<uint8_t> snapshot_of(const std::vector<uint8_t>& state);
  uint64_t checksum_after(int64_t tick, uint64_t world_checksum);
  const std::vector<uint8_t>& game_after(int64_t tick) const;
  void simulate(int64_t tick);
  void roll_back();
  void confirm();
  void check_checksum(int64_t tick, int player);
  bool report_desync_at(int64_t tick, int player);
  void event(const SessionEvent& e);
  void watch_links();
  void receive_desync_state(const SessionMessage& m);
  void send_inputs(bool always = false);
  SessionMessage& next_message(SessionMessage::Kind kind);
  void send(SessionMessage message);
  std::vector<PlayerInput>* used_at(int64_t tick);
  const CheckedState* checked_state(int64_t tick) const;
  int64_t acked_by_all(int except = -1) const;
  void apply_roster(const RosterEvent& event);
  void run_roster();
  bool receive_inputs(const SessionMessage& m, int player);
  void try_join();
  void keep_join_state(int64_t tick);
  const std::vector<uint8_t>& state_after(int64_t tick);
  bool receive_join_state(const SessionMessage& m);

  template <class K, class V>
  using PooledMap = std::map<K, V, std::less<>, PoolAllocator<std::pair<const K, V>>>;

  Simulation sim_;
  SessionConfig config_;
  GameHooks game_;
  // The maps' nodes (every tick's input, hash, checksum): kept when freed,
  // so a warm session does not call the allocator per tick.
  std::unique_ptr<NodePool> pool_ = std::make_unique<NodePool>();
  int64_t tick_ = 0, confirmed_ = 0;
  int64_t next_local_ = 1;               // the tick of the next local input
  int64_t rollback_from_ = INT64_MAX;    // the first tick simulated with a wrong prediction
  std::vector<PooledMap<int64_t, PlayerInput>> inputs_;  // per player: known inputs by tick
  std::vector<int64_t> acked_;           // per player: the ack they last sent
  RollbackStates states_;                              // rollback: the state after each tick since the
  std::vector<std::vector<uint8_t>> ring_;             // confirmed one, at ring_[tick % size]
  std::vector<int64_t> ring_tick_;
  // At ring_tick_'s places too, for the ticks from the confirmed one to the
  // last run: the inputs each ran with, and the hash after it.
  std::vector<std::vector<PlayerInput>> used_;
  std::vector<std::vector<uint8_t>> game_states_;  // the game's state after each of those ticks (GameHooks::save)
  std::vector<int64_t> game_tick_;
  std::vector<uint64_t> hashes_;
  std::vector<int64_t> run_tick_;
  PooledMap<int64_t, uint64_t> confirmed_hashes_;      // the last confirmed ticks'
  // The state at checksum ticks, until compared: the last few, by tick.
  std::vector<CheckedState> checked_states_;
  std::vector<uint8_t> desync_snapshot_, desync_game_;             // ours, at the desync's tick
  PooledMap<std::pair<int64_t, int>, uint64_t> remote_checksums_;  // by (tick, player)
  std::vector<SessionMessage> outgoing_;  // [0, outgoing_count_) to send; the rest kept for reuse
  size_t outgoing_count_ = 0;
  std::optional<Desync> desync_;
  SessionStats stats_;
  const PlayerInput empty_;

  // Leaving and joining.
  Roster roster_;
  std::vector<RosterEvent> roster_log_;
  uint64_t start_hash_ = 0;
  bool joined_ = true;
  int64_t first_tick_ = 0;
  int64_t frames_ = 0;                                   // advance calls
  bool running_ = false;                                 // the running event was given
  std::vector<int64_t> heard_at_;                        // per player: the frame it was last heard (or relayed)
  std::vector<int64_t> spoke_at_;                        // per player: the frame its own message last came
  std::vector<int64_t> host_asked_at_;                   // per player: the frame the host last relayed (asked for) it
  std::vector<RosterEvent> next_roster_;                 // the host's: for its next input
  std::map<int64_t, std::vector<RosterEvent>> roster_at_;  // the host's: by the tick of the input carrying them
  std::vector<Presence> wants_in_;                       // the host's: slots asked for (absent: none)
  std::vector<int64_t> join_tick_;                       // per player: the tick it joins at, until it acked it
  std::vector<std::optional<SessionMessage>> join_state_;  // the host's: the state sent to each joiner
  std::optional<SessionMessage> candidate_;              // a joiner's: the state waiting for its checks
  std::map<int, std::pair<int64_t, uint64_t>> join_checks_;  // a joiner's: per player, (tick, hash) checked

  // The links (replay/session_link.h) and the events.
  PeerLinks links_;
  uint32_t next_sequence_ = 0;
  std::vector<uint8_t> interrupted_;  // per player: an `interrupted` event not yet resumed
  int64_t last_recommendation_ = 0;   // the frame of the last wait_recommended
  std::vector<SessionEvent> events_;  // [0, event_count_) to take
  size_t event_count_ = 0;
};

}  // namespace bitstep
