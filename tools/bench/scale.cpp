// Scale. Two structures at 10 to 10,000 bodies, each timed awake (sleep off)
// and asleep (sleep on, every body created asleep at rest):
//   pyramid  a 2D pyramid of unit cubes, base b: b (b + 1) / 2 bodies;
//   columns  10-cube stacks side by side on a square grid, 1.5 m apart.
// Method: 3 untimed steps, then steps are timed (std::chrono::steady_clock)
// until 0.5 s have passed or 200 steps ran, at least 3.
#include "tools/bench/scale.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/world.h"
#include "replay/generators.h"
#include "replay/replay.h"

namespace bitstep::bench {

namespace {

SceneBody ground_body() {
  SceneBody ground{"ground", {}};
  ground.def.type = BodyType::static_body;
  // A half-space: the widest structure (a 141-cube pyramid base) is wider
  // than the largest box the world envelope allows.
  ground.def.shapes.push_back({ShapeType::plane, {}, {}, {}, {}});
  return ground;
}

void add(Scene& scene, const std::vector<SceneBody>& bodies) {
  scene.bodies.insert(scene.bodies.end(), bodies.begin(), bodies.end());
}

// The pyramid base whose b (b + 1) / 2 is nearest `bodies`.
int pyramid_base(int bodies) {
  int base = 1;
  while ((base + 1) * (base + 2) / 2 <= bodies) ++base;
  const int below = base * (base + 1) / 2, above = (base + 1) * (base + 2) / 2;
  return bodies - below <= above - bodies ? base : base + 1;
}

Scene build_scene(const std::string& structure, int bodies, bool asleep) {
  Scene scene;
  scene.settings.sleep_method = asleep ? SleepMethod::motion : SleepMethod::off;
  scene.bodies.push_back(ground_body());
  Substance substance;
  substance.asleep = asleep;
  if (structure == "pyramid") {
    PyramidParams params;
    params.base = pyramid_base(bodies);
    params.substance = substance;
    add(scene, generate_pyramid(params));
  } else if (structure == "columns") {
    const int columns = std::max(1, bodies / 10);
    const int side = static_cast<int>(std::ceil(std::sqrt(columns)));
    for (int c = 0; c < columns; ++c) {
      StackParams params;
      params.name = "column" + std::to_string(c);
      params.count = 10;
      params.position = {Fixed::from_int(c % side) * 1.5_fx, Fixed{}, Fixed::from_int(c / side) * 1.5_fx};
      params.substance = substance;
      add(scene, generate_stack(params));
    }
  } else {
    throw std::runtime_error("unknown scale structure " + structure);
  }
  return scene;
}

}  // namespace

std::vector<int> scale_sizes(bool quick) {
  if (quick) return {10, 30, 100, 300, 1000};
  return {10, 30, 100, 300, 1000, 3000, 10000};
}

ScaleRow measure_scale(const std::string& structure, int bodies, bool asleep) {
  const Scene scene = build_scene(structure, bodies, asleep);
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) throw std::runtime_error(built.error().message());
  ScaleRow row{structure, asleep, 0, 0, 0, true};
  for (const Body& b : world.bodies()) row.bodies += b.alive && b.type == BodyType::dynamic;
  for (int i = 0; i < 3; ++i) world.step();
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  std::chrono::duration<double, std::milli> elapsed{};
  while (row.steps < 3 || (row.steps < 200 && elapsed.count() < 500)) {
    world.step();
    ++row.steps;
    elapsed = clock::now() - start;
  }
  row.ms_per_step = elapsed.count() / row.steps;
  if (asleep) {
    for (const Body& b : world.bodies()) row.stayed_asleep = row.stayed_asleep && !is_awake_dynamic(b);
  }
  return row;
}

}  // namespace bitstep::bench
