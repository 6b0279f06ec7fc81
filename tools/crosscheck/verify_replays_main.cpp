// Standalone golden-replay verifier for tools/crosscheck/crosscheck.sh: built by each
// compiler and cross compiler from fixed/, core/ and replay/ alone (xxhash
// inlined, nlohmann header-only, no fmt), it prints one line per replay,
// "<file> match <final hash> <final snapshot checksum>" or "<file> DIFFERS
// <where>", and exits
// 0 only if every replay matches at every step.
#include <cinttypes>
#include <cstdio>
#include <string>

#include "replay/replay.h"

int main(int argc, char** argv) {
  int status = 0;
  for (int i = 1; i < argc; ++i) {
    const bitstep::Result<bitstep::Replay> loaded = bitstep::load_replay_file(argv[i], true);
    if (!loaded.ok()) {
      std::printf("%s ERROR %s\n", argv[i], loaded.error().message().c_str());
      status = 1;
      continue;
    }
    const bitstep::Verification v = bitstep::verify_replay(loaded.value());
    if (!v.built.ok()) {
      std::printf("%s ERROR %s\n", argv[i], v.built.error().message().c_str());
      status = 1;
    } else if (!v.scene_matches) {
      std::printf("%s DIFFERS scene-hash\n", argv[i]);
      status = 1;
    } else if (v.divergent_step != 0) {
      std::printf("%s DIFFERS step-%" PRId64 "\n", argv[i], v.divergent_step);
      status = 1;
    } else {
      std::printf("%s match %016" PRIx64 " %016" PRIx64 "\n", argv[i],
                  v.hashes.empty() ? v.scene_hash : v.hashes.back(), v.snapshot_checksum);
    }
  }
  return status;
}
