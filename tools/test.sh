#!/usr/bin/env bash
# The test command: install what is missing, then
#   1. a Debug build with BITSTEP_CHECKED, AddressSanitizer and UBSan: every test;
#   2. a Release build: every test again, optimised, unchecked;
#   3. tools/crosscheck.sh: the known-answer hash across compilers, the
#      portable 128-bit path and i686 / aarch64 / s390x under qemu-user.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

tools/install_deps.sh test

step() { printf '\n== %s\n' "$*"; }

step "checked Debug build with ASan + UBSan"
# (the bench's Bullet peer programs are built in the Release step only)
cmake -S . -B build/checked -DCMAKE_BUILD_TYPE=Debug -DBITSTEP_CHECKED=ON -DBITSTEP_SANITIZE=ON -DBITSTEP_TESTS=ON -DBITSTEP_PEER=OFF >/dev/null
cmake --build build/checked -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/checked --no-tests=error --output-on-failure -j"$jobs"

step "Release build"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=ON >/dev/null
cmake --build build/release -j"$jobs"
ctest --test-dir build/release --no-tests=error --output-on-failure -j"$jobs"

step "cross-build check"
tools/crosscheck.sh
