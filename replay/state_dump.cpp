#include "replay/state_dump.h"

#include <array>
#include <type_traits>
#include <utility>

#include "fixed/decimal.h"
#include "replay/json_tree.h"
#include "replay/state_description.h"

namespace bitstep {

namespace {

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


// Writes the state description as JSON: one field per line at the top,
// one line per item of a top-level list, everything deeper inline. A list
// item is an object of its named fields (opened at the first), or the bare
// value of an unnamed one.
class JsonWriter {
 public:
  static constexpr bool reading = false;

  std::string finish() {
    out_ += "\n}\n";
    return std::move(out_);
  }

  template <class T>
  void integer(const char* name, const T& value, int, uint64_t, uint64_t) {
    key(name);
    if constexpr (std::is_same_v<T, bool>) {
      out_ += value ? "true" : "false";
    } else {
      out_ += std::to_string(value);
    }
  }
  template <class T>
  void integers(const char* name, const T& a, const T& b, int, uint64_t) {
    key(name);
    out_ += "[";
    out_ += std::to_string(a);
    out_ += ", ";
    out_ += std::to_string(b);
    out_ += "]";
  }
  template <class E, size_t N>
  void choice(const char* name, const E& value, const std::array<const char*, N>& names, size_t) {
    key(name);
    const size_t i = static_cast<size_t>(value);
    out_ += i < N ? json::quote(names[i]) : std::to_string(i);
  }
  template <size_t N>
  void flags(const char* name, const uint8_t& bits, const std::array<const char*, N>& names) {
    key(name);
    out_ += "[";
    bool first = true;
    for (size_t i = 0; i < N; ++i) {
      if ((bits & (1u << i)) == 0) continue;
      out_ += first ? "" : ", ";
      out_ += json::quote(names[i]);
      first = false;
    }
    out_ += "]";
  }
  void fixed(const char* name, Fixed f) {
    key(name);
    out_ += to_string(f);
  }
  void fixeds(const char* name, const Fixed* values, size_t n) {
    key(name);
    out_ += "[";
    for (size_t i = 0; i < n; ++i) {
      out_ += i == 0 ? "" : ", ";
      out_ += to_string(values[i]);
    }
    out_ += "]";
  }
  void vec(const char* name, Vec3 v) {
    const Fixed values[] = {v.x, v.y, v.z};
    fixeds(name, values, 3);
  }
  void quat(const char* name, Quat q) {
    const Fixed values[] = {q.w, q.x, q.y, q.z};
    fixeds(name, values, 4);
  }
  void mat(const char* name, const Mat33& m) {
    key(name);
    out_ += "[";
    for (size_t r = 0; r < 3; ++r) {
      out_ += r == 0 ? "" : ", ";
      vec(nullptr, m.rows[r]);
    }
    out_ += "]";
  }
  template <class F>
  void object(const char* name, F&& describe) {
    key(name);
    out_ += "{";
    levels_.push_back({});
    describe();
    levels_.pop_back();
    out_ += "}";
  }
  template <class T, class F>
  void list(const char* name, const std::vector<T>& items, size_t, uint64_t, const char* index_key, F&& describe) {
    key(name);
    const bool lines = levels_.size() == 1;  // a top-level list: one item per line
    out_ += "[";
    for (size_t i = 0; i < items.size(); ++i) {
      out_ += lines ? (i == 0 ? "\n    " : ",\n    ") : (i == 0 ? "" : ", ");
      item([&] { describe(items[i]); }, index_key, i);
    }
    out_ += lines && !items.empty() ? "\n  ]" : "]";
  }
  template <class F>
  void items(const char* name, size_t count, F&& describe) {
    key(name);
    out_ += "[";
    for (size_t i = 0; i < count; ++i) {
      out_ += i == 0 ? "" : ", ";
      item([&] { describe(i); }, nullptr, i);
    }
    out_ += "]";
  }
  template <class Test, class Reason>
  void require(Test&&, Reason&&) {}  // a world's own state holds
  template <class F>
  void trailing(bool present, bool in_dump, F&& describe) {
    if (present || in_dump) describe();  // the joints always, empty or not; the filters where there are any
  }
  template <class F>
  void statics(F&& describe) {
    describe();
  }
  void identity(const Body&) {}  // a serial is not state

 private:
  struct Level {
    bool first = true;
    bool item = false;    // a list item, not yet known to be an object
    bool opened = false;  // an item whose "{" is written
  };

  template <class F>
  void item(F&& describe, const char* index_key, size_t index) {
    levels_.push_back({true, true, false});
    if (index_key != nullptr) integer(index_key, index, 0, 0, 0);
    describe();
    const bool opened = levels_.back().opened;
    levels_.pop_back();
    if (opened) out_ += "}";
  }

  // The separator and "name": before a value; a list item's first named
  // field opens its object.
  void key(const char* name) {
    Level& level = levels_.back();
    if (name == nullptr) return;  // a list's bare item
    if (level.item && !level.opened) {
      out_ += "{";
      level.opened = true;
    }
    if (levels_.size() == 1) {
      out_ += level.first ? "\n  " : ",\n  ";
    } else if (!level.first) {
      out_ += ", ";
    }
    level.first = false;
    out_ += json::quote(name);
    out_ += ": ";
  }

  std::string out_ = "{\n  \"format\": \"bitstep-state\"";
  std::vector<Level> levels_{Level{false, false, false}};
};

}  // namespace

std::string dump_state(const World& world) {
  const uint64_t step = world.step_count();
  JsonWriter writer;
  describe_state(writer, state_parts_of(world, step));
  return writer.finish();
}

Result<DumpDifference> diff_dumps(const std::string& a, const std::string& b, const std::string& name_a,
                                  const std::string& name_b) {
  const Result<json::Node> tree_a = json::parse(a);
  if (!tree_a.ok()) return tree_a.error().within(name_a);
  const Result<json::Node> tree_b = json::parse(b);
  if (!tree_b.ok()) return tree_b.error().within(name_b);
  for (const auto& [root, name] : {std::pair{&tree_a.value(), &name_a}, std::pair{&tree_b.value(), &name_b}}) {
    const json::Node* format = root->member("format");
    if (format == nullptr || format->text != "bitstep-state") return Error{*name, "not a bitstep-state dump"};
  }
  const json::Node& root_a = tree_a.value();
  DumpDifference first = first_difference(root_a, tree_b.value());
  // Name the bodies of a contact or joint that differs.
  for (const char* list : {"contacts", "joints"}) {
    const std::string prefix = std::string("$.") + list + "[";
    if (!first || first->compare(0, prefix.size(), prefix) != 0) continue;
    const size_t index = std::stoul(first->substr(prefix.size()));
    const json::Node* items = root_a.member(list);
    if (items == nullptr || index >= items->children.size()) continue;
    const json::Node& item = items->children[index];
    const json::Node* bodies = item.member("bodies");
    if (bodies == nullptr) continue;
    const json::Node* type = item.member("type");
    const std::string what = type != nullptr ? "the " + type->text + " joint" : "the contact";
    *first += " (" + what + " between bodies " + json::write(*bodies) + ")";
  }
  return first;
}

}  // namespace bitstep
