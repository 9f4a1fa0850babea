# Sourced by validation/*/run.sh with BUILD_DIR set: configures BUILD_DIR (clang++, Ninja,
# Release) if it is not configured yet, or re-runs CMake when the target $1 is unknown
# (validation/<topic>/ directories are globbed at configure time).
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
    cmake -G Ninja -B "$BUILD_DIR" -S . -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Release \
        >/dev/null
elif [ -n "${1:-}" ] && ! ninja -C "$BUILD_DIR" -t targets all 2>/dev/null | grep -q "^$1:"; then
    cmake -B "$BUILD_DIR" -S . >/dev/null
fi
