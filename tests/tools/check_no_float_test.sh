#!/usr/bin/env bash
# tests/tools/check_no_float_test.sh CXX
#
# Shows that tools/check_no_float.sh can fail: compiles planted_float.cpp
# (a double multiply, an int -> double conversion, std::sqrt) with CXX at -O0
# and -O2 into a temporary directory laid out like a build dir's
# CMakeFiles/bitstep_{fixed,core}.dir, runs the check on it, and asserts
# that it exits 1 naming each planted instruction and reference in each
# object; and that a directory without objects is an error (exit 2), not
# a pass.
set -euo pipefail
cxx=${1:?usage: tests/tools/check_no_float_test.sh CXX}
here=$(cd "$(dirname "$0")" && pwd)
check=$here/../../tools/check_no_float.sh

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/CMakeFiles/bitstep_fixed.dir" "$work/CMakeFiles/bitstep_core.dir"
"$cxx" -std=c++20 -O0 -c "$here/planted_float.cpp" -o "$work/CMakeFiles/bitstep_fixed.dir/planted.o"
"$cxx" -std=c++20 -O2 -c "$here/planted_float.cpp" -o "$work/CMakeFiles/bitstep_core.dir/planted.o"

status=0
output=$("$check" "$work" 2>&1) || status=$?
printf '%s\n' "$output"
fail() { echo "check_no_float_test.sh: $*" >&2; exit 1; }
[ "$status" -eq 1 ] || fail "the check exited $status on planted floating point, not 1"
for target in bitstep_fixed bitstep_core; do
  object="$work/CMakeFiles/$target.dir/planted.o"
  for expected in "planted_product(double, double): mulsd " \
                  "planted_conversion(int): cvtsi2sd " \
                  "undefined reference: sqrt (libm)"; do
    grep -qF "$object: $expected" <<<"$output" || fail "not named in $target: $expected"
  done
done

mkdir "$work/empty"
status=0
output=$("$check" "$work/empty" 2>&1) || status=$?
[ "$status" -eq 2 ] || fail "the check exited $status on a directory without objects, not 2: $output"
echo "check_no_float_test.sh: the check names the planted float at -O0 and -O2, and refuses an empty build dir"
