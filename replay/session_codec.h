// Session messages as network packets, and the hello a peer opens with.
// Little-endian, versioned:
//   "bS", version (u8: 3), type (u8: 0 inputs, 1 checksum, 2 state, 3 relay,
//   4 join state, 5 join check, 6 quality, 16 hello, 17 refused), then, but for
//   a hello or a refusal,
//   the sender's message number (sequence u32), then
//   inputs:     player u8, ack i64, tick i64, count u8 (<= 128), each input: length u16 (<= 1024), bytes;
//               roster count u8 (<= 16), each change: at i64, from i64, player u8, presence u8
//               (0 absent, 1 present, 2 watching)
//   checksum:   player u8, ack i64, tick i64, checksum u64, count u8 (<= 3), the earlier checksums u64
//   state:      player u8, ack i64, tick i64, length u32 (<= 64 MiB), a snapshot image,
//               game length u32 (<= 16 MiB), the game's state (GameHooks::save)
//   relay:      player u8, ack i64, tick i64, subject u8, count u8, the inputs as above
//   join state: player u8, ack i64, tick i64, subject u8, present u16, watching u16, start hash u64,
//               length u32, a snapshot image, game length u32, the game's state
//   join check: player u8, ack i64, tick i64, subject u8, checksum u64
//   quality:    player u8, ack i64, tick i64 (the newest input's), frame i64, count u8 (<= 16),
//               each player's echo: frame i64 (-1: none), held i64
//   hello:      player u8, players u8, mode u8, input delay u8, the start state's hash u64,
//               joining u8 (0 no, 1 to play, 2 to watch)
//   refused:    (type 17) reason u8 (HelloRefused), then the refuser's hello as above; read from
//               any version from 3 on (its layout stays), so a refused build hears why
// Versions 1 (no roster, relay or join) and 2 (no game state, earlier
// checksums, message numbers or quality) are refused:
// peers of one match run one build.
// decode refuses anything else (a wrong magic, version or type, a count or
// length over its limit, bytes missing or left over) with a reason; the
// session then checks the values against its window.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "core/error.h"
#include "replay/session.h"

namespace bitstep {

// Who a peer is: sent first, and checked against the receiver's own match.
struct Hello {
  int player = 0, players = 0;
  SessionMode mode = SessionMode::rollback;
  int input_delay = 0;
  uint64_t start_hash = 0;  // the state hash before tick 1: the same scene and settings
  bool joining = false;     // asks to join (or rejoin) a match in progress in its slot
  bool watching = false;    // ... as a spectator
  friend bool operator==(const Hello&, const Hello&) = default;
};

// Why a peer refused a hello: sent back before it hangs up, so that both
// sides can say why (bitstep peer prints it; the refused one stops).
enum class HelloRefused : uint8_t {
  another_scene = 1,  // the start state's hash differs: another scene or settings
  player_count,
  mode,
  input_delay,
  no_such_player,  // a player number outside the match
  our_player,      // the refuser's own player number
  player_taken,    // a player who said hello already
  not_joinable,    // a join to the host's slot, or to a peer that is joining itself
  version,         // another packet version (another build)
};
struct Refusal {
  HelloRefused reason = HelloRefused::another_scene;
  Hello refuser;    // who refused, and the match it plays
  int version = 0;  // the refuser's packet version (decode sets it)
  friend bool operator==(const Refusal&, const Refusal&) = default;
};
// What keeps `theirs` out of the match `ours` plays, or nullopt: it fits.
// `said_hello`: theirs->player already said hello (or is us).
std::optional<HelloRefused> refusal_of(const Hello& ours, const Hello& theirs, bool said_hello);
// Why, in words both sides print alike: "another player count: 2 in the
// match, 3 in the hello" (`match`: the refuser's hello; `hello`: the one
// refused; each with its packet version).
std::string describe(HelloRefused why, const Hello& match, int match_version, const Hello& hello, int hello_version);
// The packet version a packet says it has (the byte after the magic), or
// -1; and whether it opens as a hello (so a hello of another build can be
// answered).
int packet_version(std::span<const uint8_t> packet);
int packet_version();  // this build's
bool looks_like_hello(std::span<const uint8_t> packet);

inline constexpr size_t max_state_bytes = size_t{64} << 20;
inline constexpr size_t max_game_state_bytes = size_t{16} << 20;

std::vector<uint8_t> encode(const SessionMessage& message);
std::vector<uint8_t> encode(const Hello& hello);
std::vector<uint8_t> encode(const Refusal& refusal);

// A packet is a session message or a hello; decode's error names the part
// ("hello", "inputs", "state"; none for the header) and the reason.
using Packet = std::variant<SessionMessage, Hello, Refusal>;
Result<Packet> decode(std::span<const uint8_t> packet);

}  // namespace bitstep
