#!/usr/bin/env bash
# Builds seam (scripts/build.sh, or scripts/fuzz.sh's sanitized build) and runs the test suite
# with ctest.
#   scripts/test.sh              Release build in build/
#   scripts/test.sh --sanitize   AddressSanitizer + UBSan build in build-fuzz/ (clang, CGAL's
#                                assertions on; the build the fuzz targets use, see scripts/fuzz.sh)
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
  # One sanitized build serves the suite and the fuzzers: clang, -O1 with line tables only (CGAL
  # compiles much faster), ASan + UBSan, coverage instrumentation for libFuzzer, and CGAL's
  # assertions on (no NDEBUG), so that a CGAL precondition the suite reaches fails it too.
  build_dir=build-fuzz
  bash scripts/fuzz.sh --configure
  cmake --build "$build_dir" -j"${SEAM_JOBS:-2}"
  export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=0:detect_stack_use_after_return=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
else
  build_dir=build
  bash scripts/build.sh
fi

# The package test (install + find_package from another project) runs in the Release build only;
# so do some slow tests whose code the sanitized run reaches through smaller ones (the seam pair
# command on files: the CLI contract tests; the quality stage on a set of crossovers: the other
# quality-stage tests; the chain on a 4 x 4 weave: the chain on the bundled 2 x 2 weave; the
# agreement of seam check and tetgen -d on many pairs: the other check tests; signals at every
# moment of a run: the other contract tests; the generator's near-degenerate cells, whose seam
# pair on cell 16 takes 9 s in Release and over 300 s sanitized: the unit tests of its rules and
# the generator's other cells), to keep CI well under 30 minutes.
exclude=()
if [[ $sanitize -eq 1 ]]; then
  exclude=(-E "install_and_find_package|the seam pair command conforms two tow files|crossovers the old repair steps were tuned on|a generated 4x4 plain weave|mesh_meshio_weave_4x4|seam check and tetgen -d agree on every pair|SIGINT or SIGTERM at any moment|other_generator_near_degenerate")
fi
ctest --test-dir "$build_dir" --output-on-failure -j2 "${exclude[@]}"
