#!/usr/bin/python3
"""seam embed on real tows with given curves that lie off the facets: the CT-scanned tows of
../shared/data/polytex (as scanned, and turned or tilted copies), each cut by planes across and
along it; each cross-section, resampled at half the mean edge length and smoothed (three passes
of a 1-2-1 average), is a closed curve off the facets by up to their staircase's depth, as a
curve from a smooth (NURBS) tow model would be. Each is run through `seam embed` (default
options, exact kernel), `seam check-embed` at the tolerance embed states and `tetgen -d` on the
output, and again with --no-improve for comparison.

Usage: scripts/real_tows_embed.py [--data DIR] [--seam build/seam] [--out DIR] [--markdown FILE]
Prints one row per configuration. Skips cleanly when the data is absent. Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_tows import FILES, read_stl, tetgen_verdict, transformed, write_off  # noqa: E402


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def cross_sections(points, faces, normal, offset):
    """The closed loops where the plane normal . p = offset cuts the mesh (edge crossings chained
    face to face). The offset is nudged so that no vertex lies on the plane."""
    s = [sum(normal[k] * p[k] for k in range(3)) - offset for p in points]
    if any(x == 0 for x in s):
        return cross_sections(points, faces, normal, offset + 1e-9 * math.pi)
    at = {}
    links = {}
    for f in faces:
        crossed = []
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            if (s[a] < 0) != (s[b] < 0):
                key = (min(a, b), max(a, b))
                if key not in at:
                    t = s[a] / (s[a] - s[b])
                    at[key] = tuple(points[a][k] + t * (points[b][k] - points[a][k]) for k in range(3))
                crossed.append(key)
        if len(crossed) == 2:
            links.setdefault(crossed[0], []).append(crossed[1])
            links.setdefault(crossed[1], []).append(crossed[0])
    loops, seen = [], set()
    for start in links:
        if start in seen:
            continue
        loop, prev, cur = [], None, start
        while cur not in seen:
            seen.add(cur)
            loop.append(at[cur])
            nxt = [k for k in links[cur] if k != prev]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
        loops.append(loop)
    return loops


def resampled_smoothed(loop, spacing, passes=3):
    n = len(loop)
    lengths = [0.0]
    for i in range(n):
        p, q = loop[i], loop[(i + 1) % n]
        lengths.append(lengths[-1] + math.dist(p, q))
    total = lengths[-1]
    m = max(8, int(total / spacing))
    out, j = [], 0
    for i in range(m):
        t = total * i / m
        while lengths[j + 1] < t:
            j += 1
        p, q = loop[j % n], loop[(j + 1) % n]
        u = (t - lengths[j]) / max(lengths[j + 1] - lengths[j], 1e-300)
        out.append(tuple(p[k] + u * (q[k] - p[k]) for k in range(3)))
    for _ in range(passes):
        out = [tuple((out[i - 1][k] + 2 * out[i][k] + out[(i + 1) % m][k]) / 4 for k in range(3)) for i in range(m)]
    return out


def write_polylines(path, loops):
    with open(path, 'w') as f:
        for loop in loops:
            pts = loop + [loop[0]]
            f.write('%d %s\n' % (len(pts), ' '.join('%.17g %.17g %.17g' % p for p in pts)))


def mean_edge(points, faces):
    total, n = 0.0, 0
    for f in faces:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            total += math.dist(points[a], points[b])
            n += 1
    return total / n


# name, tow, transform, planes: None (three across the tow's long axis, at 0.3, 0.5 and 0.7 of
# its extent), 'four' (four across, at 0.2, 0.4, 0.6, 0.8), 'tilted' (one across, turned 30
# degrees), 'along' (one along it, through the middle). The planes are placed by the tow's own
# extent, so a turned copy differs from the tow by its facets' rounding and degeneracies (a turn
# about the long axis, or a scaling, with the same planes gave the same figures as the tow).
CONFIGS = [
    ('weft, 3 planes across', 'weft', [], None),
    ('weft, plane across tilted 30 deg', 'weft', [], 'tilted'),
    ('weft, plane along it (long curve over the voxel steps)', 'weft', [], 'along'),
    ('weft turned 5 deg about z, 3 planes across', 'weft', [('turn', 'z', 5)], None),
    ('weft tilted 3 deg about y, plane along it', 'weft', [('turn', 'y', 3)], 'along'),
    ('weft turned 2 deg about x, plane across tilted 30 deg', 'weft', [('turn', 'x', 2)], 'tilted'),
    ('binder, 3 planes across', 'binder', [], None),
    ('binder, plane across tilted 30 deg', 'binder', [], 'tilted'),
    ('binder, plane along it', 'binder', [], 'along'),
    ('binder turned 2 deg about y, 3 planes across', 'binder', [('turn', 'y', 2)], None),
    ('binder turned 7 deg about z, plane along it', 'binder', [('turn', 'z', 7)], 'along'),
    ('binder scaled by 1.02, 4 planes across', 'binder', [('scale', 1.02)], 'four'),
]


def planes_for(points, spec):
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    extent = [hi[k] - lo[k] for k in range(3)]
    long_axis = max(range(3), key=lambda k: extent[k])
    along = [0.0, 0.0, 0.0]
    along[long_axis] = 1.0
    if spec is None:
        spec = [(tuple(along), f) for f in (0.3, 0.5, 0.7)]
    elif spec == 'four':
        spec = [(tuple(along), f) for f in (0.2, 0.4, 0.6, 0.8)]
    elif spec == 'tilted':
        other = (long_axis + 2) % 3
        n = [0.0, 0.0, 0.0]
        n[long_axis], n[other] = math.cos(0.52), math.sin(0.52)
        spec = [(tuple(n), 0.5)]
    elif spec == 'along':
        n = [0.0, 0.0, 0.0]
        n[(long_axis + 1) % 3], n[(long_axis + 2) % 3] = 0.2, 1.0
        spec = [(tuple(n), 0.5)]
    out = []
    for normal, fraction in spec:
        normal = unit(normal)
        values = [sum(normal[k] * p[k] for k in range(3)) for p in points]
        out.append((normal, min(values) + fraction * (max(values) - min(values))))
    return out


def run(cmd, timeout=1800):
    t = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, time.time() - t, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return 'timeout', time.time() - t, ''


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--data', default=os.path.join(here, '..', '..', 'shared', 'data', 'polytex'))
    ap.add_argument('--seam', default=os.path.join(here, '..', 'build', 'seam'))
    ap.add_argument('--out', default=os.path.join(here, '..', 'build', 'real_tows_embed'))
    ap.add_argument('--markdown', default='')
    args = ap.parse_args()
    if not all(os.path.exists(os.path.join(args.data, f)) for f in FILES.values()):
        print('real_tows_embed: no CT tows in %s: skipped' % args.data)
        return 0
    os.makedirs(args.out, exist_ok=True)
    tows = {name: read_stl(os.path.join(args.data, f)) for name, f in FILES.items()}
    header = ('| # | configuration | curves (points) | given to embedded | exit | time (s) | seam check-embed | tetgen -d '
              '| new faces | below 10 deg | below 20 deg | without the quality stage: below 10 / 20 of new |')
    rows = [header, '|' + '---|' * (header.count('|') - 1)]
    print(header)
    failures = 0
    for i, (name, tow, ops, spec) in enumerate(CONFIGS, 1):
        d = os.path.join(args.out, str(i))
        os.makedirs(d, exist_ok=True)
        points, faces = tows[tow]
        points = transformed(points, ops) if ops else points
        mesh = os.path.join(d, 'tow.off')
        write_off(mesh, points, faces)
        spacing = 0.5 * mean_edge(points, faces)
        loops = []
        for normal, offset in planes_for(points, spec):
            for loop in cross_sections(points, faces, normal, offset):
                if len(loop) >= 20:
                    loops.append(resampled_smoothed(loop, spacing))
        given = os.path.join(d, 'given.txt')
        write_polylines(given, loops)
        out, curves_out, report = (os.path.join(d, n) for n in ('out.off', 'curves.txt', 'report.json'))
        for f in (out, curves_out, report):
            if os.path.exists(f):
                os.remove(f)
        code, seconds, text = run([args.seam, 'embed', mesh, '--curves', given, '-o', out, '--curves-out', curves_out,
                                   '--report', report])
        verdict, tet, figures, off = '-', '-', ('-', '-', '-'), '-'
        if code == 0:
            r = json.load(open(report))
            tol = r['verify']['tolerance']
            c, _, ctext = run([args.seam, 'check-embed', mesh, out, curves_out, '--given', given, '--tol', repr(tol),
                               '--report', os.path.join(d, 'check.json')])
            verdict = 'OK' if c == 0 else ('FAILED' if c == 1 else 'error %s' % c)
            if c in (0, 1):
                cr = json.load(open(os.path.join(d, 'check.json')))
                figures = (cr['output']['new_faces'], cr['quality']['below_10'], cr['quality']['below_20'])
                off = '%.2g' % cr['given']['given_to_embedded']
            tet = tetgen_verdict(out, out, os.path.join(d, 'merged.off'), d)
        else:
            failures += 1
            print('   ', text.strip().splitlines()[-1] if text.strip() else '', file=sys.stderr)
        out0 = os.path.join(d, 'out0.off')
        if os.path.exists(out0):
            os.remove(out0)
        c0, _, t0 = run([args.seam, 'embed', mesh, '--curves', given, '-o', out0, '--no-improve',
                         '--report', os.path.join(d, 'report0.json')])
        before = '-'
        if c0 == 0:
            r0 = json.load(open(os.path.join(d, 'report0.json')))
            before = '%d / %d of %d' % (r0['quality']['below_10'], r0['quality']['below_20'], r0['faces']['added'])
        row = '| %d | %s | %d (%d) | %s | %s | %.1f | %s | %s | %s | %s | %s | %s |' % (
            i, name, len(loops), sum(len(l) for l in loops), off, code, seconds, verdict, tet, figures[0], figures[1],
            figures[2], before)
        print(row, flush=True)
        rows.append(row)
        if code == 0 and (verdict != 'OK' or tet != 'clean'):
            failures += 1
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(rows) + '\n')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
