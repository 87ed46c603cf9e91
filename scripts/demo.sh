#!/usr/bin/env bash
# Builds seam, embeds the example ring curve into the example tow and summarises the result.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/build.sh

out=out/demo
mkdir -p "$out"
build/seam embed examples/tow.off --curves examples/ring.polylines.txt \
  -o "$out/tow_embedded.off" \
  --curves-out "$out/curve_embedded.polylines.txt" \
  --report "$out/report.json"

echo
echo "== seam demo: summary"
python3 - "$out/report.json" <<'PY'
import json
import sys

with open(sys.argv[1]) as f:
    report = json.load(f)

# The report format is still being designed: print the keys we know about, if any, else all.
known = [
    "kernel", "status", "input", "output",
    "input_faces", "output_faces", "input_vertices", "output_vertices",
    "new_faces", "new_vertices", "curves", "curve_points", "curve_edges",
    "snapped", "max_snap_distance", "max_deviation", "timings", "time_seconds",
]
shown = [k for k in known if isinstance(report, dict) and k in report]
if shown:
    width = max(len(k) for k in shown)
    for k in shown:
        v = report[k]
        text = json.dumps(v) if isinstance(v, (dict, list)) else str(v)
        print(f"  {k:<{width}}  {text}")
else:
    print(json.dumps(report, indent=2, sort_keys=True))
PY
echo
echo "Outputs (in $PWD/$out):"
echo "  mesh with the curve embedded:  $out/tow_embedded.off"
echo "  curve on the mesh's edges:     $out/curve_embedded.polylines.txt"
echo "  report:                        $out/report.json"
