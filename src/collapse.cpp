// seam, pair: collapse short curve segments in both meshes. See seam/internal/collapse.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/collapse.h>
#include <seam/quality.h>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <utility>

namespace seam::internal {

namespace {

template <class K> using VertexLists = std::vector<std::vector<typename MeshTypes<K>::V>>;

/// One mesh's side of a collapse of the curve segment (P, Q): P is merged into Q.
template <class K> struct Side {
  using T = MeshTypes<K>;
  typename T::V p, q;
};

/// A candidate: curve c, the positions of P and Q in it, |PQ| (rounded).
struct Candidate {
  std::size_t curve, at_p, at_q;
  double length;
};

/// The smallest angle of some faces and how many are below 10 degrees.
struct Angles {
  double min = 180;
  std::size_t below_10 = 0;
  void add(double angle) {
    min = std::min(min, angle);
    below_10 += angle < 10 ? 1 : 0;
  }
  /// Better: fewer faces below 10 degrees without the smallest angle halving, or as many and a
  /// larger smallest angle.
  bool better_than(const Angles& o) const {
    if (below_10 != o.below_10) return below_10 < o.below_10 && min >= 0.5 * o.min;
    return min > o.min;
  }
};

template <class K> double face_min_angle(const Mesh<K>& m, typename MeshTypes<K>::F f) {
  const auto h = m.halfedge(f);
  return min_angle_deg(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
}

/// Can P merge into Q in `m`? Fills the smallest angle of the faces around P and Q before and
/// after. Exact tests for degeneracy and orientation under the exact kernel.
template <class K>
bool collapse_allowed(const Mesh<K>& m, typename MeshTypes<K>::V p, typename MeshTypes<K>::V q,
                      std::size_t input_vertices, Angles& before, Angles& after) {
  using V = typename MeshTypes<K>::V;
  const auto h = m.halfedge(p, q);
  if (h == Mesh<K>::null_halfedge() || m.is_border(p) || m.is_border(q)) return false;
  if (std::size_t(p) < input_vertices) return false;
  // CGAL keeps the target of the edge's own halfedge: the other vertex's index goes away.
  const auto e = m.edge(h);
  const V kept = m.target(m.halfedge(e));
  if (kept == p && std::size_t(q) < input_vertices) return false;
  if (!CGAL::Euler::does_satisfy_link_condition(e, m)) return false;
  before = after = Angles{};
  const auto& pq = m.point(q);
  for (auto f : CGAL::faces_around_target(m.halfedge(q), m)) {
    const double angle = face_min_angle<K>(m, f);
    before.add(angle);
    bool has_p = false;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) has_p = has_p || v == p;
    if (!has_p) after.add(angle);
  }
  for (auto f : CGAL::faces_around_target(m.halfedge(p), m)) {
    std::array<typename K::Point_3, 3> c;
    bool has_q = false;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      has_q = has_q || v == q;
      c[k++] = m.point(v);
    }
    if (!has_q) before.add(min_angle_deg(c[0], c[1], c[2]));  // faces with Q were counted above
    if (has_q) continue;  // removed by the collapse
    std::array<typename K::Point_3, 3> d = c;
    int kp = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (v == p) break;
      ++kp;
    }
    d[kp] = pq;
    if (CGAL::collinear(d[0], d[1], d[2])) return false;
    const auto n0 = CGAL::cross_product(c[1] - c[0], c[2] - c[0]);
    const auto n1 = CGAL::cross_product(d[1] - d[0], d[2] - d[0]);
    if (CGAL::sign(n0 * n1) != CGAL::POSITIVE) return false;
    after.add(min_angle_deg(d[0], d[1], d[2]));
  }
  return true;
}

/// Vertices of the faces around v.
template <class K> void ring(const Mesh<K>& m, typename MeshTypes<K>::V v, std::vector<typename MeshTypes<K>::V>& out) {
  out.push_back(v);
  for (auto u : CGAL::vertices_around_target(m.halfedge(v), m)) out.push_back(u);
}

/// Merges P into Q; returns the vertex that stays (it holds Q's point).
template <class K> typename MeshTypes<K>::V merge(Mesh<K>& m, typename MeshTypes<K>::V p, typename MeshTypes<K>::V q) {
  const auto point = m.point(q);
  const auto kept = CGAL::Euler::collapse_edge(m.edge(m.halfedge(p, q)), m);
  m.point(kept) = point;
  return kept;
}

/// Faces of `m` in `faces` that meet `other` anywhere but in a common curve vertex or along a
/// common curve segment. Exact predicates (do_intersect, coplanarity) on the kernel's points.
template <class K>
std::vector<char> crossing_faces(const Mesh<K>& m, const std::vector<typename MeshTypes<K>::F>& faces,
                                 const Mesh<K>& other, const std::vector<char>& on_curve_other,
                                 const std::set<std::pair<std::uint32_t, std::uint32_t>>& curve_edges_other) {
  using F = typename MeshTypes<K>::F;
  using V = typename MeshTypes<K>::V;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  auto box_of = [](const Mesh<K>& mesh, F f, std::size_t info) {
    CGAL::Bbox_3 b;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) b += to_filtered(mesh.point(v)).bbox();
    return Box(b, info);
  };
  std::vector<Box> mine, theirs;
  for (std::size_t i = 0; i < faces.size(); ++i) mine.push_back(box_of(m, faces[i], i));
  for (auto f : other.faces()) theirs.push_back(box_of(other, f, std::size_t(f)));
  std::vector<char> bad(faces.size(), 0);
  auto corners = [](const Mesh<K>& mesh, F f) {
    std::array<V, 3> c;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) c[k++] = v;
    return c;
  };
  using Triangle = typename K::Triangle_3;
  using Segment = typename K::Segment_3;
  auto test = [&](const Box& bm, const Box& bo) {
    const std::size_t i = bm.info();
    if (bad[i]) return;
    const auto cm = corners(m, faces[i]);
    const auto co = corners(other, F(typename F::size_type(bo.info())));
    std::array<typename K::Point_3, 3> pm, po;
    for (int k = 0; k < 3; ++k) pm[k] = m.point(cm[k]), po[k] = other.point(co[k]);
    int shared = 0, jm[3] = {-1, -1, -1};  // jm[k]: corner of the face of m at corner k of the other's
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        if (pm[j] == po[k]) jm[k] = j, ++shared;
    const Triangle tm(pm[0], pm[1], pm[2]), to(po[0], po[1], po[2]);
    bool crossing = false;
    if (shared == 0) {
      crossing = CGAL::do_intersect(tm, to);
    } else if (shared == 1) {
      int k = 0;
      while (jm[k] < 0) ++k;
      const int j = jm[k];
      // They meet in more than the common corner iff an opposite edge meets the other face.
      crossing = !on_curve_other[std::size_t(co[k])] ||
                 CGAL::do_intersect(Segment(pm[(j + 1) % 3], pm[(j + 2) % 3]), to) ||
                 CGAL::do_intersect(Segment(po[(k + 1) % 3], po[(k + 2) % 3]), tm);
    } else if (shared == 2) {
      int k = 0;
      while (jm[k] >= 0) ++k;
      const auto u = std::uint32_t(co[(k + 1) % 3]), w = std::uint32_t(co[(k + 2) % 3]);
      const int j = 3 - jm[(k + 1) % 3] - jm[(k + 2) % 3];
      const auto &p = po[(k + 1) % 3], &q = po[(k + 2) % 3];
      // Faces with a common edge overlap iff they are coplanar and on the same side of it.
      crossing = !curve_edges_other.count({std::min(u, w), std::max(u, w)}) ||
                 (CGAL::coplanar(p, q, po[k], pm[j]) && CGAL::coplanar_orientation(p, q, po[k], pm[j]) == CGAL::POSITIVE);
    } else {
      crossing = true;
    }
    if (crossing) bad[i] = 1;
  };
  CGAL::box_intersection_d(mine.begin(), mine.end(), theirs.begin(), theirs.end(), test);
  return bad;
}

template <class K>
void curve_marks(const Mesh<K>& m, const VertexLists<K>& lists, std::vector<char>& on_curve,
                 std::set<std::pair<std::uint32_t, std::uint32_t>>& edges) {
  on_curve.assign(m.number_of_vertices() + m.number_of_removed_vertices(), 0);
  edges.clear();
  for (const auto& vs : lists)
    for (std::size_t i = 0; i < vs.size(); ++i) {
      on_curve[std::size_t(vs[i])] = 1;
      if (i + 1 < vs.size()) {
        const auto u = std::uint32_t(vs[i]), w = std::uint32_t(vs[i + 1]);
        edges.insert({std::min(u, w), std::max(u, w)});
      }
    }
}

/// Removes garbage and maps the vertex lists to the new indices.
template <class K> void compact(Mesh<K>& m, VertexLists<K>& lists) {
  using V = typename MeshTypes<K>::V;
  auto [old_index, created] = m.template add_property_map<V, std::uint32_t>("v:seam_collapse_old_index", 0);
  for (auto v : m.vertices()) old_index[v] = std::uint32_t(v);
  m.collect_garbage();
  std::vector<std::pair<std::uint32_t, V>> pairs;
  for (auto v : m.vertices()) pairs.push_back({old_index[v], v});
  std::sort(pairs.begin(), pairs.end());
  for (auto& vs : lists)
    for (auto& v : vs) {
      const auto it = std::lower_bound(pairs.begin(), pairs.end(), std::uint32_t(v),
                                       [](const std::pair<std::uint32_t, V>& x, std::uint32_t y) { return x.first < y; });
      if (it == pairs.end() || it->first != std::uint32_t(v)) throw InternalError("collapse: a curve vertex was lost");
      v = it->second;
    }
  m.remove_property_map(old_index);
}

}  // namespace

template <class K>
CurveCollapseReport collapse_short_curve_segments(Mesh<K>& a, Mesh<K>& b, std::vector<Polyline<K>>& curves,
                                                  VertexLists<K>& cva, VertexLists<K>& cvb, double max_length,
                                                  std::size_t input_vertices_a, std::size_t input_vertices_b) {
  using V = typename MeshTypes<K>::V;
  using F = typename MeshTypes<K>::F;
  CurveCollapseReport report;
  if (!(max_length > 0) || curves.empty()) return report;
  if (cva.size() != curves.size() || cvb.size() != curves.size())
    throw InternalError("collapse: curve vertex lists do not match the curves");

  std::set<std::array<std::size_t, 3>> excluded;  // candidates (curve, P, Q) refused or undone
  for (int round = 0; round < 12; ++round) {
    // How often each vertex appears on the curves (closing repeats once): only vertices on one
    // curve, once, are merged.
    std::vector<int> uses_a(a.number_of_vertices() + a.number_of_removed_vertices(), 0),
        uses_b(b.number_of_vertices() + b.number_of_removed_vertices(), 0);
    std::vector<Candidate> candidates;
    for (std::size_t c = 0; c < curves.size(); ++c) {
      const bool closed = is_closed(curves[c]);
      const std::size_t n = closed ? curves[c].size() - 1 : curves[c].size();
      for (std::size_t i = 0; i < n; ++i) ++uses_a[std::size_t(cva[c][i])], ++uses_b[std::size_t(cvb[c][i])];
      if (n < (closed ? 4u : 3u)) continue;  // keep at least a triangle / a segment
      for (std::size_t i = closed ? 0 : 1; i < (closed ? n : n - 1); ++i)
        for (int dir : {-1, 1}) {
          const std::size_t j = (i + n + std::size_t(dir)) % n;
          const auto& p = curves[c][i];
          const auto& q = curves[c][j];
          const double len = std::sqrt(CGAL::to_double(CGAL::squared_distance(p, q)));
          if (len <= max_length) candidates.push_back({c, i, j, len});
        }
    }
    if (candidates.empty()) break;
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
      return x.length != y.length ? x.length < y.length : std::tie(x.curve, x.at_p) < std::tie(y.curve, y.at_p);
    });

    // Choose collapses whose neighbourhoods do not overlap, each improving the angles in both.
    std::vector<char> locked_a(uses_a.size(), 0), locked_b(uses_b.size(), 0);
    std::vector<Candidate> chosen;
    std::vector<V> near;
    for (const auto& cand : candidates) {
      const std::array<std::size_t, 3> key{cand.curve, cand.at_p, cand.at_q};
      if (excluded.count(key)) continue;
      const V pa = cva[cand.curve][cand.at_p], qa = cva[cand.curve][cand.at_q];
      const V pb = cvb[cand.curve][cand.at_p], qb = cvb[cand.curve][cand.at_q];
      if (uses_a[std::size_t(pa)] != 1 || uses_b[std::size_t(pb)] != 1) continue;
      near.clear();
      ring<K>(a, pa, near), ring<K>(a, qa, near);
      const bool free_a = std::none_of(near.begin(), near.end(), [&](V v) { return locked_a[std::size_t(v)]; });
      std::vector<V> near_b;
      ring<K>(b, pb, near_b), ring<K>(b, qb, near_b);
      const bool free_b = std::none_of(near_b.begin(), near_b.end(), [&](V v) { return locked_b[std::size_t(v)]; });
      if (!free_a || !free_b) continue;
      Angles before_a, after_a, before_b, after_b;
      const bool oka = collapse_allowed<K>(a, pa, qa, input_vertices_a, before_a, after_a);
      const bool okb = oka && collapse_allowed<K>(b, pb, qb, input_vertices_b, before_b, after_b);
      Angles before = before_a, after = after_a;  // both meshes' faces around P and Q together
      before.min = std::min(before.min, before_b.min), before.below_10 += before_b.below_10;
      after.min = std::min(after.min, after_b.min), after.below_10 += after_b.below_10;
      if (!oka || !okb || !after.better_than(before)) {
        excluded.insert(key);
        continue;
      }
      for (V v : near) locked_a[std::size_t(v)] = 1;
      for (V v : near_b) locked_b[std::size_t(v)] = 1;
      chosen.push_back(cand);
    }
    if (chosen.empty()) break;

    // Apply them; undo (start again from the copies without them) those whose faces cross.
    const Mesh<K> a0 = a, b0 = b;
    for (;;) {
      std::vector<V> kept_a, kept_b;
      for (const auto& cand : chosen) {
        kept_a.push_back(merge<K>(a, cva[cand.curve][cand.at_p], cva[cand.curve][cand.at_q]));
        kept_b.push_back(merge<K>(b, cvb[cand.curve][cand.at_p], cvb[cand.curve][cand.at_q]));
      }
      // The curves after the collapses, by the vertices that stay.
      auto lists_a = cva, lists_b = cvb;
      auto without_p = [&](VertexLists<K>& lists, const std::vector<V>& kept) {
        std::vector<std::vector<char>> drop(lists.size());
        for (std::size_t c = 0; c < lists.size(); ++c) drop[c].assign(lists[c].size(), 0);
        for (std::size_t k = 0; k < chosen.size(); ++k) {
          auto& vs = lists[chosen[k].curve];
          const bool closed = vs.size() > 1 && vs.front() == vs.back();
          drop[chosen[k].curve][chosen[k].at_p] = 1;
          vs[chosen[k].at_q] = kept[k];
          if (closed && chosen[k].at_q == 0) vs.back() = kept[k];
          if (closed && chosen[k].at_p == 0) drop[chosen[k].curve].back() = 1;
        }
        for (std::size_t c = 0; c < lists.size(); ++c) {
          std::vector<V> out;
          for (std::size_t i = 0; i < lists[c].size(); ++i)
            if (!drop[c][i]) out.push_back(lists[c][i]);
          if (drop[c].back() && !out.empty() && lists[c].front() == lists[c].back()) out.push_back(out.front());
          lists[c] = std::move(out);
        }
      };
      without_p(lists_a, kept_a);
      without_p(lists_b, kept_b);

      std::vector<char> on_a, on_b;
      std::set<std::pair<std::uint32_t, std::uint32_t>> edges_a, edges_b;
      curve_marks<K>(a, lists_a, on_a, edges_a);
      curve_marks<K>(b, lists_b, on_b, edges_b);
      std::vector<F> faces_a, faces_b;
      std::vector<std::size_t> owner_a, owner_b;
      for (std::size_t k = 0; k < chosen.size(); ++k) {
        for (auto f : CGAL::faces_around_target(a.halfedge(kept_a[k]), a)) faces_a.push_back(f), owner_a.push_back(k);
        for (auto f : CGAL::faces_around_target(b.halfedge(kept_b[k]), b)) faces_b.push_back(f), owner_b.push_back(k);
      }
      const auto bad_a = crossing_faces<K>(a, faces_a, b, on_b, edges_b);
      const auto bad_b = crossing_faces<K>(b, faces_b, a, on_a, edges_a);
      std::vector<char> undo(chosen.size(), 0);
      for (std::size_t i = 0; i < faces_a.size(); ++i)
        if (bad_a[i]) undo[owner_a[i]] = 1;
      for (std::size_t i = 0; i < faces_b.size(); ++i)
        if (bad_b[i]) undo[owner_b[i]] = 1;
      if (std::none_of(undo.begin(), undo.end(), [](char u) { return u != 0; })) {
        auto is_new_a = a.template property_map<F, bool>(new_face_property);
        auto is_new_b = b.template property_map<F, bool>(new_face_property);
        if (is_new_a.second)
          for (auto f : faces_a) is_new_a.first[f] = true;
        if (is_new_b.second)
          for (auto f : faces_b) is_new_b.first[f] = true;
        // The shared curves lose the merged points.
        std::vector<std::vector<char>> drop(curves.size());
        for (std::size_t c = 0; c < curves.size(); ++c) drop[c].assign(curves[c].size(), 0);
        for (const auto& cand : chosen) {
          drop[cand.curve][cand.at_p] = 1;
          if (cand.at_p == 0 && is_closed(curves[cand.curve])) drop[cand.curve].back() = 1;
        }
        for (std::size_t c = 0; c < curves.size(); ++c) {
          const bool closed = is_closed(curves[c]);
          Polyline<K> out;
          for (std::size_t i = 0; i < curves[c].size(); ++i)
            if (!drop[c][i]) out.push_back(curves[c][i]);
          if (closed && drop[c].back()) out.push_back(out.front());
          curves[c] = std::move(out);
        }
        cva = std::move(lists_a);
        cvb = std::move(lists_b);
        report.collapsed += chosen.size();
        break;
      }
      a = a0;
      b = b0;
      std::vector<Candidate> keep;
      for (std::size_t k = 0; k < chosen.size(); ++k)
        if (undo[k]) {
          excluded.insert({chosen[k].curve, chosen[k].at_p, chosen[k].at_q});
        } else {
          keep.push_back(chosen[k]);
        }
      chosen = std::move(keep);
      if (chosen.empty()) break;
    }
    if (chosen.empty()) continue;
    compact<K>(a, cva);
    compact<K>(b, cvb);
    excluded.clear();  // positions moved: the next round evaluates every short segment again
  }
  for (const auto& c : curves)  // what is left
    for (std::size_t i = 0; i + 1 < c.size(); ++i)
      if (std::sqrt(CGAL::to_double(CGAL::squared_distance(c[i], c[i + 1]))) <= max_length) ++report.refused;
  return report;
}

#define SEAM_INSTANTIATE(K)                                                                                     \
  template CurveCollapseReport collapse_short_curve_segments<K>(                                                 \
      Mesh<K>&, Mesh<K>&, std::vector<Polyline<K>>&, VertexLists<K>&, VertexLists<K>&, double, std::size_t, \
      std::size_t);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
