#include "tools/cli/progress_bar.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace bitstep {

ProgressBar::ProgressBar(int total)
    : total_(std::max(total, 1)), terminal_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()) {}

void ProgressBar::advance(const std::string& label) {
  done_ = std::min(done_ + 1, total_);
  label_ = label;
  draw();
}

void ProgressBar::note(const std::string& text) {
  if (terminal_) fmt::print(stderr, "\r\033[K");
  fmt::print(stderr, "{}\n", text);
  draw();
}

void ProgressBar::draw() {
  if (!terminal_) return;
  constexpr int width = 30;
  const int filled = done_ * width / total_;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
  fmt::print(stderr, "\r\033[K[{:#<{}}{:.<{}}] {:3}% {:5.0f} s  {}", "", filled, "", width - filled,
             done_ * 100 / total_, elapsed.count(), label_.substr(0, 60));
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (terminal_) fmt::print(stderr, "\r\033[K");
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
  fmt::print(stderr, "done in {:.0f} s\n", elapsed.count());
}

}  // namespace bitstep
