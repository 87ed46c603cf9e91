"""Shared inputs and invariants of the Python binding tests (run by ctest: python_bindings)."""
import os

import numpy as np
import pytest

import seam

SOURCE_DIR = os.environ.get("SEAM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def box(lo, hi):
    """An axis-aligned box, closed and outward-oriented: 8 vertices, 12 triangles."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    V = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]], dtype=np.int64)
    return V, F


@pytest.fixture(scope="session")
def boxes():
    """Two boxes crossing like a plus sign, corners in general position."""
    return box((-2.0, -0.5, -0.5), (2.0, 0.5, 0.5)), box((-0.6, -1.9, -0.3), (0.7, 2.1, 0.8))


@pytest.fixture(scope="session")
def crossover():
    """A small generated weave crossing (seam.make_crossover)."""
    return seam.make_crossover(24, 12, 20, 12)


@pytest.fixture(scope="session")
def crossover_pair(crossover):
    (VA, FA), (VB, FB) = crossover
    return seam.pair(VA, FA, VB, FB)


def row_index(V):
    """Each vertex's exact bytes -> its index: lookups are bit for bit."""
    return {row.tobytes(): i for i, row in enumerate(np.ascontiguousarray(V))}


def edge_set(F):
    return {frozenset((int(u), int(v))) for t in F for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}


def assert_curves_shared(V1, F1, V2, F2, curves):
    """Every curve point is a vertex of both meshes (bit for bit), every segment an edge of both."""
    assert curves, "no curves"
    for mesh_V, mesh_F in ((V1, F1), (V2, F2)):
        index, edges = row_index(mesh_V), edge_set(mesh_F)
        for c in curves:
            assert c.dtype == np.float64 and c.ndim == 2 and c.shape[1] == 3 and c.flags.c_contiguous
            ids = [index.get(p.tobytes()) for p in c]
            assert None not in ids, "a curve point is not a vertex"
            for u, v in zip(ids, ids[1:]):
                assert frozenset((u, v)) in edges, "a curve segment is not an edge"


def assert_output_arrays(V, F, source, new, input_faces):
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3 and V.flags.c_contiguous
    assert F.dtype == np.int64 and F.ndim == 2 and F.shape[1] == 3 and F.flags.c_contiguous
    assert F.min() >= 0 and F.max() < len(V)
    assert source.shape == (len(F),) and source.dtype == np.int64
    assert new.shape == (len(F),) and new.dtype == np.bool_
    assert source.min() >= -1 and source.max() < input_faces
    assert (source[~new] >= 0).all(), "a face seam did not make has its input face"
    assert np.isfinite(V).all()
