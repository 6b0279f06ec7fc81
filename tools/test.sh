#!/usr/bin/env bash
# The test command: install what is missing, then
#   1. a Debug build with BITSTEP_CHECKED, AddressSanitizer and UBSan: every test;
#   2. a Release build: every test again, optimised, unchecked;
#   3. tools/crosscheck/crosscheck.sh (beside 2's tests): the known-answer hash and the
#      golden replays across compilers, the portable 128-bit path, i686 /
#      aarch64 / s390x / armhf / riscv64 / ppc64le under qemu-user, Windows
#      (mingw-w64) under wine and WebAssembly under node;
#   4. the installed package: a C and a C++ consumer built against it
#      (tools/check_package.sh);
#   5. the fuzz targets (libFuzzer, ASan, UBSan): each reader of untrusted
#      input, and the C API's call sequences, for a fixed number of runs from
#      its seeds (tools/fuzz_test.sh);
#   6. bitstep peer processes on 127.0.0.1 playing a match, 2 and 4 peers,
#      lockstep and rollback, with and without faults, and a killed peer's
#      slot rejoined or watched (tools/peer_test.sh);
#   7. the browser viewer: its wasm engine under node, then the page in
#      headless Chromium (tools/viewer_test.sh);
#   8. a ThreadSanitizer build: the threaded solver's golden replays and the
#      thread pool (tests/replay/thread_golden_tests.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

tools/install_deps.sh test

# Each part's heading carries the minutes since the start (CI's budget is 40).
step() { printf '\n== %s (at %d min %02d s)\n' "$*" $((SECONDS / 60)) $((SECONDS % 60)); }

step "checked Debug build with ASan + UBSan"
# (the bench's Bullet peer programs are built in the Release step only)
cmake -S . -B build/checked -DCMAKE_BUILD_TYPE=Debug -DBITSTEP_CHECKED=ON -DBITSTEP_SANITIZE=ON -DBITSTEP_TESTS=ON -DBITSTEP_PEER=OFF >/dev/null
cmake --build build/checked -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/checked --no-tests=error --output-on-failure -j"$jobs"

step "Release build"
# (the bench's programs at -O0 and -O3 -ffast-math are for its determinism
# section only: tools/run.sh builds them)
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=ON -DBITSTEP_FLAG_PEERS=OFF >/dev/null
cmake --build build/release -j"$jobs"

# The cross-build check runs beside the Release tests (~3.5 minutes): its
# 16 compiles make this the longest part, ~16 minutes on 2 cores. The golden replays on 2, 3 and 8 workers (~3.5 minutes here)
# are left to the ThreadSanitizer build at the end, which runs the same test
# on every full replay, optimised. Its tables print after.
step "Release tests, and the cross-build check beside them"
mkdir -p build
tools/crosscheck/crosscheck.sh >build/crosscheck.log 2>&1 &
crosscheck=$!
release_status=0
ctest --test-dir build/release --no-tests=error --output-on-failure -j"$jobs" \
  -E 'hash chain on 2, 3 and 8 workers' || release_status=$?
crosscheck_status=0
wait "$crosscheck" || crosscheck_status=$?
step "cross-build check"
cat build/crosscheck.log
if [ "$release_status" -ne 0 ]; then echo "test.sh: Release tests failed" >&2; exit 1; fi
if [ "$crosscheck_status" -ne 0 ]; then echo "test.sh: cross-build check failed" >&2; exit 1; fi

step "the installed package: a C and a C++ consumer print the golden hash"
tools/check_package.sh build/release

step "fuzz targets: scene, replay, settings, snapshot and packet readers, the C API (libFuzzer, ASan, UBSan)"
tools/fuzz_test.sh

step "bitstep peer: 2 and 4 peers on 127.0.0.1, lockstep and rollback, with faults"
tools/peer_test.sh build/release/bitstep

step "the browser viewer: the wasm engine under node, the page in headless Chromium"
tools/viewer_test.sh build/release/bitstep

# The solver's sweeps on several workers (core/ordered_sweeps.h) under
# ThreadSanitizer: every golden replay on 2, 3 and 8 workers, optimised,
# and the thread pool (~5 minutes on 2 cores, the build included: only
# tests/thread_tests is built). With the waits removed it reports a data
# race on the first replay.
step "ThreadSanitizer build: the golden replays on 2, 3 and 8 workers, the thread pool"
cmake -S . -B build/tsan -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TSAN=ON -DBITSTEP_TESTS=ON -DBITSTEP_PEER=OFF >/dev/null
cmake --build build/tsan -j"$jobs" --target thread_tests
TSAN_OPTIONS=halt_on_error=1 build/tsan/tests/thread_tests
printf '\n== every part passed in %d min %02d s\n' $((SECONDS / 60)) $((SECONDS % 60))
