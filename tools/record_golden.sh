#!/usr/bin/env bash
# Re-records every golden replay in scenes/ with its own inputs and step
# count, after a change that moves the hash chains on purpose (say so in the
# commit). Uses build/release/bitstep (run tools/run.sh first), or $BITSTEP.
set -euo pipefail
cd "$(dirname "$0")/.."
bitstep=${BITSTEP:-build/release/bitstep}
[ -x "$bitstep" ] || { echo "record_golden: build $bitstep first (tools/run.sh)" >&2; exit 1; }
for replay in scenes/*.replay.json; do
  scene="scenes/$(sed -n 's/^ *"scene": "\(.*\)",$/\1/p' "$replay")"
  steps=$(sed -n 's/^ *"steps": \([0-9]*\),$/\1/p' "$replay")
  "$bitstep" record "$scene" --inputs "$replay" --steps "$steps" -o "$replay"
done
