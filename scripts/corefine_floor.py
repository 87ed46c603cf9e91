#!/usr/bin/python3
"""What seam pair's speed targets against CGAL corefine would need: per case, seam's whole run and
the stages no tool that verifies its output can skip (reading, the intersection, the verification
of the outputs as written, writing), each as a multiple of corefine's whole run in the same
alternated benchmark run (build/benchmarks/bench_pair, JSON counters).

Usage: scripts/corefine_floor.py [--bench build/benchmarks/bench_pair] [--rows DIR] [--only 1,5,...]
                                 [--pair A.off,B.off] [--runs 3] [--markdown FILE]
--rows: the output directory of scripts/real_tows.py (cNN/a.off and cNN/b.off per configuration);
--pair: one more case (the benchmark pair's files, say). Ratios are the range over the
alternated pairs of runs (seam, corefine), as bench_pair orders them. Standard library only.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def run_case(bench, a, b, runs):
    """bench_pair's seam and corefine iterations on files a, b (lists of dicts, in run order)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'bench.json')
        cmd = [bench, '--pair_runs=%d' % runs, '--pair_files=%s,%s' % (a, b), '--benchmark_filter=run:',
               '--benchmark_format=json', '--benchmark_out=' + out]
        done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode != 0 or not os.path.exists(out):
            sys.exit('corefine_floor: %s failed on %s, %s: %s' % (bench, a, b, done.stderr.strip()[-300:]))
        rows = json.load(open(out))['benchmarks']
    seam = [r for r in rows if r['name'].startswith('seam_pair')]
    core = [r for r in rows if r['name'].startswith('corefine')]
    if not seam or len(seam) != len(core) or any('error_message' in r for r in rows):
        sys.exit('corefine_floor: %s gave no complete pairs of runs on %s, %s' % (bench, a, b))
    return seam, core


def summary(name, seam, core):
    def span(values):
        lo, hi = min(values), max(values)
        return '%.1fx' % lo if '%.1f' % lo == '%.1f' % hi else '%.1f-%.1fx' % (lo, hi)
    whole = [s['real_time'] / c['real_time'] for s, c in zip(seam, core)]
    floor = [(s['read_s'] + s['intersect_s'] + s['verify_s'] + s['write_s']) * 1000 / c['real_time']
             for s, c in zip(seam, core)]
    verify = [s['verify_s'] * 1000 / c['real_time'] for s, c in zip(seam, core)]
    quality = statistics.median(s['improve_s'] * 1000 / s['real_time'] for s in seam)
    s0, c0 = seam[0], core[0]
    return ('| %s | %s | %s | %s | %.2f | %d / %d | %.1f%% / %.1f%% |' %
            (name, span(whole), span(floor), span(verify), quality, s0['new_faces'], c0['new_faces'],
             100 * s0['share_below_20'], 100 * c0['share_below_20']))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bench', default='build/benchmarks/bench_pair')
    ap.add_argument('--rows', help='scripts/real_tows.py output directory (cNN/a.off, cNN/b.off)')
    ap.add_argument('--only', help='row numbers, comma-separated (default: every cNN found)')
    ap.add_argument('--pair', help='one more case: A.off,B.off')
    ap.add_argument('--runs', type=int, default=3)
    ap.add_argument('--markdown', help='write the table here too')
    args = ap.parse_args()
    if not os.access(args.bench, os.X_OK):
        sys.exit('corefine_floor: %s: not an executable (build the benchmarks first)' % args.bench)
    cases = []
    if args.pair:
        parts = args.pair.split(',')
        if len(parts) != 2:
            sys.exit('corefine_floor: --pair wants two files, A,B')
        cases.append(('pair', parts[0], parts[1]))
    if args.rows and not os.path.isdir(args.rows):
        sys.exit('corefine_floor: %s: no such directory (the output of scripts/real_tows.py)' % args.rows)
    if args.rows:
        wanted = {int(x) for x in args.only.split(',')} if args.only else None
        for entry in sorted(os.listdir(args.rows)):
            if not (entry.startswith('c') and entry[1:].isdigit()) or (wanted and int(entry[1:]) not in wanted):
                continue
            a, b = (os.path.join(args.rows, entry, f) for f in ('a.off', 'b.off'))
            if os.path.exists(a) and os.path.exists(b):
                cases.append(('row %d' % int(entry[1:]), a, b))
    if not cases:
        sys.exit('corefine_floor: no case (give --rows and/or --pair)')
    lines = ['| case | seam / corefine | read + intersect + verify + write | verify alone | quality stage share of '
             'seam\'s run | new faces seam / corefine | new faces below 20 deg seam / corefine |',
             '|---|---|---|---|---|---|---|']
    print('\n'.join(lines), flush=True)
    for name, a, b in cases:
        lines.append(summary(name, *run_case(args.bench, a, b, args.runs)))
        print(lines[-1], flush=True)
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main()
