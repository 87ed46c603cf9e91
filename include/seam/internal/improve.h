// seam internal: improve the triangles next to the shared curves of a pair (pair step, with
// snapping on). See src/improve.cpp; the steps on thin faces that follow are in
// seam/internal/thin_faces.h.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <memory>

namespace seam::internal {

/// Chooses which curve points to keep so that consecutive kept points are between about 0.5 and
/// 1.2 `spacing` apart along the curve (every point is kept where the curve is shorter). Returns,
/// per curve, the indices of the kept points (for a closed curve, without the closing repeat).
/// A point is also kept where skipping it would leave a curve point farther than
/// `max_chord_deviation` (> 0) from the chord.
template <class K>
std::vector<std::vector<std::size_t>> choose_curve_points(const std::vector<Polyline<K>>& curves, double spacing,
                                                          double max_chord_deviation);

/// In `mesh`, whose curve vertices are `curve_vertices` (as embedded, closed curves repeating
/// their first vertex), removes the curve vertices not in `kept` by collapsing them onto kept
/// neighbours along the curve, then remeshes the faces with a vertex within one ring of a curve
/// vertex with CGAL's isotropic remeshing (target `target_edge_length`, on double coordinates;
/// curve vertices fixed; curve edges, sharp edges of the surface (faces more than 60 degrees
/// apart, where the collapses onto kept curve vertices left them alone) and the border of the
/// remeshed band neither split, collapsed nor flipped). Faces that are tiny or flat once rounded
/// to doubles stay out of the band, with the faces around them. Kept curve vertices keep their
/// exact coordinates, so two meshes treated with the same `kept` share the coarser curve
/// exactly; vertices that did not move keep theirs.
/// Faces that changed get source_face_property = UINT32_MAX ("remeshed") and new_face_property.
/// Returns false (mesh unchanged) when it fails; `refused` then lists, per curve, the positions
/// that could not be dropped (a collapse would make the surface non-manifold): keep those too and
/// call again, for both meshes. On success `curve_vertices` holds the new curve vertices.
/// `frozen` (per curve, per position; may be empty) marks stretches of the curves left alone:
/// their positions must be in `kept`, and no face with a vertex within one ring of a frozen curve
/// vertex is remeshed (the caller freezes where earlier attempts failed). Where the value is 2,
/// those faces are marked with internal::frozen_face_property too (no later step changes them).
template <class K>
bool coarsen_and_remesh_near_curves(Mesh<K>& mesh, std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const std::vector<std::vector<std::size_t>>& kept,
                                    const std::vector<std::vector<char>>& frozen, double target_edge_length,
                                    std::vector<std::vector<std::size_t>>& refused);

/// Distances from points to an input surface: an AABB tree on its faces, double coordinates
/// (rounded), built once.
class SurfaceDistance {
 public:
  explicit SurfaceDistance(std::vector<Filtered::Triangle_3> triangles);
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;
  double distance(const Filtered::Point_3& p) const;
  Filtered::Point_3 closest_point(const Filtered::Point_3& p) const;
  /// The largest distance of the triangle's corners, edge middles and centroid (a sampled bound,
  /// not a Hausdorff distance).
  double sampled_distance(const Filtered::Point_3& p, const Filtered::Point_3& q, const Filtered::Point_3& r) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

/// The faces of `mesh` as triangles in double coordinates (rounded).
template <class K> std::vector<Filtered::Triangle_3> triangles_of(const Mesh<K>& mesh);

/// The remeshed faces of `mesh` (those coarsen_and_remesh_near_curves gives no single source
/// face) that stray farther than `tol` from `surface`: a corner, edge midpoint or the centroid
/// is farther than `tol` from it (a sampled bound, not a Hausdorff distance). `max_distance`
/// receives the largest sampled distance.
template <class K>
std::vector<std::size_t> remeshed_faces_off_surface(const Mesh<K>& mesh, const SurfaceDistance& surface, double tol,
                                                    double& max_distance);

/// Splits, at their middle moved onto `surface` (closest point), the edges of remeshed faces that
/// stray farther than `tol` from it (in each such face the edge whose middle is farthest, or its
/// longest edge when only the centroid is too far), for up to `rounds` rounds. Curve edges
/// (consecutive `curve_vertices`) are never split. The faces of a split edge are marked
/// remeshed. Splitting an edge of a well-shaped triangle at most halves its angles, and the
/// distance from the surface falls about fourfold. Returns the number of splits.
template <class K>
std::size_t split_edges_off_surface(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const SurfaceDistance& surface, double tol, int rounds);

/// Flips edges between two new faces (remeshed, or new faces of the embedding) where that raises
/// the smaller of their smallest angles by more than a degree, the new faces turn by less than 30
/// degrees from the old ones (a wide cap, its largest angle 150 degrees or more, is not
/// compared, its normal says little, unless its long edge is sharp: faces more than 60 degrees
/// apart) and the new edge's middle lies within `tol` of `surface` (doubles);
/// curve edges are never flipped. Two new faces of one input face keep it as their source (the
/// flip stays in its plane); other flipped faces are marked remeshed.
/// Up to `rounds` passes over the edges. Returns the number of flips.
template <class K>
std::size_t flip_to_improve_angles(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                   const SurfaceDistance& surface, double tol, int rounds);

/// Moves vertices all of whose faces are remeshed (not curve vertices, not the band's border) to
/// the closest point of `surface` to the centroid of their neighbours, where that raises the
/// smallest angle of their faces by more than a degree, the faces turn by less than 30 degrees
/// and their centroids and spokes' middles stay within `tol` of `surface`. Up to `rounds`
/// passes. Returns the number of moves.
template <class K>
std::size_t smooth_remeshed_vertices(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                     const SurfaceDistance& surface, double tol, int rounds);

}  // namespace seam::internal
