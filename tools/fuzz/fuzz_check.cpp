// The properties every fuzz target checks: a failed one aborts, which
// libFuzzer reports as a crash and keeps the input for.
#include <cstdio>
#include <cstdlib>

#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

void require(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz property failed: %s\n", what);
  std::abort();
}

void require_one_line_error(const std::string& message, const std::string& file) {
  require(!message.empty(), "a refusal has a message");
  require(message.find('\n') == std::string::npos && message.find('\r') == std::string::npos,
          "a refusal's message is one line");
  if (!file.empty()) require(message.rfind(file + ": ", 0) == 0, "a refusal's message starts with the file's name");
}

}  // namespace bitstep::fuzz
