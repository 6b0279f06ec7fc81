#include "replay/state_dump.h"

#include <initializer_list>
#include <variant>

#include "fixed/decimal.h"
#include "replay/json_tree.h"

namespace bitstep {

namespace {

std::string num(Fixed f) { return to_string(f); }
std::string list(std::initializer_list<std::string> items) {
  std::string out = "[";
  bool first = true;
  for (const std::string& item : items) {
    if (!first) out += ", ";
    out += item;
    first = false;
  }
  out += "]";
  return out;
}
std::string vec(Vec3 v) { return list({num(v.x), num(v.y), num(v.z)}); }
std::string quat(Quat q) { return list({num(q.w), num(q.x), num(q.y), num(q.z)}); }
std::string mat(const Mat33& m) { return list({vec(m.rows[0]), vec(m.rows[1]), vec(m.rows[2])}); }

const char* type_name(BodyType type) {
  switch (type) {
    case BodyType::static_body: return "static";
    case BodyType::kinematic: return "kinematic";
    case BodyType::dynamic: return "dynamic";
  }
  return "?";
}

// The first difference under `a` and `b` (same path), or nullopt.
std::optional<std::string> first_difference(const json::Node& a, const json::Node& b) {
  if (a.kind != b.kind) return a.path + ": " + json::describe(a.kind) + " vs " + json::describe(b.kind);
  if (a.kind != json::Kind::array && a.kind != json::Kind::object) {
    if (a.text == b.text && a.boolean == b.boolean) return std::nullopt;
    return a.path + ": " + json::write(a) + " vs " + json::write(b);
  }
  const size_t common = std::min(a.children.size(), b.children.size());
  for (size_t i = 0; i < common; ++i) {
    if (a.kind == json::Kind::object && a.children[i].key != b.children[i].key) {
      return a.path + ": key " + json::quote(a.children[i].key) + " vs " + json::quote(b.children[i].key);
    }
    if (auto d = first_difference(a.children[i], b.children[i])) return d;
  }
  if (a.children.size() != b.children.size()) {
    return a.path + ": " + std::to_string(a.children.size()) + " vs " + std::to_string(b.children.size()) + " entries";
  }
  return std::nullopt;
}

}  // namespace

// Appends "key": value pairs of one JSON object.
struct ObjectWriter {
  std::string& out;
  bool first = true;
  void field(const char* key, const std::string& value) {
    out += first ? "{\"" : ", \"";
    out += key;
    out += "\": ";
    out += value;
    first = false;
  }
  void close() { out += first ? "{}" : "}"; }
};

std::string dump_state(const World& world) {
  std::string out = "{\n  \"format\": \"bitstep-state\",\n  \"step\": ";
  out += std::to_string(world.step_count());
  out += ",\n  \"bodies\": [";
  for (size_t i = 0; i < world.bodies().size(); ++i) {
    const Body& b = world.bodies()[i];
    out += i == 0 ? "\n    " : ",\n    ";
    ObjectWriter o{out};
    o.field("slot", std::to_string(i));
    o.field("alive", b.alive ? "true" : "false");
    o.field("generation", std::to_string(b.generation));
    if (b.alive) {
      std::string type = "\"";
      type += type_name(b.type);
      type += "\"";
      o.field("type", type);
      o.field("position", vec(b.pose.position));
      o.field("orientation", quat(b.pose.orientation));
      o.field("linear_velocity", vec(b.linear_velocity));
      o.field("angular_velocity", vec(b.angular_velocity));
      o.field("force", vec(b.force));
      o.field("torque", vec(b.torque));
      o.field("inverse_mass", num(b.inverse_mass));
      o.field("inverse_inertia_world", mat(b.inverse_inertia_world));
      o.field("shapes", std::to_string(b.shapes.size()));
      if (world.settings().sleep_method != SleepMethod::off) {
        o.field("asleep", b.asleep ? "true" : "false");
        o.field("sleep_motion", num(b.sleep_motion));
        o.field("sleepy_steps", std::to_string(b.sleepy_steps));
        o.field("sleep_reference", "{\"position\": " + vec(b.sleep_reference.position) +
                                       ", \"orientation\": " + quat(b.sleep_reference.orientation) + "}");
      }
    }
    o.close();
  }
  out += "\n  ],\n  \"free_slots\": [";
  for (size_t i = 0; i < world.free_slots().size(); ++i) {
    if (i > 0) out += ", ";
    out += std::to_string(world.free_slots()[i]);
  }
  out += "],\n  \"contacts\": [";
  for (size_t i = 0; i < world.contacts().size(); ++i) {
    const Contact& c = world.contacts()[i];
    const Manifold& m = c.manifold;
    out += i == 0 ? "\n    " : ",\n    ";
    ObjectWriter o{out};
    o.field("bodies", list({std::to_string(c.key.body_a), std::to_string(c.key.body_b)}));
    o.field("shapes", list({std::to_string(c.key.shape_a), std::to_string(c.key.shape_b)}));
    o.field("normal", vec(m.normal));
    o.field("friction_impulse", list({num(m.friction_impulse[0]), num(m.friction_impulse[1])}));
    o.field("twist_impulse", num(m.twist_impulse));
    o.field("rolling_impulse", list({num(m.rolling_impulse[0]), num(m.rolling_impulse[1])}));
    std::string points = "[";
    for (int k = 0; k < m.point_count; ++k) {
      const ContactPoint& p = m.points[static_cast<size_t>(k)];
      if (k > 0) points += ", ";
      ObjectWriter point{points};
      point.field("feature", std::to_string(p.feature));
      point.field("position", vec(p.position));
      point.field("depth", num(p.depth));
      point.field("normal_impulse", num(p.normal_impulse));
      point.close();
    }
    points += "]";
    o.field("points", points);
    o.close();
  }
  out += "\n  ]\n}\n";
  return out;
}

DumpDifference diff_dumps(const std::string& a, const std::string& b) {
  auto tree_a = json::parse(a);
  auto tree_b = json::parse(b);
  if (const auto* e = std::get_if<json::SyntaxError>(&tree_a)) return {false, "first dump: " + e->where + ": " + e->reason, {}};
  if (const auto* e = std::get_if<json::SyntaxError>(&tree_b)) return {false, "second dump: " + e->where + ": " + e->reason, {}};
  const json::Node& root_a = std::get<json::Node>(tree_a);
  const json::Node& root_b = std::get<json::Node>(tree_b);
  for (const json::Node* root : {&root_a, &root_b}) {
    const json::Node* format = root->member("format");
    if (format == nullptr || format->text != "bitstep-state") return {false, "not a bitstep-state dump", {}};
  }
  DumpDifference d{true, {}, first_difference(root_a, root_b)};
  // Name the bodies of a contact that differs.
  const std::string prefix = "$.contacts[";
  if (d.first && d.first->compare(0, prefix.size(), prefix) == 0) {
    const size_t index = std::stoul(d.first->substr(prefix.size()));
    const json::Node* contacts = root_a.member("contacts");
    if (contacts != nullptr && index < contacts->children.size()) {
      if (const json::Node* bodies = contacts->children[index].member("bodies")) {
        *d.first += " (the contact between bodies " + json::write(*bodies) + ")";
      }
    }
  }
  return d;
}

}  // namespace bitstep
