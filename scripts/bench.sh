#!/usr/bin/env bash
# Builds seam (scripts/build.sh, Release) and runs the embed benchmark: seam::embed with the
# exact, filtered and float kernels on a generated tow of ~100k faces with three dense rings.
# Writes the Google Benchmark JSON to out/bench_embed.json, then prints a table (whole-embed
# real time and the per-stage seconds) and the ratios exact/filtered and exact/float.
#   scripts/bench.sh [extra benchmark arguments, e.g. --benchmark_filter=Filtered]
# The build directory can be changed with SEAM_BUILD_DIR (default: build), as for build.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir="${SEAM_BUILD_DIR:-build}"
SEAM_BUILD_DIR="$build_dir" bash scripts/build.sh
bench="$build_dir/benchmarks/bench_embed"
if [[ ! -x "$bench" ]]; then
  echo "bench.sh: $bench was not built (is Google Benchmark, libbenchmark-dev, installed?)" >&2
  exit 1
fi

mkdir -p out
"$bench" --benchmark_format=json --benchmark_out=out/bench_embed.json --benchmark_out_format=json "$@" \
  >/dev/null

python3 - out/bench_embed.json <<'EOF'
import json
import sys

with open(sys.argv[1]) as f:
    report = json.load(f)

to_ms = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
stages = ["snap", "locate", "cross", "coarsen", "retriangulate", "splice"]
whole = {}  # kernel -> whole-embed real time (ms)

print("whole-embed real time (ms) and mean stage times (s) over the iterations")
print("%-9s %10s  %s  %8s %8s %8s %9s" % (
    "kernel", "embed_ms", " ".join("%8s" % s[:8] for s in stages),
    "crossed", "crossing", "new", "min_angle"))
for b in report.get("benchmarks", []):
    if b.get("run_type", "iteration") != "iteration":
        continue
    kernel = b.get("label") or b["name"]
    if b.get("error_occurred"):
        print("%-9s ERROR: %s" % (kernel, b.get("error_message", "?")))
        continue
    ms = b["real_time"] * to_ms.get(b.get("time_unit", "ns"), 1e-6)
    whole[kernel] = ms
    print("%-9s %10.1f  %s  %8d %8d %8d %9.4f" % (
        kernel, ms, " ".join("%8.3f" % b.get(s + "_s", float("nan")) for s in stages),
        b.get("faces_crossed", 0), b.get("crossing_points", 0), b.get("new_faces", 0),
        b.get("min_angle", float("nan"))))

print()
for other in ["filtered", "float"]:
    if "exact" in whole and other in whole and whole[other] > 0:
        print("exact/%-8s %6.2f" % (other, whole["exact"] / whole[other]))
    else:
        print("exact/%-8s n/a (a run is missing or failed)" % other)
EOF
