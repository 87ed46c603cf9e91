"""The example script, and the binding against the CLI on the same input files."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import seam
from conftest import SOURCE_DIR

CLI = os.environ.get("SEAM_CLI")


def test_the_example_script_writes_a_vtu(tmp_path):
    meshio = pytest.importorskip("meshio")
    out = tmp_path / "example.vtu"
    run = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "examples", "python_pair.py"), str(out)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "seam check: OK" in run.stdout
    mesh = meshio.read(str(out))
    assert {"triangle", "line"} <= {c.type for c in mesh.cells}


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.17g")
        np.savetxt(f, np.column_stack([np.full(len(F), 3), F]), fmt="%d")


def keys(value):
    """The tree of keys of a JSON value (lists: the keys of their first element)."""
    if isinstance(value, dict):
        return {k: keys(v) for k, v in value.items()}
    if isinstance(value, list):
        return [keys(value[0])] if value and isinstance(value[0], (dict, list)) else []
    return None


@pytest.mark.skipif(not CLI, reason="SEAM_CLI (the seam executable) not given")
def test_the_binding_gives_the_clis_outputs_and_report_keys(tmp_path, crossover, crossover_pair):
    (VA, FA), (VB, FB) = crossover
    a, b = str(tmp_path / "a.off"), str(tmp_path / "b.off")
    write_off(a, VA, FA)
    write_off(b, VB, FB)
    out_a, out_b, report = (str(tmp_path / n) for n in ("a2.off", "b2.off", "report.json"))
    run = subprocess.run([CLI, "pair", a, b, "--out-a", out_a, "--out-b", out_b, "--report", report],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr

    def read_off(path):
        with open(path) as f:
            tokens = [t for line in f for t in line.split("#")[0].split()]
        assert tokens[0] == "OFF"
        nv, nf = int(tokens[1]), int(tokens[2])
        V = np.array([float(t) for t in tokens[4:4 + 3 * nv]]).reshape(nv, 3)
        F = np.array([int(t) for t in tokens[4 + 3 * nv:4 + 3 * nv + 4 * nf]]).reshape(nf, 4)
        assert (F[:, 0] == 3).all()
        return V, F[:, 1:]

    r = crossover_pair
    for (V, F), V2, F2 in ((read_off(out_a), r.VA, r.FA), (read_off(out_b), r.VB, r.FB)):
        assert np.array_equal(V, V2) and np.array_equal(F, F2), "the binding's output differs from the CLI's"
    with open(report) as f:
        cli = json.load(f)
    cli.pop("files")
    ours = json.loads(json.dumps(r.report))  # a copy: the fixture's report stays as it is
    for tree in (cli, ours):  # stage timings: the CLI reads and writes files, the binding converts arrays
        tree["seconds"] = {}
        for mesh in ("a", "b"):
            tree[mesh]["seconds"] = {}
    assert keys(cli) == keys(ours)
    assert cli["curves"] == ours["curves"] and cli["a"]["output"] == ours["a"]["output"]
