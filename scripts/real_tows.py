#!/usr/bin/python3
"""seam on real tows: interpenetrating configurations made from the CT-scanned tows of
../shared/data/polytex (crossing pairs; tows against turned, tilted, shifted and scaled copies
of themselves and of each other), each run through `seam pair`, `seam check` and `tetgen -d`.

Usage: scripts/real_tows.py [--data DIR] [--seam build/seam] [--out DIR] [--only NAME,...]
                            [--timeout S] [--markdown FILE] [--textile] [-- extra seam options]
--textile runs `seam textile` on the two tows instead of `seam pair` (its curves file a__b, its
report's verify_tolerance for seam check; the curve and quality-stage columns are then '-').
Prints one row per configuration: exit code, time, seam check's verdict, TetGen's verdict on the
merged outputs (common vertices merged, shared faces written once), curves (closed/open), new
faces below 10 and 20 degrees (seam check's figures). Skips cleanly when the data is absent.
Standard library only (no numpy); the transforms are done in doubles about each tow's centre.
"""
import argparse
import json
import math
import os
import struct
import subprocess
import sys
import time


def read_stl(path):
    data = open(path, 'rb').read()
    points, index, faces = [], {}, []

    def vertex(p):
        if p not in index:
            index[p] = len(points)
            points.append(p)
        return index[p]

    binary = not data[:5] == b'solid' or b'facet' not in data[:512]
    if binary:
        n = struct.unpack('<I', data[80:84])[0]
        for k in range(n):
            v = struct.unpack('<12f', data[84 + 50 * k:84 + 50 * k + 48])
            faces.append(tuple(vertex(tuple(float(x) for x in v[3 + 3 * j:6 + 3 * j])) for j in range(3)))
    else:
        corners = []
        for line in data.decode('ascii', 'replace').splitlines():
            t = line.split()
            if t and t[0] == 'vertex':
                corners.append(vertex((float(t[1]), float(t[2]), float(t[3]))))
                if len(corners) == 3:
                    faces.append(tuple(corners))
                    corners = []
    return points, faces


def read_off(path):
    tok = [t for line in open(path) for t in line.split('#')[0].split()]
    assert tok[0] == 'OFF'
    nv, nf = int(tok[1]), int(tok[2])
    i = 4
    points = []
    for _ in range(nv):
        points.append((float(tok[i]), float(tok[i + 1]), float(tok[i + 2])))
        i += 3
    faces = []
    for _ in range(nf):
        n = int(tok[i])
        faces.append(tuple(int(x) for x in tok[i + 1:i + 1 + n]))
        i += 1 + n
    return points, faces


def write_off(path, points, faces):
    with open(path, 'w') as f:
        f.write('OFF\n%d %d 0\n' % (len(points), len(faces)))
        for p in points:
            f.write('%.17g %.17g %.17g\n' % p)
        for t in faces:
            f.write('3 %d %d %d\n' % t)


def transformed(points, ops):
    """ops: ('move', (dx, dy, dz)), ('scale', s), ('turn', axis, degrees): about the centre of
    the bounding box; a quarter turn is exact (cos 0, sin 1)."""
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    out = list(points)
    for op in ops:
        if op[0] == 'move':
            d = op[1]
            out = [(p[0] + d[0], p[1] + d[1], p[2] + d[2]) for p in out]
        elif op[0] == 'scale':
            s = op[1]
            out = [tuple(c[k] + s * (p[k] - c[k]) for k in range(3)) for p in out]
        elif op[0] == 'turn':
            axis, degrees = op[1], op[2]
            co, si = (0.0, 1.0) if degrees == 90 else (math.cos(math.radians(degrees)), math.sin(math.radians(degrees)))
            i, j = {'x': (1, 2), 'y': (2, 0), 'z': (0, 1)}[axis]
            res = []
            for p in out:
                q = list(p)
                u, v = p[i] - c[i], p[j] - c[j]
                q[i] = c[i] + co * u - si * v
                q[j] = c[j] + si * u + co * v
                res.append(tuple(q))
            out = res
    return out


# name, A (tow, ops), B (tow, ops)
CONFIGS = [
    ('binder raised 2.4 through the weft', ('weft', []), ('binder', [('move', (0, 0, 2.4))])),
    ('binder turned 90 deg, raised 2.4, through the weft', ('weft', []),
     ('binder', [('turn', 'z', 90), ('move', (-4.0, 0, 2.4))])),
    ('weft x weft turned 90 deg about z, raised 0.4', ('weft', []), ('weft', [('turn', 'z', 90), ('move', (0, 0, 0.4))])),
    ('weft x weft turned 30 deg about z, moved (0.2, 0, 0.2)', ('weft', []),
     ('weft', [('turn', 'z', 30), ('move', (0.2, 0, 0.2))])),
    ('weft x weft turned 5 deg about z', ('weft', []), ('weft', [('turn', 'z', 5)])),
    ('weft x weft turned 2 deg about x', ('weft', []), ('weft', [('turn', 'x', 2)])),
    ('weft x weft tilted 3 deg about y', ('weft', []), ('weft', [('turn', 'y', 3)])),
    ('weft x weft moved (0.3, 0.2, 0.3)', ('weft', []), ('weft', [('move', (0.3, 0.2, 0.3))])),
    ('weft x weft moved along y by 0.5 (grid planes kept)', ('weft', []), ('weft', [('move', (0, 0.5, 0))])),
    ('weft x weft scaled by 1.02', ('weft', []), ('weft', [('scale', 1.02)])),
    ('binder x binder turned 90 deg, raised 0.5', ('binder', []),
     ('binder', [('turn', 'z', 90), ('move', (0, 0, 0.5))])),
    ('binder x binder moved (0.1, 0.15, 0.2)', ('binder', []), ('binder', [('move', (0.1, 0.15, 0.2))])),
    ('binder x binder moved along x by 0.3 (grid planes kept)', ('binder', []), ('binder', [('move', (0.3, 0, 0))])),
    ('binder x binder turned 2 deg about x', ('binder', []), ('binder', [('turn', 'x', 2)])),
]

FILES = {'weft': 'profile_0_weft.stl', 'binder': 'profile_51_binder.stl'}


def tetgen_verdict(a2, b2, merged, workdir):
    """Merges the outputs (vertices by exact coordinates; a face in both written once) and runs
    tetgen -d: 'clean', 'N pairs', or 'error'."""
    return tetgen_merged([a2, b2], merged, workdir)


def tetgen_merged(paths, merged, workdir, timeout=600):
    """The meshes of `paths` as one surface (vertices merged by exact coordinates, a face of two
    meshes written once) in `merged`, through tetgen -d: 'clean', 'N pairs', or 'error'."""
    index, points, faces, seen = {}, [], [], set()
    for path in paths:
        p, f = read_off(path)
        m = []
        for q in p:
            if q not in index:
                index[q] = len(points)
                points.append(q)
            m.append(index[q])
        for t in f:
            g = tuple(m[k] for k in t)
            key = tuple(sorted(g))
            if key in seen:
                continue
            seen.add(key)
            faces.append(g)
    write_off(merged, points, faces)
    try:
        out = subprocess.run(['tetgen', '-d', merged], cwd=workdir, capture_output=True, text=True,
                             timeout=timeout).stdout
    except (OSError, subprocess.TimeoutExpired):
        return 'error'
    if 'No faces are intersecting' in out:
        return 'clean'
    at = out.find('!! Found ')
    return (out[at + 9:].split()[0] + ' pairs') if at >= 0 else 'error'


def curve_counts(path):
    """(closed, open, loose ends): a curve is closed when its first point is its last. Where a
    crossing meets the border of a flat contact three curve pieces meet, so curves end there;
    a loose end is an end point no other curve reaches (a touching contact that stops, or a
    piece of the intersection lost). A one-point curve (the tows touch at a point) is counted as
    closed."""
    curves = []
    for line in open(path):
        t = line.split()
        if not t or t[0].startswith('#'):
            continue
        n = int(t[0])
        curves.append([tuple(t[1 + 3 * k:4 + 3 * k]) for k in range(n)])
    is_closed = [len(c) == 1 or (len(c) > 2 and c[0] == c[-1]) for c in curves]
    degree = {}  # pieces of curve meeting at each point: 1 per open end, 2 per pass through
    for c, closed in zip(curves, is_closed):
        if closed:
            for q in set(c):
                degree[q] = degree.get(q, 0) + 2
        else:
            for k, q in enumerate(c):
                degree[q] = degree.get(q, 0) + (1 if k in (0, len(c) - 1) else 2)
    ends = set(q for c, closed in zip(curves, is_closed) if not closed for q in (c[0], c[-1]))
    loose = sum(1 for q in ends if degree[q] == 1)
    return sum(is_closed), len(curves) - sum(is_closed), loose


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--data', default=os.path.join(here, '..', '..', 'shared', 'data', 'polytex'))
    ap.add_argument('--seam', default=os.path.join(here, '..', 'build', 'seam'))
    ap.add_argument('--out', default=os.path.join(here, '..', 'build', 'real_tows'))
    ap.add_argument('--only', default='')
    ap.add_argument('--timeout', type=float, default=1800)
    ap.add_argument('--markdown', default='')
    ap.add_argument('--textile', action='store_true')
    ap.add_argument('extra', nargs='*')
    args = ap.parse_args()
    args.out = os.path.abspath(args.out)  # tetgen runs in each case's directory
    if not all(os.path.exists(os.path.join(args.data, f)) for f in FILES.values()):
        print('real_tows: no CT tows in %s: skipped' % args.data)
        return 0
    os.makedirs(args.out, exist_ok=True)
    tows = {name: read_stl(os.path.join(args.data, f)) for name, f in FILES.items()}
    only = [int(x) for x in args.only.split(',') if x]
    header = '| # | configuration | exit | time (s) | seam check | tetgen -d | curves closed / open / loose ends (causes) | shared faces | new faces | below 10 deg | of them where curves come closer than the feature size | below 20 deg |'
    rows = [header, '|' + '---|' * 12]
    print(header)
    print(rows[1])
    for k, (name, (ta, opa), (tb, opb)) in enumerate(CONFIGS, 1):
        if only and k not in only:
            continue
        d = os.path.join(args.out, 'c%02d' % k)
        os.makedirs(d, exist_ok=True)
        a, b, a2, b2, curves, report, check = (os.path.join(d, x) for x in (
            'a.off', 'b.off', 'a2.off', 'b2.off', 'curves.txt', 'pair.json', 'check.json'))
        for path in (a2, b2, curves, report, check):
            if os.path.exists(path):
                os.remove(path)
        write_off(a, transformed(tows[ta][0], opa), tows[ta][1])
        write_off(b, transformed(tows[tb][0], opb), tows[tb][1])
        t0 = time.time()
        try:
            if args.textile:  # outputs DIR/out/a.off, b.off and a__b.polylines.txt, moved to the pair's names
                out_dir = os.path.join(d, 'out')
                command = [args.seam, 'textile', a, b, '--out-dir', out_dir, '--report', report, '--quiet']
            else:
                command = [args.seam, 'pair', a, b, '--out-a', a2, '--out-b', b2, '--curves-out', curves, '--report', report]
            run = subprocess.run(command + args.extra, capture_output=True, text=True, timeout=args.timeout)
            if args.textile and run.returncode == 0:
                for written, path in (('a.off', a2), ('b.off', b2), ('a__b.polylines.txt', curves)):
                    os.replace(os.path.join(out_dir, written), path)
            code = run.returncode
            message = (run.stderr.strip().splitlines() or [''])[-1]
            open(os.path.join(d, 'pair.stderr'), 'w').write(run.stderr)  # the whole message
        except subprocess.TimeoutExpired:
            code, message = 'timeout', ''
        seconds = time.time() - t0
        verdict = tet = 'n/a'
        closed = open_ = loose = shared = new = b10 = b20 = closer = '-'
        if code == 0:
            pair_report = json.load(open(report))
            tol = pair_report['verify_tolerance']
            ends = pair_report['curves']['open_ends'] if not args.textile else None
            c = subprocess.run([args.seam, 'check', a, b, a2, b2, curves, '--tol', repr(tol), '--report', check],
                               capture_output=True, text=True)
            verdict = {0: 'OK', 1: 'FAILED'}.get(c.returncode, 'exit %d' % c.returncode)
            if os.path.exists(check):
                r = json.load(open(check))
                shared = r.get('shared_faces', '-')
                new = r['a2']['new_faces'] + r['b2']['new_faces']
                nb10 = r['a2']['new_below_10'] + r['b2']['new_below_10']
                nb20 = r['a2']['new_below_20'] + r['b2']['new_below_20']
                b10 = '%d (%.1f%%)' % (nb10, 100.0 * nb10 / max(new, 1))
                b20 = '%d (%.1f%%)' % (nb20, 100.0 * nb20 / max(new, 1))
            # seam's own account of the faces below 10 degrees (its report): those where two curve
            # segments with no common point come closer than the feature size
            improve = pair_report.get('improve', {})
            fs = improve.get('feature_size', 0)
            closer = sum(1 for f in improve.get('shortfall_faces', [])
                         if f['min_angle'] < 10 and f.get('curve_gap') is not None and f['curve_gap'] < fs)
            tet = tetgen_verdict(a2, b2, os.path.join(d, 'merged.off'), d)
            closed, open_, loose = curve_counts(curves)
            # seam's own account of the loose ends: where the surfaces only touch, or unexplained
            if ends is not None:  # (textile's report has no such account)
                loose = '%d (%d touching, %d unexplained)' % (loose, ends['touching'], ends['unexplained'])
        row = '| %d | %s | %s | %.1f | %s | %s | %s / %s / %s | %s | %s | %s | %s | %s |' % (
            k, name, code, seconds, verdict, tet, closed, open_, loose, shared, new, b10, closer, b20)
        if code != 0 and message:
            row += ' ' + message[:200]
        print(row, flush=True)
        rows.append(row)
    if args.markdown:
        open(args.markdown, 'w').write('\n'.join(rows) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
