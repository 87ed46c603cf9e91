#!/usr/bin/env python3
"""Turns the JSON of bench_kernels and seam_robustness into Markdown tables and a plot.

    scripts/bench_report.py --kernels out/bench_kernels.json --robustness out/robustness.json \
        --markdown benchmarks/results/kernels.md --plot benchmarks/results/kernels.png

Either input may be left out. The plot needs matplotlib (Debian: apt-get install
python3-matplotlib); without it the tables are still written and the plot is skipped with a
message. The machine line (cores, OS, CPU, date) comes from the benchmark's context and from this
machine (/etc/os-release, /proc/cpuinfo): run the script where the benchmark ran (scripts/bench.sh
kernels does).
"""
import argparse
import json
import math
import os
import statistics
import sys

TOOLS = ["exact", "filtered", "float", "corefine"]
TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def machine_line(context):
    os_name = "?"
    try:
        with open("/etc/os-release") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    os_name = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    cores = context.get("num_cpus", os.cpu_count())
    date = context.get("date", "?")
    return "%s cores (%s), %s, run %s" % (cores, cpu, os_name, date)


def fmt_ms(x):
    if x is None:
        return "n/a"
    return "{:,.0f}".format(x) if x >= 100 else "{:.1f}".format(x)


def slope(points):
    """Least-squares slope of log(t) against log(n)."""
    if len(points) < 2:
        return None
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = statistics.mean(xs), statistics.mean(ys)
    den = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / den if den else None


def kernels_report(report, out):
    runs = {}  # (tool, faces) -> [benchmark entries]
    memory = {}  # (tool, faces) -> entry
    errors = []
    for b in report.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration":
            continue
        parts = b["name"].split("/")
        if len(parts) < 3 or not parts[2].startswith("faces:"):
            continue
        tool, faces = parts[1], int(parts[2].split(":")[1])
        if b.get("error_occurred"):
            errors.append("%s: %s" % (b["name"], b.get("error_message", "?")))
            continue
        if parts[0] == "kernels":
            b["ms"] = b["real_time"] * TO_MS.get(b.get("time_unit", "ns"), 1e-6)
            runs.setdefault((tool, faces), []).append(b)
        elif parts[0] == "memory":
            memory[(tool, faces)] = b
    sizes = sorted({f for _, f in runs} | {f for _, f in memory})
    med = {k: statistics.median(b["ms"] for b in v) for k, v in runs.items()}
    nruns = max((len(v) for v in runs.values()), default=0)
    input_faces = {}
    for (tool, f), v in runs.items():
        input_faces[f] = int(v[0].get("input_faces", 0))

    out.append("Whole runs (read both OFF files, compute, write both), wall-clock milliseconds, median of "
               "%d runs alternating between the tools; seam = `seam::pair` with `--snap-tol 0` and the "
               "default minimum angle, corefine = CGAL's `corefine` (Epeck) with the same reading and "
               "writing.\n" % nruns)
    out.append("| faces per tow | input faces | exact | filtered | float | corefine | exact / filtered | "
               "exact / float | exact / corefine |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ratios = {"exact/filtered": [], "exact/float": [], "exact/corefine": []}
    for f in sizes:
        cells = ["{:,}".format(f), "{:,}".format(input_faces.get(f, 0))]
        for t in TOOLS:
            cells.append(fmt_ms(med.get((t, f))))
        for other in ["filtered", "float", "corefine"]:
            e, o = med.get(("exact", f)), med.get((other, f))
            r = e / o if e and o else None
            if r:
                ratios["exact/" + other].append((input_faces.get(f, f), r))
            cells.append("%.2f" % r if r else "n/a")
        out.append("| " + " | ".join(cells) + " |")
    slopes = {}
    for t in TOOLS:
        pts = [(input_faces[f] / 2, med[(t, f)]) for f in sizes if (t, f) in med and 10000 <= f <= 1000000]
        slopes[t] = slope(pts)
    out.append("| log-log slope 10k..1M | | " + " | ".join(
        "%.2f" % slopes[t] if slopes[t] is not None else "n/a" for t in TOOLS) + " | | | |")
    out.append("")

    # Stages at the largest size where all tools ran.
    full = [f for f in sizes if all((t, f) in runs for t in TOOLS)]
    for f in sorted({f for f in full if f == 10000} | set(full[-1:])):
        out.append("Where the time goes at {:,} faces per tow (seconds, median over the runs; `locate` to "
                   "`rest of embed` summed over both meshes, whose embeddings run concurrently: `embedding "
                   "(wall)` is the longer of the two):\n".format(f))
        stages = [("read", "read"), ("intersection curves", "intersect"), ("snap", "snap"),
                  ("locate", "locate"), ("cross", "cross"), ("coarsen", "coarsen"),
                  ("re-triangulate", "retriangulate"), ("splice", "splice"),
                  ("rest of embed", "embed_rest"), ("embedding (wall)", "embed_wall"),
                  ("rest of pair", "pair_other"), ("corefine", "corefine"),
                  ("write", "write")]
        out.append("| stage | " + " | ".join(TOOLS) + " |")
        out.append("|---|" + "---:|" * len(TOOLS))
        for label, key in stages:
            cells = []
            for t in TOOLS:
                vals = [b.get(key + "_s") for b in runs[(t, f)] if (key + "_s") in b]
                cells.append("%.3f" % statistics.median(vals) if vals else "")
            if any(cells):
                out.append("| %s | %s |" % (label, " | ".join(cells)))
        out.append("")

    if memory:
        out.append("Peak memory of a whole run in a fresh process (getrusage maxrss, minus the process's "
                   "resident size before reading) against the heap holding the two input meshes of the "
                   "same kernel once read (mallinfo2: small and mapped blocks), MB:\n")
        out.append("| faces per tow | " + " | ".join("%s input / peak / ratio" % t for t in TOOLS) + " |")
        out.append("|---:|" + "---:|" * len(TOOLS))
        for f in sizes:
            cells = []
            for t in TOOLS:
                m = memory.get((t, f))
                cells.append("%.1f / %.1f / %.2f" % (m["input_mb"], m["peak_mb"], m["peak_ratio"]) if m else "n/a")
            out.append("| {:,} | {} |".format(f, " | ".join(cells)))
        out.append("")
    if errors:
        out.append("Runs that failed: " + "; ".join(errors) + "\n")
    return {"sizes": sizes, "med": med, "input_faces": input_faces, "ratios": ratios, "slopes": slopes}


def robustness_report(r, out):
    kernels = r.get("kernels", {})
    keys = ["cases", "valid", "invalid", "exception", "crash", "timeout"]
    out.append("Seed %s, time limit %s s per run, every run in its own process; valid = `seam::check_pair` "
               "(the checks of `seam check`, evaluated exactly on the kernel's own input and output) "
               "passes.\n" % (r.get("seed", "?"), r.get("timeout", "?")))
    out.append("| kernel | " + " | ".join(keys) + " | valid share |")
    out.append("|---|" + "---:|" * (len(keys) + 1))
    for k, v in kernels.items():
        share = 100.0 * v["valid"] / v["cases"] if v["cases"] else 0
        out.append("| %s | %s | %.1f%% |" % (k, " | ".join(str(v.get(x, 0)) for x in keys), share))
    out.append("")
    fams = r.get("families", {})
    if fams:
        names = list(kernels)
        out.append("Valid runs per family of configurations:\n")
        out.append("| family | " + " | ".join(names) + " |")
        out.append("|---|" + "---:|" * len(names))
        for fam, ks in fams.items():
            out.append("| %s | %s |" % (fam, " | ".join(
                "%d / %d" % (ks[k]["valid"], ks[k]["cases"]) if k in ks else "-" for k in names)))
        out.append("")
    exact_fail = [x for x in r.get("failures", []) if x["kernel"] == "exact"]
    if exact_fail:
        out.append("Exact runs that are not valid:\n")
        for x in exact_fail:
            out.append("- case %d (%s, %s): %s. %s" % (x["case"], x["family"], x["outcome"], x["description"],
                                                       x["detail"][:300]))
        out.append("")


def plot(data, path, title):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench_report.py: matplotlib is not installed (apt-get install python3-matplotlib): no plot",
              file=sys.stderr)
        return False
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    styles = {"exact": "o-", "filtered": "s-", "float": "^-", "corefine": "x--"}
    for t in TOOLS:
        pts = [(data["input_faces"][f] / 2, data["med"][(t, f)]) for f in data["sizes"] if (t, f) in data["med"]]
        if pts:
            label = t if t == "corefine" else "seam " + t
            if data["slopes"].get(t) is not None:
                label += " (slope %.2f)" % data["slopes"][t]
            ax1.loglog([p[0] for p in pts], [p[1] for p in pts], styles[t], label=label)
    ax1.set_xlabel("faces per tow")
    ax1.set_ylabel("read + compute + write (ms, median)")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8)
    for name, pts in data["ratios"].items():
        if pts:
            ax2.semilogx([p[0] / 2 for p in pts], [p[1] for p in pts], "o-", label=name.replace("exact/corefine",
                                                                                            "seam (exact) / corefine"))
    ax2.axhline(1.5, color="gray", lw=0.8, ls=":")
    ax2.axhline(2.0, color="gray", lw=0.8, ls="--")
    ax2.set_xlabel("faces per tow")
    ax2.set_ylabel("time ratio")
    ax2.set_ylim(bottom=0)
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fig.savefig(path, dpi=90)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kernels", help="bench_kernels JSON (--benchmark_out)")
    ap.add_argument("--robustness", help="seam_robustness --json output")
    ap.add_argument("--markdown", help="write the tables here (also printed)")
    ap.add_argument("--plot", help="write the plot here (.png or .svg)")
    a = ap.parse_args()
    out = []
    context = {}
    data = None
    if a.kernels:
        with open(a.kernels) as f:
            report = json.load(f)
        context = report.get("context", {})
        out.append("### Time per kernel\n")
        out.append("Machine: %s.\n" % machine_line(context))
        data = kernels_report(report, out)
    if a.robustness:
        with open(a.robustness) as f:
            rob = json.load(f)
        out.append("### Robustness (`seam_robustness`)\n")
        if not a.kernels:
            out.append("Machine: %s.\n" % machine_line({}))
        robustness_report(rob, out)
    text = "\n".join(out)
    print(text)
    if a.markdown:
        os.makedirs(os.path.dirname(a.markdown) or ".", exist_ok=True)
        with open(a.markdown, "w") as f:
            f.write(text + "\n")
    if a.plot and data:
        plot(data, a.plot, "seam pair per kernel vs CGAL corefine; " + machine_line(context))
    return 0


if __name__ == "__main__":
    sys.exit(main())
