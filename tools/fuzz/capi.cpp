// Fuzzes the C API (replay/bitstep.h) as a game calls it: the bytes are a
// sequence of calls with their arguments (capi_input.h says how they are
// read), made on a simulation of a small built-in scene: bodies and joints
// added from JSON fragments (built-in ones with numbers the bytes choose,
// or the bytes themselves), removed, or named by stale and made-up handles;
// inputs with any 64-bit numbers; steps; saves and loads of snapshots and
// rollback states, as saved or with bytes flipped and cut; getters, rays,
// calls with null pointers; a new simulation from a cut scene text; bodies
// and joints from plain structs of any numbers and enumerations; and the
// getters, batch reads and events with buffers of any size.
//
// Must hold after every call: a call that did not return BITSTEP_OK changed
// nothing (the hash and the snapshot image as before) and, unless it was
// BITSTEP_NULL_ARGUMENT, left a one-line message; a getter changed
// nothing; a load of an image as saved gives back the hash it was saved
// with (a snapshot also snapshots to the same bytes); a rollback state
// saved since the world's last load restores. And no crash, no undefined
// behaviour, no leak (every simulation is destroyed at the end).
#include <xxhash.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "replay/bitstep.h"
#include "tools/fuzz/capi_input.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

namespace {

using capi_input::Call;
using capi_input::Reader;

// A ground, a box and a ball joined by a point joint, and a car (a chassis
// on four wheels of one ray each) so that `drive` has one to drive: the
// scene as a person writes it. Every input builds its simulation again
// (and `recreate` once more), so the target builds it from `capi_scene`,
// the same scene with every number but 0 written as its exact raw value:
// a decimal costs a 63-step long division of 1024-bit numbers, every
// comparison of it traced by libFuzzer, which was 17% of a run's time. The
// decimal path stays fuzzed through the fragments and add_body_text, and
// same_world() checks once a process that both texts make one world.
constexpr std::string_view capi_scene_decimal = R"({"format": "bitstep-scene", "version": 1,
  "bodies": [
    {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [20, 1, 20]}]},
    {"name": "box", "position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"name": "ball", "position": [0, 2, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
    {"name": "chassis", "position": [5, 1, 0], "mass": 1200, "shapes": [{"type": "box", "half_extents": [0.9, 0.3, 2.1]}]}],
  "joints": [{"type": "point", "name": "pin", "body_a": "box", "body_b": "ball", "anchor": [0, 1.25, 0]}],
  "cars": [{"name": "car", "chassis": "chassis", "rays_per_wheel": 1, "wheels": [
    {"attachment": [0.8, -0.3, 1.45], "steered": true}, {"attachment": [-0.8, -0.3, 1.45], "steered": true},
    {"attachment": [0.8, -0.3, -1.45], "driven": true}, {"attachment": [-0.8, -0.3, -1.45], "driven": true}]}]})";
constexpr std::string_view capi_scene = R"({"format": "bitstep-scene", "version": 1,
  "bodies": [
    {"name": "ground", "type": "static", "position": [0, "raw:-100000000", 0],
     "shapes": [{"type": "box", "half_extents": ["raw:1400000000", "raw:100000000", "raw:1400000000"]}]},
    {"name": "box", "position": [0, "raw:80000000", 0],
     "shapes": [{"type": "box", "half_extents": ["raw:80000000", "raw:80000000", "raw:80000000"]}]},
    {"name": "ball", "position": [0, "raw:200000000", 0], "shapes": [{"type": "sphere", "radius": "raw:80000000"}]},
    {"name": "chassis", "position": ["raw:500000000", "raw:100000000", 0], "mass": "raw:4b000000000",
     "shapes": [{"type": "box", "half_extents": ["raw:e6666666", "raw:4ccccccd", "raw:21999999a"]}]}],
  "joints": [{"type": "point", "name": "pin", "body_a": "box", "body_b": "ball", "anchor": [0, "raw:140000000", 0]}],
  "cars": [{"name": "car", "chassis": "chassis", "rays_per_wheel": "raw:100000000", "wheels": [
    {"attachment": ["raw:cccccccd", "raw:-4ccccccd", "raw:173333333"], "steered": true},
    {"attachment": ["raw:-cccccccd", "raw:-4ccccccd", "raw:173333333"], "steered": true},
    {"attachment": ["raw:cccccccd", "raw:-4ccccccd", "raw:-173333333"], "driven": true},
    {"attachment": ["raw:-cccccccd", "raw:-4ccccccd", "raw:-173333333"], "driven": true}]}]})";

// Body objects of the scene format; each `#` becomes a number's text the
// bytes choose (capi_input::number_texts), in or out of range or not a
// number at all.
constexpr const char* body_fragments[] = {
    R"({"shapes": [{"type": "sphere", "radius": 0.25}], "position": [#, #, #]})",
    R"({"name": "crate", "position": [1, #, 0], "shapes": [{"type": "box", "half_extents": [#, 0.5, 0.5]}]})",
    R"({"name": "pill", "type": "kinematic", "velocity": [#, 0, 0], "shapes": [{"type": "capsule", "radius": 0.2, "half_height": #}]})",
    R"({"name": "wall", "type": "static", "position": [0, 0, #], "shapes": [{"type": "box", "half_extents": [5, 5, 0.1]}]})",
    R"({"mass": #, "angular_velocity": [0, #, 0], "shapes": [{"type": "box", "half_extents": [0.01, 0.01, 0.01]}]})",
    R"({"name": "pair", "orientation": {"axis": [#, 1, 0], "degrees": #}, "shapes": [{"type": "sphere", "radius": 0.3},
       {"type": "sphere", "radius": 0.3, "position": [0.6, 0, 0]}]})",
    R"({"name": "sensor", "sensor": true, "type": "static", "shapes": [{"type": "sphere", "radius": #}]})",
    R"({"density": #, "position": [0, 10, 0], "shapes": [{"type": "box", "half_extents": [50, 0.01, 50]}]})",
};
// Joint objects, their bodies by name (the scene's, or bodies the fragments above name).
constexpr const char* joint_fragments[] = {
    R"({"type": "point", "body_a": "ground", "body_b": "crate", "anchor": [#, #, 0]})",
    R"({"type": "hinge", "body_a": "box", "body_b": "pair", "anchor": [0, 1, 0], "axis": [0, 0, #], "limits": [-45, #]})",
    R"({"type": "max_distance", "body_a": "ball", "body_b": "chassis", "anchor": [0, 2, 0], "anchor_b": [5, 1, 0], "length": #})",
    R"({"type": "slider", "body_a": "ground", "body_b": "pill", "anchor": [0, 0, 0], "axis": [1, 0, 0], "limits": [#, 2]})",
};
// Character objects (bitstep_add_character), and the names calls give.
constexpr const char* character_fragments[] = {
    R"({"name": "hero", "position": [#, #, #]})",
    R"({"name": "guest", "position": [0, 1, 3], "radius": #, "half_height": #, "step_height": #})",
    R"({"name": "hero", "position": [2, 0.91, 2], "max_slope": #, "facing": [#, 0, 1], "jump_speed": #})",
};
constexpr const char* character_names[] = {"hero", "guest", ""};
constexpr const char* names[] = {"ground", "box", "ball", "chassis", "crate", "pill", "pair", "sensor", "wall", ""};
constexpr const char* car_names[] = {"car", "van", ""};

// A saved image: its bytes, the hash it was saved with, and for a rollback
// state the load epoch it was saved in.
struct Saved {
  std::vector<uint8_t> bytes;
  uint64_t hash = 0;
  uint64_t epoch = 0;
};

std::vector<uint8_t> image_of(bitstep_simulation* sim) {
  size_t size = 0;
  require(bitstep_save(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL, "save asks for a buffer");
  std::vector<uint8_t> image(size);
  require(bitstep_save(sim, image.data(), image.size(), &size) == BITSTEP_OK && size == image.size(),
          "save fills a buffer of the size it asked for");
  return image;
}

// The rollback state of `sim` now.
std::vector<uint8_t> state_of(bitstep_simulation* sim) {
  size_t size = 0;
  require(bitstep_save_state(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL, "save_state asks for a buffer");
  std::vector<uint8_t> state(size);
  require(bitstep_save_state(sim, state.data(), state.size(), &size) == BITSTEP_OK && size == state.size(),
          "save_state fills a buffer of the size it asked for");
  return state;
}

// Whether capi_scene and capi_scene_decimal make one world: the same
// snapshot image, so the same bodies, shapes, masses, joint and car.
bool same_world() {
  const auto image_of_text = [](std::string_view text) {
    bitstep_simulation* sim = nullptr;
    require(bitstep_create_from_text(text.data(), text.size(), "capi.json", &sim, nullptr, 0) == BITSTEP_OK,
            "the built-in scene makes a simulation");
    std::vector<uint8_t> image = image_of(sim);
    bitstep_destroy(sim);
    return image;
  };
  return image_of_text(capi_scene) == image_of_text(capi_scene_decimal);
}

// Rewrites an image's payload-size field (at `size_at`, the payload after
// `header` bytes) and its trailing XXH3-64 to fit its bytes, so that flips
// reach the payload's reader instead of stopping at the checksum.
void put_le(std::vector<uint8_t>& bytes, size_t at, uint64_t value) {
  for (size_t i = 0; i < 8; ++i) bytes[at + i] = static_cast<uint8_t>(value >> (8 * i));
}

// A snapshot (replay/snapshot.h): magic, version, payload size at 12, the
// payload, XXH3-64 of everything before the trailer.
void make_snapshot_right(std::vector<uint8_t>& bytes) {
  constexpr size_t header = 8 + 4 + 8;
  if (bytes.size() < header + 8) return;
  put_le(bytes, 12, bytes.size() - header - 8);
  put_le(bytes, bytes.size() - 8, XXH3_64bits(bytes.data(), bytes.size() - 8));
}

// A rollback state (replay/rollback_state.h): the payload's size (at 40)
// after the header and the serials (their count at 36), its hash (at 28),
// and the trailer over the header and the serials.
void make_state_right(std::vector<uint8_t>& bytes) {
  constexpr size_t header = 48;
  if (bytes.size() < header + 8) return;
  uint64_t serials = 0;
  for (size_t i = 0; i < 4; ++i) serials |= uint64_t{bytes[36 + i]} << (8 * i);
  if (serials > (bytes.size() - header - 8) / 8) return;
  const size_t payload_at = header + 8 * static_cast<size_t>(serials);
  const size_t payload = bytes.size() - 8 - payload_at;
  put_le(bytes, 40, payload);
  put_le(bytes, 28, XXH3_64bits(bytes.data() + payload_at, payload));
  put_le(bytes, bytes.size() - 8, XXH3_64bits(bytes.data(), payload_at));
}

class Session {
 public:
  explicit Session(Reader& in) : in_(in) {
    sim_ = created(0);
    require(sim_ != nullptr, "the built-in scene makes a simulation");
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session() { bitstep_destroy(sim_); }

  // What a refused call must leave as it was: the state hash (every body's
  // pose, velocities, sleep, contacts, joints, cars: the state the replays'
  // chains hold), kept between calls that cannot have changed it.
  uint64_t mark() {
    if (!hash_known_) hash_ = bitstep_hash(sim_);
    hash_known_ = true;
    return hash_;
  }

  // The properties of one call's outcome, `before` the hash mark() gave
  // just before it.
  void check_outcome(bitstep_status status, uint64_t before) {
    require(status >= BITSTEP_OK && status <= BITSTEP_NOT_READY, "a status is one of the enum's");
    if (status == BITSTEP_OK) {
      hash_known_ = false;  // it may have changed the world
      return;
    }
    require(bitstep_hash(sim_) == before, "a refused call leaves the hash as it was");
    require_one_line_error(bitstep_last_error(sim_), "");  // every failure on a handle names itself
  }

  // A getter's, a ray's and a save's property: it changed nothing.
  void check_unchanged(uint64_t before) { require(bitstep_hash(sim_) == before, "a getter leaves the hash as it was"); }

  void run() {
    for (int calls = 0; calls < capi_input::max_calls && !in_.empty(); ++calls) one(in_.call());
  }

 private:
  // A simulation of the scene's text cut to `cut` bytes (0: whole), its
  // message cut to an error buffer of 0..8 bytes.
  bitstep_simulation* created(size_t cut) {
    bitstep_simulation* sim = nullptr;
    char error[8];
    const size_t capacity = in_.byte() % (sizeof error + 1);
    const size_t length = cut == 0 ? capi_scene.size() : std::min(cut, capi_scene.size());
    const bitstep_status status =
        bitstep_create_from_text(capi_scene.data(), length, "capi.json", &sim, error, capacity);
    if (status == BITSTEP_OK) {
      require(sim != nullptr, "a created simulation is there");
    } else {
      require(sim == nullptr, "a refused scene makes no simulation");
      if (capacity > 0) require(std::strlen(error) < capacity, "a message is cut to the caller's buffer");
    }
    return sim;
  }

  bitstep_body body() {
    const uint8_t how = in_.byte();
    if (how < 0x80 && !bodies_.empty()) return bodies_[in_.byte() % bodies_.size()];
    if (how < 0xc0) return {in_.byte(), in_.byte()};
    return {in_.u32(), in_.u32()};
  }

  bitstep_vec3 vec3() { return {in_.number(), in_.number(), in_.number()}; }

  std::string fragment(const char* const* table, size_t count) {
    std::string text = table[in_.byte() % count];
    for (size_t at = text.find('#'); at != std::string::npos; at = text.find('#', at)) {
      const std::string number = in_.number_text();
      text.replace(at, 1, number);
      at += number.size();
    }
    const size_t cut = in_.byte();
    if (cut != 0 && cut < text.size()) text.resize(cut);  // malformed: cut short
    return text;
  }

  // The bytes as text, a NUL among them ending it as C would.
  std::string raw_text() {
    std::string text;
    for (size_t n = in_.byte(); n > 0; --n) text.push_back(static_cast<char>(in_.byte()));
    return text;
  }

  // add_body or add_joint of JSON text, create_body or create_joint of a
  // struct; the handle made kept in `made`.
  template <typename Handle, typename Argument>
  void add(bitstep_status (*call)(bitstep_simulation*, Argument, Handle*), std::type_identity_t<Argument> argument,
           std::vector<Handle>& made) {
    const uint64_t before = mark();
    Handle added{};
    const bitstep_status status = call(sim_, argument, &added);
    check_outcome(status, before);
    if (status == BITSTEP_OK) made.push_back(added);
  }

  // A load of a saved image, as saved or flipped, cut and made right.
  template <typename Load>
  void load(std::vector<Saved>& saved, void (*make_right)(std::vector<uint8_t>&), bool rollback, Load&& load_image) {
    if (saved.empty()) return;
    const Saved& chosen = saved[in_.byte() % saved.size()];
    std::vector<uint8_t> bytes = chosen.bytes;
    const uint8_t flips = in_.byte() % 4;
    for (uint8_t i = 0; i < flips && !bytes.empty(); ++i) bytes[in_.u16() % bytes.size()] ^= in_.byte();
    const uint16_t cut = in_.u16();
    if (cut != 0 && cut < bytes.size()) bytes.resize(bytes.size() - cut);
    if (in_.byte() & 1) make_right(bytes);
    const bool as_saved = bytes == chosen.bytes;
    const uint64_t before = mark();
    // The world as it is, to come back to after a changed image: the
    // readers check ranges, not that a state is one a world could reach, and
    // stepping a made-up state is not what this target tries (README.md,
    // "Open findings").
    const std::vector<uint8_t> backup = as_saved ? std::vector<uint8_t>{} : rollback ? state_of(sim_) : image_of(sim_);
    const bitstep_status status = load_image(bytes);
    check_outcome(status, before);
    if (as_saved && (!rollback || chosen.epoch == epoch_)) {
      require(status == BITSTEP_OK, "an image as saved loads");
    }
    if (status != BITSTEP_OK) return;
    if (as_saved) require(bitstep_hash(sim_) == chosen.hash, "an image as saved loads with the hash it was saved with");
    if (!rollback) {
      require(image_of(sim_) == bytes, "a loaded snapshot snapshots to the same bytes");
      ++epoch_;  // a new world: the rollback states saved so far are of another
    }
    if (!as_saved) {
      require(load_image(backup) == BITSTEP_OK && bitstep_hash(sim_) == before,
              "the state saved just before loads with its hash");
    }
  }

  void save(std::vector<Saved>& saved, bool rollback) {
    const uint64_t before = mark();
    size_t size = 0;
    const auto save_into = rollback ? bitstep_save_state : bitstep_save;
    std::vector<uint8_t> small(in_.byte() % 16);
    bitstep_status status = save_into(sim_, small.data(), small.size(), &size);
    check_outcome(status, before);
    if (status == BITSTEP_OK) {
      small.resize(size);
    } else {
      require(status == BITSTEP_BUFFER_TOO_SMALL && size > small.size(), "a short buffer says the size it needs");
      small.resize(size);
      status = save_into(sim_, small.data(), small.size(), &size);
      require(status == BITSTEP_OK && size == small.size(), "a save fills a buffer of the size it asked for");
    }
    check_unchanged(before);
    if (saved.size() < 8) saved.push_back({std::move(small), before, epoch_});
  }

  // A call on a body (remove_body, wake), or with two vectors too
  // (set_velocity, apply_impulse, apply_force).
  void on_body(bitstep_status (*call)(bitstep_simulation*, bitstep_body)) {
    const bitstep_body b = body();
    const uint64_t before = mark();
    check_outcome(call(sim_, b), before);
  }
  void on_body(bitstep_status (*call)(bitstep_simulation*, bitstep_body, bitstep_vec3, bitstep_vec3)) {
    const bitstep_body b = body();
    const bitstep_vec3 first = vec3(), second = vec3();
    const uint64_t before = mark();
    check_outcome(call(sim_, b, first, second), before);
  }

  void one(Call call) {
    switch (call) {
      case Call::add_body_fragment:
        add(bitstep_add_body, fragment(body_fragments, std::size(body_fragments)).c_str(), bodies_);
        break;
      case Call::add_body_text: add(bitstep_add_body, raw_text().c_str(), bodies_); break;
      case Call::add_joint_fragment:
        add(bitstep_add_joint, fragment(joint_fragments, std::size(joint_fragments)).c_str(), joints_);
        break;
      case Call::add_joint_text: add(bitstep_add_joint, raw_text().c_str(), joints_); break;
      case Call::remove_body: on_body(bitstep_remove_body); break;
      case Call::remove_joint: {
        const uint8_t how = in_.byte();
        const bitstep_joint j = how < 0x80 && !joints_.empty() ? joints_[in_.byte() % joints_.size()]
                                                               : bitstep_joint{in_.byte(), in_.byte()};
        const uint64_t before = mark();
        check_outcome(bitstep_remove_joint(sim_, j), before);
        break;
      }
      case Call::set_velocity: on_body(bitstep_set_velocity); break;
      case Call::apply_impulse: on_body(bitstep_apply_impulse); break;
      case Call::apply_force: on_body(bitstep_apply_force); break;
      case Call::drive: {
        const char* car = car_names[in_.byte() % std::size(car_names)];
        const bitstep_fixed throttle = in_.number(), brake = in_.number(), steer = in_.number();
        const uint64_t before = mark();
        check_outcome(bitstep_drive(sim_, car, throttle, brake, steer), before);
        break;
      }
      case Call::wake: on_body(bitstep_wake); break;
      case Call::step: {
        const uint64_t tick = bitstep_tick(sim_);
        for (int n = 1 + in_.byte() % 8; n > 0 && steps_ < capi_input::max_steps; --n, ++steps_) {
          require(bitstep_step(sim_) == BITSTEP_OK, "a step steps");
        }
        require(bitstep_tick(sim_) >= tick, "the tick counts up");
        hash_known_ = false;
        break;
      }
      case Call::save: save(snapshots_, false); break;
      case Call::load:
        load(snapshots_, make_snapshot_right, false,
             [&](const std::vector<uint8_t>& b) { return bitstep_load(sim_, b.data(), b.size()); });
        break;
      case Call::save_state: save(states_, true); break;
      case Call::load_state:
        load(states_, make_state_right, true,
             [&](const std::vector<uint8_t>& b) { return bitstep_load_state(sim_, b.data(), b.size()); });
        break;
      case Call::get: get(); break;
      case Call::cast_ray: {
        const bitstep_vec3 origin = vec3(), translation = vec3();
        const uint64_t before = mark();
        bitstep_ray_hit hit{};
        const bitstep_status status = bitstep_cast_ray(sim_, origin, translation, &hit);
        require(status == BITSTEP_OK || status == BITSTEP_NOT_FOUND, "a ray hits or meets nothing");
        check_unchanged(before);
        if (status == BITSTEP_OK)
          require(hit.fraction >= 0 && hit.fraction <= (int64_t{1} << 32), "a hit's fraction is 0..1");
        break;
      }
      case Call::find_body: {
        const uint64_t before = mark();
        bitstep_body found{};
        const bitstep_status status = bitstep_find_body(sim_, names[in_.byte() % std::size(names)], &found);
        check_outcome(status, before);
        if (status == BITSTEP_OK) bodies_.push_back(found);
        break;
      }
      case Call::null_arguments: null_arguments(); break;
      case Call::create_body_struct: create_body_struct(); break;
      case Call::create_joint_struct: create_joint_struct(); break;
      case Call::read_all: read_all(); break;
      case Call::character: character(); break;
      case Call::recreate: {
        bitstep_simulation* made = created(in_.u16());
        if (made == nullptr) break;
        bitstep_destroy(sim_);
        sim_ = made;
        hash_known_ = false;
        ++epoch_;
        break;
      }
    }
  }

  bitstep_quat quat() {
    if (in_.byte() < 0x80) return {int64_t{1} << 32, 0, 0, 0};
    return {in_.number(), in_.number(), in_.number(), in_.number()};
  }
  bitstep_pose pose() { return {vec3(), quat()}; }

  // A body from a struct of the bytes' numbers and enumerations (some
  // past the enumerations' ends), 0 to 3 shapes or a NULL array.
  void create_body_struct() {
    bitstep_shape shapes[3]{};
    bitstep_vec3 points[3][8]{};
    bitstep_body_def def = bitstep_default_body_def();
    def.type = in_.byte() % 4;
    if (in_.byte() & 1) def.pose = pose();
    if (in_.byte() & 1) def.linear_velocity = vec3();
    if (in_.byte() & 1) def.angular_velocity = vec3();
    if (in_.byte() & 1) def.density = in_.number();
    if (in_.byte() & 1) def.mass = in_.number();
    if (in_.byte() & 1) def.material = {in_.number(), in_.number(), in_.number(), in_.number()};
    if (in_.byte() & 1) def.linear_damping = in_.number(), def.angular_damping = in_.number();
    if (in_.byte() & 1) def.layers = in_.u32(), def.collides_with = in_.u32();
    def.asleep = in_.byte() & 1;
    def.sensor = in_.byte() & 1;
    const uint8_t naming = in_.byte() % 3;
    def.name = naming == 0 ? nullptr : naming == 1 ? "ball" : "made";
    def.shape_count = in_.byte() % 4;
    for (uint32_t i = 0; i < def.shape_count; ++i) {
      shapes[i].type = in_.byte() % 7;
      shapes[i].point_count = in_.byte() % 9;  // a hull's 0..8 points (or a NULL array)
      for (uint32_t k = 0; k < shapes[i].point_count; ++k) points[i][k] = vec3();
      shapes[i].points = in_.byte() < 0x10 ? nullptr : points[i];
      shapes[i].half_extents = vec3();
      shapes[i].radius = in_.number();
      shapes[i].half_height = in_.number();
      shapes[i].local = in_.byte() & 1 ? pose() : bitstep_pose{{0, 0, 0}, {int64_t{1} << 32, 0, 0, 0}};
    }
    def.shapes = in_.byte() < 0x10 ? nullptr : shapes;
    add(bitstep_create_body, &def, bodies_);
  }

  void create_joint_struct() {
    bitstep_joint_def def = bitstep_default_joint_def();
    def.type = in_.byte() % 6;
    def.body_a = body();
    def.body_b = body();
    def.anchor_a = vec3();
    if (in_.byte() & 1) def.anchor_b = vec3(), def.length = in_.number();
    def.axis = vec3();
    def.limited = in_.byte() & 1;
    if (in_.byte() & 1) {
      def.lower_angle = in_.number(), def.upper_angle = in_.number(), def.swing_angle = in_.number();
      def.lower_translation = in_.number(), def.upper_translation = in_.number();
    }
    if (in_.byte() & 1) def.motor_speed = in_.number(), def.motor_max = in_.number();
    if (in_.byte() & 1) def.break_impulse = in_.number(), def.friction_torque = in_.number();
    if (in_.byte() & 1) def.velocity_iterations = in_.u16(), def.position_iterations = in_.u16();
    add(bitstep_create_joint, &def, joints_);
  }

  // The getters, the batch reads and the events, into buffers of any size
  // (a short one says the size it needs), and the integer conversions:
  // none changes the world; every failure names itself.
  void read_all() {
    const uint64_t before = mark();
    const bitstep_body b = body();
    const auto read = [&](bitstep_status status) {
      require(status == BITSTEP_OK || status == BITSTEP_NOT_FOUND || status == BITSTEP_BUFFER_TOO_SMALL,
              "a read finds, misses or asks for room");
      if (status != BITSTEP_OK) require_one_line_error(bitstep_last_error(sim_), "");
      return status;
    };
    bitstep_vec3 v{}, w{};
    int32_t asleep = 0;
    uint32_t shapes = 0;
    bitstep_shape shape{};
    char name[8];
    size_t size = 0;
    const bitstep_status found = read(bitstep_get_velocity(sim_, b, &v, &w));
    require(read(bitstep_is_asleep(sim_, b, &asleep)) == found, "a body is found by every getter or none");
    require(read(bitstep_get_shape_count(sim_, b, &shapes)) == found, "a body is found by every getter or none");
    if (found == BITSTEP_OK) {
      require(shapes >= 1 && shapes <= 256 && (asleep == 0 || asleep == 1), "a body's shapes and sleep");
      require(read(bitstep_get_shape(sim_, b, in_.byte() % (shapes + 1), &shape)) != BITSTEP_BUFFER_TOO_SMALL,
              "a shape or none");
      bitstep_vec3 corners[8];
      size_t corner_count = 0;
      const bitstep_status cornered =
          bitstep_get_hull_points(sim_, b, in_.byte() % (shapes + 1), corners, in_.byte() % 9, &corner_count);
      require(cornered == BITSTEP_OK || cornered == BITSTEP_NOT_FOUND || cornered == BITSTEP_INVALID ||
                  cornered == BITSTEP_BUFFER_TOO_SMALL,
              "a hull's corners, the room they need, or no hull");
      const size_t capacity = in_.byte() % sizeof name;
      const bitstep_status named =
          read(bitstep_get_body_name(sim_, b, capacity == 0 ? nullptr : name, capacity, &size));
      require(named == (size <= capacity ? BITSTEP_OK : BITSTEP_BUFFER_TOO_SMALL) && size >= 1,
              "a name, or the room it needs with its NUL");
    }
    std::vector<bitstep_body_pose> poses(in_.byte() % 8);
    const bitstep_status posed = read(bitstep_get_poses(sim_, poses.data(), poses.size(), &size));
    require(posed == (size <= poses.size() ? BITSTEP_OK : BITSTEP_BUFFER_TOO_SMALL), "every pose, or the room");
    std::vector<bitstep_body_render_pose> render(in_.byte() % 8);
    read(bitstep_get_render_poses(sim_, render.data(), render.size(), &size));
    std::vector<bitstep_event> events(in_.byte() % 4);
    const bitstep_status listed = read(bitstep_get_events(sim_, events.data(), events.size(), &size));
    require(listed == (size <= events.size() ? BITSTEP_OK : BITSTEP_BUFFER_TOO_SMALL), "every event, or the room");
    for (size_t i = 0; listed == BITSTEP_OK && i < size; ++i) {
      require(events[i].type >= BITSTEP_CONTACT_BEGIN && events[i].type <= BITSTEP_JOINT_BROKEN, "an event's type");
    }
    require(bitstep_set_events(sim_, in_.byte() & 1) == BITSTEP_OK, "events on or off");
    bitstep_fixed f = 0;
    const bitstep_fixed numerator = in_.number(), denominator = in_.number();
    const bitstep_status divided = bitstep_fixed_from_ratio(numerator, denominator, &f);
    require(divided == BITSTEP_OK || divided == BITSTEP_INVALID, "a quotient or a refusal");
    if (divided == BITSTEP_OK && denominator == 1) require(f == numerator * (int64_t{1} << 32), "n / 1 is n");
    (void)bitstep_fixed_round(in_.number());
    check_unchanged(before);
  }

  void get() {
    const uint64_t before = mark();
    const bitstep_body b = body();
    bitstep_pose pose{};
    const bitstep_status status = bitstep_get_pose(sim_, b, &pose);
    require(status == BITSTEP_OK || status == BITSTEP_NOT_FOUND, "a pose or no body");
    bitstep_render_pose from{}, to{}, between{};
    require(bitstep_get_render_pose(sim_, b, &from) == status, "a render pose where there is a pose");
    to = from;
    for (float& p : to.position) p = in_.real();
    for (float& q : to.orientation) q = in_.real();
    bitstep_interpolate(&from, &to, in_.real(), &between);
    const uint32_t slots = bitstep_slot_count(sim_);
    bitstep_body in_slot{};
    const uint32_t slot = in_.byte() < 0x80 && slots > 0 ? in_.byte() % slots : in_.u32();
    const bitstep_status found = bitstep_body_in_slot(sim_, slot, &in_slot);
    require(found == BITSTEP_OK || found == BITSTEP_NOT_FOUND, "a body or an empty slot");
    if (found == BITSTEP_OK) {
      require(in_slot.index == slot && bitstep_get_pose(sim_, in_slot, &pose) == BITSTEP_OK,
              "a slot's body has a pose");
      if (bodies_.size() < 64) bodies_.push_back(in_slot);
    }
    (void)bitstep_tick(sim_);
    check_unchanged(before);
  }

  // A character joins (a fragment), is moved, leaves or is read, by name.
  void character() {
    const uint64_t before = mark();
    const char* name = character_names[in_.byte() % std::size(character_names)];
    switch (in_.byte() % 4) {
      case 0: {
        const std::string text = fragment(character_fragments, std::size(character_fragments));
        check_outcome(bitstep_add_character(sim_, text.c_str()), before);
        break;
      }
      case 1: {
        const bitstep_vec3 velocity{in_.number(), in_.number(), in_.number()};
        check_outcome(bitstep_move_character(sim_, name, velocity, in_.byte() & 1), before);
        break;
      }
      case 2: check_outcome(bitstep_remove_character(sim_, name), before); break;
      default: {
        bitstep_character_state state{};
        const bitstep_status status = bitstep_get_character(sim_, name, &state);
        require(status == BITSTEP_OK || status == BITSTEP_NOT_FOUND, "a character or none");
        if (status == BITSTEP_OK)
          require(state.ground >= 0 && state.ground <= 2, "a ground state of the enum");
        else
          require_one_line_error(bitstep_last_error(sim_), "");
        check_unchanged(before);
      }
    }
  }

  // Every call that takes a pointer, given none where it must have one.
  void null_arguments() {
    const uint64_t before = mark();
    const bitstep_body b = body();
    size_t size = 0;
    const bitstep_status statuses[] = {bitstep_find_body(sim_, nullptr, nullptr),
                                       bitstep_add_body(sim_, nullptr, nullptr),
                                       bitstep_add_body(sim_, "{}", nullptr),
                                       bitstep_add_joint(sim_, nullptr, nullptr),
                                       bitstep_body_in_slot(sim_, 0, nullptr),
                                       bitstep_drive(sim_, nullptr, 0, 0, 0),
                                       bitstep_add_character(sim_, nullptr),
                                       bitstep_remove_character(sim_, nullptr),
                                       bitstep_move_character(sim_, nullptr, {}, 0),
                                       bitstep_get_character(sim_, "hero", nullptr),
                                       bitstep_get_pose(sim_, b, nullptr),
                                       bitstep_create_body(sim_, nullptr, nullptr),
                                       bitstep_create_joint(sim_, nullptr, nullptr),
                                       bitstep_get_velocity(sim_, b, nullptr, nullptr),
                                       bitstep_get_shape(sim_, b, 0, nullptr),
                                       bitstep_get_poses(sim_, nullptr, 0, nullptr),
                                       bitstep_get_events(sim_, nullptr, 1, &size),
                                       bitstep_get_render_pose(sim_, b, nullptr),
                                       bitstep_save(sim_, nullptr, 16, &size),
                                       bitstep_save(sim_, nullptr, 0, nullptr),
                                       bitstep_save_state(sim_, nullptr, 16, &size),
                                       bitstep_load(sim_, nullptr, 16),
                                       bitstep_load_state(sim_, nullptr, 0),
                                       bitstep_cast_ray(sim_, {}, {}, nullptr),
                                       bitstep_step(nullptr),
                                       bitstep_remove_body(nullptr, b),
                                       bitstep_set_velocity(nullptr, b, {}, {}),
                                       bitstep_fixed_parse(nullptr, nullptr),
                                       bitstep_create_from_text(nullptr, 0, "x", nullptr, nullptr, 0)};
    for (const bitstep_status status : statuses) require(status == BITSTEP_NULL_ARGUMENT, "a null pointer is refused");
    bitstep_interpolate(nullptr, nullptr, 0.5f, nullptr);
    require(bitstep_hash(nullptr) == 0 && bitstep_tick(nullptr) == 0 && bitstep_slot_count(nullptr) == 0,
            "a null simulation reads as empty");
    require(*bitstep_last_error(nullptr) == '\0', "a null simulation has no message");
    check_outcome(BITSTEP_NULL_ARGUMENT, before);
  }

  Reader& in_;
  bitstep_simulation* sim_ = nullptr;
  std::vector<bitstep_body> bodies_;
  std::vector<bitstep_joint> joints_;
  std::vector<Saved> snapshots_, states_;
  uint64_t hash_ = 0;
  bool hash_known_ = false;  // hash_ is the simulation's
  uint64_t epoch_ = 0;       // loads and new simulations so far: a rollback state restores only in its own
  int steps_ = 0;
};

}  // namespace

Outcome capi_calls(std::span<const uint8_t> data) {
  static const bool same = same_world();
  require(same, "the raw scene is the decimal scene");
  Reader in(data);
  Session session(in);
  session.run();
  return {true, {}};
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::capi_calls({data, size});
  return 0;
}
#endif
