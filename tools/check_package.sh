#!/usr/bin/env bash
# The installed package as a game uses it: installs a Release build tree
# (default build/release) into a temporary prefix, builds tests/consumer (a C
# and a C++ program, find_package(bitstep)) against it, runs both on
# scenes/pyramid20.json with the ball of scenes/pyramid20.short.replay.json
# thrown in, and checks they print that golden's last hash; builds
# tests/consumer/shared (the C program again, from a project without C++,
# find_package(bitstep COMPONENTS c) with every other package disabled,
# linking the shared libbitstep.so) and checks the same line; checks that
# the installed libbitstep.so exports only bitstep_ symbols and that its
# soname is libbitstep.so.MAJOR (0.MINOR before 1.0); that no
# file of the installed CMake package names a path of this machine; that
# the installed command line verifies that golden; then that
# docs/embedding.md's example is tests/consumer/cpp_consumer.cpp, byte for
# byte; and plays a rollback match over ENet between C peers and between a
# C and a C# peer (below). Needs libenet-dev and mono-mcs
# (tools/install_deps.sh test). The prefix and the consumers' builds are removed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
tree=${1:-build/release}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/install
cmake --install "$tree" --prefix "$prefix" >/dev/null
cmake -S tests/consumer -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/consumer" -j"$(nproc)" >/dev/null
# The C-only consumer finds no package but bitstep's component c: any
# find_dependency left in its way fails the configure (the disabled packages
# are never asked for, hence --no-warn-unused-cli).
cmake -S tests/consumer/shared -B "$work/shared" --no-warn-unused-cli -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON -DCMAKE_DISABLE_FIND_PACKAGE_Threads=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_fmt=ON >/dev/null
cmake --build "$work/shared" -j"$(nproc)" >/dev/null

golden=$(grep -o '"[0-9a-f]\{16\}"' scenes/pyramid20.short.replay.json | tail -1 | tr -d '"')
status=0
for consumer in consumer/c_consumer consumer/cpp_consumer shared/c_shared_consumer; do
  name=${consumer#*/}
  line=$("$work/$consumer" scenes/pyramid20.json | tail -1)
  if [ "$line" = "tick 20 hash $golden" ]; then
    echo "$name: $line (the golden's)"
  else
    echo "check_package.sh: $name printed '$line', the golden ends with $golden" >&2
    status=1
  fi
done

# The shared library: only the C API's symbols, and the soname of its binary interface.
lib=$(find "$prefix" -name libbitstep.so -print -quit)
version=$(sed -n 's/^set(PACKAGE_VERSION "\(.*\)")$/\1/p' "$prefix"/lib*/cmake/bitstep/bitstepConfigVersion.cmake)
if [ -z "$lib" ] || [ ! -e "$lib.$version" ]; then
  echo "check_package.sh: no libbitstep.so and libbitstep.so.$version installed" >&2
  status=1
else
  exported=$(nm -D --defined-only "$lib" | awk '{print $NF}')
  others=$(grep -v '^bitstep_' <<<"$exported" || true)
  if [ -n "$others" ]; then
    echo "check_package.sh: libbitstep.so exports $(wc -l <<<"$others") symbols not named bitstep_, first:" \
      $(head -5 <<<"$others") >&2
    status=1
  else
    echo "libbitstep.so exports $(grep -c . <<<"$exported") symbols, every one named bitstep_"
  fi
  soname=$(readelf -d "$lib" | sed -n 's/.*Library soname: \[\(.*\)\]$/\1/p')
  abi=${version%%.*}
  if [ "$abi" = 0 ]; then abi=$(cut -d. -f1,2 <<<"$version"); fi  # before 1.0 a minor version may break it
  if [ "$soname" = "libbitstep.so.$abi" ]; then
    echo "libbitstep.so's soname is $soname (version $version)"
  else
    echo "check_package.sh: libbitstep.so's soname is '$soname', not libbitstep.so.$abi (version $version)" >&2
    status=1
  fi
fi

# The CMake package names no path of this machine (the prefix's own are
# relative to its files): not the system's libraries, the sources, the
# build tree or the prefix.
if paths=$(grep -rnF -e /usr/ -e "$PWD" -e "$(cd "$tree" && pwd)" -e "$prefix" "$prefix"/lib*/cmake/bitstep/); then
  echo "check_package.sh: the installed CMake package names paths of this machine:" >&2
  echo "$paths" >&2
  status=1
else
  echo "the installed CMake package names no path of this machine"
fi

# The command line is installed too: it verifies a golden replay.
if "$prefix/bin/bitstep" verify scenes/pyramid20.short.replay.json >/dev/null; then
  echo "the installed bitstep verifies scenes/pyramid20.short.replay.json"
else
  echo "check_package.sh: the installed bitstep did not verify scenes/pyramid20.short.replay.json" >&2
  status=1
fi

# A rollback match with the game's own state (health and score changed by
# contacts, rolled back with the physics) over ENet on 127.0.0.1: two C
# peers (tests/consumer/session_peer.c, on the shared library), then a C
# peer against a C# one (tests/consumer/csharp: a P/Invoke binding under
# mono), each dropping 10% of the packets it sends unreliably. Every peer
# must print the line of a reference run that knows every input, in C and
# in C# alike.
ticks=300
mcs -nologo -out:"$work/SessionPeer.exe" tests/consumer/csharp/Bitstep.cs tests/consumer/csharp/SessionPeer.cs
c_peer=("$work/shared/session_peer")
csharp_peer=(env LD_LIBRARY_PATH="$prefix/lib:${LD_LIBRARY_PATH:-}" mono "$work/SessionPeer.exe")
run() {  # a peer of kind $1 (c, csharp) as player $2 on port $3, dialling $4
  local -n peer_command=${1}_peer
  timeout 90 "${peer_command[@]}" "$scene" "$2" "$3" "$4" "$ticks" 10
}
scene=tests/consumer/arena.json
reference=$("${c_peer[@]}" "$scene" reference "$ticks")
if [ "$("${csharp_peer[@]}" "$scene" reference "$ticks")" != "$reference" ]; then
  echo "check_package.sh: the C# reference run differs from the C one ($reference)" >&2
  status=1
fi
port=$((20000 + $$ % 20000))
for pair in "c c" "c csharp"; do
  read -r first second <<<"$pair"
  run "$first" 0 "$port" $((port + 1)) >"$work/peer0" 2>"$work/peer0.err" &
  player0=$!
  run "$second" 1 $((port + 1)) "$port" >"$work/peer1" 2>"$work/peer1.err" || true
  wait "$player0" || true
  port=$((port + 2))
  for p in 0 1; do
    if [ "$(cat "$work/peer$p")" = "$reference" ]; then
      echo "a $first and a $second peer under 10% loss: player $p printed the reference's line ($(cat "$work/peer$p.err"))"
    else
      echo "check_package.sh: $first vs $second: player $p printed '$(cat "$work/peer$p")', the reference '$reference'" >&2
      cat "$work/peer$p.err" >&2
      status=1
    fi
  done
done
echo "the reference: $reference"

# docs/embedding.md's example: the lines between its two markers.
if ! sed -n '/^<!-- example: tests\/consumer\/cpp_consumer.cpp -->$/,/^<!-- end of example -->$/p' docs/embedding.md |
    sed '1,2d;$d' | sed '$d' | diff -u tests/consumer/cpp_consumer.cpp - >/dev/null; then
  echo "check_package.sh: docs/embedding.md's example differs from tests/consumer/cpp_consumer.cpp" >&2
  status=1
else
  echo "docs/embedding.md's example is tests/consumer/cpp_consumer.cpp"
fi
exit "$status"
