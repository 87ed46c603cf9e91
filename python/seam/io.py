"""seam.io: meshes to and from meshio (https://github.com/nschloe/meshio; Debian python3-meshio),
and so to and from every file format meshio knows (.vtu, .vtk, .off, .obj, .ply, .stl, ...).

    import seam, seam.io
    VA, FA = seam.io.read("weft.stl")
    r = seam.pair(VA, FA, VB, FB)
    seam.io.write("weft_out.vtu", r.VA, r.FA, source_face=r.source_face_a, new=r.new_face_a)
    seam.io.pair_to_meshio(r).write("pair.vtu")    # both outputs and the curves, as `seam pair --vtk`

Only this module needs meshio; `import seam` does not.
"""

import numpy as _np

try:
    import meshio as _meshio
except ImportError as _e:  # pragma: no cover - depends on the machine
    raise ImportError("seam.io needs meshio (pip install meshio, or Debian's python3-meshio)") from _e

from . import InputError, _faces, _vertices

__all__ = ["to_meshio", "from_meshio", "read", "write", "pair_to_meshio"]

# Cell types that are not surface triangles: from_meshio refuses these (a mesh of quads or
# tetrahedra is not a triangle surface) and ignores the rest (points, lines).
_SURFACE_OR_VOLUME = {"quad", "polygon", "triangle6", "quad8", "quad9", "tetra", "tetra10", "hexahedron",
                      "hexahedron20", "hexahedron27", "wedge", "pyramid"}


def to_meshio(V, F, **cell_data) -> "_meshio.Mesh":
    """A meshio.Mesh of triangles; keyword arguments are per-face arrays (cell data), e.g.
    source_face=r.source_face_a, new=r.new_face_a (bool arrays are stored as int8)."""
    V = _vertices("V", V)
    F = _faces("F", F, len(V), "V")
    data = {}
    for name, values in cell_data.items():
        values = _np.asarray(values)
        if values.shape[:1] != (len(F),):
            raise InputError(f"{name}: must have one value per face ({len(F)}), got shape {values.shape}")
        data[name] = [values.astype(_np.int8) if values.dtype == bool else values]
    return _meshio.Mesh(V, [("triangle", F)], cell_data=data)


def from_meshio(mesh) -> tuple:
    """(V, F) of a meshio.Mesh's triangles (all triangle blocks, in order), as seam takes them.
    Raises InputError when the mesh holds no triangles or cells of another surface or volume type
    (quads, tetrahedra: triangulate or extract the surface first); points and lines are ignored."""
    blocks = []
    for block in mesh.cells:
        if block.type == "triangle":
            blocks.append(_np.asarray(block.data))
        elif block.type in _SURFACE_OR_VOLUME:
            raise InputError(f"mesh: has cells of type '{block.type}' (seam takes triangle surfaces only)")
    if not blocks:
        raise InputError("mesh: has no triangles")
    V = _vertices("mesh.points", mesh.points)
    F = _faces("mesh cells", _np.concatenate(blocks), len(V), "mesh.points")
    return V, F


def read(path, file_format=None) -> tuple:
    """(V, F) of a mesh file, read by meshio (format by extension unless file_format is given)."""
    return from_meshio(_meshio.read(path, file_format=file_format))


def write(path, V, F, file_format=None, **cell_data):
    """Writes the triangle mesh (V, F) with meshio; cell_data as in to_meshio(). Formats that
    store text (.off, .obj) are written by meshio, which may not keep every bit of a coordinate;
    .vtu (binary) and .ply keep them."""
    to_meshio(V, F, **cell_data).write(path, file_format=file_format)


def pair_to_meshio(result) -> "_meshio.Mesh":
    """One meshio.Mesh of a seam.pair result: both outputs as triangles and the curves as lines,
    with the cell data of `seam pair --vtk`: tow (0: A, 1: B, -1: curve), source_face (-1 for
    curves and for faces remeshed next to the curves) and new (1 for triangles seam made)."""
    VA, VB = result.VA, result.VB
    points = [VA, VB]
    offset = len(VA) + len(VB)
    segments, singles = [], []
    for c in result.curves:  # each curve's points appended; a segment per consecutive pair
        idx = _np.arange(offset, offset + len(c))
        if len(c) == 1:  # an isolated point of contact
            singles.append(idx)
        else:
            segments.append(_np.stack([idx[:-1], idx[1:]], axis=1))
        points.append(c)
        offset += len(c)
    cells = [("triangle", result.FA), ("triangle", result.FB + len(VA))]
    tow = [_np.zeros(len(result.FA), _np.int32), _np.ones(len(result.FB), _np.int32)]
    source = [result.source_face_a, result.source_face_b]
    new = [result.new_face_a.astype(_np.int8), result.new_face_b.astype(_np.int8)]
    for cell_type, blocks in (("line", segments), ("vertex", [s[:, None] for s in singles])):
        if blocks:
            block = _np.concatenate(blocks)
            cells.append((cell_type, block))
            tow.append(_np.full(len(block), -1, _np.int32))
            source.append(_np.full(len(block), -1, _np.int64))
            new.append(_np.zeros(len(block), _np.int8))
    return _meshio.Mesh(_np.concatenate(points), cells, cell_data={"tow": tow, "source_face": source, "new": new})
