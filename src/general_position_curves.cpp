// seam internal: the intersection curves of two meshes in general position, computed directly.
// See include/seam/internal/general_position_curves.h.
//
// Why not always CGAL's surface_intersection: it handles every degenerate contact (vertices on
// faces, coplanar faces), and pays for that on every input: on the 77k/64k-face benchmark pair it
// costs as much as the whole of CGAL's corefine. Generic tow pairs (crossings without snapping)
// are in general position; this path decides that with the same exact predicates and stops at the
// first zero, so nothing degenerate is ever decided here.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/general_position_curves.h>

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/box_intersection_d.h>

#include <tbb/parallel_for.h>

#ifndef CGAL_HAS_THREADS
#error "general_position_curves reads the meshes' lazy exact points on several threads: CGAL must be thread-aware"
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>

namespace seam::internal {

namespace {

/// A curve point: an edge of one mesh crossing the inside of a face of the other.
struct CrossingKey {
  std::uint32_t edge_of_b = 0;  ///< 0: an edge of A and a face of B; 1: an edge of B and a face of A
  std::uint32_t edge = 0, face = 0;
  bool operator<(const CrossingKey& o) const {
    return std::tie(edge_of_b, edge, face) < std::tie(o.edge_of_b, o.edge, o.face);
  }
  bool operator==(const CrossingKey& o) const {
    return edge_of_b == o.edge_of_b && edge == o.edge && face == o.face;
  }
};

/// What two faces have in common: nothing, a segment between two crossing points, or a
/// configuration this path does not decide (a zero predicate).
struct FacePairResult {
  enum { none, segment, degenerate } kind = none;
  std::array<CrossingKey, 2> ends;
};

template <class K> struct FaceCorners {
  using M = Mesh<K>;
  std::array<typename M::Vertex_index, 3> v;
  std::array<typename M::Edge_index, 3> e;  ///< e[i] joins v[i] and v[(i + 1) % 3]
  FaceCorners(const M& m, typename M::Face_index f) {
    auto h = m.halfedge(f);
    for (int i = 0; i < 3; ++i, h = m.next(h)) {
      v[i] = m.source(h);
      e[i] = m.edge(h);
    }
  }
};

/// Where triangle `p` (of mesh P) and triangle `q` (of mesh Q) meet, from exact predicates only.
/// `p_is_b` says which mesh P is, for the keys.
/// The three corners of a face, by reference (copies of lazy points would each change a shared
/// reference count, on every core).
template <class K> using Corners = std::array<const typename K::Point_3*, 3>;

template <class K>
void crossings_of_edges(const Corners<K>& p, const FaceCorners<K>& pc, const std::array<CGAL::Orientation, 3>& side,
                        const Corners<K>& q, std::uint32_t q_face, std::uint32_t p_is_b, FacePairResult& r,
                        int& count) {
  for (int i = 0; i < 3 && r.kind != FacePairResult::degenerate; ++i) {
    const int j = (i + 1) % 3;
    if (side[i] == side[j]) continue;  // the edge does not cross q's plane
    // The edge crosses the plane; through the inside of q when it turns the same way about all
    // three edges of q. A zero: through an edge or vertex of q, or along a line through them.
    const auto s0 = CGAL::orientation(*p[i], *p[j], *q[0], *q[1]);
    const auto s1 = CGAL::orientation(*p[i], *p[j], *q[1], *q[2]);
    const auto s2 = CGAL::orientation(*p[i], *p[j], *q[2], *q[0]);
    const bool has_positive = s0 == CGAL::POSITIVE || s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE;
    const bool has_negative = s0 == CGAL::NEGATIVE || s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE;
    if (has_positive && has_negative) continue;  // misses q, surely
    if (s0 == CGAL::ZERO || s1 == CGAL::ZERO || s2 == CGAL::ZERO || count == 2) {
      r.kind = FacePairResult::degenerate;
      return;
    }
    r.ends[count++] = CrossingKey{p_is_b, std::uint32_t(pc.e[i]), q_face};
  }
}

template <class K>
FacePairResult meet(const Mesh<K>& a, typename Mesh<K>::Face_index fa, const Mesh<K>& b,
                    typename Mesh<K>::Face_index fb) {
  FacePairResult r;
  const FaceCorners<K> ca(a, fa), cb(b, fb);
  const Corners<K> pa{&a.point(ca.v[0]), &a.point(ca.v[1]), &a.point(ca.v[2])};
  const Corners<K> pb{&b.point(cb.v[0]), &b.point(cb.v[1]), &b.point(cb.v[2])};
  auto sides = [](const Corners<K>& plane, const Corners<K>& p) {
    return std::array<CGAL::Orientation, 3>{CGAL::orientation(*plane[0], *plane[1], *plane[2], *p[0]),
                                            CGAL::orientation(*plane[0], *plane[1], *plane[2], *p[1]),
                                            CGAL::orientation(*plane[0], *plane[1], *plane[2], *p[2])};
  };
  auto one_side = [](const std::array<CGAL::Orientation, 3>& s) {
    return s[0] != CGAL::ZERO && s[0] == s[1] && s[1] == s[2];
  };
  const auto side_a = sides(pb, pa);  // A's corners against B's plane
  if (one_side(side_a)) return r;
  const auto side_b = sides(pa, pb);
  if (one_side(side_b)) return r;
  for (const auto& s : {side_a, side_b})
    if (s[0] == CGAL::ZERO || s[1] == CGAL::ZERO || s[2] == CGAL::ZERO) {  // a corner in the other plane
      r.kind = FacePairResult::degenerate;
      return r;
    }
  // Both faces straddle the other's plane: they meet along the common line in the overlap of two
  // intervals, whose ends (in general position) are edges of one face crossing the other face.
  int count = 0;
  crossings_of_edges<K>(pa, ca, side_a, pb, std::uint32_t(fb), 0, r, count);
  if (r.kind != FacePairResult::degenerate) crossings_of_edges<K>(pb, cb, side_b, pa, std::uint32_t(fa), 1, r, count);
  if (r.kind == FacePairResult::degenerate) return r;
  if (count == 2)
    r.kind = FacePairResult::segment;
  else if (count != 0)
    r.kind = FacePairResult::degenerate;
  return r;
}

/// The parameter lambda at which p + lambda (q - p) lies in the plane through r, s and t (p and
/// q strictly on opposite sides of it), in the points' own kernel.
template <class P> auto crossing_parameter(const P& p, const P& q, const P& r, const P& s, const P& t) {
  const auto ds = s - r, dt = t - r;
  const auto du = CGAL::determinant(ds, dt, p - r), dv = CGAL::determinant(ds, dt, q - r);
  return du / (du - dv);
}

/// A point of a rounded kernel as an exact one (its doubles, exactly).
template <class P> Exact::Point_3 exactly(const P& x) {
  return Exact::Point_3(CGAL::to_double(x.x()), CGAL::to_double(x.y()), CGAL::to_double(x.z()));
}

/// Under a rounded kernel: the exact point where edge `e` of `m` crosses the plane of face `f` of
/// `other`, from the meshes' doubles.
template <class K>
Exact::Point_3 exact_crossing_point(const Mesh<K>& m, typename Mesh<K>::Edge_index e, const Mesh<K>& other,
                                    typename Mesh<K>::Face_index f) {
  const FaceCorners<K> c(other, f);
  const auto p = exactly(m.point(m.vertex(e, 0))), q = exactly(m.point(m.vertex(e, 1)));
  return p + (q - p) * crossing_parameter(p, q, exactly(other.point(c.v[0])), exactly(other.point(c.v[1])),
                                          exactly(other.point(c.v[2])));
}

/// The point where edge `e` of `m` crosses the plane of face `f` of `other`: exact under the
/// exact kernel, rounded under Epick (from the edge's end with the smaller index, so the same
/// doubles every time).
template <class K>
typename K::Point_3 crossing_point(const Mesh<K>& m, typename Mesh<K>::Edge_index e, const Mesh<K>& other,
                                   typename Mesh<K>::Face_index f) {
  auto u = m.vertex(e, 0), v = m.vertex(e, 1);
  if (v < u) std::swap(u, v);
  const FaceCorners<K> c(other, f);
  const auto &p = m.point(u), &q = m.point(v);
  // du and dv (see crossing_parameter) have opposite signs, decided exactly.
  const auto lambda = crossing_parameter(p, q, other.point(c.v[0]), other.point(c.v[1]), other.point(c.v[2]));
  if constexpr (!kernel_traits<K>::exact_constructions) {
    // Rounded determinants near a degenerate configuration can agree in sign or vanish (NaN or a
    // point off the edge): then the point is constructed exactly and rounded.
    const double l = CGAL::to_double(lambda);
    if (!(l >= 0 && l <= 1)) {
      const auto x = exact_crossing_point<K>(m, e, other, f);
      return typename K::Point_3(CGAL::to_double(CGAL::exact(x.x())), CGAL::to_double(CGAL::exact(x.y())),
                                 CGAL::to_double(CGAL::exact(x.z())));
    }
  }
  return p + (q - p) * lambda;
}

constexpr std::size_t no_point = std::size_t(-1);

/// Candidate face pairs: overlapping bounding boxes (of the exact kernel's interval
/// approximations: they contain the exact faces), sorted.
template <class K>
std::vector<std::pair<std::uint32_t, std::uint32_t>> candidate_face_pairs(const Mesh<K>& a, const Mesh<K>& b) {
  using F = typename Mesh<K>::Face_index;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  namespace PMP = CGAL::Polygon_mesh_processing;
  const CGAL::Bbox_3 box_a = PMP::bbox(a), box_b = PMP::bbox(b);
  auto boxes_near = [&](const Mesh<K>& m, const CGAL::Bbox_3& other) {
    std::vector<Box> boxes;
    for (F f : m.faces())
      if (const auto box = PMP::face_bbox(f, m); CGAL::do_overlap(box, other)) boxes.emplace_back(box, std::uint32_t(f));
    return boxes;
  };
  std::vector<Box> faces_a = boxes_near(a, box_b), faces_b = boxes_near(b, box_a);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates;
  CGAL::box_intersection_d(faces_a.begin(), faces_a.end(), faces_b.begin(), faces_b.end(),
                           [&](const Box& x, const Box& y) { candidates.emplace_back(x.info(), y.info()); });
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

/// Each candidate pair decided with exact predicates, on all cores; nothing when one is degenerate.
template <class K>
std::optional<std::vector<FacePairResult>> meet_all(const Mesh<K>& a, const Mesh<K>& b,
                                                    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& candidates) {
  using F = typename Mesh<K>::Face_index;
  std::vector<FacePairResult> met(candidates.size());
  std::atomic<bool> degenerate{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (degenerate.load(std::memory_order_relaxed)) return;
                        met[i] = meet<K>(a, F(candidates[i].first), b, F(candidates[i].second));
                        if (met[i].kind == FacePairResult::degenerate) degenerate = true;
                      }
                    });
  if (degenerate) return std::nullopt;
  return met;
}

/// The crossing points, each once (sorted keys), and per point its (at most two) neighbours and
/// the face pairs of the segments to them.
struct CrossingGraph {
  std::vector<CrossingKey> keys;
  std::vector<std::array<std::size_t, 2>> neighbours, segment_of;
};

/// Nothing when the segments do not form simple curves: three segments at one point, or two to
/// the same point (two faces with the same corners: a mesh meeting itself).
inline std::optional<CrossingGraph> crossing_graph(const std::vector<FacePairResult>& met) {
  CrossingGraph g;
  for (const auto& m : met)
    if (m.kind == FacePairResult::segment) g.keys.insert(g.keys.end(), m.ends.begin(), m.ends.end());
  std::sort(g.keys.begin(), g.keys.end());
  g.keys.erase(std::unique(g.keys.begin(), g.keys.end()), g.keys.end());
  auto index_of = [&](const CrossingKey& k) {
    return std::size_t(std::lower_bound(g.keys.begin(), g.keys.end(), k) - g.keys.begin());
  };
  g.neighbours.assign(g.keys.size(), {no_point, no_point});
  g.segment_of.resize(g.keys.size());
  for (std::size_t s = 0; s < met.size(); ++s) {
    const auto& m = met[s];
    if (m.kind != FacePairResult::segment) continue;
    const std::size_t i = index_of(m.ends[0]), j = index_of(m.ends[1]);
    for (auto [from, to] : {std::pair{i, j}, std::pair{j, i}}) {
      auto& n = g.neighbours[from];
      const int slot = n[0] == no_point ? 0 : n[1] == no_point ? 1 : -1;
      if (slot < 0 || n[0] == to) return std::nullopt;
      n[slot] = to;
      g.segment_of[from][slot] = s;
    }
  }
  return g;
}

/// The crossing points (exact under the exact kernel, rounded otherwise), one after the other.
/// On all cores, the same input gave different outputs from run to run where a vertex had been
/// closed onto a curve (CT row 9 of docs/real_tows.md, two ways of seam pair: three different
/// meshes in five runs; on one core, or with this loop sequential, the same mesh in every run).
/// What in the threaded loop made the difference is not pinned down: presumably lazy values
/// shared by points of both threads, evaluated in the threads' order.
template <class K>
std::vector<typename K::Point_3> crossing_points(const Mesh<K>& a, const Mesh<K>& b, const std::vector<CrossingKey>& keys) {
  using F = typename Mesh<K>::Face_index;
  std::vector<typename K::Point_3> points(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const auto& k = keys[i];
    points[i] = k.edge_of_b ? crossing_point<K>(b, typename Mesh<K>::Edge_index(k.edge), a, F(k.face))
                            : crossing_point<K>(a, typename Mesh<K>::Edge_index(k.edge), b, F(k.face));
    make_exact(points[i]);  // kept points: cut the expression trees once
  }
  return points;
}

/// Under exact constructions: where each crossing point lies in A and in B (inside the edge it
/// was constructed on, inside the face it crosses).
template <class K>
void record_sites(const std::vector<CrossingKey>& keys, const std::vector<typename K::Point_3>& points,
                  GeneralPositionCurves<K>& result) {
  for (std::size_t i = 0; i < keys.size(); ++i) {
    SurfacePoint<K> on_edge, in_face;
    on_edge.where = Where::edge;
    on_edge.e = typename Mesh<K>::Edge_index(keys[i].edge);
    on_edge.p = points[i];
    in_face.where = Where::face;
    in_face.f = typename Mesh<K>::Face_index(keys[i].face);
    in_face.p = points[i];
    result.sites_a.sites.emplace_back(points[i], keys[i].edge_of_b ? in_face : on_edge);
    result.sites_b.sites.emplace_back(points[i], keys[i].edge_of_b ? on_edge : in_face);
  }
  result.sites_a.sort();
  result.sites_b.sort();
}

}  // namespace

template <class K>
std::optional<GeneralPositionCurves<K>> general_position_curves(const Mesh<K>& a, const Mesh<K>& b) {
  using Point = typename K::Point_3;
  using F = typename Mesh<K>::Face_index;
  const auto candidates = candidate_face_pairs<K>(a, b);
  const auto met = meet_all<K>(a, b, candidates);
  if (!met) return std::nullopt;
  const auto graph = crossing_graph(*met);
  if (!graph) return std::nullopt;
  const auto& keys = graph->keys;
  const auto& neighbours = graph->neighbours;
  const auto& segment_of = graph->segment_of;
  const std::vector<Point> points = crossing_points<K>(a, b, keys);
  constexpr std::size_t none = no_point;
  // The sign of (q - p) . (n_A x n_B) for the segment pq (points i and j) of face pair s:
  // positive when pq runs along n_A x n_B. Exact: under a rounded kernel from the exact points of
  // the inputs' doubles (a short segment's rounded ends could point the other way).
  auto direction = [&](std::size_t i, std::size_t j, std::size_t s) {
    const FaceCorners<K> ca(a, F(candidates[s].first)), cb(b, F(candidates[s].second));
    if constexpr (kernel_traits<K>::exact_constructions) {
      const auto na = CGAL::cross_product(a.point(ca.v[1]) - a.point(ca.v[0]), a.point(ca.v[2]) - a.point(ca.v[0]));
      const auto nb = CGAL::cross_product(b.point(cb.v[1]) - b.point(cb.v[0]), b.point(cb.v[2]) - b.point(cb.v[0]));
      return CGAL::sign(CGAL::determinant(points[j] - points[i], na, nb));
    } else {
      auto exact_point = [&](const CrossingKey& k) {
        return k.edge_of_b ? exact_crossing_point<K>(b, typename Mesh<K>::Edge_index(k.edge), a, F(k.face))
                           : exact_crossing_point<K>(a, typename Mesh<K>::Edge_index(k.edge), b, F(k.face));
      };
      const auto a0 = exactly(a.point(ca.v[0])), b0 = exactly(b.point(cb.v[0]));
      const auto na = CGAL::cross_product(exactly(a.point(ca.v[1])) - a0, exactly(a.point(ca.v[2])) - a0);
      const auto nb = CGAL::cross_product(exactly(b.point(cb.v[1])) - b0, exactly(b.point(cb.v[2])) - b0);
      return CGAL::sign(CGAL::determinant(exact_point(keys[j]) - exact_point(keys[i]), na, nb));
    }
  };
  // Chains: open ones from their ends (an edge on a mesh border), then the closed ones; each
  // turned to run along n_A x n_B.
  std::vector<char> used(keys.size(), 0);
  GeneralPositionCurves<K> result;
  auto& curves = result.curves;
  auto walk = [&](std::size_t start) {
    std::vector<Point> line{points[start]};
    used[start] = 1;
    CGAL::Sign along = CGAL::ZERO;
    for (std::size_t previous = none, at = start;;) {
      const auto& n = neighbours[at];
      const int slot = n[0] != previous ? 0 : 1;
      const std::size_t next = n[slot];
      if (next == none) break;  // an open end
      if (along == CGAL::ZERO) along = direction(at, next, segment_of[at][slot]);
      if (next == start) {  // closed
        line.push_back(points[start]);
        break;
      }
      if (used[next]) return false;  // (not reached on simple chains)
      used[next] = 1;
      line.push_back(points[next]);
      previous = at;
      at = next;
    }
    if (along == CGAL::NEGATIVE) std::reverse(line.begin(), line.end());
    curves.push_back(std::move(line));
    return true;
  };
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (!used[i] && (neighbours[i][0] == none || neighbours[i][1] == none) && !walk(i)) return std::nullopt;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (!used[i] && !walk(i)) return std::nullopt;

  if constexpr (kernel_traits<K>::exact_constructions) record_sites<K>(keys, points, result);
  return result;
}

#define SEAM_INSTANTIATE(K) \
  template std::optional<GeneralPositionCurves<K>> general_position_curves<K>(const Mesh<K>&, const Mesh<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
