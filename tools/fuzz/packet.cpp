// Fuzzes the session packet decoder: the bytes to decode
// (replay/session_codec.h). Must hold: no crash, no undefined behaviour, no
// leak; either a message or a hello, or a PacketError with a one-line
// reason; a decoded packet encodes to exactly the same bytes (the format
// has one encoding of each message).
#include <algorithm>
#include <vector>

#include "replay/session_codec.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

Outcome packet_decoder(std::span<const uint8_t> data) {
  const auto decoded = decode(data);
  if (const PacketError* error = std::get_if<PacketError>(&decoded)) {
    require_one_line_error(error->reason, "");
    return {false, error->reason};
  }
  const std::vector<uint8_t> encoded = std::holds_alternative<Hello>(decoded)
                                           ? encode(std::get<Hello>(decoded))
                                           : encode(std::get<SessionMessage>(decoded));
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
