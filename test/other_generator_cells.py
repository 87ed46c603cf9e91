#!/usr/bin/python3
"""seam textile on cells of the second, independent generator (scripts/other_weave.py), which seam
was not tuned on: a plain weave of lenticular tows with jittered, mixed rings and strip caps, an
orthogonal cell (straight wefts and stuffers, a binder), a plain weave whose tows barely overlap
(one curve far smaller than a face) and a coarse 2/2 twill of flat tows.
Asserts the output invariants, not a printout: exit 0; every pair that meets passes `seam check`
(conformity: every curve point a vertex and every curve segment an edge of both tows; no crossing
off the curves; each tow within the tolerance of its input; the curves cover the intersection) at
the reported tolerance; and all tows merged into one surface go through `tetgen -d` with no
intersecting faces.

Usage: other_generator_cells.py SEAM_BINARY
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, '..', 'scripts')
sys.path.insert(0, SCRIPTS)
from real_tows import tetgen_merged  # noqa: E402

CELLS = [
    ('plain, lenticular, jittered', ['--cell', 'plain', '--seed', '2', '--section', 'lenticular', '--path', 'hermite',
                                     '--waviness', '0.04', '--jitter', '0.25', '--ring-mix', '--cap', 'strip',
                                     '--dense', '0.7']),
    ('orthogonal, jittered', ['--cell', 'orthogonal', '--seed', '5', '--jitter', '0.1']),
    ('plain, grazing (a curve far smaller than a face: small curves)',
     ['--cell', 'plain', '--seed', '11', '--section', 'lenticular', '--overlap', '0.0005', '--jitter', '0.3']),
    ('twill, coarse', ['--cell', 'twill', '--seed', '4', '--exponent', '3', '--path', 'hermite', '--tension', '0.3',
                       '--along', '7', '--around', '12', '--crimp', '0.7']),
]


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def main():
    seam = sys.argv[1]
    failures = []
    with tempfile.TemporaryDirectory() as work:
        for n, (name, gen_args) in enumerate(CELLS):
            cell = os.path.join(work, 'cell%d' % n)
            inputs_dir, out_dir = os.path.join(cell, 'in'), os.path.join(cell, 'out')
            gen = run([sys.executable, os.path.join(SCRIPTS, 'other_weave.py'), '--out', inputs_dir] + gen_args)
            if gen.returncode != 0:
                failures.append('%s: the generator failed: %s' % (name, gen.stderr.strip()))
                continue
            inputs = sorted(os.path.join(inputs_dir, f) for f in os.listdir(inputs_dir) if f.endswith('.off'))
            report = os.path.join(cell, 'textile.json')
            t = run([seam, 'textile'] + inputs + ['--out-dir', out_dir, '--report', report, '--quiet'])
            if t.returncode != 0:
                failures.append('%s: seam textile exit %d: %s' % (name, t.returncode, t.stderr.strip()))
                continue
            r = json.load(open(report))
            met = [p for p in r['pairs'] if p['curves'] + p['contact'].get('points', 0) > 0]
            if not met:
                failures.append('%s: no pair of tows meets (the cell is meant to interpenetrate)' % name)
            for p in met:
                a, b = p['a'], p['b']
                c = run([seam, 'check', os.path.join(inputs_dir, a + '.off'), os.path.join(inputs_dir, b + '.off'),
                         os.path.join(out_dir, a + '.off'), os.path.join(out_dir, b + '.off'),
                         os.path.join(out_dir, '%s__%s.polylines.txt' % (a, b)), '--tol', repr(r['verify_tolerance'])])
                if c.returncode != 0:
                    failures.append('%s: seam check %s %s exit %d: %s' % (name, a, b, c.returncode, c.stdout.strip()))
            outputs = [os.path.join(out_dir, os.path.basename(f)) for f in inputs]
            verdict = tetgen_merged(outputs, os.path.join(cell, 'merged.off'), cell)
            if verdict != 'clean':
                failures.append('%s: tetgen -d on all tows merged: %s' % (name, verdict))
            print('%s: %d tows, %d pairs meet, every check passed so far: %s' % (
                name, len(inputs), len(met), not failures), flush=True)
    for f in failures:
        print('FAIL: ' + f)
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
