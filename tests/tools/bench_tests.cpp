// tests/tools mirrors tools/: the benchmark's statistics and its experiments
// run on bitstep through the engine interface.
#include <catch2/catch.hpp>

#include <cmath>

#include "tools/bench/bitstep_engine.h"
#include "tools/bench/costs.h"
#include "tools/bench/experiments.h"
#include "tools/bench/speed.h"
#include "tools/bench/stats.h"

namespace bitstep::bench {

namespace {

const std::string scenes_dir = std::string(BITSTEP_SOURCE_DIR) + "/scenes";

ExperimentResult run(const std::string& experiment, const std::string& variant, double dt = 1.0 / 60,
                     int iterations = 10) {
  StepConfig config;
  config.dt = dt;
  config.iterations = iterations;
  RunOptions options;
  options.quick = true;
  // Assigned from a std::string, not a literal: GCC 12 at -O3 warns,
  // falsely (-Warray-bounds), when a literal of exactly 15 characters (the
  // short-string buffer) is assigned, and a clone in a folder of 8
  // characters made this one 15 long.
  options.scenes_dir = scenes_dir;
  for (const Variant& v : bitstep_variants()) {
    if (v.name == variant) return find_experiment(experiment)->run(v, config, options);
  }
  FAIL("no variant " << variant);
  return {};
}

double metric(const ExperimentResult& r, const std::string& name) {
  for (const auto& [key, value] : r.metrics) {
    if (key == name) return value;
  }
  FAIL("no metric " << name);
  return 0;
}

}  // namespace

TEST_CASE("pareto_front keeps exactly the points nothing beats in both cost and error", "[bench]") {
  // (cost, error): b beats a; c and b trade off; d duplicates c; e is beaten by c.
  const std::vector<CostError> points{{2, 5}, {1, 4}, {3, 1}, {3, 1}, {4, 1}};
  const std::vector<bool> front = pareto_front(points);
  CHECK(front == std::vector<bool>{false, true, true, false, false});
}

TEST_CASE("fit_power_law recovers the exponent of exact power laws", "[bench]") {
  const std::vector<double> x{100, 300, 1000, 3000, 10000};
  std::vector<double> linear, quadratic;
  for (double n : x) {
    linear.push_back(0.02 * n);
    quadratic.push_back(3e-6 * n * n);
  }
  CHECK(fit_power_law(x, linear).exponent == Approx(1.0).margin(1e-12));
  CHECK(fit_power_law(x, quadratic).exponent == Approx(2.0).margin(1e-12));
  CHECK(fit_power_law(x, quadratic).coefficient == Approx(3e-6).epsilon(1e-9));
  CHECK_FALSE(fit_power_law({5, 5}, {1, 2}).ok);
}

TEST_CASE("the speed table reports medians of the rounds and their ratio", "[bench]") {
  CHECK(median({3, 1, 2}) == 2);
  CHECK(median({4, 1, 3, 2}) == 2.5);
  SpeedRow row{{"stack20.json", "standing", 60, 240}, {3, 1, 2}, {1, 2, 0.5}, {4, 3, 5}, {2, 2.5, 3}, 3.6e6, 1.2e6};
  const std::string md = speed_section({row}, "standard+shock", 2);
  // Wall clock: 4 ms on one thread, 2.5 on two (medians): 1.60x.
  // Instructions per step: 3.6M against 1.2M, 3.00x.
  CHECK(md.find("| stack20.json | standing | 60-300 | 2 | 1 | 2.00x | 3.6M / 1.2M (3.00x) | 2.5 | 1.60x |") !=
        std::string::npos);
  CHECK(md.find("median of 3 alternating rounds") != std::string::npos);
  CHECK(speed_csv({row}, 2).find("stack20.json,standing,60,240,3,2,0.5,5,3,3600000,1200000\n") != std::string::npos);
  // Not counted (no valgrind): a dash, and zeros in the CSV.
  row.bitstep_instructions = row.bullet_instructions = 0;
  CHECK(speed_section({row}, "standard+shock", 2).find("| 2.00x | - | 2.5 |") != std::string::npos);
}

TEST_CASE("the speed section times the steps after the warm-up, in CPU and wall-clock time", "[bench]") {
  for (const Variant& v : bitstep_variants()) {
    if (v.name != "standard+shock") continue;
    StepConfig two_workers;
    two_workers.threads = 2;
    auto engine = v.make(two_workers);
    BodySpec ball;
    ball.shapes.push_back({ShapeKind::sphere, {}, 0.5});
    ball.position = {0, 10, 0};
    ball.mass = 1;
    engine->add_body(ball);
    const StepTimes ms = ms_per_step(*engine, 30, 30);
    CHECK((std::isfinite(ms.cpu) && std::isfinite(ms.wall) && ms.cpu >= 0 && ms.wall > 0));
    // 60 steps of free fall: the warm-up steps ran too (y = 10 - g t^2 / 2 at t = 1 s).
    CHECK(std::abs(engine->state(0).position[1] - (10 - 9.81 / 2)) < 1e-3);
  }
}

TEST_CASE("an experiment result survives its text form", "[bench]") {
  ExperimentResult r;
  r.error = 0.1 + 1e-17;
  r.failed = true;
  r.wall_ms = 12.5;
  r.simulated_s = 2.0 / 3.0;
  r.metrics = {{"a", -1.25e-300}, {"b", 7}};
  r.columns = {"t_s", "x"};
  r.rows = {{0.5, 1e-9}, {1.0, 2.0}};
  ExperimentResult back;
  std::string reason;
  REQUIRE(parse_result(serialize(r), back, reason));
  CHECK(back.error == r.error);
  CHECK(back.failed);
  CHECK(back.simulated_s == r.simulated_s);
  CHECK(back.metrics == r.metrics);
  CHECK(back.columns == r.columns);
  CHECK(back.rows == r.rows);
  CHECK_FALSE(parse_result("error 1\nrow 1 2\n", back, reason));  // a row without columns
  CHECK_FALSE(parse_result("failed 0\n", back, reason));          // no error line
}

TEST_CASE("bench accuracy on bitstep: free flight, sliding, rolling and bouncing against the analytic answers",
          "[bench][physics]") {
  // Free flight moves by the mean of the step's velocities: the exact
  // parabola, up to the rounding of dt to Q32.32 (t is off by ~1e-8 s).
  CHECK(run("free_fall", "standard+shock").error < 1e-6);
  CHECK(run("projectile", "standard+shock").error < 1e-6);
  CHECK(run("incline_hold", "standard+shock").error < 1e-3);
  CHECK(run("incline_slide", "standard+shock").error < 0.02);
  CHECK(run("stop_distance", "standard+shock").error < 0.02);
  CHECK(run("bounce", "standard+shock").error < 0.02);
  // Rolling: 5/7 v0 once the slip ends, within 1%; the slip ends within two
  // steps of 2 v0 / (7 mu g).
  const ExperimentResult rolling = run("rolling_sphere", "standard+shock");
  CHECK(rolling.error < 0.01);
  CHECK(std::abs(metric(rolling, "slip_end_s") - metric(rolling, "slip_end_exact_s")) < 2.0 / 60);
  // guendelman finds contacts at the predicted poses; their points must be
  // moved back with the ball or the lever v dt brakes it (was 0.61 x 5/7 v0).
  const ExperimentResult predicted = run("rolling_sphere", "guendelman+shock");
  CHECK(predicted.error < 0.01);
  CHECK(std::abs(metric(predicted, "slip_end_s") - metric(predicted, "slip_end_exact_s")) < 2.0 / 60);
}

TEST_CASE("bench tumbling box: angular momentum and energy drift shrink with the step (implicit gyroscopic term)",
          "[bench][physics]") {
  // Without the gyroscopic term w stays constant and L = R I R^T w turned
  // with the body: 15% in 20 s. The implicit step keeps L within ~1% at
  // 60 Hz (5 s here) and shrinks with dt; it loses a little energy.
  const ExperimentResult at60 = run("tumbling", "standard+shock");
  const ExperimentResult at240 = run("tumbling", "standard+shock", 1.0 / 240);
  CHECK(metric(at60, "momentum_drift") < 0.02);
  CHECK(metric(at60, "energy_drift") < 0.02);
  CHECK(metric(at240, "momentum_drift") < metric(at60, "momentum_drift") / 2);
  CHECK(metric(at240, "energy_drift") < metric(at60, "energy_drift") / 2);
}

TEST_CASE("bench stability on bitstep: stack20 stands with the shock step and falls without it at 1 iteration",
          "[bench][physics]") {
  CHECK(run("stack20", "standard+shock").error < 0.01);
  CHECK_FALSE(run("stack20", "standard+shock").failed);
  CHECK(run("stack20", "standard", 1.0 / 60, 1).failed);
}

// The costs section's rollback: the snapshot restores the world each round
// and the 8 re-simulated frames end on one state hash; the thrown cubes are
// still moving at step 30, so a restore that missed anything would show.
TEST_CASE("bench rollback: every restore and 8 steps of thrown ends on the same bits", "[bench]") {
  const RollbackRow row = measure_rollback(scenes_dir, "thrown.json", 30, 3);
  CHECK(row.same_bits);
  CHECK(row.rounds == 3);
  CHECK(row.snapshot_bytes > 50 * 530);  // 50 cubes, each more than its ~530 bytes at rest
  CHECK(row.rollback_ms > row.restore_ms);
  CHECK_THROWS_WITH(measure_rollback(scenes_dir, "missing.json", 0, 1),
                    Catch::Contains("missing.json"));
}

}  // namespace bitstep::bench
