// The experiments of `bitstep bench`. Each builds its bodies through the
// Engine interface, steps them with the given dt and iteration count, and
// measures one error against an analytic answer (accuracy) or one stability
// figure on a hard case (stability), with the wall-clock time spent stepping.
#include "tools/bench/experiments.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "fixed/splitmix64.h"
#include "replay/generators.h"
#include "tools/bench/scene_specs.h"

namespace bitstep::bench {

namespace {

constexpr double g = 9.81;  // m/s^2, every experiment's gravity magnitude
constexpr double pi = 3.14159265358979323846;

// --- small vector algebra on doubles --------------------------------------

V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double length(const V3& a) { return std::sqrt(dot(a, a)); }
V3 scale(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }

// Rotation matrix of a unit quaternion (w, x, y, z), row-major.
std::array<V3, 3> matrix(const Q4& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

Q4 about_z(double angle) { return {std::cos(angle / 2), 0, 0, std::sin(angle / 2)}; }

// --- bodies ------------------------------------------------------------------

BodySpec ground(double friction = 0.5, double restitution = 0.0) {
  BodySpec body;
  body.is_static = true;
  body.shapes.push_back({ShapeKind::box, {50, 1, 50}});
  body.position = {0, -1, 0};  // top face at y = 0
  body.static_friction = body.dynamic_friction = friction;
  body.restitution = restitution;
  return body;
}

BodySpec box(const V3& half_extents, const V3& position, double mass, double friction = 0.5) {
  BodySpec body;
  body.shapes.push_back({ShapeKind::box, half_extents});
  body.position = position;
  body.mass = mass;
  body.static_friction = body.dynamic_friction = friction;
  return body;
}

BodySpec sphere(double radius, const V3& position, double mass, double friction = 0.5) {
  BodySpec body;
  ShapeSpec shape;
  shape.kind = ShapeKind::sphere;
  shape.radius = radius;
  body.shapes.push_back(shape);
  body.position = position;
  body.mass = mass;
  body.static_friction = body.dynamic_friction = friction;
  return body;
}

// --- running an engine, timing only its steps -----------------------------

struct Run {
  std::unique_ptr<Engine> engine;
  StepConfig config;
  ExperimentResult result;
  std::vector<V3> start;     // each body's starting centre of mass
  std::vector<bool> moving;  // dynamic bodies

  Run(const Variant& variant, const StepConfig& step_config) : engine(variant.make(step_config)), config(step_config) {}

  int add(const BodySpec& spec) {
    start.push_back(spec.position);
    moving.push_back(!spec.is_static);
    return engine->add_body(spec);
  }
  // Builds a whole body list (a scene) and records where each starts.
  void add_all(const std::vector<BodySpec>& specs) {
    for (const BodySpec& spec : specs) {
      const int id = add(spec);
      start[static_cast<size_t>(id)] = engine->state(id).position;
    }
  }

  void step() {
    const auto before = std::chrono::steady_clock::now();
    engine->step();
    const std::chrono::duration<double, std::milli> spent = std::chrono::steady_clock::now() - before;
    result.wall_ms += spent.count();
    result.simulated_s += config.dt;
  }
  // Whole steps covering `seconds` (at least one).
  int steps_for(double seconds) const { return std::max(1, static_cast<int>(std::lround(seconds / config.dt))); }
  // Steps through `seconds`; returns the simulated time actually stepped.
  double simulate(double seconds) {
    const int n = steps_for(seconds);
    for (int i = 0; i < n; ++i) step();
    return n * config.dt;
  }
  // error = |measured - exact| / exact, both kept as figures.
  void relative_error(const char* measured_name, double measured, double exact) {
    result.error = std::abs(measured - exact) / exact;
    metric(measured_name, measured);
    metric("exact_m", exact);
  }

  // The largest distance any dynamic body has moved from its start, m.
  double max_drift() const {
    double drift = 0;
    for (size_t i = 0; i < start.size(); ++i) {
      if (moving[i]) drift = std::max(drift, length(sub(engine->state(static_cast<int>(i)).position, start[i])));
    }
    return drift;
  }
  void metric(const std::string& name, double value) { result.metrics.emplace_back(name, value); }
};

StepConfig without_gravity(StepConfig config) {
  config.gravity = {0, 0, 0};
  return config;
}

// --- accuracy ----------------------------------------------------------------

// Free fall from rest for 2 s, no ground. Exact: y0 - g t^2 / 2. Also
// against the recurrence of symplectic Euler (v += g dt, then y += v dt:
// y0 - g dt^2 n (n + 1) / 2 after n steps), the integrator of most engines
// (Bullet's); bitstep moves a body in free flight by the mean of the step's
// start and end velocities, whose recurrence is the exact parabola.
ExperimentResult free_fall(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  const double y0 = 100;
  const int body = run.add(sphere(0.5, {0, y0, 0}, 1));
  const int n = run.steps_for(2.0);  // for the recurrence
  const double t = run.simulate(2.0);
  const double y = run.engine->state(body).position[1];
  run.result.error = std::abs(y - (y0 - g * t * t / 2));
  run.metric("error_vs_euler_recurrence_m", std::abs(y - (y0 - g * config.dt * config.dt * n * (n + 1) / 2)));
  return run.result;
}

// A projectile launched at 20 m/s, 45 degrees up, flies 2 s, no ground.
ExperimentResult projectile(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  const V3 p0{0, 100, 0};
  const double v = 20 / std::sqrt(2.0);
  BodySpec ball = sphere(0.5, p0, 1);
  ball.linear_velocity = {v, v, 0};
  const int body = run.add(ball);
  const int n = run.steps_for(2.0);  // for the recurrence
  const double t = run.simulate(2.0);
  const V3 p = run.engine->state(body).position;
  const V3 exact{v * t, p0[1] + v * t - g * t * t / 2, 0};
  const V3 recurrence{v * t, p0[1] + v * t - g * config.dt * config.dt * n * (n + 1) / 2, 0};
  run.result.error = length(sub(p, exact));
  run.metric("error_vs_euler_recurrence_m", length(sub(p, recurrence)));
  return run.result;
}

// A 0.5 m cube on a static slope at 30 degrees about z, exactly touching.
// Returns the slope's downhill unit vector.
V3 build_incline(Run& run, double friction, int& block) {
  const double angle = pi / 6;
  const Q4 tilt = about_z(angle);
  const V3 normal{-std::sin(angle), std::cos(angle), 0};
  BodySpec slope;
  slope.is_static = true;
  slope.shapes.push_back({ShapeKind::box, {10, 0.5, 2}});
  slope.position = scale(normal, -0.5);  // top face through the origin
  slope.orientation = tilt;
  slope.static_friction = slope.dynamic_friction = friction;
  run.add(slope);
  BodySpec cube = box({0.25, 0.25, 0.25}, scale(normal, 0.25), 1, friction);
  cube.orientation = tilt;
  block = run.add(cube);
  return {-std::cos(angle), -std::sin(angle), 0};
}

// mu 0.6 > tan 30 = 0.577: static friction must hold the block for 5 s.
ExperimentResult incline_hold(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, config);
  int block = 0;
  build_incline(run, 0.6, block);
  run.simulate(options.quick ? 2.0 : 5.0);
  run.result.error = run.max_drift();
  return run.result;
}

// mu 0.4 < tan 30: the block slides at a = g (sin 30 - mu cos 30) = 1.507
// m/s^2; after 2 s it has gone a t^2 / 2 downhill.
ExperimentResult incline_slide(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  int block = 0;
  const double mu = 0.4;
  const V3 downhill = build_incline(run, mu, block);
  const double t = run.simulate(2.0);
  const double a = g * (std::sin(pi / 6) - mu * std::cos(pi / 6));
  const double travelled = dot(sub(run.engine->state(block).position, run.start[static_cast<size_t>(block)]), downhill);
  run.relative_error("travelled_m", travelled, a * t * t / 2);
  return run.result;
}

// A 0.5 m cube sliding at 5 m/s on the ground with mu 0.5 stops after
// v0^2 / (2 mu g) = 2.548 m.
ExperimentResult stop_distance(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  const double mu = 0.5, v0 = 5;
  run.add(ground(mu));
  BodySpec cube = box({0.25, 0.25, 0.25}, {0, 0.25, 0}, 1, mu);
  cube.linear_velocity = {v0, 0, 0};
  const int block = run.add(cube);
  run.simulate(2.0);
  run.relative_error("travelled_m", run.engine->state(block).position[0], v0 * v0 / (2 * mu * g));
  return run.result;
}

// A ball with restitution 0.5 dropped from 1 m (its bottom above the
// ground) rises to e^2 h = 0.25 m.
ExperimentResult bounce(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  const double e = 0.5, r = 0.5, h = 1.0;
  run.add(ground(0.5, e));
  BodySpec ball = sphere(r, {0, r + h, 0}, 1);
  ball.restitution = e;
  const int body = run.add(ball);
  bool rising = false;
  double peak = 0;
  const int n = run.steps_for(1.5);
  for (int i = 0; i < n; ++i) {
    run.step();
    const BodyState s = run.engine->state(body);
    if (s.linear_velocity[1] > 0) rising = true;
    if (rising) {
      if (s.linear_velocity[1] <= 0 && peak > 0) break;
      peak = std::max(peak, s.position[1] - r);
    }
  }
  const double exact = e * e * h;
  run.result.error = std::abs(peak - exact) / exact;
  run.metric("rebound_m", peak);
  return run.result;
}

// A 0.8 x 0.4 x 0.2 m box spinning free of gravity, mostly about its axis
// of largest inertia (stable): angular momentum L = R I R^T w and energy
// w.L / 2 are constant; the error is their worst relative drift over 20 s.
ExperimentResult tumbling(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, without_gravity(config));
  const V3 h{0.4, 0.2, 0.1};
  const double m = 1;
  const V3 inertia{m / 3 * (h[1] * h[1] + h[2] * h[2]), m / 3 * (h[0] * h[0] + h[2] * h[2]),
                   m / 3 * (h[0] * h[0] + h[1] * h[1])};
  BodySpec spinner = box(h, {0, 0, 0}, m);
  spinner.angular_velocity = {0.5, 0.5, 5.0};
  const int body = run.add(spinner);
  auto momentum_and_energy = [&](V3& L, double& E) {
    const BodyState s = run.engine->state(body);
    const auto R = matrix(s.orientation);
    V3 local{};  // R^T w, then I R^T w, then L = R I R^T w
    for (size_t i = 0; i < 3; ++i) {
      local[i] = inertia[i] * (R[0][i] * s.angular_velocity[0] + R[1][i] * s.angular_velocity[1] +
                               R[2][i] * s.angular_velocity[2]);
    }
    for (size_t i = 0; i < 3; ++i) L[i] = dot(R[i], local);
    E = dot(s.angular_velocity, L) / 2;
  };
  V3 L0{};
  double E0 = 0;
  momentum_and_energy(L0, E0);
  double worst_L = 0, worst_E = 0;
  const int n = run.steps_for(options.quick ? 5.0 : 20.0);
  for (int i = 0; i < n; ++i) {
    run.step();
    V3 L{};
    double E = 0;
    momentum_and_energy(L, E);
    worst_L = std::max(worst_L, length(sub(L, L0)) / length(L0));
    worst_E = std::max(worst_E, std::abs(E - E0) / E0);
  }
  run.result.error = std::max(worst_L, worst_E);
  run.metric("momentum_drift", worst_L);
  run.metric("energy_drift", worst_E);
  return run.result;
}

// A ball launched sliding at 5 m/s without spin, mu 0.3: friction slows it
// and spins it up until it rolls at t = 2 v0 / (7 mu g) = 0.485 s, then
// rolls at 5/7 v0 for good.
ExperimentResult rolling_sphere(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  const double mu = 0.3, v0 = 5, r = 0.5;
  run.add(ground(mu));
  BodySpec ball = sphere(r, {0, r, 0}, 1, mu);
  ball.linear_velocity = {v0, 0, 0};
  const int body = run.add(ball);
  double slip_end = -1;
  const int n = run.steps_for(2.0);
  for (int i = 0; i < n; ++i) {
    run.step();
    const BodyState s = run.engine->state(body);
    // Velocity of the contact point: v + w x (0, -r, 0), along x: v_x + w_z r.
    const double slip = s.linear_velocity[0] + s.angular_velocity[2] * r;
    if (slip_end < 0 && std::abs(slip) < 0.01 * v0) slip_end = run.result.simulated_s;
  }
  const double exact_v = 5.0 / 7.0 * v0;
  const double v = run.engine->state(body).linear_velocity[0];
  run.result.error = std::abs(v - exact_v) / exact_v;
  run.metric("final_speed_m_per_s", v);
  run.metric("slip_end_s", slip_end);
  run.metric("slip_end_exact_s", 2 * v0 / (7 * mu * g));
  return run.result;
}

// --- stability -----------------------------------------------------------------

constexpr double fallen = 0.10;  // m: a body that moved this far means the structure fell

// Steps a built structure for `seconds`, sampling drift and penetration about
// 200 times; error = the largest drift seen. With stop_when_fallen the run
// ends at the first step a body has moved 10 cm (wall: steps until it falls).
void watch(Run& run, double seconds, bool stop_when_fallen = false) {
  run.result.columns = {"t_s", "max_drift_m", "max_penetration_m"};
  const int n = run.steps_for(seconds);
  const int every = std::max(1, n / 200);
  double worst_drift = 0, worst_penetration = 0;
  int fell_at = -1;
  for (int i = 1; i <= n; ++i) {
    run.step();
    const bool sample = i % every == 0 || i == n;
    if (!sample && !stop_when_fallen) continue;
    const double drift = run.max_drift();
    const double penetration = run.engine->max_penetration();
    worst_drift = std::max(worst_drift, drift);
    worst_penetration = std::max(worst_penetration, penetration);
    if (sample) run.result.rows.push_back({i * run.config.dt, drift, penetration});
    if (drift > fallen && fell_at < 0) {
      fell_at = i;
      if (stop_when_fallen) {
        run.result.rows.push_back({i * run.config.dt, drift, penetration});
        break;
      }
    }
  }
  run.result.error = worst_drift;
  run.result.failed = fell_at >= 0;
  run.metric("max_penetration_m", worst_penetration);
  run.metric("steps_standing", fell_at < 0 ? n : fell_at - 1);
}

ExperimentResult scene_file(const Variant& variant, const StepConfig& config, const RunOptions& options,
                            const std::string& file, double seconds, bool stop_when_fallen = false) {
  Run run(variant, config);
  SceneSpecs specs;
  std::string reason;
  if (!specs_from_scene_file(options.scenes_dir + "/" + file, specs, reason)) {
    throw std::runtime_error(reason);
  }
  run.add_all(specs.bodies);
  specs.add_joints(*run.engine);
  watch(run, seconds, stop_when_fallen);
  return run.result;
}

ExperimentResult stack20(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "stack20.json", o.quick ? 5 : 10);
}
ExperimentResult stack50(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "stack50.json", o.quick ? 5 : 30);
}
ExperimentResult pyramid20(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "pyramid20.json", o.quick ? 5 : 20);
}
ExperimentResult jenga(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "jenga.json", o.quick ? 5 : 30);
}
ExperimentResult tables(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "tables.json", o.quick ? 5 : 20);
}
// Walls run until a brick moves 10 cm, at most 2,000 steps at 60 Hz.
ExperimentResult wall64(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "wall64.json", (o.quick ? 300 : 2000) / 60.0, true);
}
ExperimentResult wall128(const Variant& v, const StepConfig& c, const RunOptions& o) {
  return scene_file(v, c, o, "wall128.json", 2000 / 60.0, true);
}

// A 1 kg unit cube under a cube `ratio` times heavier, on the ground,
// exactly touching, for 2 s: error = the deepest overlap in the last second.
ExperimentResult light_under_heavy(const Variant& variant, const StepConfig& config, double ratio) {
  Run run(variant, config);
  run.add(ground());
  const int light = run.add(box({0.5, 0.5, 0.5}, {0, 0.5, 0}, 1));
  run.add(box({0.5, 0.5, 0.5}, {0, 1.5, 0}, ratio));
  const int n = run.steps_for(2.0);
  double worst = 0;
  for (int i = 1; i <= n; ++i) {
    run.step();
    if (i > n / 2) worst = std::max(worst, run.engine->max_penetration());
  }
  run.result.error = worst;
  run.metric("light_sink_m", run.start[static_cast<size_t>(light)][1] - run.engine->state(light).position[1]);
  run.result.failed = run.engine->state(light).position[1] < 0.25;
  return run.result;
}
ExperimentResult light_under_heavy_100(const Variant& v, const StepConfig& c, const RunOptions&) {
  return light_under_heavy(v, c, 100);
}
ExperimentResult light_under_heavy_1000(const Variant& v, const StepConfig& c, const RunOptions&) {
  return light_under_heavy(v, c, 1000);
}

// A 1,000 kg unit cube dropped from 1 m onto a 1 kg unit cube resting on
// the ground: error = the deepest overlap at any time.
ExperimentResult heavy_on_light(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  run.add(ground());
  const int light = run.add(box({0.5, 0.5, 0.5}, {0, 0.5, 0}, 1));
  run.add(box({0.5, 0.5, 0.5}, {0, 2.5, 0}, 1000));
  const int n = run.steps_for(2.0);
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    run.step();
    worst = std::max(worst, run.engine->max_penetration());
  }
  run.result.error = worst;
  run.metric("final_penetration_m", run.engine->max_penetration());
  run.metric("light_sink_m", run.start[static_cast<size_t>(light)][1] - run.engine->state(light).position[1]);
  run.result.failed = run.engine->state(light).position[1] < 0.25;
  return run.result;
}

// Five unit cubes in a column, each starting 25% inside the one below (the
// lowest 25% inside the ground): error = the time until every overlap is
// under 1 cm (3 s when never); the push-out speed is the fastest body.
ExperimentResult overlap_recovery(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  run.add(ground());
  std::vector<int> cubes;
  for (int i = 0; i < 5; ++i) cubes.push_back(run.add(box({0.5, 0.5, 0.5}, {0, 0.25 + 0.75 * i, 0}, 1)));
  const double limit = 3.0;
  double recovered = -1, fastest = 0;
  const int n = run.steps_for(limit);
  for (int i = 0; i < n; ++i) {
    run.step();
    for (int c : cubes) fastest = std::max(fastest, length(run.engine->state(c).linear_velocity));
    if (recovered < 0 && run.engine->max_penetration() < 0.01) recovered = run.result.simulated_s;
  }
  run.result.failed = recovered < 0;
  run.result.error = recovered < 0 ? limit : recovered;
  run.metric("push_out_speed_m_per_s", fastest);
  run.metric("final_penetration_m", run.engine->max_penetration());
  return run.result;
}

// Heaps of 27 cubes (half extents 0.06, 0.12, 0.18 m, 1,000 kg/m^3)
// dropped in three staggered layers of 3 x 3 into a pen 1.6 m square, in
// `arrangements` arrangements (each shifts the layers by 13 mm more and
// turns the sizes round). After 30 s a settled heap should not move: error
// = the farthest any cube moves from 30 s to 40 s (m), over the
// arrangements; "fell" beyond 1 cm; also how many heaps moved over 1 mm.
// Boxes leaning on boxes are where bitstep's shock step can let a heap
// creep (core/README.md). Which heaps creep changes with any change of
// rounding, so a change is judged on the count over many arrangements.
ExperimentResult heap_rest(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  const int arrangements = options.quick ? 2 : 24;
  ExperimentResult total;
  double farthest = 0, fastest = 0;
  int creeping = 0;
  for (int v = 0; v < arrangements; ++v) {
    Run run(variant, config);
    run.add(ground());
    for (int side = 0; side < 4; ++side) {
      BodySpec wall;
      wall.is_static = true;
      wall.shapes.push_back({ShapeKind::box, side < 2 ? V3{0.1, 1, 1} : V3{1, 1, 0.1}});
      wall.position = side < 2 ? V3{side == 0 ? 0.9 : -0.9, 1, 0} : V3{0, 1, side == 2 ? 0.9 : -0.9};
      wall.static_friction = wall.dynamic_friction = 0.5;
      run.add(wall);
    }
    std::vector<int> cubes;
    for (int k = 0; k < 27; ++k) {
      const int layer = k / 9, i = k % 9;
      const double shift = 0.013 * v;
      const double h = 0.06 * (1 + (k % 9 + k / 9 + v) % 3);
      const V3 at{(i % 3 - 1) * 0.45 + layer * (0.05 + shift), 0.25 + layer * 0.45,
                  (i / 3 - 1) * 0.45 - layer * (0.05 - shift)};
      cubes.push_back(run.add(box({h, h, h}, at, 1000 * 8 * h * h * h)));
    }
    run.simulate(30);
    std::vector<V3> settled;
    for (int c : cubes) settled.push_back(run.engine->state(c).position);
    for (int i = run.steps_for(10); i > 0; --i) {
      run.step();
      for (int c : cubes) fastest = std::max(fastest, length(run.engine->state(c).linear_velocity));
    }
    double heap_farthest = 0;
    for (size_t c = 0; c < cubes.size(); ++c) {
      heap_farthest = std::max(heap_farthest, length(sub(run.engine->state(cubes[c]).position, settled[c])));
    }
    farthest = std::max(farthest, heap_farthest);
    creeping += heap_farthest > 0.001 ? 1 : 0;
    total.wall_ms += run.result.wall_ms;
    total.simulated_s += run.result.simulated_s;
  }
  total.error = farthest;
  total.failed = farthest > 0.01;
  total.metrics.emplace_back("arrangements", arrangements);
  total.metrics.emplace_back("heaps_over_1mm", creeping);
  total.metrics.emplace_back("fastest_after_30s_m_per_s", fastest);
  return total;
}

// 50 cubes of 0.5 m thrown at 20 m/s at the ground from a 6 x 4 x 6 m
// region 5 m up (seeded): error = how far any cube's lowest corner ever got
// below the ground's top, m; also how many end with their centre below it.
ExperimentResult thrown(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  Scene scene;
  ThrowParams params;
  params.count = 50;
  params.seed = 20261121;
  params.position = {Fixed{}, 5.0_fx, Fixed{}};
  params.spread = {3.0_fx, 2.0_fx, 3.0_fx};
  params.speed = 20.0_fx;
  scene.bodies = generate_throw(params).bodies;
  std::vector<BodySpec> specs{ground()};
  SceneSpecs thrown_specs;
  std::string reason;
  if (!specs_from_scene(scene, "thrown cubes", thrown_specs, reason)) throw std::runtime_error(reason);
  specs.insert(specs.end(), thrown_specs.bodies.begin(), thrown_specs.bodies.end());
  run.add_all(specs);
  const double half = 0.25;
  double deepest = 0;
  int below_at_end = 0;
  const int n = run.steps_for(3.0);
  for (int i = 1; i <= n; ++i) {
    run.step();
    for (size_t b = 1; b < specs.size(); ++b) {
      const BodyState s = run.engine->state(static_cast<int>(b));
      const auto R = matrix(s.orientation);
      // Lowest corner: centre y minus the box's half extents projected on y.
      const double reach = half * (std::abs(R[1][0]) + std::abs(R[1][1]) + std::abs(R[1][2]));
      deepest = std::max(deepest, -(s.position[1] - reach));
      if (i == n && s.position[1] < 0) ++below_at_end;
    }
  }
  run.result.error = deepest;
  run.result.failed = below_at_end > 0;
  run.metric("below_ground_at_end", below_at_end);
  return run.result;
}

// 20 dice (scenes/dice.json's: 0.5 m cubes, corners cut 5 cm) thrown spinning at the ground from a
// seeded spread: after 6 s each should lie on a face. Error: the largest
// tilt of a die from face-down (degrees); failed when one is still moving
// or below the ground.
ExperimentResult dice(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, config);
  // The die of scenes/dice.json (its body "die0").
  const Result<Scene> shipped = load_scene_file(options.scenes_dir + "/dice.json");
  if (!shipped.ok()) throw std::runtime_error(shipped.error().message());
  const auto named = std::find_if(shipped.value().bodies.begin(), shipped.value().bodies.end(),
                                  [](const SceneBody& b) { return b.name == "die0"; });
  if (named == shipped.value().bodies.end()) throw std::runtime_error("dice.json: no body \"die0\"");
  const Shape die = named->def.shapes[0];
  Scene scene;
  SplitMix64 random{20261201};
  const auto uniform = [&](int lo, int hi) {
    return Fixed::from_int(lo + static_cast<int>(random.next() % static_cast<uint64_t>(hi - lo + 1)));
  };
  for (int i = 0; i < 20; ++i) {
    SceneBody body;
    body.def.pose.position = {Fixed::from_int(i % 5 - 2), Fixed::from_int(2 + i / 5), Fixed::from_int(i % 3 - 1)};
    body.def.linear_velocity = {uniform(-3, 3), uniform(-2, 2), uniform(-3, 3)};
    body.def.angular_velocity = {uniform(-8, 8), uniform(-8, 8), uniform(-8, 8)};
    body.def.shapes.push_back(die);
    scene.bodies.push_back(body);
  }
  std::vector<BodySpec> specs{ground()};
  SceneSpecs dice_specs;
  std::string reason;
  if (!specs_from_scene(scene, "dice", dice_specs, reason)) throw std::runtime_error(reason);
  specs.insert(specs.end(), dice_specs.bodies.begin(), dice_specs.bodies.end());
  run.add_all(specs);
  double deepest = 0;
  const int n = run.steps_for(6.0);
  for (int i = 1; i <= n; ++i) run.step();
  double worst_tilt = 0, fastest = 0;
  for (size_t b = 1; b < specs.size(); ++b) {
    const BodyState s = run.engine->state(static_cast<int>(b));
    const auto R = matrix(s.orientation);
    // Face-down: one of the die's axes (the body's, its inertia being a
    // multiple of the identity) along the vertical.
    const double most_vertical = std::max({std::abs(R[1][0]), std::abs(R[1][1]), std::abs(R[1][2])});
    worst_tilt = std::max(worst_tilt, std::acos(std::min(most_vertical, 1.0)) * 180 / 3.14159265358979);
    deepest = std::max(deepest, 0.25 - s.position[1]);
    fastest = std::max(fastest, std::hypot(s.linear_velocity[0], s.linear_velocity[1], s.linear_velocity[2]));
  }
  run.result.error = worst_tilt;
  run.result.failed = fastest > 0.01 || deepest > 0.05;
  run.metric("deepest_centre_below_rest_m", deepest);
  run.metric("fastest_at_end_m_per_s", fastest);
  return run.result;
}

// 10 boxes (0.5 m, mu 0.2) sliding down a 20-degree slope of triangles: a
// height grid's (41 x 21 samples 0.5 m apart, h = -x tan 20), as a static
// triangle mesh (`kind` mesh: bitstep's mesh shape, Bullet's
// btBvhTriangleMeshShape) or as a heightfield (bitstep's heightfield,
// Bullet's btHeightfieldTerrainShape). Each starts 1 mm above the slope,
// turned with it, at rest, at its own place across the cells so that
// triangle edges pass under the boxes at every phase. Error: the worst
// relative error of the distance slid in 1.5 s against the semi-implicit
// Euler step's a dt^2 n (n + 1) / 2, a = g (sin 20 - 0.2 cos 20); failed
// when a box left the surface by 2 cm.
ExperimentResult slope_of_triangles(const Variant& variant, const StepConfig& config, ShapeKind kind) {
  Run run(variant, config);
  const double slope = 20 * pi / 180, rise = std::tan(slope);
  BodySpec field;
  field.is_static = true;
  field.static_friction = field.dynamic_friction = 0.2;
  constexpr uint32_t columns = 41, rows = 21;
  ShapeSpec grid;
  grid.kind = kind;
  if (kind == ShapeKind::heightfield) {
    grid.columns = columns;
    grid.rows = rows;
    grid.spacing_x = grid.spacing_z = 0.5;
    for (uint32_t j = 0; j < rows; ++j) {
      for (uint32_t i = 0; i < columns; ++i) grid.heights.push_back(-(0.5 * i) * rise);
    }
    field.position = {-10, 0, -5};
  } else {
    for (uint32_t j = 0; j < rows; ++j) {
      for (uint32_t i = 0; i < columns; ++i) grid.points.push_back({-10 + 0.5 * i, -(0.5 * i) * rise, -5 + 0.5 * j});
    }
    for (uint32_t j = 0; j + 1 < rows; ++j) {
      for (uint32_t i = 0; i + 1 < columns; ++i) {
        const uint32_t s00 = j * columns + i, s10 = s00 + 1, s01 = s00 + columns, s11 = s01 + 1;
        grid.indices.insert(grid.indices.end(), {s00, s01, s11, s00, s11, s10});
      }
    }
  }
  field.shapes.push_back(grid);
  run.add(field);
  const Q4 tilt{std::cos(-slope / 2), 0, 0, std::sin(-slope / 2)};
  const V3 down_slope{std::cos(slope), -std::sin(slope), 0}, up{std::sin(slope), std::cos(slope), 0};
  std::vector<V3> starts;
  for (int k = 0; k < 10; ++k) {
    const double x = -8 + 0.4 * k, z = -4 + 0.8 * k;
    const double surface = -(x + 10) * rise;
    BodySpec b = box({0.25, 0.25, 0.25}, {x + 0.251 * up[0], surface + 0.251 * up[1], z}, 10, 0.2);
    b.orientation = tilt;
    starts.push_back(b.position);
    run.add(b);
  }
  const int n = run.steps_for(1.5);
  double off_surface = 0;
  for (int i = 1; i <= n; ++i) {
    run.step();
    for (int k = 0; k < 10; ++k) {
      const V3 p = run.engine->state(k + 1).position;
      const double normal =
          (p[0] - starts[static_cast<size_t>(k)][0]) * up[0] + (p[1] - starts[static_cast<size_t>(k)][1]) * up[1];
      off_surface = std::max(off_surface, std::abs(normal));
    }
  }
  const double a = 9.81 * (std::sin(slope) - 0.2 * std::cos(slope));
  const double expected = a * config.dt * config.dt * n * (n + 1) / 2;
  double worst = 0;
  for (int k = 0; k < 10; ++k) {
    const V3 p = run.engine->state(k + 1).position;
    const V3& s0 = starts[static_cast<size_t>(k)];
    const double along = (p[0] - s0[0]) * down_slope[0] + (p[1] - s0[1]) * down_slope[1];
    worst = std::max(worst, std::abs(along - expected) / expected);
  }
  run.result.error = worst;
  run.result.failed = off_surface > 0.02;
  run.metric("farthest_off_the_surface_m", off_surface);
  return run.result;
}

ExperimentResult mesh_slope(const Variant& variant, const StepConfig& config, const RunOptions&) {
  return slope_of_triangles(variant, config, ShapeKind::mesh);
}

ExperimentResult heightfield_slope(const Variant& variant, const StepConfig& config, const RunOptions&) {
  return slope_of_triangles(variant, config, ShapeKind::heightfield);
}

// --- characters --------------------------------------------------------------

// A character (capsule r 0.3 m, inner segment 1.2 m, step height 0.3 m,
// 45-degree slope limit) walks at 2 m/s along +x for 3 s from 2 m before a
// flight of five 0.2 m steps (0.4 m treads) up to a landing 1 m high that
// runs on to x = 8, starting 1 mm above the floor. It should walk 6 m
// (stairs should not slow it) and end on the landing. Error: the relative
// shortfall of the distance walked; failed when its feet end more than
// 5 cm from the landing's height.
ExperimentResult character_stairs(const Variant& variant, const StepConfig& config, const RunOptions&) {
  Run run(variant, config);
  BodySpec floor = box({10, 0.5, 3}, {0, -0.5, 0}, 1, 0.5);
  floor.is_static = true;
  run.add(floor);
  constexpr int steps = 5;
  constexpr double rise = 0.2, tread = 0.4, first = 2, end = 8;
  for (int k = 0; k < steps; ++k) {
    const double from = first + tread * k, height = rise * (k + 1);
    BodySpec step = box({(end - from) / 2, height / 2, 1.5}, {(end + from) / 2, height / 2, 0}, 1, 0.5);
    step.is_static = true;
    run.add(step);
  }
  CharacterSpec spec;
  const double feet = spec.radius + spec.half_height;  // from the capsule's centre
  spec.position = {0, feet + 0.001, 0};
  const int walker = run.engine->add_character(spec);
  if (walker < 0) throw std::runtime_error("the engine has no character controller");
  run.engine->walk(walker, {2, 0, 0});
  const int n = run.steps_for(3.0);
  double lowest = 0;
  for (int i = 1; i <= n; ++i) {
    run.step();
    lowest = std::min(lowest, run.engine->character_position(walker)[1] - feet);
  }
  const V3 p = run.engine->character_position(walker);
  const double walked = p[0] - spec.position[0], expected = 2 * n * config.dt;
  run.result.error = std::abs(expected - walked) / expected;
  run.result.failed = std::abs(p[1] - feet - rise * steps) > 0.05;
  run.metric("walked_m", walked);
  run.metric("expected_m", expected);
  run.metric("feet_height_m", p[1] - feet);
  run.metric("lowest_feet_m", lowest);
  return run.result;
}

// --- joints ------------------------------------------------------------------

// A static 5 cm sphere at `at`: what joints hang from (joined bodies do not
// collide, so its shape is only there because a body needs one).
BodySpec anchor_body(const V3& at) {
  BodySpec body = sphere(0.05, at, 1);
  body.is_static = true;
  return body;
}

void join(Run& run, const JointSpec& spec) {
  if (run.engine->add_joint(spec) < 0) throw std::runtime_error("the engine has no joints");
}

JointSpec point_joint(int a, int b, const V3& anchor) {
  JointSpec spec;
  spec.kind = JointKind::point;
  spec.body_a = a;
  spec.body_b = b;
  spec.anchor = anchor;
  return spec;
}

// A 1 kg ball (r 0.05 m) on a point joint 1 m below a static anchor, let go
// 5 degrees out. Its period, from the downward zero crossings of x (linear
// interpolation between steps) over 10 s, against the compound pendulum's
// 2 pi sqrt(I / (m g L)) (1 + theta0^2 / 16), I = m L^2 + 2/5 m r^2.
ExperimentResult pendulum(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, config);
  const double m = 1, r = 0.05, L = 1, theta0 = 5 * pi / 180;
  const V3 pivot{0, 2, 0};
  const int holder = run.add(anchor_body(pivot));
  const int bob = run.add(sphere(r, {L * std::sin(theta0), pivot[1] - L * std::cos(theta0), 0}, m));
  join(run, point_joint(holder, bob, pivot));
  std::vector<double> crossings;
  double x_before = run.engine->state(bob).position[0], worst_length = 0;
  const int n = run.steps_for(options.quick ? 6.0 : 10.0);
  for (int i = 1; i <= n; ++i) {
    run.step();
    const V3 p = run.engine->state(bob).position;
    if (x_before > 0 && p[0] <= 0) crossings.push_back((i - 1 + x_before / (x_before - p[0])) * config.dt);
    x_before = p[0];
    worst_length = std::max(worst_length, std::abs(length(sub(p, pivot)) - L));
  }
  const double I = m * L * L + 0.4 * m * r * r;
  const double exact = 2 * pi * std::sqrt(I / (m * g * L)) * (1 + theta0 * theta0 / 16);
  run.metric("crossings", static_cast<double>(crossings.size()));
  run.metric("max_length_error_m", worst_length);
  if (crossings.size() < 2) {
    run.result.failed = true;
    run.result.error = 1;
    return run.result;
  }
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  run.relative_error("period_s", period, exact);
  return run.result;
}

// 25 links (1 kg boxes 0.1 x 0.5 x 0.1 m) hanging straight down from a
// static anchor by point joints at their ends, a 100 kg ball (r 0.25 m) on
// the last by its top, all at rest where the straight chain hangs. Error =
// how far the ball ever gets below that rest position (the chain's
// stretch), m; "fell" beyond 1 m.
ExperimentResult chain_stretch(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, config);
  const int links = 25;
  const double half = 0.25, r = 0.25, top = 15;
  int above = run.add(anchor_body({0, top, 0}));
  for (int k = 0; k < links; ++k) {
    const double upper_end = top - 2 * half * k;
    const int link = run.add(box({0.05, half, 0.05}, {0, upper_end - half, 0}, 1));
    join(run, point_joint(above, link, {0, upper_end, 0}));
    above = link;
  }
  const double bottom = top - 2 * half * links;
  const double rest_y = bottom - r;
  const int ball = run.add(sphere(r, {0, rest_y, 0}, 100));
  join(run, point_joint(above, ball, {0, bottom, 0}));
  double worst = 0;
  const int n = run.steps_for(options.quick ? 2.0 : 5.0);
  for (int i = 0; i < n; ++i) {
    run.step();
    worst = std::max(worst, rest_y - run.engine->state(ball).position[1]);
  }
  run.result.error = worst;
  run.result.failed = !(worst < 1.0);
  run.metric("final_stretch_m", rest_y - run.engine->state(ball).position[1]);
  return run.result;
}

// A 1 m, 1 kg arm (box half extents 0.5, 0.05, 0.05, its centre 0.5 m from
// the pivot) on a hinge about z at a static anchor, limited to -30..+45
// degrees, under gravity. Engine has no force input, so the arm starts
// turning at 20 rad/s toward the upper limit (it reaches it in 2 to 3
// steps at 60 Hz) instead of being driven by a torque. Error = the worst
// overshoot past either limit over 3 s, degrees.
ExperimentResult hinge_limit(const Variant& variant, const StepConfig& config, const RunOptions& options) {
  Run run(variant, config);
  const double lower = -30 * pi / 180, upper = 45 * pi / 180, omega = 20, half = 0.5;
  const V3 pivot{0, 2, 0};
  const int holder = run.add(anchor_body(pivot));
  BodySpec arm_spec = box({half, 0.05, 0.05}, {pivot[0] + half, pivot[1], pivot[2]}, 1);
  arm_spec.angular_velocity = {0, 0, omega};
  arm_spec.linear_velocity = {0, omega * half, 0};  // w x r at the centre
  const int arm = run.add(arm_spec);
  JointSpec hinge = point_joint(holder, arm, pivot);
  hinge.kind = JointKind::hinge;
  hinge.axis = {0, 0, 1};
  hinge.limited = true;
  hinge.lower = lower;
  hinge.upper = upper;
  join(run, hinge);
  double highest = 0, lowest = 0, worst_pivot = 0;
  const int n = run.steps_for(options.quick ? 1.0 : 3.0);
  for (int i = 0; i < n; ++i) {
    run.step();
    const BodyState s = run.engine->state(arm);
    const auto R = matrix(s.orientation);
    const double angle = std::atan2(R[1][0], R[0][0]);  // the arm's x axis about z
    highest = std::max(highest, angle);
    lowest = std::min(lowest, angle);
    const V3 end{s.position[0] - half * R[0][0], s.position[1] - half * R[1][0], s.position[2] - half * R[2][0]};
    worst_pivot = std::max(worst_pivot, length(sub(end, pivot)));
  }
  const double degrees = 180 / pi;
  run.result.error = std::max({0.0, highest - upper, lower - lowest}) * degrees;
  run.metric("max_angle_deg", highest * degrees);
  run.metric("min_angle_deg", lowest * degrees);
  run.metric("max_pivot_gap_m", worst_pivot);
  return run.result;
}

}  // namespace

const std::vector<Experiment>& experiments() {
  static const std::vector<Experiment> list = {
      {"free_fall", "accuracy", "abs(y - exact) after 2 s (m)", "free fall from rest, 2 s", true, free_fall},
      {"projectile", "accuracy", "distance to the exact point after 2 s (m)", "launched at 20 m/s, 45 degrees, 2 s",
       true, projectile},
      {"incline_hold", "accuracy", "drift (m)", "cube on a 30 degree slope, mu 0.6 > tan 30: must hold 5 s", true,
       incline_hold},
      {"incline_slide", "accuracy", "relative error of the distance slid",
       "30 degree slope, mu 0.4: a = g (sin - mu cos)", true, incline_slide},
      {"stop_distance", "accuracy", "relative error of the stop distance", "sliding at 5 m/s, mu 0.5: v0^2 / (2 mu g)",
       true, stop_distance},
      {"bounce", "accuracy", "relative error of the rebound height", "ball, restitution 0.5, from 1 m: rises e^2 h",
       true, bounce},
      {"tumbling", "accuracy", "relative drift of L or energy", "torque-free box spinning 20 s without gravity", true,
       tumbling},
      {"rolling_sphere", "accuracy", "relative error of the rolling speed",
       "ball sliding at 5 m/s, mu 0.3: rolls at 5/7 v0 after 2 v0 / (7 mu g)", true, rolling_sphere},
      {"stack20", "stability", "max drift (m)", "20 unit cubes", true, stack20},
      {"stack50", "stability", "max drift (m)", "50 unit cubes", false, stack50},
      {"pyramid20", "stability", "max drift (m)", "2D pyramid, 20 at the base (210 cubes)", false, pyramid20},
      {"jenga", "stability", "max drift (m)", "18 levels of 3 blocks", false, jenga},
      {"tables", "stability", "max drift (m)", "5 compound tables stacked", false, tables},
      {"wall64", "stability", "max drift (m)", "running-bond wall, 64 at the base (2,080 bricks)", false, wall64},
      {"wall128", "stability", "max drift (m)", "running-bond wall, 128 at the base (8,256 bricks)", false, wall128},
      {"light_under_heavy_100", "stability", "max penetration, last second (m)", "1 kg cube under 100 kg, 2 s", true,
       light_under_heavy_100},
      {"light_under_heavy_1000", "stability", "max penetration, last second (m)", "1 kg cube under 1,000 kg, 2 s", true,
       light_under_heavy_1000},
      {"heavy_on_light", "stability", "max penetration (m)", "1,000 kg cube dropped 1 m on a 1 kg cube", true,
       heavy_on_light},
      {"overlap_recovery", "stability", "time until every overlap < 1 cm (s)", "5 cubes starting 25% inside each other",
       true, overlap_recovery},
      {"thrown", "stability", "deepest corner below the ground (m)", "50 cubes thrown at the ground at 20 m/s", true,
       thrown},
      {"dice", "hulls", "largest tilt from face-down after 6 s (degrees)",
       "20 dice (hulls: 0.5 m cubes, corners cut 5 cm) thrown spinning at the ground", true, dice},
      {"mesh_slope", "meshes", "worst relative error of the distance slid in 1.5 s",
       "10 boxes sliding down a 20-degree slope of a height grid's 1,600 triangles as a mesh, mu 0.2", true,
       mesh_slope},
      {"heightfield_slope", "meshes", "worst relative error of the distance slid in 1.5 s",
       "mesh_slope's slope as a heightfield (Bullet: btHeightfieldTerrainShape)", true, heightfield_slope},
      {"character_stairs", "characters", "relative shortfall of the distance walked in 3 s",
       "a character walking 2 m/s for 3 s up five 0.2 m steps (step height 0.3 m; Bullet: "
       "btKinematicCharacterController)",
       false, character_stairs},
      {"heap_rest", "stability", "farthest move 30-40 s (m)", "heaps of 27 cubes dropped into a pen (quick: 2 of 24)",
       false, heap_rest},
      {"pendulum", "joints", "relative error of the period",
       "1 kg ball on a point joint 1 m below an anchor, from 5 degrees, 10 s (quick: 6 s)", true, pendulum},
      {"chain_stretch", "joints", "max stretch of the chain (m)",
       "25 links of 1 kg, 0.5 m, on point joints, 100 kg ball at the end, 5 s (quick: 2 s)", true, chain_stretch},
      {"hinge_limit", "joints", "max overshoot past a limit (degrees)",
       "1 m arm on a hinge limited to -30..45 degrees, started at 20 rad/s toward +45 (no force input), 3 s "
       "(quick: 1 s)",
       true, hinge_limit},
  };
  return list;
}

const Experiment* find_experiment(const std::string& name) {
  for (const Experiment& e : experiments()) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

std::string serialize(const ExperimentResult& r) {
  std::ostringstream out;
  out.precision(17);
  out << "error " << r.error << "\nfailed " << (r.failed ? 1 : 0) << "\nwall_ms " << r.wall_ms << "\nsimulated_s "
      << r.simulated_s << "\n";
  for (const auto& [name, value] : r.metrics) out << "metric " << name << " " << value << "\n";
  if (!r.columns.empty()) {
    out << "columns";
    for (const std::string& c : r.columns) out << " " << c;
    out << "\n";
  }
  for (const auto& row : r.rows) {
    out << "row";
    for (double v : row) out << " " << v;
    out << "\n";
  }
  return out.str();
}

bool parse_result(const std::string& text, ExperimentResult& r, std::string& reason) {
  r = {};
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  bool has_error = false;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    bool ok = true;
    if (key == "error") {
      ok = static_cast<bool>(fields >> r.error);
      has_error = ok;
    } else if (key == "failed") {
      int failed = 0;
      ok = static_cast<bool>(fields >> failed);
      r.failed = failed != 0;
    } else if (key == "wall_ms") {
      ok = static_cast<bool>(fields >> r.wall_ms);
    } else if (key == "simulated_s") {
      ok = static_cast<bool>(fields >> r.simulated_s);
    } else if (key == "metric") {
      std::string name;
      double value = 0;
      ok = static_cast<bool>(fields >> name >> value);
      r.metrics.emplace_back(name, value);
    } else if (key == "columns") {
      std::string c;
      while (fields >> c) r.columns.push_back(c);
    } else if (key == "row") {
      std::vector<double> row;
      double v = 0;
      while (fields >> v) row.push_back(v);
      ok = row.size() == r.columns.size();
      r.rows.push_back(row);
    } else {
      ok = false;
    }
    if (!ok) {
      reason = "line " + std::to_string(line_number) + ": cannot read '" + line + "'";
      return false;
    }
  }
  if (!has_error) reason = "no 'error' line";
  return has_error;
}

}  // namespace bitstep::bench
