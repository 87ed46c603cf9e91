#!/usr/bin/env bash
# Builds seam (scripts/build.sh, Release) and runs the benchmarks:
#  * bench_embed: seam::embed with the exact, filtered and float kernels on a generated tow of
#    ~100k faces with three dense rings. JSON in out/bench_embed.json; prints a table (whole-embed
#    real time and the per-stage seconds) and the ratios exact/filtered and exact/float.
#  * bench_pair: a whole `seam pair` run (exact, --snap-tol 0, read + compute + write) against
#    CGAL's corefine with the same reading and writing, on a generated weft/warp crossover of
#    76,928 and 64,000 faces, runs alternating. JSON in out/bench_pair.json; prints the ratio
#    seam/corefine of the median run times, seam's stage breakdown, and the quality of the new
#    triangles of both (count, share below 10 and 20 degrees, minimum angle).
#   scripts/bench.sh [extra bench_embed arguments, e.g. --benchmark_filter=Filtered]
# Environment: SEAM_BUILD_DIR (default: build), as for build.sh; SEAM_BENCH, the benchmarks to
# run (default: "embed pair"); SEAM_BENCH_PAIR_ARGS, extra bench_pair arguments (e.g.
# --pair_runs=5, the number of alternating seam/corefine pairs, default 3); SEAM_NO_BUILD=1 to
# skip the build and use the binaries already in the build directory.
#
#   scripts/bench.sh kernels [extra bench_kernels arguments, e.g. --kernels_max_faces=100000]
# runs the exact-versus-float comparison instead (issue 4): seam_robustness --json (the degenerate
# configurations under each kernel; extra arguments in SEAM_ROBUSTNESS_ARGS) into
# out/robustness.json, bench_kernels (each stage per kernel, 1k..1M faces per tow, corefine as the
# peer, peak memory) into out/bench_kernels.json, then scripts/bench_report.py writes
# benchmarks/results/kernels.md and benchmarks/results/kernels.png (the plot needs
# python3-matplotlib). The full run takes about ten minutes on 2 cores.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

if [[ "${1:-}" == kernels ]]; then
  shift
  build_dir="${SEAM_BUILD_DIR:-build}"
  if [[ "${SEAM_NO_BUILD:-0}" != 1 ]]; then
    SEAM_BUILD_DIR="$build_dir" bash scripts/build.sh
  fi
  for exe in bench_kernels seam_robustness; do
    if [[ ! -x "$build_dir/benchmarks/$exe" ]]; then
      echo "bench.sh: $build_dir/benchmarks/$exe was not built (is libbenchmark-dev installed?)" >&2
      exit 1
    fi
  done
  mkdir -p out benchmarks/results
  status=0
  # shellcheck disable=SC2086  # a list of arguments
  "$build_dir/benchmarks/seam_robustness" --json ${SEAM_ROBUSTNESS_ARGS:-} >out/robustness.json || status=$?
  "$build_dir/benchmarks/bench_kernels" --benchmark_format=json --benchmark_out=out/bench_kernels.json \
    --benchmark_out_format=json "$@" >/dev/null
  py=python3  # the plot needs Debian's python3-matplotlib, which a python3 of its own may not see
  if ! python3 -c 'import matplotlib' 2>/dev/null && [[ -x /usr/bin/python3 ]]; then py=/usr/bin/python3; fi
  "$py" scripts/bench_report.py --kernels out/bench_kernels.json --robustness out/robustness.json \
    --markdown benchmarks/results/kernels.md --plot benchmarks/results/kernels.png
  [[ $status -eq 0 ]] || echo "bench.sh: seam_robustness: the exact kernel has runs that are not valid (exit $status)" >&2
  exit 0
fi

build_dir="${SEAM_BUILD_DIR:-build}"
benches="${SEAM_BENCH:-embed pair}"
if [[ "${SEAM_NO_BUILD:-0}" != 1 ]]; then
  SEAM_BUILD_DIR="$build_dir" bash scripts/build.sh
fi
for name in $benches; do
  if [[ ! -x "$build_dir/benchmarks/bench_$name" ]]; then
    echo "bench.sh: $build_dir/benchmarks/bench_$name was not built (is Google Benchmark, libbenchmark-dev, installed?)" >&2
    exit 1
  fi
done

mkdir -p out
if [[ " $benches " == *" embed "* ]]; then
"$build_dir/benchmarks/bench_embed" --benchmark_format=json --benchmark_out=out/bench_embed.json \
  --benchmark_out_format=json "$@" >/dev/null

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
fi

if [[ " $benches " == *" pair "* ]]; then
# shellcheck disable=SC2086  # SEAM_BENCH_PAIR_ARGS is a list of arguments
"$build_dir/benchmarks/bench_pair" --benchmark_format=json --benchmark_out=out/bench_pair.json \
  --benchmark_out_format=json ${SEAM_BENCH_PAIR_ARGS:-} >/dev/null
[[ " $benches " == *" embed "* ]] && echo
python3 - out/bench_pair.json <<'EOF'
import json
import statistics
import sys

with open(sys.argv[1]) as f:
    report = json.load(f)

to_ms = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
runs = {"seam_pair": [], "corefine": []}  # tool -> the runs' benchmark entries, in order
failed = False
for b in report.get("benchmarks", []):
    if b.get("run_type", "iteration") != "iteration":
        continue
    tool = b["name"].split("/")[0]
    if tool not in runs:
        continue
    if b.get("error_occurred"):
        print("%s ERROR: %s" % (b["name"], b.get("error_message", "?")))
        failed = True
        continue
    b["ms"] = b["real_time"] * to_ms.get(b.get("time_unit", "ns"), 1e-6)
    runs[tool].append(b)

print("seam pair vs CGAL corefine, whole runs (read + compute + write, exact kernel), ms, in run order")
for tool, bs in runs.items():
    print("%-10s %s" % (tool, "  ".join("%9.1f" % b["ms"] for b in bs)))
if not runs["seam_pair"] or not runs["corefine"]:
    print("seam/corefine n/a (a run is missing or failed)")
    sys.exit(1)
med = {tool: statistics.median(b["ms"] for b in bs) for tool, bs in runs.items()}
print("median: seam %.1f ms, corefine %.1f ms; seam/corefine %.3f" % (
    med["seam_pair"], med["corefine"], med["seam_pair"] / med["corefine"]))

print()
print("stages, median over the runs (s)")
stages = {"seam_pair": ["read", "intersect", "snap", "embed_a", "embed_b", "remesh", "pair_other", "write"],
          "corefine": ["read", "corefine", "write"]}
for tool, names in stages.items():
    cells = []
    for s in names:
        v = statistics.median(b.get(s + "_s", 0.0) for b in runs[tool])
        if s in ("snap", "remesh") and v == 0.0:
            continue
        cells.append("%s %.3f" % (s, v))
    print("%-10s %s" % (tool, ", ".join(cells)))
cells = []
for s in ["snap", "locate", "cross", "coarsen", "retriangulate", "splice", "rest"]:
    cells.append("%s %.3f" % (s, statistics.median(b.get("embed_" + s + "_s", 0.0) for b in runs["seam_pair"])))
print("%-10s %s" % ("  embed", ", ".join(cells) + "  (embed_a + embed_b)"))

print()
print("new triangles (both meshes; last run)")
print("%-10s %10s %10s %10s %10s %9s" % ("", "out_faces", "new_faces", "<10 deg", "<20 deg", "min_angle"))
for tool, bs in runs.items():
    b = bs[-1]
    print("%-10s %10d %10d %9.2f%% %9.2f%% %9.3f" % (
        tool, b.get("output_faces", 0), b.get("new_faces", 0), 100 * b.get("share_below_10", 0),
        100 * b.get("share_below_20", 0), b.get("min_angle", float("nan"))))
b = runs["seam_pair"][-1]
print("seam: %d curve(s), %d shared vertices; faces crossed %d (weft) + %d (warp); %d Steiner points, "
      "refinement undone in %d faces; new faces by coordinates %d" % (
    b.get("curves", 0), b.get("curve_vertices", 0), b.get("faces_crossed_a", 0), b.get("faces_crossed_b", 0),
    b.get("steiner_points", 0), b.get("refinement_undone", 0), b.get("new_faces_by_coords", 0)))
sys.exit(1 if failed else 0)
EOF
fi
# bench_textile (SEAM_BENCH="textile"): `seam textile` on a generated 4x4 plain weave (532,592
# faces) with 1 and 2 threads, against 16 sequential `seam pair` runs; prints the ratios.
if [[ " $benches " == *" textile "* ]]; then
"$build_dir/benchmarks/bench_textile" --benchmark_out=out/bench_textile.json --benchmark_out_format=json
fi
