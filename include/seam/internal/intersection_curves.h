// seam internal: the intersection curves of two triangle meshes (pair stage 1, "intersect"): the
// exact common points, classified, chained and oriented as include/seam/pair.h describes. See
// src/intersection_curves.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>
#include <seam/pair.h>

#include <vector>

namespace seam::internal {

template <class K> struct IntersectionCurves {
  std::vector<Polyline<K>> curves;  ///< closed ones repeat their first point; sorted by first point
  /// When the general-position path computed them (exact kernel): where each curve point lies in
  /// each mesh (empty otherwise).
  KnownSites<K> sites_a, sites_b;
  std::vector<typename K::Point_3> contacts;  ///< isolated points of contact (not curves)
  std::size_t touching_points = 0;           ///< pieces of surface_intersection that are one point
  CurveEnds ends;                            ///< why each open curve ends where it does
};

/// The intersection curves of `a` and `b` (exact under the exact kernel; under the float kernel
/// computed with Epick on the same doubles). `known_degenerate`: a vertex of one lies exactly on
/// the other (moved onto a curve), so the general-position path would stop at that zero
/// predicate after its box search: CGAL's surface_intersection at once.
template <class K>
IntersectionCurves<K> compute_intersection_curves(const Mesh<K>& a, const Mesh<K>& b, bool known_degenerate = false);

}  // namespace seam::internal
