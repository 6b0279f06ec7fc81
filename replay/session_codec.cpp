#include "replay/session_codec.h"

#include <optional>

#include "replay/replay.h"

namespace bitstep {

namespace {

constexpr uint8_t magic[2] = {'b', 'S'};
constexpr uint8_t version = 3;
constexpr uint8_t last_message_type = 6;
constexpr uint8_t hello_type = 16;
constexpr uint8_t refused_type = 17;
constexpr uint8_t first_refusal_version = 3;  // the refusal's layout, read from any version since

void put(std::vector<uint8_t>& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<uint8_t>(value >> (8 * i)));
}

std::vector<uint8_t> header(uint8_t type) { return {magic[0], magic[1], version, type}; }

// Reads little-endian fields; any read past the end fails the packet.
class Reader {
 public:
  explicit Reader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  bool ok() const { return ok_; }
  bool done() const { return at_ == bytes_.size(); }
  uint64_t take(int n) {
    if (!ok_ || bytes_.size() - at_ < static_cast<size_t>(n)) {
      ok_ = false;
      return 0;
    }
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(bytes_[at_ + static_cast<size_t>(i)]) << (8 * i);
    at_ += static_cast<size_t>(n);
    return v;
  }
  std::span<const uint8_t> bytes(size_t n) {
    if (!ok_ || bytes_.size() - at_ < n) {
      ok_ = false;
      return {};
    }
    const auto out = bytes_.subspan(at_, n);
    at_ += n;
    return out;
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
  bool ok_ = true;
};

}  // namespace

std::vector<uint8_t> encode(const SessionMessage& m) {
  std::vector<uint8_t> out = header(static_cast<uint8_t>(m.kind));
  put(out, m.sequence, 4);
  put(out, static_cast<uint64_t>(m.player), 1);
  put(out, static_cast<uint64_t>(m.ack), 8);
  put(out, static_cast<uint64_t>(m.tick), 8);
  const auto put_inputs = [&] {
    put(out, m.inputs.size(), 1);
    for (const PlayerInput& input : m.inputs) {
      put(out, input.size(), 2);
      out.insert(out.end(), input.begin(), input.end());
    }
  };
  const auto put_state = [&] {
    put(out, m.state.size(), 4);
    out.insert(out.end(), m.state.begin(), m.state.end());
    put(out, m.game_state.size(), 4);
    out.insert(out.end(), m.game_state.begin(), m.game_state.end());
  };
  switch (m.kind) {
    case SessionMessage::Kind::inputs:
      put_inputs();
      put(out, m.roster.size(), 1);
      for (const RosterEvent& e : m.roster) {
        put(out, static_cast<uint64_t>(e.at), 8);
        put(out, static_cast<uint64_t>(e.from), 8);
        put(out, static_cast<uint64_t>(e.player), 1);
        put(out, static_cast<uint64_t>(e.presence), 1);
      }
      break;
    case SessionMessage::Kind::checksum:
      put(out, m.checksum, 8);
      put(out, m.earlier.size(), 1);
      for (const uint64_t earlier : m.earlier) put(out, earlier, 8);
      break;
    case SessionMessage::Kind::state: put_state(); break;
    case SessionMessage::Kind::relay:
      put(out, static_cast<uint64_t>(m.subject), 1);
      put_inputs();
      break;
    case SessionMessage::Kind::join_state:
      put(out, static_cast<uint64_t>(m.subject), 1);
      put(out, m.present, 2);
      put(out, m.watching, 2);
      put(out, m.start_hash, 8);
      put_state();
      break;
    case SessionMessage::Kind::join_check:
      put(out, static_cast<uint64_t>(m.subject), 1);
      put(out, m.checksum, 8);
      break;
    case SessionMessage::Kind::quality:
      put(out, static_cast<uint64_t>(m.frame), 8);
      put(out, m.echoes.size(), 1);
      for (const SessionMessage::Echo& echo : m.echoes) {
        put(out, static_cast<uint64_t>(echo.frame), 8);
        put(out, static_cast<uint64_t>(echo.held), 8);
      }
      break;
  }
  return out;
}

namespace {

void put_hello(std::vector<uint8_t>& out, const Hello& h) {
  put(out, static_cast<uint64_t>(h.player), 1);
  put(out, static_cast<uint64_t>(h.players), 1);
  put(out, static_cast<uint64_t>(h.mode), 1);
  put(out, static_cast<uint64_t>(h.input_delay), 1);
  put(out, h.start_hash, 8);
  put(out, h.watching ? 2 : h.joining ? 1 : 0, 1);
}

Result<Hello> take_hello(Reader& r, const char* part) {
  Hello h;
  h.player = static_cast<int>(r.take(1));
  h.players = static_cast<int>(r.take(1));
  const uint64_t mode = r.take(1);
  h.input_delay = static_cast<int>(r.take(1));
  h.start_hash = r.take(8);
  const uint64_t joining = r.take(1);
  if (mode > 1) return Error{part, "mode out of range"};
  if (joining > 2) return Error{part, "joining is not 0, 1 or 2"};
  h.joining = joining >= 1;
  h.watching = joining == 2;
  h.mode = static_cast<SessionMode>(mode);
  if (!r.ok() || !r.done()) return Error{part, "wrong length"};
  return h;
}

}  // namespace

std::vector<uint8_t> encode(const Hello& h) {
  std::vector<uint8_t> out = header(hello_type);
  put_hello(out, h);
  return out;
}

std::vector<uint8_t> encode(const Refusal& refusal) {
  std::vector<uint8_t> out = header(refused_type);
  put(out, static_cast<uint64_t>(refusal.reason), 1);
  put_hello(out, refusal.refuser);
  return out;
}

int packet_version() { return version; }

int packet_version(std::span<const uint8_t> packet) {
  if (packet.size() < 3 || packet[0] != magic[0] || packet[1] != magic[1]) return -1;
  return packet[2];
}

bool looks_like_hello(std::span<const uint8_t> packet) {
  return packet_version(packet) >= 0 && packet.size() >= 4 && packet[3] == hello_type;
}

std::optional<HelloRefused> refusal_of(const Hello& ours, const Hello& theirs, bool said_hello) {
  if (theirs.start_hash != ours.start_hash) return HelloRefused::another_scene;
  if (theirs.players != ours.players) return HelloRefused::player_count;
  if (theirs.mode != ours.mode) return HelloRefused::mode;
  if (theirs.input_delay != ours.input_delay) return HelloRefused::input_delay;
  if (theirs.player < 0 || theirs.player >= ours.players) return HelloRefused::no_such_player;
  if (theirs.player == ours.player) return HelloRefused::our_player;
  if (theirs.joining) {
    if (theirs.player == 0 || ours.joining) return HelloRefused::not_joinable;
  } else if (said_hello) {
    return HelloRefused::player_taken;
  }
  return std::nullopt;
}

std::string describe(HelloRefused why, const Hello& match, int match_version, const Hello& hello, int hello_version) {
  const auto mode = [](SessionMode m) { return std::string(m == SessionMode::lockstep ? "lockstep" : "rollback"); };
  const auto both = [](const std::string& in_match, const std::string& in_hello) {
    return in_match + " in the match, " + in_hello + " in the hello";
  };
  using std::to_string;
  switch (why) {
    case HelloRefused::another_scene:
      return "another scene or settings: start state hash " + both(hex16(match.start_hash), hex16(hello.start_hash));
    case HelloRefused::player_count:
      return "another player count: " + both(to_string(match.players), to_string(hello.players));
    case HelloRefused::mode: return "another mode: " + both(mode(match.mode), mode(hello.mode));
    case HelloRefused::input_delay:
      return "another input delay: " + both(to_string(match.input_delay), to_string(hello.input_delay));
    case HelloRefused::no_such_player:
      return "no player " + to_string(hello.player) + " in a match of " + to_string(match.players);
    case HelloRefused::our_player: return "player " + to_string(hello.player) + " plays on the peer that refused";
    case HelloRefused::player_taken: return "player " + to_string(hello.player) + " said hello already";
    case HelloRefused::not_joinable:
      return hello.player == 0 ? "the host's slot (player 0) cannot be joined"
                               : "the peer that refused is joining itself: join through the host";
    case HelloRefused::version:
      return "another build: packet version " + both(to_string(match_version), to_string(hello_version));
  }
  return "refused";
}

Result<Packet> decode(std::span<const uint8_t> packet) {
  Reader r(packet);
  if (r.take(1) != magic[0] || r.take(1) != magic[1]) return Error{{}, "not a bitstep packet (bad magic)"};
  const uint64_t v = r.take(1);
  if (v >= first_refusal_version && packet.size() > 3 && packet[3] == refused_type) {
    r.take(1);
    Refusal refusal;
    refusal.version = static_cast<int>(v);
    const uint64_t reason = r.take(1);
    if (reason < 1 || reason > static_cast<uint64_t>(HelloRefused::version))
      return Error{"refused", "reason out of range"};
    refusal.reason = static_cast<HelloRefused>(reason);
    Result<Hello> h = take_hello(r, "refused");
    if (!h.ok()) return h.error();
    refusal.refuser = h.value();
    return Packet{refusal};
  }
  if (v != version) return Error{{}, "packet version " + std::to_string(v)};
  const uint64_t type = r.take(1);
  if (type == hello_type) {
    Result<Hello> h = take_hello(r, "hello");
    if (!h.ok()) return h.error();
    return Packet{h.value()};
  }
  if (type > last_message_type) return Error{{}, "packet type " + std::to_string(type)};
  SessionMessage m;
  m.kind = static_cast<SessionMessage::Kind>(type);
  m.sequence = static_cast<uint32_t>(r.take(4));
  m.player = static_cast<int>(r.take(1));
  m.ack = static_cast<int64_t>(r.take(8));
  m.tick = static_cast<int64_t>(r.take(8));
  const auto take_inputs = [&]() -> Result<void> {
    const uint64_t count = r.take(1);
    if (count > max_inputs_per_message) return Error{"inputs", "more than 128"};
    for (uint64_t i = 0; i < count && r.ok(); ++i) {
      const uint64_t length = r.take(2);
      if (length > max_input_bytes) return Error{"inputs", "an input longer than 1024 bytes"};
      const auto bytes = r.bytes(static_cast<size_t>(length));
      m.inputs.emplace_back(bytes.begin(), bytes.end());
    }
    return {};
  };
  const auto take_state = [&]() -> Result<void> {
    const uint64_t length = r.take(4);
    if (length > max_state_bytes) return Error{"state", "longer than 64 MiB"};
    const auto bytes = r.bytes(static_cast<size_t>(length));
    m.state.assign(bytes.begin(), bytes.end());
    const uint64_t game_length = r.take(4);
    if (game_length > max_game_state_bytes) return Error{"state", "a game state longer than 16 MiB"};
    const auto game = r.bytes(static_cast<size_t>(game_length));
    m.game_state.assign(game.begin(), game.end());
    return {};
  };
  switch (m.kind) {
    case SessionMessage::Kind::inputs: {
      if (Result<void> taken = take_inputs(); !taken.ok()) return taken.error();
      const uint64_t changes = r.take(1);
      if (changes > max_roster_events) return Error{"inputs", "more than 16 roster changes"};
      for (uint64_t i = 0; i < changes && r.ok(); ++i) {
        RosterEvent e;
        e.at = static_cast<int64_t>(r.take(8));
        e.from = static_cast<int64_t>(r.take(8));
        e.player = static_cast<int>(r.take(1));
        const uint64_t presence = r.take(1);
        if (presence > 2) return Error{"inputs", "a roster change's presence is not 0, 1 or 2"};
        e.presence = static_cast<Presence>(presence);
        m.roster.push_back(e);
      }
      break;
    }
    case SessionMessage::Kind::checksum: {
      m.checksum = r.take(8);
      const uint64_t count = r.take(1);
      if (count > max_earlier_checksums) return Error{"checksum", "more than 3 earlier checksums"};
      for (uint64_t i = 0; i < count && r.ok(); ++i) m.earlier.push_back(r.take(8));
      break;
    }
    case SessionMessage::Kind::state:
      if (Result<void> taken = take_state(); !taken.ok()) return taken.error();
      break;
    case SessionMessage::Kind::relay:
      m.subject = static_cast<int>(r.take(1));
      if (Result<void> taken = take_inputs(); !taken.ok()) return taken.error();
      break;
    case SessionMessage::Kind::join_state:
      m.subject = static_cast<int>(r.take(1));
      m.present = static_cast<uint32_t>(r.take(2));
      m.watching = static_cast<uint32_t>(r.take(2));
      m.start_hash = r.take(8);
      if (Result<void> taken = take_state(); !taken.ok()) return taken.error();
      break;
    case SessionMessage::Kind::join_check:
      m.subject = static_cast<int>(r.take(1));
      m.checksum = r.take(8);
      break;
    case SessionMessage::Kind::quality: {
      m.frame = static_cast<int64_t>(r.take(8));
      const uint64_t count = r.take(1);
      if (count > 16) return Error{"quality", "more than 16 players"};
      for (uint64_t i = 0; i < count && r.ok(); ++i) {
        const auto frame = static_cast<int64_t>(r.take(8));
        m.echoes.push_back({frame, static_cast<int64_t>(r.take(8))});
      }
      break;
    }
  }
  if (!r.ok()) return Error{{}, "truncated packet"};
  if (!r.done()) return Error{{}, "bytes left after the packet"};
  return Packet{std::move(m)};
}

}  // namespace bitstep
