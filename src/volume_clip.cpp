// seam internal: tows cut by the matrix box (periodic unit cells). See seam/internal/volume_plc.h.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Exact: which side of a box plane a point is on, the cut points (the intersection of an edge
// with a plane, constructed with lazy exact numbers), the Delaunay triangulation of each cut
// face. Rounded: the cut points are written as doubles at the end. A cut point's coordinate along
// the plane's axis is the plane's coordinate itself, a double, so it stays exactly in the box face.
// Before the cut, vertices near a box plane may move onto it (snap_to_planes): decided on doubles
// and exact predicates, per point, so that no cut leaves a sliver next to a vertex.
#include <seam/internal/message.h>
#include <seam/internal/volume_plc.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <CGAL/Projection_traits_xz_3.h>
#include <CGAL/Projection_traits_yz_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <utility>

namespace seam::internal {

namespace {

using EPoint = Exact::Point_3;
using EFT = Exact::FT;

bool in_closed_box(const Point3d& p, const AxisBox& box) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < box.min[a] || p[a] > box.max[a]) return false;
  return true;
}

/// Whether a tow has a vertex outside the closed box.
bool crosses_box(const TriangleSoup& tow, const AxisBox& box) {
  return !std::all_of(tow.points.begin(), tow.points.end(), [&](const Point3d& p) { return in_closed_box(p, box); });
}

/// The point of segment pq on the plane x_a = c (p and q strictly on either side of it, or one on
/// it): exact, with coordinate a exactly c. The same value whichever way round p and q are given.
EPoint cut_point(const EPoint& p, const EPoint& q, int a, double c) {
  const EFT t = (EFT(c) - p[a]) / (q[a] - p[a]);
  EFT x[3];
  for (int k = 0; k < 3; ++k) x[k] = k == a ? EFT(c) : p[k] + t * (q[k] - p[k]);
  EPoint r(x[0], x[1], x[2]);
  make_exact(r);
  return r;
}

/// The convex polygon of a triangle inside the closed box: Sutherland-Hodgman against the six
/// half-spaces, exactly. Empty when less than a polygon with area is left.
std::vector<EPoint> clip_to_box(std::vector<EPoint> polygon, const AxisBox& box) {
  for (int a = 0; a < 3; ++a)
    for (const bool lower : {true, false}) {
      const double c = lower ? box.min[a] : box.max[a];
      const EFT cc(c);
      auto inside = [&](const EPoint& p) { return lower ? p[a] >= cc : p[a] <= cc; };
      std::vector<EPoint> out;
      for (std::size_t i = 0; i < polygon.size(); ++i) {
        const EPoint& p = polygon[i];
        const EPoint& q = polygon[(i + 1) % polygon.size()];
        const bool p_in = inside(p), q_in = inside(q);
        // A cut point equals a corner on the plane: each point once (consecutive repeats dropped).
        auto add = [&](const EPoint& r) {
          if (out.empty() || out.back() != r) out.push_back(r);
        };
        if (p_in) add(p);
        if (p_in != q_in) add(p_in ? cut_point(q, p, a, c) : cut_point(p, q, a, c));
      }
      while (out.size() > 1 && out.front() == out.back()) out.pop_back();
      polygon.swap(out);
      if (polygon.size() < 3) return {};
    }
  return polygon;
}

/// The Delaunay triangulation of a convex polygon's corners in a projection (exact predicates;
/// cocircular corners are resolved by CGAL's symbolic perturbation, so the result depends on the
/// points only, not on their order): the same triangles for a face that two tows share.
template <class Traits> std::vector<std::array<std::size_t, 3>> delaunay(const std::vector<EPoint>& polygon, bool reverse) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Traits>;
  using Fb = CGAL::Triangulation_face_base_2<Traits>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  CGAL::Delaunay_triangulation_2<Traits, Tds> dt;
  for (std::size_t i = 0; i < polygon.size(); ++i) dt.insert(polygon[i])->info() = i;
  std::vector<std::array<std::size_t, 3>> triangles;
  if (dt.number_of_vertices() != polygon.size()) return triangles;  // two corners with one projection
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    std::array<std::size_t, 3> t{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
    if (reverse) std::swap(t[1], t[2]);
    triangles.push_back(t);
  }
  return triangles;
}

/// A cut face: its polygon inside the box triangulated, in the orientation of the face.
std::vector<std::array<std::size_t, 3>> triangulate_cut(const std::array<Point3d, 3>& corners,
                                                        const std::vector<EPoint>& polygon) {
  // The projection axis from the corners in a fixed order (the same for a face two tows share,
  // whichever way round each has it): the largest normal component, in doubles.
  std::array<Point3d, 3> sorted = corners;
  std::sort(sorted.begin(), sorted.end());
  const Filtered::Point_3 p(sorted[0][0], sorted[0][1], sorted[0][2]), q(sorted[1][0], sorted[1][1], sorted[1][2]),
      r(sorted[2][0], sorted[2][1], sorted[2][2]);
  const auto n = CGAL::cross_product(q - p, r - p);
  const double x = std::abs(n.x()), y = std::abs(n.y()), z = std::abs(n.z());
  const int axis = x >= y && x >= z ? 0 : (y >= z ? 1 : 2);
  const EPoint a(corners[0][0], corners[0][1], corners[0][2]), b(corners[1][0], corners[1][1], corners[1][2]),
      c(corners[2][0], corners[2][1], corners[2][2]);
  auto with = [&](auto traits) {
    using Traits = decltype(traits);
    const bool reverse = traits.orientation_2_object()(a, b, c) != CGAL::LEFT_TURN;
    return delaunay<Traits>(polygon, reverse);
  };
  if (axis == 0) return with(CGAL::Projection_traits_yz_3<Exact>());
  if (axis == 1) return with(CGAL::Projection_traits_xz_3<Exact>());
  return with(CGAL::Projection_traits_xy_3<Exact>());
}

/// The candidates of snap_to_planes: each point (a key of `points`) within `snap` of a box plane,
/// and within `snap` of the box in the other two axes, and where it would go (onto the nearer
/// plane of each such axis).
template <class PointMap>
std::map<Point3d, Point3d> plane_snap_candidates(const PointMap& points, const AxisBox& box, double snap) {
  std::map<Point3d, Point3d> moved;
  for (const auto& [p, unused] : points) {
    Point3d q = p;
    for (int a = 0; a < 3; ++a) {
      bool near_box = true;  // within snap of the box in the other two axes
      for (int b = 0; b < 3; ++b)
        if (b != a && (p[b] < box.min[b] - snap || p[b] > box.max[b] + snap)) near_box = false;
      if (!near_box) continue;
      const double to_min = std::abs(p[a] - box.min[a]), to_max = std::abs(p[a] - box.max[a]);
      const double c = to_min <= to_max ? box.min[a] : box.max[a];
      if (std::min(to_min, to_max) <= snap) q[a] = c;
    }
    if (q != p) moved.emplace(p, q);
  }
  return moved;
}

/// Moves tow vertices near a box plane onto it (see ClippedTows in the header): returns how many
/// distinct points moved, and the longest move. Every point near a plane is a candidate; each
/// candidate is tested with all the others moved, and those that fail go back, until all pass:
/// each round drops at least one candidate or ends, so there are at most as many rounds as
/// candidates (in practice one or two). Testing with the others moved lets a ring of vertices a
/// few units in the last place on either side of a plane move together.
std::pair<std::size_t, double> snap_to_planes(std::vector<TriangleSoup>& tows, const AxisBox& box, double snap) {
  struct Use {
    std::size_t tow, face;
  };
  std::map<Point3d, std::vector<Use>> uses;  // every tow point, with the faces at it
  for (std::size_t i = 0; i < tows.size(); ++i)
    for (std::size_t f = 0; f < tows[i].triangles.size(); ++f)
      for (const std::size_t v : tows[i].triangles[f]) uses[tows[i].points[v]].push_back({i, f});
  std::map<Point3d, Point3d> moved = plane_snap_candidates(uses, box, snap);  // the candidates still in
  auto now = [&](const Point3d& p) {
    const auto it = moved.find(p);
    return it == moved.end() ? p : it->second;
  };
  auto fp = [](const Point3d& p) { return Filtered::Point_3(p[0], p[1], p[2]); };
  std::vector<int> orientation;  // per tow: +1 outward normals
  for (const auto& tow : tows) orientation.push_back(signed_volume(tow) >= 0 ? 1 : -1);
  // Whether moving p to q (the other candidates moved) keeps every face at p sound and the plane
  // crossing the tow there.
  auto valid = [&](const Point3d& p, const Point3d& q) {
    const auto& faces = uses.at(p);
    for (const Use& u : faces) {  // no face degenerate (exact) or turned over
      const auto& t = tows[u.tow].triangles[u.face];
      std::array<Point3d, 3> before, after;
      for (int k = 0; k < 3; ++k) {
        before[k] = tows[u.tow].points[t[k]];
        after[k] = now(before[k]);
      }
      if (CGAL::collinear(fp(after[0]), fp(after[1]), fp(after[2]))) return false;
      const auto n0 = CGAL::cross_product(fp(before[1]) - fp(before[0]), fp(before[2]) - fp(before[0]));
      const auto n1 = CGAL::cross_product(fp(after[1]) - fp(after[0]), fp(after[2]) - fp(after[0]));
      if (!(n0 * n1 > 0)) return false;
    }
    // Where the plane would then touch the tow instead of crossing it (the neighbours around q,
    // or the two faces at an edge in the plane, all on one side), the tow's interior must lie
    // away from the plane (a tow lying against the box face from inside, or touching it from
    // outside): where it faced the plane, the tow's part in the box would be pinched to a line
    // or a point, with caps on both sides (a ridge of a CT tow 0.004 beyond the plane did that).
    // Left as it is, the cut makes small pieces there instead, which are valid. More than one arc
    // on either side around q is refused too.
    for (int a = 0; a < 3; ++a) {
      if (q[a] == p[a]) continue;  // only the planes p moves onto
      const int out = q[a] == box.max[a] ? 1 : -1;  // the box's outward direction along a
      auto side = [&](const Point3d& x) { return x[a] == q[a] ? 0 : ((x[a] - q[a]) * out < 0 ? -1 : 1); };  // -1: inner
      // The normal of face (x, y, z) of tow i along a, outward from the tow, positive out of the
      // box (doubles; twice the face's area times the cosine).
      auto normal_out = [&](std::size_t i, const Point3d& x, const Point3d& y, const Point3d& z) {
        return CGAL::cross_product(fp(y) - fp(x), fp(z) - fp(x))[a] * out * orientation[i];
      };
      std::map<std::pair<std::size_t, Point3d>, std::pair<std::vector<int>, double>> at_edge;  // (tow, w): sides, normals
      std::map<std::size_t, std::map<Point3d, Point3d>> link;  // per tow: the fan's link around q, w -> x
      std::map<std::size_t, double> fan_normal;                // per tow: the sum of the fan's normals along a
      for (const Use& u : faces) {
        const auto& t = tows[u.tow].triangles[u.face];
        std::array<Point3d, 3> c;
        int k0 = 0;
        for (int k = 0; k < 3; ++k) {
          const Point3d& x = tows[u.tow].points[t[k]];
          c[k] = now(x);
          if (x == p) k0 = k;
        }
        const double n = normal_out(u.tow, c[0], c[1], c[2]);
        const Point3d &w = c[(k0 + 1) % 3], &x = c[(k0 + 2) % 3];
        link[u.tow][w] = x;
        fan_normal[u.tow] += n;
        for (const auto& [end, third] : {std::pair{w, x}, std::pair{x, w}})
          if (side(end) == 0) {
            auto& e = at_edge[{u.tow, end}];
            e.first.push_back(side(third));
            e.second += n;
          }
      }
      // The tow lies away from the plane where the faces there face out of the box (their normals
      // summed) from the inner side, or into it from the outer side.
      auto away = [](int s, double n) { return s == -1 ? n > 0 : n < 0; };
      // An edge in the plane with both faces on one side.
      for (const auto& [edge, e] : at_edge)
        if (e.first.size() == 2 && e.first[0] == e.first[1] && e.first[0] != 0 && !away(e.first[0], e.second))
          return false;
      for (const auto& [tow, next] : link) {
        std::vector<int> signs;  // the sides of the neighbours off the plane, around q
        Point3d w = next.begin()->first;
        for (std::size_t steps = 0; steps < next.size(); ++steps) {
          if (side(w) != 0) signs.push_back(side(w));
          const auto it = next.find(w);
          if (it == next.end()) break;
          w = it->second;
        }
        int changes = 0;
        for (std::size_t k = 0; k < signs.size(); ++k) changes += signs[k] != signs[(k + 1) % signs.size()];
        // All neighbours off the plane on one side: the same test on the whole fan.
        const bool fan_away = signs.empty() || changes > 0 || away(signs.front(), fan_normal[tow]);
        if (w != next.begin()->first || changes > 2 || !fan_away) return false;
      }
    }
    return true;
  };
  for (;;) {
    std::map<Point3d, int> at;  // how many points end where (two at one place would merge)
    for (const auto& [p, faces] : uses) ++at[now(p)];
    std::vector<Point3d> back;
    for (const auto& [p, q] : moved)
      if (at[q] > 1 || !valid(p, q)) back.push_back(p);
    if (back.empty()) break;
    for (const auto& p : back) moved.erase(p);
  }
  double max_move = 0;
  for (const auto& [p, q] : moved) max_move = std::max(max_move, std::sqrt(CGAL::squared_distance(fp(p), fp(q))));
  for (auto& tow : tows)
    for (auto& p : tow.points) p = now(p);
  return {moved.size(), max_move};
}

}  // namespace

ClippedTows clip_tows_to_box(const std::vector<TriangleSoup>& input, const std::vector<std::string>& names,
                             const AxisBox& box, double snap) {
  ClippedTows result;
  result.uncut = input;
  const bool any_crosses = std::any_of(input.begin(), input.end(), [&](const TriangleSoup& tow) { return crosses_box(tow, box); });
  if (any_crosses && snap > 0) std::tie(result.snapped, result.max_move) = snap_to_planes(result.uncut, box, snap);
  const std::vector<TriangleSoup>& tows = result.uncut;
  for (std::size_t i = 0; i < tows.size(); ++i) {
    const TriangleSoup& tow = tows[i];
    const bool crosses = crosses_box(tow, box);  // after the moves: a tow moved onto the box lies against it
    result.clipped.push_back(crosses ? 1 : 0);
    if (!crosses) {
      result.surfaces.push_back(tow);
      continue;
    }
    const int orientation = signed_volume(tow) >= 0 ? 1 : -1;  // +1: outward normals
    TriangleSoup out;
    std::map<Point3d, std::size_t> index;
    auto point_index = [&](const Point3d& p) {
      const auto [it, added] = index.emplace(p, out.points.size());
      if (added) out.points.push_back(p);
      return it->second;
    };
    for (std::size_t f = 0; f < tow.triangles.size(); ++f) {
      const auto& t = tow.triangles[f];
      const std::array<Point3d, 3> corners{tow.points[t[0]], tow.points[t[1]], tow.points[t[2]]};
      // A face lying in a plane of the box: kept where the tow lies inside the box there (the
      // face is then part of the box's boundary), dropped where it lies outside (exact: the sign
      // of the face's normal along the plane's axis, with the tow's orientation).
      bool drop = false;
      for (int a = 0; a < 3; ++a)
        for (const bool upper : {false, true}) {
          const double c = upper ? box.max[a] : box.min[a];
          if (!(corners[0][a] == c && corners[1][a] == c && corners[2][a] == c)) continue;
          const int u = (a + 1) % 3, v = (a + 2) % 3;
          const CGAL::Orientation turn = CGAL::orientation(Filtered::Point_2(corners[0][u], corners[0][v]),
                                                           Filtered::Point_2(corners[1][u], corners[1][v]),
                                                           Filtered::Point_2(corners[2][u], corners[2][v]));
          if (turn == CGAL::COLLINEAR) throw InvalidInput(say(names[i], ": face ", f, " is degenerate"));
          const int outward_along_a = (turn == CGAL::LEFT_TURN ? 1 : -1) * orientation;
          drop = outward_along_a != (upper ? 1 : -1);
        }
      if (drop) continue;
      if (in_closed_box(corners[0], box) && in_closed_box(corners[1], box) && in_closed_box(corners[2], box)) {
        out.triangles.push_back({point_index(corners[0]), point_index(corners[1]), point_index(corners[2])});
        continue;
      }
      bool outside = false;  // all corners on the outer side of one plane (on it, or beyond)
      for (int a = 0; a < 3 && !outside; ++a)
        outside = std::all_of(corners.begin(), corners.end(), [&](const Point3d& p) { return p[a] <= box.min[a]; }) ||
                  std::all_of(corners.begin(), corners.end(), [&](const Point3d& p) { return p[a] >= box.max[a]; });
      if (outside) continue;
      std::vector<EPoint> polygon;
      for (const auto& p : corners) polygon.emplace_back(p[0], p[1], p[2]);
      polygon = clip_to_box(std::move(polygon), box);
      if (polygon.empty()) continue;
      // Rounded to doubles (the same rounding of the same exact point in every face and tow).
      std::vector<std::size_t> ids;
      for (const auto& p : polygon) {
        const auto& e = CGAL::exact(p);
        ids.push_back(point_index({CGAL::to_double(e.x()), CGAL::to_double(e.y()), CGAL::to_double(e.z())}));
      }
      for (const auto& tri : triangulate_cut(corners, polygon)) {
        const std::array<std::size_t, 3> m{ids[tri[0]], ids[tri[1]], ids[tri[2]]};
        // Two corners that round to one point (a box edge passing a few units in the last place
        // from a tow edge, say): the triangle between them collapses, in every face that has
        // them (they round alike), and the faces around it close over it.
        if (m[0] == m[1] || m[1] == m[2] || m[0] == m[2]) continue;
        out.triangles.push_back(m);
      }
    }
    if (out.triangles.empty()) throw InvalidInput(names[i] + ": the tow lies outside the matrix box");
    result.surfaces.push_back(std::move(out));
  }
  return result;
}

}  // namespace seam::internal
