// A session's transport over UDP with ENet (Debian's libenet-dev), on the
// loopback interface only: one host bound to 127.0.0.1:port, connected to
// every other peer. Session messages go unreliable and unsequenced (the
// session repeats what was lost); hellos and desync states reliable.
// Faults for tests, applied to the unreliable packets this peer sends:
// loss, a delay drawn from [min, max] ms (jitter, so reordering) and
// duplication. A datagram from an address that is no peer's, and no
// connection request, is counted (stray) and left to ENet, which drops it.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fixed/splitmix64.h"

struct _ENetHost;
struct _ENetPeer;

namespace bitstep {

struct NetFaults {
  int loss_percent = 0;       // 0..100
  int duplicate_percent = 0;  // 0..100
  int min_delay_ms = 0, max_delay_ms = 0;
  uint64_t seed = 1;
};

struct NetStats {
  uint64_t sent = 0, received = 0;
  uint64_t dropped = 0, duplicated = 0;  // by the injected faults
  uint64_t stray = 0;  // datagrams from no peer that were not a connection request (ENet drops them)
};

class EnetTransport {
 public:
  // A host on 127.0.0.1:port, or nullptr and why.
  static std::unique_ptr<EnetTransport> open(uint16_t port, const NetFaults& faults, std::string& error);
  ~EnetTransport();
  EnetTransport(const EnetTransport&) = delete;
  EnetTransport& operator=(const EnetTransport&) = delete;

  // Starts connecting to "127.0.0.1:port" (or "localhost:port"); false and
  // why for any other host or a malformed address.
  bool connect(const std::string& host_port, std::string& error);

  // Every packet to every connected peer; `reliable` skips the faults.
  void send_all(const std::vector<uint8_t>& packet, bool reliable);
  // One packet to one peer, reliably (a hello).
  void send_to(uint32_t peer, const std::vector<uint8_t>& packet);
  void disconnect(uint32_t peer);
  // Hangs up once the packets queued for the peer are sent (a refusal).
  void disconnect_later(uint32_t peer);
  // Whether we connected to the peer (--connect) rather than it to us.
  bool dialled(uint32_t peer) const;
  // Sends what is queued now (before a peer that stops closes its host).
  void flush();

  // Services the host for up to wait_ms: sends what the delay queue holds
  // now, then hands each event over: on_connect(peer), on_packet(peer,
  // bytes), on_disconnect(peer). A peer is a small number of its own.
  struct Handlers {
    std::function<void(uint32_t)> on_connect, on_disconnect;
    std::function<void(uint32_t, std::span<const uint8_t>)> on_packet;
  };
  void poll(int wait_ms, const Handlers& handlers);

  const NetStats& stats() const { return stats_; }

 private:
  EnetTransport(_ENetHost* host, const NetFaults& faults);
  void send_now(_ENetPeer* peer, const std::vector<uint8_t>& packet, bool reliable);
  void flush_due();

  struct Delayed {
    int64_t due_ms;
    std::vector<uint8_t> packet;
  };
  _ENetHost* host_;
  NetFaults faults_;
  SplitMix64 rng_{1};
  std::deque<Delayed> delayed_;
  NetStats stats_;
  std::vector<uint32_t> dialled_;  // the peers we connected to
};

}  // namespace bitstep
