"""seam: make two interpenetrating triangle meshes (textile tows) conform along their
intersection curves, from NumPy arrays, without files in between.

    import seam
    r = seam.pair(VA, FA, VB, FB)      # vertices (n, 3) float64, faces (m, 3) int64
    r.VA, r.FA, r.VB, r.FB             # the conforming outputs
    r.curves                           # the shared curves: (k, 3) float64 arrays, whose points
                                       # are vertices of both outputs, bit for bit
    r.source_face_a, r.new_face_a      # per face of FA: the input face it lies in (-1: none,
                                       # remeshed next to the curves), made by seam or not
    r.report                           # dict: the keys of `seam pair --report`
    seam.check((VA, FA), (VB, FB), r.a, r.b, r.curves, tol=r.report["verify_tolerance"])

Functions: pair, embed, check, textile, make_crossover; seam.io converts to and from meshio.
Options are keyword arguments named after the CLI's long options (--snap-tol -> snap_tol) with
the same defaults; kernel="exact" | "filtered" | "float".

Arrays in: vertices of any real dtype whose values are exactly float64 (float16/32/64, integers
up to 2**53), faces of any integer dtype, shape (n, 3), anything np.asarray accepts (lists too).
Anything else raises seam.InputError naming the array (no silent rounding, no float faces).
Arrays out: C-contiguous float64 vertices, int64 faces, bool/int64 per-face arrays, owned by
NumPy (writable; no copy is made after the library's own conversion).

Errors: seam.InputError (also a ValueError) for bad input, naming the array ("FA: face 3 has a
vertex index 9 out of range (VA has 8 vertices)") or the option; seam.InternalError (also a
RuntimeError) when seam cannot produce a valid result from valid input (the CLI's exit code 3);
both derive from seam.Error. The GIL is released while seam computes.

More in docs/python.md.
"""

import json as _json
import math as _math
import numbers as _numbers
from dataclasses import dataclass as _dataclass
from typing import List, Optional

import numpy as _np

from . import _seam
from ._seam import Error, InputError, InternalError

__all__ = [
    "Error", "InputError", "InternalError", "KERNELS",
    "pair", "embed", "check", "textile", "make_crossover",
    "PairResult", "EmbedResult", "CheckResult", "TextileResult", "Tow", "TextilePair",
]

KERNELS = ("exact", "filtered", "float")

_EXACT_INTEGERS = 2 ** 53  # integers up to this magnitude are exact in float64


# ---------------------------------------------------------------- arguments

def _array(name, value):
    try:
        return _np.asarray(value)
    except (ValueError, TypeError) as e:  # ragged lists, say
        raise InputError(f"{name}: not an array of numbers ({e})") from None


def _shape_text(a):
    return "(" + ", ".join(str(n) for n in a.shape) + ("," if a.ndim == 1 else "") + ")"


def _vertices(name, value, what="vertex"):
    """`value` as C-contiguous float64 (n, 3), n >= 1, finite; refuses what float64 cannot hold."""
    a = _array(name, value)
    kind = a.dtype.kind
    if kind not in "fiu":
        raise InputError(f"{name}: must hold real numbers, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise InputError(f"{name}: must have shape (n, 3), got {_shape_text(a)}")
    if a.shape[0] == 0:
        raise InputError(f"{name}: no {'points' if what == 'point' else 'vertices'} (shape {_shape_text(a)})")
    if kind in "iu" and a.dtype.itemsize * 8 > 53 and (a.max() > _EXACT_INTEGERS or a.min() < -_EXACT_INTEGERS):
        raise InputError(f"{name}: integer coordinates beyond 2**53 are not exact in float64")
    converted = _np.require(a, dtype=_np.float64, requirements=["C", "A"])
    if kind == "f" and a.dtype.itemsize > 8:  # long double: only if every value is a double
        with _np.errstate(invalid="ignore"):
            same = (converted == a) | (_np.isnan(converted) & _np.isnan(a))
        if not same.all():
            raise InputError(f"{name}: values of dtype {a.dtype} that float64 cannot hold exactly")
    finite = _np.isfinite(converted).all(axis=1)
    if not finite.all():
        i = int(_np.argmin(finite))
        raise InputError(f"{name}: {what} {i} has a non-finite coordinate ({', '.join(repr(float(x)) for x in converted[i])})")
    return converted


def _faces(name, value, vertex_count, vertices_name):
    """`value` as C-contiguous int64 (m, 3), m >= 1, each index in [0, vertex_count)."""
    a = _array(name, value)
    if a.dtype.kind not in "iu":
        hint = f" (use {name}.astype(numpy.int64) if its values are whole)" if a.dtype.kind == "f" else ""
        raise InputError(f"{name}: must hold integer vertex indices, got dtype {a.dtype}{hint}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise InputError(f"{name}: must have shape (m, 3), got {_shape_text(a)}")
    if a.shape[0] == 0:
        raise InputError(f"{name}: no faces (shape {_shape_text(a)})")
    bad = _np.argwhere(a < 0) if a.dtype.kind == "i" else ()
    if len(bad):
        f, k = bad[0]
        raise InputError(f"{name}: face {f} has a negative vertex index {a[f, k]}")
    bad = _np.argwhere(a >= vertex_count)
    if len(bad):
        f, k = bad[0]
        raise InputError(f"{name}: face {f} has a vertex index {a[f, k]} out of range "
                         f"({vertices_name} has {vertex_count} vertices)")
    return _np.require(a, dtype=_np.int64, requirements=["C", "A"])


def _mesh(v_name, f_name, V, F):
    V = _vertices(v_name, V)
    return V, _faces(f_name, F, len(V), v_name)


def _mesh_argument(name, value):
    """A mesh given as (V, F), or as an object with attributes V and F (a Tow, say)."""
    if hasattr(value, "V") and hasattr(value, "F"):
        return value.V, value.F
    try:
        V, F = value
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a pair (V, F) of vertex and face arrays") from None
    return V, F


def _curves(value, name="curves"):
    if isinstance(value, _np.ndarray):
        raise InputError(f"{name}: must be a list of (n, 3) arrays, got one array (put it in a list)")
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"{name}: must be a list of (n, 3) arrays") from None
    return [_vertices(f"{name}[{i}]", c, what="point") for i, c in enumerate(items)]


def _number(name, value, low=0.0, high=_math.inf, auto=False, integer=False, note=""):
    """A numeric option as the CLI checks it: finite, in [low, high], or 'auto' (-1) where allowed."""
    if auto and isinstance(value, str) and value == "auto":
        return -1.0
    expected = ("'auto' or " if auto else "") + ("an integer" if integer else "a finite number")
    expected += f" >= {low:g}" if high == _math.inf else f" from {low:g} to {high:g}"
    if note:
        expected += ", " + note
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, _numbers.Real):
        raise InputError(f"{name}={value!r}: not a number (must be {expected})")
    x = float(value)
    if not _math.isfinite(x):
        raise InputError(f"{name}={value!r}: not a finite number (must be {expected})")
    if integer and x != _math.floor(x):
        raise InputError(f"{name}={value!r}: not an integer (must be {expected})")
    if not low <= x <= high:
        raise InputError(f"{name}={value!r}: out of range (must be {expected})")
    return int(x) if integer else x


def _bound_reach(value):
    """bound_reach as --bound-reach takes it: 'auto' (-1) or an integer >= 0 (254 or more: no limit)."""
    reach = _number("bound_reach", value, 0, 1e9, auto=True, integer=True, note="faces")
    return int(reach)  # (-1: auto; the library takes 254 and more as no limit)


def _flag(name, value):
    if not isinstance(value, (bool, _np.bool_)):
        raise InputError(f"{name}={value!r}: must be True or False")
    return bool(value)


def _kernel(value):
    if not isinstance(value, str) or value not in KERNELS:
        raise InputError(f"kernel={value!r}: must be 'exact', 'filtered' or 'float'")
    return value


def _report(raw):
    return _json.loads(raw)


def _size(a):
    return "x".join(str(n) for n in a.shape)


# ---------------------------------------------------------------- results

@_dataclass(repr=False)
class PairResult:
    """What seam.pair returns: both outputs, the shared curves, provenance and the report."""
    VA: _np.ndarray              #: (n, 3) float64, A made conforming
    FA: _np.ndarray              #: (m, 3) int64
    VB: _np.ndarray
    FB: _np.ndarray
    curves: List[_np.ndarray]    #: (k, 3) float64 each; closed ones repeat their first point;
                                 #: one point: an isolated point of contact
    source_face_a: _np.ndarray   #: (m,) int64: the face of FA (input) each face of FA lies in; -1: none
    new_face_a: _np.ndarray      #: (m,) bool: made by seam
    source_face_b: _np.ndarray
    new_face_b: _np.ndarray
    report: dict                 #: the keys of `seam pair --report` (no "files")

    @property
    def a(self):
        """(VA, FA): output A as a mesh argument of check()."""
        return self.VA, self.FA

    @property
    def b(self):
        """(VB, FB): output B."""
        return self.VB, self.FB

    def __repr__(self):
        return (f"PairResult(VA {_size(self.VA)}, FA {_size(self.FA)}, VB {_size(self.VB)}, FB {_size(self.FB)}, "
                f"{len(self.curves)} curve(s), verified={self.report.get('verified')})")


@_dataclass(repr=False)
class EmbedResult:
    """What seam.embed returns."""
    V: _np.ndarray                      #: (n, 3) float64
    F: _np.ndarray                      #: (m, 3) int64
    curves: List[_np.ndarray]           #: the curves as embedded (coarsened), (k, 3) float64 each
    curve_vertices: List[_np.ndarray]   #: per curve, its points as indices into V, (k,) int64
    source_face: _np.ndarray            #: (m,) int64: input face each face lies in
    new_face: _np.ndarray               #: (m,) bool
    report: dict                        #: the keys of `seam embed --report` (no "files")

    def __repr__(self):
        return f"EmbedResult(V {_size(self.V)}, F {_size(self.F)}, {len(self.curves)} curve(s))"


@_dataclass(repr=False)
class CheckResult:
    """What seam.check returns; true when every check holds."""
    ok: bool
    problems: List[str]   #: one line per failed check (the CLI's "FAIL: ..." lines)
    report: dict          #: the keys of `seam check --report` (no "files", "seconds")

    def __bool__(self):
        return self.ok

    def __repr__(self):
        return f"CheckResult(ok={self.ok}, {len(self.problems)} problem(s))"


@_dataclass(repr=False)
class Tow:
    """One tow after seam.textile."""
    V: _np.ndarray
    F: _np.ndarray
    source_face: _np.ndarray
    new_face: _np.ndarray

    def __repr__(self):
        return f"Tow(V {_size(self.V)}, F {_size(self.F)})"


@_dataclass(repr=False)
class TextilePair:
    """Two tows of seam.textile that meet (a < b, indices into the tows), and their curves."""
    a: int
    b: int
    curves: List[_np.ndarray]

    def __repr__(self):
        return f"TextilePair({self.a}, {self.b}, {len(self.curves)} curve(s))"


@_dataclass(repr=False)
class TextileResult:
    """What seam.textile returns."""
    tows: List[Tow]
    pairs: List[TextilePair]
    report: dict  #: the keys of `seam textile --report` (no file names)

    def __repr__(self):
        return f"TextileResult({len(self.tows)} tows, {len(self.pairs)} pair(s))"


# ---------------------------------------------------------------- operations

def pair(VA, FA, VB, FB, *, curves=None, snap_tol="auto", min_angle=20.0, max_area=0.0, bound_reach="auto",
         improve=True, kernel="exact") -> PairResult:
    """Makes meshes A (VA, FA) and B (VB, FB) conform along their intersection curves (`seam pair`).

    Computes the intersection curves exactly, embeds the same curves into both, refines the faces
    next to them to the angle bound, and verifies the outputs as `seam check` would: both outputs
    share every curve point (bit-identical coordinates) and every curve segment.

    VA, VB: (n, 3) vertices; FA, FB: (m, 3) vertex indices of valid, consistently oriented
    2-manifold triangle meshes without self-intersections (unreferenced vertices are dropped).
    curves: given curves near both surfaces (a list of (k, 3) arrays; `--curves`) instead of the
        computed intersection.
    snap_tol: tolerance of the quality stage, 'auto' (0.1 x the smaller mean edge length) or >= 0;
        0 keeps both surfaces.
    min_angle: the angle bound in degrees, 0..60.
    max_area: largest area of a new triangle within the faces the curves cross or touch (the
        re-triangulation and the quality stage refine to it); 0: no bound.
    bound_reach: how far (in faces, from those the curves cross) faces whose input faces are below
        the angle bound are held to it; farther, to their input face's smallest angle. 'auto'
        (per mesh: no limit where at least half of its faces meet the bound, else 1) or an
        integer >= 0 (254 or more: no limit). `--bound-reach`.
    improve: run the quality stage (False: `--no-improve`).
    kernel: 'exact' (default), 'filtered' or 'float'.

    Raises InputError (bad arrays or options, invalid or self-intersecting meshes, curves too far
    from the surfaces) or InternalError (no valid result; the inputs are not modified anyway).
    """
    VA, FA = _mesh("VA", "FA", VA, FA)
    VB, FB = _mesh("VB", "FB", VB, FB)
    given = None if curves is None else _curves(curves)
    r = _seam.pair(VA, FA, VB, FB, kernel=_kernel(kernel),
                   snap_tol=_number("snap_tol", snap_tol, auto=True),
                   min_angle=_number("min_angle", min_angle, 0, 60, note="degrees"),
                   max_area=_number("max_area", max_area), bound_reach=_bound_reach(bound_reach),
                   improve=_flag("improve", improve), curves=given)
    a, b = r["a"], r["b"]
    return PairResult(a["V"], a["F"], b["V"], b["F"], r["curves"], a["source_face"], a["new_face"],
                      b["source_face"], b["new_face"], _report(r["report"]))


def embed(V, F, curves, *, snap_tol="auto", min_angle=20.0, max_area=0.0, max_distance="auto", curve_tol=0.0,
          kernel="exact") -> EmbedResult:
    """Embeds polylines into one mesh (`seam embed`): every curve becomes a chain of edges.

    curves: a list of (k, 3) arrays, k >= 2 (closed when the last point equals the first), near
        the surface.
    snap_tol: vertices this close to a curve node move onto it; 'auto' (0.1 x the mean edge
        length) or >= 0 (0: no snapping).
    min_angle: degrees, 0..60, the refinement's aim in re-triangulated faces; 0: no refinement.
    max_area: largest area of a new triangle within the faces the curve crosses or touches; 0: no bound.
    max_distance: a curve node farther than this from the surface is an InputError; 'auto' (the
        mean edge length) or >= 0.
    curve_tol: keep a curve node between two crossings when dropping it would move the curve by
        more than this; 0 drops them all.
    kernel: 'exact' (default), 'filtered' or 'float'.
    """
    V, F = _mesh("V", "F", V, F)
    r = _seam.embed(V, F, _curves(curves), kernel=_kernel(kernel),
                    snap_tol=_number("snap_tol", snap_tol, auto=True),
                    min_angle=_number("min_angle", min_angle, 0, 60, note="degrees"),
                    max_area=_number("max_area", max_area),
                    max_distance=_number("max_distance", max_distance, auto=True),
                    curve_tol=_number("curve_tol", curve_tol))
    return EmbedResult(r["V"], r["F"], r["curves"], r["curve_vertices"], r["source_face"], r["new_face"],
                       _report(r["report"]))


def check(A, B, A2, B2, curves, *, tol="auto", kernel="exact") -> CheckResult:
    """Verifies a conforming pair independently of the code that made it (`seam check`).

    A, B: the inputs, A2, B2: the outputs, each (V, F) or an object with V and F; curves: the
    shared curves (a list of (k, 3) arrays; empty: A2 and B2 must not meet at all).
    tol: largest allowed distance of a vertex of A2 (B2) from A (B); 'auto' is 1e-9 x the diagonal
        of the bounding box of A and B; after seam.pair pass r.report["verify_tolerance"].
    Returns a CheckResult (true when every check holds; problems: one line per failure). A failed
    check is not an exception; invalid meshes raise InputError.
    """
    arrays = []
    for name, mesh in (("A", A), ("B", B), ("A2", A2), ("B2", B2)):
        V, F = _mesh_argument(name, mesh)
        arrays += _mesh("V" + name, "F" + name, V, F)
    r = _seam.check(*arrays, _curves(curves), tol=_number("tol", tol, auto=True), kernel=_kernel(kernel))
    return CheckResult(bool(r["ok"]), list(r["problems"]), _report(r["report"]))


def textile(tows, *, names=None, snap_tol="auto", min_angle=20.0, max_area=0.0, bound_reach="auto", improve=True,
            threads=0, kernel="exact") -> TextileResult:
    """Makes every interpenetrating pair among N tows conform at once, in parallel (`seam textile`).

    tows: a list of meshes, each (V, F) or an object with V and F; names: one string per tow, for
        messages and the report (default "tow0", "tow1", ...).
    snap_tol: 'auto' (1e-10 x the smallest bounding-box diagonal) or >= 0.
    min_angle, max_area: as for embed(). bound_reach: as for pair(). improve: run the quality
        stage on the faces along the curves of all tows at once (False: `--no-improve`).
        threads: worker threads, 0 (every core) to 1024; the result is the same for any number.
    Returns the tows made conforming and, for each pair that meets, its curves (every point a
    vertex of both tows); every pair is verified as written (seam.check passes at
    report["verify_tolerance"]).
    """
    try:
        items = list(tows)
    except TypeError:
        raise InputError("tows: must be a list of (V, F) meshes") from None
    meshes = []
    for i, t in enumerate(items):
        V, F = _mesh_argument(f"tows[{i}]", t)
        meshes.append(_mesh(f"tows[{i}].V", f"tows[{i}].F", V, F))
    if names is None:
        names = [f"tow{i}" for i in range(len(meshes))]
    names = [str(n) for n in names]
    r = _seam.textile(meshes, names, kernel=_kernel(kernel), snap_tol=_number("snap_tol", snap_tol, auto=True),
                      min_angle=_number("min_angle", min_angle, 0, 60, note="degrees"),
                      max_area=_number("max_area", max_area), bound_reach=_bound_reach(bound_reach),
                      improve=_flag("improve", improve),
                      threads=_number("threads", threads, 0, 1024, integer=True, note="0: every core"))
    return TextileResult([Tow(t["V"], t["F"], t["source_face"], t["new_face"]) for t in r["tows"]],
                         [TextilePair(p["a"], p["b"], p["curves"]) for p in r["pairs"]], _report(r["report"]))


def make_crossover(weft_along=60, weft_around=24, warp_along=50, warp_around=24, warp_section="lenticular",
                   warp_height=0.45):
    """Two generated tows crossing like a plain weave (seam::make_crossover + seam::make_tow):
    ((V_weft, F_weft), (V_warp, F_warp)).

    The weft runs along x (elliptical section 2 x 0.7, crimped, x from -5 to 5), the warp along y
    (warp_section 'elliptical' or 'lenticular', crimped the other way) lifted by warp_height, so
    they interpenetrate by 0.7 - warp_height. *_along and *_around are the segments along each
    tow and around it. The benchmark pair (bench_pair) is make_crossover(600, 64, 499, 64).
    """
    counts = [_number(name, value, 1, 1e6, integer=True) for name, value in
              (("weft_along", weft_along), ("weft_around", weft_around), ("warp_along", warp_along),
               ("warp_around", warp_around))]
    if counts[1] < 3 or counts[3] < 3:
        raise InputError("weft_around and warp_around: must be at least 3")
    if counts[0] * counts[1] > 5e7 or counts[2] * counts[3] > 5e7:
        raise InputError("make_crossover: more than 10**8 triangles in one tow")
    if warp_section not in ("elliptical", "lenticular"):
        raise InputError(f"warp_section={warp_section!r}: must be 'elliptical' or 'lenticular'")
    return _seam.make_crossover(*counts, warp_section, _number("warp_height", warp_height, -_math.inf))
