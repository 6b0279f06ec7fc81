// Hulls and meshes in scenes and states: a hull's points and a mesh's
// arrays, the builders' refusals with their JSON paths, and worlds of hulls
// and meshes in motion saved and restored mid-tumble, continuing bit for bit.
#include <catch2/catch.hpp>
#include <string>

#include "core/convex_hull.h"
#include "core/triangle_mesh.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"

using namespace bitstep;

namespace {

std::string error_of(const std::string& text) {
  const auto result = parse_scene(text, "f.json");
  return result.ok() ? "no error" : result.error().message();
}

std::string hull_body(const std::string& points) {
  return R"({"format": "bitstep-scene", "version": 1, "bodies": [{"shapes": [{"type": "hull", "points": )" + points +
         "}]}]}";
}

const std::string cube_points = "[[-1,-1,-1],[1,-1,-1],[-1,1,-1],[1,1,-1],[-1,-1,1],[1,-1,1],[-1,1,1],[1,1,1]]";

// A shipped scene saved at step `saved_at` and restored into an empty
// world: its image round-trips and its chain matches the straight run's.
void continues_after_restore(const std::string& scene, int saved_at, int end) {
  World straight = test::world_of(scene);
  std::vector<uint8_t> image;
  std::vector<uint64_t> chain(static_cast<size_t>(end) + 1);
  for (int step = 1; step <= end; ++step) {
    straight.step();
    chain[static_cast<size_t>(step)] = state_hash(straight);
    if (step == saved_at) image = snapshot(straight);
  }
  World restored;
  REQUIRE(restore(image, restored).ok());
  CHECK(snapshot(restored) == image);
  for (int step = saved_at + 1; step <= end; ++step) {
    restored.step();
    REQUIRE(state_hash(restored) == chain[static_cast<size_t>(step)]);
  }
}

}  // namespace

TEST_CASE("hull scenes: points in, a hull with its mass out", "[scene][hull]") {
  const auto scene = parse_scene(hull_body(cube_points), "f.json");
  REQUIRE(scene.ok());
  const Shape& shape = scene.value().bodies[0].def.shapes[0];
  REQUIRE(shape.type == ShapeType::hull);
  CHECK(shape.hull->vertices.size() == 8);
  CHECK(shape.hull->faces.size() == 6);
  CHECK(shape.hull->volume == Fixed::from_int(8));
  // A point inside is not a corner.
  const auto inner = parse_scene(hull_body("[[0,0,0]," + cube_points.substr(1)), "f.json");
  REQUIRE(inner.ok());
  CHECK(inner.value().bodies[0].def.shapes[0].hull->vertices.size() == 8);
}

TEST_CASE("hull scenes: refused points name their place and the reason", "[scene][hull]") {
  CHECK(error_of(hull_body("[[0,0,0],[1,0,0],[0,1,0]]")) ==
        "f.json: $.bodies[0].shapes[0].points: 3 points: a hull needs 4 to 1024");
  CHECK(error_of(hull_body("[[0,0,0],[1,0,0],[0,1,0],[0,0,50.5]]")) ==
        "f.json: $.bodies[0].shapes[0].points[3].z: outside -50..50 m");
  CHECK(
      error_of(hull_body("[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]")).rfind("f.json: $.bodies[0].shapes[0].points: flat", 0) ==
      0);
  CHECK(error_of(hull_body("[[0,0,0],[1,0,0],[0,1,0],[0,0,true]]")) ==
        "f.json: $.bodies[0].shapes[0].points[3][2]: expected a number, got a boolean");
  CHECK(error_of(hull_body("\"cube\"")) ==
        "f.json: $.bodies[0].shapes[0].points: expected an array of points, got a string");
  CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "bodies": [{"shapes": [{"type": "hull"}]}]})") ==
        "f.json: $.bodies[0].shapes[0]: missing key \"points\"");
}

TEST_CASE("hull worlds: restored mid-tumble from a snapshot, the chain is the same", "[snapshot][hull]") {
  // Dice landing on the wedge, rocks in flight.
  continues_after_restore("dice.json", 45, 120);
}

TEST_CASE("mesh scenes: arrays in, triangles out, and refusals that name their place", "[scene][mesh]") {
  const auto mesh_body = [](const std::string& type, const std::string& vertices, const std::string& indices) {
    return R"({"format": "bitstep-scene", "version": 1, "bodies": [{"type": ")" + type +
           R"(", "shapes": [{"type": "mesh", "vertices": )" + vertices + R"(, "indices": )" + indices + "}]}]}";
  };
  const std::string square = "[[0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1]]";
  const auto scene = parse_scene(mesh_body("static", square, "[0, 2, 1, 1, 2, 3]"), "f.json");
  REQUIRE(scene.ok());
  CHECK(scene.value().bodies[0].def.shapes[0].mesh->triangles.size() == 2);
  CHECK(error_of(mesh_body("dynamic", square, "[0, 2, 1]")) ==
        "f.json: $.bodies[0].shapes[0].type: a mesh belongs to a static body");
  CHECK(error_of(mesh_body("static", square, "[0, 2, 7]")) ==
        "f.json: $.bodies[0].shapes[0].indices[2]: vertex 7 of 4");
  CHECK(error_of(mesh_body("static", square, "[0, 2]")) ==
        "f.json: $.bodies[0].shapes[0].indices: 2 indices, not a multiple of 3");
  CHECK(error_of(mesh_body("static", "[[0, 0, 0], [1, 0, 0], [0, 0, 17000]]", "[0, 2, 1]")) ==
        "f.json: $.bodies[0].shapes[0].vertices[2].z: outside -16000..16000 m");
  CHECK(error_of(mesh_body("static", "[[0, 0, 0], [1, 0, 0], [2, 0, 0]]", "[0, 2, 1]")) ==
        "f.json: $.bodies[0].shapes[0].indices (triangle 0): area below 1e-6 m^2");
  CHECK(error_of(mesh_body("static", square, "[0, 2, -1]")).rfind("f.json: $.bodies[0].shapes[0].indices[2]: ", 0) ==
        0);
}

TEST_CASE("mesh worlds: restored mid-slide from a snapshot, the chain is the same", "[snapshot][mesh]") {
  // Rocks rolling down the hill, crates in flight.
  continues_after_restore("terrain.json", 60, 120);
}

TEST_CASE("heightfield scenes: a grid in, its triangles out, and refusals that name their place",
          "[scene][heightfield]") {
  const auto field = [](const std::string& type, const std::string& fields) {
    return R"({"format": "bitstep-scene", "version": 1, "bodies": [{"type": ")" + type +
           R"(", "shapes": [{"type": "heightfield", )" + fields + "}]}]}";
  };
  const std::string sizes = R"("columns": 3, "rows": 2, "spacing": [1, 0.5], )";
  const auto scene =
      parse_scene(field("static", sizes + R"("heights": [0, 1, 0, 0, 1, 0], "holes": [[1, 0]])"), "f.json");
  REQUIRE(scene.ok());
  const Shape& shape = scene.value().bodies[0].def.shapes[0];
  CHECK(shape.type == ShapeType::heightfield);
  CHECK(shape.mesh->triangles.size() == 2);
  CHECK(shape.mesh->vertices[4] == Vec3{Fixed::one(), Fixed::one(), 0.5_fx});
  CHECK(error_of(field("dynamic", sizes + R"("heights": [0, 0, 0, 0, 0, 0])")) ==
        "f.json: $.bodies[0].shapes[0].type: a heightfield belongs to a static body");
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 0])")) ==
        "f.json: $.bodies[0].shapes[0].heights: 5 heights, not 3 x 2");
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 17000, 0])")) ==
        "f.json: $.bodies[0].shapes[0].heights[4]: outside +-16000 m");
  CHECK(error_of(field("static", R"("columns": 1, "rows": 2, "spacing": [1, 1], "heights": [0, 0])")) ==
        "f.json: $.bodies[0].shapes[0].columns: outside 2..4097");
  CHECK(error_of(field("static", R"("columns": 3, "rows": 2, "spacing": [0.001, 1], "heights": [0, 0, 0, 0, 0, 0])"))
            .rfind("f.json: $.bodies[0].shapes[0].spacing[0]: ", 0) == 0);
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 0, 0], "holes": [[0, 0], [2, 0]])")) ==
        "f.json: $.bodies[0].shapes[0].holes[1][0]: outside 0..1");
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 0, 0], "holes": [[1, 0], [1, 0]])")) ==
        "f.json: $.bodies[0].shapes[0].holes[1]: a cell listed twice");
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 0, 0], "holes": [[1, 0], [0, 0]])")) ==
        "f.json: $.bodies[0].shapes[0].holes: every cell a hole: no ground");
  CHECK(error_of(field("static", sizes + R"("heights": [0, 0, 0, 0, 0, 0], "slope": 3)"))
            .rfind("f.json: $.bodies[0].shapes[0].slope: unknown key", 0) == 0);
}

TEST_CASE("heightfield worlds: restored mid-drive from a snapshot, the chain is the same", "[snapshot][heightfield]") {
  // The car starting over the bumps, rocks tumbling off the hill, ragdolls falling onto the slope.
  continues_after_restore("hills.json", 40, 100);
}
