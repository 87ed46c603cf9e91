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

namespace seam::internal {

template <class K> struct SnapReport {
  std::size_t snapped = 0;
  std::size_t refused = 0;
  double max_move = 0;
  std::vector<typename MeshTypes<K>::V> moved;  ///< in the order they moved
};

template <class K>
SnapReport<K> snap_vertices(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance);

}  // namespace seam::internal
