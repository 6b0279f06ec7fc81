// The fuzz targets' entry points (tools/fuzz/fuzz_targets.h) in a normal
// build: every committed seed (tools/fuzz/corpus/<target>/) must be
// accepted, and every input a fuzzer once crashed on
// (tools/fuzz/regressions/<target>/) must now be refused with a one-line
// error or accepted, without a crash and with the target's properties
// holding (a broken one aborts the test).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tools/fuzz/fuzz_targets.h"

namespace {

using Entry = bitstep::fuzz::Outcome (*)(std::span<const uint8_t>);

std::vector<std::filesystem::path> files_in(const std::string& folder) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path dir = std::filesystem::path(BITSTEP_SOURCE_DIR) / folder;
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<uint8_t> bytes_of(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void check_target(const std::string& target, Entry entry) {
  const auto seeds = files_in("tools/fuzz/corpus/" + target);
  REQUIRE(seeds.size() >= 5);
  for (const auto& path : seeds) {
    INFO(path.string());
    const auto outcome = entry(bytes_of(path));
    INFO(outcome.error);
    CHECK(outcome.accepted);
  }
  for (const auto& path : files_in("tools/fuzz/regressions/" + target)) {
    INFO(path.string());
    const auto outcome = entry(bytes_of(path));
    if (!outcome.accepted) {
      CHECK(!outcome.error.empty());
      CHECK(outcome.error.find('\n') == std::string::npos);
    }
  }
}

}  // namespace

TEST_CASE("fuzz seeds and regressions: the scene reader", "[fuzz]") {
  check_target("scene", bitstep::fuzz::scene_reader);
}

TEST_CASE("fuzz seeds and regressions: the replay reader", "[fuzz]") {
  check_target("replay", bitstep::fuzz::replay_reader);
}

TEST_CASE("fuzz seeds and regressions: the settings override", "[fuzz]") {
  check_target("settings", bitstep::fuzz::settings_override);
}

TEST_CASE("fuzz seeds and regressions: snapshot restore", "[fuzz]") {
  check_target("snapshot", bitstep::fuzz::snapshot_restore);
}

TEST_CASE("fuzz seeds and regressions: the packet decoder", "[fuzz]") {
  check_target("packet", bitstep::fuzz::packet_decoder);
}

TEST_CASE("fuzz seeds and regressions: C API call sequences", "[fuzz]") {
  check_target("capi", bitstep::fuzz::capi_calls);
}
