// seam internal, pipeline step 4: coarsen the traced curve (report: "Using interpenetration
// points to coarsen and embed boundary curve").
//
// Kept: every point on a mesh edge or vertex (crossing points, snapped vertices), the end points
// of open curves, and, with curve_tol > 0, interior nodes whose removal would move the curve by
// more than curve_tol (Douglas-Peucker inside each face). Dropped: the other nodes between two
// kept points, which all lie inside one face. Two cases keep a node regardless, so that the
// embedded curve stays a simple path through the face: a run whose two kept ends lie on one
// edge of the face (the curve leaves and re-enters through the same edge) keeps its node
// farthest from that edge; a closed curve that never meets an edge keeps three nodes.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <map>

namespace seam::internal {

/// The distinct locations of the kept curve points, shared by all curves.
template <class K> struct CurvePoints {
  std::vector<SurfacePoint<K>> points;
  /// Returns the id of sp, adding it if new. Identity: same vertex; same edge or face and the
  /// same point (compared exactly).
  std::size_t id(const SurfacePoint<K>& sp);

 private:
  struct Less {
    bool operator()(const SurfacePoint<K>& a, const SurfacePoint<K>& b) const;
  };
  std::map<SurfacePoint<K>, std::size_t, Less> index_;
};

/// An embedded (coarsened) curve: ids into CurvePoints; segment i joins ids[i] and ids[i+1]
/// (and, when closed, the last joins the first). segment_face[i] is the face whose interior the
/// segment crosses, or null_face() when the segment runs along a mesh edge.
template <class K> struct CoarseCurve {
  std::vector<std::size_t> ids;
  std::vector<typename MeshTypes<K>::F> segment_face;
  /// For each entry of ids, the index of that point in the traced curve (increasing): segment i
  /// replaces the traced points from traced_index[i] to traced_index[i+1].
  std::vector<std::size_t> traced_index;
  bool closed = false;
};

template <class K> struct CoarsenOutput {
  CurvePoints<K> points;
  std::vector<CoarseCurve<K>> curves;
};

template <class K>
CoarsenOutput<K> coarsen_curves(const Mesh<K>& mesh, const std::vector<TracedCurve<K>>& traced, double curve_tol,
                                bool keep_all_nodes = false);

/// True when two locations in the closed face f lie on a common edge of f.
template <class K>
bool on_common_edge(const Mesh<K>& mesh, typename MeshTypes<K>::F f, const SurfacePoint<K>& a,
                    const SurfacePoint<K>& b);

}  // namespace seam::internal
