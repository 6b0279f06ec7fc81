#!/usr/bin/env bash
# The test command: install what is missing, then
#   1. a Debug build (-O1) with BITSTEP_CHECKED, AddressSanitizer and UBSan:
#      every test;
#   2. a Release build: every test again, optimised, unchecked;
#   3. the installed package: a C and a C++ consumer built against it, the
#      C one against its shared library alone, and a rollback match over
#      ENet between C peers and between a C and a C# peer (mono)
#      (tools/check_package.sh);
#   4. the fuzz targets (libFuzzer, ASan, UBSan): each reader of untrusted
#      input, and the C API's call sequences, for a fixed number of runs from
#      its seeds (tools/fuzz_test.sh);
#   5. a ThreadSanitizer build: the threaded solver on seven golden replays
#      and the thread pool (tests/replay/thread_golden_tests.cpp);
#   6. tools/crosscheck/crosscheck.sh (started first, beside 1 to 5): the
#      known-answer hash and the golden replays across compilers, the
#      portable 128-bit path, i686 / aarch64 / s390x / armhf / riscv64 /
#      ppc64le under qemu-user, Windows (mingw-w64) under wine and
#      WebAssembly under node;
#   7. bitstep peer processes on 127.0.0.1 playing a match, 2 and 4 peers,
#      lockstep and rollback, with and without faults, and a killed peer's
#      slot rejoined or watched, a corrupted host's state refused by a joiner
#      (tools/peer_test.sh), alone;
#   8. the browser viewer: its wasm engine (the one 6 built) under node, then
#      the page in headless Chromium (tools/viewer_test.sh).
# The cross check writes to build/crosscheck.log, printed under its heading
# when it ends; the script fails if any part failed.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

tools/install_deps.sh test

# A compiler cache (ccache) under every build of this script: CMake takes the
# launcher from these variables when it configures a new build folder, and
# the cross check runs its compiles through it. On a machine that ran this
# before, only the translation units a change touched are compiled again;
# the first run pays for every compile. The base directory makes paths
# inside the clone relative, so that a clone elsewhere hits the same
# entries; the sloppiness lets precompiled headers be cached.
export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache
export CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1 CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
ccache --zero-stats >/dev/null

# Each part's heading carries the minutes since the start (CI's budget is 25).
step() { printf '\n== %s (at %d min %02d s)\n' "$*" $((SECONDS / 60)) $((SECONDS % 60)); }

# The cross check is the longest part (16 builds, each run, ~17 minutes of
# CPU) and needs none of the builds below: it starts first and keeps both
# cores busy while the parts below wait on a link or a single-threaded test.
mkdir -p build
tools/crosscheck/crosscheck.sh >build/crosscheck.log 2>&1 &
crosscheck=$!
# A part that fails ends the script: the cross check ends with it.
trap 'kill $crosscheck 2>/dev/null || true' EXIT

step "checked Debug build with ASan + UBSan"
# (the bench's Bullet peer programs are built in the Release step only)
# At -O1, as AddressSanitizer's documentation advises for reasonable
# speed: the checks are the same, and the tests take about a third of the
# CPU time they take at -O0. -g1 keeps the line tables the sanitizers'
# reports need. (The cross check builds and runs -O0 code.) The test
# programs' own files, still instrumented, compile at -O0: optimising their
# instrumented bodies was most of this build's compile time, and the code
# under test (the libraries) stays at -O1.
cmake -S . -B build/checked -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DBITSTEP_CHECKED=ON -DBITSTEP_SANITIZE=ON -DBITSTEP_TESTS=ON -DBITSTEP_PEER=OFF \
  -DBITSTEP_TEST_COMPILE_OPTIONS=-O0 >/dev/null
cmake --build build/checked -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/checked --no-tests=error --output-on-failure -j"$jobs"

step "Release build"
# (the bench's programs at -O0 and -O3 -ffast-math are for its determinism
# section only: `cmake --build build/release` builds them for the bench)
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=ON -DBITSTEP_FLAG_PEERS=OFF >/dev/null
cmake --build build/release -j"$jobs"

step "Release tests"
ctest --test-dir build/release --no-tests=error --output-on-failure -j"$jobs"

step "the installed package: C and C++ consumers, the shared library, a C and C# rollback match"
tools/check_package.sh build/release

step "fuzz targets: scene, replay, settings, snapshot and packet readers, the C API (libFuzzer, ASan, UBSan)"
tools/fuzz_test.sh

# The solver's sweeps on several workers (core/ordered_sweeps.h) under
# ThreadSanitizer: seven golden replays on 2, 3 and 8 workers (the Release
# tests ran all of them on 3), optimised, and the thread pool (only
# tests/thread_tests is built). With the waits removed it reports a data
# race on the first replay.
step "ThreadSanitizer build: seven golden replays on 2, 3 and 8 workers, the thread pool"
cmake -S . -B build/tsan -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TSAN=ON -DBITSTEP_TESTS=ON -DBITSTEP_PEER=OFF >/dev/null
cmake --build build/tsan -j"$jobs" --target thread_tests
TSAN_OPTIONS=halt_on_error=1 build/tsan/tests/thread_tests

step "cross-build check"
crosscheck_status=0
wait "$crosscheck" || crosscheck_status=$?
cat build/crosscheck.log
if [ "$crosscheck_status" -ne 0 ]; then echo "test.sh: cross-build check failed" >&2; exit 1; fi

# Alone on the machine: beside CPU-bound parts a joining peer misses its
# slot's deadline (a spectator timed out at tick 0 with 4 compiles beside it).
step "bitstep peer: 2 and 4 peers on 127.0.0.1, lockstep and rollback, with faults"
tools/peer_test.sh build/release/bitstep

step "the browser viewer: the wasm engine under node, the page in headless Chromium"
tools/viewer_test.sh build/release/bitstep
# What the cache saved: compiles served from it against those run.
ccache --print-stats | awk -F'\t' '$1 ~ /^(direct_cache_hit|preprocessed_cache_hit|cache_miss)$/ {n[$1] = $2}
  END {printf "\n== compiler cache: %d compiles from the cache, %d compiled\n",
       n["direct_cache_hit"] + n["preprocessed_cache_hit"], n["cache_miss"]}'
printf '\n== every part passed in %d min %02d s\n' $((SECONDS / 60)) $((SECONDS % 60))
