#!/usr/bin/env bash
# shvol set-up: installs the Debian packages shvol needs (only those missing), builds, then
#   ./setup.sh render   renders the default scene media/default.json to default.exr
#   ./setup.sh test     runs every test (ctest)
#   ./setup.sh build    only builds
# Nothing is downloaded except Debian packages through apt-get.
set -euo pipefail
cd "$(dirname "$0")"

packages=(cmake ninja-build clang g++ pkg-config
          libopenvdb-dev libboost-iostreams-dev libembree-dev libeigen3-dev libopenexr-dev
          libtbb-dev libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
          libboost-math-dev zlib1g-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
fi

# clang++ compiles the OpenVDB translation unit about 2.5x faster than g++.
cmake -G Ninja -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build build -j "$(nproc)"

case "${1:-build}" in
  render) build/shvol render media/default.json -o default.exr ;;
  test)   cd build && ctest --output-on-failure -j "$(nproc)" ;;
  build)  ;;
  *) echo "usage: $0 [render|test|build]" >&2; exit 2 ;;
esac
