#!/usr/bin/env bash
# Configures and builds seam (Release) in build/. Extra arguments go to the configure step,
# e.g. scripts/build.sh -DSEAM_BUILD_BENCHMARKS=OFF. The build directory can be changed with
# SEAM_BUILD_DIR (default: build).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/deps.sh

build_dir="${SEAM_BUILD_DIR:-build}"
generator=()
if command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi
# An existing build directory keeps its generator: do not ask for another one.
if [[ -f "$build_dir/CMakeCache.txt" ]]; then
  generator=()
fi

cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build_dir" -j2
