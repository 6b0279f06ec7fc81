// Fuzzes the replay reader: the bytes as replay JSON text to parse_replay
// (replay/replay.h), as if read from a folder that holds no scene files, so
// only an inline scene ("scene": {...}) is read and nothing else on disk.
// Must hold: no crash, no undefined behaviour, no leak; either a replay or
// one Error whose message is one line naming the file; an accepted
// replay written back (replay_json) reads again and writes the same text.
#include "replay/replay.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

Outcome replay_reader(std::span<const uint8_t> data) {
  // A folder that does not exist: a scene named by file cannot be read.
  const std::string file = "/nonexistent-bitstep-fuzz/fuzz.replay.json";
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  const Result<Replay> parsed = parse_replay(text, file, false);
  if (!parsed.ok()) {
    const Error& error = parsed.error();
    require(error.place.rfind(file, 0) == 0 && !error.reason.empty(), "a replay error names the file and a reason");
    require_one_line_error(error.message(), file);
    return {false, error.message()};
  }
  const std::string written = replay_json(parsed.value(), "fuzz");
  const Result<Replay> again = parse_replay(written, file, false);
  require(again.ok(), "a replay written back reads again");
  require(replay_json(again.value(), "fuzz") == written, "a replay written back reads as the same replay");
  return {true, {}};
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::replay_reader({data, size});
  return 0;
}
#endif
