// `bitstep bench queries`: what a game's questions to the world cost.
//
// Method. A world of n bodies (n = 100, 1,000, 10,000: a third boxes, a
// third spheres, a third turned capsules, 0.2-1.2 m, at seeded random places
// in a 200 x 40 x 200 m region above a ground plane at -20 m) and 1,000 seeded
// random questions of each kind: rays of up to ~300 m from anywhere in the
// region (nearest hit, and every hit), sphere casts of 0.5 m the same way,
// and 10 m boxes for overlap_box. A sample times the whole set with
// std::chrono::steady_clock; the table shows the best of the samples (the
// run least disturbed by other processes), as microseconds per query, and
// the time to build the WorldQuery (its tree) once. Then the raycast car's
// cost: 600 steps of a 1,200 kg chassis on a ground box with and without
// its car (4 wheels of 1 and of 3 rays, driving), over 100 and 1,000 other
// bodies resting on the ground (the car's query tree covers them all).
// Then a level's terrain: a 225 x 225 heightfield 1 m apart (100,352
// triangles, seeded bumps up to 3 m), the time to build its mesh and tree,
// 1,000 rays straight down and 1,000 slanted ones, sphere and capsule
// casts, shape overlaps of a 0.5 m box resting on it, and the cost of a
// step of one character walking across it.
#include "tools/bench/queries.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "core/height_grid.h"
#include "core/query.h"
#include "fixed/splitmix64.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/options.h"

namespace bitstep {

namespace {

using Clock = std::chrono::steady_clock;

struct Region {
  SplitMix64 rng;
  // A raw value uniform in [-span/2, span/2) metres (span > 0).
  Fixed coordinate(int64_t span) {
    return Fixed::from_raw(static_cast<int64_t>(rng.next() % static_cast<uint64_t>(span << 32)) - (span << 31));
  }
  Vec3 point(int64_t x, int64_t y, int64_t z) { return {coordinate(x), coordinate(y), coordinate(z)}; }
};

World world_of(int n) {
  World world;
  BodyDef ground;
  ground.type = BodyType::static_body;
  ground.pose.position = {Fixed{}, Fixed::from_int(-20), Fixed{}};
  ground.shapes.push_back({ShapeType::plane, {}, {}, {}, {}});
  world.create_body(ground);
  Region region{SplitMix64{2026}};
  for (int i = 0; i < n; ++i) {
    BodyDef def;
    def.pose.position = region.point(200, 40, 200);
    const Fixed size = Fixed::from_ratio(1, 5) + Fixed::from_raw(static_cast<int64_t>(region.rng.next() % (uint64_t{1} << 32)));
    Shape shape;
    if (i % 3 == 0) {
      shape.type = ShapeType::box;
      shape.half_extents = {size, size / Fixed::from_int(2), size};
    } else if (i % 3 == 1) {
      shape.type = ShapeType::sphere;
      shape.radius = size;
    } else {
      shape.type = ShapeType::capsule;
      shape.radius = size / Fixed::from_int(2);
      shape.half_height = size;
      def.pose.orientation = normalize(Quat{Fixed::one(), Fixed::from_ratio(i % 7, 5), Fixed{}, Fixed::from_ratio(i % 5, 7)});
    }
    def.shapes.push_back(shape);
    world.create_body(def);
  }
  return world;
}

template <typename F>
double best_seconds(int samples, F&& work) {
  double best = 1e30;
  for (int s = 0; s < samples; ++s) {
    const auto start = Clock::now();
    work();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
  }
  return best;
}

// A ground box, `others` small boxes resting on it in a grid, and a chassis
// driving at full throttle, with a car of `rays` rays per wheel (0: no car).
World car_world(int others, int rays) {
  World world;
  BodyDef ground;
  ground.type = BodyType::static_body;
  ground.pose.position = {Fixed{}, -Fixed::one(), Fixed{}};
  ground.shapes.push_back({ShapeType::box, {Fixed::from_int(50), Fixed::one(), Fixed::from_int(50)}, {}, {}, {}});
  world.create_body(ground);
  for (int i = 0; i < others; ++i) {
    BodyDef box;
    box.pose.position = {Fixed::from_int(-45 + (i % 40) * 2), Fixed::from_ratio(1, 4), Fixed::from_int(5 + (i / 40) * 2)};
    const Fixed h = Fixed::from_ratio(1, 4);
    box.shapes.push_back({ShapeType::box, {h, h, h}, {}, {}, {}});
    box.asleep = false;
    world.create_body(box);
  }
  BodyDef chassis;
  chassis.pose.position = {Fixed{}, Fixed::from_ratio(9, 10), Fixed::from_int(-40)};
  chassis.mass = Fixed::from_int(1200);
  chassis.shapes.push_back({ShapeType::box, {Fixed::from_ratio(9, 10), Fixed::from_ratio(3, 10), Fixed::from_int(2)}, {}, {}, {}});
  const BodyId id = world.create_body(chassis).value();
  if (rays > 0) {
    CarDef def;
    def.chassis = id;
    def.rays_per_wheel = rays;
    for (int w = 0; w < 4; ++w) {
      const Fixed x = Fixed::from_ratio(w % 2 == 0 ? 4 : -4, 5), z = Fixed::from_ratio(w < 2 ? 7 : -7, 5);
      def.wheels.push_back({{x, -Fixed::from_ratio(3, 10), z}, w >= 2, w < 2});
    }
    const CarId car = world.create_car(def).value();  // a car the bench built to fit
    world.set_car_controls(car, {Fixed::from_ratio(1, 2), Fixed{}, Fixed{}});
  }
  return world;
}

// 225 x 225 samples 1 m apart: heights of two seeded sine ridges, 0..3 m.
HeightGrid terrain_grid() {
  HeightGrid g;
  g.columns = g.rows = 225;
  g.spacing_x = g.spacing_z = Fixed::one();
  SplitMix64 rng{11};
  const Fixed a = Fixed::from_raw(static_cast<int64_t>(rng.next() % (uint64_t{1} << 32)));
  for (uint32_t j = 0; j < g.rows; ++j) {
    for (uint32_t i = 0; i < g.columns; ++i) {
      const Fixed x = Fixed::from_ratio(static_cast<int64_t>(i), 9), z = Fixed::from_ratio(static_cast<int64_t>(j), 13);
      g.heights.push_back(Fixed::from_ratio(3, 4) * (sin(x + a) + sin(z) + Fixed::from_int(2)));
    }
  }
  return g;
}

void terrain_queries(int samples) {
  constexpr size_t questions = 1000;
  std::shared_ptr<const TriangleMesh> mesh;
  const double build_mesh = best_seconds(samples, [&] { mesh = build_height_grid_mesh(terrain_grid()).value(); });
  World world;
  BodyDef def;
  def.type = BodyType::static_body;
  def.pose.position = {Fixed::from_int(-112), Fixed{}, Fixed::from_int(-112)};
  Shape field;
  field.type = ShapeType::heightfield;
  field.mesh = mesh;
  def.shapes.push_back(field);
  world.create_body(def);
  Region region{SplitMix64{5}};
  std::vector<Vec3> above, slanted_from, slanted;
  for (size_t q = 0; q < questions; ++q) {
    const Fixed x = region.coordinate(220), z = region.coordinate(220);
    above.push_back({x, Fixed::from_int(20), z});
    slanted_from.push_back({x, Fixed::from_int(10), z});
    slanted.push_back({region.coordinate(60), -Fixed::from_int(12), region.coordinate(60)});
  }
  const WorldQuery query(world);
  const Vec3 down{Fixed{}, -Fixed::from_int(40), Fixed{}};
  int met = 0;
  const double straight = best_seconds(samples, [&] {
    met = 0;
    for (size_t q = 0; q < questions; ++q) met += query.cast_ray(above[q], down) ? 1 : 0;
  });
  const double oblique = best_seconds(samples, [&] {
    for (size_t q = 0; q < questions; ++q) (void)query.cast_ray(slanted_from[q], slanted[q]);
  });
  const double sphere = best_seconds(samples, [&] {
    for (size_t q = 0; q < questions; ++q) (void)query.cast_sphere(Fixed::from_ratio(1, 2), above[q], down);
  });
  const Shape capsule{ShapeType::capsule, {}, Fixed::from_ratio(3, 10), Fixed::from_ratio(3, 5), {}};
  const double capsule_cast = best_seconds(samples, [&] {
    for (size_t q = 0; q < questions; ++q) (void)query.cast_shape(capsule, {above[q], {}}, down);
  });
  const Fixed half = Fixed::from_ratio(1, 2);
  const Shape box{ShapeType::box, {half, half, half}, {}, {}, {}};
  std::vector<ShapeOverlap> overlaps;
  std::vector<Pose> resting;
  for (size_t q = 0; q < questions; ++q) {
    const auto hit = query.cast_ray(above[q], down);
    resting.push_back({hit ? hit->point : above[q], {}});
  }
  const double overlap = best_seconds(samples, [&] {
    for (size_t q = 0; q < questions; ++q) query.overlap_shape(box, resting[q], overlaps);
  });
  // One character walking 3 m/s across the ridges for 600 steps.
  constexpr int steps = 600;
  double walked = 0;
  const double character_step =
      best_seconds(samples,
                   [&] {
                     World walk;
                     walk.create_body(def);
                     CharacterDef hero;
                     hero.position = {Fixed::from_int(-100), Fixed::from_int(6), Fixed::from_int(-90)};
                     const CharacterId id = walk.create_character(hero).value();
                     walk.set_character_controls(id, {{Fixed::from_int(3), Fixed{}, Fixed::one()}, false});
                     for (int s = 0; s < steps; ++s) walk.step();
                     walked =
                         static_cast<double>((walk.characters()[0].position.x + Fixed::from_int(100)).raw()) * 0x1p-32;
                   }) /
      steps;
  const double us = 1e6 / questions;
  fmt::print(
      "\n| terrain | build (ms) | ray down (us) | slanted ray (us) | sphere cast 0.5 m (us) | "
      "capsule cast 0.3 x 1.2 m (us) | box overlap (us) | a character's step (us) | rays meeting it |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  fmt::print(
      "| heightfield 225 x 225, {} triangles | {:.1f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.1f} "
      "(walked {:.1f} m in x) | {} of {} |\n",
      mesh->triangles.size(), build_mesh * 1e3, straight * us, oblique * us, sphere * us, capsule_cast * us,
      overlap * us, character_step * 1e6, walked, met, questions);
}

}  // namespace

int run_bench_queries(int argc, char** argv) {
  int samples = 5;
  CLI::App app("us per ray, shape cast and overlap over 100 to 10,000 bodies", "bitstep bench queries");
  app.add_flag_callback("--quick", [&samples] { samples = 2; }, "fewer samples");
  if (const std::optional<int> code = cli::parse(app, "bench queries", argc, argv)) return *code;
  constexpr size_t questions = 1000;
  fmt::print("| bodies | build the query (us) | ray, nearest (us) | ray, every hit (us) | sphere cast 0.5 m (us) | "
             "capsule cast 0.3 x 1.2 m (us) | box cast 0.5 m (us) | overlap_box 10 m (us) | rays meeting something |\n"
             "|---|---|---|---|---|---|---|---|---|\n");
  const Shape capsule{ShapeType::capsule, {}, Fixed::from_ratio(3, 10), Fixed::from_ratio(3, 10), {}};
  const Fixed half = Fixed::from_ratio(1, 2);
  const Shape box{ShapeType::box, {half, half, half}, {}, {}, {}};
  for (const int n : {100, 1000, 10000}) {
    const World world = world_of(n);
    Region region{SplitMix64{7}};
    std::vector<Vec3> origins, translations;
    std::vector<Aabb> boxes;
    for (size_t q = 0; q < questions; ++q) {
      origins.push_back(region.point(240, 60, 240));
      translations.push_back(region.point(300, 60, 300));
      const Vec3 c = region.point(200, 40, 200), h{Fixed::from_int(5), Fixed::from_int(5), Fixed::from_int(5)};
      boxes.push_back({c - h, c + h});
    }
    double build = best_seconds(samples, [&] { const WorldQuery query(world); });
    const WorldQuery query(world);
    int met = 0;
    std::vector<QueryHit> hits;
    std::vector<BodyId> bodies;
    const double nearest = best_seconds(samples, [&] {
      met = 0;
      for (size_t q = 0; q < questions; ++q) met += query.cast_ray(origins[q], translations[q]) ? 1 : 0;
    });
    const double every = best_seconds(samples, [&] {
      for (size_t q = 0; q < questions; ++q) query.cast_ray_all(origins[q], translations[q], hits);
    });
    const double sphere = best_seconds(samples, [&] {
      for (size_t q = 0; q < questions; ++q) (void)query.cast_sphere(Fixed::from_ratio(1, 2), origins[q], translations[q]);
    });
    const auto shape_cast = [&](const Shape& shape) {
      return best_seconds(samples, [&] {
        for (size_t q = 0; q < questions; ++q) (void)query.cast_shape(shape, {origins[q], {}}, translations[q]);
      });
    };
    const double capsule_cast = shape_cast(capsule), box_cast = shape_cast(box);
    const double overlap = best_seconds(samples, [&] {
      for (size_t q = 0; q < questions; ++q) query.overlap_box(boxes[q], bodies);
    });
    const double us = 1e6 / questions;
    fmt::print("| {} | {:.0f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {} of {} |\n", n, build * 1e6,
               nearest * us, every * us, sphere * us, capsule_cast * us, box_cast * us, overlap * us, met, questions);
  }
  fmt::print("\n| other bodies | step without a car (us) | with a car, 1 ray per wheel (us) | 3 rays per wheel (us) |\n"
             "|---|---|---|---|\n");
  constexpr int steps = 600;
  for (const int others : {100, 1000}) {
    double per_step[3];
    for (int rays = 0; rays <= 2; ++rays) {
      per_step[rays] = best_seconds(samples, [&] {
        World world = car_world(others, rays == 2 ? 3 : rays);
        for (int s = 0; s < steps; ++s) world.step();
      }) / steps;
    }
    fmt::print("| {} | {:.1f} | {:.1f} | {:.1f} |\n", others, per_step[0] * 1e6, per_step[1] * 1e6, per_step[2] * 1e6);
  }
  terrain_queries(samples);
  return 0;
}

}  // namespace bitstep
