#!/usr/bin/env bash
# Runs an emscripten-built program under node (tools/build_wasm.sh):
# Node 20's fetch would make the generated loader fetch its .wasm by a file
# path, which fails; without it the loader reads the file.
exec node --no-experimental-fetch "$@"
