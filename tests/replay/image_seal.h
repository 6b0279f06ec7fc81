// Images changed on purpose by the readers' tests, their checksums made
// right again, so that the reader itself must refuse them or read them
// whole: a snapshot's trailer (snapshot.h), a rollback state's checksum in
// its header and its trailer (rollback_state.h).
#pragma once

#include <xxhash.h>

#include <cstdint>
#include <vector>

namespace bitstep::test {

inline void put_le(std::vector<uint8_t>& image, size_t at, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) image[at + static_cast<size_t>(i)] = static_cast<uint8_t>(value >> (8 * i));
}

// A snapshot: XXH3-64 of everything before its last 8 bytes, there.
inline void reseal_snapshot(std::vector<uint8_t>& image) {
  const size_t end = image.size() - 8;
  put_le(image, end, XXH3_64bits(image.data(), end), 8);
}

// A rollback state's header: magic 8, version 4, world 8, save 8, checksum
// 8 (at 28), live bodies 4 (at 36), payload size 8; then the serials.
inline constexpr size_t rollback_header_bytes = 48;
inline size_t rollback_payload_at(const std::vector<uint8_t>& image) {
  if (image.size() < rollback_header_bytes) return image.size() + 1;  // no header: none
  uint64_t live = 0;
  for (size_t i = 0; i < 4; ++i) live |= uint64_t{image.at(36 + i)} << (8 * i);
  return rollback_header_bytes + 8 * static_cast<size_t>(live);
}

// A rollback state: the payload's hash into the header, then the trailer
// over the header and the serials (left as it is when the count of live
// bodies, itself changed, leaves no payload to hash).
inline void reseal_rollback_state(std::vector<uint8_t>& image) {
  if (image.size() < rollback_header_bytes + 8) return;
  const size_t payload_at = rollback_payload_at(image);
  if (payload_at > image.size() - 8) return;
  put_le(image, 28, XXH3_64bits(image.data() + payload_at, image.size() - 8 - payload_at), 8);
  put_le(image, image.size() - 8, XXH3_64bits(image.data(), payload_at), 8);
}

}  // namespace bitstep::test
