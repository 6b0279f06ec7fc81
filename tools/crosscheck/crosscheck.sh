#!/usr/bin/env bash
# The cross-build matrix: builds the known-answer program (fixed/, whose
# known_answer.cpp it runs) and the golden-replay verifier (fixed/, core/,
# replay/ + tools/crosscheck/verify_replays_main.cpp; xxhash inlined, nlohmann
# header-only) with every compiler, option set, 128-bit backend and CPU
# below, each program one translation unit (its sources #included into one
# file, the heavy headers parsed once), runs each (foreign CPUs under
# qemu-user, statically linked; Windows under wine,
# tools/crosscheck/wine_run.sh) and fails
# unless every build prints the frozen known-answer hash and reproduces every
# golden replay's hash chain at every step. Prints two tables.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=build/crosscheck
mkdir -p "$out"

sources=(fixed/*.cpp tools/crosscheck/known_answer_main.cpp)
# The verifier links neither the known-answer test, sessions, the C API,
# render poses, Simulation nor the thread pool: leaving them out saves ~15%
# of each compile.
replay_sources=()
for f in fixed/*.cpp; do
  [ "$f" = fixed/known_answer.cpp ] || replay_sources+=("$f")
done
replay_sources+=(core/*.cpp tools/crosscheck/verify_replays_main.cpp)
for f in replay/*.cpp; do
  case "$f" in replay/session*|replay/bitstep_c.cpp|replay/bitstep_session_c.cpp|replay/render_pose.cpp|replay/simulation.cpp|replay/sync_test.cpp|replay/thread_pool.cpp) ;; *) replay_sources+=("$f") ;; esac
done
# Each program is compiled as one translation unit that #includes its
# sources (a unity build): the standard library's and nlohmann's headers are
# parsed, and their templates instantiated and optimised, once instead of per
# source, which halves each compile. (Anonymous-namespace names must not
# clash across the sources of a library.)
# unity NAME SOURCES...: writes $out/NAME.cpp and prints it.
unity() {
  local name=$1 f
  shift
  : >"$out/$name.cpp"
  for f in "$@"; do echo "#include \"$f\"" >>"$out/$name.cpp"; done
  echo "$out/$name.cpp"
}
mapfile -t sources < <(unity kat_unity "${sources[@]}")
mapfile -t replay_sources < <(unity replays_unity "${replay_sources[@]}")
common=(-std=c++20 -I. -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror)
# The header-only libraries, visible to the cross compilers too (their own
# sysroots have no nlohmann or xxhash); no other host header leaks in.
mkdir -p "$out/include"
ln -sfn /usr/include/nlohmann "$out/include/nlohmann"
ln -sf /usr/include/xxhash.h "$out/include/xxhash.h"
replay_flags=(-isystem "$out/include" -DXXH_INLINE_ALL -DXXH_VECTOR=0)

# Golden replays: every build verifies them all (wasm under node too, in
# ~12 s; Windows under wine in ~30 s), except that the builds run under qemu,
# and the unoptimised and checked ones, take the short versions of the six
# heaviest scenes
# (<scene>.short.replay.json: 2 to 20 steps) instead of their full replays
# (minutes each when emulated; ragdolls' 8 substeps alone took 38 s at -O0);
# so every scene runs in every build, and every full replay in the
# optimised native builds, wasm and Windows.
replays=(scenes/*.replay.json)
short_replays=()
for r in "${replays[@]}"; do
  # A heavy scene is one that has a short replay beside its full one (the
  # rule tests/replay/golden_replays.h follows too).
  [ -e "${r%.replay.json}.short.replay.json" ] || short_replays+=("$r")
done

# name | compiler | flags | runner ("-" = run directly). armhf: -Wno-psabi
# silences GCC's notes that the ABI of some std::vector iterator arguments
# changed in GCC 7.1 (nothing here crosses that boundary). wasm: CMake with
# emscripten's toolchain file (tools/build_wasm.sh, -O3), run under node.
# Windows: mingw-w64 (posix threads: std::thread), without __int128 as MSVC
# would be, linked -static so that wine needs no DLL of the toolchain.
builds=(
  "gcc -O0|g++|-O0|-"
  "gcc -O2|g++|-O2|-"
  "gcc -O3 -march=native -ffast-math|g++|-O3 -march=native -ffast-math|-"
  "clang -O2|clang++|-O2|-"
  "clang -O3 -ffast-math LTO|clang++|-O3 -ffast-math -flto|-"
  "clang-16 -O3|clang++-16|-O3|-"
  "gcc -O2 portable 128-bit|g++|-O2 -DBITSTEP_PORTABLE_128=1|-"
  "gcc -O1 checked + UBSan|g++|-O1 -DBITSTEP_CHECKED=1 -fsanitize=undefined -fno-sanitize-recover=all|-"
  "i686 gcc -O2 (no __int128)|i686-linux-gnu-g++|-O2 -static|qemu-i386"
  "aarch64 gcc -O2|aarch64-linux-gnu-g++|-O2 -static|qemu-aarch64"
  "s390x gcc -O2 (big-endian)|s390x-linux-gnu-g++|-O2 -static|qemu-s390x"
  "armhf gcc -O2 (32-bit ARM, no __int128)|arm-linux-gnueabihf-g++|-O2 -static -Wno-psabi|qemu-arm"
  "riscv64 gcc -O2|riscv64-linux-gnu-g++|-O2 -static|qemu-riscv64"
  "ppc64le gcc -O2|powerpc64le-linux-gnu-g++|-O2 -static|qemu-ppc64le"
  "wasm32 emscripten -O3 (node)|wasm|-|tools/node_wasm.sh"
  "Windows x86-64 mingw-w64 gcc -O2 portable 128-bit (wine)|x86_64-w64-mingw32-g++-posix|-O2 -static -DBITSTEP_PORTABLE_128=1|tools/crosscheck/wine_run.sh"
)

slug() { echo "$1" | tr -c 'A-Za-z0-9\n' '_'; }
# A build's program ("kat" or "replays"): mingw-w64 names it .exe.
program() {
  local suffix=
  case "$3" in *mingw32*) suffix=.exe ;; esac
  echo "$out/$1_$(slug "$2")$suffix"
}

# The compiler cache of tools/test.sh (CMAKE_CXX_COMPILER_LAUNCHER, ccache),
# when it set one: it caches compiles, not links, so each program is
# compiled to an object and linked apart.
launcher=()
[ -n "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ] && launcher=("$CMAKE_CXX_COMPILER_LAUNCHER")
# build_program COMPILER FLAGS OUTPUT ARGS...: the object, then the program;
# the compiler's messages in OUTPUT.log.
build_program() {
  local compiler=$1 flags=$2 output=$3
  shift 3
  # shellcheck disable=SC2086
  "${launcher[@]}" "$compiler" "$@" $flags -c -o "$output.o" 2>"$output.log" &&
    "$compiler" $flags "$output.o" -o "$output" 2>>"$output.log"
}

# Compiles one build's two programs.
compile() {
  IFS='|' read -r name compiler flags _ <<<"$1"
  local exe verifier
  exe=$(program kat "$name" "$compiler")
  verifier=$(program replays "$name" "$compiler")
  if [ "$compiler" = wasm ]; then
    # node finds each program's .wasm beside the link's target.
    if ! tools/build_wasm.sh build/wasm >"$exe.log" 2>&1; then
      echo "crosscheck: build '$name' failed:" >&2
      cat "$exe.log" >&2
      return 1
    fi
    ln -sf "$PWD/build/wasm/tools/wasm/bitstep-known-answer.js" "$exe"
    ln -sf "$PWD/build/wasm/tools/wasm/bitstep-verify-replays.js" "$verifier"
    return 0
  fi
  if ! build_program "$compiler" "$flags" "$exe" "${common[@]}" "${sources[@]}"; then
    echo "crosscheck: build '$name' failed to compile:" >&2
    cat "$exe.log" >&2
    return 1
  fi
  if ! build_program "$compiler" "$flags" "$verifier" "${common[@]}" "${replay_flags[@]}" "${replay_sources[@]}"; then
    echo "crosscheck: the replay verifier of build '$name' failed to compile:" >&2
    cat "$verifier.log" >&2
    return 1
  fi
}
# Runs FUNCTION once per build, nproc at a time (CI has 2 cores), starting
# the next as soon as any one ends (a slow emulated run must not hold a
# core idle); fails if any run failed. A subshell, so that `wait -n` waits
# for these runs only (wine's prefix is made beside the compiles).
for_each_build() (
  status=0 running=0
  for b in "${builds[@]}"; do
    if [ "$running" -ge "$(nproc)" ]; then
      wait -n || status=1
      running=$((running - 1))
    fi
    "$1" "$b" &
    running=$((running + 1))
  done
  while [ "$running" -gt 0 ]; do
    wait -n || status=1
    running=$((running - 1))
  done
  exit $status
)
# wine's prefix, made once per run beside the compiles (~10 s).
timeout 300 tools/crosscheck/wine_run.sh wineboot --init >"$out/wineboot.log" 2>&1 &
wineboot=$!
for_each_build compile || exit 1
wait "$wineboot" || { echo "crosscheck: wine's prefix failed:" >&2; cat "$out/wineboot.log" >&2; exit 1; }

expected=$(sed -n 's/.*expected_known_answer_hash = 0x\([0-9a-f]*\);.*/\1/p' fixed/known_answer.h)
printf '| build | 128-bit backend | byte order | known-answer hash | result |\n|---|---|---|---|---|\n'
failed=0
for b in "${builds[@]}"; do
  IFS='|' read -r name compiler _ runner <<<"$b"
  exe=$(program kat "$name" "$compiler")
  if [ "$runner" = "-" ]; then
    line=$("$exe" || true)
  else
    line=$("$runner" "$exe" || true)
  fi
  read -r hash _ backend order <<<"$line"
  if [ "$hash" = "$expected" ]; then
    result=match
  elif [ -z "$hash" ]; then
    result="FAILED: no output (crashed or aborted)"; failed=1
  else
    result="MISMATCH (expected $expected)"; failed=1
  fi
  printf '| %s | %s | %s | %s | %s |\n' "$name" "${backend:-?}" "${order:-?}" "${hash:-none}" "$result"
done
[ $failed -eq 0 ] || { echo "crosscheck: builds disagree" >&2; exit 1; }
echo "crosscheck: all ${#builds[@]} builds print $expected"
echo

# Golden replays: one column per replay, "match" or the first divergent step;
# the snapshot image after the last step must also be the same bytes in every
# build (its checksum is compared with the first build's).
declare -A snapshot_of
header="| build |"; rule="|---|"
for r in "${replays[@]}"; do
  header+=" $(basename "$r" .replay.json) |"; rule+="---|"
done
printf '%s\n%s\n' "$header" "$rule"
# Each build's replays as a separate job, two at a time (each verifier is one
# thread); the table is read from their result files in build order.
set_of() {
  case "$2" in qemu-*) printf '%s\n' "${short_replays[@]}"; return ;; esac
  case "$1" in *-O0*|*checked*) printf '%s\n' "${short_replays[@]}" ;; *) printf '%s\n' "${replays[@]}" ;; esac
}
# A verifier's failure shows in its results (the table below), not here.
verify() {
  IFS='|' read -r name compiler _ runner <<<"$1"
  local verifier set_ run
  verifier=$(program replays "$name" "$compiler")
  mapfile -t set_ < <(set_of "$name" "$runner")
  run=("$verifier")
  [ "$runner" = "-" ] || run=("$runner" "$verifier")
  "${run[@]}" "${set_[@]}" >"$out/replays_$(slug "$name").results" || true
}
for_each_build verify
for b in "${builds[@]}"; do
  IFS='|' read -r name _ _ runner <<<"$b"
  mapfile -t set_ < <(set_of "$name" "$runner")
  results=$(cat "$out/replays_$(slug "$name").results")
  row="| $name |"
  for r in "${replays[@]}"; do
    line=$(grep -F "$r " <<<"$results" | head -1 || true)
    read -r _ verdict detail checksum <<<"$line"
    case "$verdict" in
      match)
        cell=match
        if [ -z "${snapshot_of[$r]:-}" ]; then
          snapshot_of[$r]=$checksum
        elif [ "${snapshot_of[$r]}" != "$checksum" ]; then
          cell="SNAPSHOT BYTES DIFFER"; failed=1
        fi ;;
      DIFFERS) cell="DIFFERS ($detail)"; failed=1 ;;
      ERROR) cell="ERROR"; failed=1 ;;
      *)
        if printf '%s\n' "${set_[@]}" | grep -qxF "$r"; then cell="FAILED (no output)"; failed=1; else cell="-"; fi ;;
    esac
    row+=" $cell |"
  done
  echo "$row"
done
[ $failed -eq 0 ] || { echo "crosscheck: a golden replay differs" >&2; exit 1; }
echo "crosscheck: every build reproduces every golden replay it runs (- = the full replay of a heavy scene, replaced by its short one under qemu, -O0 and checked; wasm and Windows run every full replay)"
