// What a session knows of its link to each peer, learnt from the messages
// themselves. The session has no clock: times are in frames (its advance
// calls), which a game runs at its display rate.
//
// - Lost messages: every message a peer sends carries its number (one
//   count per sender, over every kind). A number never seen below the
//   highest is a loss; one that arrives late, within 64 of the highest,
//   is taken back; a number seen twice is a duplicate.
// - Ping: every `quality_every` frames each peer sends a quality message:
//   its frame, its newest local input tick, and for each player the frame
//   of that player's last quality message and how many frames it held it.
//   The round trip is now minus our frame it echoes minus the frames held
//   (smoothed: each sample moves the estimate a quarter of the way).
// - Frames ahead: how far our newest input runs ahead of a peer's, its
//   newest input tick moved on by the frames since it was sent (one a
//   frame) and by half the round trip. A peer ahead of the slowest by two
//   frames or more is advised to wait that many frames (GGPO's and GGRS's
//   time sync): predictions then stay short and rollbacks few.
#pragma once

#include <cstdint>
#include <vector>

namespace bitstep {

struct SessionMessage;

inline constexpr int64_t quality_every = 30;  // frames between quality messages

struct PeerStats {
  int ping_frames = -1;           // round trip, frames (-1 until measured)
  int frames_ahead = 0;           // our newest input tick minus the peer's now (negative: behind)
  int64_t frames_silent = 0;      // frames since its last message
  int64_t messages_received = 0;  // distinct numbers
  int64_t messages_lost = 0;      // numbers below its highest that never came
  int64_t duplicates = 0;
};

class PeerLinks {
 public:
  explicit PeerLinks(int players);
  // A new process in the player's slot: its numbers start again.
  void reset(int player);
  // Any message of the player's, as it arrives (frame: ours now).
  void received(int player, uint32_t sequence, int64_t frame);
  // The player's quality message.
  void quality(int player, const SessionMessage& m, int local_player, int64_t frame);
  // Our quality message: `frame` and `newest_input` ours, the echoes.
  void fill_quality(SessionMessage& m, int64_t frame, int64_t newest_input) const;
  PeerStats stats(int player, int64_t frame, int64_t newest_input) const;

 private:
  struct Link {
    bool any = false;
    uint32_t first = 0, highest = 0;
    uint64_t seen = 0;  // bit k: number highest - k arrived
    int64_t received = 0, duplicates = 0;
    int64_t heard_at = 0;          // our frame at its last message
    int64_t ping16 = -1;           // the round trip in 1/16 frames
    int64_t quality_frame = -1;    // its frame in its last quality message
    int64_t quality_heard_at = 0;  // our frame when that came
    int64_t newest_input = 0;      // its newest input tick then
  };
  std::vector<Link> links_;
};

}  // namespace bitstep
