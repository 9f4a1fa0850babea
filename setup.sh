#!/usr/bin/env bash
# shvol set-up: installs the Debian packages shvol needs (only those missing), builds, then
#   ./setup.sh render   renders the default scene media/default.json to default.exr
#   ./setup.sh test     runs every test (ctest), then the tests under ASan+UBSan and the fuzzers
#   ./setup.sh build    only builds
# Nothing is downloaded except Debian packages through apt-get.
set -euo pipefail
cd "$(dirname "$0")"

# libclang-rt-14-dev: the sanitizer and libFuzzer runtimes (only recommended by clang, and
# recommendations are not installed).
packages=(cmake ninja-build clang libclang-rt-14-dev g++ pkg-config
          libopenvdb-dev libboost-iostreams-dev libembree-dev libeigen3-dev libopenexr-dev
          libtbb-dev libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libtinyobjloader-dev
          libboost-math-dev zlib1g-dev python3-matplotlib libopenmpi-dev openmpi-bin)
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

# After the release tests: the test suite again under AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan/), then each libFuzzer target over a copy of its seed
# corpus for SHVOL_FUZZ_SECONDS (default 20) seconds (build-fuzz/), one per core at a time; all
# run even when one fails. A fuzzer's crash input is kept in build-fuzz/artifacts/. README,
# "Fuzzing and sanitizers".
sanitizers() {
  local configure=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++
                   -DSHVOL_BUILD_BENCH=OFF -DSHVOL_BUILD_VALIDATION=OFF -DSHVOL_MPI=OFF)
  local t0=$SECONDS
  cmake -S . -B build-asan "${configure[@]}" -DSHVOL_SANITIZE=ON >/dev/null
  cmake --build build-asan -j "$(nproc)"
  # ctest starts the tests it knows to be long first. On a fresh build-asan it knows none, and
  # the longest (30 s under ASan) ran last with one core idle; the release run's timings (the
  # same tests) tell it which they are.
  local costs=Testing/Temporary/CTestCostData.txt
  if [ ! -e build-asan/$costs ] && [ -e build/$costs ]; then
    mkdir -p build-asan/Testing/Temporary
    cp build/$costs build-asan/$costs
  fi
  (cd build-asan && ctest --output-on-failure -j "$(nproc)")
  echo "setup: sanitizer build and tests took $((SECONDS - t0)) s" >&2

  t0=$SECONDS
  cmake -S . -B build-fuzz "${configure[@]}" -DSHVOL_FUZZ=ON -DSHVOL_BUILD_TESTS=OFF >/dev/null
  cmake --build build-fuzz -j "$(nproc)" --target fuzzers
  local work artifacts="$PWD/build-fuzz/artifacts" supp="$PWD/tests/sanitizers/lsan.supp"
  work=$(mktemp -d)
  mkdir -p "$artifacts"
  # Each fuzzer is one process on one core, so nproc of them run side by side, each for the full
  # time.
  local names=(scene phase_spec phase_csv exr vdb ply obj) jobs i k name failed=()
  jobs=$(nproc)
  for ((i = 0; i < ${#names[@]}; i += jobs)); do
    local batch=("${names[@]:i:jobs}") pids=()
    for name in "${batch[@]}"; do
      mkdir "$work/$name"
      cp tests/fuzz/"$name"/* "$work/$name/"
      LSAN_OPTIONS="suppressions=$supp" build-fuzz/"${name}_fuzzer" "$work/$name" \
        -max_total_time="${SHVOL_FUZZ_SECONDS:-20}" -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix="$artifacts/${name}-" >"$work/$name.log" 2>&1 &
      pids+=($!)
    done
    for k in "${!batch[@]}"; do
      name=${batch[k]}
      if wait "${pids[k]}"; then
        echo "setup: ${name}_fuzzer: $(grep -Eo '#[0-9]+[[:space:]]+DONE.*' "$work/$name.log" | tail -n 1)" >&2
      else
        tail -n 60 "$work/$name.log" >&2
        failed+=("$name")
      fi
    done
  done
  rm -rf "$work"
  if ((${#failed[@]})); then
    echo "setup: failed: ${failed[*]/%/_fuzzer}; the inputs are in $artifacts" >&2
    return 1
  fi
  echo "setup: fuzz build and runs took $((SECONDS - t0)) s" >&2
}

case "${1:-build}" in
  render) build/shvol render media/default.json -o default.exr ;;
  test)   (cd build && ctest --output-on-failure -j "$(nproc)")
          sanitizers ;;
  build)  ;;
  *) echo "usage: $0 [render|test|build]" >&2; exit 2 ;;
esac
