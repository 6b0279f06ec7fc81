#include "tools/cli/enet_transport.h"

#include <enet/enet.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>

namespace bitstep {

namespace {

constexpr size_t max_peers = 32;
constexpr uint8_t unreliable_channel = 0, reliable_channel = 1;

int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The peer's number: its slot in the host's peer array.
uint32_t number_of(const ENetHost* host, const ENetPeer* peer) { return static_cast<uint32_t>(peer - host->peers); }

// The stray datagrams of each host (ENet's intercept hook has no user pointer).
std::map<const ENetHost*, uint64_t*>& stray_counters() {
  static std::map<const ENetHost*, uint64_t*> counters;
  return counters;
}

// Counts a datagram from no peer's address that does not open a
// connection (ENet's header: a 12-bit peer id of all ones and flags, the
// sent time when flagged, then the first command); ENet goes on with it.
int ENET_CALLBACK count_stray(ENetHost* host, ENetEvent*) {
  const ENetAddress& from = host->receivedAddress;
  for (size_t i = 0; i < host->peerCount; ++i) {
    const ENetPeer& peer = host->peers[i];
    if (peer.state != ENET_PEER_STATE_DISCONNECTED && peer.address.host == from.host && peer.address.port == from.port) {
      return 0;
    }
  }
  const uint8_t* data = host->receivedData;
  const size_t size = host->receivedDataLength;
  if (size >= 4) {
    const unsigned header = (unsigned{data[0]} << 8) | data[1];
    const size_t command = (header & ENET_PROTOCOL_HEADER_FLAG_SENT_TIME) != 0 ? 4 : 2;
    if ((header & ENET_PROTOCOL_MAXIMUM_PEER_ID) == ENET_PROTOCOL_MAXIMUM_PEER_ID && size > command &&
        (data[command] & ENET_PROTOCOL_COMMAND_MASK) == ENET_PROTOCOL_COMMAND_CONNECT) {
      return 0;
    }
  }
  const auto counter = stray_counters().find(host);
  if (counter != stray_counters().end()) ++*counter->second;
  return 0;
}

bool initialise(std::string& error) {
  static const bool ok = [] {
    if (enet_initialize() != 0) return false;
    std::atexit(enet_deinitialize);
    return true;
  }();
  if (!ok) error = "cannot initialise ENet";
  return ok;
}

}  // namespace

std::unique_ptr<EnetTransport> EnetTransport::open(uint16_t port, const NetFaults& faults, std::string& error) {
  if (!initialise(error)) return nullptr;
  ENetAddress address{};
  enet_address_set_host_ip(&address, "127.0.0.1");
  address.port = port;
  ENetHost* host = enet_host_create(&address, max_peers, 2, 0, 0);
  if (host == nullptr) {
    error = "cannot listen on 127.0.0.1:" + std::to_string(port) + " (in use?)";
    return nullptr;
  }
  return std::unique_ptr<EnetTransport>(new EnetTransport(host, faults));
}

EnetTransport::EnetTransport(ENetHost* host, const NetFaults& faults)
    : host_(host), faults_(faults), rng_{faults.seed} {
  stray_counters()[host_] = &stats_.stray;
  host_->intercept = count_stray;
}

EnetTransport::~EnetTransport() {
  stray_counters().erase(host_);
  for (size_t i = 0; i < host_->peerCount; ++i) {
    if (host_->peers[i].state == ENET_PEER_STATE_CONNECTED) enet_peer_disconnect_now(&host_->peers[i], 0);
  }
  enet_host_destroy(host_);
}

bool EnetTransport::connect(const std::string& host_port, std::string& error) {
  const size_t colon = host_port.rfind(':');
  const std::string host = colon == std::string::npos ? "" : host_port.substr(0, colon);
  if (host != "127.0.0.1" && host != "localhost") {
    error = "--connect " + host_port + ": peers run on 127.0.0.1 only";
    return false;
  }
  char* end = nullptr;
  const long port = std::strtol(host_port.c_str() + colon + 1, &end, 10);
  if (end == host_port.c_str() + colon + 1 || *end != '\0' || port < 1 || port > 65535) {
    error = "--connect " + host_port + ": not a port";
    return false;
  }
  ENetAddress address{};
  enet_address_set_host_ip(&address, "127.0.0.1");
  address.port = static_cast<uint16_t>(port);
  ENetPeer* peer = enet_host_connect(host_, &address, 2, 0);
  if (peer == nullptr) {
    error = "--connect " + host_port + ": no free peer slot";
    return false;
  }
  dialled_.push_back(static_cast<uint32_t>(peer - host_->peers));
  return true;
}

bool EnetTransport::dialled(uint32_t peer) const {
  return std::find(dialled_.begin(), dialled_.end(), peer) != dialled_.end();
}

void EnetTransport::flush() { enet_host_flush(host_); }

void EnetTransport::send_now(ENetPeer* peer, const std::vector<uint8_t>& packet, bool reliable) {
  ENetPacket* p = enet_packet_create(packet.data(), packet.size(),
                                     reliable ? ENET_PACKET_FLAG_RELIABLE : ENET_PACKET_FLAG_UNSEQUENCED);
  if (p == nullptr) return;
  if (enet_peer_send(peer, reliable ? reliable_channel : unreliable_channel, p) != 0) {
    enet_packet_destroy(p);
    return;
  }
  ++stats_.sent;
}

void EnetTransport::send_all(const std::vector<uint8_t>& packet, bool reliable) {
  for (size_t i = 0; i < host_->peerCount; ++i) {
    ENetPeer* peer = &host_->peers[i];
    if (peer->state != ENET_PEER_STATE_CONNECTED) continue;
    if (reliable) {
      send_now(peer, packet, true);
      continue;
    }
    if (rng_.below(100) < faults_.loss_percent) {
      ++stats_.dropped;
      continue;
    }
    const int copies = rng_.below(100) < faults_.duplicate_percent ? 2 : 1;
    if (copies == 2) ++stats_.duplicated;
    for (int k = 0; k < copies; ++k) {
      const int span = faults_.max_delay_ms - faults_.min_delay_ms + 1;
      const int delay = faults_.min_delay_ms + (span > 1 ? rng_.below(span) : 0);
      if (delay == 0) {
        send_now(peer, packet, false);
      } else {
        // Tagged with the peer's number in front, stripped when sent.
        std::vector<uint8_t> tagged{static_cast<uint8_t>(i)};
        tagged.insert(tagged.end(), packet.begin(), packet.end());
        delayed_.push_back({now_ms() + delay, std::move(tagged)});
      }
    }
  }
}

void EnetTransport::send_to(uint32_t peer, const std::vector<uint8_t>& packet) {
  if (peer < host_->peerCount) send_now(&host_->peers[peer], packet, true);
}

void EnetTransport::disconnect(uint32_t peer) {
  if (peer < host_->peerCount) enet_peer_disconnect_now(&host_->peers[peer], 0);
}

void EnetTransport::disconnect_later(uint32_t peer) {
  if (peer < host_->peerCount) enet_peer_disconnect_later(&host_->peers[peer], 0);
}

// Sends the delayed packets that are due, in due order (a later packet
// with a shorter delay overtakes: reordering).
void EnetTransport::flush_due() {
  const int64_t now = now_ms();
  std::deque<Delayed> waiting;
  for (Delayed& d : delayed_) {
    if (d.due_ms > now) {
      waiting.push_back(std::move(d));
      continue;
    }
    ENetPeer* peer = &host_->peers[d.packet[0]];
    if (peer->state == ENET_PEER_STATE_CONNECTED) {
      send_now(peer, std::vector<uint8_t>(d.packet.begin() + 1, d.packet.end()), false);
    }
  }
  delayed_ = std::move(waiting);
}

void EnetTransport::poll(int wait_ms, const Handlers& handlers) {
  flush_due();
  ENetEvent event;
  int wait = wait_ms;
  while (enet_host_service(host_, &event, static_cast<enet_uint32>(wait)) > 0) {
    wait = 0;
    const uint32_t peer = number_of(host_, event.peer);
    switch (event.type) {
      case ENET_EVENT_TYPE_CONNECT:
        if (handlers.on_connect) handlers.on_connect(peer);
        break;
      case ENET_EVENT_TYPE_RECEIVE:
        ++stats_.received;
        if (handlers.on_packet) handlers.on_packet(peer, {event.packet->data, event.packet->dataLength});
        enet_packet_destroy(event.packet);
        break;
      case ENET_EVENT_TYPE_DISCONNECT:
        if (handlers.on_disconnect) handlers.on_disconnect(peer);
        break;
      case ENET_EVENT_TYPE_NONE: break;
    }
  }
  enet_host_flush(host_);
}

}  // namespace bitstep
