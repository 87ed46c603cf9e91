// seam internal: the steps on thin faces that the remeshing next to the shared curves of a pair
// leaves (pair step, with snapping on, after seam/internal/improve.h's). See src/thin_faces.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/improve.h>

namespace seam::internal {

/// Removes thin new faces (remeshed, or new faces of the embedding; smallest angle below
/// `thin_deg`) by collapsing one of their edges that is not a curve edge: one end is merged into
/// the other, which keeps its exact point (no vertex moves). Of the six merges (three edges, two
/// directions) the one that raises the smallest angle of the faces around the removed vertex most,
/// by more than a degree, is made, if the removed end is not a curve vertex nor on a border and the
/// merge keeps the mesh a 2-manifold (link condition), leaves no face flat or turned over (exact
/// under the exact kernel), turns no face by 30 degrees or more and keeps each changed face's
/// centroid and new edges' middles within `tol` of `surface` (doubles). Faces of the input may
/// change too. Changed faces are marked new and remeshed, but for a merge over an edge no longer
/// than `tol` (a snap), after which a face of the input keeps its source. Where no such merge
/// passes, both ends of an edge (neither a curve vertex nor on a border; the link condition holds)
/// may be merged at a point between them (the closest point of `surface` to p + t (q - p), t in
/// eighths), under the same tests for the faces of both ends; the faces of an end moved by more
/// than `tol` are marked remeshed. A cap (largest angle 120 degrees or more) that neither helps has
/// its apex moved onto its long edge (not a curve edge): the edge is split at the apex's closest
/// point (exactly on it under the exact kernel), the face across is split in its plane (keeping its
/// source), and the apex is merged into the new vertex, under the same geometric tests; faces of
/// the input change only if the apex moves by `tol` at most (they keep their source). Up to
/// `rounds` passes. The mesh is compacted afterwards; `curve_vertices` follow. Returns the number
/// of merges.
template <class K>
std::size_t collapse_short_edges_of_thin_faces(Mesh<K>& mesh,
                                               std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                               const SurfaceDistance& surface, double tol, double thin_deg, int rounds);

/// Thin new faces (smallest angle below `thin_deg`) that no merge, flip or move removed: an edge
/// at the smallest angle (not a curve edge, not on a border) is split at its middle (exact under
/// the exact kernel; within `tol` of `surface`), the two faces on it split in their planes
/// (keeping their source, marked new), and flip_to_improve_angles runs. Kept only if the new
/// faces below `thin_deg` are then fewer and the smallest angle of the new faces did not fall;
/// else the mesh is restored. (A needle in a strip of the input between a sharp edge and the
/// next row of vertices, its small angle at a curve vertex on the edge: the sharp edge's middle
/// lets a flip make two faces of twice the angle.) At most 256 splits are tried (each copies the
/// mesh and runs the flips over it). Returns the number of splits kept.
template <class K>
std::size_t split_edges_of_thin_faces(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                      const SurfaceDistance& surface, double tol, double thin_deg);

/// Caps standing on a curve segment, which no step on one mesh removes: thin new faces of `a` or
/// `b` (smallest angle below `thin_deg`) whose largest angle, 120 degrees or more, is opposite a
/// curve segment and at a vertex x that is neither a curve vertex nor on a border. The segment is
/// split in both meshes at the point m closest to x (its parameter rounded to a multiple of 2^-16
/// and in (0.1, 0.9): m is exactly on the segment under the exact kernel, the same point in both
/// meshes), the faces on it split in their planes (keeping their source), and x is merged into m.
/// Under the tests of collapse_short_edges_of_thin_faces' move of a cap's apex (no face around x
/// flat, turned over or turned by 30 degrees or more; centroids and moved edges' middles within
/// `tol` of the mesh's input `surface_a` or `surface_b`; faces of the input change only when x
/// moves by `tol` at most), and the smallest angle of the changed faces of both meshes must rise
/// by more than a degree. The new curve vertex is inserted in `curve_vertices_a` and
/// `curve_vertices_b`; both meshes are compacted. Returns the number of splits.
template <class K>
std::size_t split_curve_segments_under_caps(Mesh<K>& a, Mesh<K>& b,
                                            std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices_a,
                                            std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices_b,
                                            const SurfaceDistance& surface_a, const SurfaceDistance& surface_b,
                                            double tol, double thin_deg);

/// Moves the vertices of thin new faces (smallest angle below `thin_deg`; not curve vertices, not
/// on a border) to raise the smallest angle of their faces by more than a degree: a pattern search
/// in the tangent plane (16 directions, halving steps, doubles), the point found moved onto
/// `surface` (closest point) and, should it fail the tests, brought back towards the start. The
/// tests are the merges' (no face flat or turned over, an exact test under the exact kernel; none
/// turned by 30 degrees or more; centroids and spokes' middles within `tol` of `surface`). A
/// vertex of a face of the input that no step changed yet moves by `tol` at most, as snapping
/// would move it: that face keeps its input face and is marked new (a later move of one of its
/// vertices reshapes it as a new face). Every other face a move reshapes is marked remeshed.
/// Up to `rounds` passes. Returns the number of moves.
template <class K>
std::size_t relocate_vertices_of_thin_faces(Mesh<K>& mesh,
                                            const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                            const SurfaceDistance& surface, double tol, double thin_deg, int rounds);

}  // namespace seam::internal
