#!/usr/bin/env python3
"""Two crossing tows built with NumPy, made conforming by seam, written as one ParaView file.

    PYTHONPATH=build/python python3 examples/python_pair.py [out.vtu]

The weft runs along x, the warp along y; both are elliptical tubes (semi-axes 1 x 0.35) on a
crimped path, closed by fan caps, and the warp is lifted by 0.45 so that the two interpenetrate
by 0.25 where they cross. seam.pair computes their intersection curves exactly and embeds them
into both; seam.check verifies the result independently; seam.io writes both outputs and the
curves into one .vtu (cell data tow, source_face, new) for ParaView.
"""
import sys

import numpy as np

import seam
import seam.io


def tube(along=80, around=24, length=10.0, half_width=1.0, half_height=0.35, crimp=0.3):
    """A closed, outward-oriented tube along x from -length/2 to length/2: (V, F)."""
    s = np.linspace(-length / 2, length / 2, along + 1)
    phi = 2 * np.pi * np.arange(around) / around
    x = np.repeat(s, around)
    y = np.tile(half_width * np.cos(phi), along + 1)
    z = np.tile(half_height * np.sin(phi), along + 1) + np.repeat(crimp * np.sin(2 * np.pi * (s + length / 2) / length), around)
    V = np.column_stack([x, y, z])
    ring = lambda i, j: i * around + j % around  # noqa: E731
    i, j = np.meshgrid(np.arange(along), np.arange(around), indexing="ij")
    i, j = i.ravel(), j.ravel()
    sides = np.concatenate([np.column_stack([ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)]),
                            np.column_stack([ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)])])
    start, end = len(V), len(V) + 1  # the caps' centres
    V = np.vstack([V, [s[0], 0, 0], [s[-1], 0, crimp * np.sin(2 * np.pi)]])
    k = np.arange(around)
    caps = np.concatenate([np.column_stack([np.full(around, start), ring(0, k + 1), ring(0, k)]),
                           np.column_stack([np.full(around, end), ring(along, k), ring(along, k + 1)])])
    return V, np.vstack([sides, caps])


def main(out="python_pair.vtu"):
    weft = tube()
    V, F = tube(crimp=-0.3)
    warp = (np.column_stack([-V[:, 1], V[:, 0], V[:, 2] + 0.45]), F)  # turned 90 degrees about z, lifted

    r = seam.pair(*weft, *warp)
    verdict = seam.check(weft, warp, r.a, r.b, r.curves, tol=r.report["verify_tolerance"])
    print(f"{len(r.curves)} curve(s), {sum(len(c) for c in r.curves)} points shared by both; "
          f"A: {len(weft[1])} -> {len(r.FA)} faces ({r.new_face_a.sum()} new), "
          f"B: {len(warp[1])} -> {len(r.FB)} faces ({r.new_face_b.sum()} new); "
          f"seam check: {'OK' if verdict else 'FAILED: ' + '; '.join(verdict.problems)}")
    seam.io.pair_to_meshio(r).write(out)
    print("wrote", out)
    return 0 if verdict else 1


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
