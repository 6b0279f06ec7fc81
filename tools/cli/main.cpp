// The bitstep command line.
#include <fmt/core.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "fixed/checked.h"
#include "fixed/known_answer.h"
#include "fixed/u128.h"
#include "tools/bench/command.h"
#include "tools/bench/fixed_ops.h"
#include "tools/bench/queries.h"
#include "tools/bench/session.h"
#include "tools/bench/sleep.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/options.h"
#include "tools/cli/peer_command.h"
#include "tools/cli/replay_command.h"
#include "tools/cli/run_command.h"
#include "tools/cli/synctest_command.h"

namespace {

constexpr const char* usage =
    "usage: bitstep <command> [options]   (bitstep <command> --help: that command's options)\n"
    "\n"
    "commands:\n"
    "  run SCENE [--steps N] [--seconds S] [--hash-every K] [--json] [--settings JSON]\n"
    "            [--snapshot-at K FILE] [--restore FILE]\n"
    "            [--trace FILE [--trace-every K] [--trace-format csv|jsonl]] [--threads N] [--events]\n"
    "                           run a scene: per-second summary and the final state hash;\n"
    "                           --events prints each step's contact and sensor begin/end events\n"
    "                           (a body that left the world's bound prints without it);\n"
    "                           --settings overrides scene settings: '{\"sleep\": \"still\"}';\n"
    "                           --trace writes every body's pose and velocities every K-th step\n"
    "  record SCENE [--inputs FILE] [--settings JSON] [--embed-scene] [--threads N] [--trace FILE ...]\n"
    "         --steps N -o REPLAY\n"
    "                           run a scene with inputs and write a replay with its hash chain;\n"
    "                           the replay keeps --settings (else that of a replay given as --inputs);\n"
    "                           --embed-scene puts the scene itself in the replay\n"
    "  verify REPLAY... [--dump-at STEP FILE] [--trace FILE ...] [--threads N]\n"
    "                           re-run replays; exit 0 only if every step's hash matches;\n"
    "                           --dump-at writes the full state after STEP as exact JSON;\n"
    "                           record's and verify's --trace (one replay) is run's, with the inputs;\n"
    "                           --threads N: N workers step the world (the same bits for any N)\n"
    "  diff DUMP_A DUMP_B       the first body, contact or field where two dumps differ\n"
    "  synctest SCENE|REPLAY [--frames K] [--steps N]\n"
    "                           after every tick roll back K ticks (default 8) and simulate them\n"
    "                           again: every hash must be the same (GGPO's sync test); a replay's\n"
    "                           inputs and chain, or N ticks of a scene (default 600)\n"
    "  peer --scene SCENE --player K --players N --port P [--connect 127.0.0.1:PORT]... [--inputs FILE]\n"
    "       [--reference] [--mode lockstep|rollback] [--delay D] [--ticks N] [--hz F] [--checksum-every K] [--json]\n"
    "       [--max-prediction K] [--loss PCT] [--jitter MIN-MAX] [--duplicate PCT] [--seed S]\n"
    "       [--corrupt BODY@TICK] [--timeout S] [--leave-after FRAMES] [--join | --watch]\n"
    "       [--absent P@TICK]... [--present P@TICK]... [--watching P@TICK]... [--chain-from TICK]  (--reference)\n"
    "                           play one player of a session over ENet on 127.0.0.1; --reference runs\n"
    "                           every player's --inputs in one process (the chain the peers must reach);\n"
    "                           --leave-after: the host marks a silent player absent; --join (--watch):\n"
    "                           play (watch) the match in progress in --player's slot; --absent,\n"
    "                           --present, --watching: the host's roster changes for --reference,\n"
    "                           --chain-from: its chain after TICK\n"
    "                           faults: --loss, --jitter, --duplicate drawn from --seed; --corrupt\n"
    "                           nudges a body at a tick (a desync to be found)\n"
    "  selftest                 the fixed-point known-answer hash: does this build give the frozen bits?\n"
    "  bench [--quick | --full] [--out DIR] [--sections LIST] [--only EXPERIMENTS] [--no-peer] [--scenes DIR]\n"
    "        [--threads N] [--readme FILE]\n"
    "                           the suite: accuracy and stability experiments on bitstep's variants and\n"
    "                           Bullet, work-precision sweeps, scale, speed against Bullet, costs; writes\n"
    "                           CSV, summary.md and plots to DIR (default bench-report); sections:\n"
    "                           results,sweep,scale,speed,costs,determinism; --threads N: the workers of\n"
    "                           the speed table's threaded column (default 2); --readme FILE: then writes\n"
    "                           the headline table into FILE\n"
    "  bench fixed [--quick] [--csv FILE]\n"
    "                           ns/op of fixed-point operations next to float and double\n"
    "  bench headline [--report DIR] [--readme FILE] [--check]\n"
    "                           the README's headline table from a report's CSV files (default\n"
    "                           tools/report, README.md); --check: exit 1 if FILE's table differs\n"
    "  bench queries [--quick]  us per ray, shape cast and overlap over 100 to 10,000 bodies\n"
    "  bench session [--quick] [--scenes DIR]\n"
    "                           what a session adds to a tick; the largest world lockstep and rollback\n"
    "                           sustain at 60 and 20 Hz\n"
    "  bench sleep [--quick] [--still] [--scenes DIR]\n"
    "                           ms/step of scenes awake and asleep (sleep motion, or still)\n"
    "  version                  engine version and build options\n"
    "  help                     this text\n"
    "\n"
    "exit status (every failure also prints one line: the file, the place, the reason):\n"
    "  0  success\n"
    "  1  a check failed: a hash differs (verify, synctest, selftest), two dumps differ (diff), a peer\n"
    "     timed out\n"
    "  2  usage error: an unknown or malformed option, --settings that is not a settings object\n"
    "  3  peer: a desync (the peers' states differ)\n"
    "  4  an input file refused: missing, unreadable, over a limit (replay/limits.h), malformed, or not\n"
    "     fitting (a snapshot of another scene, a scene body the world refuses)\n"
    "  5  an output file could not be written (nothing is left under its name)\n"
    "  6  peer: another peer refused our hello (another scene or settings, player count, mode, input\n"
    "     delay, a player number taken or out of range, another build), named on both sides\n";

// The known-answer hash proves this build computes the frozen bits; with the
// same bits, every function has the accuracy tests/fixed measures.
int selftest(int argc, char** argv) {
  CLI::App app("the fixed-point layer's known-answer hash", "bitstep selftest");
  if (const std::optional<int> code = bitstep::cli::parse(app, "selftest", argc, argv)) return *code;
  const bitstep::KnownAnswer answer = bitstep::run_known_answer();
  const bool hash_ok = answer.hash == bitstep::expected_known_answer_hash;
  fmt::print("known-answer hash: {:016x} over {} operations ({}; expected {:016x})\n", answer.hash, answer.operations,
             hash_ok ? "match" : "MISMATCH", bitstep::expected_known_answer_hash);
  return hash_ok ? bitstep::exit_code::success : bitstep::exit_code::check_failed;
}

int version(int argc, char** argv) {
  CLI::App app("engine version and build options", "bitstep version");
  if (const std::optional<int> code = bitstep::cli::parse(app, "version", argc, argv)) return *code;
  fmt::print("bitstep {} (Q32.32, {} 128-bit arithmetic{})\n", BITSTEP_VERSION, bitstep::wide_backend_name,
             bitstep::checked_build ? ", checked" : "");
  return bitstep::exit_code::success;
}

int record(int argc, char** argv) { return bitstep::record_command(argc, argv, BITSTEP_VERSION); }

int help(int, char**) {
  fmt::print("{}", usage);
  return bitstep::exit_code::success;
}

// A command's name and what runs it on the words after the name. Each
// command declares its own options (tools/cli/options.h); this table only
// picks the command.
struct Command {
  std::string_view name;
  int (*run)(int argc, char** argv);
};

// `bitstep bench NAME` runs one of these; `bitstep bench` with options, the suite.
constexpr Command bench_commands[] = {
    {"fixed", bitstep::run_bench_fixed},     {"headline", bitstep::run_bench_headline},
    {"queries", bitstep::run_bench_queries}, {"session", bitstep::run_bench_session},
    {"sleep", bitstep::run_bench_sleep},
};

int bench(int argc, char** argv) {
  for (const Command& c : bench_commands) {
    if (argc >= 1 && c.name == argv[0]) return c.run(argc - 1, argv + 1);
  }
  return bitstep::run_bench_suite(argc, argv);
}

constexpr Command commands[] = {
    {"run", bitstep::run_scene_command},
    {"record", record},
    {"verify", bitstep::verify_command},
    {"diff", bitstep::diff_command},
    {"synctest", bitstep::synctest_command},
    {"peer", bitstep::peer_command},
    {"selftest", selftest},
    {"bench", bench},
    {"version", version},
    {"help", help},
    {"--help", help},
    {"-h", help},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "{}", usage);
    return bitstep::exit_code::usage;
  }
  for (const Command& c : commands) {
    if (c.name == argv[1]) return c.run(argc - 2, argv + 2);
  }
  fmt::print(stderr, "bitstep: unknown command '{}'\n{}", argv[1], usage);
  return bitstep::exit_code::usage;
}
