// seam, pipeline steps 2-3: locate curve nodes and follow the curve across the mesh.
// See seam/internal/trace.h for the method and what is exact.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/trace.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <tuple>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace seam::internal {

namespace {

using DK = CGAL::Exact_predicates_inexact_constructions_kernel;  // the AABB search runs on doubles
using DTriangle = DK::Triangle_3;
using DIterator = std::vector<DTriangle>::const_iterator;
using DPrimitive = CGAL::AABB_triangle_primitive<DK, DIterator>;
using DTree = CGAL::AABB_tree<CGAL::AABB_traits<DK, DPrimitive>>;

template <class K> class Tracer {
  using T = MeshTypes<K>;
  using V = typename T::V;
  using E = typename T::E;
  using F = typename T::F;
  using Point = typename K::Point_3;
  using Vector = typename K::Vector_3;
  using FT = typename K::FT;
  using SP = SurfacePoint<K>;

 public:
  /// The search covers the faces whose bounding box meets `region` (all faces when it is null).
  /// A node whose closest point found there is not surely the closest on the whole mesh (the
  /// ball around it reaches out of the region) is searched again among all faces.
  Tracer(const Mesh<K>& mesh, double feature_tol, const CGAL::Bbox_3* region)
      : m_(mesh), feature_tol_(feature_tol) {
    if (region) region_ = *region;
  }

  /// The face closest to q (searched in doubles), the (rounded) distance from q to the surface in
  /// `distance`, and the face's squared area (doubles).
  F closest_face(const Point& q, double& distance, double& squared_area) const {
    const auto dq = to_filtered(q);
    if (!near_) near_ = build_search(region_ ? &*region_ : nullptr);  // on the first node searched for
    const Search* search = near_.get();
    auto [dp, it] = search->tree.closest_point_and_primitive(dq);
    distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(dq, dp)));
    if (region_) {
      // Faces outside the region lie farther from dq than the region's walls.
      const auto& r = *region_;
      const double wall = std::min({dq.x() - r.xmin(), r.xmax() - dq.x(), dq.y() - r.ymin(), r.ymax() - dq.y(),
                                    dq.z() - r.zmin(), r.zmax() - dq.z()});
      if (!(distance * (1 + 1e-12) < wall)) {
        if (!all_) all_ = build_search(nullptr);
        search = all_.get();
        std::tie(dp, it) = search->tree.closest_point_and_primitive(dq);
        distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(dq, dp)));
      }
    }
    squared_area = CGAL::to_double(it->squared_area());
    return search->face_of[std::size_t(it - search->triangles.begin())];
  }

  /// locate() for a point that lies on the surface exactly (under exact constructions): the face
  /// holding q is found among the closest face and the faces around its corners (locate's
  /// candidates) by exact predicates on q itself, instead of by constructing q's projection onto
  /// each and comparing it with q (which needs the projections' exact values). The same answer
  /// as locate's where q lies on one of those faces (what q lies on does not depend on which face
  /// holding it is tested first); otherwise locate().
  SP locate_on_surface(const Point& q, double& distance) const {
    double squared_area = 0;
    const F f = closest_face(q, distance, squared_area);
    const auto hf = m_.halfedge(f);
    // (A closest face with collinear corners, which a valid input has not: locate's answer.)
    if (CGAL::collinear(m_.point(m_.source(hf)), m_.point(m_.target(hf)), m_.point(m_.target(m_.next(hf)))))
      return locate(q, distance);
    if (distance <= 1e-9 * std::sqrt(squared_area)) {
      auto holds = [&](F g) {  // q in the closed face g (a face with collinear corners: no)
        auto h = m_.halfedge(g);
        const Point &a = m_.point(m_.source(h)), &b = m_.point(m_.target(h)), &c = m_.point(m_.target(m_.next(h)));
        return !CGAL::collinear(a, b, c) && CGAL::orientation(a, b, c, q) == CGAL::COPLANAR &&
               CGAL::coplanar_orientation(a, b, c, q) != CGAL::NEGATIVE &&
               CGAL::coplanar_orientation(b, c, a, q) != CGAL::NEGATIVE &&
               CGAL::coplanar_orientation(c, a, b, q) != CGAL::NEGATIVE;
      };
      F found = holds(f) ? f : Mesh<K>::null_face();
      for (V w : CGAL::vertices_around_face(m_.halfedge(f), m_)) {
        if (found != Mesh<K>::null_face()) break;
        for (F g : CGAL::faces_around_target(m_.halfedge(w), m_))
          if (g != Mesh<K>::null_face() && g != f && holds(g)) {
            found = g;
            break;
          }
      }
      if (found != Mesh<K>::null_face()) {
        ++located_by_predicates;
        return classify_in_face(found, q);
      }
    }
    return locate(q, distance);
  }

  /// Nodes locate_on_surface found on a face by exact predicates (not by locate).
  mutable std::size_t located_by_predicates = 0;

  /// Projects q onto the closest face and classifies the projection. `distance` gets the
  /// (rounded) distance from q to the surface.
  SP locate(const Point& q, double& distance) const {
    double squared_area = 0;
    F f = closest_face(q, distance, squared_area);
    auto project = [&](F g) { return typename K::Construct_projected_point_3()(triangle(g), q); };
    // The closest point of the triangle, constructed in the kernel (exact under Epeck).
    // Not made exact here: most located nodes are dropped by coarsening, and forcing the exact
    // value of each projection dominated the run time. The points that are kept are made exact
    // when coarsening registers them (CurvePoints::id).
    Point p = project(f);
    if constexpr (kernel_traits<K>::exact_constructions) {
      // A point lying exactly on the surface (a computed intersection point): the search on
      // doubles may return a neighbour of the face that contains it. Look for that face among
      // the faces around the found one, so that such a point is located exactly where it is.
      if (distance <= 1e-9 * std::sqrt(squared_area) && !(p == q)) {
        for (V w : CGAL::vertices_around_face(m_.halfedge(f), m_))
          for (F g : CGAL::faces_around_target(m_.halfedge(w), m_))
            if (g != Mesh<K>::null_face() && g != f && project(g) == q) {
              f = g;
              p = q;
              break;
            }
      }
    }
    auto h = m_.halfedge(f);
    const V va = m_.source(h), vb = m_.target(h), vc = m_.target(m_.next(h));
    const Point &a = m_.point(va), &b = m_.point(vb), &c = m_.point(vc);
    if (std::optional<SP> on_boundary = classify_on_boundary(f, p)) return *on_boundary;
    SP sp;
    sp.p = p;
    if (!kernel_traits<K>::exact_constructions || (feature_tol_ > 0 && !(p == q))) {
      // Rounded constructions: a projection onto the boundary of the triangle comes back a
      // rounding error off it, so the exact tests above miss it. Classify by barycentric
      // coordinates instead, with a relative tolerance of 1e-9 (a node that close to an edge is
      // put on it, by the exact projection under Epeck). Under exact constructions only with a
      // feature tolerance, for a node off the surface (given curves, rounded to doubles).
      const double A[3] = {CGAL::to_double(a.x()), CGAL::to_double(a.y()), CGAL::to_double(a.z())};
      const double B[3] = {CGAL::to_double(b.x()), CGAL::to_double(b.y()), CGAL::to_double(b.z())};
      const double C[3] = {CGAL::to_double(c.x()), CGAL::to_double(c.y()), CGAL::to_double(c.z())};
      const double P[3] = {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
      auto cross_norm = [](const double* o, const double* u, const double* w) {
        const double x1 = u[0] - o[0], y1 = u[1] - o[1], z1 = u[2] - o[2];
        const double x2 = w[0] - o[0], y2 = w[1] - o[1], z2 = w[2] - o[2];
        const double cx = y1 * z2 - z1 * y2, cy = z1 * x2 - x1 * z2, cz = x1 * y2 - y1 * x2;
        return std::sqrt(cx * cx + cy * cy + cz * cz);
      };
      const double area = cross_norm(A, B, C);
      const double la = cross_norm(P, B, C) / area, lb = cross_norm(P, C, A) / area, lc = cross_norm(P, A, B) / area;
      const double eps = kernel_traits<K>::exact_constructions ? feature_tol_ : std::max(1e-9, feature_tol_);
      const int small = (la < eps) + (lb < eps) + (lc < eps);
      if (small >= 2) {
        sp.where = Where::vertex;
        sp.v = la >= eps ? va : lb >= eps ? vb : vc;
        sp.p = m_.point(sp.v);
        return sp;
      }
      if (small == 1) {
        const V s = la < eps ? vb : lb < eps ? vc : va;
        const V t = la < eps ? vc : lb < eps ? va : vb;
        sp.where = Where::edge;
        sp.e = m_.edge(m_.halfedge(s, t));
        // the projection onto the edge's line (rounded)
        const auto& ps = m_.point(s);
        const auto& pt = m_.point(t);
        sp.p = ps + (pt - ps) * (((p - ps) * (pt - ps)) / (pt - ps).squared_length());
        make_exact(sp.p);
        if (sp.p == ps || sp.p == pt) {
          sp.where = Where::vertex;
          sp.v = sp.p == ps ? s : t;
        }
        return sp;
      }
    }
    sp.where = Where::face;
    sp.f = f;
    return sp;
  }

  /// Point p of the closed face f (exact tests) where it is a corner or on a side of f.
  std::optional<SP> classify_on_boundary(F f, const Point& p) const {
    auto h = m_.halfedge(f);
    const V va = m_.source(h), vb = m_.target(h), vc = m_.target(m_.next(h));
    const Point &a = m_.point(va), &b = m_.point(vb), &c = m_.point(vc);
    SP sp;
    sp.p = p;
    if (p == a || p == b || p == c) {
      sp.where = Where::vertex;
      sp.v = (p == a) ? va : (p == b) ? vb : vc;
      sp.p = m_.point(sp.v);
      return sp;
    }
    const std::pair<V, V> sides[3] = {{va, vb}, {vb, vc}, {vc, va}};
    for (const auto& [s, t] : sides) {
      if (CGAL::collinear(m_.point(s), m_.point(t), p)) {
        sp.where = Where::edge;
        sp.e = m_.edge(m_.halfedge(s, t));
        return sp;
      }
    }
    return std::nullopt;
  }

  /// Point p of the closed face f (exact tests): a corner, a side or the face.
  SP classify_in_face(F f, const Point& p) const {
    if (std::optional<SP> on_boundary = classify_on_boundary(f, p)) return *on_boundary;
    SP sp;
    sp.p = p;
    sp.where = Where::face;
    sp.f = f;
    return sp;
  }

  /// Face g as a kernel triangle, built once per face: under Epeck each projection onto it keeps
  /// a reference to the triangle in its lazy expression, so one triangle per located node cost
  /// about 200 bytes per node (a million nodes in one face: 200 MB).
  const typename K::Triangle_3& triangle(F g) const {
    auto [it, inserted] = triangles_.try_emplace(std::size_t(g));
    if (inserted) it->second = face_triangle<K>(m_, g);
    return it->second;
  }

  /// Unnormalised outward normal of face f (exact under Epeck).
  Vector face_normal(F f) const {
    auto h = m_.halfedge(f);
    const Point& a = m_.point(m_.source(h));
    return CGAL::cross_product(m_.point(m_.target(h)) - a, m_.point(m_.target(m_.next(h))) - a);
  }

  Vector normal_at(const SP& sp) const {
    Vector n = CGAL::NULL_VECTOR;
    for (F f : incident_faces<K>(m_, sp)) n = n + face_normal(f);
    return n;
  }

  /// A point through which the cutting plane passes: a mesh vertex itself, else the point
  /// rounded to double.
  static Point anchor(const SP& x) {
    if (x.where == Where::vertex) return x.p;
    const auto r = to_filtered(x.p);
    return Point(r.x(), r.y(), r.z());
  }

  /// Appends the path from P (excluded) to Q (included) to `points`/`faces`. False on failure.
  bool walk(const SP& P, const SP& Q, const Vector& n, std::vector<SP>& points, std::vector<F>& faces) const {
    // The cutting plane only guides the walk: the path is valid (consecutive points share a
    // face) whatever the plane, and every crossing is an exact point of its edge. So the plane
    // goes through P and Q rounded to double (exactly through them when they are mesh
    // vertices): its coefficients stay small, and so do the exact crossing points, instead of
    // compounding the exact projections of the nodes.
    const Point P0 = anchor(P), Q0 = anchor(Q);
    const Point R = P0 + n;
    if (n == CGAL::NULL_VECTOR || CGAL::collinear(P0, Q0, R)) return false;
    // Side of the cutting plane through P0, Q0 and R, cached per vertex (exact predicate).
    std::unordered_map<std::size_t, CGAL::Orientation> side_cache;
    auto side = [&](V w) {
      auto [it, inserted] = side_cache.try_emplace(std::size_t(w), CGAL::COPLANAR);
      if (inserted) it->second = CGAL::orientation(P0, Q0, R, m_.point(w));
      return it->second;
    };
    const Vector plane_normal = CGAL::cross_product(Q0 - P0, R - P0);

    auto common_face = [&](const SP& x) -> F {
      for (F f : incident_faces<K>(m_, x))
        if (face_contains<K>(m_, f, Q)) return f;
      return Mesh<K>::null_face();
    };

    SP cur = P, prev = P;
    bool has_prev = false;
    std::unordered_set<std::size_t> used;
    const std::size_t limit = m_.number_of_faces() + 8;
    for (std::size_t step = 0; step < limit; ++step) {
      if (F g = common_face(cur); g != Mesh<K>::null_face()) {
        points.push_back(Q);
        faces.push_back(g);
        return true;
      }
      // Which exit heads most directly towards Q is a choice, not a topological decision (every
      // candidate is an exact point of the plane section): it is made on rounded coordinates.
      const auto cur_d = to_filtered(cur.p);
      const auto to_q = to_filtered(Q.p) - cur_d;
      bool found = false;
      SP best;
      F best_face;
      double best_score = 0;
      for (F f : incident_faces<K>(m_, cur)) {
        if (used.count(std::size_t(f))) continue;
        for (auto h : CGAL::halfedges_around_face(m_.halfedge(f), m_)) {
          const V s = m_.source(h), t = m_.target(h);
          const E e = m_.edge(h);
          SP cand;
          const CGAL::Orientation ss = side(s), st = side(t);
          if (st == CGAL::COPLANAR) {
            cand.where = Where::vertex;
            cand.v = t;
            cand.p = m_.point(t);
            if (cur.where == Where::vertex && cur.v == t) continue;
          } else if (ss != CGAL::COPLANAR && ss != st) {
            if (cur.where == Where::edge && cur.e == e) continue;
            // Exact intersection of edge (s, t) with the plane: s + (t - s) * ds / (ds - dt).
            const Point &ps = m_.point(s), &pt = m_.point(t);
            const FT ds = plane_normal * (ps - P0), dt = plane_normal * (pt - P0);
            const Point x = ps + (pt - ps) * (ds / (ds - dt));  // made exact once chosen
            if (x == ps || x == pt) {
              // Only with rounded constructions: the crossing rounded onto an end point of the
              // edge. Take that vertex, so that no two curve points coincide.
              cand.where = Where::vertex;
              cand.v = (x == ps) ? s : t;
              cand.p = m_.point(cand.v);
              if (cur.where == Where::vertex && cur.v == cand.v) continue;
            } else {
              cand.where = Where::edge;
              cand.e = e;
              cand.p = x;
            }
          } else {
            continue;
          }
          if (has_prev && cand.same_as(prev)) continue;
          if (cand.p == cur.p) continue;
          const auto d = to_filtered(cand.p) - cur_d;
          const double dd = d.squared_length(), dot = d * to_q;
          const double score = dd > 0 ? (dot < 0 ? -dot * dot : dot * dot) / dd : 0;  // signed cos^2 * |to_q|^2
          if (!found || score > best_score) {
            found = true;
            best = cand;
            best_face = f;
            best_score = score;
          }
        }
      }
      if (!found) return false;
      make_exact(best.p);  // the walk goes on from it and the curve keeps it
      points.push_back(best);
      faces.push_back(best_face);
      used.insert(std::size_t(best_face));
      prev = cur;
      has_prev = true;
      cur = best;
    }
    return false;
  }

  /// Path from P to Q, trying the normals of P's faces, of Q's faces and their sum.
  /// P and Q are taken by value: P is usually points.back(), which the walk reallocates.
  bool connect(const SP P, const SP Q, std::vector<SP>& points, std::vector<F>& faces, std::size_t& retries) const {
    for (F f : incident_faces<K>(m_, P))
      if (face_contains<K>(m_, f, Q)) {
        points.push_back(Q);
        faces.push_back(f);
        return true;
      }
    const Vector np = normal_at(P), nq = normal_at(Q);
    const Vector normals[3] = {np, nq, np + nq};
    for (int i = 0; i < 3; ++i) {
      // A failed walk is undone: both lists back to their own sizes (faces holds one entry fewer
      // than points, a step between two points; restoring it to the points' size left the failed
      // walk's first face in place, and every later step one face off).
      const std::size_t n0 = points.size(), f0 = faces.size();
      if (walk(P, Q, normals[i], points, faces)) {
        if (i > 0) ++retries;
        return true;
      }
      points.resize(n0);
      faces.resize(f0);
    }
    return false;
  }

 private:
  /// An AABB tree over some of the faces, on doubles.
  struct Search {
    std::vector<DTriangle> triangles;
    std::vector<F> face_of;  ///< the face of each triangle
    DTree tree;
  };
  /// The faces whose bounding box meets `region` (all faces when it is null or none does).
  std::unique_ptr<Search> build_search(const CGAL::Bbox_3* region) const {
    auto s = std::make_unique<Search>();
    for (int pass = 0; pass < 2 && s->triangles.empty(); ++pass)
      for (F f : m_.faces()) {
        auto h = m_.halfedge(f);
        DTriangle t(to_filtered(m_.point(m_.source(h))), to_filtered(m_.point(m_.target(h))),
                    to_filtered(m_.point(m_.target(m_.next(h)))));
        if (pass == 0 && region && !CGAL::do_overlap(t.bbox(), *region)) continue;
        s->triangles.push_back(t);
        s->face_of.push_back(f);
      }
    s->tree.insert(s->triangles.begin(), s->triangles.end());
    s->tree.build();
    s->tree.accelerate_distance_queries();
    return s;
  }

  const Mesh<K>& m_;
  double feature_tol_ = 0;
  std::optional<CGAL::Bbox_3> region_;  ///< where near_ is complete; none: near_ holds all faces
  mutable std::unique_ptr<Search> near_;
  mutable std::unique_ptr<Search> all_;  ///< built on the first node near the region's walls
  mutable std::unordered_map<std::size_t, typename K::Triangle_3> triangles_;  ///< see triangle()
};

template <class P> std::string describe_point(const P& p) {
  std::ostringstream out;
  out.precision(17);
  out << "(" << CGAL::to_double(p.x()) << ", " << CGAL::to_double(p.y()) << ", " << CGAL::to_double(p.z()) << ")";
  return out.str();
}

}  // namespace

template <class K>
SurfacePoint<K> traced_location(const Mesh<K>& mesh, const TracedCurve<K>& tc, std::size_t i) {
  SurfacePoint<K> sp = tc.points[i];
  if (tc.face_points_deferred && sp.where == Where::face)
    sp.p = typename K::Construct_projected_point_3()(face_triangle<K>(mesh, sp.f), sp.p);
  return sp;
}

template <class K>
std::vector<TracedCurve<K>> trace_curves(const Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                                         double max_distance, TraceReport& report, bool nodes_on_surface,
                                         double feature_tol, const KnownSites<K>* known, bool defer_projections) {
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  // The region the nodes can be located in: their bounding box, grown by max_distance (or by a
  // relative 1e-9 when that is unbounded: nodes on the surface), so that the search tree holds
  // only the faces near the curves.
  CGAL::Bbox_3 nodes_box;
  bool any_node = false;
  for (const auto& c : curves)
    for (const auto& p : c) {
      nodes_box += to_filtered(p).bbox();
      any_node = true;
    }
  const double diagonal = std::sqrt(CGAL::square(nodes_box.xmax() - nodes_box.xmin()) +
                                    CGAL::square(nodes_box.ymax() - nodes_box.ymin()) +
                                    CGAL::square(nodes_box.zmax() - nodes_box.zmin()));
  const double grow = std::isfinite(max_distance) && max_distance < 1e300 ? max_distance : 0.0;
  const double margin = grow + 1e-9 * (diagonal + std::max({std::abs(nodes_box.xmin()), std::abs(nodes_box.xmax()),
                                                              std::abs(nodes_box.ymin()), std::abs(nodes_box.ymax()),
                                                              std::abs(nodes_box.zmin()), std::abs(nodes_box.zmax())}));
  const CGAL::Bbox_3 region(nodes_box.xmin() - margin, nodes_box.ymin() - margin, nodes_box.zmin() - margin,
                            nodes_box.xmax() + margin, nodes_box.ymax() + margin, nodes_box.zmax() + margin);
  Tracer<K> tracer(mesh, feature_tol, any_node && std::isfinite(margin) ? &region : nullptr);

  // Locate each node and follow the curve from the previous one, node after node: a located
  // node's projection (under Epeck a lazy expression of about 100 bytes) is needed only until the
  // walk has left it. With `defer_projections` a face point then keeps its input node as p (see
  // TracedCurve::face_points_deferred), so memory stays at the traced curve's own size.
  const bool defer = defer_projections && kernel_traits<K>::exact_constructions && !nodes_on_surface && !known;
  double locate_seconds = 0;
  auto locate_node = [&](std::size_t c, std::size_t i) {
    const auto& curve = curves[c];
    if (const SurfacePoint<K>* site = known ? known->find(curve[i]) : nullptr) return *site;
    const auto t = Clock::now();
    double distance = 0;
    const bool on_surface = nodes_on_surface && kernel_traits<K>::exact_constructions;  // (exact predicates)
    SurfacePoint<K> sp = on_surface ? tracer.locate_on_surface(curve[i], distance) : tracer.locate(curve[i], distance);
    if (nodes_on_surface && sp.where != Where::vertex) sp.p = curve[i];
    locate_seconds += std::chrono::duration<double>(Clock::now() - t).count();
    if (!(distance <= max_distance)) {
      std::ostringstream msg;
      msg << "curve " << c << " node " << i << " " << describe_point(curve[i]) << " is " << distance
          << " from the surface (max distance " << max_distance << ")";
      throw InvalidInput(msg.str());
    }
    return sp;
  };
  // A walk that fails is an internal error, but a node too far from the surface is bad input and
  // is reported first, wherever it comes in the curves.
  auto fail = [&](std::size_t c, std::size_t i, const std::string& what) {
    for (std::size_t c2 = c; c2 < curves.size(); ++c2) {
      const std::size_t n2 = is_closed(curves[c2]) ? curves[c2].size() - 1 : curves[c2].size();
      for (std::size_t i2 = c2 == c ? i + 1 : 0; i2 < n2; ++i2) locate_node(c2, i2);
    }
    throw InternalError(what);
  };
  // Replaces the projection of a face point by the input node it was located from.
  auto demote = [&](TracedCurve<K>& tc, std::size_t k, std::size_t c) {
    if (!defer || k >= tc.points.size() || tc.points[k].where != Where::face || tc.input_node[k] < 0) return;
    tc.points[k].p = curves[c][std::size_t(tc.input_node[k])];
  };

  std::vector<TracedCurve<K>> traced(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    TracedCurve<K>& tc = traced[c];
    tc.closed = is_closed(curves[c]);
    tc.face_points_deferred = defer;
    const std::size_t n = is_closed(curves[c]) ? curves[c].size() - 1 : curves[c].size();
    SurfacePoint<K> first;  // the first point, projected (the closing walk goes back to it)
    std::size_t last_node_point = 0;  // index in tc.points of the last located node
    for (std::size_t i = 0; i < n; ++i) {
      SurfacePoint<K> node = locate_node(c, i);
      if (tc.points.empty()) {
        first = node;
        tc.points.push_back(node);
        tc.input_node.push_back(long(i));
        continue;
      }
      if (tc.points.back().same_as(node)) continue;  // duplicate node on the surface
      if (!tracer.connect(tc.points.back(), node, tc.points, tc.step_face, report.retries)) {
        std::ostringstream msg;
        msg << "could not follow curve " << c << " on the surface from node " << (i - 1) << " to node " << i;
        fail(c, i, msg.str());
      }
      tc.input_node.resize(tc.points.size(), -1);
      tc.input_node.back() = long(i);
      demote(tc, last_node_point, c);  // the walk has left it
      last_node_point = tc.points.size() - 1;
    }
    if (tc.closed && tc.points.size() > 1) {
      // Close the loop back to the first point.
      if (!tc.points.back().same_as(first)) {
        if (!tracer.connect(tc.points.back(), first, tc.points, tc.step_face, report.retries)) {
          std::ostringstream msg;
          msg << "could not close curve " << c << " on the surface";
          fail(c, n - 1, msg.str());
        }
        tc.input_node.resize(tc.points.size(), -1);
        tc.input_node.back() = 0;
      }
      // Drop the repeated first point: the loop is implied by `closed`.
      tc.points.pop_back();
      tc.input_node.pop_back();
      // step_face keeps the closing step: size == points.size() for a closed curve.
    }
    demote(tc, 0, c);
    demote(tc, last_node_point, c);
    if (tc.points.size() < 2) {
      std::ostringstream msg;
      msg << "curve " << c << " has no length on the surface (all its nodes project to one point)";
      throw InvalidInput(msg.str());
    }
  }
  const double total = std::chrono::duration<double>(Clock::now() - t0).count();
  report.locate_seconds = locate_seconds;
  report.located_by_predicates = tracer.located_by_predicates;
  report.cross_seconds = std::max(0.0, total - locate_seconds);
  return traced;
}

template SurfacePoint<Exact> traced_location<Exact>(const Mesh<Exact>&, const TracedCurve<Exact>&, std::size_t);
template SurfacePoint<Filtered> traced_location<Filtered>(const Mesh<Filtered>&, const TracedCurve<Filtered>&, std::size_t);
template SurfacePoint<Float> traced_location<Float>(const Mesh<Float>&, const TracedCurve<Float>&, std::size_t);
template std::vector<TracedCurve<Exact>> trace_curves<Exact>(const Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double, TraceReport&, bool, double, const KnownSites<Exact>*, bool);
template std::vector<TracedCurve<Filtered>> trace_curves<Filtered>(const Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double, TraceReport&, bool, double, const KnownSites<Filtered>*, bool);
template std::vector<TracedCurve<Float>> trace_curves<Float>(const Mesh<Float>&, const std::vector<Polyline<Float>>&, double, TraceReport&, bool, double, const KnownSites<Float>*, bool);

}  // namespace seam::internal
