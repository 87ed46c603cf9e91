// seam internal: whether a point lies on a closed triangle, with the kernel's orientation
// predicates.
//
// CGAL's Triangle_3::has_on solves a 3x3 system for the barycentric coordinates and tests their
// sum for equality with 1, which no interval filter can certify: under Epeck it evaluates on
// rationals every time (plane construction and solve). The orientation tests here are exact
// alike, and their filters fail only where the point lies exactly in the plane (one determinant
// on rationals) or exactly on an edge's line.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>

namespace seam::internal {

/// p lies on the closed triangle (a, b, c): in its plane, and not beyond any of its edges. A
/// degenerate triangle is left to Triangle_3::has_on.
template <class K>
bool on_triangle(const typename K::Point_3& a, const typename K::Point_3& b, const typename K::Point_3& c,
                 const typename K::Point_3& p) {
  if (CGAL::collinear(a, b, c)) return typename K::Triangle_3(a, b, c).has_on(p);
  if (CGAL::orientation(a, b, c, p) != CGAL::COPLANAR) return false;
  return CGAL::coplanar_orientation(a, b, c, p) != CGAL::NEGATIVE &&
         CGAL::coplanar_orientation(b, c, a, p) != CGAL::NEGATIVE &&
         CGAL::coplanar_orientation(c, a, b, p) != CGAL::NEGATIVE;
}

}  // namespace seam::internal
