#!/usr/bin/env bash
# The main command: install what is missing, build Release, run the main job.
#   tools/run.sh                      runs scenes/playground.json for 10 s
#   tools/run.sh SCENE [OPTIONS...]   bitstep run SCENE [OPTIONS...]
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install_deps.sh bench
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DBITSTEP_TESTS=OFF >/dev/null
# bitstep, and the bench's peer programs when Bullet is installed (bitstep bench).
cmake --build build/release -j"$(nproc)"
if [[ $# -eq 0 ]]; then
  set -- scenes/playground.json
fi
exec build/release/bitstep run "$@"
