#include "replay/json_tree.h"

#include <nlohmann/json.hpp>

#include <set>

namespace bitstep::json {

const char* describe(Kind kind) {
  switch (kind) {
    case Kind::null: return "null";
    case Kind::boolean: return "a boolean";
    case Kind::number: return "a number";
    case Kind::string: return "a string";
    case Kind::array: return "an array";
    case Kind::object: return "an object";
  }
  return "an unknown value";
}

const Node* Node::member(std::string_view member_key) const {
  if (kind != Kind::object) return nullptr;
  for (const Node& child : children) {
    if (child.key == member_key) return &child;
  }
  return nullptr;
}

namespace {

// Keys longer than a quoted excerpt are written quoted (and so cut to 60
// bytes) even when they are identifiers: every node stores its path, and an
// uncut megabyte key over an array of 10^5 elements would be 10^11 bytes.
constexpr size_t max_plain_key_bytes = 60;

bool is_identifier(std::string_view key) {
  if (key.empty() || key.size() > max_plain_key_bytes) return false;
  for (size_t i = 0; i < key.size(); ++i) {
    const char c = key[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && i > 0)) return false;
  }
  return true;
}

// Builds the tree from nlohmann's SAX events. Open arrays and objects wait on
// a stack and move into their parent when they close, so no pointer into a
// growing vector is ever kept. Work grows with the text, not its square:
// each value is placed once, and each key is checked against an ordered
// index of its object's keys (O(log n) comparisons, where a scan of the
// members made an object of n keys cost O(n^2)).
class TreeBuilder {
 public:
  explicit TreeBuilder(size_t max_tree_bytes) : max_tree_bytes_(max_tree_bytes) {}

  using number_integer_t = nlohmann::json::number_integer_t;
  using number_unsigned_t = nlohmann::json::number_unsigned_t;
  using number_float_t = nlohmann::json::number_float_t;
  using string_t = nlohmann::json::string_t;
  using binary_t = nlohmann::json::binary_t;

  bool null() { return add_scalar(Node{}); }
  bool boolean(bool value) {
    Node node;
    node.kind = Kind::boolean;
    node.boolean = value;
    return add_scalar(std::move(node));
  }
  // Integers arrive as exact integers; their decimal text is their lexeme.
  bool number_integer(number_integer_t value) { return add_number(std::to_string(value)); }
  bool number_unsigned(number_unsigned_t value) { return add_number(std::to_string(value)); }
  // The double nlohmann computed is ignored: only the lexeme is kept.
  bool number_float(number_float_t /*unused*/, const string_t& lexeme) { return add_number(lexeme); }
  bool string(string_t& value) {
    Node node;
    node.kind = Kind::string;
    node.text = std::move(value);
    return add_scalar(std::move(node));
  }
  bool binary(binary_t& /*unused*/) { return fail("$", "binary values are not JSON"); }

  bool start_object(std::size_t /*unused*/) { return open(Kind::object); }
  bool end_object() { return close(); }
  bool start_array(std::size_t /*unused*/) { return open(Kind::array); }
  bool end_array() { return close(); }
  bool key(string_t& value) {
    OpenValue& object = open_.back();
    // An ordered set, not a hash set: no crafted set of keys can make it
    // slow, and it is only asked "seen before?" (members keep document order).
    if (!object.keys.insert(value).second) return fail(member_path(object.node.path, value), "duplicate key");
    pending_key_ = std::move(value);
    return true;
  }

  bool parse_error(std::size_t position, const std::string& /*last_token*/, const nlohmann::json::exception& ex) {
    return fail("byte " + std::to_string(position), "malformed JSON: " + clean_message(ex.what()));
  }

  bool failed() const { return failed_; }
  Error error() const { return error_; }
  Node take_root() { return std::move(root_); }

 private:
  // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax
  // error ..." -> "line 1, column 5: syntax error ...".
  static std::string clean_message(std::string_view what) {
    const std::string_view marker = "parse error at ";
    if (const size_t at = what.find(marker); at != std::string_view::npos) what.remove_prefix(at + marker.size());
    return std::string(what);
  }

  bool fail(std::string where, std::string reason) {
    if (!failed_) error_ = {std::move(where), std::move(reason)};
    failed_ = true;
    return false;
  }

  // The path of the next value: a member of the open object, the next
  // element of the open array, or the root.
  std::string next_path() const {
    if (open_.empty()) return "$";
    const Node& parent = open_.back().node;
    if (parent.kind == Kind::object) return member_path(parent.path, pending_key_);
    return parent.path + "[" + std::to_string(parent.children.size()) + "]";
  }

  // Counts a node's memory (its node, text, path, and its key twice: the
  // member's and the object's index) against the limit;
  // false (failed) when it crosses it.
  bool count(const Node& node) {
    tree_bytes_ += sizeof(Node) + node.path.size() + node.text.size() + 2 * pending_key_.size();
    if (tree_bytes_ <= max_tree_bytes_) return true;
    return fail(node.path, "the JSON tree would take more than the limit of " + std::to_string(max_tree_bytes_) +
                               " bytes in memory");
  }

  bool place(Node node) {
    node.path = next_path();
    if (!count(node)) return false;
    if (open_.empty()) {
      root_ = std::move(node);
      return true;
    }
    Node& parent = open_.back().node;
    if (parent.kind == Kind::object) node.key = std::move(pending_key_);
    parent.children.push_back(std::move(node));
    return true;
  }

  bool add_scalar(Node node) { return place(std::move(node)); }
  bool add_number(std::string lexeme) {
    Node node;
    node.kind = Kind::number;
    node.text = std::move(lexeme);
    return add_scalar(std::move(node));
  }

  bool open(Kind kind) {
    Node node;
    node.kind = kind;
    node.path = next_path();
    if (static_cast<int>(open_.size()) >= max_depth) {
      return fail(node.path, "nesting deeper than " + std::to_string(max_depth) + " levels");
    }
    if (!count(node)) return false;
    if (!open_.empty() && open_.back().node.kind == Kind::object) node.key = std::move(pending_key_);
    open_.push_back({std::move(node), {}});
    return true;
  }

  bool close() {
    Node node = std::move(open_.back().node);
    open_.pop_back();
    if (open_.empty()) {
      root_ = std::move(node);
    } else {
      open_.back().node.children.push_back(std::move(node));
    }
    return true;
  }

  // An array or object being read, with the keys seen so far (objects).
  struct OpenValue {
    Node node;
    std::set<std::string, std::less<>> keys;
  };

  Node root_;
  std::vector<OpenValue> open_;
  std::string pending_key_;
  size_t max_tree_bytes_;
  size_t tree_bytes_ = 0;
  bool failed_ = false;
  Error error_;
};

}  // namespace

std::string quote(std::string_view text) {
  constexpr size_t max_bytes = 60;
  std::string out = "\"";
  for (size_t i = 0; i < text.size() && i < max_bytes; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      const char* hex = "0123456789abcdef";
      out += "\\u00";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (text.size() > max_bytes) out += "...";
  return out + "\"";
}

std::string member_path(const std::string& parent_path, std::string_view key) {
  if (is_identifier(key)) return parent_path + "." + std::string(key);
  return parent_path + "[" + quote(key) + "]";
}

Result<Node> parse(std::string_view text, size_t max_tree_bytes) {
  TreeBuilder builder(max_tree_bytes);
  try {
    const bool ok = nlohmann::json::sax_parse(text.begin(), text.end(), &builder);
    if (!ok || builder.failed()) {
      if (builder.failed()) return builder.error();
      return Error{"$", "malformed JSON"};
    }
  } catch (const std::exception& e) {  // only allocation failure can get here
    return Error{"$", std::string("cannot parse: ") + e.what()};
  }
  return builder.take_root();
}

namespace {

void write_string(std::string_view text, std::string& out) {
  static constexpr char hex[] = "0123456789abcdef";
  out += '"';
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20) {
      out += "\\u00";
      out += hex[byte >> 4];
      out += hex[byte & 15];
    } else {
      out += c;
    }
  }
  out += '"';
}

void write_node(const Node& node, std::string& out) {
  switch (node.kind) {
    case Kind::null: out += "null"; break;
    case Kind::boolean: out += node.boolean ? "true" : "false"; break;
    case Kind::number: out += node.text; break;
    case Kind::string: write_string(node.text, out); break;
    case Kind::array:
    case Kind::object: {
      const bool object = node.kind == Kind::object;
      out += object ? '{' : '[';
      for (size_t i = 0; i < node.children.size(); ++i) {
        if (i > 0) out += ", ";
        if (object) {
          write_string(node.children[i].key, out);
          out += ": ";
        }
        write_node(node.children[i], out);
      }
      out += object ? '}' : ']';
      break;
    }
  }
}

}  // namespace

std::string write(const Node& node) {
  std::string out;
  write_node(node, out);
  return out;
}

}  // namespace bitstep::json
