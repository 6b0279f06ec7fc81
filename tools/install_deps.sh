#!/usr/bin/env bash
# Installs the Debian 12 packages bitstep needs, only those missing.
#   tools/install_deps.sh build   compiler, cmake and the libraries
#   tools/install_deps.sh bench   build + gnuplot (the bench's plots), Bullet (its optional peer) and
#                                 valgrind (its instruction counts)
#   tools/install_deps.sh wasm    cmake, the header-only libraries, emscripten with node
#   tools/install_deps.sh viewer  wasm + Chromium (the viewer's browser test)
#   tools/install_deps.sh npm     npm, where node came without it (tools/viewer/install.sh)
#   tools/install_deps.sh test    bench + viewer + clang, clang-16, libFuzzer and the cross toolchains with
#                                 qemu-user, mingw-w64 with wine, mono (the C# binding)
set -euo pipefail

build_packages=(cmake make gcc g++ catch2 libcli11-dev libfmt-dev nlohmann-json3-dev libxxhash-dev libenet-dev pkg-config)
bench_packages=(gnuplot-nox libbullet-dev valgrind)
# Debian's emscripten 3.1.6 with its prebuilt system libraries; emcc needs
# node-acorn. nodejs: Debian's, unless a newer one is installed already.
wasm_packages=(cmake make nlohmann-json3-dev libxxhash-dev emscripten node-acorn nodejs)
viewer_packages=("${wasm_packages[@]}" chromium)
test_packages=(clang libfuzzer-14-dev g++-i686-linux-gnu g++-aarch64-linux-gnu g++-s390x-linux-gnu g++-arm-linux-gnueabihf
  g++-riscv64-linux-gnu g++-powerpc64le-linux-gnu qemu-user clang-16 g++-mingw-w64-x86-64-posix wine64
  mono-mcs mono-runtime python3 ccache)  # mono: the C# binding of tests/consumer/csharp (tools/check_package.sh);
                                 # python3: tools/check_layers.py; ccache: test.sh's compiler cache

case "${1:-build}" in
  build) wanted=("${build_packages[@]}") ;;
  bench) wanted=("${build_packages[@]}" "${bench_packages[@]}") ;;
  wasm) wanted=("${wasm_packages[@]}") ;;
  viewer) wanted=("${viewer_packages[@]}") ;;
  npm) wanted=(npm) ;;
  test) wanted=("${build_packages[@]}" "${bench_packages[@]}" "${viewer_packages[@]}" "${test_packages[@]}") ;;
  *) echo "install_deps.sh: unknown set '$1' (expected build, bench, wasm, viewer or test)" >&2; exit 2 ;;
esac

missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing: ${missing[*]}"
sudo=()
[ "$(id -u)" -ne 0 ] && sudo=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
