#include "replay/session_roster.h"

namespace bitstep {

Roster::Roster(int players) : players_(static_cast<std::size_t>(players)) {}

Roster::Roster(int players, uint32_t present_mask) : Roster(players) {
  for (std::size_t p = 0; p < players_.size(); ++p) players_[p].initially = ((present_mask >> p) & 1u) != 0;
}

bool Roster::present(int player, int64_t tick) const {
  const Player& p = players_[static_cast<std::size_t>(player)];
  for (auto at = p.changes.rbegin(); at != p.changes.rend(); ++at) {
    if (at->first <= tick) return at->second;
  }
  return p.initially;
}

bool Roster::present_now(int player) const {
  const Player& p = players_[static_cast<std::size_t>(player)];
  return p.changes.empty() ? p.initially : p.changes.back().second;
}

int64_t Roster::last_change(int player) const {
  const Player& p = players_[static_cast<std::size_t>(player)];
  return p.changes.empty() ? 0 : p.changes.back().first;
}

void Roster::set(int player, int64_t from, bool present) {
  auto& changes = players_[static_cast<std::size_t>(player)].changes;
  while (!changes.empty() && changes.back().first >= from) changes.pop_back();
  changes.emplace_back(from, present);
}

uint32_t Roster::mask_at(int64_t tick) const {
  uint32_t mask = 0;
  for (std::size_t p = 0; p < players_.size(); ++p) {
    if (present(static_cast<int>(p), tick)) mask |= 1u << p;
  }
  return mask;
}

void Roster::forget_before(int64_t tick) {
  for (Player& p : players_) {
    std::size_t folded = 0;
    while (folded < p.changes.size() && p.changes[folded].first <= tick) p.initially = p.changes[folded++].second;
    p.changes.erase(p.changes.begin(), p.changes.begin() + static_cast<std::ptrdiff_t>(folded));
  }
}

}  // namespace bitstep
