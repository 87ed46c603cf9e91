#!/usr/bin/env bash
# Checks that the Debian packages seam needs are installed; installs the missing ones when run
# as root, otherwise prints the command to run and fails. Quiet when everything is there.
# The Python packages are for the bindings (python/) and their tests.
# --fuzz: also what scripts/fuzz.sh needs (clang, compiler-rt).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

packages=(
  cmake ninja-build g++
  libcgal-dev libboost-dev libgmp-dev libmpfr-dev
  catch2 libcli11-dev nlohmann-json3-dev libbenchmark-dev libtbb-dev
  tetgen libtet1.5-dev
  python3-dev python3-numpy pybind11-dev python3-pybind11 python3-pytest python3-meshio
)
# scripts/fuzz.sh needs clang and its libFuzzer/sanitizer runtimes.
if [[ "${1:-}" == "--fuzz" ]]; then
  packages+=(clang libclang-rt-14-dev)
fi

missing=()
for pkg in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$pkg")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "deps.sh: missing packages: ${missing[*]}" >&2
if [[ "$(id -u)" -eq 0 ]]; then
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "deps.sh: run as root, or install them with:" >&2
  echo "sudo apt-get install -y ${missing[*]}"
  exit 1
fi
