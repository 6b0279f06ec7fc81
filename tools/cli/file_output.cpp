#include "tools/cli/file_output.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace bitstep {

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (file_ != nullptr) std::fclose(file_);
  file_ = nullptr;
  if (!temporary_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
    temporary_.clear();
  }
}

bool AtomicFile::open(const std::string& path, std::string& reason) {
  discard();
  path_ = path;
  temporary_ = path + ".partial";
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr) {
    // Named by the path the user gave (the temporary sits next to it).
    reason = "cannot write " + path_ + ": " + std::strerror(errno);
    temporary_.clear();  // nothing was created
    return false;
  }
  return true;
}

bool AtomicFile::commit(std::string& reason) {
  if (file_ == nullptr) {
    reason = "cannot write " + path_ + ": the file is not open";
    return false;
  }
  const bool written = std::ferror(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed) {
    reason = "cannot write " + path_ + ": " + std::strerror(errno);
    discard();
    return false;
  }
  std::error_code error;
  std::filesystem::rename(temporary_, path_, error);
  if (error) {
    reason = "cannot rename " + temporary_ + " to " + path_ + ": " + error.message();
    discard();
    return false;
  }
  temporary_.clear();
  return true;
}

bool write_file_atomically(const std::string& path, const std::string& text, std::string& reason) {
  AtomicFile file;
  if (!file.open(path, reason)) return false;
  std::fwrite(text.data(), 1, text.size(), file.stream());
  return file.commit(reason);
}

}  // namespace bitstep
