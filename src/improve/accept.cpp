// seam: the quality stage's acceptance predicate, the one test every edit that changes the
// surface passes before it is made (see seam/improve.h).
//
// Shape and degeneracy are decided by the kernel's predicates; the turn from the input surface
// and the distance to it in doubles (rounded); whether two faces meet, and where, by the kernel's
// predicates after certified interval filters (exact under Exact and Filtered). Two faces may meet
// as seam check allows: in one common vertex or edge of the same mesh, or, faces of two meshes,
// in a common curve point or along a common curve segment.
//
// As written: exact points are rounded when written, and an exact curve point that rounds a few
// units in the last place into the other surface, where two tows touch almost flat, makes faces
// that cross once written, even after an edit that keeps the surface exactly (a split, an exact
// insertion, a coplanar flip). Under the exact kernel every edit is therefore also checked on its
// corners rounded to doubles as the writer rounds them, unless a face it removes already crosses
// once rounded (left so by the embedding): then refusing it would only keep that crossing. (Under
// the other kernels coordinates are doubles already.)
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/internal/certified.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/triangle_predicates.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>

namespace seam::internal {

namespace {

/// Who a corner is: a vertex of a mesh (or the edit's fresh vertex), and its curve point.
template <class K> struct CornerId {
  std::size_t mesh;
  typename Mesh<K>::Vertex_index v;
  bool fresh;
  int point;  ///< curve point id, -1 for others
};

template <class K> bool same_corner(const CornerId<K>& a, const CornerId<K>& b) {
  if (a.mesh == b.mesh) return a.fresh ? b.fresh : (!b.fresh && a.v == b.v);
  return a.point >= 0 && a.point == b.point;
}

/// A triangle to test: its corners in kernel PK (K itself, or Filtered for the corners rounded to
/// doubles as written: exact predicates on doubles, no lazy construction), and who they are.
template <class K, class PK = K> struct Tri {
  std::array<typename PK::Point_3, 3> p;
  std::array<CornerId<K>, 3> id;
  std::array<certified::IP, 3> ip;
  bool doubles = false;  ///< every corner's coordinates are doubles exactly: as written, as it is
  void intervals() {
    for (int i = 0; i < 3; ++i) ip[std::size_t(i)] = certified::interval_point(p[std::size_t(i)]);
  }
};

/// Whether (x, y) is a curve segment once the edit is made, held by meshes m1 and m2.
template <class K>
bool segment_after(const ImproveState<K>& s, const Edit<K>& edit, int x, int y, std::size_t m1, std::size_t m2) {
  if (x < 0 || y < 0) return false;
  const int fresh = edit.fresh_curve_point ? int(s.points.size()) : -2;
  auto is = [&](int a, int b) { return (x == a && y == b) || (x == b && y == a); };
  int curve = -1;
  if (edit.split_a >= 0 && (is(edit.split_a, fresh) || is(fresh, edit.split_b))) {
    curve = s.curve_of_segment(edit.split_a, edit.split_b);
  } else if (edit.split_a >= 0 && is(edit.split_a, edit.split_b)) {
    return false;
  } else if (edit.merged_point >= 0 && (x == edit.merged_point || y == edit.merged_point)) {
    return false;
  } else {
    curve = s.curve_of_segment(x, y);
    // A merge of u into w makes every segment (z, u) a segment (z, w).
    if (curve < 0 && edit.merged_point >= 0 && (x == edit.merged_into || y == edit.merged_into))
      curve = s.curve_of_segment(x == edit.merged_into ? y : x, edit.merged_point);
  }
  return curve >= 0 && s.holds_curve(m1, curve) && s.holds_curve(m2, curve);
}

/// Whether two of the three points are one point (a face that is no triangle, as written).
template <class P> bool two_coincide(const P& a, const P& b, const P& c) { return a == b || b == c || c == a; }

/// Whether triangles t and u meet only as allowed (see the top of this file). Exact under the
/// exact and filtered kernels. `by_intervals` (if given) is set where the certified interval
/// filters proved them allowed: then they are, for any corners within those intervals (see
/// no_crossing).
template <class K, class PK>
bool meet_as_allowed(const ImproveState<K>& s, const Edit<K>& edit, const Tri<K, PK>& t, const Tri<K, PK>& u,
                     bool* by_intervals = nullptr) {
  if constexpr (!std::is_same_v<PK, K>) {
    // As written, a face two of whose corners round to one point is no triangle (CGAL's tests
    // do not take it): not tested as written. It was tested as it is; and if it stays, seam
    // check refuses the output (two vertices at one point).
    if (two_coincide(t.p[0], t.p[1], t.p[2]) || two_coincide(u.p[0], u.p[1], u.p[2])) return true;
  }
  const auto proved = [by_intervals] {
    if (by_intervals) *by_intervals = true;
    return true;
  };
  int shared = 0;
  std::array<int, 3> in_u{-1, -1, -1};  // for each corner of t, the same corner of u
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (same_corner<K>(t.id[std::size_t(i)], u.id[std::size_t(j)])) in_u[std::size_t(i)] = j, ++shared;
  using T3 = typename PK::Triangle_3;
  using S3 = typename PK::Segment_3;
  if (shared == 0) {
    if (certified::surely_disjoint({&t.ip[0], &t.ip[1], &t.ip[2]}, {&u.ip[0], &u.ip[1], &u.ip[2]})) return proved();
    return !CGAL::do_intersect(T3(t.p[0], t.p[1], t.p[2]), T3(u.p[0], u.p[1], u.p[2]));
  }
  if (shared == 1) {
    const int i = int(std::find_if(in_u.begin(), in_u.end(), [](int x) { return x >= 0; }) - in_u.begin());
    const int j = in_u[std::size_t(i)];
    const auto& tp = t.p;
    const auto& up = u.p;
    const std::size_t i1 = std::size_t((i + 1) % 3), i2 = std::size_t((i + 2) % 3);
    const std::size_t j1 = std::size_t((j + 1) % 3), j2 = std::size_t((j + 2) % 3);
    const auto sure = certified::surely_only_vertex(t.ip[std::size_t(i)], t.ip[i1], t.ip[i2], u.ip[j1], u.ip[j2]);
    if (sure) return *sure ? proved() : false;
    if (const auto along = only_vertex_along_edges(tp[std::size_t(i)], tp[i1], tp[i2], up[j1], up[j2])) return *along;
    return !CGAL::do_intersect(S3(tp[i1], tp[i2]), T3(up[0], up[1], up[2])) &&
           !CGAL::do_intersect(S3(up[j1], up[j2]), T3(tp[0], tp[1], tp[2]));
  }
  if (shared == 2) {
    std::array<std::size_t, 2> ti{}, uj{};
    std::size_t n = 0, k = 3;
    for (std::size_t i = 0; i < 3; ++i)
      if (in_u[i] >= 0) ti[n] = i, uj[n] = std::size_t(in_u[i]), ++n;
      else k = i;
    const std::size_t l = 3 - uj[0] - uj[1];  // u's third corner
    if (t.id[0].mesh != u.id[0].mesh &&
        !segment_after(s, edit, t.id[ti[0]].point, t.id[ti[1]].point, t.id[0].mesh, u.id[0].mesh))
      return false;
    if (certified::surely_only_edge(t.ip[ti[0]], t.ip[ti[1]], t.ip[k], u.ip[l])) return proved();
    if (!CGAL::coplanar(t.p[ti[0]], t.p[ti[1]], t.p[k], u.p[l])) return true;
    return CGAL::coplanar_orientation(t.p[ti[0]], t.p[ti[1]], t.p[k], u.p[l]) == CGAL::NEGATIVE;
  }
  return false;  // the same triangle twice
}

/// The point in kernel PK: itself, or rounded to doubles as the writer rounds it (Filtered).
template <class PK, class P> typename PK::Point_3 point_in(const P& p) {
  if constexpr (std::is_same_v<typename PK::Point_3, P>)
    return p;
  else
    return to_filtered(p);
}

template <class K, class PK>
Tri<K, PK> existing_tri(const ImproveState<K>& s, std::size_t m, typename Mesh<K>::Face_index f) {
  Tri<K, PK> t;
  const auto c = s.corners(m, f);
  t.doubles = true;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& p = s.mesh(m).point(c[i]);
    t.p[i] = point_in<PK>(p);
    t.id[i] = {m, c[i], false, s.meshes[m].point[c[i]]};
    t.doubles = t.doubles && is_double_by_approximation(p);
  }
  t.intervals();
  return t;
}

template <class K, class PK>
Tri<K, PK> new_tri(const ImproveState<K>& s, const Edit<K>& edit, const EditPart<K>& part, std::size_t i) {
  Tri<K, PK> t;
  const int fresh_id = edit.fresh_curve_point ? int(s.points.size()) : -1;
  t.doubles = true;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& c = part.added[i][k];
    t.p[k] = point_in<PK>(c.p);
    t.id[k] = {part.mesh, c.v, c.fresh, c.fresh ? fresh_id : s.meshes[part.mesh].point[c.v]};
    t.doubles = t.doubles && is_double_by_approximation(c.p);
  }
  t.intervals();
  return t;
}

/// The new face lies within the tolerance of the input surface and turns less than 80 degrees
/// from it there (from the input face closest to its centroid; doubles). A face thinner than the
/// vertex separation (its height on its longest edge) has no normal worth the name: rounding
/// decides it. It is held to the distance (and, by the caller, to the crossing tests) only; so is
/// a face whose cross product is 0 in doubles, if `coincident_corners_allowed`
/// (Edit::coincident_corners_allowed).
template <class K>
Verdict near_input(const ImproveState<K>& s, std::size_t m, const Tri<K, K>& t, bool coincident_corners_allowed) {
  const Filtered::Point_3 p = to_filtered(t.p[0]), q = to_filtered(t.p[1]), r = to_filtered(t.p[2]);
  const Filtered::Vector_3 n = CGAL::cross_product(q - p, r - p);
  const double len = std::sqrt(n.squared_length());
  const double longest = std::sqrt(std::max({CGAL::squared_distance(p, q), CGAL::squared_distance(q, r),
                                             CGAL::squared_distance(r, p)}));
  if (!(len > 0) && !(coincident_corners_allowed && longest > 0)) return Verdict::shape;
  const bool thinner_than_separation = !(len > 0) || len / longest < s.options.min_separation;
  const double slack = 1e-9 * s.mean_edge;
  const auto normal = s.meshes[m].input->face_within(p, q, r, s.tolerance + slack);
  if (!normal) return Verdict::tolerance;
  if (!thinner_than_separation && n * *normal < std::cos(80 * M_PI / 180) * len) return Verdict::shape;
  return Verdict::accepted;
}

/// The box of an edit part's new face i: from the corners' boxes (under Exact, their intervals,
/// which hold the corners as they are and as written).
template <class K> CGAL::Bbox_3 new_face_box(const EditPart<K>& part, std::size_t i) {
  CGAL::Bbox_3 box;
  for (const auto& c : part.added[i]) box += c.p.bbox();
  return box;
}

/// Per part of the edit: the faces of the meshes that the edit keeps (live, not removed by it)
/// whose boxes overlap the box of the part's new faces, with their boxes; one grid query per part.
/// Each new face is then tested against those whose boxes overlap its own: the faces one query per
/// new face would give. The boxes hold the faces as they are and as written, so these serve both
/// crossing tests.
using NearbyFaces = std::vector<std::vector<FaceGrid::Item>>;
template <class K> NearbyFaces nearby_faces(const ImproveState<K>& s, const Edit<K>& edit) {
  auto removed = [&](std::size_t m, typename Mesh<K>::Face_index f) {
    for (const auto& part : edit.parts)
      if (part.mesh == m && std::find(part.removed.begin(), part.removed.end(), f) != part.removed.end()) return true;
    return false;
  };
  NearbyFaces near(edit.parts.size());
  for (std::size_t k = 0; k < edit.parts.size(); ++k) {
    if (edit.parts[k].added.empty()) continue;
    CGAL::Bbox_3 box;
    for (std::size_t i = 0; i < edit.parts[k].added.size(); ++i) box += new_face_box(edit.parts[k], i);
    for (const FaceGrid::Item& item : s.grid.query_items(box)) {
      const typename Mesh<K>::Face_index f(item.entry.face);
      if (!s.is_live(item.entry) || removed(item.entry.mesh, f)) continue;
      near[k].push_back(item);
    }
  }
  return near;
}

/// Per part k, new face i and nearby face j (`near`): whether the pair is to be tested as written.
using Recheck = std::vector<std::vector<std::vector<bool>>>;

/// Whether the new faces of the edit meet the faces of the meshes it keeps (`near`, from
/// nearby_faces) and each other only as allowed; on the corners as they are (PK = K), or rounded
/// as written (Filtered). `tested_as_they_are`: the test on the corners as they are has passed,
/// so a pair of triangles whose corners are all doubles (the same as written) is not tested again.
/// `record` (the test as they are): marks the pairs of a new face and a nearby face that the
/// certified interval filters did not prove allowed. `recheck` (as written, after that): only
/// those pairs are tested. A proof by intervals holds for any corners within the intervals, and
/// the corners as written (the middles of the same approximations, or of narrower ones once a
/// lazy number is refined) lie within them.
template <class K, class PK>
bool no_crossing(const ImproveState<K>& s, const Edit<K>& edit, const NearbyFaces& near, bool tested_as_they_are,
                 Recheck* record = nullptr, const Recheck* recheck = nullptr) {
  std::vector<std::vector<Tri<K, PK>>> made(edit.parts.size());
  for (std::size_t k = 0; k < edit.parts.size(); ++k)
    for (std::size_t i = 0; i < edit.parts[k].added.size(); ++i)
      made[k].push_back(new_tri<K, PK>(s, edit, edit.parts[k], i));
  auto settled = [&](const Tri<K, PK>& t, const Tri<K, PK>& u) { return tested_as_they_are && t.doubles && u.doubles; };
  if (record) {
    record->assign(edit.parts.size(), {});
    for (std::size_t k = 0; k < edit.parts.size(); ++k) (*record)[k].assign(made[k].size(), std::vector<bool>(near[k].size()));
  }
  for (std::size_t k = 0; k < edit.parts.size(); ++k) {
    std::vector<std::optional<Tri<K, PK>>> kept(near[k].size());  // made once per edit, when needed
    for (std::size_t i = 0; i < made[k].size(); ++i) {
      const Tri<K, PK>& t = made[k][i];
      const CGAL::Bbox_3 box = new_face_box(edit.parts[k], i);
      for (std::size_t j = 0; j < near[k].size(); ++j) {
        const FaceGrid::Item& item = near[k][j];
        if (!CGAL::do_overlap(item.box, box) || (recheck && !(*recheck)[k][i][j])) continue;
        if (!kept[j])
          kept[j] = existing_tri<K, PK>(s, item.entry.mesh, typename Mesh<K>::Face_index(item.entry.face));
        if (settled(t, *kept[j])) continue;
        bool by_intervals = false;
        if (!meet_as_allowed<K, PK>(s, edit, t, *kept[j], &by_intervals)) return false;
        if (record) (*record)[k][i][j] = !by_intervals;
      }
      for (std::size_t l = k + 1; l < edit.parts.size(); ++l)  // new faces of the other meshes
        for (const Tri<K, PK>& u : made[l])
          if (edit.parts[l].mesh != edit.parts[k].mesh && !settled(t, u) && !meet_as_allowed<K, PK>(s, edit, t, u))
            return false;
    }
  }
  return true;
}

/// Whether a face the edit removes meets a face it keeps otherwise than allowed, rounded as
/// written: a crossing the edit cannot make worse there.
template <class K> bool removes_a_written_crossing(const ImproveState<K>& s, const Edit<K>& edit) {
  const Edit<K> none;  // the curves as they are before the edit
  for (const auto& part : edit.parts)
    for (const auto f0 : part.removed) {
      const auto t = existing_tri<K, Filtered>(s, part.mesh, f0);
      CGAL::Bbox_3 box;
      for (const auto& p : t.p) box += p.bbox();  // conservative: from the intervals under Exact
      for (const auto& e : s.grid.query(box)) {
        const typename Mesh<K>::Face_index f(e.face);
        if ((e.mesh == part.mesh && f == f0) || !s.is_live(e)) continue;
        if (!meet_as_allowed<K, Filtered>(s, none, t, existing_tri<K, Filtered>(s, e.mesh, f))) return true;
      }
    }
  return false;
}

/// Whether the edit's fresh point, rounded as written, lies closer than min_separation to a
/// vertex of any mesh (distance 0 included: two distinct vertices at one point; the fresh point
/// is no vertex yet, so none may be there, in the meshes that get it or in the others).
template <class K> bool too_near_a_vertex(const ImproveState<K>& s, const Edit<K>& edit) {
  const double sep = s.options.min_separation;
  const Filtered::Point_3 p = to_filtered(edit.fresh_point);
  const CGAL::Bbox_3 box(p.x() - sep, p.y() - sep, p.z() - sep, p.x() + sep, p.y() + sep, p.z() + sep);
  for (const auto& e : s.grid.query(box)) {
    const typename Mesh<K>::Face_index f(e.face);
    if (!s.is_live(e)) continue;
    for (const auto v : s.corners(e.mesh, f))
      if (CGAL::squared_distance(p, s.fpoint(e.mesh, v)) < sep * sep) return true;
  }
  return false;
}

template <class K> Verdict judge(const ImproveState<K>& s, const Edit<K>& edit) {
  if (!keeps_curve_points<K>(s, edit)) return Verdict::shape;
  for (const auto& part : edit.parts)
    for (const auto& a : part.added) {
      if (CGAL::collinear(a[0].p, a[1].p, a[2].p)) return Verdict::shape;
      if constexpr (kernel_traits<K>::exact_constructions) {  // once written
        const auto p0 = to_filtered(a[0].p), p1 = to_filtered(a[1].p), p2 = to_filtered(a[2].p);
        if (edit.coincident_corners_allowed && two_coincide(p0, p1, p2)) continue;
        if (CGAL::collinear(p0, p1, p2)) return Verdict::shape;
      }
    }
  if (edit.has_fresh && s.options.min_separation > 0 && too_near_a_vertex<K>(s, edit)) return Verdict::separation;
  if (!edit.keeps_surface && !(s.tolerance > 0)) return Verdict::tolerance;  // no tolerance: the surfaces stay
  NearbyFaces near;
  Recheck recheck;  // the pairs to test again as written (if tested as they are)
  if (edit.keeps_surface) {  // the new point lies on the current surface: within the tolerance of the input too?
    if (edit.has_fresh) {
      const double slack = 1e-9 * s.mean_edge;
      const Filtered::Point_3 p = to_filtered(edit.fresh_point);
      for (const auto& part : edit.parts)
        if (!s.meshes[part.mesh].input->within(p, s.tolerance + slack)) return Verdict::tolerance;
    }
  } else {
    for (std::size_t k = 0; k < edit.parts.size(); ++k)
      for (std::size_t i = 0; i < edit.parts[k].added.size(); ++i)
        if (const Verdict v = near_input<K>(s, edit.parts[k].mesh, new_tri<K, K>(s, edit, edit.parts[k], i),
                                            edit.coincident_corners_allowed);
            v != Verdict::accepted)
          return v;
    near = nearby_faces<K>(s, edit);
    if (!no_crossing<K, K>(s, edit, near, false, &recheck)) return Verdict::crossing;  // exactly
  }
  if constexpr (kernel_traits<K>::exact_constructions) {
    // As written; unless a face it removes already crosses once written (the embedding's
    // rounding): an edit that does not add a crossing where there is one is not refused for it.
    const bool tested_as_they_are = !edit.keeps_surface;
    if (edit.keeps_surface) near = nearby_faces<K>(s, edit);
    if (!no_crossing<K, Filtered>(s, edit, near, tested_as_they_are, nullptr, tested_as_they_are ? &recheck : nullptr) &&
        !removes_a_written_crossing<K>(s, edit))
      return Verdict::crossing;
  }
  return Verdict::accepted;
}

}  // namespace

template <class K> bool keeps_curve_points(const ImproveState<K>& s, const Edit<K>& edit) {
  for (const auto& part : edit.parts) {
    const auto& g = s.mesh(part.mesh);
    for (const auto f : part.removed)
      for (const auto v : CGAL::vertices_around_face(g.halfedge(f), g)) {
        const int id = s.meshes[part.mesh].point[v];
        if (id < 0 || id == edit.merged_point) continue;
        bool kept = false;  // a face of v outside the region
        for (const auto fv : CGAL::faces_around_target(g.halfedge(v), g))
          kept = kept || (fv != Mesh<K>::null_face() &&
                          std::find(part.removed.begin(), part.removed.end(), fv) == part.removed.end());
        if (!kept) return false;
      }
  }
  return true;
}

template <class K> Verdict accept_edit(ImproveState<K>& s, const Edit<K>& edit) {
  Verdict v = Verdict::shape;
  try {
    v = judge<K>(s, edit);
  } catch (const CGAL::Failure_exception&) {  // a precondition of a rounded kernel: refused
    v = Verdict::shape;
  }
  if (v == Verdict::tolerance) ++s.stats.refused_tolerance;
  if (v == Verdict::crossing) ++s.stats.refused_crossing;
  if (v == Verdict::shape) ++s.stats.refused_shape;
  if (v == Verdict::separation) ++s.stats.refused_separation;
  return v;
}

#define SEAM_INSTANTIATE(K)                                          \
  template Verdict accept_edit<K>(ImproveState<K>&, const Edit<K>&); \
  template bool keeps_curve_points<K>(const ImproveState<K>&, const Edit<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
