// seam::pair_with_curves: two tows, one given interface (report: "the crossing points of both
// meshes are collected on the curve before it is coarsened"). See seam/pair.h.
//
// 1. Snap each mesh's vertices onto the curve nodes (report step 1).
// 2. Follow the curve on each mesh (internal/trace.h) and keep, per mesh, the points the
//    embedding needs: its crossings (points on its edges and vertices), the end nodes of open
//    curves, and the nodes of a run that leaves and re-enters a face through the same edge.
//    Each kept point gets its place along the curve: node index + fraction of the next segment
//    (the foot of the point on that segment, rounded to double).
// 3. Merge both meshes' kept points in curve order: the common coarsened curve. Its point k lies
//    on the given curve at S_k (exact: a node, or node + fraction x segment, the fraction a
//    double).
// 4. Embed it into each mesh: a point the mesh itself kept goes where the trace found it (on an
//    edge or at a vertex); a point of the other mesh goes into the face holding this mesh's two
//    neighbouring kept points, at the projection of S_k onto the face's plane (or on the chord
//    between the two when a projection falls outside the face).
// 5. Move every curve vertex of both outputs onto S_k, so both share bit-identical coordinates
//    on the given curve. A move that would
//    flip or flatten a face is refused (InvalidInput: the curve is too far from the surface for
//    the mesh's resolution there).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/internal/coarsen.h>
#include <seam/internal/snap.h>
#include <seam/internal/trace.h>
#include <seam/internal/verify_output.h>
#include <seam/pair.h>

#include <seam/internal/message.h>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <map>
#include <set>
#include <optional>
#include <chrono>
#include <cmath>
#include <sstream>

namespace seam {

namespace {

using internal::say;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Given nodes were rounded to doubles: one within this relative distance of a mesh edge or
/// vertex is put on it (internal/trace.h).
constexpr double kFeatureTol = 1e-9;

/// A point one mesh keeps, with its place along the given curve: segment s (from node s to node
/// s + 1) at fraction t in [0, 1); a node is (node, 0).
template <class K> struct KeptPoint {
  std::size_t s = 0;
  double t = 0;
  long node = -1;  ///< the input node, or -1 for a crossing found on the way
  internal::SurfacePoint<K> sp;
  /// For a crossing of an edge: the point of the curve closest to the edge's line (exact), when
  /// the closest pair falls inside both; sp.p is then moved to its partner on the edge, so that
  /// the two differ only across the surface, not along it.
  std::optional<typename K::Point_3> on_curve;
  double param() const { return double(s) + t; }
};

template <class P> std::array<double, 3> rounded(const P& p) {
  const auto q = to_filtered(p);
  return {q.x(), q.y(), q.z()};
}

/// Each traced point's place along the given curve: a node, or a crossing between nodes s and
/// s + 1 at the foot of the point on that segment (rounded; on an edge, the closest points of the
/// edge's line and the segment's line, exact, when they lie inside both).
template <class K>
std::vector<KeptPoint<K>> places_along_curve(const Mesh<K>& mesh, const internal::TracedCurve<K>& tc,
                                             const Polyline<K>& curve) {
  using internal::Where;
  const std::size_t n = tc.points.size();  // a closed trace does not repeat its first point
  std::vector<KeptPoint<K>> all(n);
  // Places: a crossing between nodes s and s + 1 at the foot of the point on that segment
  // (rounded), kept monotone along the curve.
  long node = 0;
  for (std::size_t i = 0; i < n; ++i) {
    KeptPoint<K>& k = all[i];
    k.sp = tc.points[i];
    k.node = tc.input_node[i];
    if (k.node >= 0) {
      node = k.node;
      k.s = std::size_t(node);
      k.t = 0;
    } else {
      const auto p0 = rounded(curve[std::size_t(node)]), p1 = rounded(curve[std::size_t(node) + 1]);
      const auto x = rounded(k.sp.p);
      double dd = 0, dx = 0;
      for (int c = 0; c < 3; ++c) {
        dd += (p1[c] - p0[c]) * (p1[c] - p0[c]);
        dx += (x[c] - p0[c]) * (p1[c] - p0[c]);
      }
      k.s = std::size_t(node);
      k.t = dd > 0 ? std::clamp(dx / dd, 0.0, 1.0) : 0.0;
      if (k.sp.where == Where::edge) {
        // The closest points of the edge's line and the segment's line (exact): x0 + u d1 and
        // p0 + w d2.
        using FT = typename K::FT;
        const auto& x0 = mesh.point(mesh.source(mesh.halfedge(k.sp.e)));
        const auto& x1 = mesh.point(mesh.target(mesh.halfedge(k.sp.e)));
        const auto& q0 = curve[std::size_t(node)];
        const auto& q1 = curve[std::size_t(node) + 1];
        const auto d1 = x1 - x0, d2 = q1 - q0, r = x0 - q0;
        const FT a = d1 * d1, b = d1 * d2, c = d2 * d2, d = d1 * r, e = d2 * r;
        const FT denom = a * c - b * b;
        if (CGAL::is_positive(denom)) {
          const FT u = (b * e - c * d) / denom, w = (a * e - b * d) / denom;
          if (CGAL::is_positive(u) && u < FT(1) && CGAL::is_positive(w) && w < FT(1)) {
            auto on_edge = x0 + d1 * u;
            auto on_curve = q0 + d2 * w;
            make_exact(on_edge);
            make_exact(on_curve);
            k.sp.p = on_edge;
            k.on_curve = on_curve;
            k.t = CGAL::to_double(w);
          }
        }
      }
      if (k.t == 1.0) ++k.s, k.t = 0;  // at the next node
      // ...unless that is the closing node of a closed curve: just before it.
      if (tc.closed && k.s + 1 == curve.size()) k.s = curve.size() - 2, k.t = std::nextafter(1.0, 0.0);
    }
  }
  return all;
}

/// Makes the places strictly increasing along each segment (see below).
template <class K> void make_places_increasing(std::vector<KeptPoint<K>>& all, const Polyline<K>& curve) {
  const std::size_t n = all.size();
  // Places strictly increasing along each segment: a crossing whose foot does not come after the
  // previous one's (the curve bends back across the mesh there) goes evenly between its
  // neighbours, and is no longer paired with a point of the curve.
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && all[j].node < 0) ++j;  // crossings i+1 .. j-1 follow node (or start) i
    double lo = all[i].node >= 0 ? 0.0 : all[i].t;
    // In order: after the previous place on this segment, at the next node (foot past it), or at
    // node i itself (the walk met the node's place again, the difference lost to rounding).
    const auto node_at = rounded(curve[all[i].s]), next_at = rounded(curve[all[i].s + 1]);
    const double seg2 = (next_at[0] - node_at[0]) * (next_at[0] - node_at[0]) +
                        (next_at[1] - node_at[1]) * (next_at[1] - node_at[1]) +
                        (next_at[2] - node_at[2]) * (next_at[2] - node_at[2]);
    auto at_node = [&](std::size_t x) {
      const auto p = rounded(all[x].sp.p);
      const double d2 = (p[0] - node_at[0]) * (p[0] - node_at[0]) + (p[1] - node_at[1]) * (p[1] - node_at[1]) +
                        (p[2] - node_at[2]) * (p[2] - node_at[2]);
      return all[x].t == 0 && d2 <= 1e-18 * seg2;
    };
    auto in_order = [&](std::size_t x) { return all[x].s != all[i].s || all[x].t > lo || at_node(x); };
    for (std::size_t q = i + 1; q < j;) {
      if (in_order(q)) {
        if (all[q].s == all[i].s && all[q].t > lo) lo = all[q].t;
        ++q;
        continue;
      }
      // A run of crossings out of order: q .. r-1, spread between lo and the next place.
      std::size_t r = q;
      while (r < j && !in_order(r)) ++r;
      const double hi = r < j && all[r].s == all[i].s ? all[r].t : 1.0;
      for (std::size_t x = q; x < r; ++x) {
        all[x].t = lo + (hi - lo) * double(x - q + 1) / double(r - q + 1);
        all[x].on_curve.reset();
      }
      lo = all[r - 1].t;
      q = r;
    }
    i = j;
  }
}

/// Which points the embedding keeps: points on edges and vertices, the end nodes of an open
/// curve, and runs of face points that must stay for the curve to remain a simple path.
template <class K>
std::vector<char> kept_mask(const Mesh<K>& mesh, const internal::TracedCurve<K>& tc, const std::vector<KeptPoint<K>>& all) {
  using internal::Where;
  const std::size_t n = all.size();
  std::vector<char> keep(n, 0);
  for (std::size_t i = 0; i < n; ++i) keep[i] = all[i].sp.where != Where::face;
  if (!tc.closed && n > 0) keep[0] = keep[n - 1] = 1;
  std::vector<std::size_t> anchors;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) anchors.push_back(i);
  if (anchors.empty()) {  // a closed curve inside one face: keep its nodes
    std::fill(keep.begin(), keep.end(), 1);
  } else {
    // A run of face points between two kept points on one edge of its face (or the same point):
    // keep the run, so that the embedded curve stays a simple path through the face.
    const std::size_t m = anchors.size();
    for (std::size_t j = 0; j < (tc.closed ? m : m - 1); ++j) {
      const std::size_t s = anchors[j], e = anchors[(j + 1) % m];
      const std::size_t first = (s + 1) % n;
      if (first == e) continue;  // no face point between
      const auto f = all[first].sp.f;
      if (all[s].sp.same_as(all[e].sp) || internal::on_common_edge<K>(mesh, f, all[s].sp, all[e].sp))
        for (std::size_t i = first; i != e; i = (i + 1) % n) keep[i] = 1;
    }
  }
  return keep;
}

/// The points of one traced curve that the embedding keeps (see step 2 above), in curve order;
/// for a closed curve without the closing repeat.
template <class K>
std::vector<KeptPoint<K>> kept_points(const Mesh<K>& mesh, const internal::TracedCurve<K>& tc,
                                      const Polyline<K>& curve) {
  std::vector<KeptPoint<K>> all = places_along_curve<K>(mesh, tc, curve);
  make_places_increasing<K>(all, curve);
  const std::vector<char> keep = kept_mask<K>(mesh, tc, all);
  const std::size_t n = all.size();
  std::vector<KeptPoint<K>> kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    if (!kept.empty() && kept.back().sp.same_as(all[i].sp)) continue;  // the walk met a node again
    if (!kept.empty() && kept.back().s == all[i].s && kept.back().t >= all[i].t) {
      // The same place on the curve (a node a hair beyond the edge where the walk crossed, the
      // difference lost to rounding): one point, the one on an edge or vertex; two such points
      // stay apart by the smallest step along the curve.
      if (all[i].sp.where == internal::Where::face) continue;
      if (kept.back().sp.where == internal::Where::face) {
        kept.back() = all[i];
        continue;
      }
      all[i].t = std::nextafter(kept.back().t, 1.0);
      if (all[i].t >= 1.0) throw InternalError("pair: crossings of a given curve could not be ordered along it");
    }
    kept.push_back(all[i]);
  }
  return kept;
}

/// One point of the common coarsened curve: the kept point of A and/or of B.
struct Joint {
  std::size_t s;
  double t;
  long ia = -1, ib = -1;  ///< index into A's and B's kept points
  double param() const { return double(s) + t; }
};

/// The positions of the joints in one mesh: its own kept points where it has one. The other
/// mesh's points between two of its kept points go into the face holding both: at the
/// projection of their place on the curve (`on_curve`) onto the face's plane when all of them
/// fall strictly inside the face (exact tests), otherwise on the chord between the two kept
/// points at the fractions given by the curve places (strictly increasing inside the chord).
template <class K>
std::vector<typename K::Point_3> positions_in(const Mesh<K>& mesh, const std::vector<Joint>& joints,
                                              const std::vector<KeptPoint<K>>& kept, const Polyline<K>& on_curve,
                                              bool use_a, bool closed, double period) {
  using FT = typename K::FT;
  const std::size_t n = joints.size();
  std::vector<typename K::Point_3> pos(n);
  auto own = [&](std::size_t j) { return use_a ? joints[j].ia : joints[j].ib; };
  std::vector<std::size_t> owned;
  for (std::size_t j = 0; j < n; ++j)
    if (own(j) >= 0) owned.push_back(j);
  if (owned.empty()) throw InternalError("pair: a given curve has no point on one of the meshes");
  for (std::size_t j : owned) pos[j] = kept[std::size_t(own(j))].sp.p;
  const std::size_t m = owned.size();
  for (std::size_t g = 0; g < (closed ? m : m - 1); ++g) {
    const std::size_t s = owned[g], e = owned[(g + 1) % m];
    std::vector<std::size_t> between;
    for (std::size_t j = (s + 1) % n; j != e; j = (j + 1) % n) between.push_back(j);
    if (between.empty()) continue;
    const double ps = joints[s].param();
    double pe = joints[e].param();
    if (e <= s) pe += period;  // around the end of a closed curve
    std::vector<double> lambda;
    bool ok = pe > ps;
    for (std::size_t j : between) {
      double p = joints[j].param();
      if (p < ps) p += period;
      const double l = ok ? (p - ps) / (pe - ps) : 0;
      ok = ok && l > 0 && l < 1 && (lambda.empty() || l > lambda.back());
      lambda.push_back(l);
    }
    if (!ok)  // places that do not order the points strictly: by rank
      for (std::size_t r = 0; r < between.size(); ++r) lambda[r] = double(r + 1) / double(between.size() + 1);
    const auto& a = pos[s];
    const auto& b = pos[e];
    // The face holding both kept points, when there is exactly one.
    const auto& sa = kept[std::size_t(own(s))].sp;
    const auto& sb = kept[std::size_t(own(e))].sp;
    std::vector<typename internal::MeshTypes<K>::F> common;
    for (auto f : internal::incident_faces<K>(mesh, sa))
      if (internal::face_contains<K>(mesh, f, sb)) common.push_back(f);
    if (common.size() == 1) {
      std::array<typename K::Point_3, 3> c;
      int i = 0;
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(common[0]), mesh)) c[i++] = mesh.point(v);
      const typename K::Plane_3 plane(c[0], c[1], c[2]);
      std::vector<typename K::Point_3> projected;
      for (std::size_t j : between) {
        auto q = plane.projection(on_curve[j]);
        make_exact(q);
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k)
          inside = CGAL::orientation(c[k], c[(k + 1) % 3], q, c[k] + plane.orthogonal_vector()) ==
                   CGAL::orientation(c[k], c[(k + 1) % 3], c[(k + 2) % 3], c[k] + plane.orthogonal_vector());
        if (!inside) break;
        projected.push_back(q);
      }
      // ...and only when the path through the face stays simple (exact tests).
      bool simple = projected.size() == between.size();
      if (simple) {
        std::vector<typename K::Point_3> path{a};
        path.insert(path.end(), projected.begin(), projected.end());
        path.push_back(b);
        for (std::size_t x = 0; x + 1 < path.size() && simple; ++x)
          for (std::size_t y = x + 2; y + 1 < path.size() && simple; ++y)
            simple = !CGAL::do_intersect(typename K::Segment_3(path[x], path[x + 1]),
                                         typename K::Segment_3(path[y], path[y + 1]));
      }
      if (simple) {
        for (std::size_t r = 0; r < between.size(); ++r) pos[between[r]] = projected[r];
        continue;
      }
    }
    for (std::size_t r = 0; r < between.size(); ++r) {
      pos[between[r]] = a + (b - a) * FT(lambda[r]);  // exactly on the chord under Epeck
      make_exact(pos[between[r]]);
    }
  }
  return pos;
}

/// Moving the meshes onto the curve would fold a face.
struct FoldError : InvalidInput {
  using InvalidInput::InvalidInput;
};

/// What move_onto_curves did: the largest move, or where a face would fold.
struct CurveMove {
  double max_move = 0;
  std::string folded;  ///< empty, or the point (as text) where a face would fold
  double fold_distance = 0;
};

/// Moves the curve vertices of `m` onto their `target`s (exactly), and the other vertices within
/// `rings` rings of them (along faces new from the embedding, then any: the second and later
/// rings) by a blend of those moves (inverse distance weights over the neighbours one ring closer
/// to the curve; rounded): so the faces along the curve move with it instead of folding where the
/// embedding made them thin. A move is made only when no face around a moved vertex folds or
/// flattens (exact tests).
template <class K>
CurveMove move_onto_curves(Mesh<K>& m, const std::map<typename Mesh<K>::Vertex_index, typename K::Point_3>& target,
                           int rings) {
  using V = typename Mesh<K>::Vertex_index;
  using Vec = Filtered::Vector_3;
  CurveMove report;
  const auto [is_new, has_new] = m.template property_map<typename Mesh<K>::Face_index, bool>(new_face_property);
  std::map<V, Vec> shift;  // the blended moves of the vertices off the curves
  std::map<V, Vec> layer;  // the moves of the last ring
  for (const auto& [v, p] : target) layer.emplace(v, to_filtered(p) - to_filtered(m.point(v)));
  std::map<V, Vec> all = layer;
  for (int ring = 0; ring < rings; ++ring) {
    std::map<V, std::pair<Vec, double>> next;
    for (const auto& [v, d] : layer)
      for (auto h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
        const V w = m.source(h);
        if (all.count(w)) continue;
        // only along faces new from the embedding
        const auto f = m.face(h), g = m.face(m.opposite(h));
        if (ring == 0 &&
            (!has_new || !((f != Mesh<K>::null_face() && is_new[f]) || (g != Mesh<K>::null_face() && is_new[g]))))
          continue;
        const double l2 = CGAL::squared_distance(to_filtered(m.point(v)), to_filtered(m.point(w)));
        const double weight = 1.0 / std::max(l2, 1e-300);
        auto& [sum, weights] = next.try_emplace(w, Vec(0, 0, 0), 0.0).first->second;
        sum = sum + d * weight;
        weights += weight;
      }
    layer.clear();
    for (const auto& [w, sw] : next) {
      const Vec d = sw.first / sw.second;
      layer.emplace(w, d);
      all.emplace(w, d);
      shift.emplace(w, d);
    }
  }
  // The new positions, then the test of every face around a moved vertex.
  std::map<V, typename K::Point_3> position;
  for (const auto& [v, p] : target) position.emplace(v, p);
  for (const auto& [w, d] : shift) {
    auto p = m.point(w) + typename K::Vector_3(d.x(), d.y(), d.z());
    make_exact(p);
    position.emplace(w, p);
  }
  auto at = [&](V v) -> const typename K::Point_3& {
    const auto it = position.find(v);
    return it != position.end() ? it->second : m.point(v);
  };
  std::set<typename Mesh<K>::Face_index> faces;
  for (const auto& [v, p] : position)
    for (auto f : CGAL::faces_around_target(m.halfedge(v), m))
      if (f != Mesh<K>::null_face()) faces.insert(f);
  for (auto f : faces) {
    std::array<V, 3> c;
    int i = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c[i++] = v;
    const auto n_old = CGAL::cross_product(m.point(c[1]) - m.point(c[0]), m.point(c[2]) - m.point(c[0]));
    const auto n_new = CGAL::cross_product(at(c[1]) - at(c[0]), at(c[2]) - at(c[0]));
    if (CGAL::collinear(at(c[0]), at(c[1]), at(c[2])) || !CGAL::is_positive(n_old * n_new)) {
      for (const V v : c)
        if (target.count(v)) {
          const auto q = to_filtered(target.at(v));
          report.folded = say("(", q.x(), ", ", q.y(), ", ", q.z(), ")");
          report.fold_distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(m.point(v), target.at(v))));
          return report;
        }
      report.folded = "a face next to the curve";
      return report;
    }
  }
  for (const auto& [v, p] : position) {
    report.max_move = std::max(report.max_move, std::sqrt(CGAL::to_double(CGAL::squared_distance(m.point(v), p))));
    m.point(v) = p;
  }
  return report;
}

/// A and B's crossings of one given curve (`ka`, `kb`, each in order along it) merged by their
/// place along the curve: A's and B's points at the same place are one joint.
template <class K>
std::vector<Joint> merge_by_place(std::size_t c, const std::vector<KeptPoint<K>>& ka, const std::vector<KeptPoint<K>>& kb) {
  std::vector<Joint> joints;
  std::size_t i = 0, j = 0;
  auto key = [](const KeptPoint<K>& k) { return std::make_pair(k.s, k.t); };
  while (i < ka.size() || j < kb.size()) {
    if (i < ka.size() && j < kb.size() && key(ka[i]) == key(kb[j])) {
      joints.push_back({ka[i].s, ka[i].t, long(i), long(j)});
      ++i, ++j;
    } else if (j == kb.size() || (i < ka.size() && key(ka[i]) < key(kb[j]))) {
      joints.push_back({ka[i].s, ka[i].t, long(i), -1});
      ++i;
    } else {
      joints.push_back({kb[j].s, kb[j].t, -1, long(j)});
      ++j;
    }
    if (joints.size() >= 2 && joints[joints.size() - 2].s == joints.back().s &&
        joints[joints.size() - 2].t == joints.back().t) {
      std::ostringstream msg;
      msg << "curve " << c << ": two crossings of one mesh fall on the same place of the curve (node "
          << joints.back().s << "); refine the curve there";
      throw InvalidInput(msg.str());
    }
  }
  return joints;
}

/// The shared points, on the given curve: a node, the curve's point closest to a crossed edge,
/// or node + fraction x segment (exact).
template <class K>
Polyline<K> shared_points(const Polyline<K>& curve, const std::vector<Joint>& joints,
                          const std::vector<KeptPoint<K>>& ka, const std::vector<KeptPoint<K>>& kb) {
  Polyline<K> u;
  for (const Joint& jt : joints) {
    if (jt.ia >= 0 && ka[std::size_t(jt.ia)].on_curve) {
      u.push_back(*ka[std::size_t(jt.ia)].on_curve);
      continue;
    }
    if (jt.ib >= 0 && kb[std::size_t(jt.ib)].on_curve) {
      u.push_back(*kb[std::size_t(jt.ib)].on_curve);
      continue;
    }
    if (jt.t == 0) {
      u.push_back(curve[jt.s]);
      continue;
    }
    typename K::Point_3 p = curve[jt.s] + (curve[jt.s + 1] - curve[jt.s]) * typename K::FT(jt.t);
    make_exact(p);
    u.push_back(p);
  }
  return u;
}

/// Steps 3, 4: the common coarsened curves (`shared`), and where each of their points lies in A
/// and in B (`in_a`, `in_b`: on the mesh, to be embedded; moved onto `shared` afterwards).
template <class K> struct CommonCurves {
  std::vector<Polyline<K>> in_a, in_b, shared;
};

template <class K>
CommonCurves<K> common_curves(const Mesh<K>& a, const Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                              const std::vector<internal::TracedCurve<K>>& ta,
                              const std::vector<internal::TracedCurve<K>>& tb) {
  CommonCurves<K> result;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto ka = kept_points<K>(a, ta[c], curves[c]);
    const auto kb = kept_points<K>(b, tb[c], curves[c]);
    const bool closed = ta[c].closed && tb[c].closed;
    if (ta[c].closed != tb[c].closed) throw InternalError("pair: a given curve is closed on one mesh only");
    const std::vector<Joint> joints = merge_by_place<K>(c, ka, kb);
    const double period = double(curves[c].size() - 1);
    Polyline<K> u = shared_points<K>(curves[c], joints, ka, kb);
    auto pa = positions_in<K>(a, joints, ka, u, true, closed, period);
    auto pb = positions_in<K>(b, joints, kb, u, false, closed, period);
    if (closed) pa.push_back(pa.front()), pb.push_back(pb.front()), u.push_back(u.front());
    result.in_a.push_back(std::move(pa));
    result.in_b.push_back(std::move(pb));
    result.shared.push_back(std::move(u));
  }
  return result;
}

/// Runs `step` on mesh `name`, its InvalidInput prefixed with the mesh's name.
template <class Step> auto on_mesh(const char* name, Step&& step) {
  try {
    return step();
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("mesh ") + name + ": " + e.what());
  }
}

/// Step 5: the curve vertices of `m` (embedded at `r.curve_vertices`) onto the shared curves,
/// the faces around them along; a fold is a FoldError. Returns the largest move.
template <class K>
double move_onto_shared(Mesh<K>& m, const char* name, EmbedResult<K>& r, const std::vector<Polyline<K>>& shared) {
  if (r.curve_vertices.size() != shared.size())
    throw InternalError("pair: the given curves were embedded into a different number of curves");
  std::map<typename Mesh<K>::Vertex_index, typename K::Point_3> target;
  for (std::size_t c = 0; c < shared.size(); ++c) {
    const auto& vs = r.curve_vertices[c];
    if (vs.size() != shared[c].size()) {
      std::ostringstream msg;
      msg << "pair: given curve " << c << " has " << shared[c].size() << " common points but " << vs.size()
          << " after embedding into mesh " << name << (kernel_traits<K>::exact_constructions ? "" : " (rounded arithmetic)");
      throw InternalError(msg.str());
    }
    for (std::size_t k = 0; k < vs.size(); ++k) target.emplace(vs[k], shared[c][k]);
  }
  const auto moved = move_onto_curves<K>(m, target, 3);
  if (!moved.folded.empty()) {
    std::ostringstream msg;
    msg << "a given curve lies " << moved.fold_distance << " from mesh " << name << " at " << moved.folded
        << ", too far for the mesh's resolution there: moving the mesh onto it would fold a face";
    throw FoldError(msg.str());
  }
  r.curves = shared;
  return moved.max_move;
}

template <class K>
PairResult<K> pair_given_once(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                              const PairOptions& options) {
  validate_options(options.embed);
  for (std::size_t c = 0; c < curves.size(); ++c)
    if (curves[c].size() < 2) {
      std::ostringstream msg;
      msg << "curve " << c << " has fewer than 2 points";
      throw InvalidInput(msg.str());
    }
  PairResult<K> result;
  PairStats& st = result.stats;
  st.given_curves = true;
  const double la = mean_edge_length<K>(a), lb = mean_edge_length<K>(b);
  const double snap_tol = options.embed.snap_tol < 0 ? 0.1 * std::min(la, lb) : options.embed.snap_tol;
  st.snap_tol = snap_tol;

  // ---- 1. snap both meshes onto the curve nodes
  auto t = Clock::now();
  std::size_t snapped_a = 0, snapped_b = 0;
  if (snap_tol > 0) {
    snapped_a = internal::snap_vertices<K>(a, curves, snap_tol).snapped;
    snapped_b = internal::snap_vertices<K>(b, curves, snap_tol).snapped;
  }
  st.stage_seconds["snap"] = seconds_since(t);

  // ---- 2. follow the curves on both meshes
  t = Clock::now();
  const double dist_a = options.embed.max_distance < 0 ? la : options.embed.max_distance;
  const double dist_b = options.embed.max_distance < 0 ? lb : options.embed.max_distance;
  internal::TraceReport report;
  const auto ta = on_mesh("A", [&] { return internal::trace_curves<K>(a, curves, dist_a, report, false, kFeatureTol); });
  const auto tb = on_mesh("B", [&] { return internal::trace_curves<K>(b, curves, dist_b, report, false, kFeatureTol); });
  st.stage_seconds["trace"] = seconds_since(t);

  // ---- 3, 4. the common coarsened curve, placed in each mesh
  t = Clock::now();
  const CommonCurves<K> common = common_curves<K>(a, b, curves, ta, tb);
  st.stage_seconds["merge"] = seconds_since(t);

  // Embed: every point lies on its mesh (edges, vertices or faces of the trace), keep them all.
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();
  t = Clock::now();
  result.a = on_mesh("A", [&] { return embed<K>(a, common.in_a, eo); });
  st.stage_seconds["embed_a"] = seconds_since(t);
  t = Clock::now();
  result.b = on_mesh("B", [&] { return embed<K>(b, common.in_b, eo); });
  st.stage_seconds["embed_b"] = seconds_since(t);
  result.a.stats.vertices_snapped = snapped_a;
  result.b.stats.vertices_snapped = snapped_b;

  // ---- 5. both meshes' curve vertices onto the given curve, the faces around them along
  t = Clock::now();
  const double moved_a = move_onto_shared<K>(a, "A", result.a, common.shared);
  const double moved_b = move_onto_shared<K>(b, "B", result.b, common.shared);
  st.max_curve_move = std::max(moved_a, moved_b);
  st.stage_seconds["move"] = seconds_since(t);

  const auto& shared = common.shared;
  result.curves = shared;
  st.curves = shared.size();
  for (const auto& c : shared) {
    const bool closed = is_closed(c);
    st.closed_curves += closed ? 1 : 0;
    st.curve_vertices += closed ? c.size() - 1 : c.size();
  }
  if (shared.empty()) st.note = "no curves given: nothing to embed";
  return result;
}

}  // namespace

/// The given curves as the shape of the computed intersection (the first method): the meshes'
/// exact intersection curves are embedded by seam::pair (with its snapping and remeshing as the
/// options say), then every curve vertex moves, in both meshes alike, to the closest point of the
/// given curves (its segment parameter rounded to a double: exactly on the given segment), and
/// the faces along with it (move_onto_curves). Both meshes share the moved curve by
/// construction; they met only along it before the move. Empty, with `why`, where a curve point
/// is farther than max_distance from the given curves, two consecutive ones go to the same point,
/// a face would fold, or the meshes do not intersect.
template <class K>
std::optional<PairResult<K>> pair_onto_given(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& given,
                                             const PairOptions& options, bool improve_before_move, std::string& why) {
  using FT = typename K::FT;
  using Point = typename K::Point_3;
  using FS = Filtered::Segment_3;
  PairOptions o = options;
  o.verify_output = false;  // (the caller verifies the moved result)
  o.improve = false;
  PairResult<K> r = pair<K>(a, b, o);
  if (r.curves.empty()) {
    why = "the meshes do not intersect";
    return std::nullopt;
  }
  const double max_distance = options.embed.max_distance >= 0
                                  ? options.embed.max_distance
                                  : std::min(mean_edge_length<K>(a), mean_edge_length<K>(b));
  std::vector<FS> segments;
  std::vector<std::pair<std::size_t, std::size_t>> which;
  for (std::size_t c = 0; c < given.size(); ++c)
    for (std::size_t i = 0; i + 1 < given[c].size(); ++i) {
      const auto p = to_filtered(given[c][i]), q = to_filtered(given[c][i + 1]);
      if (p == q) continue;
      segments.emplace_back(p, q);
      which.emplace_back(c, i);
    }
  if (segments.empty()) {
    why = "no given curve has a segment";
    return std::nullopt;
  }
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Filtered, CGAL::AABB_segment_primitive<Filtered, std::vector<FS>::const_iterator>>>;
  Tree tree(segments.begin(), segments.end());
  tree.accelerate_distance_queries();
  // Each curve point's target: the closest point of the given curves (on a given segment, at a
  // parameter rounded to a double); false (and `why`) when one is too far or two coincide.
  double farthest = 0;
  std::vector<Polyline<K>> moved;
  auto targets = [&]() {
    moved.assign(r.curves.size(), {});
    farthest = 0;
    for (std::size_t c = 0; c < r.curves.size(); ++c) {
      const bool closed = is_closed(r.curves[c]);
      for (std::size_t k = 0; k < r.curves[c].size(); ++k) {
        if (closed && k + 1 == r.curves[c].size()) {
          moved[c].push_back(moved[c].front());
          break;
        }
        const Point& p = r.curves[c][k];
        const auto [closest, id] = tree.closest_point_and_primitive(to_filtered(p));
        const auto [gc, gi] = which[std::size_t(id - segments.cbegin())];
        const Point &q0 = given[gc][gi], &q1 = given[gc][gi + 1];
        const auto d = q1 - q0;
        const double t = std::clamp(CGAL::to_double(((p - q0) * d) / (d * d)), 0.0, 1.0);
        Point target = t == 0 ? q0 : t == 1 ? q1 : q0 + d * FT(t);
        make_exact(target);
        const double distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(p, target)));
        farthest = std::max(farthest, distance);
        if (distance > max_distance) {
          why = say("the computed intersection passes ", distance, " from the given curves (more than ", max_distance,
                    ")");
          return false;
        }
        if (!moved[c].empty() && moved[c].back() == target) {
          why = "two consecutive points of the computed intersection have the same closest point on the given curves";
          return false;
        }
        moved[c].push_back(target);
      }
    }
    return true;
  };
  if (!targets()) return std::nullopt;
  // Before the move, the quality stage at a tolerance of twice the farthest move: the faces next
  // to the curves then move by a fraction of their size, instead of folding.
  if (improve_before_move) {
    r.stats.snap_tol = std::max(r.stats.snap_tol, 2 * farthest);
    improve_pair<K>(a, b, r, o);
    if (!targets()) return std::nullopt;
  }
  auto& st = r.stats;
  for (auto* e : {&r.a, &r.b}) {
    Mesh<K>& m = e == &r.a ? a : b;
    std::map<typename Mesh<K>::Vertex_index, Point> target;
    for (std::size_t c = 0; c < moved.size(); ++c)
      for (std::size_t k = 0; k < moved[c].size(); ++k) target.emplace(e->curve_vertices[c][k], moved[c][k]);
    // The move spread over more rings where it would fold a face (three, then six, then ten).
    CurveMove how;
    for (int rings : {3, 6, 10})
      if ((how = move_onto_curves<K>(m, target, rings)).folded.empty()) break;
    if (!how.folded.empty()) {
      why = say("moving mesh ", e == &r.a ? "A" : "B", " onto the given curves would fold a face at ", how.folded);
      return std::nullopt;
    }
    st.max_curve_move = std::max(st.max_curve_move, how.max_move);
    e->curves = moved;
  }
  r.curves = moved;
  st.given_curves = true;
  // The quality stage on the moved meshes (they are its input surfaces), the curves kept.
  if (options.improve) {
    PairOptions fixed = options;
    fixed.quality.curves_fixed = true;
    improve_pair<K>(a, b, r, fixed);
  }
  return r;
}

template <class K>
PairResult<K> pair_with_curves(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                               const PairOptions& options) {
  check_coordinate_range<K>(a, "A");
  check_coordinate_range<K>(b, "B");
  check_coordinate_range<K>(curves, "the given curves");
  for (std::size_t c = 0; c < curves.size(); ++c)
    if (curves[c].size() < 2) {
      std::ostringstream msg;
      msg << "curve " << c << " has fewer than 2 points";
      throw InvalidInput(msg.str());
    }
  const Mesh<K> a0 = a, b0 = b;
  std::string problem, tried;
  auto passes = [&](PairResult<K>& result) {
    return !options.verify_output || internal::verify_outputs<K>(a0, b0, a, b, result, problem);
  };
  auto restore = [&]() {
    a = a0;
    b = b0;
  };
  // 1. The computed intersection moved onto the given curves: embedded and improved first (the
  //    quality stage removes the slivers that the move would fold), then, failing that, as
  //    embedded; the quality stage runs again after the move (as the options say).
  for (const bool improve_first : {true, false}) {
    std::string why;
    if (auto r = pair_onto_given<K>(a, b, curves, options, improve_first, why)) {
      if (passes(*r)) {
        if (!tried.empty()) r->stats.note = tried + (r->stats.note.empty() ? "" : "; " + r->stats.note);
        return std::move(*r);
      }
      why = problem;
    }
    tried += (tried.empty() ? "" : "; ") +
             std::string(improve_first ? "improved, then " : "as embedded, then ") +
             "the computed intersection moved onto the given curves failed (" + why + ")";
    restore();
  }
  // 2. The given curves followed on each mesh (see the top of this file), with snapping, then
  //    without where a face would fold.
  PairOptions no_snap = options;
  no_snap.embed.snap_tol = 0;
  const bool snapping = options.embed.snap_tol != 0;
  std::optional<PairResult<K>> result;
  try {
    try {
      result = pair_given_once<K>(a, b, curves, options);
    } catch (const FoldError& e) {
      if (!snapping) throw;
      restore();
      result = pair_given_once<K>(a, b, curves, no_snap);
      result->stats.note = std::string("snapping undone (") + e.what() + ")";
    }
  } catch (const FoldError& e) {
    restore();
    throw FoldError(std::string(e.what()) + " (before: " + tried + ")");
  }
  if (options.improve) {
    PairOptions fixed = options;
    fixed.quality.curves_fixed = true;
    improve_pair<K>(a, b, *result, fixed);
  }
  result->stats.note = tried + (result->stats.note.empty() ? "" : "; " + result->stats.note);
  if (passes(*result)) return std::move(*result);
  restore();
  throw InternalError("pair: the outputs fail seam check's tests, so none is given (" + problem + "; before: " +
                      tried + ")");
}

#define SEAM_INSTANTIATE(K)                                                                                \
  template PairResult<K> pair_with_curves<K>(Mesh<K>&, Mesh<K>&, const std::vector<Polyline<K>>&,         \
                                             const PairOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
