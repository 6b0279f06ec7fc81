#!/usr/bin/env bash
# Builds bitstep for WebAssembly with Debian's emscripten, through CMake and
# emscripten's toolchain file, into build/wasm (tools/wasm/CMakeLists.txt
# lists what it makes). Run node on the results with
# --no-experimental-fetch (tools/node_wasm.sh): under Node 20 the generated
# loader otherwise fetches its .wasm by a file path and fails.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh wasm
# emcc finds acorn (node-acorn) here.
export NODE_PATH=/usr/share/nodejs
out=${1:-build/wasm}
cmake -S . -B "$out" -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=OFF \
  -DCMAKE_TOOLCHAIN_FILE=/usr/share/emscripten/cmake/Modules/Platform/Emscripten.cmake >/dev/null
cmake --build "$out" -j"$(nproc)"
