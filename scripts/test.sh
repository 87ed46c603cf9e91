#!/usr/bin/env bash
# Builds seam (scripts/build.sh) and runs the test suite with ctest.
#   scripts/test.sh              Release build in build/
#   scripts/test.sh --sanitize   AddressSanitizer + UBSan build in build-asan/ (no benchmarks)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

sanitize=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    -h|--help)
      echo "usage: scripts/test.sh [--sanitize]"
      exit 0
      ;;
    *)
      echo "test.sh: unknown argument: $arg (usage: scripts/test.sh [--sanitize])" >&2
      exit 2
      ;;
  esac
done

if [[ $sanitize -eq 1 ]]; then
  build_dir=build-asan
  # The later -DCMAKE_BUILD_TYPE overrides build.sh's Release.
  SEAM_BUILD_DIR="$build_dir" bash scripts/build.sh \
    -DSEAM_SANITIZE=ON -DSEAM_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"  # line tables only: CGAL compiles much faster
  export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=0:detect_stack_use_after_return=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
else
  build_dir=build
  bash scripts/build.sh
fi

# The package test (install + find_package from another project) runs in the Release build only.
exclude=()
if [[ $sanitize -eq 1 ]]; then exclude=(-E install_and_find_package); fi
ctest --test-dir "$build_dir" --output-on-failure -j2 "${exclude[@]}"
