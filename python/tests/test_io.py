"""seam.io: meshio conversions and a round trip through files."""
import numpy as np
import pytest

meshio = pytest.importorskip("meshio")

import seam  # noqa: E402
import seam.io  # noqa: E402


def test_round_trip_through_a_vtu_file_keeps_every_bit(tmp_path, crossover_pair):
    r = crossover_pair
    path = str(tmp_path / "a.vtu")
    seam.io.write(path, r.VA, r.FA, source_face=r.source_face_a, new=r.new_face_a)
    V, F = seam.io.read(path)
    assert np.array_equal(V, r.VA) and np.array_equal(F, r.FA)
    assert V.tobytes() == r.VA.tobytes()
    mesh = meshio.read(path)
    assert np.array_equal(mesh.cell_data["source_face"][0], r.source_face_a)
    assert np.array_equal(mesh.cell_data["new"][0].astype(bool), r.new_face_a)


def test_meshes_read_by_meshio_pair_as_the_arrays_do(tmp_path, crossover, crossover_pair):
    (VA, FA), (VB, FB) = crossover
    for name, (V, F) in (("a.ply", (VA, FA)), ("b.vtu", (VB, FB))):
        seam.io.write(str(tmp_path / name), V, F)
    A, B = seam.io.read(str(tmp_path / "a.ply")), seam.io.read(str(tmp_path / "b.vtu"))
    r = seam.pair(*A, *B)
    assert all(np.array_equal(x, y) for x, y in zip((r.VA, r.FA, r.VB, r.FB), crossover_pair.a + crossover_pair.b))


def test_pair_to_meshio_holds_both_outputs_and_the_curves(tmp_path, crossover_pair):
    r = crossover_pair
    mesh = seam.io.pair_to_meshio(r)
    path = str(tmp_path / "pair.vtu")
    mesh.write(path)
    back = meshio.read(path)
    triangles = sum(len(c.data) for c in back.cells if c.type == "triangle")  # a reader may merge blocks
    assert triangles == len(r.FA) + len(r.FB) and "line" in {c.type for c in back.cells}
    assert len(back.points) == len(r.VA) + len(r.VB) + sum(len(c) for c in r.curves)
    tow = np.concatenate(back.cell_data["tow"])
    assert (tow == 0).sum() == len(r.FA) and (tow == 1).sum() == len(r.FB)


def test_from_meshio_refuses_what_is_not_a_triangle_surface():
    quads = meshio.Mesh(np.zeros((4, 3)), [("quad", np.array([[0, 1, 2, 3]]))])
    with pytest.raises(seam.InputError, match="quad"):
        seam.io.from_meshio(quads)
    with pytest.raises(seam.InputError, match="no triangles"):
        seam.io.from_meshio(meshio.Mesh(np.zeros((2, 3)), [("line", np.array([[0, 1]]))]))
    with pytest.raises(seam.InputError, match="one value per face"):
        seam.io.to_meshio(np.eye(3), np.array([[0, 1, 2]]), source_face=np.arange(2))
