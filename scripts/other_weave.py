#!/usr/bin/python3
"""other_weave.py: an independent TexGen-style generator of textile unit cells (one closed
triangle mesh per tow, OFF), written to test seam on inputs it was not tuned on.

Usage: scripts/other_weave.py --cell plain|twill|orthogonal --out DIR [--seed N] [--jitter F] [...]
(see --help). Writes DIR/<tow>.off for every tow and prints the file names. Standard library only.

Geometry
- Cells: plain weave (warp i over weft j when i+j is even), 2/2 twill (warp i over weft j when
  (j-i) mod 4 < 2; 4 warps x 4 wefts by default), and a 3D orthogonal cell: straight wefts in
  --layers layers (columns y = j*s), straight stuffer warps in the layers between them, and binder
  warps halfway between the stuffer columns that run over the top weft of one column and under the
  bottom weft of the next.
- Warps run along y, wefts along x. The centre path of a tow goes through its crossover heights
  (the separation of the two tows at a crossover is the sum of their half heights less --overlap x
  their mean height, shared as --crimp : 1-crimp between warp and weft) with either a cosine
  blend (zero slope at every crossover, --path cosine) or a cubic Hermite spline with Catmull-Rom
  tangents scaled by 1-tension (--path hermite), plus an optional in-plane meander (--waviness,
  a sinusoid of period two spacings with a random phase per tow).
- Cross-sections: super-ellipse |x/a|^p + |y/b|^p = 1 (--exponent p), lenticular (two circular
  arcs meeting at sharp tips), or 'varying': a super-ellipse whose width changes along the path
  (1 + vary*sin(2 pi u/3 + phase)), whose height thins between crossovers (1 - vary/2*sin^2(pi u))
  and which turns about the tangent by twist*sin(pi u) degrees (u: path position in spacings from
  the first crossover; height and rotation are nominal at the crossovers).
- Frame: --frame rmf (default) is a rotation-minimising frame (double reflection, Wang et al. 2008)
  started from the horizontal frame at the first ring and stored as a twist angle about the
  tangent relative to the fixed-up-vector frame; --frame up is the fixed-up-vector frame (width
  axis horizontal, perpendicular to the tangent).

Meshing (deliberately not a structured grid)
- Rings (planar sections) along the path are denser at crossovers: ring positions
  v = c0 + s*(U - dense/(2 pi) sin(2 pi U)) for uniform U; tows end halfway between crossovers.
- Every other ring is turned by half a step (--no-stagger to keep them aligned); with --ring-mix,
  every third ring has two more points; each tow has its own number of points per ring
  (--around plus a seeded per-tow offset of -2, 0, +2 or +4).
- Consecutive rings are stitched by merging their angle sequences (works for any point counts).
- --jitter F moves each vertex by up to F of a step along the path and around the section, on
  the smooth surface (the surface is evaluated at the moved parameters): vertices stay in the
  surface. End rings are not moved along the path (planar caps); on a lenticular section the
  jitter fades out within two steps of the sharp tips (none there, never across them).
- Caps: a fan to the centre of the end section (--cap fan) or a zigzag strip (--cap strip;
  falls back to the fan where a strip triangle would be thinner than 2 degrees).

Every written mesh is checked here: each edge used by exactly two faces in opposite directions,
no face of (near) zero area, no two vertices at one point, Euler characteristic 2, positive
signed volume, and no two faces without a common vertex that intersect (self-intersection, a
bucketed segment/triangle test). --pairs also lists which tows intersect which (same test).
"""
import argparse
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_tows import write_off  # noqa: E402  (the OFF writer of the real-tow scripts)

TWO_PI = 2.0 * math.pi
PARAMS = []  # (ring, index, angle, path position) of each vertex of the last tow meshed (debugging)


# ---------------------------------------------------------------- small vector helpers
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def rotate_about(v, axis, angle):
    """Rodrigues: v turned by angle about the unit axis."""
    c, s = math.cos(angle), math.sin(angle)
    return add(add(mul(v, c), mul(cross(axis, v), s)), mul(axis, dot(axis, v) * (1 - c)))


# ---------------------------------------------------------------- cross-sections
def superellipse(theta, p):
    c, s = math.cos(theta), math.sin(theta)
    e = 2.0 / p
    return (math.copysign(abs(c) ** e, c), math.copysign(abs(s) ** e, s))


def lenticular(theta, aspect):
    """Unit lens (half width 1, half height 1/aspect... scaled later to 1 x 1): two circular arcs
    through (+-1, 0) and (0, +-1) of the real half-height; returns coordinates in units of the half
    width and half height."""
    # In real units the lens has half width 1 and half height h = 1/aspect (aspect = w/t).
    h = 1.0 / aspect
    r = (1.0 + h * h) / (2.0 * h)
    x = math.cos(theta)
    y = math.sqrt(max(r * r - x * x, 0.0)) - (r - h)
    if math.sin(theta) < 0:
        y = -y
    return (x, y / h)


class Section:
    def __init__(self, kind, width, height, exponent=2.5, vary=0.0, twist=0.0, phase=0.0, s=1.0, c0=0.0):
        self.kind, self.width, self.height, self.exponent = kind, width, height, exponent
        self.vary, self.twist, self.phase, self.s, self.c0 = vary, math.radians(twist), phase, s, c0

    def shape(self, theta):
        if self.kind == 'lenticular':
            return lenticular(theta, self.width / self.height)
        return superellipse(theta, self.exponent)

    def at(self, v, theta):
        """(a, b): the section point in the (width axis, height axis) frame at path position v."""
        x, y = self.shape(theta)
        w, t, psi = self.width / 2, self.height / 2, 0.0
        if self.kind == 'varying':
            u = (v - self.c0) / self.s
            w *= 1.0 + self.vary * math.sin(TWO_PI * u / 3.0 + self.phase)
            t *= 1.0 - 0.5 * self.vary * math.sin(math.pi * u) ** 2
            psi = self.twist * math.sin(math.pi * u)
        a, b = w * x, t * y
        if psi:
            c, sn = math.cos(psi), math.sin(psi)
            a, b = c * a - sn * b, sn * a + c * b
        return a, b


# ---------------------------------------------------------------- centre paths
class Path:
    """A tow centre path along axis 'x' or 'y': main coordinate v, lateral offset (meander) and
    height h(v) through crossover heights heights(k) at v = c0 + k*s (k any integer)."""

    def __init__(self, axis, offset, c0, s, heights, kind='cosine', tension=0.0, waviness=0.0, phase=0.0,
                 base=0.0):
        self.axis, self.offset, self.c0, self.s, self.heights = axis, offset, c0, s, heights
        self.kind, self.tension, self.waviness, self.phase, self.base = kind, tension, waviness, phase, base

    def _slope(self, k):
        return (1.0 - self.tension) * (self.heights(k + 1) - self.heights(k - 1)) / (2.0 * self.s)

    def height(self, v):
        """(h, dh/dv)"""
        u = (v - self.c0) / self.s
        k = math.floor(u)
        t = u - k
        h0, h1 = self.heights(k), self.heights(k + 1)
        if self.kind == 'cosine':
            f = (1 - math.cos(math.pi * t)) / 2
            df = math.pi * math.sin(math.pi * t) / 2
            return self.base + h0 + (h1 - h0) * f, (h1 - h0) * df / self.s
        m0, m1 = self._slope(k) * self.s, self._slope(k + 1) * self.s
        t2, t3 = t * t, t * t * t
        h = (2 * t3 - 3 * t2 + 1) * h0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * h1 + (t3 - t2) * m1
        dh = (6 * t2 - 6 * t) * h0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * h1 + (3 * t2 - 2 * t) * m1
        return self.base + h, dh / self.s

    def lateral(self, v):
        if not self.waviness:
            return 0.0, 0.0
        arg = math.pi * (v - self.c0) / self.s + self.phase
        return self.waviness * self.s * math.sin(arg), self.waviness * math.pi * math.cos(arg)

    def point(self, v):
        """(C(v), C'(v))"""
        h, dh = self.height(v)
        l, dl = self.lateral(v)
        if self.axis == 'y':
            return (self.offset + l, v, h), (dl, 1.0, dh)
        return (v, self.offset + l, h), (1.0, dl, dh)


UP = (0.0, 0.0, 1.0)


def up_frame(tangent):
    """(e1, e2): e1 horizontal width axis, e2 = T x e1 (roughly up), e1 x e2 = T."""
    t = unit(tangent)
    e1 = unit(cross(UP, t))
    return t, e1, cross(t, e1)


class Tow:
    def __init__(self, name, path, section, v0, v1, frame='rmf'):
        self.name, self.path, self.section, self.v0, self.v1, self.frame = name, path, section, v0, v1, frame
        self.twist_samples = None
        if frame == 'rmf':
            self._build_rmf()

    def _build_rmf(self, n=2000):
        """Twist of the rotation-minimising frame relative to the up frame at n+1 samples."""
        vs = [self.v0 + (self.v1 - self.v0) * k / n for k in range(n + 1)]
        xs, ts = [], []
        for v in vs:
            c, d = self.path.point(v)
            xs.append(c)
            ts.append(unit(d))
        r = up_frame(ts[0])[1]
        angles = [0.0]
        for k in range(n):
            v1 = sub(xs[k + 1], xs[k])
            c1 = dot(v1, v1)
            rl = sub(r, mul(v1, 2 * dot(v1, r) / c1))
            tl = sub(ts[k], mul(v1, 2 * dot(v1, ts[k]) / c1))
            v2 = sub(ts[k + 1], tl)
            c2 = dot(v2, v2)
            r = rl if c2 < 1e-30 else sub(rl, mul(v2, 2 * dot(v2, rl) / c2))
            r = unit(sub(r, mul(ts[k + 1], dot(r, ts[k + 1]))))
            _, e1, e2 = up_frame(ts[k + 1])
            a = math.atan2(dot(r, e2), dot(r, e1))
            while a - angles[-1] > math.pi:  # unwrap
                a -= TWO_PI
            while a - angles[-1] < -math.pi:
                a += TWO_PI
            angles.append(a)
        self.twist_samples = (vs, angles)

    def _twist(self, v):
        vs, angles = self.twist_samples
        n = len(vs) - 1
        x = (v - vs[0]) / (vs[-1] - vs[0]) * n
        k = min(max(int(x), 0), n - 1)
        f = x - k
        return angles[k] * (1 - f) + angles[k + 1] * f

    def frame_at(self, v):
        c, d = self.path.point(v)
        t, e1, e2 = up_frame(d)
        if self.frame == 'rmf':
            a = self._twist(v)
            if a:
                e1, e2 = rotate_about(e1, t, a), rotate_about(e2, t, a)
        return c, t, e1, e2

    def surface(self, v, theta):
        c, _, e1, e2 = self.frame_at(v)
        a, b = self.section.at(v, theta)
        return add(c, add(mul(e1, a), mul(e2, b)))


# ---------------------------------------------------------------- meshing
def ring_positions(tow, along, dense):
    """Ring positions along the path: tows run from halfway before the first crossover to halfway
    after the last; U uniform, v = c0 + s*(U - dense/(2 pi) sin(2 pi U)), denser at crossovers."""
    s, c0 = tow.path.s, tow.path.c0
    u0, u1 = (tow.v0 - c0) / s, (tow.v1 - c0) / s
    n = max(2, int(round((u1 - u0) * along)))
    out = []
    for k in range(n + 1):
        u = u0 + (u1 - u0) * k / n
        out.append(c0 + s * (u - dense / TWO_PI * math.sin(TWO_PI * u)))
    out[0], out[-1] = tow.v0, tow.v1
    return out


def mesh_tow(tow, along, around, dense, stagger=True, ring_mix=False, jitter=0.0, cap='fan', rng=None):
    del PARAMS[:]
    vs = ring_positions(tow, along, dense)
    points, rings = [], []  # rings: list of (angles, vertex ids)
    for k, v in enumerate(vs):
        n = around + (2 if ring_mix and k % 3 == 1 else 0)
        off = 0.5 if (stagger and k % 2 == 1) else 0.0
        dv = min(v - vs[k - 1] if k > 0 else 1e9, vs[k + 1] - v if k + 1 < len(vs) else 1e9)
        angles, ids = [], []
        for j in range(n):
            th = TWO_PI * (j + off) / n
            vv = v
            if jitter and rng is not None:
                scale = 1.0
                if tow.section.kind == 'lenticular':  # none at the sharp tips, never across them
                    d = min(abs(math.remainder(th, math.pi)), math.pi) / (TWO_PI / n)
                    scale = min(1.0, max(0.0, (d - 0.5) / 1.5))
                th += scale * jitter * (TWO_PI / n) * rng.uniform(-1, 1)
                if 0 < k < len(vs) - 1:
                    vv += scale * jitter * dv * rng.uniform(-1, 1)
            angles.append(th)
            ids.append(len(points))
            points.append(tow.surface(vv, th))
            PARAMS.append((k, j, th, vv))
        rings.append((angles, ids))
    faces = []
    for k in range(len(rings) - 1):
        faces += stitch(rings[k], rings[k + 1])
    for end, (angles, ids) in ((0, rings[0]), (1, rings[-1])):
        v = vs[0] if end == 0 else vs[-1]
        faces += make_cap(points, ids, tow.frame_at(v)[0], end, cap)
    return points, faces


def stitch(ra, rb):
    """Triangles between ring A (earlier) and ring B: merge their (increasing) angle sequences.
    Advancing on A gives (A_i, A_i+1, B_j), on B (A_i, B_j+1, B_j): outward when the angles
    increase about the tangent."""
    aa, ia = ra
    ab, ib = rb
    n, m = len(aa), len(ab)
    j0 = min(range(m), key=lambda j: abs(math.remainder(ab[j] - aa[0], TWO_PI)))
    shift = aa[0] + math.remainder(ab[j0] - aa[0], TWO_PI) - ab[j0]

    def alpha(i):
        return aa[i % n] + TWO_PI * (i // n)

    def beta(j):
        return ab[(j0 + j) % m] + TWO_PI * ((j0 + j) // m) + shift

    faces = []
    i = j = 0
    while i < n or j < m:
        if j >= m or (i < n and alpha(i + 1) <= beta(j + 1)):
            faces.append((ia[i % n], ia[(i + 1) % n], ib[(j0 + j) % m]))
            i += 1
        else:
            faces.append((ia[i % n], ib[(j0 + j + 1) % m], ib[(j0 + j) % m]))
            j += 1
    return faces


def min_angle_deg(p, q, r):
    best = 180.0
    for a, b, c in ((p, q, r), (q, r, p), (r, p, q)):
        u, w = sub(b, a), sub(c, a)
        nu, nw = norm(u), norm(w)
        if nu == 0 or nw == 0:
            return 0.0
        best = min(best, math.degrees(math.acos(max(-1.0, min(1.0, dot(u, w) / (nu * nw))))))
    return best


def make_cap(points, ids, centre, end, cap):
    """Cap of a planar end ring; end 0 faces backwards (reversed order)."""
    n = len(ids)
    tris = []
    if cap == 'strip':
        lo, hi = 0, n - 1
        while hi - lo >= 2:
            tris.append((ids[lo], ids[lo + 1], ids[hi]))
            lo += 1
            if hi - lo >= 2:
                tris.append((ids[lo], ids[hi - 1], ids[hi]))
                hi -= 1
        if any(min_angle_deg(points[a], points[b], points[c]) < 2.0 for a, b, c in tris):
            tris = []
    if not tris:
        c = len(points)
        points.append(centre)
        tris = [(c, ids[j], ids[(j + 1) % n]) for j in range(n)]
    if end == 0:
        tris = [(a, c, b) for a, b, c in tris]
    return tris


# ---------------------------------------------------------------- checks
def seg_tri(p, q, a, b, c, eps=1e-14):
    """Does the segment pq cross triangle abc (proper crossing, float test)?"""
    def vol(x, y, z, w):
        return dot(sub(y, x), cross(sub(z, x), sub(w, x)))
    d1, d2 = vol(a, b, c, p), vol(a, b, c, q)
    if (d1 > eps and d2 > eps) or (d1 < -eps and d2 < -eps) or (abs(d1) <= eps and abs(d2) <= eps):
        return False
    s1, s2, s3 = vol(p, q, a, b), vol(p, q, b, c), vol(p, q, c, a)
    return (s1 > 0 and s2 > 0 and s3 > 0) or (s1 < 0 and s2 < 0 and s3 < 0)


def tri_tri(t, u):
    for k in range(3):
        if seg_tri(t[k], t[(k + 1) % 3], *u) or seg_tri(u[k], u[(k + 1) % 3], *t):
            return True
    return False


def buckets(points, faces, cell):
    grid = {}
    for fi, f in enumerate(faces):
        lo = [min(points[i][d] for i in f) for d in range(3)]
        hi = [max(points[i][d] for i in f) for d in range(3)]
        for x in range(int(math.floor(lo[0] / cell)), int(math.floor(hi[0] / cell)) + 1):
            for y in range(int(math.floor(lo[1] / cell)), int(math.floor(hi[1] / cell)) + 1):
                for z in range(int(math.floor(lo[2] / cell)), int(math.floor(hi[2] / cell)) + 1):
                    grid.setdefault((x, y, z), []).append(fi)
    return grid


def mean_edge(points, faces):
    tot = 0.0
    for f in faces:
        tot += norm(sub(points[f[0]], points[f[1]]))
    return tot / max(len(faces), 1)


def self_intersections(points, faces, limit=5):
    cell = 2.0 * mean_edge(points, faces)
    grid = buckets(points, faces, cell)
    found, seen = [], set()
    for ids in grid.values():
        for x in range(len(ids)):
            for y in range(x + 1, len(ids)):
                a, b = ids[x], ids[y]
                if (a, b) in seen:
                    continue
                seen.add((a, b))
                if set(faces[a]) & set(faces[b]):
                    continue
                if tri_tri([points[i] for i in faces[a]], [points[i] for i in faces[b]]):
                    found.append((a, b))
                    if len(found) >= limit:
                        return found
    return found


def validate(points, faces, check_self=True):
    """A list of problems (empty when the mesh is a closed, oriented, sphere-like surface)."""
    problems = []
    directed = {}
    for f in faces:
        if len(set(f)) != 3:
            problems.append('face with repeated vertex %s' % (f,))
        for k in range(3):
            e = (f[k], f[(k + 1) % 3])
            directed[e] = directed.get(e, 0) + 1
    for (a, b), n in directed.items():
        if n != 1:
            problems.append('directed edge %d-%d used %d times' % (a, b, n))
        elif directed.get((b, a), 0) != 1:
            problems.append('edge %d-%d has no opposite' % (a, b))
        if len(problems) > 10:
            break
    edges = len(directed) // 2
    used = set(i for f in faces for i in f)
    if len(used) != len(points):
        problems.append('%d unused vertices' % (len(points) - len(used)))
    chi = len(points) - edges + len(faces)
    if chi != 2:
        problems.append('Euler characteristic %d' % chi)
    if len(set(points)) != len(points):
        problems.append('%d vertices at one point' % (len(points) - len(set(points))))
    lo = [min(p[d] for p in points) for d in range(3)]
    hi = [max(p[d] for p in points) for d in range(3)]
    diag = norm(sub(tuple(hi), tuple(lo)))
    vol, small, worst = 0.0, 0, 180.0
    for f in faces:
        a, b, c = (points[i] for i in f)
        n = cross(sub(b, a), sub(c, a))
        if norm(n) / 2 <= 1e-12 * diag * diag:
            small += 1
        worst = min(worst, min_angle_deg(a, b, c))
        vol += dot(a, n) / 6.0
    if small:
        problems.append('%d faces of (near) zero area' % small)
    if vol <= 0:
        problems.append('signed volume %.6g is not positive' % vol)
    if check_self:
        si = self_intersections(points, faces)
        if si:
            problems.append('self-intersecting faces %s' % si)
    return problems, {'vertices': len(points), 'faces': len(faces), 'volume': vol, 'min_angle': worst}


def intersecting_pairs(meshes):
    """Names of tow pairs whose faces cross (bounding boxes, then buckets, then the float test)."""
    out = []
    boxes = {}
    for name, (p, f) in meshes.items():
        boxes[name] = ([min(q[d] for q in p) for d in range(3)], [max(q[d] for q in p) for d in range(3)])
    names = list(meshes)
    for x in range(len(names)):
        for y in range(x + 1, len(names)):
            a, b = names[x], names[y]
            (la, ha), (lb, hb) = boxes[a], boxes[b]
            if any(ha[d] < lb[d] or hb[d] < la[d] for d in range(3)):
                continue
            pa, fa = meshes[a]
            pb, fb = meshes[b]
            cell = 2.0 * max(mean_edge(pa, fa), mean_edge(pb, fb))
            ga, gb = buckets(pa, fa, cell), buckets(pb, fb, cell)
            hit, tried = 0, set()
            for key, ia in ga.items():
                for j in gb.get(key, ()):
                    for i in ia:
                        if (i, j) in tried:
                            continue
                        tried.add((i, j))
                        if tri_tri([pa[k] for k in fa[i]], [pb[k] for k in fb[j]]):
                            hit += 1
            if hit:
                out.append((a, b, hit))
    return out


# ---------------------------------------------------------------- cells
def build_cell(a, rng):
    s = a.spacing
    sw = a.spacing_weft or s  # spacing of the wefts (along y)
    tows = []

    def section(width, height, kind=None, k=0):
        kind = kind or a.section
        return Section(kind, width, height, a.exponent, a.vary, a.twist * (1 if k % 2 == 0 else -1),
                       rng.uniform(0, TWO_PI), 1.0, 0.0)

    def phase():
        return rng.uniform(0, TWO_PI)

    ww, tw = a.width * s, a.height * s  # warp width, height
    wf, tf = (a.width_weft or a.width) * sw, (a.height_weft or a.height) * s
    if a.cell in ('plain', 'twill'):
        nx, ny = a.repeat or ((2, 2) if a.cell == 'plain' else (4, 4))
        sep = (tw + tf) / 2 * (1 - a.overlap)
        aw, af = a.crimp * sep, (1 - a.crimp) * sep

        def over(i, j):  # warp i over weft j
            if a.cell == 'plain':
                return (i + j) % 2 == 0
            return (j - i) % 4 < 2

        for i in range(nx):
            path = Path('y', i * s, 0.0, sw, (lambda k, i=i: aw if over(i, k) else -aw), a.path, a.tension,
                        a.waviness, phase())
            sec = section(ww, tw, k=i)
            sec.s, sec.c0 = sw, 0.0
            tows.append(Tow('warp%d' % i, path, sec, -sw / 2, (ny - 0.5) * sw, a.frame))
        for j in range(ny):
            path = Path('x', j * sw, 0.0, s, (lambda k, j=j: -af if over(k, j) else af), a.path, a.tension,
                        a.waviness, phase())
            sec = section(wf, tf, k=j + 1)
            sec.s, sec.c0 = s, 0.0
            tows.append(Tow('weft%d' % j, path, sec, -s / 2, (nx - 0.5) * s, a.frame))
    else:  # orthogonal
        nx, ny = a.repeat or (2, 2)
        L = a.layers
        wb, tb = a.binder_width * s, a.binder_height * s
        d = (tw + tf) / 2 * (1 - a.overlap)  # weft layer to stuffer layer
        db = (tf + tb) / 2 * (1 - a.overlap)  # top/bottom weft to binder
        top, bottom = 2 * (L - 1) * d, 0.0
        for lay in range(L):  # wefts: straight, along x
            for j in range(ny):
                path = Path('x', j * sw, 0.0, s, lambda k: 0.0, a.path, 0.0, a.waviness, phase(), base=2 * lay * d)
                sec = section(wf, tf, k=j)
                sec.s, sec.c0 = s, 0.0
                tows.append(Tow('weft_l%d_%d' % (lay, j), path, sec, -s / 2, (nx - 0.5) * s, a.frame))
        for lay in range(L - 1):  # stuffer warps: straight, along y
            for i in range(nx):
                path = Path('y', i * s, 0.0, sw, lambda k: 0.0, a.path, 0.0, a.waviness, phase(),
                            base=(2 * lay + 1) * d)
                sec = section(ww, tw, k=i)
                sec.s, sec.c0 = sw, 0.0
                tows.append(Tow('stuffer_l%d_%d' % (lay, i), path, sec, -sw / 2, (ny - 0.5) * sw, a.frame))
        mid, amp = (top + bottom) / 2, (top - bottom) / 2 + db
        for i in range(nx - 1):  # binders between the stuffer columns
            path = Path('y', (i + 0.5) * s, 0.0, sw, (lambda k, i=i: amp if (k + i) % 2 == 0 else -amp), a.path,
                        a.tension, 0.0, 0.0, base=mid)
            sec = section(wb, tb, kind='lenticular' if a.section == 'lenticular' else 'superellipse', k=i)
            sec.s, sec.c0 = sw, 0.0
            tows.append(Tow('binder%d' % i, path, sec, -sw / 2, (ny - 0.5) * sw, a.frame))
    return tows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--cell', choices=['plain', 'twill', 'orthogonal'], required=True)
    ap.add_argument('--out', required=True, help='output directory')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--repeat', type=int, nargs=2, metavar=('NWARP', 'NWEFT'),
                    help='warps and wefts (columns) in the cell (default 2 2; twill 4 4)')
    ap.add_argument('--spacing', type=float, default=1.0, help='warp spacing s (along x)')
    ap.add_argument('--spacing-weft', type=float, default=0.0, help='weft spacing (along y; default s)')
    ap.add_argument('--width', type=float, default=0.6, help='tow width / spacing')
    ap.add_argument('--height', type=float, default=0.16, help='tow height / s')
    ap.add_argument('--width-weft', type=float, default=0.0, help='weft width / weft spacing (default --width)')
    ap.add_argument('--height-weft', type=float, default=0.0, help='weft height / s (default --height)')
    ap.add_argument('--overlap', type=float, default=0.04,
                    help='interpenetration at a crossover, as a fraction of the mean tow height')
    ap.add_argument('--crimp', type=float, default=0.5, help="warp's share of the undulation (0..1)")
    ap.add_argument('--waviness', type=float, default=0.0, help='in-plane meander amplitude / s')
    ap.add_argument('--path', choices=['cosine', 'hermite'], default='cosine')
    ap.add_argument('--tension', type=float, default=0.0, help='Hermite: tangents scaled by 1 - tension')
    ap.add_argument('--section', choices=['superellipse', 'lenticular', 'varying'], default='superellipse')
    ap.add_argument('--exponent', type=float, default=2.5, help='super-ellipse exponent (>= 1.5)')
    ap.add_argument('--vary', type=float, default=0.12, help='varying section: relative size change')
    ap.add_argument('--twist', type=float, default=4.0, help='varying section: rotation amplitude (deg)')
    ap.add_argument('--frame', choices=['rmf', 'up'], default='rmf')
    ap.add_argument('--along', type=int, default=10, help='rings per spacing')
    ap.add_argument('--around', type=int, default=18, help='points per ring (plus a per-tow offset)')
    ap.add_argument('--same-around', action='store_true', help='no per-tow offset of --around')
    ap.add_argument('--dense', type=float, default=0.5, help='ring densification at crossovers (0..0.8)')
    ap.add_argument('--no-stagger', action='store_true')
    ap.add_argument('--ring-mix', action='store_true', help='every third ring has two more points')
    ap.add_argument('--jitter', type=float, default=0.0, help='in-surface vertex jitter, fraction of a step (<0.4)')
    ap.add_argument('--cap', choices=['fan', 'strip'], default='fan')
    ap.add_argument('--layers', type=int, default=3, help='orthogonal: weft layers')
    ap.add_argument('--binder-width', type=float, default=0.3, help='orthogonal: binder width / s')
    ap.add_argument('--binder-height', type=float, default=0.12, help='orthogonal: binder height / s')
    ap.add_argument('--pairs', action='store_true', help='also list the intersecting tow pairs (slow)')
    ap.add_argument('--no-self-check', action='store_true', help='skip the self-intersection check')
    a = ap.parse_args(argv)
    if not 0 <= a.jitter < 0.4:
        ap.error('--jitter must be in [0, 0.4)')
    rng = random.Random(a.seed)
    os.makedirs(a.out, exist_ok=True)
    tows = build_cell(a, rng)
    meshes, bad = {}, 0
    for tow in tows:
        around = a.around + (0 if a.same_around else rng.choice([-2, 0, 2, 4]))
        points, faces = mesh_tow(tow, a.along, max(around, 6), a.dense, not a.no_stagger, a.ring_mix,
                                 a.jitter, a.cap, rng)
        problems, info = validate(points, faces, not a.no_self_check)
        path = os.path.join(a.out, tow.name + '.off')
        write_off(path, points, faces)
        meshes[tow.name] = (points, faces)
        if problems:
            bad += 1
            print('%s: INVALID: %s' % (path, '; '.join(problems)), file=sys.stderr)
        print('%s  (%d vertices, %d faces, volume %.5g, min angle %.1f deg)' % (
            path, info['vertices'], info['faces'], info['volume'], info['min_angle']))
    if a.pairs:
        for x, y, n in intersecting_pairs(meshes):
            print('# intersecting: %s %s (%d face pairs)' % (x, y, n))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
