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
#include <seam/internal/coarsen.h>
#include <seam/internal/snap.h>
#include <seam/internal/trace.h>
#include <seam/pair.h>

#include <algorithm>
#include <optional>
#include <chrono>
#include <cmath>
#include <sstream>

namespace seam {

namespace {

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

/// The points of one traced curve that the embedding keeps (see step 2 above), in curve order;
/// for a closed curve without the closing repeat.
template <class K>
std::vector<KeptPoint<K>> kept_points(const Mesh<K>& mesh, const internal::TracedCurve<K>& tc,
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
  // Kept: points on edges and vertices, the end nodes of an open curve.
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

template <class K>
PairResult<K> pair_given_once(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                              const PairOptions& options) {
  using FT = typename K::FT;
  using Point = typename K::Point_3;
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
  if (snap_tol > 0) {
    const auto sa = internal::snap_vertices<K>(a, curves, snap_tol);
    const auto sb = internal::snap_vertices<K>(b, curves, snap_tol);
    st.vertices_snapped_a = sa.snapped;
    st.vertices_snapped_b = sb.snapped;
    st.snaps_refused = sa.refused + sb.refused;
  }
  st.stage_seconds["snap"] = seconds_since(t);

  // ---- 2. follow the curves on both meshes
  t = Clock::now();
  const double dist_a = options.embed.max_distance < 0 ? la : options.embed.max_distance;
  const double dist_b = options.embed.max_distance < 0 ? lb : options.embed.max_distance;
  internal::TraceReport report;
  std::vector<internal::TracedCurve<K>> ta, tb;
  try {
    ta = internal::trace_curves<K>(a, curves, dist_a, report, false, kFeatureTol);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("mesh A: ") + e.what());
  }
  try {
    tb = internal::trace_curves<K>(b, curves, dist_b, report, false, kFeatureTol);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("mesh B: ") + e.what());
  }
  st.stage_seconds["trace"] = seconds_since(t);

  // ---- 3, 4. the common coarsened curve, placed in each mesh
  t = Clock::now();
  std::vector<Polyline<K>> in_a, in_b, shared;
  std::vector<std::size_t> sizes;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto ka = kept_points<K>(a, ta[c], curves[c]);
    const auto kb = kept_points<K>(b, tb[c], curves[c]);
    const bool closed = ta[c].closed && tb[c].closed;
    if (ta[c].closed != tb[c].closed) throw InternalError("pair: a given curve is closed on one mesh only");
    // Merge by place along the curve; A's and B's points at the same place are one point.
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
    const double period = double(curves[c].size() - 1);
    // The shared points, on the given curve: a node, the curve's point closest to a crossed edge,
    // or node + fraction x segment.
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
        u.push_back(curves[c][jt.s]);
        continue;
      }
      Point p = curves[c][jt.s] + (curves[c][jt.s + 1] - curves[c][jt.s]) * FT(jt.t);
      make_exact(p);
      u.push_back(p);
    }
    auto pa = positions_in<K>(a, joints, ka, u, true, closed, period);
    auto pb = positions_in<K>(b, joints, kb, u, false, closed, period);
    if (closed) pa.push_back(pa.front()), pb.push_back(pb.front()), u.push_back(u.front());
    in_a.push_back(std::move(pa));
    in_b.push_back(std::move(pb));
    shared.push_back(std::move(u));
  }
  st.stage_seconds["merge"] = seconds_since(t);

  // Embed: every point lies on its mesh (edges, vertices or faces of the trace), keep them all.
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();
  t = Clock::now();
  try {
    result.a = embed<K>(a, in_a, eo);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("mesh A: ") + e.what());
  }
  st.stage_seconds["embed_a"] = seconds_since(t);
  t = Clock::now();
  try {
    result.b = embed<K>(b, in_b, eo);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("mesh B: ") + e.what());
  }
  st.stage_seconds["embed_b"] = seconds_since(t);
  result.a.stats.vertices_snapped = st.vertices_snapped_a;
  result.b.stats.vertices_snapped = st.vertices_snapped_b;

  // ---- 5. both meshes' curve vertices onto the given curve
  t = Clock::now();
  for (auto* r : {&result.a, &result.b}) {
    Mesh<K>& m = r == &result.a ? a : b;
    const char* name = r == &result.a ? "A" : "B";
    if (r->curve_vertices.size() != shared.size())
      throw InternalError("pair: the given curves were embedded into a different number of curves");
    for (std::size_t c = 0; c < shared.size(); ++c) {
      const auto& vs = r->curve_vertices[c];
      if (vs.size() != shared[c].size()) {
        std::ostringstream msg;
        msg << "pair: given curve " << c << " has " << shared[c].size() << " common points but " << vs.size()
            << " after embedding into mesh " << name << (kernel_traits<K>::exact_constructions ? "" : " (rounded arithmetic)");
        throw InternalError(msg.str());
      }
      for (std::size_t k = 0; k < vs.size(); ++k) {
        if (m.point(vs[k]) == shared[c][k]) continue;
        if (!internal::move_keeps_faces<K>(m, vs[k], shared[c][k])) {
          double shortest = std::numeric_limits<double>::max();
          for (auto h : CGAL::halfedges_around_target(m.halfedge(vs[k]), m))
            shortest = std::min(shortest, std::sqrt(CGAL::to_double(
                                              CGAL::squared_distance(m.point(m.source(h)), m.point(vs[k])))));
          std::ostringstream msg;
          msg << "curve " << c << ": point " << k << " lies "
              << std::sqrt(CGAL::to_double(CGAL::squared_distance(m.point(vs[k]), shared[c][k]))) << " from mesh "
              << name << ", too far for its resolution there (edges from " << shortest
              << "): moving the mesh onto it would fold a face";
          throw FoldError(msg.str());
        }
        st.max_curve_move = std::max(
            st.max_curve_move, std::sqrt(CGAL::to_double(CGAL::squared_distance(m.point(vs[k]), shared[c][k]))));
        m.point(vs[k]) = shared[c][k];
      }
    }
    r->curves = shared;
  }
  st.stage_seconds["move"] = seconds_since(t);

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

template <class K>
PairResult<K> pair_with_curves(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                               const PairOptions& options) {
  if (options.embed.snap_tol == 0) return pair_given_once<K>(a, b, curves, options);
  // Snapping bends each surface towards the curve nodes only, and the curve vertices between them
  // can then lie too far from a small face to move onto the curve: without snapping, then.
  const Mesh<K> a0 = a, b0 = b;
  try {
    return pair_given_once<K>(a, b, curves, options);
  } catch (const FoldError& e) {
    a = a0;
    b = b0;
    PairOptions no_snap = options;
    no_snap.embed.snap_tol = 0;
    PairResult<K> result = pair_given_once<K>(a, b, curves, no_snap);
    result.stats.note = std::string("snapping undone (") + e.what() + ")";
    return result;
  }
}

#define SEAM_INSTANTIATE(K)                                                                                \
  template PairResult<K> pair_with_curves<K>(Mesh<K>&, Mesh<K>&, const std::vector<Polyline<K>>&,         \
                                             const PairOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
