// seam, pair: collapse short curve segments in both meshes. See seam/internal/collapse.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/certified.h>
#include <seam/internal/collapse.h>
#include <seam/internal/local_edits.h>
#include <seam/quality.h>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
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

/// Distance in doubles (no lazy exact number is built).
template <class P> double rounded_distance(const P& p, const P& q) {
  return std::sqrt(CGAL::squared_distance(to_filtered(p), to_filtered(q)));
}

template <class K> double face_min_angle(const Mesh<K>& m, typename MeshTypes<K>::F f) {
  const auto h = m.halfedge(f);
  return min_angle_deg(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
}

/// Is v a corner of a face whose smallest angle is below `degrees`?
template <class K> bool has_face_below(const Mesh<K>& m, typename MeshTypes<K>::V v, double degrees) {
  for (auto f : CGAL::faces_around_target(m.halfedge(v), m))
    if (f != MeshTypes<K>::M::null_face() && face_min_angle<K>(m, f) < degrees) return true;
  return false;
}

/// Can P merge into Q in `m` (Q staying, or both moving to `to` when given)? Fills the smallest
/// angle of the faces around P and Q before and after. Exact tests for degeneracy and
/// orientation under the exact kernel.
template <class K>
bool collapse_allowed(const Mesh<K>& m, typename MeshTypes<K>::V p, typename MeshTypes<K>::V q,
                      std::size_t input_vertices, Angles& before, Angles& after, const MergedFaceTest& accept_face,
                      int mesh_id, const std::optional<typename K::Point_3>& to) {
  using V = typename MeshTypes<K>::V;
  const auto h = m.halfedge(p, q);
  if (h == Mesh<K>::null_halfedge() || m.is_border(p) || m.is_border(q)) return false;
  if (std::size_t(p) < input_vertices) return false;
  // CGAL keeps the target of the edge's own halfedge: the other vertex's index goes away.
  const auto e = m.edge(h);
  const V kept = m.target(m.halfedge(e));
  if ((kept == p || to) && std::size_t(q) < input_vertices) return false;
  if (!CGAL::Euler::does_satisfy_link_condition(e, m)) return false;
  before = after = Angles{};
  const auto& pq = to ? *to : m.point(q);
  // The face with corners c once the corner at `moved` is at pq: false if it goes flat or turns
  // over, or fails accept_face.
  auto moved_face_allowed = [&](const std::array<typename K::Point_3, 3>& c, int moved) {
    std::array<typename K::Point_3, 3> d = c;
    d[moved] = pq;
    if (CGAL::collinear(d[0], d[1], d[2])) return false;
    const auto n0 = CGAL::cross_product(c[1] - c[0], c[2] - c[0]);
    const auto n1 = CGAL::cross_product(d[1] - d[0], d[2] - d[0]);
    if (CGAL::sign(n0 * n1) != CGAL::POSITIVE) return false;
    if (accept_face && !accept_face(mesh_id, to_filtered(d[0]), to_filtered(d[1]), to_filtered(d[2]))) return false;
    after.add(min_angle_deg(d[0], d[1], d[2]));
    return true;
  };
  for (auto f : CGAL::faces_around_target(m.halfedge(q), m)) {
    const double angle = face_min_angle<K>(m, f);
    before.add(angle);
    bool has_p = false;
    std::array<typename K::Point_3, 3> c;
    int k = 0, kq = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      has_p = has_p || v == p;
      if (v == q) kq = k;
      c[k++] = m.point(v);
    }
    if (has_p) continue;  // removed by the collapse
    if (!to) after.add(angle);
    else if (!moved_face_allowed(c, kq)) return false;
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
    int kp = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (v == p) break;
      ++kp;
    }
    if (!moved_face_allowed(c, kp)) return false;
  }
  return true;
}

/// Vertices of the faces around v.
template <class K> void ring(const Mesh<K>& m, typename MeshTypes<K>::V v, std::vector<typename MeshTypes<K>::V>& out) {
  out.push_back(v);
  for (auto u : CGAL::vertices_around_target(m.halfedge(v), m)) out.push_back(u);
}

/// Merges P into Q; returns the vertex that stays (it holds Q's point, or `to` when given).
template <class K>
typename MeshTypes<K>::V merge(Mesh<K>& m, typename MeshTypes<K>::V p, typename MeshTypes<K>::V q,
                               const std::optional<typename K::Point_3>& to) {
  const auto point = to ? *to : m.point(q);
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
  CGAL::Bbox_3 around;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    mine.push_back(box_of(m, faces[i], i));
    around += mine.back().bbox();
  }
  for (auto f : other.faces()) {
    Box box = box_of(other, f, std::size_t(f));
    if (CGAL::do_overlap(box.bbox(), around)) theirs.push_back(box);
  }
  std::vector<char> bad(faces.size(), 0);
  // Two shared faces (a flat contact's common triangulation, in both meshes) may be one face, or
  // meet in any common vertex or edge, as in seam check.
  // (std::pair, not structured bindings: the lambda below captures them.)
  const auto shared_in_m = m.template property_map<F, bool>(shared_face_property);
  const auto shared_in_other = other.template property_map<F, bool>(shared_face_property);
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
    const F fo(typename F::size_type(bo.info()));
    const auto co = corners(other, fo);
    const bool both_shared = shared_in_m.second && shared_in_other.second && shared_in_m.first[faces[i]] &&
                             shared_in_other.first[fo];
    std::array<typename K::Point_3, 3> pm, po;
    for (int k = 0; k < 3; ++k) pm[k] = m.point(cm[k]), po[k] = other.point(co[k]);
    int shared = 0, jm[3] = {-1, -1, -1};  // jm[k]: corner of the face of m at corner k of the other's
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        if (pm[j] == po[k]) jm[k] = j, ++shared;
    const Triangle tm(pm[0], pm[1], pm[2]), to(po[0], po[1], po[2]);
    // Certified interval tests first (internal/certified.h), exact predicates when they cannot tell.
    certified::IP im[3], io[3];
    for (int k = 0; k < 3; ++k) im[k] = certified::interval_point(pm[k]), io[k] = certified::interval_point(po[k]);
    bool crossing = false;
    if (shared == 0) {
      crossing = !certified::surely_disjoint({&im[0], &im[1], &im[2]}, {&io[0], &io[1], &io[2]}) &&
                 CGAL::do_intersect(tm, to);
    } else if (shared == 1) {
      int k = 0;
      while (jm[k] < 0) ++k;
      const int j = jm[k];
      if (!on_curve_other[std::size_t(co[k])] && !both_shared) {
        crossing = true;
      } else if (const auto only = certified::surely_only_vertex(im[j], im[(j + 1) % 3], im[(j + 2) % 3],
                                                                  io[(k + 1) % 3], io[(k + 2) % 3])) {
        crossing = !*only;
      } else {
        // They meet in more than the common corner iff an opposite edge meets the other face.
        crossing = CGAL::do_intersect(Segment(pm[(j + 1) % 3], pm[(j + 2) % 3]), to) ||
                   CGAL::do_intersect(Segment(po[(k + 1) % 3], po[(k + 2) % 3]), tm);
      }
    } else if (shared == 2) {
      int k = 0;
      while (jm[k] >= 0) ++k;
      const auto u = std::uint32_t(co[(k + 1) % 3]), w = std::uint32_t(co[(k + 2) % 3]);
      const int j = 3 - jm[(k + 1) % 3] - jm[(k + 2) % 3];
      const auto &p = po[(k + 1) % 3], &q = po[(k + 2) % 3];
      // Faces with a common edge overlap iff they are coplanar and on the same side of it.
      crossing = (!curve_edges_other.count({std::min(u, w), std::max(u, w)}) && !both_shared) ||
                 (!certified::surely_only_edge(io[(k + 1) % 3], io[(k + 2) % 3], io[k], im[j]) &&
                  CGAL::coplanar(p, q, po[k], pm[j]) && CGAL::coplanar_orientation(p, q, po[k], pm[j]) == CGAL::POSITIVE);
    } else {
      crossing = !both_shared;
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

}  // namespace

template <class K>
void compact_keeping_curve_vertices(Mesh<K>& m, std::vector<std::vector<typename MeshTypes<K>::V>>& lists) {
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
      if (it == pairs.end() || it->first != std::uint32_t(v)) throw InternalError("compact: a curve vertex was lost");
      v = it->second;
    }
  m.remove_property_map(old_index);
}


namespace {

/// collapse_short_curve_segments, as a sequence of rounds: each proposes merges (curve segments
/// in both meshes, tiny edges off the curves in one), chooses those whose neighbourhoods do not
/// overlap and that are allowed, applies them, and undoes those whose faces cross the other mesh.
template <class K> class CurveSegmentCollapser {
 public:
  using V = typename MeshTypes<K>::V;
  using F = typename MeshTypes<K>::F;

  struct Parameters {
    double max_length, tiny_length;
    std::size_t input_vertices[2];
    const MergedFaceTest& accept_face;
    double only_next_to_faces_below;
    bool merge_onto_curves;
  };

  CurveSegmentCollapser(Mesh<K>& a, Mesh<K>& b, std::vector<Polyline<K>>& curves, VertexLists<K>& cva,
                        VertexLists<K>& cvb, const Parameters& parameters)
      : a_(a), b_(b), curves_(curves), cva_(cva), cvb_(cvb), meshes_{&a, &b}, lists_{&cva, &cvb}, par_(parameters) {}

  CurveCollapseReport run() {
    for (int round = 0; round < 16; ++round) {
      count_uses();
      std::vector<Op> ops = curve_segment_merges();
      if (par_.tiny_length > 0) add_tiny_edge_merges(ops);
      if (ops.empty()) break;
      sort_by_priority(ops);
      std::vector<Op> chosen = choose(ops);
      if (chosen.empty()) break;
      if (!apply_undoing_crossings(chosen)) continue;
      compact_keeping_curve_vertices<K>(a_, cva_);
      compact_keeping_curve_vertices<K>(b_, cvb_);
      excluded_.clear();  // indices moved: the next round evaluates every candidate again
    }
    for (const auto& c : curves_)  // what is left
      for (std::size_t i = 0; i + 1 < c.size(); ++i)
        if (rounded_distance(c[i], c[i + 1]) <= par_.max_length) ++report_.refused;
    return report_;
  }

 private:
  static constexpr std::size_t no_curve = std::numeric_limits<std::size_t>::max();

  /// P merged into Q in A (mask 1), B (mask 2) or both (3: a curve segment, at positions
  /// at_p / at_q of curve `curve`). With `to` (only with accept_face: it keeps the moved faces
  /// near the inputs), both P and Q move there: a point of the segment, exact.
  struct Op {
    int mask;
    V p[2], q[2];
    std::size_t curve, at_p, at_q;
    double length;
    bool tiny;
    std::optional<typename K::Point_3> to = std::nullopt;
    int quarters = 0;  ///< with `to`: it is P + quarters / 4 (Q - P)
    /// P may be an input vertex: a tiny edge from a vertex off the curves to a curve vertex (P
    /// merged into the curve point, as snapping would: an exact construction left the point a
    /// few units in the last place away, and two distinct vertices that close are one for a
    /// volume mesher). Its index then goes, as with snapping's own merges.
    bool input_ok = false;
  };
  /// (mask + 4 quarters; P in A, P in B, Q in A or B): the identity of a merge refused or undone.
  static std::array<std::size_t, 4> key(const Op& op) {
    return {std::size_t(op.mask) + 4 * std::size_t(op.quarters), op.mask & 1 ? std::size_t(op.p[0]) : 0,
            op.mask & 2 ? std::size_t(op.p[1]) : 0, op.mask & 1 ? std::size_t(op.q[0]) : std::size_t(op.q[1])};
  }

  /// How often each vertex appears on the curves (closing repeats once): only vertices on one
  /// curve, once, are merged along the curve; vertices off the curves only in tiny edges.
  void count_uses() {
    for (int m = 0; m < 2; ++m) {
      uses_[m].assign(meshes_[m]->number_of_vertices() + meshes_[m]->number_of_removed_vertices(), 0);
      for (std::size_t c = 0; c < curves_.size(); ++c) {
        const auto& vs = (*lists_[m])[c];
        for (std::size_t i = 0; i + (is_closed(curves_[c]) ? 1 : 0) < vs.size(); ++i) ++uses_[m][std::size_t(vs[i])];
      }
    }
  }

  /// Curve segments short enough, merged in both meshes (into either end, or at a point between).
  std::vector<Op> curve_segment_merges() const {
    std::vector<Op> ops;
    for (std::size_t c = 0; c < curves_.size(); ++c) {
      const bool closed = is_closed(curves_[c]);
      const std::size_t n = closed ? curves_[c].size() - 1 : curves_[c].size();
      if (n < (closed ? 4u : 3u)) continue;  // keep at least a triangle / a segment
      for (std::size_t i = closed ? 0 : 1; i < (closed ? n : n - 1); ++i)
        for (int dir : {-1, 1}) {
          const std::size_t j = (i + n + std::size_t(dir)) % n;
          const double len = rounded_distance(curves_[c][i], curves_[c][j]);
          if (!(len <= std::max(par_.max_length, par_.tiny_length))) continue;
          if (par_.only_next_to_faces_below > 0 && len > par_.tiny_length &&
              !has_face_below<K>(a_, cva_[c][i], par_.only_next_to_faces_below) &&
              !has_face_below<K>(b_, cvb_[c][i], par_.only_next_to_faces_below))
            continue;
          ops.push_back({3, {cva_[c][i], cvb_[c][i]}, {cva_[c][j], cvb_[c][j]}, c, i, j, len, len <= par_.tiny_length});
          // Where merging either end into the other moves its faces out of the tolerance, both
          // may merge at a point between (a quarter, half or three quarters along, both ways).
          if (par_.accept_face && len > par_.tiny_length && len <= par_.max_length && (closed || (j >= 1 && j + 1 < n)))
            for (int quarter : {2, 3})
              ops.push_back({3, {cva_[c][i], cvb_[c][i]}, {cva_[c][j], cvb_[c][j]}, c, i, j, len, false,
                             curves_[c][i] + (curves_[c][j] - curves_[c][i]) * typename K::FT(quarter) / 4, quarter});
        }
    }
    return ops;
  }

  /// Tiny edges off the curves (one end off the curves and new): merged in their mesh alone.
  void add_tiny_edge_merges(std::vector<Op>& ops) const {
    for (int m = 0; m < 2; ++m) {
      const Mesh<K>& mesh = *meshes_[m];
      for (auto e : mesh.edges()) {
        const V u = mesh.vertex(e, 0), w = mesh.vertex(e, 1);
        const double len = rounded_distance(mesh.point(u), mesh.point(w));
        if (!(len <= par_.tiny_length)) continue;
        auto movable = [&](V v) { return uses_[m][std::size_t(v)] == 0 && std::size_t(v) >= par_.input_vertices[m]; };
        auto onto_curve = [&](V v, V on) {
          return par_.merge_onto_curves && uses_[m][std::size_t(v)] == 0 && uses_[m][std::size_t(on)] > 0;
        };
        Op op{1 << m, {}, {}, no_curve, 0, 0, len, true};
        if (movable(u)) op.p[m] = u, op.q[m] = w;
        else if (movable(w)) op.p[m] = w, op.q[m] = u;
        else if (onto_curve(u, w)) op.p[m] = u, op.q[m] = w, op.input_ok = true;
        else if (onto_curve(w, u)) op.p[m] = w, op.q[m] = u, op.input_ok = true;
        else continue;
        ops.push_back(op);
      }
    }
  }

  /// Tiny ones first, then the shortest; of a segment, merges into an end before the midpoint.
  static void sort_by_priority(std::vector<Op>& ops) {
    std::sort(ops.begin(), ops.end(), [&](const Op& x, const Op& y) {
      if (x.tiny != y.tiny) return x.tiny;
      if (x.length != y.length) return x.length < y.length;
      if (bool(x.to) != bool(y.to)) return !x.to;
      return key(x) < key(y);
    });
  }

  /// Collapses whose neighbourhoods do not overlap: tiny ones whenever allowed, the others when
  /// they improve the angles of both meshes together. (Faces next to a frozen stretch of curve
  /// stay as they are: see frozen_face_property. A tiny curve segment collapsed in both meshes may
  /// touch shared faces: it changes them the same way in both, and left it would be two vertices a
  /// volume mesher cannot tell apart.)
  std::vector<Op> choose(const std::vector<Op>& ops) {
    std::vector<char> locked[2];
    for (int m = 0; m < 2; ++m) locked[m].assign(uses_[m].size(), 0);
    std::vector<Op> chosen;
    std::vector<V> near[2];
    const internal::FrozenFaces<K> frozen[2] = {internal::FrozenFaces<K>(a_), internal::FrozenFaces<K>(b_)};
    for (const auto& op : ops) {
      if (excluded_.count(key(op))) continue;
      if (op.mask == 3 && (uses_[0][std::size_t(op.p[0])] != 1 || uses_[1][std::size_t(op.p[1])] != 1)) continue;
      if (op.to && (uses_[0][std::size_t(op.q[0])] != 1 || uses_[1][std::size_t(op.q[1])] != 1)) continue;  // Q moves
      bool free = true;
      const bool both_tiny = op.tiny && op.mask == 3 && !op.to;
      for (int m = 0; m < 2 && free; ++m) {
        near[m].clear();
        if (!(op.mask & (1 << m))) continue;
        ring<K>(*meshes_[m], op.p[m], near[m]), ring<K>(*meshes_[m], op.q[m], near[m]);
        free = std::none_of(near[m].begin(), near[m].end(), [&](V v) { return locked[m][std::size_t(v)]; }) &&
               !frozen[m].around(*meshes_[m], op.p[m], !both_tiny) &&
               !frozen[m].around(*meshes_[m], op.q[m], !both_tiny);
      }
      if (!free) continue;
      if (!allowed_and_better(op)) {
        excluded_.insert(key(op));
        continue;
      }
      for (int m = 0; m < 2; ++m)
        for (V v : near[m]) locked[m][std::size_t(v)] = 1;
      chosen.push_back(op);
    }
    return chosen;
  }

  /// The merge is allowed in each mesh it changes, and (unless tiny) improves their angles.
  bool allowed_and_better(const Op& op) const {
    Angles before, after;
    for (int m = 0; m < 2; ++m) {
      if (!(op.mask & (1 << m))) continue;
      Angles bm, am;
      if (!collapse_allowed<K>(*meshes_[m], op.p[m], op.q[m], op.input_ok ? 0 : par_.input_vertices[m], bm, am,
                               par_.accept_face, m, op.to))
        return false;
      before.min = std::min(before.min, bm.min), before.below_10 += bm.below_10;
      after.min = std::min(after.min, am.min), after.below_10 += am.below_10;
    }
    return op.tiny || after.better_than(before);
  }

  /// Each mesh's curve vertex lists once the chosen merges are made (`kept`: the vertex each
  /// leaves).
  std::array<VertexLists<K>, 2> lists_after(const std::vector<Op>& chosen,
                                            const std::vector<std::array<V, 2>>& kept) const {
    std::array<VertexLists<K>, 2> after = {cva_, cvb_};
    for (int m = 0; m < 2; ++m) {
      auto& ls = after[m];
      std::vector<std::vector<char>> drop(ls.size());
      for (std::size_t c = 0; c < ls.size(); ++c) drop[c].assign(ls[c].size(), 0);
      for (std::size_t k = 0; k < chosen.size(); ++k) {
        const Op& op = chosen[k];
        if (!(op.mask & (1 << m))) continue;
        if (op.curve == no_curve) {  // Q may be a curve vertex whose index went to P's
          if (kept[k][m] != op.q[m])
            for (auto& vs : ls)
              for (auto& v : vs)
                if (v == op.q[m]) v = kept[k][m];
          continue;
        }
        auto& vs = ls[op.curve];
        const bool closed = vs.size() > 1 && vs.front() == vs.back();
        drop[op.curve][op.at_p] = 1;
        vs[op.at_q] = kept[k][m];
        if (closed && op.at_q == 0) vs.back() = kept[k][m];
        if (closed && op.at_p == 0) drop[op.curve].back() = 1;
      }
      for (std::size_t c = 0; c < ls.size(); ++c) {
        const bool closed = ls[c].size() > 1 && ls[c].front() == ls[c].back();
        std::vector<V> out;
        for (std::size_t i = 0; i < ls[c].size(); ++i)
          if (!drop[c][i]) out.push_back(ls[c][i]);
        if (closed && drop[c].back() && !out.empty()) out.push_back(out.front());
        ls[c] = std::move(out);
      }
    }
    return after;
  }

  /// The shared curves lose the merged points (and a segment merged at a point between moves Q).
  void update_curves(const std::vector<Op>& chosen) {
    std::vector<std::vector<char>> drop(curves_.size());
    for (std::size_t c = 0; c < curves_.size(); ++c) drop[c].assign(curves_[c].size(), 0);
    for (const auto& op : chosen) {
      if (op.curve == no_curve) continue;
      if (op.to) {  // Q moved to the point between
        if (op.at_q == 0 && is_closed(curves_[op.curve])) curves_[op.curve].back() = *op.to;
        curves_[op.curve][op.at_q] = *op.to;
      }
      drop[op.curve][op.at_p] = 1;
      if (op.at_p == 0 && is_closed(curves_[op.curve])) drop[op.curve].back() = 1;
    }
    for (std::size_t c = 0; c < curves_.size(); ++c) {
      const bool closed = is_closed(curves_[c]);
      Polyline<K> out;
      for (std::size_t i = 0; i < curves_[c].size(); ++i)
        if (!drop[c][i]) out.push_back(curves_[c][i]);
      if (closed && drop[c].back()) out.push_back(out.front());
      curves_[c] = std::move(out);
    }
  }

  /// Makes the chosen merges; where a merged vertex's faces cross the other mesh, starts again
  /// from the meshes as they were without those merges. False when none is left.
  bool apply_undoing_crossings(std::vector<Op>& chosen) {
    const Mesh<K> a0 = a_, b0 = b_;
    while (!chosen.empty()) {
      std::vector<std::array<V, 2>> kept(chosen.size());
      for (std::size_t k = 0; k < chosen.size(); ++k)
        for (int m = 0; m < 2; ++m)
          if (chosen[k].mask & (1 << m))
            kept[k][m] = merge<K>(*meshes_[m], chosen[k].p[m], chosen[k].q[m], chosen[k].to);
      auto after = lists_after(chosen, kept);
      std::vector<char> on_curve[2];
      std::set<std::pair<std::uint32_t, std::uint32_t>> curve_edges[2];
      for (int m = 0; m < 2; ++m) curve_marks<K>(*meshes_[m], after[m], on_curve[m], curve_edges[m]);
      std::vector<char> undo(chosen.size(), 0);
      std::vector<F> faces[2];
      for (int m = 0; m < 2; ++m) {
        std::vector<std::size_t> owner;
        for (std::size_t k = 0; k < chosen.size(); ++k)
          if (chosen[k].mask & (1 << m))
            for (auto f : CGAL::faces_around_target(meshes_[m]->halfedge(kept[k][m]), *meshes_[m]))
              faces[m].push_back(f), owner.push_back(k);
        const auto bad = crossing_faces<K>(*meshes_[m], faces[m], *meshes_[1 - m], on_curve[1 - m], curve_edges[1 - m]);
        for (std::size_t i = 0; i < faces[m].size(); ++i)
          if (bad[i]) undo[owner[i]] = 1;
      }
      if (std::none_of(undo.begin(), undo.end(), [](char u) { return u != 0; })) {
        for (int m = 0; m < 2; ++m) {
          auto is_new = meshes_[m]->template property_map<F, bool>(new_face_property);
          if (is_new.second)
            for (auto f : faces[m]) is_new.first[f] = true;
        }
        update_curves(chosen);
        cva_ = std::move(after[0]);
        cvb_ = std::move(after[1]);
        for (const auto& op : chosen) (op.curve == no_curve ? report_.tiny_edges_collapsed : report_.collapsed) += 1;
        return true;
      }
      a_ = a0;
      b_ = b0;
      std::vector<Op> keep;
      for (std::size_t k = 0; k < chosen.size(); ++k)
        if (undo[k])
          excluded_.insert(key(chosen[k]));
        else
          keep.push_back(chosen[k]);
      chosen = std::move(keep);
    }
    return false;
  }

  Mesh<K>& a_;
  Mesh<K>& b_;
  std::vector<Polyline<K>>& curves_;
  VertexLists<K>& cva_;
  VertexLists<K>& cvb_;
  Mesh<K>* meshes_[2];
  VertexLists<K>* lists_[2];
  Parameters par_;
  std::vector<int> uses_[2];
  std::set<std::array<std::size_t, 4>> excluded_;  ///< merges refused or undone (by key)
  CurveCollapseReport report_;
};

}  // namespace

template <class K>
CurveCollapseReport collapse_short_curve_segments(Mesh<K>& a, Mesh<K>& b, std::vector<Polyline<K>>& curves,
                                                  VertexLists<K>& cva, VertexLists<K>& cvb, double max_length,
                                                  double tiny_length, std::size_t input_vertices_a,
                                                  std::size_t input_vertices_b, const MergedFaceTest& accept_face,
                                                  double only_next_to_faces_below, bool merge_onto_curves) {
  if (!(max_length > 0) && !(tiny_length > 0)) return {};
  if (cva.size() != curves.size() || cvb.size() != curves.size())
    throw InternalError("collapse: curve vertex lists do not match the curves");
  const typename CurveSegmentCollapser<K>::Parameters parameters{
      max_length, tiny_length, {input_vertices_a, input_vertices_b}, accept_face, only_next_to_faces_below,
      merge_onto_curves};
  return CurveSegmentCollapser<K>(a, b, curves, cva, cvb, parameters).run();
}

#define SEAM_INSTANTIATE(K)                                                                                     \
  template CurveCollapseReport collapse_short_curve_segments<K>(                                                 \
      Mesh<K>&, Mesh<K>&, std::vector<Polyline<K>>&, VertexLists<K>&, VertexLists<K>&, double, double,     \
      std::size_t, std::size_t, const MergedFaceTest&, double, bool);                                                                           \
  template void compact_keeping_curve_vertices<K>(Mesh<K>&, VertexLists<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
