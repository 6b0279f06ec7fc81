#!/usr/bin/env bash
# The viewer, tested (tools/test.sh runs it; ~1 minute):
#   1. its wasm engine under node (tools/viewer/engine_test.mjs): the
#      playground's golden replay at every step, scrubbing, a tampered copy,
#      a click recorded into a replay, hills (a heightfield, hulls) and the
#      course (characters);
#   2. that replay verified by the native bitstep, and the tampered one
#      refused by it at the same step;
#   3. the page in headless Chromium (tools/viewer/browser_test.mjs): every
#      step's hash, a screenshot that is not blank, DIVERGED at the right step,
#      the course's and the hills' hashes, the course's characters drawn.
# Usage: tools/viewer_test.sh [BITSTEP]   (default build/release/bitstep)
set -euo pipefail
cd "$(dirname "$0")/.."
bitstep=${1:-build/release/bitstep}
tools/install_deps.sh viewer
tools/viewer/install.sh
tools/build_wasm.sh build/wasm >build/wasm.log 2>&1 || { cat build/wasm.log >&2; exit 1; }
out=build/viewer_test
rm -rf "$out"
mkdir -p "$out"

echo "-- the wasm engine under node"
tools/node_wasm.sh tools/viewer/engine_test.mjs "$out"

echo "-- the viewer's replays, natively"
"$bitstep" verify "$out/clicked.replay.json"
if "$bitstep" verify "$out/tampered.replay.json" >"$out/tampered.log" 2>&1; then
  echo "viewer_test: the native verify accepted the tampered replay" >&2
  exit 1
fi
grep -q "DIFFERS at step 30 " "$out/tampered.log" || { cat "$out/tampered.log" >&2; exit 1; }
cat "$out/tampered.log"

echo "-- the page in headless Chromium"
node tools/viewer/browser_test.mjs "$out"
