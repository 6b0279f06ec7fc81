// Fuzzes the session packet decoder: the bytes to decode
// (replay/session_codec.h). Must hold: no crash, no undefined behaviour, no
// leak; either a message, a hello or a refusal, or an Error with a one-line
// message; a decoded packet encodes to exactly the same bytes (the format
// has one encoding of each message).
#include <algorithm>
#include <vector>

#include "replay/session_codec.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

Outcome packet_decoder(std::span<const uint8_t> data) {
  const Result<Packet> decoded = decode(data);
  if (!decoded.ok()) {
    require_one_line_error(decoded.error().message(), "");
    return {false, decoded.error().message()};
  }
  const Packet& packet = decoded.value();
  std::vector<uint8_t> encoded;
  if (const auto* hello = std::get_if<Hello>(&packet)) {
    encoded = encode(*hello);
  } else if (const auto* refusal = std::get_if<Refusal>(&packet)) {
    // A refusal reads from any version from 3 on (its layout stays): it
    // encodes alike but for that version byte, which it keeps.
    encoded = encode(*refusal);
    require(refusal->version == data[2], "a refusal keeps its version");
    encoded[2] = data[2];
  } else {
    encoded = encode(std::get<SessionMessage>(packet));
  }
  require(encoded.size() == data.size() && std::equal(encoded.begin(), encoded.end(), data.begin()),
          "a decoded packet encodes to the same bytes");
  return {true, {}};
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::packet_decoder({data, size});
  return 0;
}
#endif
