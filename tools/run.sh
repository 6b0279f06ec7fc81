#!/usr/bin/env bash
# The main command: install what is missing, build Release bitstep (and
# nothing else: the bench's peer programs are `cmake --build build/release`
# after `tools/install_deps.sh bench`, docs/bench.md), run the main job.
#   tools/run.sh                      runs scenes/playground.json for 10 s
#   tools/run.sh SCENE [OPTIONS...]   bitstep run SCENE [OPTIONS...]
#   tools/run.sh --view [FILE [PORT]] the browser viewer on a replay or a scene
#                                     (default: the playground's golden replay),
#                                     served on 127.0.0.1:PORT (default 8080)
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${1:-}" == --view ]]; then
  file=${2:-scenes/playground.replay.json}
  port=${3:-8080}
  [ -f "$file" ] || { echo "run.sh --view: $file: no such file" >&2; exit 2; }
  tools/install_deps.sh wasm
  tools/viewer/install.sh
  echo "building the wasm engine (tools/build_wasm.sh)..."
  tools/build_wasm.sh build/wasm >build/wasm.log 2>&1 || { cat build/wasm.log >&2; exit 1; }
  # A replay holds a hash chain; anything else is played as a scene.
  kind=scene
  grep -q '"hashes"' "$file" && kind=replay
  exec node tools/viewer/serve.mjs --port "$port" --files "$(dirname "$file")" \
    --page "$kind=/files/$(basename "$file")&play=1"
fi

tools/install_deps.sh build
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=OFF -DBITSTEP_FLAG_PEERS=ON >/dev/null
cmake --build build/release -j"$(nproc)" --target bitstep
if [[ $# -eq 0 ]]; then
  set -- scenes/playground.json
fi
exec build/release/bitstep run "$@"
