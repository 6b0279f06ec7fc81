#include "tools/cli/thread_option.h"

#include <cstdlib>

namespace bitstep {

bool parse_threads(const char* text, int& out) {
  if (*text < '0' || *text > '9') return false;  // strtol would skip blanks and take a sign
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < 1 || value > max_threads) return false;
  out = static_cast<int>(value);
  return true;
}

std::unique_ptr<ThreadPool> make_pool(int threads) {
  return threads > 1 ? std::make_unique<ThreadPool>(threads) : nullptr;
}

}  // namespace bitstep
