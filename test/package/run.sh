#!/usr/bin/env bash
# Install + find_package test: installs the seam build in BUILD_DIR into a temporary prefix,
# then configures, builds (Release) and runs the consumer in this directory against it.
#   usage: test/package/run.sh BUILD_DIR
# The library (and the CLI, which is installed too) must already be built in BUILD_DIR.
set -euo pipefail

if [[ $# -ne 1 ]]; then
  echo "usage: $0 BUILD_DIR" >&2
  exit 2
fi
build_dir="$(cd "$1" && pwd)"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

tmp="$(mktemp -d "${TMPDIR:-/tmp}/seam-package-test.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"

echo "== install $build_dir -> $prefix"
cmake --install "$build_dir" --prefix "$prefix"

generator=()
if command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi

echo "== configure the consumer"
cmake -S "$here" -B "$tmp/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix"

echo "== build the consumer"
cmake --build "$tmp/build" -j1

echo "== run the consumer"
"$tmp/build/consumer"
