// Typed reads from the JSON tree for the scene loader: each either returns
// an exact value or fails with the JSON path of the value and the reason
// (a thrown Error, caught by read_json: none leaves the readers).
#pragma once

#include <exception>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/body.h"
#include "core/error.h"
#include "fixed/decimal.h"
#include "fixed/quat.h"
#include "replay/json_tree.h"
#include "replay/material_table.h"

namespace bitstep::scene_reader {

// pi rounded once to Q32.32 (the literal is parsed exactly at compile time):
// degrees -> radians is mul_div(d, pi_q32, 180), one rounding of the exact
// product, wherever a scene's angle is read or generated.
inline constexpr Fixed pi_q32 = 3.14159265358979323846264338327950288_fx;

// Throws Error{path, reason}: the typed reads stop at the first bad value,
// however deep, and read_json turns it into the reader's result.
[[noreturn]] void fail(const std::string& path, std::string reason);
[[noreturn]] void fail(const json::Node& at, std::string reason);

// The keys of one JSON object, read by name. Every key the loader asks for
// is a known key; finish() refuses the first member nobody asked for and
// lists the known ones.
class ObjectReader {
 public:
  explicit ObjectReader(const json::Node& node);  // fails unless `node` is an object

  const json::Node* find(std::string_view key);
  const json::Node& require(std::string_view key);  // fails when missing
  void finish() const;
  const json::Node& node() const { return node_; }

 private:
  const json::Node& node_;
  std::vector<std::string_view> known_;
};

// What a number may be.
enum class Bound { any, non_negative, positive, unit_interval };

// A JSON number or a string holding exact text: decimal, ratio "a/b" or
// "raw:<hex>" (fixed/decimal.h), rounded once.
Fixed read_fixed(const json::Node& node, Bound bound = Bound::any);
// A number in lo..hi, else "outside lo..hi <unit>" ("outside +-hi <unit>"
// when lo = -hi).
Fixed read_fixed_within(const json::Node& node, Fixed lo, Fixed hi, std::string_view unit);
// An integer in lo..hi, written as a JSON number or a string of digits.
int read_int(const json::Node& node, int lo, int hi);
// Any integer 0..2^64-1 (random seeds).
uint64_t read_u64(const json::Node& node);
bool read_bool(const json::Node& node);
const std::string& read_string(const json::Node& node);
// One of `choices`; returns its index.
size_t read_choice(const json::Node& node, const std::vector<std::string_view>& choices);
// [x, y, z]
Vec3 read_vec3(const json::Node& node, Bound bound = Bound::any);
// [x, y, z], each in lo..hi.
Vec3 read_vec3_within(const json::Node& node, Fixed lo, Fixed hi, std::string_view unit);
// {"axis": [x, y, z], "degrees": d} or {"axis": ..., "radians": r} or
// {"quaternion": [w, x, y, z]} (normalised).
Quat read_orientation(const json::Node& node);

// An object of material fields (defaults from Material{}).
Material read_material_fields(const json::Node& node);
// A material name from the table, or an inline object.
Material read_material(const json::Node& node, const MaterialTable& table);

// The helpers below override a field only when the key is present: an
// absent key keeps the default already in the field.
void read_optional(ObjectReader& reader, std::string_view key, Fixed& field, Bound bound = Bound::any);
void read_optional(ObjectReader& reader, std::string_view key, Vec3& field, Bound bound = Bound::any);
void read_optional(ObjectReader& reader, std::string_view key, int& field, int lo, int hi);
void read_optional(ObjectReader& reader, std::string_view key, bool& field);
void read_optional_within(ObjectReader& reader, std::string_view key, Fixed& field, Fixed lo, Fixed hi,
                          std::string_view unit);
void read_optional_within(ObjectReader& reader, std::string_view key, Vec3& field, Fixed lo, Fixed hi,
                          std::string_view unit);

// JSON text read by `read` (from the tree's root, with the reads above):
// its value, or the first error with `source` (a file, "add_body") in front
// of its place. The one place the reads' throws are caught. Never throws.
template <class Read>
auto read_json(std::string_view text, const std::string& source, Read&& read)
    -> Result<decltype(read(std::declval<const json::Node&>()))> {
  try {
    Result<json::Node> tree = json::parse(text);
    if (!tree.ok()) return tree.error().within(source);
    return read(tree.value());
  } catch (const Error& error) {
    return error.within(source);
  } catch (const std::exception& e) {  // allocation failure
    return Error{"$", std::string("cannot load: ") + e.what()}.within(source);
  }
}

}  // namespace bitstep::scene_reader
