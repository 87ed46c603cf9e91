"""seam.embed, seam.check and seam.textile through the binding."""
import numpy as np

import seam
from conftest import assert_curves_shared, assert_output_arrays, box, edge_set, row_index


def test_embed_makes_each_curve_a_chain_of_edges():
    V, F = box((0.0, 0.0, 0.0), (2.0, 1.0, 1.0))
    # A segment just above the top face, crossing its diagonal.
    top = np.array([[0.3, 0.2, 1.0005], [1.6, 0.7, 1.0005]])
    r = seam.embed(V, F, [top])
    assert_output_arrays(r.V, r.F, r.source_face, r.new_face, len(F))
    assert len(r.curves) == len(r.curve_vertices) == 1
    index, edges = row_index(r.V), edge_set(r.F)
    for c, ids in zip(r.curves, r.curve_vertices):
        assert ids.dtype == np.int64
        assert [index[p.tobytes()] for p in c] == ids.tolist()
        assert all(frozenset((int(u), int(v))) in edges for u, v in zip(ids, ids[1:]))
    assert r.report["curve"]["curves"] == 1 and r.report["output"]["faces"] == len(r.F)
    assert np.allclose(r.curves[0][[0, -1], :2], top[:, :2])


def test_check_finds_the_crossings_of_the_unchanged_inputs(crossover, crossover_pair):
    (VA, FA), (VB, FB) = crossover
    r = crossover_pair
    ok = seam.check((VA, FA), (VB, FB), r.a, r.b, r.curves, tol=r.report["verify_tolerance"])
    assert ok and ok.problems == [] and ok.report["face_pairs"]["intersecting_off_curves"] == 0
    bad = seam.check((VA, FA), (VB, FB), (VA, FA), (VB, FB), r.curves)
    assert not bad and bad.problems
    assert bad.report["face_pairs"]["intersecting_off_curves"] > 0
    assert any("are not vertices" in p for p in bad.problems), bad.problems[:5]
    # An output moved off its surface fails check 4 at the default tolerance.
    moved = r.VA.copy()
    moved[:, 2] += 1e-3
    assert not seam.check((VA, FA), (VB, FB), (moved, r.FA), r.b, r.curves)


def test_textile_three_tows_every_pair_conforms(crossover):
    (V0, F0), (V1, F1) = crossover
    V2 = V1 + np.array([3.0, 0.0, 0.0])  # a second warp, crossing the weft too
    tows = [(V0, F0), (V1, F1), (V2, F1)]
    r = seam.textile(tows, names=["weft", "warp1", "warp2"], threads=2)
    assert [(p.a, p.b) for p in r.pairs] == [(0, 1), (0, 2)]
    assert r.report["intersecting_pairs"] == 2 and [t["name"] for t in r.report["tows"]] == ["weft", "warp1", "warp2"]
    for t, (_, F) in zip(r.tows, tows):
        assert_output_arrays(t.V, t.F, t.source_face, t.new_face, len(F))
    for p in r.pairs:
        a, b = r.tows[p.a], r.tows[p.b]
        assert_curves_shared(a.V, a.F, b.V, b.F, p.curves)
        assert seam.check(tows[p.a], tows[p.b], a, b, p.curves, tol=r.report["verify_tolerance"])
    assert r.report["verified"] is True
    untouched = seam.textile(tows[1:])  # the two warps do not meet
    assert untouched.pairs == [] and np.array_equal(untouched.tows[0].V, V1)
