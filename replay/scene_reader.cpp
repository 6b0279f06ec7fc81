#include "replay/scene_reader.h"

#include <algorithm>

#include "fixed/decimal.h"
#include "replay/input_bounds.h"

namespace bitstep::scene_reader {

using json::Kind;
using json::Node;

void fail(const std::string& path, std::string reason) { throw Error{path, std::move(reason)}; }
void fail(const Node& at, std::string reason) { fail(at.path, std::move(reason)); }

namespace {

std::string got(const Node& node) { return std::string(", got ") + json::describe(node.kind); }

void check_bound(const Node& node, Fixed value, Bound bound) {
  switch (bound) {
    case Bound::any: return;
    case Bound::non_negative:
      if (value < Fixed{}) fail(node, "must be >= 0");
      return;
    case Bound::positive:
      if (value <= Fixed{}) fail(node, "must be > 0");
      return;
    case Bound::unit_interval:
      if (value < Fixed{} || value > Fixed::one()) fail(node, "outside 0..1");
      return;
  }
}

// The text of a number written as a JSON number or as a string.
const std::string& number_text(const Node& node, const char* expected) {
  if (node.kind != Kind::number && node.kind != Kind::string) fail(node, std::string("expected ") + expected + got(node));
  return node.text;
}


}  // namespace

ObjectReader::ObjectReader(const Node& node) : node_(node) {
  if (node.kind != Kind::object) fail(node, "expected an object" + got(node));
}

const Node* ObjectReader::find(std::string_view key) {
  // A key may be read twice (a sign check, then a range); listed once. The
  // keys are the reader's own few names, so the scan stays short.
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
  return node_.member(key);
}

const Node& ObjectReader::require(std::string_view key) {
  const Node* member = find(key);
  if (member == nullptr) fail(node_, "missing key \"" + std::string(key) + "\"");
  return *member;
}

void ObjectReader::finish() const {
  for (const Node& member : node_.children) {
    bool known = false;
    for (std::string_view key : known_) known = known || key == member.key;
    if (known) continue;
    std::string list;
    for (std::string_view key : known_) list += (list.empty() ? "" : ", ") + std::string(key);
    fail(member, "unknown key (known keys: " + list + ")");
  }
}

Fixed read_fixed(const Node& node, Bound bound) {
  const std::string& text = number_text(node, "a number");
  const ParseResult parsed = parse_fixed(text);
  if (!parsed.ok()) fail(node, "bad number " + json::quote(text) + ": " + describe(parsed.error));
  check_bound(node, parsed.value, bound);
  return parsed.value;
}

Fixed read_fixed_within(const Node& node, Fixed lo, Fixed hi, std::string_view unit) {
  const Fixed value = read_fixed(node);
  if (value < lo || value > hi) {
    fail(node, input_bounds::outside(lo, hi, unit));
  }
  return value;
}

int read_int(const Node& node, int lo, int hi) {
  const std::string& text = number_text(node, "an integer");
  const std::string range = "outside " + std::to_string(lo) + ".." + std::to_string(hi);
  const ParseResult parsed = parse_fixed(text);
  if (parsed.error == ParseError::out_of_range) fail(node, range);
  if (!parsed.ok()) fail(node, "bad number " + json::quote(text) + ": " + describe(parsed.error));
  if (floor(parsed.value) != parsed.value) fail(node, "expected an integer, got " + json::quote(text));
  if (parsed.value < Fixed::from_int(lo) || parsed.value > Fixed::from_int(hi)) fail(node, range);
  return static_cast<int>(parsed.value.raw() >> 32);
}

uint64_t read_u64(const Node& node) {
  const std::string& text = number_text(node, "an integer");
  const char* expected = "expected an integer 0..18446744073709551615";
  if (text.empty()) fail(node, expected);
  uint64_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') fail(node, std::string(expected) + ", got " + json::quote(text));
    const auto digit = static_cast<uint64_t>(c - '0');
    if (value > (UINT64_MAX - digit) / 10) fail(node, std::string(expected) + ", got " + json::quote(text));
    value = value * 10 + digit;
  }
  return value;
}

bool read_bool(const Node& node) {
  if (node.kind != Kind::boolean) fail(node, "expected true or false" + got(node));
  return node.boolean;
}

const std::string& read_string(const Node& node) {
  if (node.kind != Kind::string) fail(node, "expected a string" + got(node));
  return node.text;
}

size_t read_choice(const Node& node, const std::vector<std::string_view>& choices) {
  std::string list;
  for (size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) list.append(i + 1 == choices.size() ? " or " : ", ");
    list.append("\"").append(choices[i]).append("\"");
  }
  if (node.kind != Kind::string) fail(node, "expected " + list + got(node));
  for (size_t i = 0; i < choices.size(); ++i) {
    if (node.text == choices[i]) return i;
  }
  fail(node, "expected " + list + ", got " + json::quote(node.text));
}

Vec3 read_vec3(const Node& node, Bound bound) {
  if (node.kind != Kind::array) fail(node, "expected an array of 3 numbers" + got(node));
  if (node.children.size() != 3) {
    fail(node, "expected 3 numbers, got " + std::to_string(node.children.size()));
  }
  return {read_fixed(node.children[0], bound), read_fixed(node.children[1], bound),
          read_fixed(node.children[2], bound)};
}

Vec3 read_vec3_within(const Node& node, Fixed lo, Fixed hi, std::string_view unit) {
  read_vec3(node);  // the shape and the number texts first
  const auto& c = node.children;
  return {read_fixed_within(c[0], lo, hi, unit), read_fixed_within(c[1], lo, hi, unit),
          read_fixed_within(c[2], lo, hi, unit)};
}

Quat read_orientation(const Node& node) {
  ObjectReader reader(node);
  const Node* axis = reader.find("axis");
  const Node* degrees = reader.find("degrees");
  const Node* radians = reader.find("radians");
  const Node* quaternion = reader.find("quaternion");
  reader.finish();
  if (quaternion != nullptr) {
    if (axis != nullptr || degrees != nullptr || radians != nullptr) {
      fail(node, "give either \"quaternion\" or \"axis\" with \"degrees\" or \"radians\", not both");
    }
    if (quaternion->kind != Kind::array) fail(*quaternion, "expected an array of 4 numbers" + got(*quaternion));
    if (quaternion->children.size() != 4) {
      fail(*quaternion, "expected 4 numbers [w, x, y, z], got " + std::to_string(quaternion->children.size()));
    }
    const auto& c = quaternion->children;
    const Quat q{read_fixed(c[0]), read_fixed(c[1]), read_fixed(c[2]), read_fixed(c[3])};
    if (q == Quat{Fixed{}, Fixed{}, Fixed{}, Fixed{}}) fail(*quaternion, "the zero quaternion is no rotation");
    return normalize(q);
  }
  if (axis == nullptr) fail(node, "missing key \"axis\" (or \"quaternion\")");
  if ((degrees == nullptr) == (radians == nullptr)) fail(node, "give the angle as \"degrees\" or \"radians\" (one of them)");
  const Vec3 direction = read_vec3(*axis);
  if (direction == Vec3::zero()) fail(*axis, "the axis must not be zero");
  // degrees -> radians: d * pi / 180 with one rounding of the exact product.
  const Fixed angle = degrees != nullptr ? mul_div(read_fixed(*degrees), pi_q32, Fixed::from_int(180)) : read_fixed(*radians);
  return from_axis_angle(normalize(direction), angle);
}

Material read_material_fields(const Node& node) {
  ObjectReader reader(node);
  Material material;
  read_optional(reader, "static_friction", material.static_friction, Bound::non_negative);
  read_optional(reader, "dynamic_friction", material.dynamic_friction, Bound::non_negative);
  read_optional(reader, "restitution", material.restitution, Bound::unit_interval);
  read_optional(reader, "rolling_resistance", material.rolling_resistance, Bound::unit_interval);
  reader.finish();
  return material;
}

Material read_material(const Node& node, const MaterialTable& table) {
  if (node.kind == Kind::object) return read_material_fields(node);
  if (node.kind != Kind::string) fail(node, "expected a material name or an object" + got(node));
  if (const Material* material = table.find(node.text)) return *material;
  // The first few names, so that a table of thousands stays a one-line error.
  constexpr size_t listed = 8;
  const auto& names = table.names();
  std::string list;
  for (size_t i = 0; i < names.size() && i < listed; ++i) list += (list.empty() ? "" : ", ") + json::quote(names[i]);
  if (names.size() > listed) list += ", ... (" + std::to_string(names.size()) + " in all)";
  fail(node, "unknown material " + json::quote(node.text) + " (defined: " + (list.empty() ? "none" : list) + ")");
}

void read_optional(ObjectReader& reader, std::string_view key, Fixed& field, Bound bound) {
  if (const Node* node = reader.find(key)) field = read_fixed(*node, bound);
}
void read_optional(ObjectReader& reader, std::string_view key, Vec3& field, Bound bound) {
  if (const Node* node = reader.find(key)) field = read_vec3(*node, bound);
}
void read_optional(ObjectReader& reader, std::string_view key, int& field, int lo, int hi) {
  if (const Node* node = reader.find(key)) field = read_int(*node, lo, hi);
}
void read_optional(ObjectReader& reader, std::string_view key, bool& field) {
  if (const Node* node = reader.find(key)) field = read_bool(*node);
}

void read_optional_within(ObjectReader& reader, std::string_view key, Fixed& field, Fixed lo, Fixed hi,
                          std::string_view unit) {
  if (const Node* node = reader.find(key)) field = read_fixed_within(*node, lo, hi, unit);
}
void read_optional_within(ObjectReader& reader, std::string_view key, Vec3& field, Fixed lo, Fixed hi,
                          std::string_view unit) {
  if (const Node* node = reader.find(key)) field = read_vec3_within(*node, lo, hi, unit);
}

}  // namespace bitstep::scene_reader
