#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -fsanitize=fuzzer,address,undefined, CGAL assertions on)
# in build-fuzz/ and runs one of them for SECONDS on its committed seed corpus.
#   scripts/fuzz.sh TARGET SECONDS     TARGET: off obj ply stl polylines pair
#   scripts/fuzz.sh --build            only build every target
#   scripts/fuzz.sh --configure        only configure build-fuzz/ (scripts/test.sh --sanitize
#                                      builds and runs the test suite in the same directory)
# Corpus: fuzz/corpus/TARGET/ (read only; new inputs found go to build-fuzz/corpus/TARGET/).
# A crash, a sanitizer finding, a leak or an input slower than 10 s (the pair target: 30 s) fails
# the run; libFuzzer writes the input to build-fuzz/crash-*: minimise it (fuzz_TARGET -minimize_crash=1 FILE),
# commit it under fuzz/regressions/TARGET/ (test/test_fuzz_regressions.cpp runs it through ctest)
# and fix the bug.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

usage="usage: scripts/fuzz.sh TARGET SECONDS | --build | --configure   (TARGET: off obj ply stl polylines pair)"
targets=(off obj ply stl polylines pair)
build_only=0
configure_only=0
if [[ $# -eq 1 && "$1" == "--build" ]]; then
  build_only=1
elif [[ $# -eq 1 && "$1" == "--configure" ]]; then
  configure_only=1
elif [[ $# -eq 2 ]]; then
  target="$1"
  seconds="$2"
  if [[ ! " ${targets[*]} " == *" $target "* ]]; then
    echo "fuzz.sh: unknown target: $target ($usage)" >&2
    exit 2
  fi
  if [[ ! "$seconds" =~ ^[0-9]+$ ]]; then
    echo "fuzz.sh: SECONDS must be a whole number: $seconds" >&2
    exit 2
  fi
else
  echo "$usage" >&2
  exit 2
fi

bash scripts/deps.sh --fuzz
for tool in clang++; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "fuzz.sh: $tool not found (Debian: apt-get install clang libclang-rt-14-dev)" >&2
    exit 1
  fi
done

build_dir=build-fuzz
generator=()
if command -v ninja >/dev/null 2>&1 && [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  generator=(-G Ninja)
fi
# -O1 -g1 (line tables) without NDEBUG: CGAL's assertions stay on and throw, so the fuzzer reports them.
# The test suite is configured too: scripts/test.sh --sanitize runs it on this same build, so the
# library is compiled once for both.
[[ "${SEAM_FUZZ_NO_BUILD:-0}" == 1 && $build_only -eq 0 && $configure_only -eq 0 ]] ||
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Fuzz \
  -DCMAKE_CXX_FLAGS_FUZZ="-O1 -g1" -DSEAM_FUZZ=ON -DSEAM_BUILD_TESTS=ON -DSEAM_BUILD_BENCHMARKS=OFF >/dev/null
if [[ $configure_only -eq 1 ]]; then
  exit 0
fi
if [[ $build_only -eq 1 ]]; then
  cmake --build "$build_dir" -j"${SEAM_JOBS:-2}" --target "${targets[@]/#/fuzz_}"
  exit 0
fi
# SEAM_FUZZ_NO_BUILD=1: the targets were built already (scripts/fuzz.sh --build), so that several
# can run at once without two builds in one directory.
if [[ "${SEAM_FUZZ_NO_BUILD:-0}" != 1 ]]; then
  cmake --build "$build_dir" -j"${SEAM_JOBS:-2}" --target "fuzz_$target"
fi

work="$build_dir/corpus/$target"
mkdir -p "$work"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# New inputs go to $work (first directory); the committed seeds are read only.
# The pair target runs the whole pipeline under the exact kernel with the sanitizers, 5 to 25 times
# slower than a Release build: the quality stage's budget (16 insertions per band face) bounds a
# unit's work, and the inputs that reach it take up to about 10 s here (under 0.5 s in Release).
unit_timeout=10
[[ "$target" == pair ]] && unit_timeout=30
"$build_dir/fuzz/fuzz_$target" "$work" "fuzz/corpus/$target" -max_total_time="$seconds" -timeout="$unit_timeout" \
  -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$build_dir/" -print_final_stats=1
