#!/usr/bin/python3
"""seam textile on cells of three or four real tows: the CT-scanned tows of ../shared/data/polytex,
with moved, turned and tilted copies, so that one tow meets several others at once (the case
`seam textile` is for; scripts/real_tows.py runs pairs). Each cell is run through
`seam textile` (default options, exact kernel); every pair it reports is checked with
`seam check --tol <its verify_tolerance>`, and all the outputs merged into one surface (common
vertices merged, a face of two tows written once) go through `tetgen -d`.

Usage: scripts/real_cells.py [--data DIR] [--seam build/seam] [--out DIR] [--only N,...]
                             [--markdown FILE] [-- extra seam textile options]
Prints one row per cell. Skips cleanly when the data is absent. Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_tows import FILES, read_off, read_stl, tetgen_merged, transformed, write_off  # noqa: E402

# name, tows: (tow, ops) each
CELLS = [
    ('three wefts side by side, each overlapping the next by 0.2 along x (grid planes kept)',
     [('weft', []), ('weft', [('move', (2.29, 0, 0))]), ('weft', [('move', (-2.29, 0, 0))])]),
    ('two wefts side by side, overlapping by 0.2, one tilted 1 deg about y; a binder raised 2.4 across both',
     [('weft', []), ('weft', [('turn', 'y', 1), ('move', (2.29, 0, 0))]), ('binder', [('move', (0, 0, 2.4))])]),
    ('weft; binder raised 2.4 and binder turned 90 deg, raised 2.4, through it',
     [('weft', []), ('binder', [('move', (0, 0, 2.4))]), ('binder', [('turn', 'z', 90), ('move', (-4.0, 0, 2.4))])]),
    ('weft, copies scaled by 1.02 and moved (0.3, 0.2, 0.3); binder raised 2.4',
     [('weft', []), ('weft', [('scale', 1.02)]), ('weft', [('move', (0.3, 0.2, 0.3))]),
      ('binder', [('move', (0, 0, 2.4))])]),
    ('binder, copies turned 2 deg about x and moved along x by 0.3 (grid planes kept)',
     [('binder', []), ('binder', [('turn', 'x', 2)]), ('binder', [('move', (0.3, 0, 0))])]),
    # Not a cell: three copies of one tow overlapping along their whole length, so that the
    # boundaries of flat contacts of all three coincide along segments (exit 2, a documented
    # limitation of seam textile).
    ('weft between two copies moved along y by +-0.5 (grid planes kept; all three overlap along their length)',
     [('weft', []), ('weft', [('move', (0, 0.5, 0))]), ('weft', [('move', (0, -0.5, 0))])]),
]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--data', default=os.path.join(here, '..', '..', 'shared', 'data', 'polytex'))
    ap.add_argument('--seam', default=os.path.join(here, '..', 'build', 'seam'))
    ap.add_argument('--out', default=os.path.join(here, '..', 'build', 'real_cells'))
    ap.add_argument('--only', default='')
    ap.add_argument('--markdown', default='')
    ap.add_argument('extra', nargs='*')
    args = ap.parse_args()
    if not all(os.path.exists(os.path.join(args.data, f)) for f in FILES.values()):
        print('real_cells: no data in %s: skipped' % args.data)
        return 0
    tows = {k: read_stl(os.path.join(args.data, f)) for k, f in FILES.items()}
    only = set(int(x) for x in args.only.split(',') if x)
    header = ('| # | cell | tows | exit | time (s) | pairs (triple points, flat-crossing points) | seam check on every pair | tetgen -d on all '
              '| new faces | below 10 deg | below 20 deg |\n|---|---|---|---|---|---|---|---|---|---|---|')
    rows = [header]
    print(header, flush=True)
    for n, (name, parts) in enumerate(CELLS, 1):
        if only and n not in only:
            continue
        work = os.path.join(args.out, 'cell%02d' % n)
        os.makedirs(work, exist_ok=True)
        inputs = []
        for k, (tow, ops) in enumerate(parts):
            points, faces = tows[tow]
            path = os.path.join(work, 't%d.off' % k)
            write_off(path, transformed(points, ops), faces)
            inputs.append(path)
        out_dir = os.path.join(work, 'out')
        report = os.path.join(work, 'textile.json')
        start = time.time()
        run = subprocess.run([args.seam, 'textile'] + inputs + ['--out-dir', out_dir, '--report', report, '--quiet']
                             + args.extra, capture_output=True, text=True)
        seconds = time.time() - start
        if run.returncode != 0:
            row = '| %d | %s | %d | %d | %.1f | - | - | - | - | - | - | %s' % (
                n, name, len(parts), run.returncode, seconds, run.stderr.strip()[:300])
        else:
            r = json.load(open(report))
            tol = r['verify_tolerance']
            checks = []
            pairs = [p for p in r['pairs'] if p['curves'] + p['contact'].get('points', 0) > 0]
            for p in pairs:
                a, b = p['a'], p['b']
                cr = os.path.join(work, 'check_%s_%s.json' % (a, b))
                c = subprocess.run([args.seam, 'check', os.path.join(work, a + '.off'), os.path.join(work, b + '.off'),
                                    os.path.join(out_dir, a + '.off'), os.path.join(out_dir, b + '.off'),
                                    os.path.join(out_dir, '%s__%s.polylines.txt' % (a, b)), '--tol', repr(tol),
                                    '--report', cr], capture_output=True, text=True)
                checks.append(c.returncode == 0)
            # New faces over the whole cell: each tow's faces not in its input (by coordinates).
            new, b10, b20 = new_face_angles(inputs, [os.path.join(out_dir, 't%d.off' % k) for k in range(len(parts))])
            verdict = tetgen_merged([os.path.join(out_dir, 't%d.off' % k) for k in range(len(parts))],
                                    os.path.join(work, 'merged.off'), work, timeout=1800)
            row = '| %d | %s | %d | 0 | %.1f | %d (%d, %d) | %s | %s | %d | %d (%.1f%%) | %d (%.1f%%) |' % (
                n, name, len(parts), seconds, len(pairs), r['triple_points'], r.get('flat_crossing_points', 0),
                'OK' if all(checks) else '%d of %d fail' % (checks.count(False), len(checks)), verdict, new, b10,
                100.0 * b10 / max(new, 1), b20, 100.0 * b20 / max(new, 1))
        rows.append(row)
        print(row, flush=True)
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(rows) + '\n')
    return 0


def new_face_angles(inputs, outputs):
    """New faces (corners not a face of the input, by coordinates), below 10 and 20 degrees."""
    new = b10 = b20 = 0
    for a, b in zip(inputs, outputs):
        p0, f0 = read_off(a)
        p1, f1 = read_off(b)
        old = set(tuple(sorted(p0[i] for i in t)) for t in f0)
        for t in f1:
            corners = [p1[i] for i in t]
            if tuple(sorted(corners)) in old:
                continue
            new += 1
            angle = min_angle(corners)
            b10 += angle < 10
            b20 += angle < 20
    return new, b10, b20


def min_angle(p):
    """The smallest angle (degrees) of the triangle of three points."""
    best = 180.0
    for k in range(3):
        a, b, c = p[k], p[(k + 1) % 3], p[(k + 2) % 3]
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        nu = math.sqrt(sum(x * x for x in u))
        nv = math.sqrt(sum(x * x for x in v))
        if nu == 0 or nv == 0:
            return 0.0
        cos = max(-1.0, min(1.0, sum(u[i] * v[i] for i in range(3)) / (nu * nv)))
        best = min(best, math.degrees(math.acos(cos)))
    return best


if __name__ == '__main__':
    sys.exit(main())
