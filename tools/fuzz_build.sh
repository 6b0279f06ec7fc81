#!/usr/bin/env bash
# Configures (once) and builds the libFuzzer targets in build/fuzz: clang,
# BITSTEP_FUZZ (libFuzzer, ASan, UBSan), optimised with debug information.
#   tools/fuzz_build.sh [TARGET...]   fuzz_scene, fuzz_replay, ... (default: all six)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=build/fuzz
if [ ! -f "$dir/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBITSTEP_FUZZ=ON \
    -DBITSTEP_TESTS=OFF -DBITSTEP_PEER=OFF >/dev/null
fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_scene fuzz_replay fuzz_settings fuzz_snapshot fuzz_packet fuzz_capi)
cmake --build "$dir" -j"$(nproc)" --target "${targets[@]}"
