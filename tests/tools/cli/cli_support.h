// Running the bitstep binary from a test: a temporary folder, the command's
// exit status and captured output, and text helpers. BITSTEP_BINARY and
// BITSTEP_SOURCE_DIR come from tests/CMakeLists.txt.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bitstep::test_cli {

inline const std::string scenes_dir = std::string(BITSTEP_SOURCE_DIR) + "/scenes";

// A folder of its own under the system's temporary folder, removed after.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("bitstep_cli_tests_" + name)) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

inline std::string read_all(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

struct Run {
  int status = -1;
  std::string out, err;
};

// Runs `bitstep ARGS` (arguments as shell words, already quoted) in `dir`.
inline Run run_bitstep(const TempDir& dir, const std::string& args) {
  const std::string command = std::string("cd '") + dir.path.string() + "' && '" + BITSTEP_BINARY + "' " + args +
                              " >" + (dir / "stdout.txt") + " 2>" + (dir / "stderr.txt");
  const int raw = std::system(command.c_str());
  Run run;
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.out = read_all(dir / "stdout.txt");
  run.err = read_all(dir / "stderr.txt");
  return run;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace bitstep::test_cli
