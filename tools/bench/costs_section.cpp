// `bitstep bench`'s costs section: an 8-frame rollback's cost on shipped
// scenes (tools/bench/costs.h), and wall128's peak memory for bitstep's
// default and the peer engine, each in the peer program.
#include <fmt/core.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "tools/bench/costs.h"
#include "tools/bench/sections.h"

namespace bitstep::bench {

namespace {

constexpr int memory_steps = 10;

struct MemoryRow {
  std::string engine;
  long loaded_kib, peak_kib;
};

std::vector<std::string> rollback_scenes() {
  return {"stack20.json", "pyramid20.json", "wall128.json", "thrown.json", "playground.json"};
}

// Rollbacks from step 60 (1 s in: thrown's cubes in their pile, the
// playground's bodies still moving): rollback.csv. False when a scene fails.
bool measure_rollbacks(Context& context, std::vector<RollbackRow>& rollback) {
  const int rounds = context.options.quick ? 10 : 50;
  for (const std::string& scene : rollback_scenes()) {
    context.progress->advance("rollback " + scene);
    try {
      rollback.push_back(measure_rollback(context.options.scenes, scene, 60, rounds));
    } catch (const std::exception& error) {
      fmt::print(stderr, "bitstep bench: rollback: {}\n", error.what());
      return false;
    }
  }
  std::string csv =
      "scene,from_step,bodies,snapshot_bytes,state_bytes,rounds,snapshot_save_ms,state_save_ms,restore_ms,"
      "rollback_ms,state_restore_ms,state_rollback_ms,frame_share,pushed_rollback_ms,pushed_frame_share,same_bits\n";
  for (const RollbackRow& r : rollback) {
    csv += fmt::format("{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},{:.6g},{:.4g},{}\n", r.scene,
                       r.from_step, r.bodies, r.snapshot_bytes, r.state_bytes, r.rounds, r.snapshot_save_ms,
                       r.state_save_ms, r.restore_ms, r.rollback_ms, r.state_restore_ms, r.state_rollback_ms,
                       r.state_rollback_ms / frame_ms, r.pushed_rollback_ms, r.pushed_rollback_ms / frame_ms,
                       r.same_bits ? 1 : 0);
  }
  return context.write("rollback.csv", csv);
}

// wall128's peak memory in the peer program, bitstep's default and Bullet,
// 10 steps each (every contact of the standing wall exists from the first
// step): memory.csv.
bool measure_memory(Context& context, std::vector<MemoryRow>& memory) {
  for (std::string_view variant : {default_variant, peer_variant}) {
    context.progress->advance(fmt::format("memory wall128 {}", variant));
    std::string output;
    const std::string command = fmt::format("{} memory {} --variant {} --steps {}", quote(context.peer),
                                            quote(context.options.scenes + "/wall128.json"), variant, memory_steps);
    MemoryRow row{std::string(variant), 0, 0};
    if (!capture(command, output) || std::sscanf(output.c_str(), "%ld %ld", &row.loaded_kib, &row.peak_kib) != 2) {
      fmt::print(stderr, "bitstep bench: memory {}: {}\n", variant, output);
      return false;
    }
    memory.push_back(row);
  }
  std::string csv = "scene,engine,steps,loaded_kib,peak_kib\n";
  for (const MemoryRow& r : memory) {
    csv += fmt::format("wall128.json,{},{},{},{}\n", r.engine, memory_steps, r.loaded_kib, r.peak_kib);
  }
  return context.write("memory.csv", csv);
}

std::string rollback_markdown(const std::vector<RollbackRow>& rollback) {
  std::string md = fmt::format(
      "## Costs a game pays\n\nAn {}-frame rollback: restore the state saved at step 60, then {} steps, "
      "against the {:.1f} ms of a 60 Hz frame (mean of {} rounds; every round, either way, must end on the same "
      "state hash). `state`: a rollback state (the step's state alone, saved into a kept buffer, restored in "
      "place); `snapshot`: the whole world's image, restored into a new world. `pushed`: the same rollback "
      "state's, when the input that caused the rollback pushes a body (the scene's last dynamic one, 2 m/s "
      "sideways) at its first step: a resting pile wakes, and this is what a game must budget.\n\n"
      "| scene | bodies | state (bytes/body) | snapshot (bytes/body) | save state (us) | save snapshot (us) | "
      "restore state (us) | restore snapshot (us) | state + {} steps (ms) | snapshot + {} steps (ms) | "
      "share of the frame | pushed: state + {} steps (ms) | pushed: share of the frame | same bits |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
      rollback_frames, rollback_frames, frame_ms, rollback.empty() ? 0 : rollback.front().rounds, rollback_frames,
      rollback_frames, rollback_frames);
  for (const RollbackRow& r : rollback) {
    const double n = static_cast<double>(std::max<size_t>(r.bodies, 1));
    md += fmt::format(
        "| {} | {} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.3g} | {:.3g} | {:.0f}% | {:.3g} | "
        "{:.0f}% | "
        "{} |\n",
        r.scene, r.bodies, static_cast<double>(r.state_bytes) / n, static_cast<double>(r.snapshot_bytes) / n,
        1000 * r.state_save_ms, 1000 * r.snapshot_save_ms, 1000 * r.state_restore_ms, 1000 * r.restore_ms,
        r.state_rollback_ms, r.rollback_ms, 100 * r.state_rollback_ms / frame_ms, r.pushed_rollback_ms,
        100 * r.pushed_rollback_ms / frame_ms, r.same_bits ? "yes" : "**no**");
  }
  return md;
}

std::string memory_markdown(const Context& context, const std::vector<MemoryRow>& memory) {
  if (memory.empty()) return "\nwall128's peak memory: needs the peer program (" + context.peer_note + ").\n\n";
  std::string md = fmt::format(
      "\nPeak resident memory of wall128 (8,256 bricks), each engine in a process of its own (the peer "
      "program), after {} steps; `loaded`: the process after reading the scene, before building the engine.\n\n"
      "| engine | loaded (MiB) | peak (MiB) |\n|---|---:|---:|\n",
      memory_steps);
  for (const MemoryRow& r : memory) {
    md += fmt::format("| {} | {:.1f} | {:.1f} |\n", r.engine, static_cast<double>(r.loaded_kib) / 1024,
                      static_cast<double>(r.peak_kib) / 1024);
  }
  return md + "\n";
}

}  // namespace

int costs_runs(const Context& context) {
  return static_cast<int>(rollback_scenes().size()) + (context.peer.empty() ? 0 : 2);
}

Section run_costs(Context& context) {
  Section section;
  std::vector<RollbackRow> rollback;
  std::vector<MemoryRow> memory;
  section.ok = measure_rollbacks(context, rollback) && (context.peer.empty() || measure_memory(context, memory));
  if (!rollback.empty()) section.markdown = rollback_markdown(rollback) + memory_markdown(context, memory);
  return section;
}

}  // namespace bitstep::bench
