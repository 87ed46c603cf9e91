#!/usr/bin/python3
"""seam resolve on real tows: configurations of scripts/real_tows.py (CT-scanned tows of
../shared/data/polytex) run through `seam pair`, then `seam resolve` with each keeper choice,
then `tetgen -d` on the two resolved tows merged.

Usage: scripts/resolve_real_tows.py [--data DIR] [--seam build/seam] [--out DIR] [--only 1,3,13]
                                    [--markdown FILE]
Prints one row per configuration and keeper: exit codes, times of pair and resolve, the volumes
before and after, the overlap, the contact faces and TetGen's verdict. Skips cleanly when the data
is absent. Standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import real_tows  # noqa: E402  (read_stl, write_off, transformed, CONFIGS, FILES, tetgen_verdict)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--data', default=os.path.join(here, '..', '..', 'shared', 'data', 'polytex'))
    ap.add_argument('--seam', default=os.path.join(here, '..', 'build', 'seam'))
    ap.add_argument('--out', default=os.path.join(here, '..', 'build', 'resolve_real_tows'))
    ap.add_argument('--only', default='1,3,13')
    ap.add_argument('--markdown', default='')
    args = ap.parse_args()
    if not all(os.path.exists(os.path.join(args.data, f)) for f in real_tows.FILES.values()):
        print('resolve_real_tows: no CT tows in %s: skipped' % args.data)
        return 0
    tows = {name: real_tows.read_stl(os.path.join(args.data, f)) for name, f in real_tows.FILES.items()}
    only = [int(x) for x in args.only.split(',') if x]
    header = ('| # | configuration | faces A2 + B2 | pair (s) | keep | resolve exit | resolve (s) | vol A before -> after '
              '| vol B before -> after | overlap | contact faces | tetgen -d |')
    rows = [header, '|' + '---|' * 12]
    print(header)
    print(rows[1], flush=True)
    for k, (name, (ta, opa), (tb, opb)) in enumerate(real_tows.CONFIGS, 1):
        if only and k not in only:
            continue
        d = os.path.join(args.out, 'c%02d' % k)
        os.makedirs(d, exist_ok=True)
        a, b, a2, b2 = (os.path.join(d, x) for x in ('a.off', 'b.off', 'a2.off', 'b2.off'))
        real_tows.write_off(a, real_tows.transformed(tows[ta][0], opa), tows[ta][1])
        real_tows.write_off(b, real_tows.transformed(tows[tb][0], opb), tows[tb][1])
        t0 = time.time()
        p = subprocess.run([args.seam, 'pair', a, b, '--out-a', a2, '--out-b', b2], capture_output=True, text=True)
        pair_seconds = time.time() - t0
        if p.returncode != 0:
            row = '| %d | %s | - | %.1f (exit %d) | - | - | - | - | - | - | - | - |' % (k, name, pair_seconds, p.returncode)
            print(row, flush=True)
            rows.append(row)
            continue
        faces = len(real_tows.read_off(a2)[1]) + len(real_tows.read_off(b2)[1])
        for keep in ('auto', 'a', 'b'):
            a3, b3, report = (os.path.join(d, '%s_%s' % (keep, x)) for x in ('a3.off', 'b3.off', 'resolve.json'))
            for path in (a3, b3, report):
                if os.path.exists(path):
                    os.remove(path)
            t0 = time.time()
            r = subprocess.run([args.seam, 'resolve', a2, b2, '--out-a', a3, '--out-b', b3, '--keep', keep,
                                '--report', report], capture_output=True, text=True)
            seconds = time.time() - t0
            if r.returncode != 0:
                row = '| %d | %s | %d | %.1f | %s | %d | %.1f | %s |' % (
                    k, name, faces, pair_seconds, keep, r.returncode, seconds, r.stderr.strip()[:200])
            else:
                j = json.load(open(report))
                v = j['volume']
                tet = real_tows.tetgen_verdict(a3, b3, os.path.join(d, 'merged_%s.off' % keep), d)
                row = ('| %d | %s | %d | %.1f | %s (%s keeps) | 0 | %.2f (validate %.2f, classify %.2f, verify %.2f) '
                       '| %.6g -> %.6g | %.6g -> %.6g | %.6g | %d | %s |') % (
                    k, name, faces, pair_seconds, keep, j['keeper'].upper(), seconds, j['seconds']['validate'],
                    j['seconds']['classify'], j['seconds']['verify'], v['a_before'], v['a_after'], v['b_before'],
                    v['b_after'], v['overlap'], j['contact_faces'], tet)
            print(row, flush=True)
            rows.append(row)
    if args.markdown:
        open(args.markdown, 'w').write('\n'.join(rows) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
