// The world's full state as JSON (every value exact: fixed-point numbers as
// the shortest decimal that reads back to the same bits), for `bitstep
// verify --dump-at`, and the first difference between two such dumps, for
// `bitstep diff`.
#pragma once

#include <optional>
#include <string>

#include "core/world.h"

namespace bitstep {

std::string dump_state(const World& world);

// The first difference between two dumps, as "<JSON path>: <a> vs <b>" with
// the path naming the body (slot), contact or field; nullopt when equal.
// Fails with a reason when either text is not a dump.
struct DumpDifference {
  bool readable = true;
  std::string reason;                // when not readable
  std::optional<std::string> first;  // the first difference
};
DumpDifference diff_dumps(const std::string& a, const std::string& b);

}  // namespace bitstep
