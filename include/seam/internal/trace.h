// seam internal, pipeline steps 2-3: locate curve nodes on the mesh and follow the curve across
// it, constructing the crossing points on the mesh edges.
//
// Locate: each node is projected onto the closest face (AABB tree on double coordinates finds
// the face; the projection onto that face's triangle is then constructed in the kernel), and
// classified as lying at a vertex, inside an edge or inside a face (exact under Epeck).
//
// Cross: between two consecutive located nodes P and Q the curve follows the section of the mesh
// by the plane through P and Q (rounded to double, unless they are mesh vertices) that contains
// the local surface normal n. The plane only guides the walk: consecutive points always share a
// face, and every crossing is the exact intersection of its edge with the plane; rounding P and
// Q keeps the plane's coefficients, and so the exact crossing points, small. The walk goes from
// face to face; each step exits the current face where the plane meets its boundary: at a
// vertex (the vertex lies on the plane: exact orientation test) or inside an edge (its end points
// lie strictly on opposite sides), and that crossing point is constructed as the exact
// intersection of the edge with the plane. It stops in the first face that contains Q. Paths
// through vertices, along edges and through saddles need no tolerance: at each point the walk
// takes, among the plane's exits from the incident faces not yet used, the one heading most
// directly towards Q. If the walk fails (mesh boundary, a face lying in the plane) it is retried
// with the normal of Q's face and with the sum of both normals; then InternalError.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

namespace seam::internal {

struct TraceReport {
  double locate_seconds = 0, cross_seconds = 0;
  std::size_t retries = 0;  ///< segments that needed a second cutting plane
  /// Nodes on the surface (nodes_on_surface, exact kernel) found on a face by exact predicates on
  /// the node, without a projection (the others: projected).
  std::size_t located_by_predicates = 0;
};

/// Follows each curve on the mesh. Throws InvalidInput when a node is farther than
/// max_distance from the surface or a curve has no length on the surface.
/// With `nodes_on_surface` (curves that lie on the mesh, such as computed intersection curves) a
/// located node that is not at a mesh vertex keeps the node's own coordinates: under the exact
/// kernel they are its projection anyway, and under rounded kernels the same node then gets the
/// same coordinates in every mesh it is embedded into.
/// `feature_tol` > 0: a node whose projection lies within that relative (barycentric) distance of
/// an edge or vertex of its face is put on it (given curves, rounded to doubles); rounded kernels
/// always use at least 1e-9.
/// `known`: nodes found there are taken as located there (distance 0), without a search; the
/// search tree is built only if some node is not.
/// `defer_projections` (exact constructions, nodes off the surface, no `known`): face points
/// keep their input node instead of its projection (TracedCurve::face_points_deferred). Under
/// Epeck a projection is a lazy expression of about 100 bytes, and most face points are dropped
/// by coarsening: a curve of 10 million nodes needed 1 GB for them.
template <class K>
std::vector<TracedCurve<K>> trace_curves(const Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                                         double max_distance, TraceReport& report, bool nodes_on_surface = false,
                                         double feature_tol = 0, const KnownSites<K>* known = nullptr,
                                         bool defer_projections = false);

/// Point i of a traced curve where it lies on the mesh: with `face_points_deferred`, a face point
/// holds its input node, and its location (the node's exact projection onto the face, the same
/// value locating it computed) is constructed here.
template <class K>
SurfacePoint<K> traced_location(const Mesh<K>& mesh, const TracedCurve<K>& tc, std::size_t i);

}  // namespace seam::internal
