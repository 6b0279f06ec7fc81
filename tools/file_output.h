// Output files that are never left half-written.
#pragma once

#include <string>

namespace bitstep {

// Writes `text` to `path` through a temporary file renamed into place, so a
// failure never leaves a partial file behind; false with a reason.
bool write_file_atomically(const std::string& path, const std::string& text, std::string& reason);

}  // namespace bitstep
