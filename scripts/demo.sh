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

r = json.load(open(sys.argv[1]))
c, f, q, s = r["curve"], r["faces"], r["quality"], r["snap"]
print(f"  kernel               {r['kernel']}")
print(f"  mesh                 {r['input']['faces']} faces in, {r['output']['faces']} faces out")
print(f"  curve                {c['nodes_in']} nodes in, {c['nodes_out']} embedded vertices "
      f"({c['crossing_points']} crossing points, {c['at_mesh_vertices']} at mesh vertices)")
print(f"  snapping             {s['vertices_snapped']} vertices moved (largest move {s['max_move']:.3g}), "
      f"{s['snaps_refused']} refused")
print(f"  re-triangulation     {f['crossed']} faces -> {f['added']} new faces, {f['steiner_points']} Steiner points")
print(f"  quality (new faces)  min angle {q['min_angle_deg']:.2f} deg, {q['below_20']} below 20 deg, "
      f"{q['below_10']} below 10 deg (input faces: min {q['input_min_angle_deg']:.2f} deg)")
print(f"  curve moved by       at most {c['max_deviation']:.3g}")
print(f"  time                 " + ", ".join(f"{k} {v*1000:.1f} ms" for k, v in r["seconds"].items()))
PY
echo
echo "Outputs (in $PWD/$out):"
echo "  mesh with the curve embedded:  $out/tow_embedded.off"
echo "  curve on the mesh's edges:     $out/curve_embedded.polylines.txt"
echo "  report:                        $out/report.json"
