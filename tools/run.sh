#!/usr/bin/env bash
# The main command: install what is missing, build Release, run the main job.
# Until the engine exists the main job is the fixed-point self test (the
# known-answer hash and the accuracy table).
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install_deps.sh build
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=OFF >/dev/null
cmake --build build/release -j"$(nproc)" --target bitstep
exec build/release/bitstep selftest "$@"
