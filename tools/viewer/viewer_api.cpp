// The browser viewer's engine: bitstep compiled to WebAssembly
// (tools/wasm/CMakeLists.txt) behind a small C interface that viewer.js
// calls through emscripten's ccall. The same fixed/, core/ and replay/ as
// the native build, so a replay re-simulated here checks its recorded hash
// chain step by step, as `bitstep verify` does.
//
// Two players, 0 and 1: the replay shown, and another to compare with it.
// Each is a world, the replay's inputs and recorded chain, the chain
// computed so far, and a snapshot every `keyframe_every` steps so that a
// seek backwards restores one and steps forward from it. Files (scenes and
// replays) are read from emscripten's in-memory file system, where the page
// writes what it fetched or the user picked.
//
// Floats appear only in what is handed to the page for drawing (poses,
// contacts, joint anchors); a click reaches the world as an input parsed
// from decimal text, as a replay file's inputs are, so the replay the page
// offers for download verifies natively.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/convex_hull.h"
#include "core/query.h"
#include "core/triangle_mesh.h"
#include "fixed/decimal.h"
#include "replay/render_pose.h"
#include "replay/replay.h"
#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"

#if defined(__EMSCRIPTEN__)
#include <emscripten/emscripten.h>
#define VIEWER_EXPORT extern "C" EMSCRIPTEN_KEEPALIVE
#else
#define VIEWER_EXPORT extern "C"
#endif

namespace {

using namespace bitstep;

constexpr int64_t keyframe_every = 30;

struct Keyframe {
  int64_t tick;
  std::vector<uint8_t> image;
  InputRun run;
};

struct Player {
  bool loaded = false;
  Replay replay;  // scene, inputs and the recorded chain (empty for a scene played live)
  std::unique_ptr<World> world;
  std::optional<InputRun> run;
  std::vector<uint64_t> computed;  // the state hash after each step computed so far
  int64_t diverged_at = 0;         // the first step whose hash differs from the recorded one
  uint64_t start_hash = 0;         // the state hash of the world before step 1
  std::vector<Keyframe> keyframes;
  std::vector<uint32_t> first_generation;  // per scene body: its slot's generation when built
  std::vector<float> floats;               // the last buffer handed out
  std::string text;                        // the last string handed out
};

Player players[2];
std::string last_error;

Player* player(int v) { return v == 0 || v == 1 ? &players[v] : nullptr; }

std::string hex(uint64_t h) {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

float to_float(Fixed value) { return static_cast<float>(static_cast<double>(value.raw()) / 4294967296.0); }

void keyframe(Player& p) {
  const int64_t tick = static_cast<int64_t>(p.world->step_count());
  if (!p.keyframes.empty() && p.keyframes.back().tick >= tick) return;
  p.keyframes.push_back({tick, snapshot(*p.world), *p.run});
}

// Builds player `v` from a replay read (or a scene wrapped as one).
int start(Player& p, Replay replay) {
  auto world = std::make_unique<World>(replay.scene.settings);
  if (const Result<void> built = build_world(replay.scene, *world); !built.ok()) {
    last_error = built.error().message();
    return 1;
  }
  p = Player{};
  p.replay = std::move(replay);
  p.world = std::move(world);
  p.run.emplace(*p.world);
  p.start_hash = state_hash(*p.world);
  for (size_t i = 0; i < p.replay.scene.bodies.size(); ++i) p.first_generation.push_back(p.world->bodies()[i].generation);
  p.loaded = true;
  keyframe(p);
  return 0;
}

// One step: the step's inputs, the step, its hash against the recorded one.
// 1: the recorded hash, 0: another (the first such step is kept), 2: past
// the recorded chain (a scene played live, or after a click).
int step_once(Player& p) {
  const int64_t next = static_cast<int64_t>(p.world->step_count()) + 1;
  apply_inputs(*p.world, p.replay.inputs, next, *p.run);
  p.world->step();
  const uint64_t h = state_hash(*p.world);
  if (static_cast<int64_t>(p.computed.size()) < next) {
    p.computed.push_back(h);
  } else {
    p.computed[static_cast<size_t>(next - 1)] = h;
  }
  if (next % keyframe_every == 0) keyframe(p);
  if (next > static_cast<int64_t>(p.replay.hashes.size())) return 2;
  if (p.replay.hashes[static_cast<size_t>(next - 1)] == h) return 1;
  if (p.diverged_at == 0 || next < p.diverged_at) p.diverged_at = next;
  return 0;
}

std::string name_of(const Player& p, uint32_t slot) {
  if (slot < p.first_generation.size() && p.world->bodies()[slot].generation == p.first_generation[slot]) {
    return p.replay.scene.bodies[slot].name;
  }
  return "slot " + std::to_string(slot);
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

std::string floats_json(std::initializer_list<float> values) {
  std::string out = "[";
  for (const float f : values) {
    char number[32];
    std::snprintf(number, sizeof number, "%.6g", static_cast<double>(f));
    out += (out.size() > 1 ? "," : "") + std::string(number);
  }
  return out + "]";
}

// Points as one flat array [x, y, z, x, y, z, ...] (m).
std::string vertices_json(const std::vector<Vec3>& points) {
  std::string out = "[";
  for (const Vec3& v : points) {
    const std::string xyz = floats_json({to_float(v.x), to_float(v.y), to_float(v.z)});
    out += (out.size() > 1 ? "," : "") + xyz.substr(1, xyz.size() - 2);
  }
  return out + "]";
}

// A hull's corners ([x, y, z, x, y, z, ...], m, the shape's frame) and its
// faces' loops of corner indices (counter-clockwise seen from outside), as
// the keys that follow a shape's others.
std::string hull_json(const ConvexHull& hull) {
  std::string faces;
  for (const ConvexHull::Face& face : hull.faces) {
    std::string loop;
    for (uint16_t i = 0; i < face.count; ++i) {
      loop += (i == 0 ? "" : ",") + std::to_string(hull.face_vertices[face.first + i]);
    }
    faces += (faces.empty() ? "[" : ",[") + loop + "]";
  }
  return ",\"vertices\":" + vertices_json(hull.vertices) + ",\"faces\":[" + faces + "]";
}

// A mesh's vertices and its triangles as three-corner faces, in the keys
// hull_json gives.
std::string mesh_json(const TriangleMesh& mesh) {
  std::string faces;
  for (const TriangleMesh::Triangle& t : mesh.triangles) {
    faces += std::string(faces.empty() ? "[" : ",[") + std::to_string(t.corners[0]) + "," +
             std::to_string(t.corners[1]) + "," + std::to_string(t.corners[2]) + "]";
  }
  return ",\"vertices\":" + vertices_json(mesh.vertices) + ",\"faces\":[" + faces + "]";
}

const char* shape_type(ShapeType type) { return shape_type_names[static_cast<size_t>(type)]; }

const char* body_type(BodyType type) {
  switch (type) {
    case BodyType::static_body: return "static";
    case BodyType::kinematic: return "kinematic";
    case BodyType::dynamic: return "dynamic";
  }
  return "unknown";
}

}  // namespace

// The one-line reason of the last failed call.
VIEWER_EXPORT const char* bv_error() { return last_error.c_str(); }

// Loads a replay file (its scene beside it, or inside it) into player v.
// 0, or 1 with bv_error().
VIEWER_EXPORT int bv_load_replay(int v, const char* path) {
  Player* p = player(v);
  if (p == nullptr) return 1;
  Result<Replay> loaded = load_replay_file(path, false);
  if (!loaded.ok()) {
    last_error = loaded.error().message();
    return 1;
  }
  return start(*p, std::move(loaded).value());
}

// Loads a scene file into player v, played live: no recorded chain.
VIEWER_EXPORT int bv_load_scene(int v, const char* path) {
  Player* p = player(v);
  if (p == nullptr) return 1;
  Result<Scene> loaded = load_scene_file(path);
  if (!loaded.ok()) {
    last_error = loaded.error().message();
    return 1;
  }
  Replay replay;
  replay.scene = std::move(loaded).value();
  const std::string file = path;
  replay.scene_file = file.substr(file.find_last_of('/') + 1);  // the download sits beside the scene
  return start(*p, std::move(replay));
}

VIEWER_EXPORT void bv_unload(int v) {
  if (Player* p = player(v)) *p = Player{};
}
VIEWER_EXPORT int bv_loaded(int v) { return player(v) != nullptr && player(v)->loaded ? 1 : 0; }
// The recorded chain's length: the replay's steps (0 for a scene).
VIEWER_EXPORT int bv_recorded_steps(int v) {
  const Player* p = player(v);
  return p != nullptr && p->loaded ? static_cast<int>(p->replay.hashes.size()) : 0;
}
VIEWER_EXPORT int bv_tick(int v) {
  const Player* p = player(v);
  return p != nullptr && p->loaded ? static_cast<int>(p->world->step_count()) : 0;
}
VIEWER_EXPORT int bv_step(int v) {
  Player* p = player(v);
  return p != nullptr && p->loaded ? step_once(*p) : -1;
}
VIEWER_EXPORT int bv_diverged_at(int v) {
  const Player* p = player(v);
  return p != nullptr && p->loaded ? static_cast<int>(p->diverged_at) : 0;
}
VIEWER_EXPORT int bv_scene_matches(int v) {
  const Player* p = player(v);
  return p != nullptr && p->loaded && (p->replay.hashes.empty() || p->start_hash == p->replay.scene_hash) ? 1 : 0;
}

// The state hash now (16 hex digits), and the recorded hash after `step`
// ("" past the chain).
VIEWER_EXPORT const char* bv_hash(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return "";
  p->text = hex(state_hash(*p->world));
  return p->text.c_str();
}
VIEWER_EXPORT const char* bv_recorded_hash(int v, int step) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded || step < 1 || step > static_cast<int>(p->replay.hashes.size())) return "";
  p->text = hex(p->replay.hashes[static_cast<size_t>(step - 1)]);
  return p->text.c_str();
}

// To step `tick`: restores the last keyframe at or before it and steps
// forward (a keyframe is taken every 30 steps as they are first computed).
// Returns 0 when every step taken matched its recorded hash (or had none).
VIEWER_EXPORT int bv_seek(int v, int tick) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded || tick < 0) return -1;
  const int64_t now = static_cast<int64_t>(p->world->step_count());
  // The last keyframe at or before `tick` (they are in step order; the
  // first is step 0): restored when going back, or when it is ahead of now.
  auto best = p->keyframes.rbegin();
  while (best->tick > tick) ++best;
  if (tick < now || best->tick > now) {
    if (const Result<void> restored = restore(best->image, *p->world); !restored.ok()) {
      last_error = restored.error().within("keyframe at step " + std::to_string(best->tick)).message();
      return -1;
    }
    *p->run = best->run;
  }
  int mismatches = 0;
  while (static_cast<int64_t>(p->world->step_count()) < tick) mismatches += step_once(*p) == 0 ? 1 : 0;
  return mismatches;
}

// The number of floats in player v's last buffer (bv_poses, bv_contacts,
// bv_joints).
VIEWER_EXPORT int bv_float_count(int v) {
  const Player* p = player(v);
  return p != nullptr ? static_cast<int>(p->floats.size()) : 0;
}

// Per body slot, 9 floats: flags (1 alive, 2 asleep, 4 dynamic, 8
// kinematic), the slot's generation, position x y z (m) and orientation
// x y z w. Valid until the next call.
VIEWER_EXPORT const float* bv_poses(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return nullptr;
  p->floats.clear();
  for (const Body& body : p->world->bodies()) {
    const RenderPose pose = render_pose(body.pose);
    const int flags = (body.alive ? 1 : 0) | (body.asleep ? 2 : 0) | (body.type == BodyType::dynamic ? 4 : 0) |
                      (body.type == BodyType::kinematic ? 8 : 0);
    p->floats.insert(p->floats.end(), {static_cast<float>(flags), static_cast<float>(body.generation),
                                       pose.position[0], pose.position[1], pose.position[2], pose.orientation[0],
                                       pose.orientation[1], pose.orientation[2], pose.orientation[3]});
  }
  return p->floats.data();
}

// Every live body's name, type and shapes (in the body frame, whose origin
// is the centre of mass) as JSON: [{"slot", "generation", "name", "type",
// "shapes": [{"type", "half_extents", "radius", "half_height", "position",
// "orientation", and a hull's or mesh's "vertices" and "faces"}]}].
VIEWER_EXPORT const char* bv_shapes(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return "[]";
  std::string out = "[";
  const std::vector<Body>& bodies = p->world->bodies();
  for (uint32_t slot = 0; slot < bodies.size(); ++slot) {
    const Body& body = bodies[slot];
    if (!body.alive) continue;
    if (out.size() > 1) out += ",\n";
    out += "{\"slot\":" + std::to_string(slot) + ",\"generation\":" + std::to_string(body.generation) +
           ",\"name\":" + json_string(name_of(*p, slot)) + ",\"type\":\"" + body_type(body.type) +
           "\",\"shapes\":[";
    for (size_t i = 0; i < body.shapes.size(); ++i) {
      const Shape& s = body.shapes[i];
      const RenderPose local = render_pose(s.local);
      out += std::string(i == 0 ? "" : ",") + "{\"type\":\"" + shape_type(s.type) + "\",\"half_extents\":" +
             floats_json({to_float(s.half_extents.x), to_float(s.half_extents.y), to_float(s.half_extents.z)}) +
             ",\"radius\":" + floats_json({to_float(s.radius)}) +
             ",\"half_height\":" + floats_json({to_float(s.half_height)}) +
             ",\"position\":" + floats_json({local.position[0], local.position[1], local.position[2]}) +
             ",\"orientation\":" +
             floats_json({local.orientation[0], local.orientation[1], local.orientation[2], local.orientation[3]}) +
             (s.type == ShapeType::hull ? hull_json(*s.hull) : std::string()) +
             (has_triangles(s.type) ? mesh_json(*s.mesh) : std::string()) + "}";
    }
    out += "]}";
  }
  p->text = out + "]";
  return p->text.c_str();
}

// The contact points: 6 floats each, the point (m) and the manifold's unit
// normal.
VIEWER_EXPORT const float* bv_contacts(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return nullptr;
  p->floats.clear();
  for (const Contact& c : p->world->contacts()) {
    const Manifold& m = c.manifold;
    for (int i = 0; i < m.point_count; ++i) {
      const Vec3& at = m.points[static_cast<size_t>(i)].position;
      p->floats.insert(p->floats.end(), {to_float(at.x), to_float(at.y), to_float(at.z), to_float(m.normal.x),
                                         to_float(m.normal.y), to_float(m.normal.z)});
    }
  }
  return p->floats.data();
}

// Per character slot, 9 floats: 1 when alive (else 0), its ground state
// (0 on_ground, 1 on_steep_slope, 2 in_air), its capsule's centre x y z
// (m), radius and half_height (m), and its facing's x and z.
VIEWER_EXPORT const float* bv_characters(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return nullptr;
  p->floats.clear();
  for (const Character& c : p->world->characters()) {
    p->floats.insert(p->floats.end(), {c.alive ? 1.0f : 0.0f, static_cast<float>(c.ground), to_float(c.position.x),
                                       to_float(c.position.y), to_float(c.position.z), to_float(c.def.radius),
                                       to_float(c.def.half_height), to_float(c.facing.x), to_float(c.facing.z)});
  }
  return p->floats.data();
}

// The live joints: 6 floats each, the two anchors in the world (m).
VIEWER_EXPORT const float* bv_joints(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return nullptr;
  p->floats.clear();
  for (const Joint& joint : p->world->joints()) {
    if (!joint.alive) continue;
    const Body& a = p->world->bodies()[joint.body_a];
    const Body& b = p->world->bodies()[joint.body_b];
    const Vec3 wa = a.pose.position + rotate(a.pose.orientation, joint.local_anchor_a);
    const Vec3 wb = b.pose.position + rotate(b.pose.orientation, joint.local_anchor_b);
    p->floats.insert(p->floats.end(),
                     {to_float(wa.x), to_float(wa.y), to_float(wa.z), to_float(wb.x), to_float(wb.y), to_float(wb.z)});
  }
  return p->floats.data();
}

// A click: the ray from `origin` along the unit `direction` (decimal text,
// as a replay's numbers) meets a dynamic body; an impulse of `speed` m/s
// times its mass along the ray, at the point met, becomes an input of the
// next step. The run past this step is recorded anew: the later inputs and
// the recorded chain past it are dropped (the download then holds the run
// as played). Returns the body's slot, -1 when the ray meets no dynamic
// body, -2 on bad text.
VIEWER_EXPORT int bv_click(int v, const char* ox, const char* oy, const char* oz, const char* dx, const char* dy,
                           const char* dz, const char* speed) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return -2;
  Fixed n[7];
  const char* texts[7] = {ox, oy, oz, dx, dy, dz, speed};
  for (int i = 0; i < 7; ++i) {
    const ParseResult r = parse_fixed(texts[i]);
    if (!r.ok()) {
      last_error = std::string("not a number: ") + texts[i];
      return -2;
    }
    n[i] = r.value;
  }
  const Vec3 origin{n[0], n[1], n[2]}, direction{n[3], n[4], n[5]};
  const std::optional<QueryHit> hit = WorldQuery(*p->world).cast_ray(origin, direction * Fixed::from_int(500));
  if (!hit) return -1;
  const Body& body = p->world->body(hit->body);
  if (body.type != BodyType::dynamic || body.inverse_mass == Fixed{}) return -1;
  const Vec3 impulse = direction * (n[6] / body.inverse_mass);
  const int64_t tick = static_cast<int64_t>(p->world->step_count());
  const std::string input = "[{\"step\": " + std::to_string(tick + 1) + ", \"type\": \"impulse\", \"body\": " +
                            std::to_string(hit->body.index) + ", \"impulse\": [" + to_string(impulse.x) + ", " +
                            to_string(impulse.y) + ", " + to_string(impulse.z) + "], \"point\": [" +
                            to_string(hit->point.x) + ", " + to_string(hit->point.y) + ", " +
                            to_string(hit->point.z) + "]}]";
  Result<std::vector<Input>> parsed = parse_inputs(input, p->replay.scene, "click");
  if (!parsed.ok()) {
    last_error = parsed.error().message();
    return -2;
  }
  // The run from here on is a new recording.
  std::vector<Input>& inputs = p->replay.inputs;
  while (!inputs.empty() && inputs.back().step > tick) inputs.pop_back();
  if (static_cast<int64_t>(p->replay.hashes.size()) > tick) p->replay.hashes.resize(static_cast<size_t>(tick));
  p->computed.resize(static_cast<size_t>(tick));
  while (p->keyframes.size() > 1 && p->keyframes.back().tick > tick) p->keyframes.pop_back();
  if (p->diverged_at > tick) p->diverged_at = 0;
  for (Input& in : parsed.value()) inputs.push_back(std::move(in));
  return static_cast<int>(hit->body.index);
}

// The run so far as a replay file: the scene (by its file name, or
// inline), the inputs up to this step and the computed chain.
VIEWER_EXPORT const char* bv_replay_json(int v) {
  Player* p = player(v);
  if (p == nullptr || !p->loaded) return "";
  Replay out = p->replay;
  const int64_t tick = static_cast<int64_t>(p->world->step_count());
  while (!out.inputs.empty() && out.inputs.back().step > tick) out.inputs.pop_back();
  out.steps = tick;
  out.hashes.assign(p->computed.begin(), p->computed.begin() + static_cast<std::ptrdiff_t>(tick));
  out.scene_hash = p->start_hash;
  p->text = replay_json(out, "bitstep viewer");
  return p->text.c_str();
}

// The first field in which the two players' states differ, as `bitstep
// diff` names it ("$.bodies[6].velocity.linear[0]: 1.5 vs 1.25"); "" when
// they are the same (or either is not loaded).
VIEWER_EXPORT const char* bv_diff() {
  if (!players[0].loaded || !players[1].loaded) return "";
  const Result<DumpDifference> d = diff_dumps(dump_state(*players[0].world), dump_state(*players[1].world));
  players[0].text = !d.ok() ? d.error().message() : d.value().value_or("");
  return players[0].text.c_str();
}
