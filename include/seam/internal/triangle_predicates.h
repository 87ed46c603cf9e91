// seam internal: exact tests on triangles written with the kernel's orientation predicates,
// where CGAL's general functions evaluate on rationals more often than needed.
//
// on_triangle: CGAL's Triangle_3::has_on solves a 3x3 system for the barycentric coordinates
// and tests their sum for equality with 1, which no interval filter can certify: under Epeck it
// evaluates on rationals every time (plane construction and solve). The orientation tests here
// are exact alike, and their filters fail only where the point lies exactly in the plane (one
// determinant on rationals) or exactly on an edge's line.
//
// only_vertex_along_edges: two triangles of different meshes at a common curve point, the
// acceptance predicate's most frequent exact case (see the function).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>

#include <optional>

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

/// Triangles (p, a, b) and (p, c, d) meet only in p (true) or in more (false), decided with the
/// kernel's predicates where at least one of them meets the other's plane in one of its edges
/// from p: at a curve point, the curve runs along the line L where the two planes meet, and the
/// next curve point of a face lies exactly in the other's plane. Each face meets L in a segment
/// from p (the face's part in the other's plane), and the faces share only p when those point
/// away from each other:
///   - both are edges, [p, x] and [p, y]: when x and y lie on opposite sides of p;
///   - [p, x] an edge of one, the other straddling the first one's plane (its segment on L lies
///     strictly inside its corner at p): when x lies outside that corner.
/// Otherwise (both straddle, or a degenerate triangle) unknown: the caller's general test. Exact
/// under the exact and filtered kernels, and cheap: the interval filters fail only on the corners
/// exactly in the other plane (one determinant each).
template <class P>
std::optional<bool> only_vertex_along_edges(const P& p, const P& a, const P& b, const P& c, const P& d) {
  const auto oc = CGAL::orientation(p, a, b, c), od = CGAL::orientation(p, a, b, d);
  if (oc != CGAL::COPLANAR && oc == od) return true;
  const auto oa = CGAL::orientation(p, c, d, a), ob = CGAL::orientation(p, c, d, b);
  if (oa != CGAL::COPLANAR && oa == ob) return true;
  // (one corner in the other's plane and one off it: that triangle meets the plane in an edge)
  auto edge_end = [](CGAL::Orientation o1, CGAL::Orientation o2, const P& x1, const P& x2) -> const P* {
    if ((o1 == CGAL::COPLANAR) == (o2 == CGAL::COPLANAR)) return nullptr;
    return o1 == CGAL::COPLANAR ? &x1 : &x2;
  };
  auto straddles = [](CGAL::Orientation o1, CGAL::Orientation o2) {
    return o1 != CGAL::COPLANAR && o2 != CGAL::COPLANAR && o1 != o2;
  };
  // z (in the plane of corner (p, q, r)) lies strictly inside that corner
  auto inside_corner = [](const P& p, const P& q, const P& r, const P& z) {
    return CGAL::coplanar_orientation(p, q, r, z) == CGAL::POSITIVE &&
           CGAL::coplanar_orientation(p, r, q, z) == CGAL::POSITIVE;
  };
  const P* x = edge_end(oa, ob, a, b);
  const P* y = edge_end(oc, od, c, d);
  if (x && y) return CGAL::angle(*x, p, *y) == CGAL::OBTUSE;
  if (x && straddles(oc, od)) return !inside_corner(p, c, d, *x);
  if (y && straddles(oa, ob)) return !inside_corner(p, a, b, *y);
  return std::nullopt;
}

}  // namespace seam::internal
