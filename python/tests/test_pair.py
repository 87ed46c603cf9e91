"""seam.pair: the invariants of the C++ tests (test/test_pair.cpp) through the binding."""
import threading
import time

import numpy as np
import pytest

import seam
from conftest import assert_curves_shared, assert_output_arrays


def check_result(inputs_a, inputs_b, r, kernel="exact"):
    (VA, FA), (VB, FB) = inputs_a, inputs_b
    assert_curves_shared(r.VA, r.FA, r.VB, r.FB, r.curves)
    assert_output_arrays(r.VA, r.FA, r.source_face_a, r.new_face_a, len(FA))
    assert_output_arrays(r.VB, r.FB, r.source_face_b, r.new_face_b, len(FB))
    assert r.report["verified"] is True
    verdict = seam.check((VA, FA), (VB, FB), r.a, r.b, r.curves, tol=r.report["verify_tolerance"], kernel=kernel)
    assert verdict, verdict.problems
    assert verdict.report["ok"] and verdict.report["curves"]["curves"] == len(r.curves)


def test_crossing_tows_come_out_conforming(crossover, crossover_pair):
    r = crossover_pair
    check_result(*crossover, r)
    assert r.report["kernel"] == "exact"
    assert r.report["curves"]["count"] == len(r.curves) >= 1
    assert r.report["a"]["output"]["faces"] == len(r.FA)
    assert r.new_face_a.any() and r.new_face_b.any()
    assert "from_arrays" in r.report["seconds"] and "to_arrays" in r.report["seconds"]


def test_crossing_boxes_conform_under_every_kernel(boxes):
    (VA, FA), (VB, FB) = boxes
    for kernel in seam.KERNELS:
        try:
            r = seam.pair(VA, FA, VB, FB, kernel=kernel)
        except seam.InternalError:  # the float kernel may refuse; it never returns a broken pair
            assert kernel == "float"
            continue
        assert r.report["kernel"] == kernel
        check_result((VA, FA), (VB, FB), r, kernel="exact")


def test_without_the_quality_stage_and_snapping_untouched_faces_are_the_input_faces(crossover):
    (VA, FA), (VB, FB) = crossover
    r = seam.pair(VA, FA, VB, FB, snap_tol=0, improve=False)
    check_result(*crossover, r)
    assert r.report["improve"]["done"] is False
    for V, F, V2, F2, source, new in ((VA, FA, r.VA, r.FA, r.source_face_a, r.new_face_a),
                                      (VB, FB, r.VB, r.FB, r.source_face_b, r.new_face_b)):
        kept = np.flatnonzero(~new)
        assert len(kept) > 0
        assert np.array_equal(V2[F2[kept]], V[F[source[kept]]]), "a face seam did not make moved"


def test_inputs_are_not_modified_and_lists_are_accepted(boxes):
    (VA, FA), (VB, FB) = boxes
    copies = [a.copy() for a in (VA, FA, VB, FB)]
    r = seam.pair(VA.tolist(), FA.astype(np.int32), VB.astype(np.float32), FB.astype(np.uint16))
    for a, b in zip((VA, FA, VB, FB), copies):
        assert np.array_equal(a, b)
    assert_curves_shared(r.VA, r.FA, r.VB, r.FB, r.curves)


def test_outputs_are_writable_arrays_owned_by_numpy(crossover_pair):
    r = crossover_pair
    V = r.VA.copy()
    r.VA[0, 0] += 1.0  # must not crash nor touch seam's memory
    r.VA[0, 0] = V[0, 0]
    assert r.VA.flags.writeable


def test_meshes_that_do_not_meet_give_no_curves():
    from conftest import box
    (VA, FA), (VB, FB) = box((0, 0, 0), (1, 1, 1)), box((3, 0, 0), (4, 1, 1))
    r = seam.pair(VA, FA, VB, FB)
    assert r.curves == []
    assert np.array_equal(r.VA, VA) and np.array_equal(r.FA, FA)
    assert np.array_equal(r.source_face_a, np.arange(len(FA))) and not r.new_face_a.any()
    assert r.report["note"]


def test_given_curves_are_shared_too(crossover, crossover_pair):
    (VA, FA), (VB, FB) = crossover
    # The computed curves, moved off both surfaces by a little: seam moves the meshes onto them.
    given = [c + np.array([0.0, 0.0, 1e-4]) for c in crossover_pair.curves]
    r = seam.pair(VA, FA, VB, FB, curves=given)
    assert r.report["given_curves"] is True
    assert_curves_shared(r.VA, r.FA, r.VB, r.FB, r.curves)
    assert seam.check((VA, FA), (VB, FB), r.a, r.b, r.curves, tol=r.report["verify_tolerance"])


def test_the_gil_is_released_while_seam_computes():
    # A crossover large enough that the computation takes well over the 0.05 s asserted below.
    (VA, FA), (VB, FB) = seam.make_crossover(60, 24, 50, 24)
    done = {}

    def run():
        t = time.perf_counter()
        seam.pair(VA, FA, VB, FB)
        done["seconds"] = time.perf_counter() - t

    worker = threading.Thread(target=run)
    last = time.perf_counter()
    worker.start()
    longest_gap = 0.0
    while worker.is_alive():  # this thread keeps running Python while the other computes
        now = time.perf_counter()
        longest_gap, last = max(longest_gap, now - last), now
        time.sleep(0.001)
    worker.join()
    assert done["seconds"] > 0.05
    assert longest_gap < 0.5 * done["seconds"], (longest_gap, done["seconds"])


def test_bound_reach_limits_the_refinement_of_an_anisotropic_crossover():
    # Tows with about four times as many sections as points around: most input faces below 20
    # degrees, so 'auto' resolves to 1 for both and makes what bound_reach=1 makes; no limit
    # (254) refines more of both meshes. Every result is verified by seam.check.
    weft, warp = seam.make_crossover(150, 16, 125, 16, "lenticular", 0.45)
    results = {reach: seam.pair(*weft, *warp, bound_reach=reach) for reach in ("auto", 1, 254)}
    for r in results.values():
        check_result(weft, warp, r)
    assert results["auto"].report["improve"]["bound_reach"] == [1, 1]
    assert results[254].report["improve"]["bound_reach"] == [254, 254]
    new = {reach: int(r.new_face_a.sum() + r.new_face_b.sum()) for reach, r in results.items()}
    assert new["auto"] == new[1] < new[254]
