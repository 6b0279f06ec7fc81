#include "replay/session_roster.h"

namespace bitstep {

Roster::Roster(int players) : players_(static_cast<std::size_t>(players)) {}

Roster::Roster(int players, uint32_t present, uint32_t watching) : Roster(players) {
  for (std::size_t p = 0; p < players_.size(); ++p) {
    players_[p].initially = ((present >> p) & 1u) != 0    ? Presence::present
                            : ((watching >> p) & 1u) != 0 ? Presence::watching
                                                          : Presence::absent;
  }
}

Presence Roster::at(int player, int64_t tick) const {
  const Player& p = players_[static_cast<std::size_t>(player)];
  for (auto change = p.changes.rbegin(); change != p.changes.rend(); ++change) {
    if (change->first <= tick) return change->second;
  }
  return p.initially;
}

Presence Roster::now(int player) const {
  const Player& p = players_[static_cast<std::size_t>(player)];
  return p.changes.empty() ? p.initially : p.changes.back().second;
}

bool Roster::follows(int player) const { return now(player) != Presence::absent; }

void Roster::set(int player, int64_t from, Presence presence) {
  auto& changes = players_[static_cast<std::size_t>(player)].changes;
  while (!changes.empty() && changes.back().first >= from) changes.pop_back();
  changes.emplace_back(from, presence);
}

uint32_t Roster::mask_at(int64_t tick, Presence presence) const {
  uint32_t mask = 0;
  for (std::size_t p = 0; p < players_.size(); ++p) {
    if (at(static_cast<int>(p), tick) == presence) mask |= 1u << p;
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
