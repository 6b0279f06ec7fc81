// A progress bar on stderr for long commands: redrawn in place on a
// terminal, one line per finished section otherwise (logs stay readable).
#pragma once

#include <chrono>
#include <string>

namespace bitstep {

class ProgressBar {
 public:
  explicit ProgressBar(int total);
  // One unit of work is done; `label` says what runs next.
  void advance(const std::string& label);
  // A line of its own above the bar (a skipped step, a section done).
  void note(const std::string& text);
  void finish();

 private:
  void draw();

  int total_;
  int done_ = 0;
  std::string label_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace bitstep
