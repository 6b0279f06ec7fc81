// The world's full state as JSON (every value exact: fixed-point numbers as
// the shortest decimal that reads back to the same bits), for `bitstep
// verify --dump-at`, and the first difference between two such dumps, for
// `bitstep diff`.
#pragma once

#include <optional>
#include <string>

#include "core/error.h"
#include "core/world.h"

namespace bitstep {

std::string dump_state(const World& world);

// The first difference between two dumps, as "<JSON path>: <a> vs <b>" with
// the path naming the body (slot), contact or field; nullopt when equal.
// An error when either text is not a dump, its place the dump's name
// (`name_a`, `name_b`: a file) and where in it.
using DumpDifference = std::optional<std::string>;
Result<DumpDifference> diff_dumps(const std::string& a, const std::string& b, const std::string& name_a = "first dump",
                                  const std::string& name_b = "second dump");

}  // namespace bitstep
