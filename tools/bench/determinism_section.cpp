// `bitstep bench`'s determinism section: the final state hash of bitstep's
// default and of the peer engine from the peer programs built at -O0 and at
// -O3 -ffast-math, and bitstep's from this build.
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

#include "tools/bench/bitstep_engine.h"
#include "tools/bench/scene_specs.h"
#include "tools/bench/sections.h"

namespace bitstep::bench {

namespace {

constexpr int steps = 300;

struct HashRow {
  std::string engine, scene, build_o0, build_fast, this_build;
};

// The hash from each peer program (and this build's, for bitstep); false
// (noted) when a program fails.
bool hash_row(Context& context, const std::string& o0, const std::string& fast, HashRow& row) {
  bool ok = true;
  const std::string path = context.options.scenes + "/" + row.scene;
  for (auto [program, out] : {std::pair{o0, &row.build_o0}, std::pair{fast, &row.build_fast}}) {
    const std::string command =
        fmt::format("{} hash {} --variant {} --steps {}", quote(program), quote(path), row.engine, steps);
    if (!capture(command, *out)) {
      context.progress->note("bitstep bench: " + command + " failed: " + *out);
      ok = false;
    }
    while (!out->empty() && (out->back() == '\n' || out->back() == '\r')) out->pop_back();
  }
  if (row.engine == default_variant) row.this_build = bitstep_hash(path, steps);
  return ok;
}

bool same_bits(const HashRow& r) {
  return r.build_o0 == r.build_fast && (r.this_build == "-" || r.this_build == r.build_o0);
}

std::string determinism_markdown(const std::vector<HashRow>& hashes) {
  std::string md = "## Determinism across builds\n\n";
  md += "Final state hash after 300 steps at 60 Hz, 10 iterations, from the peer program compiled "
        "(with bitstep's sources) at -O0 and at -O3 -ffast-math, and from this bitstep. Debian's Bullet "
        "library is a prebuilt binary: only its header-inlined code changes with these flags.\n\n"
        "| engine | scene | -O0 | -O3 -ffast-math | this build | same bits? |\n|---|---|---|---|---|---|\n";
  for (const HashRow& r : hashes) {
    const bool same = same_bits(r);
    md += fmt::format("| {} | {} | `{}` | `{}` | `{}` | {} |\n", r.engine, r.scene, r.build_o0, r.build_fast,
                      r.this_build, same ? "yes" : "**no**");
  }
  const bool bitstep_differs = std::any_of(
      hashes.begin(), hashes.end(), [](const HashRow& r) { return r.engine == default_variant && !same_bits(r); });
  if (bitstep_differs) {
    md +=
        "\nA **no** on bitstep is a determinism bug, or peer programs built from older sources than this bitstep: "
        "`cmake --build` of one target leaves the others as they were. Build every target "
        "(`cmake --build build/release`) and run this section again before reading it as a bug.\n";
  }
  return md + "\n";
}

}  // namespace

int determinism_runs(const Context&) { return 1; }

Section run_determinism(Context& context) {
  Section section;
  context.progress->advance("determinism hashes");
  const std::string dir = executable_dir();
  const std::string o0 = dir + "/bitstep-peer-O0", fast = dir + "/bitstep-peer-O3-fast-math";
  if (access(o0.c_str(), X_OK) != 0 || access(fast.c_str(), X_OK) != 0) {
    const std::string note =
        "skipped: the peer programs bitstep-peer-O0 / bitstep-peer-O3-fast-math were not built "
        "(they need libbullet-dev and the CMake option BITSTEP_FLAG_PEERS, on unless tools/test.sh "
        "turned it off: `cmake --build build/release` after tools/run.sh builds them)";
    context.progress->note("determinism " + note);
    section.markdown = "## Determinism across builds\n\n" + note + "\n\n";
    return section;
  }
  std::vector<HashRow> hashes;
  for (const char* scene : {"stack20.json", "thrown.json"}) {
    for (const std::string& engine : {std::string(default_variant), std::string(peer_variant)}) {
      HashRow row{engine, scene, {}, {}, "-"};
      section.ok = hash_row(context, o0, fast, row) && section.ok;
      hashes.push_back(row);
    }
  }
  std::string csv = "engine,scene,steps,hash_O0,hash_O3_fast_math,hash_this_build\n";
  for (const HashRow& r : hashes) {
    csv += fmt::format("{},{},{},{},{},{}\n", r.engine, r.scene, steps, r.build_o0, r.build_fast, r.this_build);
  }
  section.ok = context.write("determinism.csv", csv) && section.ok;
  section.markdown = determinism_markdown(hashes);
  return section;
}

}  // namespace bitstep::bench
