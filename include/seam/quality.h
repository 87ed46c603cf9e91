// seam: triangle quality measurements (rounded to double: they are reports, not decisions).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace seam {

/// Smallest interior angle of the triangle (p, q, r) in degrees; 0 for a degenerate one.
/// (Under Epeck the coordinates come from the points' interval approximations: p.x() would build
/// a lazy number per coordinate, which made these reports a visible part of a whole run.)
/// The smallest angle lies opposite the shortest side. Where the shortest side is shorter than
/// the others by a relative 1e-6 or more (in squared length), only that angle is computed: the
/// angles then differ by a relative 5e-7 or more, their roundings by about 1e-16 over the angle in
/// radians, so for angles above about 1e-9 rad it is the same double as the smallest of the
/// three. Otherwise all three are computed.
template <class Point> double min_angle_deg(const Point& p, const Point& q, const Point& r) {
  const auto P = to_filtered(p), Q = to_filtered(q), R = to_filtered(r);
  using P3 = Filtered::Point_3;
  auto angle = [](const P3& a, const P3& b, const P3& c) {  // at a
    double u[3], v[3], uu = 0, vv = 0, uv = 0;
    for (int i = 0; i < 3; ++i) {
      u[i] = b[i] - a[i];
      v[i] = c[i] - a[i];
      uu += u[i] * u[i];
      vv += v[i] * v[i];
      uv += u[i] * v[i];
    }
    if (uu <= 0 || vv <= 0) return 0.0;
    // atan2(|u x v|, u.v) is accurate for tiny angles, unlike acos.
    const double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
    return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), uv) * 180.0 / M_PI;
  };
  const double qr = CGAL::squared_distance(Q, R), rp = CGAL::squared_distance(R, P), pq = CGAL::squared_distance(P, Q);
  const double margin = 1 + 1e-6;
  if (qr * margin < rp && qr * margin < pq) return angle(P, Q, R);  // opposite QR
  if (rp * margin < pq && rp * margin < qr) return angle(Q, R, P);
  if (pq * margin < qr && pq * margin < rp) return angle(R, P, Q);
  return std::min({angle(P, Q, R), angle(Q, R, P), angle(R, P, Q)});
}

struct NewFaceQuality {
  std::size_t new_faces = 0;
  double min_angle_deg = 0;  ///< smallest angle among new faces (0 when there are none)
  std::size_t below_10 = 0, below_20 = 0;
  /// Below 10 degrees although the input face it came from has no angle that small.
  std::size_t below_10_unforced = 0;
  /// Below 20 degrees although the input face it came from has no angle that small.
  std::size_t below_20_unforced = 0;
  double largest_area = 0;  ///< the largest area of a new face (doubles)
  /// New faces larger than the `max_area` given (0: none counted).
  std::size_t above_max_area = 0;
};

/// Quality of the faces marked new (new_face_property). `source_min_angle[i]`, when given, is
/// the smallest angle of input face i (for the "unforced" counts); `max_area`, when given, the
/// area bound faces are counted against.
template <class K>
NewFaceQuality new_face_quality(const Mesh<K>& mesh, const std::vector<double>* source_min_angle = nullptr,
                                double max_area = 0) {
  NewFaceQuality q;
  // CGAL 5.5: property_map() returns (map, found).
  const auto [is_new, has_new] = mesh.template property_map<typename Mesh<K>::Face_index, bool>(new_face_property);
  const auto [source, has_source] =
      mesh.template property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property);
  if (!has_new) return q;
  double worst = 180;
  for (auto f : mesh.faces()) {
    if (!is_new[f]) continue;
    auto h = mesh.halfedge(f);
    const double a = seam::min_angle_deg(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                                         mesh.point(mesh.target(mesh.next(h))));
    ++q.new_faces;
    worst = std::min(worst, a);
    const auto p = to_filtered(mesh.point(mesh.source(h))), r = to_filtered(mesh.point(mesh.target(h))),
               t = to_filtered(mesh.point(mesh.target(mesh.next(h))));
    const double area = 0.5 * std::sqrt(CGAL::cross_product(r - p, t - p).squared_length());
    q.largest_area = std::max(q.largest_area, area);
    if (max_area > 0 && area > max_area * (1 + 1e-9)) ++q.above_max_area;
    double forced = 180;
    if (source_min_angle && has_source && source[f] < source_min_angle->size()) forced = (*source_min_angle)[source[f]];
    if (a < 10) {
      ++q.below_10;
      if (a < forced) ++q.below_10_unforced;
    }
    if (a < 20) {
      ++q.below_20;
      if (a < forced) ++q.below_20_unforced;
    }
  }
  q.min_angle_deg = q.new_faces ? worst : 0;
  return q;
}

}  // namespace seam
