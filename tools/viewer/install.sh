#!/usr/bin/env bash
# Installs the viewer's one npm package, three.js, at the version pinned in
# package.json and package-lock.json (npm ci: the lock's exact files, its
# integrity checked), into tools/viewer/node_modules. Skipped when it is
# there already at that version.
set -euo pipefail
cd "$(dirname "$0")"
pinned=$(sed -n 's/.*"three": "\(.*\)".*/\1/p' package.json)
installed=$(sed -n 's/.*"version": "\(.*\)".*/\1/p' node_modules/three/package.json 2>/dev/null | head -1 || true)
[ "$installed" = "$pinned" ] && exit 0
command -v npm >/dev/null || ../install_deps.sh npm
npm ci --no-audit --no-fund --loglevel=error
