// seam internal: the intersection curves of two triangle meshes in general position with respect
// to each other, computed directly (pair step "curves", fast path). See
// src/general_position_curves.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <optional>
#include <vector>

namespace seam::internal {

/// The intersection curves of `a` and `b` when the two meshes are in general position with
/// respect to each other: no vertex of one lies in the plane of a face of the other that it may
/// touch (their bounding boxes meet, and neither face is strictly on one side of the other's
/// plane), and no edge of one meets an edge (or the line of an edge) of the other where that
/// could be a contact. A zero predicate that proves a miss is allowed; any other is not. Then two faces meet in a segment or not at all, each end of it is where an edge of
/// one face crosses the inside of the other face, and the curves are chains of such segments,
/// every point identified by its (edge, face) pair instead of by comparing coordinates.
///
/// Exact decisions (orientation predicates of the kernel); the points are constructed once per
/// (edge, face) pair, exact under the exact kernel, rounded under Epick. Returns the chained
/// polylines (closed ones repeating their first point; unsorted), each running along n_A x n_B
/// (the normals of the two faces its first segment lies in, exact sign), or nothing as
/// soon as a predicate is zero or the pieces do not chain into simple curves: then the caller
/// takes the general path (CGAL's surface_intersection), which handles every degenerate contact.
/// The face pairs are tested on all cores (oneTBB), the result does not depend on their number.
template <class K> struct GeneralPositionCurves {
  std::vector<std::vector<typename K::Point_3>> curves;
  /// Under exact constructions, where each curve point lies in A and in B: inside the edge it
  /// was constructed on, inside the face it crosses. (Empty otherwise: a rounded point is not
  /// exactly on its edge.)
  KnownSites<K> sites_a, sites_b;
};

template <class K>
std::optional<GeneralPositionCurves<K>> general_position_curves(const Mesh<K>& a, const Mesh<K>& b);

}  // namespace seam::internal
