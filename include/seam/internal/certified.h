// seam internal: certified interval tests for triangle pairs (used by seam check and by the
// collapse step of pair).
//
// Interval coordinates that contain the exact ones (the exact kernel's approximation, or the
// doubles themselves). A test below returns true only when the interval arithmetic proves the
// property for the exact coordinates; otherwise the caller decides with the kernel's predicates.
// They matter under the exact kernel: next to the curves and inside re-triangulated faces the
// configurations are degenerate by construction (a curve point lies exactly in the plane of the
// other mesh's faces, the faces of one input face are exactly coplanar), so the kernel's own
// filters fail and evaluate on rationals that can be a thousand bits long (seconds per thousand
// pairs); separating axes and axis projections settle nearly all of them in doubles.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>

#include <CGAL/Interval_nt.h>

#include <array>
#include <optional>
#include <type_traits>

namespace seam::internal::certified {

using I = CGAL::Interval_nt<false>;  // needs the rounding mode set by Protect_FPU_rounding
using IP = std::array<I, 3>;

template <class P> inline IP interval_point(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    const auto& a = CGAL::approx(p);
    return {I(a.x().inf(), a.x().sup()), I(a.y().inf(), a.y().sup()), I(a.z().inf(), a.z().sup())};
  } else {
    return {I(CGAL::to_double(p.x())), I(CGAL::to_double(p.y())), I(CGAL::to_double(p.z()))};
  }
}

/// +1 / -1 when the sign is certain, 0 otherwise.
inline int sure_sign(const I& x) { return x.inf() > 0 ? 1 : (x.sup() < 0 ? -1 : 0); }

/// Orientation of (a, b, c) projected along axis `ax` (dropping that coordinate).
inline I orient2(const IP& a, const IP& b, const IP& c, int ax) {
  const int i = (ax + 1) % 3, j = (ax + 2) % 3;
  return (b[i] - a[i]) * (c[j] - a[j]) - (b[j] - a[j]) * (c[i] - a[i]);
}

/// Orientation of (p, a, b, c) in 3D.
inline I orient3(const IP& p, const IP& a, const IP& b, const IP& c) {
  const I ax = a[0] - p[0], ay = a[1] - p[1], az = a[2] - p[2];
  const I bx = b[0] - p[0], by = b[1] - p[1], bz = b[2] - p[2];
  const I cx = c[0] - p[0], cy = c[1] - p[1], cz = c[2] - p[2];
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

/// Triangles (t[0], t[1], t[2]) and (u[0], u[1], u[2]) are disjoint: a separating axis strictly
/// separates them (3D: a normal or the cross product of two edges), or in some axis projection an
/// edge line does (the projection of a common point would be on both sides).
inline bool surely_disjoint(const std::array<const IP*, 3>& t, const std::array<const IP*, 3>& u) {
  CGAL::Protect_FPU_rounding<true> rounding;
  // Separating axes in 3D: the two normals and the nine cross products of an edge of each.
  auto edge = [](const std::array<const IP*, 3>& x, int m) {
    const IP &a = *x[m], &b = *x[(m + 1) % 3];
    return IP{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  };
  auto cross = [](const IP& a, const IP& b) {
    return IP{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto separates = [&](const IP& n) {  // every (u_j - t_i) . n has the same certain sign
    int sign = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const IP &a = *t[i], &b = *u[j];
        const int sij = sure_sign((b[0] - a[0]) * n[0] + (b[1] - a[1]) * n[1] + (b[2] - a[2]) * n[2]);
        if (sij == 0 || (sign != 0 && sij != sign)) return false;
        sign = sij;
      }
    return true;
  };
  if (separates(cross(edge(t, 0), edge(t, 1))) || separates(cross(edge(u, 0), edge(u, 1)))) return true;
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 3; ++k)
      if (separates(cross(edge(t, m), edge(u, k)))) return true;
  for (int ax = 0; ax < 3; ++ax)
    for (int side = 0; side < 2; ++side) {
      const auto& x = side ? u : t;
      const auto& y = side ? t : u;
      for (int m = 0; m < 3; ++m) {
        const IP &e0 = *x[m], &e1 = *x[(m + 1) % 3];
        const int own = sure_sign(orient2(e0, e1, *x[(m + 2) % 3], ax));
        if (own == 0) continue;
        if (sure_sign(orient2(e0, e1, *y[0], ax)) == -own && sure_sign(orient2(e0, e1, *y[1], ax)) == -own &&
            sure_sign(orient2(e0, e1, *y[2], ax)) == -own)
          return true;
      }
    }
  return false;
}

/// Triangles (p, q, r) and (p, q, s) meet only in their edge pq: s is off the plane of (p, q, r),
/// or in some axis projection where (p, q, r) is not degenerate (so the projection is one-to-one
/// on its plane), r and s lie strictly on opposite sides of pq.
inline bool surely_only_edge(const IP& p, const IP& q, const IP& r, const IP& s) {
  CGAL::Protect_FPU_rounding<true> rounding;
  if (sure_sign(orient3(p, q, r, s)) != 0) return true;  // not coplanar
  for (int ax = 0; ax < 3; ++ax) {
    const int o_r = sure_sign(orient2(p, q, r, ax));
    if (o_r != 0 && sure_sign(orient2(p, q, s, ax)) == -o_r) return true;
  }
  return false;
}

/// Triangles (p, a, b) and (p, c, d) meet only in p (true), more than p (false), or unknown.
inline std::optional<bool> surely_only_vertex(const IP& p, const IP& a, const IP& b, const IP& c, const IP& d) {
  CGAL::Protect_FPU_rounding<true> rounding;
  // In 3D: one triangle strictly on one side of the other's plane (it meets that plane in p
  // only); or each straddles the other's plane, and then each meets the common line of the planes
  // in a segment from p, [p, x1] and [p, x2], which overlap iff they point the same way.
  const int oc = sure_sign(orient3(p, a, b, c)), od = sure_sign(orient3(p, a, b, d));
  if (oc != 0 && oc == od) return true;
  const I o_a = orient3(p, c, d, a), o_b = orient3(p, c, d, b);
  const int oa = sure_sign(o_a), ob = sure_sign(o_b);
  if (oa != 0 && oa == ob) return true;
  if (oc != 0 && od == -oc && oa != 0 && ob == -oa) {
    const I o_c = orient3(p, a, b, c), o_d = orient3(p, a, b, d);
    const I t1 = o_a / (o_a - o_b), t2 = o_c / (o_c - o_d);  // denominators surely nonzero
    I dot(0);
    for (int i = 0; i < 3; ++i) dot += (a[i] + (b[i] - a[i]) * t1 - p[i]) * (c[i] + (d[i] - c[i]) * t2 - p[i]);
    const int sd = sure_sign(dot);
    if (sd < 0) return true;
    if (sd > 0) return false;
  }
  // In an axis projection where neither is degenerate: their angular sectors at p (each less
  // than 180 degrees) share only p, i.e. no bounding ray of one is in the closed sector of the other.
  for (int ax = 0; ax < 3; ++ax) {
    const int o1 = sure_sign(orient2(p, a, b, ax)), o2 = sure_sign(orient2(p, c, d, ax));
    if (o1 == 0 || o2 == 0) continue;
    const IP &u1 = o1 > 0 ? a : b, &u2 = o1 > 0 ? b : a;  // counterclockwise sector u1 -> u2
    const IP &v1 = o2 > 0 ? c : d, &v2 = o2 > 0 ? d : c;
    auto outside = [&](const IP& w, const IP& s1, const IP& s2) {
      return sure_sign(orient2(p, s1, w, ax)) < 0 || sure_sign(orient2(p, w, s2, ax)) < 0;
    };
    if (outside(v1, u1, u2) && outside(v2, u1, u2) && outside(u1, v1, v2) && outside(u2, v1, v2)) return true;
  }
  return std::nullopt;
}

}  // namespace seam::internal::certified
