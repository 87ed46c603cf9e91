// seam, pipeline step 1: snapping. See seam/internal/snap.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/snap.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/face_grid.h>
#include <seam/internal/retriangulate.h>  // KeepAway

#include <CGAL/boost/graph/Euler_operations.h>
#include <set>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/intersections.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <limits>
#include <cmath>
#include <tuple>

namespace seam::internal {

namespace {

using DK = CGAL::Exact_predicates_inexact_constructions_kernel;  // search on doubles
using DPoint = DK::Point_3;
using NodePointMap = CGAL::Pointer_property_map<DPoint>::type;
using BaseTraits = CGAL::Search_traits_3<DK>;
using Traits = CGAL::Search_traits_adapter<std::size_t, NodePointMap, BaseTraits>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = Search::Tree;
using Distance = Search::Distance;

}  // namespace

/// Would moving v to `target` keep every incident face non-degenerate with its orientation?
/// Under the exact kernel both tests are exact.
template <class K>
bool move_keeps_faces(const Mesh<K>& mesh, typename MeshTypes<K>::V v, const typename K::Point_3& target) {
  for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
    if (mesh.is_border(h)) continue;
    // Face (v, a, b) in its orientation, with v = target(h).
    const auto& a = mesh.point(mesh.target(mesh.next(h)));
    const auto& b = mesh.point(mesh.source(h));
    const auto& old_v = mesh.point(v);
    if (CGAL::collinear(target, a, b)) return false;  // flattened
    const auto n_old = CGAL::cross_product(a - old_v, b - old_v);
    const auto n_new = CGAL::cross_product(a - target, b - target);
    if (CGAL::is_negative(n_old * n_new) || CGAL::is_zero(n_old * n_new)) return false;  // flipped
  }
  return true;
}


template <class K>
SnapReport<K> snap_vertices(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance) {
  SnapReport<K> report;
  if (!(tolerance > 0)) return report;

  // Curve nodes (closing repeats included: a duplicate is harmless to the search).
  std::vector<const typename K::Point_3*> nodes;
  for (const auto& c : curves)
    for (const auto& p : c) nodes.push_back(&p);
  if (nodes.empty()) return report;
  std::vector<DPoint> dnodes;
  dnodes.reserve(nodes.size());
  for (auto* p : nodes) dnodes.push_back(to_filtered(*p));

  NodePointMap pmap(dnodes.data());
  std::vector<std::size_t> ids(dnodes.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  Tree tree(ids.begin(), ids.end(), Tree::Splitter(), Traits(pmap));
  tree.build();
  Distance distance(pmap);

  // Candidates: (distance, vertex, node), nearest first; ties broken by indices (deterministic).
  using V = typename MeshTypes<K>::V;
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  const double tol2 = tolerance * tolerance;
  for (V v : mesh.vertices()) {
    Search search(tree, to_filtered(mesh.point(v)), 1, 0, true, distance);
    auto it = search.begin();
    if (it == search.end()) continue;
    if (it->second <= tol2) candidates.emplace_back(std::sqrt(it->second), std::size_t(v), it->first);
  }
  std::sort(candidates.begin(), candidates.end());

  // Nodes at the same place (a closing repeat, duplicate points) are one node: a place takes at
  // most one vertex. Keyed by the candidates' rounded coordinates only (not a sort of all nodes:
  // a curve of millions of nodes snaps a handful of vertices).
  std::set<std::array<double, 3>> places_taken;
  for (const auto& [d, vi, node] : candidates) {
    const std::array<double, 3> place{dnodes[node].x(), dnodes[node].y(), dnodes[node].z()};
    if (places_taken.count(place)) continue;
    const V v(static_cast<typename V::size_type>(vi));
    const auto& target = *nodes[node];
    if (!move_keeps_faces<K>(mesh, v, target)) {
      ++report.refused;
      continue;
    }
    mesh.point(v) = target;
    places_taken.insert(place);
    ++report.snapped;
    report.max_move = std::max(report.max_move, d);
    report.moved.push_back(v);
  }
  return report;
}


namespace {
/// The faces of a mesh that stays as it is while this is used, indexed by their boxes (FaceGrid,
/// built at the first query): a vertex near a curve asks for the few faces of the other mesh near
/// it, where a scan of all its faces made snapping quadratic.
template <class K> class FacesByBox {
 public:
  explicit FacesByBox(const Mesh<K>& mesh) : mesh_(mesh) {}
  /// Calls visit(a, b, c) with the corners of each face whose box overlaps `box`, in the mesh's
  /// face order (that of a scan of all its faces), until it returns true (then true).
  template <class Visit> bool any_near(const CGAL::Bbox_3& box, Visit visit) const {
    if (!grid_) build();
    std::vector<std::uint32_t> found;
    for (const auto& entry : grid_->query(box)) found.push_back(entry.face);
    std::sort(found.begin(), found.end());
    for (const std::uint32_t i : found) {
      const typename Mesh<K>::Face_index g(i);
      const auto k = mesh_.halfedge(g);
      const auto &a = mesh_.point(mesh_.source(k)), &b = mesh_.point(mesh_.target(k)),
                 &c = mesh_.point(mesh_.target(mesh_.next(k)));
      if (CGAL::do_overlap(box, a.bbox() + b.bbox() + c.bbox()) && visit(a, b, c)) return true;
    }
    return false;
  }

 private:
  const Mesh<K>& mesh_;
  mutable std::optional<FaceGrid> grid_;
  static CGAL::Bbox_3 box_of(const Mesh<K>& g, typename Mesh<K>::Face_index f) {
    const auto k = g.halfedge(f);
    return g.point(g.source(k)).bbox() + g.point(g.target(k)).bbox() + g.point(g.target(g.next(k))).bbox();
  }
  void build() const {
    double width = 0;  // the faces' mean box width: the grid's base cell
    for (auto f : mesh_.faces()) {
      const CGAL::Bbox_3 b = box_of(mesh_, f);
      width += std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
    }
    grid_.emplace(mesh_.number_of_faces() > 0 && width > 0 ? width / double(mesh_.number_of_faces()) : 1.0);
    for (auto f : mesh_.faces()) grid_->insert({0, std::uint32_t(f), 0}, box_of(mesh_, f));
  }
};

/// Whether a face around v lies in one plane with a face of `other` and meets it (exact).
template <class K> bool in_flat_contact(const Mesh<K>& mesh, typename MeshTypes<K>::V v, const FacesByBox<K>& other) {
  using Point = typename K::Point_3;
  for (auto f : CGAL::faces_around_target(mesh.halfedge(v), mesh)) {
    if (f == MeshTypes<K>::M::null_face()) continue;
    const auto t = face_triangle<K>(mesh, f);
    if (other.any_near(t.bbox(), [&](const Point& a, const Point& b, const Point& c) {
          return CGAL::coplanar(t[0], t[1], t[2], a) && CGAL::coplanar(t[0], t[1], t[2], b) &&
                 CGAL::coplanar(t[0], t[1], t[2], c) && CGAL::do_intersect(t, typename K::Triangle_3(a, b, c));
        }))
      return true;
  }
  return false;
}

/// Where the faces around v meet `other` (exact intersections, rounded to doubles): as segments,
/// a point as a segment of length 0, a triangle or polygon of a flat contact as its edges.
template <class K>
std::vector<DK::Segment_3> contact_around(const Mesh<K>& mesh, typename MeshTypes<K>::V v, const FacesByBox<K>& other) {
  using Point = typename K::Point_3;
  std::vector<DK::Segment_3> pieces;
  auto ring = [&](const std::vector<Point>& ps) {
    for (std::size_t i = 0; i < ps.size(); ++i)
      pieces.emplace_back(to_filtered(ps[i]), to_filtered(ps[(i + 1) % ps.size()]));
  };
  for (auto f : CGAL::faces_around_target(mesh.halfedge(v), mesh)) {
    if (f == MeshTypes<K>::M::null_face()) continue;
    const auto t = face_triangle<K>(mesh, f);
    if (t.is_degenerate()) continue;
    other.any_near(t.bbox(), [&](const Point& a, const Point& b, const Point& c) {
      const typename K::Triangle_3 u(a, b, c);
      if (u.is_degenerate()) return false;
      const auto meet = CGAL::intersection(t, u);
      if (!meet) return false;
      if (const auto* p = boost::get<Point>(&*meet)) pieces.emplace_back(to_filtered(*p), to_filtered(*p));
      else if (const auto* s = boost::get<typename K::Segment_3>(&*meet))
        pieces.emplace_back(to_filtered(s->source()), to_filtered(s->target()));
      else if (const auto* w = boost::get<typename K::Triangle_3>(&*meet))
        ring({w->vertex(0), w->vertex(1), w->vertex(2)});
      else if (const auto* ps = boost::get<std::vector<Point>>(&*meet)) ring(*ps);
      return false;  // (every face)
    });
  }
  return pieces;
}

/// Moving v to `target` keeps every point where the faces around v met `other` within
/// `distance` of where they meet it after the move: a move onto a curve must not take a part of
/// the intersection with it (a vertex next to an edge that lies on the other surface, CT row 9 of
/// docs/real_tows.md: 5e-8 up, and the edge's contact, 0.028 long, was gone). A precondition of
/// a rounded kernel failing in the intersections refuses the move.
template <class K>
bool move_keeps_contact(Mesh<K>& mesh, typename MeshTypes<K>::V v, const typename K::Point_3& target,
                        const FacesByBox<K>& other, double distance) {
  std::vector<DK::Segment_3> before, after;
  const auto old = mesh.point(v);
  try {
    before = contact_around<K>(mesh, v, other);
    if (before.empty()) return true;
    mesh.point(v) = target;
    after = contact_around<K>(mesh, v, other);
    mesh.point(v) = old;
  } catch (const CGAL::Failure_exception&) {
    mesh.point(v) = old;
    return false;
  }
  auto near_after = [&](const DPoint& p) {
    return std::any_of(after.begin(), after.end(),
                       [&](const DK::Segment_3& s) { return CGAL::squared_distance(p, s) <= distance * distance; });
  };
  for (const auto& s : before)
    if (!near_after(s.source()) || !near_after(s.target())) return false;
  return true;
}

/// Per vertex: whether it lies within `distance` of one of `points`, or is a corner of a face
/// that does (in doubles). The corners of the faces holding a point, whatever their distance to it:
/// a vertex poking 1e-7 through the other surface leaves a curve around it 1e-6 across (CT row 10
/// of docs/real_tows.md), whose points are farther than that from it.
template <class K>
std::vector<bool> corners_next_to(const Mesh<K>& mesh, const std::vector<std::array<double, 3>>& points, double distance) {
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<bool> result(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), false);
  const double d2 = distance * distance;
  for (const auto& p : points) {
    const DK::Point_3 q(p[0], p[1], p[2]);
    const CGAL::Bbox_3 box(p[0] - distance, p[1] - distance, p[2] - distance, p[0] + distance, p[1] + distance,
                           p[2] + distance);
    for (auto v : mesh.vertices())
      if (CGAL::squared_distance(q, to_filtered(mesh.point(v))) <= d2) result[std::size_t(v)] = true;
    for (auto f : mesh.faces()) {
      const auto h = mesh.halfedge(f);
      const DK::Triangle_3 t(to_filtered(mesh.point(mesh.source(h))), to_filtered(mesh.point(mesh.target(h))),
                             to_filtered(mesh.point(mesh.target(mesh.next(h)))));
      if (!CGAL::do_overlap(box, t.bbox()) || t.is_degenerate() || CGAL::squared_distance(q, t) > d2) continue;
      for (auto v : CGAL::vertices_around_face(h, mesh)) result[std::size_t(v)] = true;
    }
  }
  return result;
}
}  // namespace

template <class K>
SnapReport<K> snap_vertices_to_segments(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance,
                                        bool round_to_doubles, bool skip_on_curves, const Mesh<K>* other,
                                        const std::vector<std::array<double, 3>>* near, double contact_tolerance) {
  SnapReport<K> report;
  if (!(tolerance > 0)) return report;
  using Point = typename K::Point_3;
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<DK::Segment_3> segments;
  std::vector<std::pair<const Point*, const Point*>> ends;
  std::vector<const Point*> lone;  // curves of one point (isolated points of contact): vertices move onto them
  for (const auto& c : curves) {
    // A closed curve smaller than the tolerance across (a crossing 1e-15 wide where two tows
    // touch tangentially, say) is one target too, its first point: vertices of both meshes that
    // close then meet there, instead of at different points of it.
    const auto smaller_than_tolerance = [&c, tolerance] {
      CGAL::Bbox_3 box;
      for (const auto& p : c) box += to_filtered(p).bbox();
      return internal::bbox_diagonal(box) < tolerance;
    };
    if (c.size() == 1 || (is_closed(c) && smaller_than_tolerance())) {
      lone.push_back(&c[0]);
      continue;
    }
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const auto p = to_filtered(c[i]), q = to_filtered(c[i + 1]);
      if (p == q) continue;
      segments.emplace_back(p, q);
      ends.emplace_back(&c[i], &c[i + 1]);
    }
  }
  if (segments.empty() && lone.empty()) return report;
  using Prim = CGAL::AABB_segment_primitive<DK, std::vector<DK::Segment_3>::const_iterator>;
  CGAL::AABB_tree<CGAL::AABB_traits<DK, Prim>> tree(segments.cbegin(), segments.cend());
  if (!segments.empty()) tree.accelerate_distance_queries();
  using V = typename MeshTypes<K>::V;
  const std::vector<bool> next_to_near = near ? corners_next_to<K>(mesh, *near, tolerance) : std::vector<bool>();
  // (distance, vertex, target): a segment's index, or segments.size() + a lone point's index
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  // A lone point takes one vertex of the mesh (the nearest), none if one is there already: two
  // vertices moved onto one point would be one point twice.
  std::vector<bool> taken(lone.size(), false);
  for (V v : mesh.vertices()) {
    if (near && !next_to_near[std::size_t(v)]) continue;
    const auto q = to_filtered(mesh.point(v));
    double d = std::numeric_limits<double>::infinity();
    std::size_t target = 0;
    if (!segments.empty()) {
      const auto [cp, it] = tree.closest_point_and_primitive(q);
      d = std::sqrt(CGAL::squared_distance(q, cp));
      target = std::size_t(it - segments.cbegin());
    }
    for (std::size_t i = 0; i < lone.size(); ++i) {
      const double di = std::sqrt(CGAL::squared_distance(q, to_filtered(*lone[i])));
      if (di == 0 && mesh.point(v) == *lone[i]) taken[i] = true;  // (exact test)
      if (di < d) d = di, target = segments.size() + i;
    }
    if (!(d <= tolerance)) continue;
    candidates.emplace_back(d, std::size_t(v), target);
  }
  std::optional<FacesByBox<K>> other_faces;  // (other does not change here)
  if (other) other_faces.emplace(*other);
  // The target as the move makes it: exact (short coordinates, see below), or rounded to doubles.
  const auto as_moved = [round_to_doubles](Point target) {
    make_exact(target);
    if (round_to_doubles)
      target = Point(CGAL::to_double(target.x()), CGAL::to_double(target.y()), CGAL::to_double(target.z()));
    return target;
  };
  // Moves v onto target unless that folds a face or takes a part of the intersection with it.
  const auto move = [&](V v, const Point& target, double d) {
    const bool keeps_contact =
        !other || !(contact_tolerance > 0) || move_keeps_contact<K>(mesh, v, target, *other_faces, contact_tolerance);
    if (!move_keeps_faces<K>(mesh, v, target) || !keeps_contact) {
      ++report.refused;
      return;
    }
    mesh.point(v) = target;
    ++report.snapped;
    report.max_move = std::max(report.max_move, d);
    report.moved.push_back(v);
  };
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [d, vi, si] : candidates) {
    const V v(static_cast<typename V::size_type>(vi));
    if (si >= segments.size()) {  // onto a lone point, exactly
      const std::size_t i = si - segments.size();
      const Point target = as_moved(*lone[i]);
      if (taken[i] || mesh.point(v) == target || (other && in_flat_contact<K>(mesh, v, *other_faces))) continue;
      const std::size_t before = report.snapped;
      move(v, target, d);
      taken[i] = report.snapped > before;
      continue;
    }
    // The point of the segment (which lies on the surface) at the closest point's parameter
    // rounded to a multiple of 2^-16: exactly on the segment, at most 2^-17 of its length from
    // the closest point, and with far shorter exact coordinates than the closest point itself
    // (whose parameter is a long rational): every later intersection is computed from them.
    const Point &p = *ends[si].first, &q = *ends[si].second;
    if (skip_on_curves && typename K::Segment_3(p, q).has_on(mesh.point(v))) continue;  // (exact test)
    if (other && in_flat_contact<K>(mesh, v, *other_faces)) continue;
    const auto pq = q - p;
    const double closest = CGAL::to_double(((mesh.point(v) - p) * pq) / pq.squared_length());
    double t = std::clamp(std::round(closest * 65536.0) / 65536.0, 0.0, 1.0);
    // Onto an end of the segment (a curve node) where that is within the tolerance too.
    const double length = std::sqrt(CGAL::to_double(pq.squared_length()));
    if (closest * length <= tolerance) t = 0;
    else if ((1 - closest) * length <= tolerance) t = 1;
    move(v, as_moved(t == 0 ? p : t == 1 ? q : p + pq * typename K::FT(t)), d);
  }
  return report;
}

template <class K>
EdgeSnapReport<K> snap_edges_to_points(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance) {
  EdgeSnapReport<K> report;
  if (!(tolerance > 0)) return report;
  using Point = typename K::Point_3;
  using T = MeshTypes<K>;
  using E = typename T::E;
  using F = typename T::F;
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  // The mesh edges on doubles, for the search.
  std::vector<DK::Segment_3> segments;
  std::vector<E> edge_of;
  for (E e : mesh.edges()) {
    segments.emplace_back(to_filtered(mesh.point(mesh.vertex(e, 0))), to_filtered(mesh.point(mesh.vertex(e, 1))));
    edge_of.push_back(e);
  }
  if (segments.empty()) return report;
  using Prim = CGAL::AABB_segment_primitive<DK, std::vector<DK::Segment_3>::const_iterator>;
  CGAL::AABB_tree<CGAL::AABB_traits<DK, Prim>> tree(segments.cbegin(), segments.cend());
  tree.accelerate_distance_queries();
  // Candidates: (distance, curve, point, edge), the closest edge of each curve point.
  std::vector<std::tuple<double, std::size_t, std::size_t, std::size_t>> candidates;
  for (std::size_t c = 0; c < curves.size(); ++c)
    for (std::size_t i = 0; i < curves[c].size(); ++i) {
      const auto q = to_filtered(curves[c][i]);
      const auto [cp, it] = tree.closest_point_and_primitive(q);
      const double d = std::sqrt(CGAL::squared_distance(q, cp));
      if (d > 0 && d <= tolerance) candidates.emplace_back(d, c, i, std::size_t(it - segments.cbegin()));
    }
  std::sort(candidates.begin(), candidates.end());
  std::set<std::size_t> used_faces, used_edges;
  for (const auto& [d, c, i, si] : candidates) {
    const E e = edge_of[si];
    const auto h = mesh.halfedge(e, 0);
    const Point& P = curves[c][i];
    const Point& a = mesh.point(mesh.source(h));
    const Point& b = mesh.point(mesh.target(h));
    // Only inside the edge, farther than the tolerance from its ends (vertex snapping's domain),
    // and not already on it.
    if (used_edges.count(std::size_t(e)) || CGAL::collinear(a, b, P)) continue;
    const double da = std::sqrt(CGAL::to_double(CGAL::squared_distance(a, P)));
    const double db = std::sqrt(CGAL::to_double(CGAL::squared_distance(b, P)));
    if (da <= tolerance || db <= tolerance) continue;
    const auto ab = b - a;
    const auto t = ((P - a) * ab) / ab.squared_length();
    if (!(CGAL::is_positive(t) && t < 1)) continue;
    // The faces beside the edge, each (a, b, apex) or (b, a, apex) in its orientation, and the
    // two triangles each becomes with P in place of the edge's inside.
    bool ok = true;
    std::vector<F> faces;
    for (int side = 0; side < 2 && ok; ++side) {
      const auto g = side == 0 ? h : mesh.opposite(h);
      if (mesh.is_border(g)) continue;
      const F f = mesh.face(g);
      if (used_faces.count(std::size_t(f))) ok = false;
      faces.push_back(f);
      const Point& s = mesh.point(mesh.source(g));
      const Point& r = mesh.point(mesh.target(g));
      const Point& apex = mesh.point(mesh.target(mesh.next(g)));
      const auto n = CGAL::cross_product(r - s, apex - s);
      for (const auto& [x, y] : {std::make_pair(&s, &P), std::make_pair(&P, &r)}) {
        const auto m = CGAL::cross_product(*y - *x, apex - *x);
        if (!CGAL::is_positive(m * n)) ok = false;
      }
    }
    if (!ok) {
      ++report.refused;
      continue;
    }
    // Split the edge, then cut each face beside it from the new vertex to its apex.
    const auto hnew = CGAL::Euler::split_edge(h, mesh);  // source(h) -> v, then h: v -> target
    const auto v = mesh.target(hnew);
    mesh.point(v) = P;
    used_edges.insert(std::size_t(e));
    for (int side = 0; side < 2; ++side) {
      const auto g1 = side == 0 ? hnew : mesh.opposite(h);  // a halfedge into v on this side
      if (mesh.is_border(g1)) continue;
      const F f = mesh.face(g1);
      const auto g2 = side == 0 ? mesh.next(h) : mesh.next(mesh.opposite(hnew));  // into the apex
      const std::size_t before = mesh.number_of_faces();
      CGAL::Euler::split_face(g1, g2, mesh);
      const F added(static_cast<typename F::size_type>(before));
      used_faces.insert(std::size_t(f));
      used_faces.insert(std::size_t(added));
      report.added.emplace_back(added, f);
      report.reshaped.push_back(f);
    }
    ++report.snapped;
    report.max_move = std::max(report.max_move, d);
  }
  return report;
}

template <class K>
std::vector<std::array<double, 3>> crowded_curve_points(const std::vector<Polyline<K>>& curves, const Mesh<K>& a,
                                                        const Mesh<K>& b, double distance) {
  std::vector<std::array<double, 3>> result;
  if (!(distance > 0)) return result;
  // Every curve point and vertex in the hash grid of KeepAway (doubles).
  KeepAway points(distance);
  points.add_points<K>(curves);
  points.add_vertices<K>(a);
  points.add_vertices<K>(b);
  std::set<std::array<double, 3>> seen;
  for (const auto& c : curves)
    for (const auto& p : c) {
      const auto q = to_filtered(p);
      const std::array<double, 3> x{q.x(), q.y(), q.z()};
      if (points.crowded(x) && seen.insert(x).second) result.push_back(x);
    }
  return result;
}

template SnapReport<Exact> snap_vertices<Exact>(Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double);
template SnapReport<Exact> snap_vertices_to_segments<Exact>(Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double, bool, bool, const Mesh<Exact>*, const std::vector<std::array<double, 3>>*, double);
template EdgeSnapReport<Exact> snap_edges_to_points<Exact>(Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double);
template std::vector<std::array<double, 3>> crowded_curve_points<Exact>(const std::vector<Polyline<Exact>>&, const Mesh<Exact>&, const Mesh<Exact>&, double);
template bool move_keeps_faces<Exact>(const Mesh<Exact>&, typename MeshTypes<Exact>::V, const Exact::Point_3&);
template SnapReport<Filtered> snap_vertices<Filtered>(Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double);
template SnapReport<Filtered> snap_vertices_to_segments<Filtered>(Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double, bool, bool, const Mesh<Filtered>*, const std::vector<std::array<double, 3>>*, double);
template EdgeSnapReport<Filtered> snap_edges_to_points<Filtered>(Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double);
template std::vector<std::array<double, 3>> crowded_curve_points<Filtered>(const std::vector<Polyline<Filtered>>&, const Mesh<Filtered>&, const Mesh<Filtered>&, double);
template bool move_keeps_faces<Filtered>(const Mesh<Filtered>&, typename MeshTypes<Filtered>::V, const Filtered::Point_3&);
template SnapReport<Float> snap_vertices<Float>(Mesh<Float>&, const std::vector<Polyline<Float>>&, double);
template SnapReport<Float> snap_vertices_to_segments<Float>(Mesh<Float>&, const std::vector<Polyline<Float>>&, double, bool, bool, const Mesh<Float>*, const std::vector<std::array<double, 3>>*, double);
template EdgeSnapReport<Float> snap_edges_to_points<Float>(Mesh<Float>&, const std::vector<Polyline<Float>>&, double);
template std::vector<std::array<double, 3>> crowded_curve_points<Float>(const std::vector<Polyline<Float>>&, const Mesh<Float>&, const Mesh<Float>&, double);
template bool move_keeps_faces<Float>(const Mesh<Float>&, typename MeshTypes<Float>::V, const Float::Point_3&);

}  // namespace seam::internal
