#!/usr/bin/env bash
# Runs one fuzz target for a while (tools/fuzz/README.md):
#   tools/fuzz.sh TARGET SECONDS [LIBFUZZER OPTION...]
# TARGET is scene, replay, settings, snapshot, packet or capi. Builds build/fuzz if
# needed, then fuzzes in one process (-jobs=1) for at most SECONDS, from the
# committed seeds and regressions copied into build/fuzz/work/TARGET/corpus
# (which keeps what it finds across runs; the committed corpus never grows).
# A crash leaves its input in build/fuzz/work/TARGET/ (crash-*, leak-*,
# timeout-*, oom-*) and fails the script; the run's output is fuzz-0.log there.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
if [ $# -lt 2 ]; then
  echo "usage: tools/fuzz.sh TARGET SECONDS [LIBFUZZER OPTION...]" >&2
  exit 2
fi
target=$1 seconds=$2
shift 2
case "$target" in
  scene | replay | settings) options=(-dict="$root/tools/fuzz/json.dict") ;;
  snapshot | packet) options=() ;;
  # A call sequence reaches ~50,000 coverage features, and libFuzzer's
  # entropic schedule, which updates a frequency for each of them on every
  # run, took half of fuzz_capi's time: the plain schedule runs it twice as fast.
  capi) options=(-entropic=0) ;;
  *) echo "fuzz.sh: unknown target '$target' (scene, replay, settings, snapshot, packet or capi)" >&2; exit 2 ;;
esac
tools/fuzz_build.sh "fuzz_$target"
work=build/fuzz/work/$target
mkdir -p "$work/corpus"
cp -r tools/fuzz/corpus/"$target"/. "$work/corpus/"
if [ -d tools/fuzz/regressions/"$target" ]; then cp -r tools/fuzz/regressions/"$target"/. "$work/corpus/"; fi
status=0
(cd "$work" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  "$root/build/fuzz/tools/fuzz/fuzz_$target" corpus -jobs=1 -max_total_time="$seconds" -timeout=20 -rss_limit_mb=4096 \
    -artifact_prefix=./ -print_final_stats=1 "${options[@]}" "$@") || status=$?
tail -n 30 "$work/fuzz-0.log"
exit "$status"
