#!/usr/bin/env bash
# The fuzz check of tools/test.sh (tools/fuzz/README.md): builds the
# libFuzzer targets (build/fuzz) and runs each for a fixed number of
# executions from its committed seeds and regressions (copied into a
# scratch folder: the committed corpus never grows), one after another,
# about a minute in all on 2 cores. Fails on any crash, leak, timeout, UB
# or broken property.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

tools/fuzz_build.sh >/dev/null

# target:runs, sized so that each takes about 10 s on 2 shared cores
# (fuzz_snapshot's seeds include mesh and heightfield worlds, which it
# steps, and fuzz_capi runs whole call sequences: both run far fewer
# inputs a second than the readers).
runs=(scene:8000 replay:15000 settings:100000 snapshot:2000 packet:500000 capi:1000)
failed=()
for entry in "${runs[@]}"; do
  target=${entry%%:*} n=${entry#*:}
  work=build/fuzz/test/$target
  rm -rf "$work"
  mkdir -p "$work/corpus"
  cp -r tools/fuzz/corpus/"$target"/. "$work/corpus/"
  if [ -d tools/fuzz/regressions/"$target" ]; then cp -r tools/fuzz/regressions/"$target"/. "$work/corpus/"; fi
  options=()
  case "$target" in
    scene | replay | settings) options=(-dict="$root/tools/fuzz/json.dict") ;;
    capi) options=(-entropic=0) ;;  # see fuzz.sh
  esac
  start=$SECONDS
  status=0
  (cd "$work" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$root/build/fuzz/tools/fuzz/fuzz_$target" corpus -runs="$n" -seed=1 -timeout=20 -rss_limit_mb=4096 \
      -artifact_prefix=./ "${options[@]}" >log 2>&1) || status=$?
  done_line=$(grep -o 'Done [0-9]* runs in [0-9]* second(s)' "$work/log" | tail -n 1 || true)
  if [ "$status" -ne 0 ]; then
    echo "fuzz_$target: FAILED (exit $status; input and log in $work)"
    tail -n 40 "$work/log"
    failed+=("$target")
  else
    echo "fuzz_$target: ${done_line:-done} ($((SECONDS - start)) s)"
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz_test.sh: failed: ${failed[*]}" >&2
  exit 1
fi
