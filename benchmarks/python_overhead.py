#!/usr/bin/env python3
"""The binding's overhead against the CLI on the benchmark pair (docs/python.md).

    PYTHONPATH=build/python python3 benchmarks/python_overhead.py [--cli build/seam] [--runs 3]

Input: the pair of bench_pair, seam.make_crossover(600, 64, 499, 64) (76,928 + 64,000 faces),
written once as OFF files with 17 significant digits (the doubles round-trip exactly), so both
sides compute on the same coordinates. Then, alternating so that drifts of the machine affect both
alike, `runs` times each:
  cli      `seam pair weft.off warp.off --out-a ... --out-b ...`: process start, read, pair, write;
  binding  seam.pair(VA, FA, VB, FB) on the arrays: conversion in, pair, conversion out.
Both use the default options (exact kernel, quality stage, outputs verified). Prints each run,
the medians, their ratio, the binding's conversions (report["seconds"]: from_arrays, to_arrays:
copying and checking the arrays, building the meshes, and back) against the CLI's file reading
and writing (read, write: the same plus parsing and formatting), the time of the pair stages
themselves in both, and checks that both gave the same outputs.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import seam


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.17g")
        np.savetxt(f, np.column_stack([np.full(len(F), 3), F]), fmt="%d")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cli", default=os.path.join(here, "..", "build", "seam"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--resolution", type=int, nargs=4, default=[600, 64, 499, 64],
                        metavar=("WEFT_ALONG", "WEFT_AROUND", "WARP_ALONG", "WARP_AROUND"))
    args = parser.parse_args()

    (VA, FA), (VB, FB) = seam.make_crossover(*args.resolution, warp_section="lenticular", warp_height=0.45)
    print(f"input: {len(FA)} + {len(FB)} faces; {args.runs} runs each, alternating", flush=True)
    cli_seconds, py_seconds, cli_io, py_io, cli_pair, py_pair = [], [], [], [], [], []
    io_stages = ("read", "write", "from_arrays", "to_arrays")
    with tempfile.TemporaryDirectory(prefix="seam_python_overhead.") as tmp:
        a, b = os.path.join(tmp, "weft.off"), os.path.join(tmp, "warp.off")
        write_off(a, VA, FA)
        write_off(b, VB, FB)
        out_a, out_b, report = (os.path.join(tmp, n) for n in ("a2.off", "b2.off", "report.json"))
        for run in range(args.runs):
            t = time.perf_counter()
            subprocess.run([args.cli, "pair", a, b, "--out-a", out_a, "--out-b", out_b, "--report", report],
                           check=True, stdout=subprocess.DEVNULL)
            cli_seconds.append(time.perf_counter() - t)
            with open(report) as f:
                s = json.load(f)["seconds"]
            cli_io.append(s["read"] + s["write"])
            cli_pair.append(sum(v for k, v in s.items() if k not in io_stages))

            t = time.perf_counter()
            r = seam.pair(VA, FA, VB, FB)
            py_seconds.append(time.perf_counter() - t)
            s = r.report["seconds"]
            py_io.append(s["from_arrays"] + s["to_arrays"])
            py_pair.append(sum(v for k, v in s.items() if k not in io_stages))
            print(f"run {run + 1}: cli {cli_seconds[-1]:.2f} s (read + write {cli_io[-1]:.2f} s, pair stages "
                  f"{cli_pair[-1]:.2f} s), binding {py_seconds[-1]:.2f} s (conversions {py_io[-1]:.2f} s, pair stages "
                  f"{py_pair[-1]:.2f} s)", flush=True)
        with open(out_a) as f:  # the same outputs (the OFF file holds 17 significant digits)
            f.readline()
            nv = int(f.readline().split()[0])
            V = np.loadtxt(f, max_rows=nv)
        same = np.array_equal(V, r.VA)
    cli, py = statistics.median(cli_seconds), statistics.median(py_seconds)
    print(f"median: cli {cli:.2f} s, binding {py:.2f} s, binding / cli = {py / cli:.3f}")
    print(f"median: cli read + write {statistics.median(cli_io):.2f} s, "
          f"binding conversions {statistics.median(py_io):.2f} s ({100 * statistics.median(py_io) / py:.1f}% of its call)")
    print(f"median of the pair stages (seam::pair itself): cli {statistics.median(cli_pair):.2f} s, "
          f"binding {statistics.median(py_pair):.2f} s")
    print(f"same output A as the CLI: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
