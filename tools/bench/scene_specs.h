// A bitstep scene file as engine-neutral body specs (tools/bench/engine.h),
// so a peer engine builds exactly the bodies bitstep builds.
#pragma once

#include <string>
#include <vector>

#include "replay/scene.h"
#include "tools/bench/engine.h"

namespace bitstep::bench {

// A scene's bodies and joints, joints indexing bodies.
struct SceneSpecs {
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  // Adds the bodies, then the joints; throws where the engine has no joints.
  void add_to(Engine& engine) const;
  // The joints only, after the bodies were added; throws as add_to.
  void add_joints(Engine& engine) const;
};

// Builds the scene in bitstep once, then describes each body as bitstep made
// it: the centre-of-mass pose, shapes relative to it, the mass bitstep
// computed; and each joint at its bodies' starting poses (ropes refused).
// Creation order is kept. False with a one-line reason.
bool specs_from_scene(const Scene& scene, const std::string& name, SceneSpecs& specs, std::string& reason);

// Loads the scene file, then specs_from_scene.
bool specs_from_scene_file(const std::string& path, SceneSpecs& specs, std::string& reason);

}  // namespace bitstep::bench
