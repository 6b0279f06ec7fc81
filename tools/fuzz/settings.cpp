// Fuzzes the `--settings` override: the bytes as JSON text to
// apply_settings_text (replay/scene.h) over the default settings. Must
// hold: no crash, no undefined behaviour, no leak; refused: one Error
// whose message is one line naming the source ("--settings: $.sleep: ...")
// and the settings exactly as they were (nothing partially applied);
// accepted: the compact text it returns, applied over the defaults, gives
// the same settings and the same text.
#include <vector>

#include "core/world.h"
#include "replay/scene.h"
#include "replay/state_hash.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

namespace {

// Every setting, as the state's canonical bytes of an empty world.
std::vector<uint8_t> settings_bytes(const Settings& settings) {
  std::vector<uint8_t> bytes;
  serialize_state(World(settings), bytes);
  return bytes;
}

}  // namespace

Outcome settings_override(std::span<const uint8_t> data) {
  const std::string source = "--settings";
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  const std::vector<uint8_t> before = settings_bytes(Settings{});
  Settings settings;
  const Result<std::string> applied = apply_settings_text(text, source, settings);
  if (!applied.ok()) {
    const Error& error = applied.error();
    require(error.place.rfind(source, 0) == 0 && !error.reason.empty(), "a settings error names the source and a reason");
    require_one_line_error(error.message(), source);
    require(settings_bytes(settings) == before, "a refused override changes no setting");
    return {false, error.message()};
  }
  const std::string& compact = applied.value();
  Settings again;
  const Result<std::string> reapplied = apply_settings_text(compact, source, again);
  require(reapplied.ok(), "an override's compact text applies again");
  require(reapplied.value() == compact, "an override's compact text is its own compact text");
  require(settings_bytes(again) == settings_bytes(settings), "an override's compact text gives the same settings");
  return {true, {}};
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::settings_override({data, size});
  return 0;
}
#endif
