// The resource limits of everything bitstep reads from files other people
// wrote: scenes, replays, inputs files, --settings overrides, state dumps and
// snapshot images. Each bounds the time and memory a hostile file can cost;
// each is checked before the work or the allocation it bounds, and a file
// past one is refused with one line naming the file, the place (a JSON path
// or a byte offset where there is one) and the limit. replay/README.md
// ("Limits") lists them with what the shipped scenes and tests need.
#pragma once

#include <cstddef>
#include <cstdint>

namespace bitstep::limits {

// --- files ------------------------------------------------------------------

// A JSON file (scene, replay, inputs, state dump): its size is checked
// before a byte is read. 64 MiB holds a replay of max_replay_steps hashes
// (19 bytes each) three times over; the largest shipped file is 19 KB.
inline constexpr std::uintmax_t max_json_file_bytes = std::uintmax_t{64} << 20;
// A snapshot image file (`bitstep run --restore`): a world of 800,000
// bodies at ~1,300 bytes each (wall128's image: 1,294 bytes a body).
inline constexpr std::uintmax_t max_snapshot_file_bytes = std::uintmax_t{1} << 30;

// --- JSON -------------------------------------------------------------------

// Arrays and objects nested deeper than this are refused (a scene needs 6).
inline constexpr int max_json_depth = 64;
// The memory a parsed JSON tree may take, counted as it is built: each
// value's node, its text, key and JSON path. Text is a few bytes a value
// while its node is ~150, and a path under deep long keys is up to ~4 KB:
// without this bound a 64 MiB file could ask for tens of GB.
inline constexpr std::size_t max_json_tree_bytes = std::size_t{1} << 30;

// --- scenes -----------------------------------------------------------------

// Bodies in one scene, every generator's included. The largest shipped
// scene (wall128) has 8,257; the bench builds its scales (to ~10,000) in
// code, not from files.
inline constexpr int max_scene_bodies = 100000;
// Joints in one scene, every generator's included (a chain of n links has
// n + 1; a ragdoll 10 for 11 bodies).
inline constexpr int max_scene_joints = 100000;
// Shapes in one body (a table has 5). A contact names a shape by a 16-bit
// index; this keeps every index far inside it.
inline constexpr int max_shapes_per_body = 256;
// Entries of a scene's "generators" array (each makes at least one body).
inline constexpr int max_generators = 10000;
// The bodies one generator may make: a pyramid's base(base + 1) / 2, a
// wall's bricks, a stack's count... checked from the parameters before any
// body is made.
inline constexpr int max_generated_bodies = max_scene_bodies;
// Cars in one scene.
inline constexpr int max_scene_cars = 1000;
// Named materials in one scene: one for each body at most
// (tests/replay/json_tree_tests.cpp loads 100,000).
inline constexpr int max_materials = max_scene_bodies;

// --- replays ----------------------------------------------------------------

// Steps of a replay (and `bitstep record --steps`, `verify --dump-at`):
// 4.6 hours at 60 Hz. verify needs one hash per step, so a replay claiming
// more hashes than its file holds is refused when read, before a step runs.
inline constexpr int max_replay_steps = 1000000;
// Inputs in one replay or inputs file: one a step on average.
inline constexpr int max_replay_inputs = 1000000;

// --- snapshot images --------------------------------------------------------

// The counts an image's payload may ask for, checked when the count is read
// (before the vector is allocated), as is that the bytes left could hold
// that many. A world restored from an image, or a rollback state, holds at
// most these: a scene's bodies plus a replay's spawns.
inline constexpr uint32_t max_world_bodies = static_cast<uint32_t>(max_scene_bodies + max_replay_inputs);
inline constexpr uint32_t max_world_joints = static_cast<uint32_t>(max_scene_joints + max_replay_inputs);
// Contacts: pairs of touching shapes, 4 a body of the largest world (a
// brick of wall128 has ~3; a world of max_scene_bodies, 44). Each costs
// ~300 bytes in memory for at least 17 in an image: this bounds a hostile
// image's contacts to ~1.4 GB, where its size alone would allow 40 GB.
inline constexpr uint32_t max_world_contacts = 4 * max_world_bodies;

}  // namespace bitstep::limits
