// seam::pair: make two interpenetrating tow meshes conforming along their intersection curves.
//
// Computed curves (the default): the intersection of the two surfaces, computed exactly under the
// exact kernel (CGAL::Polygon_mesh_processing::surface_intersection), chained into one polyline
// per connected curve (closed where both surfaces are closed), duplicate points merged, each
// closed curve starting at its lexicographically smallest point. Every curve point lies on both
// surfaces, so embedding keeps all of them (they are the crossing points of one mesh or the
// other) and both meshes receive the identical curve.
//
// Snapping (report step 1), when snap_tol > 0: vertices of either mesh within snap_tol of a curve
// point move onto it (a move that would flip or flatten a face is refused), and the curves are
// computed again on the moved surfaces; crossings next to vertices become curves through vertices.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>

#include <string>
#include <vector>

namespace seam {

struct PairOptions {
  /// Options of the embedding into each mesh. snap_tol < 0: automatic, 0.1 x the smaller of the
  /// two mean edge lengths; 0 disables snapping. curve_tol and max_distance are not used with
  /// computed curves.
  EmbedOptions embed;
  /// Experimental (off by default): after embedding, coarsen the shared curves to about the
  /// edge length and remesh both meshes next to them (CGAL isotropic remeshing, curve fixed).
  /// On the generated crossovers this leaves about 1% of new faces below 10 degrees instead of
  /// 30%, but the remeshed surfaces can cross each other next to the curve: the result is then
  /// checked (seam::check_pair) and the remeshing undone if they do (PairStats::note says so).
  bool remesh_near_curves = false;
};

struct PairStats {
  std::size_t curves = 0, curve_vertices = 0, closed_curves = 0;
  std::size_t vertices_snapped_a = 0, vertices_snapped_b = 0, snaps_refused = 0;
  double snap_tol = 0;  ///< the snapping tolerance in effect (pass at least this to `seam check --tol`)
  /// True when the surfaces touch (a common point) without crossing: nothing to embed.
  bool touching_only = false;
  bool remeshed = false;  ///< the curves were coarsened and the meshes remeshed next to them
  std::string note;  ///< a sentence for the report (e.g. "the meshes do not intersect")
  std::map<std::string, double> stage_seconds;  ///< snap, intersect, embed_a, embed_b
};

template <class K> struct PairResult {
  std::vector<Polyline<K>> curves;  ///< the shared curves (closed ones repeat their first point)
  EmbedResult<K> a, b;              ///< per-mesh results (curves identical in both)
  PairStats stats;
};

/// The intersection curves of two triangle meshes, chained (see the header comment).
/// `touching_points`, when given, receives the number of isolated points where the surfaces only
/// touch (they are not curves).
template <class K>
std::vector<Polyline<K>> intersection_curves(const Mesh<K>& a, const Mesh<K>& b,
                                             std::size_t* touching_points = nullptr);

/// Makes `a` and `b` conforming along their intersection curves (modified in place).
/// \pre both are valid closed or open triangle meshes without self-intersections.
template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options = {});

}  // namespace seam
