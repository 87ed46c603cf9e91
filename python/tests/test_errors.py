"""Bad input raises seam.InputError naming the array or option, never crashes."""
import numpy as np
import pytest

import seam
from conftest import box


@pytest.fixture
def meshes():
    (VA, FA), (VB, FB) = box((-2.0, -0.5, -0.5), (2.0, 0.5, 0.5)), box((-0.6, -1.9, -0.3), (0.7, 2.1, 0.8))
    return VA, FA, VB, FB


def raises_input_error(match, fn, *args, **kwargs):
    with pytest.raises(seam.InputError, match=match) as info:
        fn(*args, **kwargs)
    return str(info.value)


def test_the_exceptions_form_a_hierarchy():
    assert issubclass(seam.InputError, seam.Error) and issubclass(seam.InputError, ValueError)
    assert issubclass(seam.InternalError, seam.Error) and issubclass(seam.InternalError, RuntimeError)
    assert seam.InputError.__module__ == "seam" and seam.InternalError.__module__ == "seam"


@pytest.mark.parametrize("bad, match", [
    (np.zeros((8, 2)), r"^VA: must have shape \(n, 3\), got \(8, 2\)"),
    (np.zeros((8, 3, 1)), r"^VA: must have shape \(n, 3\), got \(8, 3, 1\)"),
    (np.zeros(24), r"^VA: must have shape \(n, 3\), got \(24,\)"),
    (np.zeros((0, 3)), r"^VA: no vertices"),
    (np.full((8, 3), "1.0"), r"^VA: must hold real numbers, got dtype <U3"),
    (np.zeros((8, 3), dtype=complex), r"^VA: must hold real numbers, got dtype complex128"),
    (np.zeros((8, 3), dtype=bool), r"^VA: must hold real numbers, got dtype bool"),
    (np.array([[0, 0, 2 ** 60]] * 8), r"^VA: integer coordinates beyond 2\*\*53"),
    ([[0, 0, 0], [1, 1]], r"^VA: not an array of numbers"),
    (None, r"^VA: must hold real numbers, got dtype object"),
])
def test_bad_vertex_arrays(meshes, bad, match):
    VA, FA, VB, FB = meshes
    raises_input_error(match, seam.pair, bad, FA, VB, FB)


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinates(meshes, value):
    VA, FA, VB, FB = meshes
    VB = VB.copy()
    VB[5, 1] = value
    raises_input_error(r"^VB: vertex 5 has a non-finite coordinate", seam.pair, VA, FA, VB, FB)


def test_coordinates_beyond_the_supported_range(meshes):
    VA, FA, VB, FB = meshes
    raises_input_error(r"^VA: ", seam.pair, VA * 1e40, FA, VB, FB)


@pytest.mark.parametrize("edit, match", [
    (lambda F: F.astype(np.float64), r"^FA: must hold integer vertex indices, got dtype float64 \(use FA.astype"),
    (lambda F: F[:, :2], r"^FA: must have shape \(m, 3\), got \(12, 2\)"),
    (lambda F: F[:0], r"^FA: no faces"),
    (lambda F: np.where(F == 7, -1, F), r"^FA: face \d+ has a negative vertex index -1$"),
    (lambda F: np.where(F == 7, 8, F), r"^FA: face \d+ has a vertex index 8 out of range \(VA has 8 vertices\)$"),
    (lambda F: np.where(F == 7, 2 ** 40, F).astype(np.uint64), r"^FA: face \d+ has a vertex index 1099511627776 out of range"),
    (lambda F: np.vstack([F, F[:1]]), r"^FA: edge .* (shared by 3 faces|same direction)"),
    (lambda F: np.vstack([F[:1, ::-1], F[1:]]),
     r"^FA: faces \d+ and \d+ use edge .* in the same direction \(inconsistent orientation\)"),
    (lambda F: np.vstack([F[:1], [[0, 0, 1]], F[1:]]), r"^FA: face 1 repeats vertex 0"),
])
def test_bad_face_arrays(meshes, edit, match):
    VA, FA, VB, FB = meshes
    raises_input_error(match, seam.pair, VA, edit(FA), VB, FB)


def test_non_manifold_vertex_is_refused(meshes):
    VA, FA, VB, FB = meshes
    # Two boxes sharing one corner only: that vertex's faces form two fans.
    V2, F2 = box((2.0, 0.5, 0.5), (3.0, 1.5, 1.5))
    V = np.vstack([VA, V2])
    F2 = F2 + len(VA)
    F2[F2 == len(VA)] = 6  # the second box's corner (2, 0.5, 0.5) is the first box's vertex 6
    raises_input_error(r"^FA: vertex 6 is non-manifold", seam.pair, V, np.vstack([FA, F2]), VB, FB)


def test_degenerate_and_self_intersecting_meshes_are_refused(meshes):
    VA, FA, VB, FB = meshes
    flat = VA.copy()
    flat[:, 2] = 0  # every face of the sides has zero area
    raises_input_error(r"^FA: face \d+ has zero area", seam.pair, flat, FA, VB, FB)
    # The same box twice, one inside the other's faces: the surface intersects itself.
    V2, F2 = box((-1.0, -0.25, -1.0), (1.0, 0.25, 1.0))
    raises_input_error(r"^FA: faces \d+ and \d+ intersect", seam.pair, np.vstack([VA, V2]),
                       np.vstack([FA, F2 + len(VA)]), VB, FB)


@pytest.mark.parametrize("options, match", [
    (dict(kernel="exactish"), r"^kernel='exactish': must be 'exact', 'filtered' or 'float'$"),
    (dict(kernel=None), r"^kernel=None"),
    (dict(snap_tol=-1), r"^snap_tol=-1: out of range \(must be 'auto' or a finite number >= 0\)$"),
    (dict(snap_tol="0.1"), r"^snap_tol='0.1': not a number"),
    (dict(snap_tol=float("nan")), r"^snap_tol=nan: not a finite number"),
    (dict(min_angle=61), r"^min_angle=61: out of range \(must be a finite number from 0 to 60, degrees\)$"),
    (dict(min_angle=True), r"^min_angle=True: not a number"),
    (dict(max_area=-1.0), r"^max_area=-1.0: out of range"),
    (dict(improve="no"), r"^improve='no': must be True or False$"),
    (dict(bound_reach=-1), r"^bound_reach=-1: out of range \(must be 'auto' or an integer from 0 to 1e\+09, faces\)$"),
    (dict(bound_reach=1.5), r"^bound_reach=1.5: not an integer"),
    (dict(bound_reach="1"), r"^bound_reach='1': not a number"),
    (dict(curves=np.zeros((3, 3))), r"^curves: must be a list of \(n, 3\) arrays, got one array"),
    (dict(curves=[np.zeros((3, 2))]), r"^curves\[0\]: must have shape \(n, 3\)"),
    (dict(curves=[np.array([[0, 0, np.nan], [1, 0, 0]])]), r"^curves\[0\]: point 0 has a non-finite coordinate"),
])
def test_bad_options(meshes, options, match):
    raises_input_error(match, seam.pair, *meshes, **options)


def test_unknown_options_are_type_errors(meshes):
    with pytest.raises(TypeError):
        seam.pair(*meshes, snap_tolerance=0.1)


def test_the_extension_checks_its_arrays_too(meshes):
    """seam._seam called directly, with arrays the package would have converted: no crash."""
    VA, FA, VB, FB = meshes
    args = dict(kernel="exact", snap_tol=-1.0, min_angle=20.0, max_area=0.0, bound_reach=-1, improve=True, curves=None)
    with pytest.raises(seam.InputError, match=r"^VA: must be an array of dtype float64"):
        seam._seam.pair(VA.astype(np.float32), FA, VB, FB, **args)
    with pytest.raises(seam.InputError, match=r"^FA: must be an array of dtype int64"):
        seam._seam.pair(VA, FA.astype(np.int32), VB, FB, **args)
    with pytest.raises(seam.InputError, match=r"^FB: must have shape \(n, 3\)"):
        seam._seam.pair(VA, FA, VB, FB.reshape(-1), **args)
    with pytest.raises(seam.InputError, match=r"^VB: must be C-contiguous"):
        seam._seam.pair(VA, FA, np.asfortranarray(VB), FB, **args)
    bad = FA.copy()
    bad[3, 1] = -5
    with pytest.raises(seam.InputError, match=r"^FA: face 3 has a negative vertex index -5"):
        seam._seam.pair(VA, bad, VB, FB, **args)
    bad[3, 1] = 99
    with pytest.raises(seam.InputError, match=r"^FA: face 3 has a vertex index 99 out of range \(VA has 8 vertices\)"):
        seam._seam.pair(VA, bad, VB, FB, **args)
    nan = VA.copy()
    nan[2, 2] = np.nan
    with pytest.raises(seam.InputError, match=r"^VA: vertex 2 has a non-finite coordinate"):
        seam._seam.pair(nan, FA, VB, FB, **args)
    with pytest.raises(seam.InputError, match=r"^kernel 'fast'"):
        seam._seam.pair(VA, FA, VB, FB, **dict(args, kernel="fast"))
    with pytest.raises(seam.InputError):
        seam._seam.pair(VA, FA, VB, FB, **dict(args, min_angle=90.0))


def test_embed_check_and_textile_name_their_arrays(meshes):
    VA, FA, VB, FB = meshes
    bad = FA.copy()
    bad[0, 0] = 100
    raises_input_error(r"^F: face 0 has a vertex index 100 out of range \(V has 8 vertices\)",
                       seam.embed, VA, bad, [np.array([[0, 0, 0.5], [1, 0, 0.5]])])
    raises_input_error(r"^curves\[0\]: ", seam.embed, VA, FA, [np.array([[0, 0, 0.5]])])
    raises_input_error(r"^FB2: face 0 has a vertex index 100", seam.check, (VA, FA), (VB, FB), (VA, FA), (VB, bad), [])
    raises_input_error(r"^A2: must be a pair \(V, F\)", seam.check, (VA, FA), (VB, FB), VA, (VB, FB), [])
    raises_input_error(r"^tows\[1\].F: face 0 has a vertex index 100", seam.textile, [(VA, FA), (VB, bad)])
    raises_input_error(r"^threads=-1: out of range", seam.textile, [(VA, FA), (VB, FB)], threads=-1)
    raises_input_error(r"^threads=1.5: not an integer", seam.textile, [(VA, FA), (VB, FB)], threads=1.5)
    raises_input_error(r"^names: 1 names for 2 tows", seam.textile, [(VA, FA), (VB, FB)], names=["x"])
    raises_input_error(r"^max_distance=", seam.embed, VA, FA, [], max_distance=-2)
    raises_input_error(r"^warp_section=", seam.make_crossover, warp_section="round")
    raises_input_error(r"^weft_along=0", seam.make_crossover, weft_along=0)


def test_a_curve_far_from_the_surface_is_an_input_error(meshes):
    VA, FA, _, _ = meshes
    raises_input_error(r"^curves: ", seam.embed, VA, FA, [np.array([[0, 0, 50.0], [1, 0, 50.0]])])
