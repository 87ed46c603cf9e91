// seam internal, pipeline step 1: snap mesh vertices onto nearby curve nodes (report step 1).
//
// A k-d tree (CGAL::Kd_tree, on double coordinates) finds each vertex's nearest curve node.
// Vertices within the tolerance move, nearest first, onto that node's exact coordinates; a node
// takes at most one vertex. A move that would flip or flatten an incident face is refused: the
// test compares each face's normal before and after the move (exact under the exact kernel).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <array>
#include <vector>

namespace seam::internal {

template <class K> struct SnapReport {
  std::size_t snapped = 0;
  std::size_t refused = 0;
  double max_move = 0;
  std::vector<typename MeshTypes<K>::V> moved;  ///< in the order they moved
};

template <class K>
SnapReport<K> snap_vertices(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance);

/// Snaps mesh vertices onto the closest point of the curves' segments (not only their nodes):
/// for curves that lie on the surface, such as intersection curves, whose nodes are sparse. A
/// curve of one point (an isolated point of contact), and a closed curve smaller than `tolerance`
/// across (its first point), is a target too: the nearest vertex within `tolerance` moves onto
/// it, unless a vertex is there already.
/// `skip_on_curves`: vertices already on their closest segment stay (exact test).
/// `other`: vertices of a face that lies in one plane with a face of `other` and meets it (a
/// flat contact) stay (exact tests): moving one would tilt the face out of the contact, and the
/// part of the contact it held would be lost.
/// `near`: when given, only vertices within `tolerance` of one of these points, or corners of a
/// face within `tolerance` of one, move (in doubles).
/// `contact_tolerance` (with `other`, when > 0): a vertex moves only if every point where its
/// faces met `other` stays within that distance of where they meet it after the move (exact
/// intersections, compared in doubles): a move must not take a part of the intersection with it.
template <class K>
SnapReport<K> snap_vertices_to_segments(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance,
                                        bool round_to_doubles = false, bool skip_on_curves = false,
                                        const Mesh<K>* other = nullptr,
                                        const std::vector<std::array<double, 3>>* near = nullptr,
                                        double contact_tolerance = 0);

/// The curve points that will make a pair of vertices closer than `distance` once embedded: a
/// curve point with a vertex of `a` or `b`, or another curve point, within `distance` of it but
/// not at it (in doubles: the outputs are written in doubles). Each is returned once, in the
/// curves' order. For snap_vertices_to_segments' `near`: the features that thin are closed
/// before the embedding rather than found by verifying its outputs.
template <class K>
std::vector<std::array<double, 3>> crowded_curve_points(const std::vector<Polyline<K>>& curves, const Mesh<K>& a,
                                                        const Mesh<K>& b, double distance);

/// Would moving v to `target` keep every incident face non-degenerate, with its orientation?
/// Exact under the exact kernel.
/// Faces created or reshaped by snap_edges_to_points.
template <class K> struct EdgeSnapReport {
  std::size_t snapped = 0, refused = 0;
  double max_move = 0;
  /// For each face added by a split (index >= the face count before), the face it was cut from.
  std::vector<std::pair<typename MeshTypes<K>::F, typename MeshTypes<K>::F>> added;
  std::vector<typename MeshTypes<K>::F> reshaped;  ///< existing faces cut by a split
};

/// Snapping for points next to an edge (report step 1, carried over from vertices to edges): a
/// curve point within `tolerance` of an edge of the mesh, but farther than that from the edge's
/// end points and not on the edge, gets a vertex of its own: the edge is split at the point's
/// projection, the two faces beside it are cut in two, and the new vertex moves onto the curve
/// point (the surface moves by less than the tolerance). Splits that would flip or flatten a face
/// are refused (exact test). Each edge and each face is split at most once per call. Cuts
/// across the intersection the tiny features (a crossing next to an edge) that no
/// re-triangulation of the face can mesh well.
template <class K>
EdgeSnapReport<K> snap_edges_to_points(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance);

template <class K>
bool move_keeps_faces(const Mesh<K>& mesh, typename MeshTypes<K>::V v, const typename K::Point_3& target);

}  // namespace seam::internal
