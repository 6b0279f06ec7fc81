// A bitstep scene file as engine-neutral body specs (tools/bench_engine.h),
// so a peer engine builds exactly the bodies bitstep builds.
#pragma once

#include <string>
#include <vector>

#include "replay/scene.h"
#include "tools/bench_engine.h"

namespace bitstep::bench {

// Builds the scene in bitstep once, then describes each body as bitstep made
// it: the centre-of-mass pose, shapes relative to it, the mass bitstep
// computed. Creation order is kept. False with a one-line reason.
bool specs_from_scene(const Scene& scene, const std::string& name, std::vector<BodySpec>& specs,
                      std::string& reason);

// Loads the scene file, then specs_from_scene.
bool specs_from_scene_file(const std::string& path, std::vector<BodySpec>& specs, std::string& reason);

}  // namespace bitstep::bench
