// Fuzzes the scene reader: the bytes as scene JSON text to parse_scene
// (replay/scene.h), and a scene it accepts with at most 64 bodies to
// build_world. Must hold: no crash, no undefined behaviour, no leak; either
// a scene or one Error whose message is one line naming the file
// ("fuzz.json: <JSON path or byte N>: <reason>"); build_world then gives a
// world or a reason, never a crash.
#include "core/world.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

Outcome scene_reader(std::span<const uint8_t> data) {
  const std::string file = "fuzz.json";
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  const Result<Scene> parsed = parse_scene(text, file);
  if (!parsed.ok()) {
    const Error& error = parsed.error();
    require(error.place.rfind(file, 0) == 0 && !error.reason.empty(), "a scene error names the file and a reason");
    require_one_line_error(error.message(), file);
    return {false, error.message()};
  }
  const Scene& scene = parsed.value();
  if (scene.bodies.size() <= 64) {
    World world(scene.settings);
    if (const Result<void> built = build_world(scene, world); !built.ok()) {
      require_one_line_error(built.error().message(), "");
      return {false, built.error().within(file).message()};
    }
  }
  return {true, {}};
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::scene_reader({data, size});
  return 0;
}
#endif
