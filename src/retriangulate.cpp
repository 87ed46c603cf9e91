// seam, pipeline step 5: re-triangulation of one face. See seam/internal/retriangulate.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/retriangulate.h>
#include <seam/internal/improve_state.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <type_traits>
#include <sstream>

namespace seam::internal {

namespace {

template <class K> struct Cdt {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<long, K>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  // Constraints that cross are split at a constructed intersection point (an error for seam,
  // detected below). With rounded constructions that point can make the triangulation
  // inconsistent (a segmentation fault inside CGAL::Triangulation_2, found by seam_robustness):
  // the rounded kernels refuse such crossings instead, with an exception.
  using Itag = std::conditional_t<kernel_traits<K>::exact_constructions, CGAL::Exact_predicates_tag,
                                  CGAL::No_constraint_intersection_requiring_constructions_tag>;
  using type = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, Itag>;
};

/// The kernel of the 2D triangulation: K, except under the float kernel, whose inexact
/// predicates break the triangulation's invariants on nearly degenerate faces (found by fuzzing:
/// a CGAL assertion in the triangulation data structure; without assertions, undefined
/// behaviour). There the CDT uses Epick on the same doubles: exact decisions, same coordinates.
template <class K> struct CdtKernel {
  using type = K;
};
template <> struct CdtKernel<Float> {
  using type = Filtered;
};

constexpr long kNoId = std::numeric_limits<long>::min();

/// Faces of the CDT outside the region bounded by the constraints: reachable from the infinite
/// face without crossing a constraint.
template <class CDT> std::set<const void*> outside_faces(const CDT& cdt) {
  std::set<const void*> outside{&*cdt.infinite_face()};
  std::vector<typename CDT::Face_handle> queue{cdt.infinite_face()};
  while (!queue.empty()) {
    auto fh = queue.back();
    queue.pop_back();
    for (int i = 0; i < 3; ++i) {
      auto nb = fh->neighbor(i);
      if (fh->is_constrained(i) || outside.count(&*nb)) continue;
      outside.insert(&*nb);
      queue.push_back(nb);
    }
  }
  return outside;
}

/// Rounded coordinates; for lazy exact points from the interval approximation (p.x() would build
/// a lazy number per call).
template <class P> std::array<double, 2> xy(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    const auto& q = CGAL::approx(p);
    return {CGAL::to_double(q.x()), CGAL::to_double(q.y())};
  } else {
    return {CGAL::to_double(p.x()), CGAL::to_double(p.y())};
  }
}

double angle_at(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
  return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / M_PI;
}

/// The smallest angle (degrees) of the triangles inside the domain, and how many of them have an
/// angle below `bound` degrees.
struct DomainQuality {
  double min_angle = 180;
  std::size_t below = 0;
};
template <class CDT> DomainQuality domain_quality(const CDT& cdt, double bound) {
  const auto outside = outside_faces(cdt);
  DomainQuality q;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (outside.count(&*f)) continue;
    const auto a = xy(f->vertex(0)->point()), b = xy(f->vertex(1)->point()), c = xy(f->vertex(2)->point());
    const double m = std::min({angle_at(a, b, c), angle_at(b, c, a), angle_at(c, a, b)});
    q.min_angle = std::min(q.min_angle, m);
    q.below += m < bound ? 1 : 0;
  }
  return q;
}

/// The angle (degrees) at vertex i of face f of the wedge that contains f and is bounded by the
/// nearest constrained edges (or the domain's boundary) on either side; 360 around a vertex with
/// no constraint.
/// Stops early once the angle reaches `enough` (the caller only compares it with that bound).
template <class CDT>
double constrained_wedge_deg(const CDT& cdt, typename CDT::Face_handle f, int i, double enough = 360) {
  const auto r = f->vertex(i);
  auto angle_in = [&](typename CDT::Face_handle g) {
    const int j = g->index(r);
    return angle_at(xy(r->point()), xy(g->vertex(CDT::ccw(j))->point()), xy(g->vertex(CDT::cw(j))->point()));
  };
  double total = angle_in(f);
  for (int turn = 0; turn < 2; ++turn) {
    auto g = f;
    for (int guard = 0; guard < 100; ++guard) {  // a wider fan counts as forced
      const int j = g->index(r);
      const int e = turn == 0 ? CDT::ccw(j) : CDT::cw(j);  // the edge of g at r on this side
      if (g->is_constrained(e)) break;
      g = g->neighbor(e);
      if (g == f) return 360;
      if (cdt.is_infinite(g)) break;
      total += angle_in(g);
      if (total >= enough) return total;
    }
  }
  return total;
}

/// Whether `point` (in face `hint`) lies in the closed diametral disk of a constrained edge on the
/// boundary of its conflict zone (the edges it would see after insertion). Rounded, as the
/// candidate points are.
template <class CDT> bool encroaches_constraint(const CDT& cdt, const typename CDT::Point& point,
                                                typename CDT::Face_handle hint) {
  std::vector<typename CDT::Face_handle> zone;
  std::vector<typename CDT::Edge> boundary;
  cdt.get_conflicts_and_boundary(point, std::back_inserter(zone), std::back_inserter(boundary), hint);
  const auto p = xy(point);
  for (const auto& [f, i] : boundary) {
    if (!f->is_constrained(i)) continue;
    const auto a = xy(f->vertex(cdt.cw(i))->point()), b = xy(f->vertex(cdt.ccw(i))->point());
    if ((a[0] - p[0]) * (b[0] - p[0]) + (a[1] - p[1]) * (b[1] - p[1]) <= 0) return true;
  }
  return false;
}

/// Whether the three vertices still form a face of the triangulation (the face in `out`),
/// circulating around all three in turn: the cost is 3 x the smallest degree (CDT::is_face
/// circulates around the first vertex, and a corner facing a curve that zig-zags 100,000 times
/// along an edge has a fan that large).
template <class CDT>
bool find_face(const CDT& cdt, const std::array<typename CDT::Vertex_handle, 3>& v, typename CDT::Face_handle& out) {
  using FC = typename CDT::Face_circulator;
  std::array<FC, 3> c, start;
  for (int k = 0; k < 3; ++k) start[k] = c[k] = cdt.incident_faces(v[k]);
  for (;;)
    for (int k = 0; k < 3; ++k) {
      const typename CDT::Face_handle f = c[k];
      if (f->has_vertex(v[0]) && f->has_vertex(v[1]) && f->has_vertex(v[2])) {
        out = f;
        return true;
      }
      if (++c[k] == start[k]) return false;
    }
}

/// The points to insert for a bad triangle with corners `v` (doubles), its shortest edge pq
/// opposite corner r (of length `shortest`), in the order to try: the circumcenter when it is
/// closer to pq than the off-center, then the off-center.
inline std::vector<std::array<double, 2>> steiner_candidates(const std::array<std::array<double, 2>, 3>& v, int r,
                                                             double shortest, double min_angle_deg) {
  const auto &p = v[std::size_t(r + 1) % 3], &q = v[std::size_t(r + 2) % 3], &o = v[std::size_t(r)];
  // The circumcenter in doubles (not CGAL::circumcenter, whose precondition a triangle that is
  // flat after rounding violates: found by fuzzing); a flat one gives a non-finite candidate.
  const std::array<double, 2> cc = [&] {
    const double bx = v[1][0] - v[0][0], by = v[1][1] - v[0][1], cx = v[2][0] - v[0][0], cy = v[2][1] - v[0][1];
    const double den = 2 * (bx * cy - by * cx), b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    if (den == 0) return std::array<double, 2>{HUGE_VAL, HUGE_VAL};
    return std::array<double, 2>{v[0][0] + (cy * b2 - by * c2) / den, v[0][1] + (bx * c2 - cx * b2) / den};
  }();
  const double mx = 0.5 * (p[0] + q[0]), my = 0.5 * (p[1] + q[1]);
  double nx = -(q[1] - p[1]), ny = q[0] - p[0];  // normal of pq, towards r
  if (nx * (o[0] - mx) + ny * (o[1] - my) < 0) nx = -nx, ny = -ny;
  const double nlen = std::hypot(nx, ny);
  // Ungor's off-center: the apex of the triangle on pq whose angle at the apex is just above
  // the bound, so that each inserted point is as far from pq as a good triangle allows and the
  // refinement grades geometrically (an equilateral apex would creep along a sliver).
  const double apex = std::min(60.0, 1.1 * min_angle_deg) * M_PI / 180.0;
  // ...but never beyond r's height over pq: the point stays inside the bad triangle.
  const double height = std::abs(nx * (o[0] - mx) + ny * (o[1] - my)) / std::hypot(nx, ny);
  const double h = std::min(0.5 * shortest / std::tan(0.5 * apex), 0.9 * height);
  const std::array<double, 2> off{mx + nx / nlen * h, my + ny / nlen * h};
  // The circumcenter when it is closer to pq than the off-center; the off-center when the
  // circumcenter falls outside the patch (it would need a split constraint).
  std::vector<std::array<double, 2>> candidates;
  if (std::hypot(cc[0] - mx, cc[1] - my) < h) candidates.push_back(cc);
  candidates.push_back(off);
  return candidates;
}

/// Delaunay refinement that never splits a constrained edge (the face's edges and the curve).
/// CGAL's Delaunay_mesher_no_edge_refinement_2 rejects every point that encroaches on a
/// constrained edge, and in a face bounded by constraints on all sides every circumcenter does,
/// so it inserts nothing. Here each bad triangle (smallest angle below the bound, or area above
/// max_area) gets an off-center (Ungor): on the bisector of its shortest edge pq, at the apex of
/// the triangle on pq whose apex angle is just above the bound, or the circumcenter when that is
/// closer to pq. The point is
/// inserted only when it falls strictly inside a triangle of the domain, so never on a
/// constraint. Angles forced by two constraints meeting at a vertex are left alone. The point's
/// coordinates are rounded to double (the lift to 3D is exact, see the header).
template <class CDT, class Allowed>
void refine_without_splitting(CDT& cdt, double min_angle_deg, double max_area, std::size_t max_steiner,
                              const Allowed& allowed) {
  using Point2 = typename CDT::Point;
  using FT = typename CDT::Geom_traits::FT;
  using FH = typename CDT::Face_handle;
  using VH = typename CDT::Vertex_handle;
  // Insertions happen strictly inside the domain, so the faces outside it never change.
  const auto outside = outside_faces(cdt);
  const double bound_sine2 = std::pow(std::sin(min_angle_deg * M_PI / 180.0), 2);

  // Bad triangles in a priority queue: oversized first (largest area ratio), then the worst
  // shaped (smallest sin^2 of the smallest angle). An entry names its three vertices; it is
  // stale when they no longer form a face. After an insertion only the new vertex's faces are
  // new (the retriangulated conflict zone is a star around it), so only they are evaluated.
  struct Bad {
    double area_ratio, sine2;
    std::array<VH, 3> v;
    bool operator<(const Bad& o) const {  // "less urgent than"
      if (area_ratio > 1 || o.area_ratio > 1) return area_ratio < o.area_ratio;
      return sine2 > o.sine2;
    }
  };
  std::priority_queue<Bad> queue;
  auto consider = [&](FH f) {
    if (cdt.is_infinite(f) || outside.count(&*f)) return;
    const auto a = xy(f->vertex(0)->point()), b = xy(f->vertex(1)->point()), c = xy(f->vertex(2)->point());
    // sin^2 of the smallest angle: (2 area)^2 over the product of the two longer sides squared.
    const double cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const double la = (b[0] - c[0]) * (b[0] - c[0]) + (b[1] - c[1]) * (b[1] - c[1]);
    const double lb = (c[0] - a[0]) * (c[0] - a[0]) + (c[1] - a[1]) * (c[1] - a[1]);
    const double lc = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
    const double sine2 = cross * cross / (la * lb * lc / std::min({la, lb, lc}));
    const double ratio = max_area > 0 ? 0.5 * std::abs(cross) / max_area : 0;
    if (sine2 < bound_sine2 || ratio > 1) queue.push({ratio, sine2, {f->vertex(0), f->vertex(1), f->vertex(2)}});
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) consider(f);

  for (std::size_t inserted = 0; inserted < max_steiner && !queue.empty();) {
    const Bad top = queue.top();
    queue.pop();
    FH worst;
    if (!find_face(cdt, top.v, worst)) continue;  // stale
    const double worst_area_ratio = top.area_ratio;
    const double worst_angle = std::asin(std::sqrt(std::min(1.0, top.sine2))) * 180.0 / M_PI;

    // Shortest edge pq, opposite vertex r.
    std::array<std::array<double, 2>, 3> v;
    for (int i = 0; i < 3; ++i) v[i] = xy(worst->vertex(i)->point());
    int r = 0;
    double shortest = std::numeric_limits<double>::max();
    for (int i = 0; i < 3; ++i) {
      const auto &p = v[(i + 1) % 3], &q = v[(i + 2) % 3];
      const double len = std::hypot(q[0] - p[0], q[1] - p[1]);
      if (len < shortest) shortest = len, r = i;
    }
    const bool angle_bad = worst_angle < min_angle_deg;
    // The small angle sits at r. It is forced when the wedge at r between the two constrained
    // edges enclosing this triangle is itself narrower than the bound: no point inside helps.
    if (angle_bad && worst_area_ratio <= 1 && constrained_wedge_deg(cdt, worst, r, min_angle_deg) < min_angle_deg) continue;
    FH fh;
    Point2 P;
    bool found = false;
    for (const auto& cand : steiner_candidates(v, r, shortest, min_angle_deg)) {
      if (!std::isfinite(cand[0]) || !std::isfinite(cand[1])) continue;  // a triangle too thin for doubles
      P = Point2{FT{cand[0]}, FT{cand[1]}};
      typename CDT::Locate_type lt;
      int li;
      fh = cdt.locate(P, lt, li, worst);
      if (lt == CDT::FACE && !cdt.is_infinite(fh) && !outside.count(&*fh)) {
        found = true;
        break;
      }
    }
    if (!found) continue;  // give this one up
    if (!allowed(P, false)) continue;  // too near a point to keep away from
    // A point inserted for the area bound alone must not encroach on a constrained edge (lie in
    // its diametral disk, seeing it at 90 degrees or more): that edge cannot be split here, and
    // such points are what made slivers of 1e-14 degrees against the curve under --max-area.
    // So the area bound holds wherever no unsplittable edge forces a larger triangle, and each
    // such point stays at least half an edge's length from every constraint it sees.
    if (!angle_bad && encroaches_constraint(cdt, P, fh)) continue;
    const VH vh = cdt.insert(P, fh);
    allowed(P, true);  // now a point to keep away from
    ++inserted;
    auto fc = cdt.incident_faces(vh), done = fc;
    do consider(fc); while (++fc != done);
  }
}


/// retriangulate_face's steps: the face's 2D frame, the constrained triangulation of its points,
/// the optional refinement of a copy, and the patch emitted from one of the two.
template <class K> class FaceRetriangulation {
 public:
  using FT = typename K::FT;
  using K2 = typename CdtKernel<K>::type;
  using Point2 = typename K2::Point_2;
  using Point3 = typename K::Point_3;
  using Vector3 = typename K::Vector_3;
  using CDT = typename Cdt<K2>::type;
  using VH = typename CDT::Vertex_handle;
  using Constraints = std::vector<std::pair<VH, VH>>;

  // The face's own 2D frame (see the header): exact affine map, rounded scale L.
  FaceRetriangulation(const FaceConstraints<K>& face, const RetriangulateOptions& options)
      : face_(face),
        options_(options),
        a_(face.corners[0]),
        u_(face.corners[1] - a_),
        n_(CGAL::cross_product(u_, face.corners[2] - a_)),
        v_(CGAL::cross_product(n_, u_)),
        L_d_(std::sqrt(CGAL::to_double(n_.squared_length()))) {
    if (!(L_d_ > 0)) throw InternalError("re-triangulation of a degenerate face");
    L_ = FT(L_d_);
    uu_ = u_.squared_length();
    vv_ = v_.squared_length();
    Luu_ = L_ * uu_;
    // Points with their ids, in a fixed order (deterministic triangulation).
    for (int i = 0; i < 3; ++i) points_.emplace_back(long(face.corner_ids[i]), face.corners[i]);
    for (int i = 0; i < 3; ++i)
      for (const auto& [id, p] : face.edge_points[i]) points_.emplace_back(long(id), p);
    for (const auto& [id, p] : face.interior_points) points_.emplace_back(long(id), p);
  }

  FacePatch<K> run() {
    CDT cdt;
    Constraints constraints;
    const bool built = build(cdt, constraints);
    if (!built || cdt.number_of_vertices() != points_.size() || !all_edges(cdt, constraints)) {
      std::ostringstream msg;
      msg << "curve segments cross each other (or an edge) inside the face with corners " << corners_text();
      if (kernel_traits<K>::exact_constructions) throw InvalidInput(msg.str());
      throw InternalError(msg.str() + " (rounded arithmetic)");
    }
    bool refinement_undone = false;
    CDT refined;
    const bool refined_ok = refine_copy(cdt, constraints, refined, refinement_undone);
    FacePatch<K> patch;
    if (refined_ok) {
      if (emit(refined, patch)) return patch;
      patch = FacePatch<K>();
      refinement_undone = true;
    }
    patch.refinement_undone = refinement_undone;
    if (!emit(cdt, patch))
      throw InternalError("rounded arithmetic produced a flat or flipped triangle in the face with corners " +
                          corners_text());
    return patch;
  }

 private:
  std::string corners_text() const {
    std::ostringstream s;
    s << face_.corner_ids[0] << ", " << face_.corner_ids[1] << ", " << face_.corner_ids[2];
    return s.str();
  }

  // X = L (p - a).u and Y = (p - a).v: no division, so exact coordinates stay small rationals.
  // Under the exact kernel on the exact values directly: one lazy node per point, not one per
  // operation (each evaluated once, behind a lock).
  Point2 to_2d(const Point3& p) const {
    if constexpr (std::is_same_v<K, Exact>) {
      const auto d = CGAL::exact(p) - CGAL::exact(a_);
      using EK = typename CGAL::Kernel_traits<std::decay_t<decltype(d)>>::Kernel;
      return Point2(typename EK::Point_2((d * CGAL::exact(u_)) * CGAL::exact(L_), d * CGAL::exact(v_)));
    } else {
      const Vector3 d = p - a_;
      Point2 q((d * u_) * L_, d * v_);
      make_exact(q);
      return q;
    }
  }
  Point3 to_3d(const Point2& q) const {
    Point3 p = a_ + u_ * (q.x() / Luu_) + v_ * (q.y() / vv_);
    make_exact(p);
    return p;
  }

  /// The constrained triangulation of the face's points, its edges (split at their points) and
  /// the curve segments inside it; false where constraints intersect (rounded kernels only).
  bool build(CDT& cdt, Constraints& constraints) const {
    std::map<long, VH> handle;
    // All points at once: CGAL sorts them spatially (Hilbert order, deterministic) before
    // inserting. One by one in curve order, the points of an edge come along a line, and a
    // curve zig-zagging 100,000 times through a face made every insertion flip a long fan:
    // quadratic time.
    std::vector<std::pair<Point2, long>> with_ids;
    with_ids.reserve(points_.size());
    for (const auto& [id, p] : points_) with_ids.emplace_back(to_2d(p), id);
    cdt.insert(with_ids.begin(), with_ids.end());
    for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit) handle[vit->info()] = vit;
    // Two input points at one place: only possible with rounded constructions.
    if (cdt.number_of_vertices() != points_.size()) throw InternalError("two curve points coincide after rounding");
    // A segment ending at a point that is not one of this face's points (found by fuzzing, under
    // the rounded kernels: the two ends were located on elements that do not bound this face).
    auto at = [&](long id) {
      const auto it = handle.find(id);
      if (it == handle.end()) {
        std::ostringstream msg;
        msg << "a curve segment inside the face with corners " << corners_text() << " ends at point " << id
            << ", which is not on that face";
        if (!kernel_traits<K>::exact_constructions) msg << " (rounded arithmetic)";
        throw InternalError(msg.str());
      }
      return it->second;
    };
    for (int i = 0; i < 3; ++i) {
      long prev = long(face_.corner_ids[i]);
      for (const auto& ep : face_.edge_points[i]) {
        constraints.emplace_back(at(prev), at(long(ep.first)));
        prev = long(ep.first);
      }
      constraints.emplace_back(at(prev), at(long(face_.corner_ids[(i + 1) % 3])));
    }
    for (const auto& [s, t] : face_.segments) constraints.emplace_back(at(long(s)), at(long(t)));
    try {
      for (const auto& [s, t] : constraints) cdt.insert_constraint(s, t);
    } catch (const typename CDT::Intersection_of_constraints_exception&) {
      return false;  // rounded kernels only (see Cdt)
    }
    return true;
  }

  static bool all_edges(const CDT& cdt, const Constraints& constraints) {
    for (const auto& [s, t] : constraints)
      if (!cdt.is_edge(s, t)) return false;
    return true;
  }

  /// Refines a copy of `cdt` into `refined` when the options ask for it and a triangle needs it;
  /// true when the copy is to be used (every constraint survived as an edge, and it is better or
  /// an area bound asks for it), else `undone` says whether a refinement was thrown away.
  bool refine_copy(const CDT& cdt, const Constraints& constraints, CDT& refined, bool& undone) const {
    const bool refine = options_.min_angle_deg > 0 || options_.max_area > 0;
    // Nothing to refine when no triangle is below the bound and no area bound is asked for.
    const bool needed =
        options_.max_area > 0 || domain_quality(cdt, std::min(options_.min_angle_deg, 60.0)).below > 0;
    if (!(refine && needed && options_.max_steiner > 0)) return false;
    // A copy shares the (already exact) points instead of building the triangulation again.
    refined = cdt;
    std::map<long, VH> by_id;
    for (auto vit = refined.finite_vertices_begin(); vit != refined.finite_vertices_end(); ++vit) by_id[vit->info()] = vit;
    Constraints refined_constraints;
    for (const auto& [s0, t0] : constraints) refined_constraints.emplace_back(by_id.at(s0->info()), by_id.at(t0->info()));
    std::set<const void*> input_vertices;
    for (auto vit = refined.finite_vertices_begin(); vit != refined.finite_vertices_end(); ++vit)
      input_vertices.insert(&*vit);

    const double max_area_2d = options_.max_area > 0 ? options_.max_area * CGAL::to_double(uu_) * L_d_ * L_d_ : 0.0;
    const double bound = std::min(options_.min_angle_deg, 60.0);
    const DomainQuality before = domain_quality(refined, bound);
    // A point near one the options keep away from is skipped, judged on its lift in doubles.
    std::array<double, 3> a{}, u{}, v{};
    double uu = 0, vv = 0;
    if (options_.keep_away) {
      for (int i = 0; i < 3; ++i) {
        a[i] = CGAL::to_double(a_[i]);
        u[i] = CGAL::to_double(u_[i]);
        v[i] = CGAL::to_double(v_[i]);
      }
      uu = CGAL::to_double(uu_);
      vv = CGAL::to_double(vv_);
    }
    // Whether q may be inserted; `inserted`: it was, and joins the set, so that Steiner points
    // keep that far from each other too.
    const auto allowed = [&](const Point2& q, bool inserted) {
      if (!options_.keep_away) return true;
      const double x = CGAL::to_double(q.x()) / (L_d_ * uu), y = CGAL::to_double(q.y()) / vv;
      const std::array<double, 3> lifted{a[0] + u[0] * x + v[0] * y, a[1] + u[1] * x + v[1] * y,
                                         a[2] + u[2] * x + v[2] * y};
      if (inserted) options_.keep_away->add(lifted);
      return inserted || !options_.keep_away->near(lifted);
    };
    refine_without_splitting(refined, bound, max_area_2d, options_.max_steiner, allowed);
    const DomainQuality after = domain_quality(refined, bound);
    // Keep the refinement when it made neither the worst angle worse nor the bad triangles more
    // numerous (or an area bound asks for it).
    const bool better = after.min_angle >= before.min_angle && after.below <= before.below;
    if (all_edges(refined, refined_constraints) && (better || max_area_2d > 0)) {
      for (auto vit = refined.finite_vertices_begin(); vit != refined.finite_vertices_end(); ++vit)
        if (!input_vertices.count(&*vit)) vit->info() = kNoId;
      return true;
    }
    undone = true;
    return false;
  }

  /// A triangulation as a patch: its Steiner points numbered, the faces inside the constraints
  /// kept (under rounded kernels a crossing point may fall just inside its edge, leaving a sliver
  /// between the edge and the convex hull), in the face's orientation (counterclockwise in the
  /// frame). False when a triangle is flat or flipped in 3D (never under the exact kernel).
  bool emit(CDT& tr, FacePatch<K>& patch) const {
    std::map<long, Point3> input_point;
    for (const auto& [id, p] : points_) input_point[id] = p;
    std::map<const void*, long> steiner_ref;
    for (auto vit = tr.finite_vertices_begin(); vit != tr.finite_vertices_end(); ++vit) {
      if (vit->info() != kNoId) continue;
      patch.steiner_points.push_back(to_3d(vit->point()));
      steiner_ref[&*vit] = -long(patch.steiner_points.size());
    }
    const auto outside = outside_faces(tr);
    for (auto fit = tr.finite_faces_begin(); fit != tr.finite_faces_end(); ++fit) {
      if (outside.count(&*fit)) continue;
      std::array<long, 3> tri;
      for (int i = 0; i < 3; ++i) {
        auto vh = fit->vertex(i);
        tri[i] = vh->info() != kNoId ? vh->info() : steiner_ref.at(&*vh);
      }
      patch.triangles.push_back(tri);
    }
    auto point_of = [&](long r) -> const Point3& {
      return r >= 0 ? input_point.at(r) : patch.steiner_points[std::size_t(-r - 1)];
    };
    for (const auto& t : patch.triangles) {
      const Point3 &p0 = point_of(t[0]), &p1 = point_of(t[1]), &p2 = point_of(t[2]);
      if (CGAL::collinear(p0, p1, p2) || !CGAL::is_positive(CGAL::cross_product(p1 - p0, p2 - p0) * n_)) return false;
    }
    return true;
  }

  const FaceConstraints<K>& face_;
  const RetriangulateOptions& options_;
  const Point3 a_;
  const Vector3 u_, n_, v_;
  const double L_d_;
  FT L_, uu_, vv_, Luu_;
  std::vector<std::pair<long, Point3>> points_;
};

}  // namespace

KeepAway::KeepAway(double distance) : distance_(distance) {
  if (!(distance > 0) || !std::isfinite(distance)) throw InternalError("keep-away distance must be positive");
}

KeepAway::Cell KeepAway::cell_of(const std::array<double, 3>& p) const {
  return {(long long)std::floor(p[0] / distance_), (long long)std::floor(p[1] / distance_),
          (long long)std::floor(p[2] / distance_)};
}

std::size_t KeepAway::CellHash::operator()(const Cell& c) const {
  std::size_t h = 1469598103934665603ull;
  for (const long long x : c) h = (h ^ std::size_t(x)) * 1099511628211ull;
  return h;
}

void KeepAway::add(const std::array<double, 3>& p) { cells_[cell_of(p)].push_back(p); }

bool KeepAway::point_near(const std::array<double, 3>& p, bool at_p) const {
  const Cell c = cell_of(p);
  for (long long dx = -1; dx <= 1; ++dx)
    for (long long dy = -1; dy <= 1; ++dy)
      for (long long dz = -1; dz <= 1; ++dz) {
        const auto it = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
        if (it == cells_.end()) continue;
        for (const auto& q : it->second) {
          const double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
          if (d2 < distance_ * distance_ && (at_p || d2 > 0)) return true;
        }
      }
  return false;
}

bool KeepAway::crowded(const std::array<double, 3>& p) const { return point_near(p, false); }

bool KeepAway::near(const std::array<double, 3>& p) const {
  if (point_near(p, true)) return true;
  const Filtered::Point_3 q(p[0], p[1], p[2]);
  for (const InputSurface* surface : surfaces_) {
    const auto [closest, normal] = surface->closest(q);
    if (normal != CGAL::NULL_VECTOR && CGAL::squared_distance(q, closest) < distance_ * distance_) return true;
  }
  return false;
}

template <class K>
FacePatch<K> retriangulate_face(const FaceConstraints<K>& face, const RetriangulateOptions& options) {
  return FaceRetriangulation<K>(face, options).run();
}

template FacePatch<Exact> retriangulate_face<Exact>(const FaceConstraints<Exact>&, const RetriangulateOptions&);
template FacePatch<Filtered> retriangulate_face<Filtered>(const FaceConstraints<Filtered>&, const RetriangulateOptions&);
template FacePatch<Float> retriangulate_face<Float>(const FaceConstraints<Float>&, const RetriangulateOptions&);

}  // namespace seam::internal
