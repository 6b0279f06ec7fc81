// The fuzz targets' entry points (tools/fuzz/README.md): each takes the
// fuzzer's bytes, feeds them to one reader of untrusted input and checks
// what must hold whatever the bytes are. libFuzzer calls them from
// LLVMFuzzerTestOneInput (one executable per target, built with
// BITSTEP_FUZZ); tests/tools/fuzz_regression_tests.cpp calls the same
// functions in a normal build (BITSTEP_FUZZ_NO_MAIN) on the seed corpora and
// on every input a fuzzer once crashed on.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace bitstep::fuzz {

// What the reader made of the bytes: accepted, or refused with its error.
struct Outcome {
  bool accepted = false;
  std::string error;  // refused: the reader's one-line message
};

// parse_scene on the bytes as scene JSON; a scene of at most 64 bodies is
// also built into a world (build_world: a world or a reason).
Outcome scene_reader(std::span<const uint8_t> data);
// parse_replay on the bytes as replay JSON (a scene file it names is not
// there: inline scenes only); an accepted replay written back and read again
// gives the same text.
Outcome replay_reader(std::span<const uint8_t> data);
// apply_settings_text on the bytes over the defaults: refused leaves the
// settings as they were; accepted, the compact text it returns applies to
// the same settings.
Outcome settings_override(std::span<const uint8_t> data);
// restore of the bytes as a snapshot image into a world built from a small
// scene, as they are and with their size and checksum fields made right (so
// that the payload reader is reached); a restored world snapshots to the
// same bytes.
Outcome snapshot_restore(std::span<const uint8_t> data);
// decode of the bytes as a session packet; a decoded packet encodes to the
// same bytes.
Outcome packet_decoder(std::span<const uint8_t> data);

// The bytes as a sequence of C API calls on a simulation of a small scene
// (capi_input.h); after each: a refused call changed nothing, an image as
// saved loads with its hash.
Outcome capi_calls(std::span<const uint8_t> data);

// A property that must hold: when it does not, prints `what` and aborts (a
// crash for libFuzzer, which keeps the input).
void require(bool condition, const char* what);
// A refusal's message: not empty, one line, starting with `file` + ": ".
void require_one_line_error(const std::string& message, const std::string& file);

}  // namespace bitstep::fuzz
