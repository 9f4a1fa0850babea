#!/usr/bin/env bash
# shvol set-up: installs the Debian packages shvol needs (only those missing), builds, then
#   ./setup.sh render   renders the default scene media/default.json to default.exr
#   ./setup.sh test     runs every test (ctest), then a sanitizer build's tests and the fuzzers
#   ./setup.sh build    only builds
# Nothing is downloaded except Debian packages through apt-get.
set -euo pipefail
cd "$(dirname "$0")"
if [ $# -gt 1 ] || ! case "${1:-build}" in render | test | build) true ;; *) false ;; esac; then
  echo "usage: $0 [render|test|build]" >&2
  exit 2
fi
# The tests build shell commands from the checkout's path, and the sanitizers' options
# (LSAN_OPTIONS) split at blanks, ':' and ',': a path of other characters than these would fail
# them by the dozen (helpers 154, 156). The path the build sees, links resolved, is checked.
case "$(pwd -P)" in
  *[!A-Za-z0-9._/+@%=-]*)
    echo "setup: the checkout's path '$(pwd -P)' has characters other than letters, digits and" \
         "._/+@%=-, which the tests' commands and the sanitizer options cannot carry: move the" \
         "checkout to such a path" >&2
    exit 1 ;;
esac

# libclang-rt-14-dev: the sanitizer and libFuzzer runtimes (only recommended by clang, and
# recommendations are not installed). git: the build names its revision by it, and a test makes
# checkouts of its own (a source archive on a machine without git failed it).
packages=(cmake ninja-build clang libclang-rt-14-dev g++ pkg-config
          libopenvdb-dev libboost-iostreams-dev libembree-dev libeigen3-dev libopenexr-dev
          libtbb-dev libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libtinyobjloader-dev
          libboost-math-dev zlib1g-dev python3-matplotlib libopenmpi-dev openmpi-bin git)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  source tools/apt_install.sh
  apt_install setup "${missing[@]}" || exit 1
fi

# clang++ compiles the OpenVDB translation unit about 2.5x faster than g++.
t0=$SECONDS
# Every option the tests depend on is given, so that a build/ configured otherwise before (tests
# off, a few test modules, no MPI, sanitizers) cannot make the test command pass on part of the
# suite (helper 154); the configure's own lines are left out but for shvol's (MPI found or not).
cmake -G Ninja -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
      -DSHVOL_BUILD_TESTS=ON -USHVOL_TEST_MODULES -DSHVOL_MPI=ON -DSHVOL_SANITIZE=OFF \
      -DSHVOL_FUZZ=OFF -DSHVOL_BUILD_BENCH=ON -DSHVOL_BUILD_VALIDATION=ON |
  { grep '^-- shvol:' >&2 || true; }
cmake --build build -j "$(nproc)"
echo "setup: release build took $((SECONDS - t0)) s" >&2

# After the release tests, one sanitizer build (build-asan/: AddressSanitizer and
# UndefinedBehaviorSanitizer, libFuzzer coverage in the loaders) of the libraries, the test
# programs of the modules in sanitized_modules, the hard-case suite and the fuzz targets; it runs
# those tests, then each libFuzzer target over a copy of its seed corpus for SHVOL_FUZZ_SECONDS
# (default 20) seconds, one per core at a time; all run even when one fails. A fuzzer's crash
# input is kept in build-asan/fuzz-artifacts/. README, "Fuzzing and sanitizers".
sanitized_modules="core;media"
sanitizers() {
  local t0=$SECONDS
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
        -DSHVOL_SANITIZE=ON -DSHVOL_FUZZ=ON -DSHVOL_MPI=OFF -DSHVOL_BUILD_BENCH=OFF \
        -DSHVOL_BUILD_VALIDATION=OFF -DSHVOL_TEST_MODULES="$sanitized_modules" >/dev/null
  local targets=(fuzzers validate_hardcases) mod
  for mod in ${sanitized_modules//;/ }; do targets+=("test_$mod"); done
  cmake --build build-asan -j "$(nproc)" --target "${targets[@]}"
  echo "setup: sanitizer build took $((SECONDS - t0)) s" >&2
  # ctest starts the tests it knows to be long first. On a fresh build-asan it knows none, and
  # the longest could run last with one core idle; the release run's timings (the same tests)
  # tell it which they are.
  t0=$SECONDS
  local costs=Testing/Temporary/CTestCostData.txt
  if [ ! -e build-asan/$costs ] && [ -e build/$costs ]; then
    mkdir -p build-asan/Testing/Temporary
    cp build/$costs build-asan/$costs
  fi
  (cd build-asan && ctest --output-on-failure --no-tests=error -j "$(nproc)")
  echo "setup: sanitizer tests took $((SECONDS - t0)) s" >&2

  t0=$SECONDS
  local work artifacts="$PWD/build-asan/fuzz-artifacts" supp="$PWD/tests/sanitizers/lsan.supp"
  work=$(mktemp -d)
  # Ctrl-C (or CI's SIGTERM) ends the fuzzers under way and removes their work directory, which
  # kept running and stayed behind (helper 154).
  local running=()
  trap 'kill "${running[@]}" 2>/dev/null; rm -rf "$work"; exit 130' INT
  trap 'kill "${running[@]}" 2>/dev/null; rm -rf "$work"; exit 143' TERM
  mkdir -p "$artifacts"
  # Each fuzzer is one process on one core, so nproc of them run side by side, each for the full
  # time. An input taking 60 s is a hang; the slowest seen took 2.3 s in a fast hour (README).
  local names=(scene phase_spec phase_csv exr vdb ply obj checkpoint sweep) jobs i k name failed=()
  jobs=$(nproc)
  for ((i = 0; i < ${#names[@]}; i += jobs)); do
    local batch=("${names[@]:i:jobs}") pids=()
    for name in "${batch[@]}"; do
      mkdir "$work/$name"
      cp tests/fuzz/"$name"/* "$work/$name/"
      LSAN_OPTIONS="suppressions=$supp" build-asan/"${name}_fuzzer" "$work/$name" \
        -max_total_time="${SHVOL_FUZZ_SECONDS:-20}" -timeout=60 -rss_limit_mb=2048 \
        -artifact_prefix="$artifacts/${name}-" >"$work/$name.log" 2>&1 &
      pids+=($!)
    done
    running=("${pids[@]}")
    for k in "${!batch[@]}"; do
      name=${batch[k]}
      if wait "${pids[k]}"; then
        echo "setup: ${name}_fuzzer: $(grep -Eo '#[0-9]+[[:space:]]+DONE.*' "$work/$name.log" | tail -n 1)" >&2
      else
        echo "setup: ${name}_fuzzer failed; the last lines of its log:" >&2
        tail -n 60 "$work/$name.log" >&2
        failed+=("$name")
      fi
    done
  done
  trap - INT TERM
  rm -rf "$work"
  if ((${#failed[@]})); then
    echo "setup: failed: ${failed[*]/%/_fuzzer}; the inputs are in $artifacts" >&2
    return 1
  fi
  echo "setup: fuzz runs took $((SECONDS - t0)) s" >&2
}

case "${1:-build}" in
  render) build/shvol render media/default.json -o default.exr ;;
  test)   t0=$SECONDS
          (cd build && ctest --output-on-failure --no-tests=error -j "$(nproc)")
          echo "setup: release tests took $((SECONDS - t0)) s" >&2
          sanitizers ;;
  build)  ;;
esac
