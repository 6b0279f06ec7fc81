#!/usr/bin/env bash
# Runs a mingw-w64-built Windows program under wine (tools/crosscheck/crosscheck.sh):
# Debian's wine64 package installs the loader outside PATH. Headless and
# quiet, in a prefix of its own under build/crosscheck (tools/crosscheck/crosscheck.sh
# makes it once per run with "tools/crosscheck/wine_run.sh wineboot --init"), no
# Mono or Gecko installers. The program's "\r\n" line ends become "\n"; its
# exit status is kept.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export WINEPREFIX="$root/build/crosscheck/wineprefix" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
unset DISPLAY WAYLAND_DISPLAY
/usr/lib/wine/wine64 "$@" | tr -d '\r'
