#!/usr/bin/env bash
# The installed package as a game uses it: installs a Release build tree
# (default build/release) into build/install, builds tests/consumer (a C and
# a C++ program, find_package(bitstep)) against it, runs both on
# scenes/pyramid20.json with the ball of scenes/pyramid20.short.replay.json
# thrown in, and checks they print that golden's last hash; checks that the
# installed command line verifies that golden; then that docs/embedding.md's
# example is tests/consumer/cpp_consumer.cpp, byte for byte.
set -euo pipefail
cd "$(dirname "$0")/.."
tree=${1:-build/release}

rm -rf build/install build/consumer
cmake --install "$tree" --prefix build/install >/dev/null
cmake -S tests/consumer -B build/consumer -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$PWD/build/install" >/dev/null
cmake --build build/consumer -j"$(nproc)" >/dev/null

golden=$(grep -o '"[0-9a-f]\{16\}"' scenes/pyramid20.short.replay.json | tail -1 | tr -d '"')
status=0
for consumer in c_consumer cpp_consumer; do
  line=$(build/consumer/$consumer scenes/pyramid20.json | tail -1)
  if [ "$line" = "tick 20 hash $golden" ]; then
    echo "$consumer: $line (the golden's)"
  else
    echo "check_package.sh: $consumer printed '$line', the golden ends with $golden" >&2
    status=1
  fi
done

# The command line is installed too: it verifies a golden replay.
if build/install/bin/bitstep verify scenes/pyramid20.short.replay.json >/dev/null; then
  echo "the installed bitstep verifies scenes/pyramid20.short.replay.json"
else
  echo "check_package.sh: the installed bitstep did not verify scenes/pyramid20.short.replay.json" >&2
  status=1
fi

# docs/embedding.md's example: the lines between its two markers.
if ! sed -n '/^<!-- example: tests\/consumer\/cpp_consumer.cpp -->$/,/^<!-- end of example -->$/p' docs/embedding.md |
    sed '1,2d;$d' | sed '$d' | diff -u tests/consumer/cpp_consumer.cpp - >/dev/null; then
  echo "check_package.sh: docs/embedding.md's example differs from tests/consumer/cpp_consumer.cpp" >&2
  status=1
else
  echo "docs/embedding.md's example is tests/consumer/cpp_consumer.cpp"
fi
exit "$status"
