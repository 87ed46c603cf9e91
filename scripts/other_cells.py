#!/usr/bin/python3
"""seam on unit cells from a second, independent generator (scripts/other_weave.py: spline/cosine
paths, super-ellipse, lenticular and varying sections, staggered and jittered rings): inputs seam
was not tuned on. Each configuration is generated (some with one tow moved, turned or scaled
afterwards), run through `seam textile` (default options, exact kernel); every pair it reports is
checked with `seam check --tol <its verify_tolerance>`, and all outputs merged into one surface go
through `tetgen -d` (as scripts/real_cells.py). The first crossing pair of each configuration is
also run through `seam pair`, `seam check` (--tol of the pair's report) and `tetgen -d`.

Usage: scripts/other_cells.py [--seam build/seam] [--out build/other_cells] [--only N,...]
                              [--markdown FILE] [--timeout S]
Prints one row per configuration; the full stderr of every failing run is in its directory
(textile.stderr, pair.stderr) and printed at the end with the command that reproduces it.
Standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from real_tows import read_off, tetgen_merged, transformed, write_off  # noqa: E402
from real_cells import new_face_angles  # noqa: E402
from other_weave import intersecting_pairs  # noqa: E402

# a fine crimped weft (3 spacings, ~30k faces) and a fine straight one (orthogonal cell, layer 0)
FINE_WEFT = ['--cell', 'plain', '--seed', '21', '--repeat', '3', '1', '--along', '40', '--around', '120',
             '--dense', '0']
STRAIGHT_WEFT = ['--cell', 'orthogonal', '--seed', '21', '--layers', '2', '--repeat', '3', '1', '--around', '128',
                 '--dense', '0']
STRAIGHT_16x32 = ['--cell', 'orthogonal', '--seed', '21', '--layers', '2', '--repeat', '3', '1', '--around', '32',
                  '--dense', '0', '--along', '16', '--no-stagger']

# name, generator arguments, transforms {tow: ops} applied after generation (see generate())
CONFIGS = [
    ('plain 2x2, super-ellipse p=2.5, RMF frame, staggered rings, 10 rings/spacing',
     ['--cell', 'plain', '--seed', '1'], {}),
    ('plain 2x2, lenticular, Hermite path, meander 0.04, jitter 0.25, ring mix, strip caps, dense 0.7',
     ['--cell', 'plain', '--seed', '2', '--section', 'lenticular', '--path', 'hermite', '--waviness', '0.04',
      '--jitter', '0.25', '--ring-mix', '--cap', 'strip', '--dense', '0.7'], {}),
    ('plain 2x2, varying section (width +-15%, twist 5 deg), up frame, meander 0.03, jitter 0.15, fine (14 x 24)',
     ['--cell', 'plain', '--seed', '3', '--section', 'varying', '--vary', '0.15', '--twist', '5', '--frame', 'up',
      '--waviness', '0.03', '--jitter', '0.15', '--along', '14', '--around', '24'], {}),
    ('twill 2/2 4x4 (8 tows), super-ellipse p=3, Hermite tension 0.3, coarse (7 x 12), crimp 0.7',
     ['--cell', 'twill', '--seed', '4', '--exponent', '3', '--path', 'hermite', '--tension', '0.3',
      '--along', '7', '--around', '12', '--crimp', '0.7'], {}),
    ('orthogonal 3 weft layers, 2 stuffer layers, 1 binder (11 tows), jitter 0.1',
     ['--cell', 'orthogonal', '--seed', '5', '--jitter', '0.1'], {}),
    ('plain 2x2 p=2; warp0 turned -0.66 deg about x (both its crossings graze), warp1 turned 3 deg about z, '
     'weft1 scaled 1.02',
     ['--cell', 'plain', '--seed', '6', '--exponent', '2'],
     {'warp0': [('turn', 'x', -0.66)], 'warp1': [('turn', 'z', 3)], 'weft1': [('scale', 1.02)]}),
    ('shallow: plain 2x2, super-ellipse p=4 (flat faces), overlap 0.4% of the height',
     ['--cell', 'plain', '--seed', '7', '--exponent', '4', '--overlap', '0.004'], {}),
    ('shallow: orthogonal 2 weft layers, p=4 (flat faces), overlap 1% (7 tows), strip caps',
     ['--cell', 'orthogonal', '--seed', '8', '--layers', '2', '--exponent', '4', '--overlap', '0.01',
      '--cap', 'strip'], {}),
    ('shallow: weft0 of a 3x1 plain cell and a copy turned 2.5 deg about z, raised 0.96 x height (near parallel)',
     ['--cell', 'plain', '--seed', '9', '--exponent', '2.5', '--repeat', '3', '1'],
     {'warp0': None, 'warp1': None, 'warp2': None,
      'copy:weft0': [('turn', 'z', 2.5), ('move', (0, 0, 0.96 * 0.16))]}),
    ('twill 2/2 4x4 (8 tows), lenticular, meander 0.03, jitter 0.25, ring mix, strip caps',
     ['--cell', 'twill', '--seed', '10', '--section', 'lenticular', '--waviness', '0.03', '--jitter', '0.25',
      '--ring-mix', '--cap', 'strip'], {}),
    ('grazing: plain 2x2, lenticular, overlap 0.05% of the height (curves far smaller than a face), jitter 0.3',
     ['--cell', 'plain', '--seed', '11', '--section', 'lenticular', '--overlap', '0.0005', '--jitter', '0.3'], {}),
    ('deep: twill 2/2 4x4, varying section, overlap 20%, meander 0.05, ring mix, jitter 0.3, up frame',
     ['--cell', 'twill', '--seed', '12', '--section', 'varying', '--overlap', '0.2', '--waviness', '0.05',
      '--ring-mix', '--jitter', '0.3', '--frame', 'up'], {}),
    ('coarse: plain 3x3, ellipse, 4 rings/spacing, 8 points/ring for all, rings aligned, no densification',
     ['--cell', 'plain', '--seed', '13', '--repeat', '3', '3', '--exponent', '2', '--along', '4', '--around', '8',
      '--same-around', '--no-stagger', '--dense', '0'], {}),
    # ---- harder: a fine tow against a copy of itself (as the CT pair table), contacts, resolution,
    # many tows, three tows overlapping in one place
    ('self: weft0 of a 3x1 plain cell, fine (40 x 120, no densification), and a copy moved (0.02, 0.03, 0.3 x height)',
     FINE_WEFT, {'keep': ['weft0'], 'copy:weft0': [('move', (0.02, 0.03, 0.3 * 0.16))]}),
    ('self: fine crimped weft0 (as above) and a copy turned 2 deg about x',
     FINE_WEFT, {'keep': ['weft0'], 'copy:weft0': [('turn', 'x', 2)]}),
    ('self: fine crimped weft0 (as above) and a copy turned 5 deg about z',
     FINE_WEFT, {'keep': ['weft0'], 'copy:weft0': [('turn', 'z', 5)]}),
    ('self: fine crimped weft0 (as above) and a copy scaled by 1.02 about its centre',
     FINE_WEFT, {'keep': ['weft0'], 'copy:weft0': [('scale', 1.02)]}),
    ('self: fine crimped weft0 (as above) and a copy moved along its length by 0.3 ring step (nearly coincident)',
     FINE_WEFT, {'keep': ['weft0'], 'copy:weft0': [('move', (0.3 / 40, 0, 0))]}),
    ('self: straight weft (orthogonal cell, 40 x 120, staggered) and a copy moved along it by 0.3 ring step',
     STRAIGHT_WEFT + ['--along', '40'], {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('move', (0.3 / 40, 0, 0))]}),
    ('flat: straight weft (32 x 128, rings aligned) and a copy moved along it by exactly one ring step '
     '(vertices and faces coincide over the whole length)',
     STRAIGHT_WEFT + ['--along', '32', '--no-stagger'],
     {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('move', (1.0 / 32, 0, 0))]}),
    ('self: straight weft (32 x 128, staggered) and a copy moved by exactly one ring step (its vertices on the '
     'smooth surface between the original\'s)',
     STRAIGHT_WEFT + ['--along', '32'], {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('move', (1.0 / 32, 0, 0))]}),
    ('contact: orthogonal 3 layers, overlap 0 (every crossover touches tangentially at a point), rings aligned, '
     '16 points/ring, up frame',
     ['--cell', 'orthogonal', '--seed', '22', '--overlap', '0', '--no-stagger', '--same-around', '--around', '16',
      '--frame', 'up'], {}),
    ('contact: straight weft and its copy half-turned about its axis, moved 0.6 across: touching along a line of '
     'shared edges; a stuffer lowered onto that line crosses both',
     ['--cell', 'orthogonal', '--seed', '23', '--layers', '2', '--no-stagger', '--same-around', '--around', '20'],
     {'keep': ['weft_l0_0', 'stuffer_l0_0'], 'copy:weft_l0_0': [('flip', 'x'), ('move', (0, 0.6, 0))],
      'stuffer_l0_0': [('move', (0, 0, -0.1536))]}),
    ('contact: straight weft and its half-turned copy touching along a line (staggered rings: isolated common '
     'vertices), no third tow',
     ['--cell', 'orthogonal', '--seed', '24', '--layers', '2', '--same-around', '--around', '20'],
     {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('flip', 'x'), ('move', (0, 0.6, 0))]}),
    ('resolution: plain 2x2, p=2.5, 100 rings/spacing x 124 points (~50k faces per tow)',
     ['--cell', 'plain', '--seed', '25', '--along', '100', '--around', '124', '--same-around'], {}),
    ('many: twill 2/2 4x4 (8 tows), varying section (vary 0.15, twist 6), jitter 0.3, meander 0.03, fine (24 x 40)',
     ['--cell', 'twill', '--seed', '26', '--section', 'varying', '--vary', '0.15', '--twist', '6', '--jitter', '0.3',
      '--waviness', '0.03', '--along', '24', '--around', '40'], {}),
    ('many: orthogonal 4x2, 3 weft layers, 3 binders (17 tows), jitter 0.2, Hermite path, strip caps',
     ['--cell', 'orthogonal', '--seed', '27', '--repeat', '4', '2', '--jitter', '0.2', '--path', 'hermite',
      '--cap', 'strip'], {}),
    ('triple: plain 2x2 and a copy of warp0 moved 0.15 across (warp0, its copy and both wefts overlap at each '
     'crossover of warp0)',
     ['--cell', 'plain', '--seed', '28', '--along', '16', '--around', '28'],
     {'copy:warp0': [('move', (0.15, 0, 0.01))]}),
    ('triple: orthogonal 2 layers, binder0 moved onto stuffer column 0 (+0.07) and pushed down 0.18 into the '
     'top weft x stuffer crossovers',
     ['--cell', 'orthogonal', '--seed', '29', '--layers', '2', '--along', '14', '--around', '24'],
     {'binder0': [('move', (-0.43, 0, -0.18))]}),
    ('self: as 19 (staggered straight weft, copy moved along it by 0.3 ring step) but coarse (20 x 60)',
     ['--cell', 'orthogonal', '--seed', '21', '--layers', '2', '--repeat', '3', '1', '--around', '60', '--dense', '0',
      '--along', '20'],
     {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('move', (0.3 / 20, 0, 0))]}),
    ('self: as 16 (crimped weft0 and a copy turned 5 deg about z) but coarse (20 x 60)',
     ['--cell', 'plain', '--seed', '21', '--repeat', '3', '1', '--along', '20', '--around', '60', '--dense', '0'],
     {'keep': ['weft0'], 'copy:weft0': [('turn', 'z', 5)]}),
    ('flat + third: straight weft (16 x 32, rings aligned), a copy moved along it by one ring step (faces coincide) '
     'and a stuffer lowered 0.1 across both (crosses their flat contact)',
     STRAIGHT_16x32,
     {'keep': ['weft_l0_0', 'stuffer_l0_1'], 'copy:weft_l0_0': [('move', (1.0 / 16, 0, 0))],
      'stuffer_l0_1': [('move', (0, 0, -0.1))]}),
    ('flat, three: straight weft (16 x 32, rings aligned) and copies moved along it by one and two ring steps '
     '(three tows coincide over an area, where the docs promise exit 2)',
     STRAIGHT_16x32,
     {'keep': ['weft_l0_0'], 'copy:weft_l0_0': [('move', (1.0 / 16, 0, 0))],
      'copy2:weft_l0_0': [('move', (2.0 / 16, 0, 0))]}),
    ('flat + third: as 32, but the stuffer also moved 0.013 along x (its bottom ridge off the weft\'s ring plane)',
     STRAIGHT_16x32,
     {'keep': ['weft_l0_0', 'stuffer_l0_1'], 'copy:weft_l0_0': [('move', (1.0 / 16, 0, 0))],
      'stuffer_l0_1': [('move', (0.013, 0, -0.1))]}),
    ('contact: orthogonal 3 layers, overlap 0 (tangential point contacts), default rings (staggered, RMF frame)',
     ['--cell', 'orthogonal', '--seed', '35', '--overlap', '0'], {}),
    ('flat + third: as 32, but the stuffer turned 7 deg about z and moved (0.013, 0.0071, -0.1) (generic position)',
     STRAIGHT_16x32,
     {'keep': ['weft_l0_0', 'stuffer_l0_1'], 'copy:weft_l0_0': [('move', (1.0 / 16, 0, 0))],
      'stuffer_l0_1': [('turn', 'z', 7), ('move', (0.013, 0.0071, -0.1))]}),
]


def apply_ops(points, ops):
    """transformed() (real_tows.py) on each run of its ops, plus ('flip', axis): an exact half turn
    about that coordinate axis through the origin (the other two coordinates negated)."""
    out, run_ = list(points), []
    for op in list(ops) + [None]:
        if op is None or op[0] == 'flip':
            if run_:
                out = transformed(out, run_)
                run_ = []
            if op is not None:
                k = 'xyz'.index(op[1])
                out = [tuple(q[d] if d == k else -q[d] for d in range(3)) for q in out]
        else:
            run_.append(op)
    return out


def generate(work, gen_args, ops):
    """Runs the generator into work/in, applies the transforms; returns the input paths in order.
    ops: {tow: list of ops (transformed in place) or None (dropped)}; 'copy:TOW' ('copyX:TOW')
    adds TOW_copy (TOW_copyX) transformed; 'keep': [tows] drops every other generated tow."""
    indir = os.path.join(work, 'in')
    if os.path.isdir(indir):
        for f in os.listdir(indir):
            os.remove(os.path.join(indir, f))
    run = subprocess.run([sys.executable, os.path.join(HERE, 'other_weave.py'), '--out', indir] + gen_args,
                         capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError('generator failed: %s' % run.stderr)
    paths = [line.split()[0] for line in run.stdout.splitlines() if line.endswith(')') and '.off' in line]
    for name, o in ops.items():
        if name == 'keep':
            for path in list(paths):
                if os.path.splitext(os.path.basename(path))[0] not in o:
                    os.remove(path)
                    paths.remove(path)
        elif name.startswith('copy') and ':' in name:
            tag, tow = name.split(':', 1)
            src = os.path.join(indir, tow + '.off')
            p, f = read_off(src)
            dst = os.path.join(indir, tow + '_' + tag + '.off')
            write_off(dst, apply_ops(p, o), f)
            paths.append(dst)
        elif o is None:  # drop the tow
            path = os.path.join(indir, name + '.off')
            os.remove(path)
            paths.remove(path)
        else:
            path = os.path.join(indir, name + '.off')
            p, f = read_off(path)
            write_off(path, apply_ops(p, o), f)
    return paths


def run(cmd, timeout):
    start = time.time()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        code, err = r.returncode, r.stderr
    except subprocess.TimeoutExpired:
        code, err = 'timeout', ''
    return code, err, time.time() - start


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--seam', default=os.path.join(HERE, '..', 'build', 'seam'))
    ap.add_argument('--out', default=os.path.join(HERE, '..', 'build', 'other_cells'))
    ap.add_argument('--only', default='')
    ap.add_argument('--markdown', default='')
    ap.add_argument('--timeout', type=float, default=1800)
    ap.add_argument('--strict', action='store_true',
                    help='exit 1 when any run fails (a seam exit other than 0, a failed check, tetgen -d not clean)')
    args = ap.parse_args()
    args.out = os.path.abspath(args.out)
    seam = os.path.abspath(args.seam)
    only = set(int(x) for x in args.only.split(',') if x)
    header = ('| # | configuration | tows | textile exit | time (s) | pairs (triple, flat-crossing points) '
              '| pairs crossing by a float test of the inputs | seam check on every pair | tetgen -d on all | new faces '
              '| below 10 deg | below 20 deg | seam pair on (first pair): exit, time (s), curves, check, tetgen -d |\n'
              '|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    rows, failures = [header], []
    print(header, flush=True)
    for n, (name, gen_args, ops) in enumerate(CONFIGS, 1):
        if only and n not in only:
            continue
        work = os.path.join(args.out, 'cfg%02d' % n)
        os.makedirs(work, exist_ok=True)
        inputs = generate(work, gen_args, ops)
        names = [os.path.splitext(os.path.basename(p))[0] for p in inputs]
        out_dir = os.path.join(work, 'out')
        report = os.path.join(work, 'textile.json')
        for f in [report] + ([os.path.join(out_dir, x) for x in os.listdir(out_dir)] if os.path.isdir(out_dir) else []):
            if os.path.exists(f):
                os.remove(f)
        cmd = [seam, 'textile'] + inputs + ['--out-dir', out_dir, '--report', report, '--quiet']
        code, err, seconds = run(cmd, args.timeout)
        open(os.path.join(work, 'textile.stderr'), 'w').write(err)
        pair_cell = '-'
        if code != 0:
            failures.append((n, 'textile', cmd, code, err))
            row = '| %d | %s | %d | %s | %.1f | - | - | - | - | - | - | - |' % (n, name, len(inputs), code, seconds)
            first = None
        else:
            r = json.load(open(report))
            tol = r['verify_tolerance']
            pairs = [p for p in r['pairs'] if p['curves'] + p['contact'].get('points', 0) > 0]
            checks = []
            for p in pairs:
                a, b = p['a'], p['b']
                ccmd = [seam, 'check', os.path.join(work, 'in', a + '.off'), os.path.join(work, 'in', b + '.off'),
                        os.path.join(out_dir, a + '.off'), os.path.join(out_dir, b + '.off'),
                        os.path.join(out_dir, '%s__%s.polylines.txt' % (a, b)), '--tol', repr(tol),
                        '--report', os.path.join(work, 'check_%s_%s.json' % (a, b))]
                c = subprocess.run(ccmd, capture_output=True, text=True)
                checks.append(c.returncode == 0)
                if c.returncode != 0:
                    failures.append((n, 'check %s %s' % (a, b), ccmd, c.returncode, c.stdout + c.stderr))
            outputs = [os.path.join(out_dir, x + '.off') for x in names]
            new, b10, b20 = new_face_angles(inputs, outputs)
            verdict = tetgen_merged(outputs, os.path.join(work, 'merged.off'), work, timeout=1800)
            if verdict != 'clean':
                failures.append((n, 'tetgen -d on all', ['tetgen', '-d', os.path.join(work, 'merged.off')],
                                 verdict, ''))
            # independent of seam: which input pairs have faces that cross (float segment/triangle test)
            own = set((a, b) for a, b, _ in intersecting_pairs({x: read_off(p) for x, p in zip(names, inputs)}))
            theirs = set((p['a'], p['b']) for p in pairs)
            agree = '%d, as seam' % len(own) if own == theirs else '%d; only here: %s; only seam: %s' % (
                len(own), sorted(own - theirs), sorted(theirs - own))
            row = '| %d | %s | %d | 0 | %.1f | %d (%d, %d) | %s | %s | %s | %d | %d (%.1f%%) | %d (%.1f%%) |' % (
                n, name, len(inputs), seconds, len(pairs), r['triple_points'], r.get('flat_crossing_points', 0), agree,
                'OK' if all(checks) else '%d of %d fail' % (checks.count(False), len(checks)), verdict, new, b10,
                100.0 * b10 / max(new, 1), b20, 100.0 * b20 / max(new, 1))
            first = (pairs[0]['a'], pairs[0]['b']) if pairs else None
        if first is None:  # textile failed: the first pair by our own ordering of names (warp x weft)
            first = (names[0], names[-1]) if len(names) > 1 else None
        if first:
            a, b = first
            pd = os.path.join(work, 'pair')
            os.makedirs(pd, exist_ok=True)
            A, B = os.path.join(work, 'in', a + '.off'), os.path.join(work, 'in', b + '.off')
            a2, b2, curves, prep = (os.path.join(pd, x) for x in ('a2.off', 'b2.off', 'curves.txt', 'pair.json'))
            for f in (a2, b2, curves, prep):
                if os.path.exists(f):
                    os.remove(f)
            pcmd = [seam, 'pair', A, B, '--out-a', a2, '--out-b', b2, '--curves-out', curves, '--report', prep]
            pcode, perr, psec = run(pcmd, args.timeout)
            open(os.path.join(pd, 'pair.stderr'), 'w').write(perr)
            if pcode != 0:
                failures.append((n, 'pair %s %s' % (a, b), pcmd, pcode, perr))
                pair_cell = '%s x %s: exit %s, %.1f, -, -, -' % (a, b, pcode, psec)
            else:
                pr = json.load(open(prep))
                ccmd = [seam, 'check', A, B, a2, b2, curves, '--tol', repr(pr['verify_tolerance']),
                        '--report', os.path.join(pd, 'check.json')]
                c = subprocess.run(ccmd, capture_output=True, text=True)
                if c.returncode != 0:
                    failures.append((n, 'check of pair %s %s' % (a, b), ccmd, c.returncode, c.stdout + c.stderr))
                tv = tetgen_merged([a2, b2], os.path.join(pd, 'merged.off'), pd)
                if tv != 'clean':
                    failures.append((n, 'tetgen -d on pair', ['tetgen', '-d', os.path.join(pd, 'merged.off')], tv, ''))
                ncurves = sum(1 for line in open(curves) if line.split() and not line.startswith('#'))
                pair_cell = '%s x %s: 0, %.1f, %d, %s, %s' % (
                    a, b, psec, ncurves, {0: 'OK', 1: 'FAILED'}.get(c.returncode, 'exit %d' % c.returncode), tv)
        row += ' %s |' % pair_cell
        rows.append(row)
        print(row, flush=True)
    if failures:
        print('\nFailures:')
        for n, what, cmd, code, err in failures:
            print('- config %d, %s: exit %s\n  %s\n  %s' % (n, what, code, ' '.join(cmd),
                                                            err.strip().replace('\n', '\n  ')))
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(rows) + '\n')
            if failures:
                f.write('\nFailures:\n\n')
                for n, what, cmd, code, err in failures:
                    f.write('- config %d, %s: exit %s\n  `%s`\n\n```\n%s\n```\n' % (n, what, code, ' '.join(cmd),
                                                                                  err.strip()))
    return 1 if args.strict and failures else 0


if __name__ == '__main__':
    sys.exit(main())
