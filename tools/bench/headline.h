// The README's small table of headline numbers, made from a bench report's
// CSV files, so that no figure on the front page is copied by hand:
// `bitstep bench --readme README.md` writes it after a run, and
// `bitstep bench headline --check` fails when the README's table is not the
// one the committed report gives.
#pragma once

#include <string>
#include <string_view>

#include "core/error.h"

namespace bitstep::bench {

// The lines that open and close the README's generated block.
inline constexpr std::string_view headline_begin =
    "<!-- headline: generated from tools/report by `bitstep bench --readme README.md`; do not edit -->";
inline constexpr std::string_view headline_end = "<!-- /headline -->";

// The block (markers included) from the text of results.csv and speed.csv;
// an error names the file and line that could not be read.
Result<std::string> headline_block(std::string_view results_csv, std::string_view speed_csv);

// `readme` with the text between its markers (inclusive) replaced by
// `block`; an error when the markers are missing or out of order.
Result<std::string> with_headline(std::string_view readme, std::string_view block);

}  // namespace bitstep::bench
