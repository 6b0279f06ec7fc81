// A small JSON tree that keeps what exactness needs: objects keep their keys
// in document order, numbers keep their text (the lexeme, never a double:
// numbers go from their decimal text straight to Fixed), and every node
// knows its JSON path ("$.bodies[2].shapes[0]") so that errors can name
// the value they are about.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "replay/limits.h"

namespace bitstep::json {

enum class Kind : uint8_t { null, boolean, number, string, array, object };

// "null", "a boolean", "a number", "a string", "an array", "an object".
const char* describe(Kind kind);

struct Node {
  Kind kind = Kind::null;
  bool boolean = false;
  std::string text;            // number: its lexeme ("5e-1"); string: its (unescaped) value
  std::string key;             // a member of an object: its key
  std::string path;            // "$", "$.bodies[2]", "$.materials[\"oak wood\"]"
  std::vector<Node> children;  // array elements or object members, in document order

  // The member with this key, or nullptr (objects only; keys are unique).
  const Node* member(std::string_view member_key) const;
};

// Nesting deeper than this is refused (it would only mean a hostile file).
inline constexpr int max_depth = limits::max_json_depth;

// Parses strict JSON (RFC 8259, UTF-8). A tree that would take more than
// `max_tree_bytes` (its nodes, texts, keys and paths) is refused at the
// value that crosses it. Never throws. An error's place is where the text
// stopped being a well-formed tree: a byte ("byte 17") for syntax errors,
// a JSON path for duplicate keys and nesting.
Result<Node> parse(std::string_view text, size_t max_tree_bytes = limits::max_json_tree_bytes);

// `text` in double quotes for a one-line message: quotes, backslashes and
// control characters escaped as in JSON, cut to 60 bytes with "...".
std::string quote(std::string_view text);

// Compact JSON text of a tree: numbers as their lexemes (exact), strings
// escaped, members in document order. parse(write(node)) gives the same tree.
std::string write(const Node& node);

// The path of `key` inside the object at `parent_path`.
std::string member_path(const std::string& parent_path, std::string_view key);

}  // namespace bitstep::json
