#include "replay/session_link.h"

#include <algorithm>

#include "replay/session.h"

namespace bitstep {

PeerLinks::PeerLinks(int players) : links_(static_cast<size_t>(players)) {}

void PeerLinks::reset(int player) { links_[static_cast<size_t>(player)] = Link{}; }

void PeerLinks::received(int player, uint32_t sequence, int64_t frame) {
  Link& l = links_[static_cast<size_t>(player)];
  l.heard_at = frame;
  if (!l.any) {
    l = Link{true, sequence, sequence, 1, 1, 0, frame, l.ping16, l.quality_frame, l.quality_heard_at, l.newest_input};
    return;
  }
  if (sequence > l.highest) {  // newer: the window moves on
    const uint32_t shift = sequence - l.highest;
    l.seen = shift >= 64 ? 1 : (l.seen << shift) | 1;
    l.highest = sequence;
    ++l.received;
    return;
  }
  const uint32_t back = l.highest - sequence;
  if (sequence < l.first || back >= 64) return;  // before we heard it first, or too late to tell
  const uint64_t bit = uint64_t{1} << back;
  if ((l.seen & bit) != 0) {
    ++l.duplicates;
    return;
  }
  l.seen |= bit;
  ++l.received;
}

void PeerLinks::quality(int player, const SessionMessage& m, int local_player, int64_t frame) {
  Link& l = links_[static_cast<size_t>(player)];
  if (m.frame <= l.quality_frame) return;  // an older one, late
  l.quality_frame = m.frame;
  l.quality_heard_at = frame;
  l.newest_input = m.tick;
  if (static_cast<size_t>(local_player) >= m.echoes.size()) return;
  const SessionMessage::Echo& echo = m.echoes[static_cast<size_t>(local_player)];
  if (echo.frame < 0 || echo.frame > frame) return;  // it has not heard ours yet
  const int64_t sample = std::max<int64_t>(0, frame - echo.frame - echo.held);
  l.ping16 = l.ping16 < 0 ? 16 * sample : l.ping16 + (16 * sample - l.ping16) / 4;
}

void PeerLinks::fill_quality(SessionMessage& m, int64_t frame, int64_t newest_input) const {
  m.frame = frame;
  m.tick = newest_input;
  m.echoes.clear();
  for (const Link& l : links_) {
    m.echoes.push_back(l.quality_frame < 0 ? SessionMessage::Echo{}
                                           : SessionMessage::Echo{l.quality_frame, frame - l.quality_heard_at});
  }
}

PeerStats PeerLinks::stats(int player, int64_t frame, int64_t newest_input) const {
  const Link& l = links_[static_cast<size_t>(player)];
  PeerStats s;
  s.ping_frames = l.ping16 < 0 ? -1 : static_cast<int>((l.ping16 + 8) / 16);
  s.frames_silent = frame - l.heard_at;
  s.messages_received = l.received;
  s.duplicates = l.duplicates;
  s.messages_lost = l.any ? static_cast<int64_t>(l.highest - l.first) + 1 - l.received : 0;
  if (l.quality_frame >= 0) {
    const int64_t theirs_now = l.newest_input + (frame - l.quality_heard_at) + std::max(0, s.ping_frames) / 2;
    s.frames_ahead = static_cast<int>(std::clamp<int64_t>(newest_input - theirs_now, -100000, 100000));
  }
  return s;
}

}  // namespace bitstep
