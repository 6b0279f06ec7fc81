// Output files that are never left half-written.
#pragma once

#include <cstdio>
#include <string>

namespace bitstep {

// A file written in pieces under a temporary name (path + ".partial") and
// renamed into place by commit(), so that a failure, or a run stopped
// half-way, never leaves a partial file under the real name. An uncommitted
// file is removed when the AtomicFile goes away.
class AtomicFile {
 public:
  AtomicFile() = default;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // Creates the temporary file; false with a reason.
  bool open(const std::string& path, std::string& reason);
  std::FILE* stream() { return file_; }
  // Closes the temporary file and renames it to the path; false with a
  // reason (a write that failed on the way is found here).
  bool commit(std::string& reason);

 private:
  void discard();

  std::string path_, temporary_;
  std::FILE* file_ = nullptr;
};

// Writes `text` to `path` through a temporary file renamed into place, so a
// failure never leaves a partial file behind; false with a reason.
bool write_file_atomically(const std::string& path, const std::string& text, std::string& reason);

}  // namespace bitstep
