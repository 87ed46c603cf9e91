// seam: flat contacts made one common triangulation. See seam/internal/flat_contacts.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/errors.h>
#include <seam/internal/certified.h>
#include <seam/improve.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/message.h>
#include <seam/internal/splice.h>
#include <seam/kernels.h>
#include <seam/quality.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <list>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

namespace seam::internal {

namespace {

struct PointLess {
  template <class P> bool operator()(const P& p, const P& q) const { return CGAL::compare_xyz(p, q) == CGAL::SMALLER; }
};

/// Disjoint sets over face nodes (A faces first, then B faces).
struct DisjointSets {
  std::vector<std::size_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::size_t x, std::size_t y) {
    x = find(x), y = find(y);
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
  }
};

/// The coordinates kept when projecting along `axis` (dropping it).
inline std::array<int, 2> kept_coordinates(int axis) {
  return axis == 0 ? std::array<int, 2>{1, 2} : axis == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1};
}

/// The area of the projection of (p, q, r) along `axis` (doubles).
template <class P> double projected_area(const P& p, const P& q, const P& r, int axis) {
  const auto [u, v] = kept_coordinates(axis);
  const auto x = to_filtered(p), y = to_filtered(q), z = to_filtered(r);
  return std::abs((y[u] - x[u]) * (z[v] - x[v]) - (y[v] - x[v]) * (z[u] - x[u])) / 2;
}

/// Orientation of the projection of (p, q, r) along `axis` (exact under the exact kernel: the
/// points' intervals first, then, where their sign is not certain, their exact values; not the
/// lazy numbers' arithmetic, which allocates a node per operation).
template <class P> CGAL::Sign projected_orientation(const P& p, const P& q, const P& r, int axis) {
  const auto [u, v] = kept_coordinates(axis);
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    {
      CGAL::Protect_FPU_rounding<true> rounding;
      const certified::IP a = certified::interval_point(p), b = certified::interval_point(q),
                          c = certified::interval_point(r);
      const int sure = certified::sure_sign((b[u] - a[u]) * (c[v] - a[v]) - (b[v] - a[v]) * (c[u] - a[u]));
      if (sure != 0) return sure > 0 ? CGAL::POSITIVE : CGAL::NEGATIVE;
    }
    const auto &a = CGAL::exact(p), &b = CGAL::exact(q), &c = CGAL::exact(r);
    return CGAL::sign_of_determinant(b[u] - a[u], b[v] - a[v], c[u] - a[u], c[v] - a[v]);
  } else {
    return CGAL::sign_of_determinant(q[u] - p[u], q[v] - p[v], r[u] - p[u], r[v] - p[v]);
  }
}

/// Two coplanar triangles, projected along `axis` (where neither is degenerate), overlap with
/// positive area: no edge line of either weakly separates them (separating axes of two convex
/// polygons; exact predicates).
template <class P> bool interiors_overlap(const std::array<const P*, 3>& s, const std::array<const P*, 3>& t, int axis) {
  auto separated_by_an_edge_of = [&](const std::array<const P*, 3>& x, const std::array<const P*, 3>& y) {
    const CGAL::Sign turn = projected_orientation(*x[0], *x[1], *x[2], axis);
    for (int i = 0; i < 3; ++i) {
      bool all_outside = true;
      for (int k = 0; k < 3 && all_outside; ++k)
        all_outside = projected_orientation(*x[i], *x[(i + 1) % 3], *y[k], axis) != turn;
      if (all_outside) return true;
    }
    return false;
  };
  return !separated_by_an_edge_of(s, t) && !separated_by_an_edge_of(t, s);
}

/// The same point without an exact evaluation: the same representation (Epeck: shared lazy
/// handles, as the curve points of both meshes are) or equal doubles. False when unsure.
template <class P> bool surely_same(const P& p, const P& q) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>)
    return CGAL::identical(p, q);
  else
    return p == q;
}

/// Interval test: some edge line of x (projected along `axis`) certainly has all of y on its
/// closed outer side, so their interiors do not overlap (a corner of y at an end of that edge is
/// on it). False when unsure.
template <class P>
bool surely_apart_in_plane(const std::array<const P*, 3>& xp, const std::array<const certified::IP*, 3>& x,
                           const std::array<const P*, 3>& yp, const std::array<const certified::IP*, 3>& y, int axis) {
  const int turn = certified::sure_sign(certified::orient2(*x[0], *x[1], *x[2], axis));
  if (turn == 0) return false;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    bool outside = true;
    for (int k = 0; k < 3 && outside; ++k) {
      if (surely_same(*yp[k], *xp[i]) || surely_same(*yp[k], *xp[j])) continue;
      const auto o = certified::orient2(*x[i], *x[j], *y[k], axis);
      outside = turn > 0 ? o.sup() <= 0 : o.inf() >= 0;
    }
    if (outside) return true;
  }
  return false;
}

/// The axis along which a triangle projects best (largest normal component, doubles); the
/// projection along it is not degenerate (checked exactly by the caller).
template <class P> int dominant_axis(const P& p, const P& q, const P& r) {
  const auto a = to_filtered(p), b = to_filtered(q), c = to_filtered(r);
  const auto n = CGAL::cross_product(b - a, c - a);
  const double x = std::abs(n.x()), y = std::abs(n.y()), z = std::abs(n.z());
  return x >= y && x >= z ? 0 : (y >= z ? 1 : 2);
}

/// A planar contact patch: its points (both meshes' vertices there, each once), the common edges
/// of both meshes (constraints), which of them are its border, and the projection axis.
template <class K> struct Patch {
  using Segment = std::pair<std::size_t, std::size_t>;  ///< two point ids, the smaller first
  std::vector<typename K::Point_3> points;
  std::vector<Segment> constraints;
  std::set<Segment> border;
  /// Constraints the refinement may split (see the header): curve segments inside, and those of
  /// the border whose faces beyond may be split with them.
  std::set<Segment> splittable;
  int axis = 2;
  /// Per point: a vertex of A there, of B there. Only the points of both are kept (see
  /// triangulate); those of one mesh only lie inside the patch and are dropped.
  std::vector<char> in_a, in_b;
  std::vector<std::array<std::size_t, 3>> triangles;  ///< the result, positively oriented in the projection
  /// Per triangle below the bound (in the projection) after the refinement: 1 + why it stays
  /// (ShortfallCause); 0 for the others.
  std::vector<std::uint8_t> reasons;
  /// The points the refinement put on a constraint given: the constraint, and the point's place
  /// along it (0 at its first point, 1 at its second; doubles, for the order only).
  struct Split {
    Segment original;
    double at = 0.5;
  };
  std::map<std::size_t, Split> splits;  ///< by point id
  std::size_t steiner_points = 0;       ///< points inserted inside (appended to `points`)
  std::size_t below_bound = 0;          ///< triangles left below the angle bound (projection)

  /// Each split constraint given, with its split points in order from its first point.
  std::map<Segment, std::vector<std::size_t>> split_chains() const {
    std::map<Segment, std::vector<std::pair<double, std::size_t>>> placed;
    for (const auto& [point, split] : splits) placed[split.original].emplace_back(split.at, point);
    std::map<Segment, std::vector<std::size_t>> chains;
    for (auto& [segment, points_at] : placed) {
      std::sort(points_at.begin(), points_at.end());
      for (const auto& pa : points_at) chains[segment].push_back(pa.second);
    }
    return chains;
  }
};

/// The smallest angle (degrees, doubles) of a triangle given by three 2D points.
template <class P2> double min_angle_2(const P2& p, const P2& q, const P2& r) {
  const auto P = CGAL::to_double(p.x()), Q = CGAL::to_double(q.x()), R = CGAL::to_double(r.x());
  const auto Py = CGAL::to_double(p.y()), Qy = CGAL::to_double(q.y()), Ry = CGAL::to_double(r.y());
  return seam::min_angle_deg(Filtered::Point_3(P, Py, 0), Filtered::Point_3(Q, Qy, 0), Filtered::Point_3(R, Ry, 0));
}

/// The point of the patch's plane that projects (along its axis) onto (x, y): exact under the
/// exact kernel (a rational function of exact coordinates), rounded under the others.
template <class K> typename K::Point_3 lifted(const Patch<K>& patch, const typename K::Point_2& q) {
  // Points 0, 1, 2 are the corners of a face of A in the patch (its first, collected first).
  const auto& p0 = patch.points[0];
  const auto n = CGAL::cross_product(patch.points[1] - p0, patch.points[2] - p0);
  const auto [u, v] = kept_coordinates(patch.axis);
  const int a = patch.axis;
  std::array<typename K::FT, 3> c;
  c[std::size_t(u)] = q.x();
  c[std::size_t(v)] = q.y();
  c[std::size_t(a)] = p0[a] - (n[u] * (q.x() - p0[u]) + n[v] * (q.y() - p0[v])) / n[a];
  typename K::Point_3 result(c[0], c[1], c[2]);
  make_exact(result);
  return result;
}

/// Ruppert's refinement of the inside of a patch (its faces of odd nesting), see the header for
/// the rules, the bound and why it ends.
/// Sorts (key, item) pairs by key alone: the order of point ids in which the flat contacts'
/// refinement takes its work, not the triangulation's storage order (see PatchRefiner::run).
template <class Pairs> void sort_by_key(Pairs& pairs) {
  std::sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
}

template <class K, class CDT> class PatchRefiner {
 public:
  using FH = typename CDT::Face_handle;
  using VH = typename CDT::Vertex_handle;
  using P2 = typename K::Point_2;
  using Segment = typename Patch<K>::Segment;

  /// With max_area > 0, faces whose area on the plane is larger are refined too, and the budget
  /// grows by twice the patch's area (projected_area, in the projection) over it.
  PatchRefiner(CDT& cdt, Patch<K>& patch, double bound, double feature_size, double max_area, double projected_area)
      : cdt_(cdt),
        patch_(patch),
        bound_(bound),
        feature_(feature_size),
        max_projected_area_(max_area > 0 && std::isfinite(plane_area_factor(patch)) ? max_area / plane_area_factor(patch) : 0),
        budget_(4 * cdt.number_of_vertices() + 64 + area_budget(projected_area, max_projected_area_)) {}

  /// Why a face still below the bound stays: the reason it was left for, or the budget.
  ShortfallCause reason(FH f) const {
    const auto it = gave_up_.find(key(f));
    return it != gave_up_.end() ? it->second : ShortfallCause::budget;
  }

  void run() {
    // In the order of the point ids, not the triangulation's storage order: CGAL's triangulation
    // places its faces in memory in an order that can depend on addresses, and the points
    // inserted here are numbered in the order they come.
    std::vector<std::pair<std::array<std::size_t, 2>, std::pair<VH, VH>>> constraints;
    for (const auto& e : cdt_.finite_edges())
      if (e.first->is_constrained(e.second)) constraints.push_back(keyed(e.first, e.second));
    sort_by_key(constraints);
    for (const auto& c : constraints) encroach_checks_.push_back(c.second);
    std::vector<std::pair<std::array<std::size_t, 3>, std::array<VH, 3>>> bad_faces;
    for (FH f : cdt_.finite_face_handles())
      if (bad(f)) bad_faces.push_back({key(f), corners(f)});
    sort_by_key(bad_faces);
    for (const auto& b : bad_faces) bad_faces_.push_back(b.second);
    while (budget_ > 0) {
      if (!encroach_checks_.empty()) {
        const auto [s, t] = encroach_checks_.front();
        encroach_checks_.pop_front();
        if (encroached_by_a_vertex(s, t)) split(s, t);
        continue;
      }
      if (bad_faces_.empty()) break;
      const auto c = bad_faces_.front();
      bad_faces_.pop_front();
      FH f;
      if (cdt_.is_face(c[0], c[1], c[2], f) && bad(f) && refine_face(f)) bad_faces_.push_back(c);  // a split: again
    }
  }

 private:
  bool inside(FH f) const { return !cdt_.is_infinite(f) && f->info().nesting % 2 == 1; }
  bool bad(FH f) const {
    return inside(f) && (min_angle_2(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()) < bound_ ||
                         too_large(f));
  }
  /// Larger than max_area on the plane (doubles).
  bool too_large(FH f) const {
    return max_projected_area_ > 0 &&
           std::abs(CGAL::to_double(CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()))) >
               max_projected_area_ * (1 + 1e-9);
  }
  /// Twice the patch's area over the bound (both in the projection), at most 1e9 (as the quality
  /// stage's budget): 0 without a bound.
  static std::size_t area_budget(double projected_area, double max_projected_area) {
    if (!(max_projected_area > 0)) return 0;
    return std::size_t(std::min(1e9, std::ceil(2 * projected_area / max_projected_area)));
  }
  /// A face's area on the patch's plane over its area in the projection along the axis (doubles;
  /// not finite where the first face rounds flat in the projection: no area bound then).
  static double plane_area_factor(const Patch<K>& patch) {
    const auto n = CGAL::cross_product(to_filtered(patch.points[1]) - to_filtered(patch.points[0]),
                                       to_filtered(patch.points[2]) - to_filtered(patch.points[0]));
    return std::sqrt(n.squared_length()) / std::abs(n[patch.axis]);
  }
  static std::array<VH, 3> corners(FH f) { return {f->vertex(0), f->vertex(1), f->vertex(2)}; }
  static std::pair<VH, VH> ends(FH f, int i) { return {f->vertex(CDT::cw(i)), f->vertex(CDT::ccw(i))}; }
  /// q lies in the closed diametral circle of s-t (exact).
  static bool encroaches(const P2& q, VH s, VH t) { return CGAL::angle(s->point(), q, t->point()) != CGAL::ACUTE; }

  /// The constraint s-t (if it still is one) has an inside face whose third corner encroaches it.
  bool encroached_by_a_vertex(VH s, VH t) const {
    FH f;
    int i = 0;
    if (!cdt_.is_edge(s, t, f, i) || !f->is_constrained(i)) return false;
    for (const auto& [g, k] : {std::pair<FH, int>(f, i), std::pair<FH, int>(f->neighbor(i), f->neighbor(i)->index(f))})
      if (inside(g) && encroaches(g->vertex(k)->point(), s, t)) return true;
    return false;
  }

  /// Splits the constraint s-t at its middle where the rules allow; whether it did.
  bool split(VH s, VH t) {
    FH f;
    int i = 0;
    if (!cdt_.is_edge(s, t, f, i) || !f->is_constrained(i)) return refuse(ShortfallCause::shape);
    const std::size_t a = std::min(s->info(), t->info()), b = std::max(s->info(), t->info());
    const auto from = original_.find({a, b});
    const Segment original = from != original_.end() ? from->second : Segment{a, b};
    if (!patch_.splittable.count(original)) return refuse(ShortfallCause::constraint_angle);  // (a border that stays)
    if (CGAL::to_double(CGAL::squared_distance(patch_.points[a], patch_.points[b])) < 4 * feature_ * feature_)
      return refuse(ShortfallCause::feature_size);
    // The middle must lie on the segment: exact under Exact; under Filtered the middle of two
    // doubles is often rounded off it (tested exactly); under Float no test is exact: no split.
    if constexpr (std::is_same_v<K, Float>) return refuse(ShortfallCause::constraint_angle);
    const typename K::Point_3 middle_3 = CGAL::midpoint(patch_.points[a], patch_.points[b]);
    if (!CGAL::collinear(patch_.points[a], middle_3, patch_.points[b])) return refuse(ShortfallCause::constraint_angle);
    // The faces around the new point on the side of a finite face beside s-t take its nesting,
    // the others that of the face across.
    FH known = f->neighbor(i), across = f;
    if (cdt_.is_infinite(known)) std::swap(known, across);
    const int nesting_known = known->info().nesting, nesting_across = across->info().nesting;
    const P2 apex = known->vertex(known->index(across))->point();
    const P2 middle = CGAL::midpoint(s->point(), t->point());
    const VH w = cdt_.insert(middle, CDT::EDGE, f, i);  // splits the constraint in two
    add_point(w, middle_3);
    auto at = [&](std::size_t x) {
      return x == original.first ? 0.0 : x == original.second ? 1.0 : patch_.splits.at(x).at;
    };
    patch_.splits[w->info()] = {original, (at(a) + at(b)) / 2};
    original_[{std::min(a, w->info()), std::max(a, w->info())}] = original;
    original_[{std::min(b, w->info()), std::max(b, w->info())}] = original;
    --budget_;
    const CGAL::Orientation side = CGAL::orientation(s->point(), t->point(), apex);
    after_insertion(w, [&](FH h) {
      for (int k = 0; k < 3; ++k) {
        const VH x = h->vertex(k);
        if (x == w || x == s || x == t) continue;
        const CGAL::Orientation o = CGAL::orientation(s->point(), t->point(), x->point());
        if (o == CGAL::COLLINEAR) continue;  // (rounded kernels: a corner on the line)
        return o == side ? nesting_known : nesting_across;
      }
      return nesting_known;
    });
    return true;
  }

  /// Refines a bad face: splits the constraint its circumcenter lies beyond or encroaches, or
  /// inserts the circumcenter. True when a constraint was split (the face may go the next time).
  bool refine_face(FH f) {
    const P2 exact_center = CGAL::circumcenter(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    if (CGAL::to_double(CGAL::squared_distance(exact_center, f->vertex(0)->point())) < feature_ * feature_)
      return give_up(f, ShortfallCause::feature_size);  // the corners are that close
    // Rounded to doubles: a point of bounded size (its lifted coordinate is exact).
    const P2 c(CGAL::to_double(exact_center.x()), CGAL::to_double(exact_center.y()));
    // Walk from f towards c; a constraint in the way is split.
    FH at = f;
    if (cdt_.oriented_side(f, c) == CGAL::ON_NEGATIVE_SIDE) {
      const P2 start = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      if (cdt_.oriented_side(f, start) != CGAL::ON_POSITIVE_SIDE) return give_up(f, ShortfallCause::shape);  // (rounded: not inside f)
      auto walk = cdt_.line_walk(start, c, f);
      FH previous = walk;
      for (std::size_t steps = 0;; ++steps) {
        ++walk;
        const FH next = walk;
        if (next == FH() || steps > 10000 || !previous->has_neighbor(next)) return give_up(f, ShortfallCause::shape);  // (through a vertex)
        const int k = previous->index(next);
        if (previous->is_constrained(k)) {
          const auto [s, t] = ends(previous, k);
          // Crossed, not touched at an end (the line through a vertex): its ends on either side.
          if (CGAL::orientation(start, c, s->point()) * CGAL::orientation(start, c, t->point()) != CGAL::NEGATIVE)
            return give_up(f, ShortfallCause::shape);
          return split(s, t) || give_up(f, refused_);
        }
        if (cdt_.is_infinite(next)) return give_up(f, ShortfallCause::shape);
        if (cdt_.oriented_side(next, c) != CGAL::ON_NEGATIVE_SIDE) {
          at = next;
          break;
        }
        previous = next;
      }
    }
    if (!inside(at)) return give_up(f, ShortfallCause::shape);
    // A constraint of c's conflict zone that c encroaches is split instead.
    zone_.clear();
    cdt_.get_conflicts(c, std::back_inserter(zone_), at);
    for (FH g : zone_)
      for (int i = 0; i < 3; ++i)
        if (g->is_constrained(i)) {
          const auto [s, t] = ends(g, i);
          if (encroaches(c, s, t)) return split(s, t) || give_up(f, refused_);
        }
    for (int i = 0; i < 3; ++i)  // (rounding moved c: keep the distance to the corners)
      if (CGAL::to_double(CGAL::squared_distance(c, at->vertex(i)->point())) < feature_ * feature_) return give_up(f, ShortfallCause::feature_size);
    typename CDT::Locate_type lt;
    int li = 0;
    const FH located = cdt_.locate(c, lt, li, at);
    if (!(lt == CDT::FACE || (lt == CDT::EDGE && !located->is_constrained(li))) || !inside(located)) return give_up(f, ShortfallCause::shape);
    const int nesting = located->info().nesting;
    const VH w = cdt_.insert(c, lt, located, li);
    add_point(w, lifted<K>(patch_, c));
    ++patch_.steiner_points;
    --budget_;
    after_insertion(w, [&](FH) { return nesting; });  // the conflict zone ends at constraints
    return false;
  }

  /// A split refused, and why (refused_).
  bool refuse(ShortfallCause why) {
    refused_ = why;
    return false;
  }
  /// A bad face left as it is, and why.
  bool give_up(FH f, ShortfallCause why) {
    gave_up_[key(f)] = why;
    return false;
  }
  /// A constraint edge (the edge i of f) with its point ids, smaller first: the order it is
  /// queued in (see run).
  static std::pair<std::array<std::size_t, 2>, std::pair<VH, VH>> keyed(FH f, int i) {
    const auto [s, t] = ends(f, i);
    return {{std::min(s->info(), t->info()), std::max(s->info(), t->info())}, {s, t}};
  }
  static std::array<std::size_t, 3> key(FH f) {
    std::array<std::size_t, 3> k = {f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
    std::sort(k.begin(), k.end());
    return k;
  }

  /// A point inserted (a vertex of both meshes).
  void add_point(VH w, const typename K::Point_3& p) {
    w->info() = patch_.points.size();
    patch_.points.push_back(p);
    patch_.in_a.push_back(1);
    patch_.in_b.push_back(1);
  }

  /// After inserting w: the nesting of its faces, its bad faces queued, the constraints it may
  /// encroach (those opposite it) queued for the test.
  /// In the order of the point ids, not the circulator's: where it starts follows the CDT's
  /// flips, whose order followed addresses (CT row 6 numbered two points in either order, and
  /// listed two faces so, depending on the output file names).
  template <class NestingOf> void after_insertion(VH w, NestingOf nesting_of) {
    std::vector<std::pair<std::array<std::size_t, 3>, FH>> faces;
    auto h = cdt_.incident_faces(w);
    const auto first = h;
    do {
      if (!cdt_.is_infinite(h)) faces.push_back({key(FH(h)), FH(h)});
    } while (++h != first);
    sort_by_key(faces);
    std::vector<std::pair<std::array<std::size_t, 2>, std::pair<VH, VH>>> constrained;
    for (const auto& [k, f] : faces) {
      f->info().nesting = nesting_of(f);
      for (int j = 0; j < 3; ++j)
        if (f->is_constrained(j)) constrained.push_back(keyed(f, j));
      if (bad(f)) bad_faces_.push_back(corners(f));
    }
    sort_by_key(constrained);
    for (const auto& c : constrained) encroach_checks_.push_back(c.second);
  }

  CDT& cdt_;
  Patch<K>& patch_;
  const double bound_, feature_;
  const double max_projected_area_;  ///< max_area in the projection; 0: no area bound
  std::size_t budget_;
  std::deque<std::pair<VH, VH>> encroach_checks_;
  std::deque<std::array<VH, 3>> bad_faces_;
  std::map<Segment, Segment> original_;  ///< a piece of a split constraint -> the constraint given
  std::vector<FH> zone_;
  ShortfallCause refused_ = ShortfallCause::constraint_angle;  ///< why the last split was refused
  std::map<std::array<std::size_t, 3>, ShortfallCause> gave_up_;  ///< bad faces left, by sorted corners
};

/// The constrained Delaunay triangulation of the patch, projected along its axis: its points of
/// both meshes (each point's two kept coordinates: exact, a projection constructs nothing), with
/// the border and the curve segments as constraints, refined inside (PatchRefiner) when
/// options.min_angle_deg > 0.
template <class K>
bool triangulate(Patch<K>& patch, double expected_area, const FlatContactOptions& options, std::string& why) {
  using Traits = K;
  struct FaceInfo {
    int nesting = -1;
  };
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Traits>;
  using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Traits>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<Traits, Fbi>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using CDT = CGAL::Constrained_Delaunay_triangulation_2<Traits, Tds, CGAL::Exact_predicates_tag>;
  using FH = typename CDT::Face_handle;
  using VH = typename CDT::Vertex_handle;
  using Edge = typename CDT::Edge;
  using P2 = typename K::Point_2;
  CDT cdt;
  const auto [u, v] = kept_coordinates(patch.axis);
  std::vector<VH> handle(patch.points.size());
  for (std::size_t i = 0; i < patch.points.size(); ++i) {
    if (!(patch.in_a[i] && patch.in_b[i])) continue;
    handle[i] = cdt.insert(P2(patch.points[i][u], patch.points[i][v]));
    handle[i]->info() = i;
  }
  for (std::size_t i = 0; i < patch.points.size(); ++i)
    if (handle[i] != VH() && handle[i]->info() != i) {  // two points with one projection: not planar after all
      why = "two of its points project onto one";
      return false;
    }
  try {
    for (const auto& [i, j] : patch.constraints) cdt.insert_constraint(handle[i], handle[j]);
  } catch (...) {  // (no exception is expected: Exact_predicates_tag inserts crossings as points,
    why = "its constraints cross";  // which the test below finds)
    return false;
  }
  for (const auto& [i, j] : patch.constraints) {
    FH f;
    int k;
    if (!cdt.is_edge(handle[i], handle[j], f, k)) {
      why = "a constraint passes through another of its points, or crosses another";
      return false;
    }
  }
  // Inside: an odd number of border edges crossed from the infinite face. An edge at the infinite
  // vertex is never one (its info was never set: reading it made the result depend on whatever
  // the allocator left there).
  auto on_border = [&](const Edge& e) {
    const auto s = e.first->vertex(CDT::cw(e.second)), t = e.first->vertex(CDT::ccw(e.second));
    if (cdt.is_infinite(s) || cdt.is_infinite(t)) return false;
    const std::size_t i = s->info(), j = t->info();
    return patch.border.count({std::min(i, j), std::max(i, j)}) > 0;
  };
  for (FH f : cdt.all_face_handles()) f->info().nesting = -1;
  std::list<Edge> crossings;
  auto flood = [&](FH start, int level) {
    if (start->info().nesting != -1) return;
    std::deque<FH> queue{start};
    while (!queue.empty()) {
      const FH f = queue.front();
      queue.pop_front();
      if (f->info().nesting != -1) continue;
      f->info().nesting = level;
      for (int i = 0; i < 3; ++i) {
        const FH n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        if (on_border(Edge(f, i)))
          crossings.push_back(Edge(f, i));
        else
          queue.push_back(n);
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!crossings.empty()) {
    const Edge e = crossings.front();
    crossings.pop_front();
    const FH n = e.first->neighbor(e.second);
    if (n->info().nesting == -1) flood(n, e.first->info().nesting + 1);
  }
  std::optional<PatchRefiner<K, CDT>> refiner;
  if (options.min_angle_deg > 0) {
    refiner.emplace(cdt, patch, options.min_angle_deg, options.feature_size, options.max_area, expected_area);
    refiner->run();
  }
  double area = 0;
  // In the order of their corners' ids (each from its smallest id, which keeps its orientation),
  // not the triangulation's storage order (see PatchRefiner::run).
  std::vector<std::pair<std::array<std::size_t, 3>, FH>> inside;
  for (FH f : cdt.finite_face_handles()) {
    if (f->info().nesting % 2 != 1) continue;
    std::array<std::size_t, 3> t;
    for (int i = 0; i < 3; ++i) t[i] = f->vertex(i)->info();
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    inside.push_back({t, f});
  }
  sort_by_key(inside);
  for (const auto& [t, f] : inside) {
    patch.triangles.push_back(t);
    patch.reasons.push_back(0);
    if (refiner && min_angle_2(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()) < options.min_angle_deg) {
      ++patch.below_bound;
      patch.reasons.back() = std::uint8_t(1 + int(refiner->reason(f)));
    }
    area += projected_area(patch.points[t[0]], patch.points[t[1]], patch.points[t[2]], patch.axis);
  }
  // The triangulation covers the region of the faces it replaces (doubles: a sanity check).
  if (!(std::abs(area - expected_area) <= 1e-9 * expected_area)) {
    why = say("its triangulation covers ", area, " where the faces it replaces cover ", expected_area);
    patch.triangles.clear();
    return false;
  }
  return true;
}

template <class K> struct FaceCorners {
  using M = Mesh<K>;
  const M& mesh;
  std::vector<std::array<typename M::Vertex_index, 3>> corners;  // by face index
  explicit FaceCorners(const M& m) : mesh(m), corners(m.number_of_faces() + m.number_of_removed_faces()) {
    for (auto f : m.faces()) {
      const auto h = m.halfedge(f);
      corners[std::size_t(f)] = {m.source(h), m.target(h), m.target(m.next(h))};
    }
  }
  std::array<const typename K::Point_3*, 3> points(std::size_t f) const {
    const auto& c = corners[f];
    return {&mesh.point(c[0]), &mesh.point(c[1]), &mesh.point(c[2])};
  }
};

/// Why triangle t could not be added after triangles 0..t-1: the first of its directed edges
/// that an earlier triangle holds already (a patch triangle or a face kept outside the patches).
template <class V>
std::string misfit_cause(const std::vector<std::array<V, 3>>& triangles, const std::vector<char>& in_patch, std::size_t t) {
  const auto& tri = triangles[t];
  for (int k = 0; k < 3; ++k) {
    const V u = tri[std::size_t(k)], v = tri[std::size_t((k + 1) % 3)];
    if (u == v) return say("a triangle of ", in_patch[t] ? "a patch" : "the mesh", " has two equal corners");
    for (std::size_t s = 0; s < t; ++s)
      for (int i = 0; i < 3; ++i)
        if (triangles[s][std::size_t(i)] == u && triangles[s][std::size_t((i + 1) % 3)] == v)
          return say("triangle ", t, in_patch[t] ? " (of a patch)" : " (kept)", " and triangle ", s,
                     in_patch[s] ? " (of a patch)" : " (kept)", " have the edge ", std::size_t(u), "-", std::size_t(v),
                     " on one side");
  }
  return say("triangle ", t, in_patch[t] ? " (of a patch)" : " (kept)", " would make a vertex non-manifold");
}

/// Hands each triangle of a unified patch to `emit` as this mesh's: its corners by `ids`, turned
/// like this mesh's faces there (`faces`), with the face it comes from (itself when this mesh has
/// it already: `unchanged`; otherwise the face holding its centroid, doubles: provenance only).
template <class K, class Emit>
void emit_patch(const Patch<K>& patch, const std::vector<std::size_t>& ids, const std::vector<std::size_t>& faces,
                const FaceCorners<K>& fc, Emit emit) {
  using Id = std::size_t;
  const auto first = fc.points(faces.front());
  const bool reverse = projected_orientation(*first[0], *first[1], *first[2], patch.axis) != CGAL::POSITIVE;
  std::map<std::array<Id, 3>, std::size_t> existing;  // this mesh's faces there, by sorted corners
  for (std::size_t g : faces) {
    const auto& c = fc.corners[g];
    std::array<Id, 3> key = {std::size_t(c[0]), std::size_t(c[1]), std::size_t(c[2])};
    std::sort(key.begin(), key.end());
    existing.emplace(key, g);
  }
  // Not a structured binding: C++17 lambdas cannot capture those (Clang refuses).
  const auto kept = kept_coordinates(patch.axis);
  auto projected = [&](const typename K::Point_3& q) {
    const auto d = to_filtered(q);
    return std::array<double, 2>{d[kept[0]], d[kept[1]]};
  };
  for (std::size_t n = 0; n < patch.triangles.size(); ++n) {
    const auto& t = patch.triangles[n];
    std::array<Id, 3> tri = {ids[t[0]], ids[t[1]], ids[t[2]]};
    if (reverse) std::swap(tri[1], tri[2]);
    auto key = tri;
    std::sort(key.begin(), key.end());
    if (const auto it = existing.find(key); it != existing.end()) {
      emit(tri, it->second, true, patch.reasons[n]);
      continue;
    }
    const auto a = projected(patch.points[t[0]]), b = projected(patch.points[t[1]]), c = projected(patch.points[t[2]]);
    const std::array<double, 2> m = {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3};
    std::size_t origin = faces.front();
    double best = -HUGE_VAL;
    for (std::size_t g : faces) {
      const auto corners = fc.points(g);
      std::array<std::array<double, 2>, 3> x = {projected(*corners[0]), projected(*corners[1]), projected(*corners[2])};
      const double turn = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]);
      double inside = HUGE_VAL;  // the smallest signed distance-like value over the three edges
      for (int i = 0; i < 3; ++i) {
        const auto &s = x[i], &e = x[(i + 1) % 3];
        inside = std::min(inside, ((e[0] - s[0]) * (m[1] - s[1]) - (e[1] - s[1]) * (m[0] - s[0])) * (turn > 0 ? 1 : -1));
      }
      if (inside > best) best = inside, origin = g;
      if (inside >= 0) break;
    }
    emit(tri, origin, false, patch.reasons[n]);
  }
}

/// A convex polygon (corners in order; points on its sides may be among them) cut into triangles
/// of the same orientation: an ear at a time, at a corner not collinear with its neighbours whose
/// cut leaves a polygon that is not flat (exact), the ear with the largest smallest angle first
/// (doubles).
template <class K>
std::vector<std::array<std::size_t, 3>> ear_cut(std::vector<std::size_t> polygon,
                                                const std::vector<typename K::Point_3>& point_of) {
  std::vector<std::array<std::size_t, 3>> result;
  auto collinear = [&](std::size_t x, std::size_t y, std::size_t z) {
    return CGAL::collinear(point_of[x], point_of[y], point_of[z]);
  };
  while (polygon.size() > 3) {
    const std::size_t n = polygon.size();
    std::size_t best = n;
    double best_angle = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t before = polygon[(i + n - 1) % n], at = polygon[i], after = polygon[(i + 1) % n];
      if (collinear(before, at, after) || collinear(polygon[(i + n - 2) % n], before, after) ||
          collinear(before, after, polygon[(i + 2) % n]))
        continue;
      const double angle = seam::min_angle_deg(to_filtered(point_of[before]), to_filtered(point_of[at]),
                                               to_filtered(point_of[after]));
      if (angle > best_angle) best_angle = angle, best = i;
    }
    if (best == n) throw InternalError("flat contacts: a face beyond a split border edge cannot be cut");
    result.push_back({polygon[(best + n - 1) % n], polygon[best], polygon[(best + 1) % n]});
    polygon.erase(polygon.begin() + std::ptrdiff_t(best));
  }
  if (collinear(polygon[0], polygon[1], polygon[2]))
    throw InternalError("flat contacts: a face beyond a split border edge is flat");
  result.push_back({polygon[0], polygon[1], polygon[2]});
  return result;
}

/// Where the points of the unified patches go in one mesh: per patch, the id of each point its
/// triangles use (the mesh's vertex there, or a new point), and per split edge of the mesh its
/// split points (in order from its smaller id). Ids from the mesh's number of vertices on are
/// new points, appended to `point_of`.
struct PatchPoints {
  std::vector<std::vector<std::size_t>> ids;
  std::map<std::pair<std::size_t, std::size_t>, std::vector<std::size_t>> split_edges;
};

template <class K>
PatchPoints place_patch_points(const Mesh<K>& mesh, const FaceCorners<K>& fc,
                               const std::vector<std::vector<std::size_t>>& faces_of,
                               const std::vector<Patch<K>>& patches, const std::vector<char>& unified,
                               std::vector<typename K::Point_3>& point_of) {
  using Id = std::size_t;
  constexpr Id none = Id(-1);
  PatchPoints out;
  out.ids.resize(patches.size());
  for (std::size_t p = 0; p < patches.size(); ++p) {
    if (!unified[p]) continue;
    const Patch<K>& patch = patches[p];
    auto& ids = out.ids[p];
    std::map<typename K::Point_3, Id, PointLess> here;
    for (std::size_t g : faces_of[p])
      for (auto v : fc.corners[g]) here.emplace(mesh.point(v), std::size_t(v));
    ids.assign(patch.points.size(), none);
    for (const auto& t : patch.triangles)
      for (std::size_t i : t) {
        if (ids[i] != none) continue;
        const auto it = here.find(patch.points[i]);
        ids[i] = it != here.end() ? it->second : point_of.size();
        if (it == here.end()) point_of.push_back(patch.points[i]);
      }
    for (const auto& [segment, chain] : patch.split_chains()) {
      const Id s = ids[segment.first], t = ids[segment.second];
      std::vector<Id> points;
      for (std::size_t i : chain) points.push_back(ids[i]);
      if (s > t) std::reverse(points.begin(), points.end());
      out.split_edges[{std::min(s, t), std::max(s, t)}] = points;
    }
  }
  return out;
}

/// A mesh rebuilt by `rebuilt`, and where the points went.
template <class K> struct Rebuilt {
  using V = typename Mesh<K>::Vertex_index;
  Mesh<K> mesh;
  std::vector<V> vertex_of_old;                 ///< per vertex of the mesh given; null: dropped
  std::vector<std::vector<V>> vertex_of_point;  ///< per unified patch, per point; null: not a vertex here
};

/// The mesh with the faces of the unified patches replaced (see the header): its vertices that
/// some face still uses, in order, then the patches' new points; faces in order, each patch's
/// triangles where its first face was, a face beyond a split border edge cut at the split points.
template <class K>
Rebuilt<K> rebuilt(const Mesh<K>& mesh, const FaceCorners<K>& fc, const std::vector<long>& patch_of_face,
                   const std::vector<Patch<K>>& patches, const std::vector<char>& unified) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  using Id = std::size_t;  // a vertex of `mesh`, or (from its number of vertices on) a new point
  constexpr Id none = Id(-1);
  std::vector<typename K::Point_3> point_of;
  for (V v : mesh.vertices()) point_of.push_back(mesh.point(v));
  const std::size_t n = point_of.size();
  // Not structured bindings: C++17 lambdas cannot capture those (Clang refuses).
  const auto source_map = mesh.template property_map<F, std::uint32_t>(source_face_property);
  const auto new_map = mesh.template property_map<F, bool>(new_face_property);
  const auto frozen_map = mesh.template property_map<F, bool>(frozen_face_property);
  const auto shared_map = mesh.template property_map<F, bool>(shared_face_property);
  const auto reason_map = mesh.template property_map<F, std::uint8_t>(shared_reason_property);
  const auto& source = source_map.first;
  const auto& is_new = new_map.first;
  const auto& frozen = frozen_map.first;
  const bool has_source = source_map.second, has_new = new_map.second, has_frozen = frozen_map.second;
  std::vector<std::vector<std::size_t>> faces_of(patches.size());
  for (auto f : mesh.faces()) {
    const long p = patch_of_face[std::size_t(f)];
    if (p >= 0 && unified[std::size_t(p)]) faces_of[std::size_t(p)].push_back(std::size_t(f));
  }
  const PatchPoints placed = place_patch_points<K>(mesh, fc, faces_of, patches, unified, point_of);
  const auto& ids = placed.ids;
  const auto& split_edges = placed.split_edges;
  std::vector<std::array<Id, 3>> triangles;
  std::vector<std::uint32_t> from;
  std::vector<char> added, shared, frozen_mark;
  std::vector<std::uint8_t> reason;
  auto emit = [&](const std::array<Id, 3>& t, std::uint32_t source_face, bool is_added, bool is_shared, bool is_frozen,
                  std::uint8_t why = 0) {
    reason.push_back(why);
    triangles.push_back(t);
    from.push_back(source_face);
    added.push_back(is_added);
    shared.push_back(is_shared);
    frozen_mark.push_back(is_frozen);
  };
  std::vector<char> emitted(patches.size(), 0);
  for (auto f : mesh.faces()) {
    const long pi = patch_of_face[std::size_t(f)];
    const std::uint32_t own_source = has_source ? source[f] : std::uint32_t(std::size_t(f));
    if (pi < 0 || !unified[std::size_t(pi)]) {
      const auto& c = fc.corners[std::size_t(f)];
      std::vector<Id> polygon;  // the corners, with the points of split edges between them
      for (int k = 0; k < 3; ++k) {
        const Id s = std::size_t(c[std::size_t(k)]), t = std::size_t(c[std::size_t((k + 1) % 3)]);
        polygon.push_back(s);
        if (split_edges.empty()) continue;
        const auto it = split_edges.find({std::min(s, t), std::max(s, t)});
        if (it == split_edges.end()) continue;
        if (s < t)
          polygon.insert(polygon.end(), it->second.begin(), it->second.end());
        else
          polygon.insert(polygon.end(), it->second.rbegin(), it->second.rend());
      }
      const bool keeps = has_new && is_new[f], stays_frozen = has_frozen && frozen[f];
      // (shared with a third mesh already: kept so, never cut, see collect)
      const bool stays_shared = shared_map.second && shared_map.first[f];
      if (polygon.size() == 3)
        emit({polygon[0], polygon[1], polygon[2]}, own_source, keeps, stays_shared, stays_frozen,
             stays_shared && reason_map.second ? reason_map.first[f] : std::uint8_t(0));
      else
        for (const auto& t : ear_cut<K>(polygon, point_of)) emit(t, own_source, true, false, stays_frozen);
      continue;
    }
    const std::size_t p = std::size_t(pi);
    if (emitted[p]) continue;
    emitted[p] = 1;
    emit_patch(patches[p], ids[p], faces_of[p], fc,
               [&](const std::array<Id, 3>& t, std::size_t origin, bool unchanged, std::uint8_t why) {
                 const F g(static_cast<typename F::size_type>(origin));
                 emit(t, has_source ? source[g] : std::uint32_t(origin), !unchanged || (has_new && is_new[g]), true,
                      false, why);
               });
  }
  // The points some triangle uses, in order, as the vertices of the result.
  std::vector<char> used(point_of.size(), 0);
  for (const auto& t : triangles)
    for (Id i : t) used[i] = 1;
  Rebuilt<K> out;
  std::vector<V> vertex(point_of.size());
  out.vertex_of_old.assign(n, V());
  for (Id i = 0; i < point_of.size(); ++i) {
    const bool isolated_before = i < n && mesh.is_isolated(V(static_cast<typename V::size_type>(i)));
    if (!used[i] && !isolated_before) continue;  // a point of this mesh only, inside a patch
    vertex[i] = out.mesh.add_vertex(point_of[i]);
    if (i < n) out.vertex_of_old[i] = vertex[i];
  }
  out.vertex_of_point.resize(patches.size());
  for (std::size_t p = 0; p < patches.size(); ++p)
    for (Id i : ids[p]) out.vertex_of_point[p].push_back(i == none ? V() : vertex[i]);
  std::vector<std::array<V, 3>> faces;
  for (const auto& t : triangles) faces.push_back({vertex[t[0]], vertex[t[1]], vertex[t[2]]});
  if (const std::size_t t = add_triangles<K>(out.mesh, faces); t != faces.size())
    throw InternalError("flat contacts: the common triangulation of a contact does not fit into the mesh (" +
                        misfit_cause(triangles, shared, t) + ")");
  auto out_source = out.mesh.template add_property_map<F, std::uint32_t>(source_face_property, 0).first;
  auto out_new = out.mesh.template add_property_map<F, bool>(new_face_property, false).first;
  auto out_shared = out.mesh.template add_property_map<F, bool>(shared_face_property, false).first;
  auto out_reason = out.mesh.template add_property_map<F, std::uint8_t>(shared_reason_property, 0).first;
  const bool any_frozen = std::any_of(frozen_mark.begin(), frozen_mark.end(), [](char c) { return c != 0; });
  std::optional<typename M::template Property_map<F, bool>> out_frozen;
  if (any_frozen) out_frozen = out.mesh.template add_property_map<F, bool>(frozen_face_property, false).first;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const F f(static_cast<typename F::size_type>(i));
    out_source[f] = from[i];
    out_new[f] = added[i] != 0;
    out_shared[f] = shared[i] != 0;
    out_reason[f] = reason[i];
    if (out_frozen) (*out_frozen)[f] = frozen_mark[i] != 0;
  }
  return out;
}

/// The steps of unify_flat_contacts on one pair of meshes, each a method.
template <class K> class FlatContactUnifier {
 public:
  using M = Mesh<K>;
  using Point = typename K::Point_3;

  using V = typename M::Vertex_index;

  FlatContactUnifier(M& a, M& b, ContactCurves<K> curves, const FlatContactOptions& options, OtherCurveVertices<K> others)
      : a_(a),
        b_(b),
        ca_(a),
        cb_(b),
        na_(ca_.corners.size()),
        nb_(cb_.corners.size()),
        curves_(curves),
        options_(options),
        others_(std::move(others)) {
    auto add_segments = [](const std::vector<V>& curve, std::set<std::pair<V, V>>& segments) {
      for (std::size_t k = 0; k + 1 < curve.size(); ++k)
        segments.emplace(std::min(curve[k], curve[k + 1]), std::max(curve[k], curve[k + 1]));
    };
    for (const auto& curve : curves.vertices_a) add_segments(curve, curve_segments_a_);
    for (const auto& curve : curves.vertices_b) add_segments(curve, curve_segments_b_);
    for (const auto* list : others_.a) add_segments(*list, other_segments_a_);
    for (const auto* list : others_.b) add_segments(*list, other_segments_b_);
  }

  FlatContactStats run() {
    FlatContactStats stats;
    const auto confirmed = coplanar_overlapping_pairs();
    if (confirmed.empty()) return stats;
    group_into_patches();
    collect(a_, ca_, patch_of_a_, true);
    collect(b_, cb_, patch_of_b_, false);
    const std::vector<char> unified = triangulate_patches(stats);
    if (stats.patches == 0) return stats;
    for (std::size_t f = 0; f < na_; ++f)
      stats.faces_replaced_a += patch_of_a_[f] >= 0 && unified[std::size_t(patch_of_a_[f])];
    for (std::size_t f = 0; f < nb_; ++f)
      stats.faces_replaced_b += patch_of_b_[f] >= 0 && unified[std::size_t(patch_of_b_[f])];
    // 5. Both meshes rebuilt with the common triangulations; the curves follow.
    Rebuilt<K> a2 = rebuilt<K>(a_, ca_, patch_of_a_, patches_, unified);
    Rebuilt<K> b2 = rebuilt<K>(b_, cb_, patch_of_b_, patches_, unified);
    const std::size_t new_points = stats.steiner_points + stats.border_splits;
    stats.points_dropped = (a_.number_of_vertices() + new_points - a2.mesh.number_of_vertices()) +
                           (b_.number_of_vertices() + new_points - b2.mesh.number_of_vertices());
    ContactCurvesData updated = updated_curves(a2, b2, unified);
    auto others_a = renumbered(others_.a, a2), others_b = renumbered(others_.b, b2);
    // Nothing was changed before this point (an InternalError above leaves all as it was).
    a_ = std::move(a2.mesh);
    b_ = std::move(b2.mesh);
    for (std::size_t i = 0; i < others_.a.size(); ++i) *others_.a[i] = std::move(others_a[i]);
    for (std::size_t i = 0; i < others_.b.size(); ++i) *others_.b[i] = std::move(others_b[i]);
    curves_.curves = std::move(updated.curves);
    curves_.vertices_a = std::move(updated.vertices_a);
    curves_.vertices_b = std::move(updated.vertices_b);
    return stats;
  }

 private:
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;

  static std::vector<Box> face_boxes(const M& m) {
    std::vector<Box> result;
    for (auto f : m.faces()) {
      CGAL::Bbox_3 box;
      for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) box += m.point(v).bbox();
      result.emplace_back(box, std::uint32_t(std::size_t(f)));
    }
    return result;
  }

  /// box_intersection_d's cutoff (as seam check's): ranges of fewer boxes are scanned pair by pair
  /// rather than split further (CGAL's default, 10, is slow on whole tows). The same pairs, in
  /// another order, which nothing here depends on (they are only joined into sets).
  static constexpr std::ptrdiff_t box_cutoff = 2000;

  /// 1. Face pairs of A and B that may lie in one plane and overlap there: neither certainly off
  ///    the other's plane nor certainly apart in it (certified interval arithmetic).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidate_pairs() const {
    std::vector<Box> boxes_a = face_boxes(a_), boxes_b = face_boxes(b_);
    std::vector<certified::IP> ia(a_.number_of_vertices()), ib(b_.number_of_vertices());
    for (auto v : a_.vertices()) ia[std::size_t(v)] = certified::interval_point(a_.point(v));
    for (auto v : b_.vertices()) ib[std::size_t(v)] = certified::interval_point(b_.point(v));
    std::vector<std::pair<std::uint32_t, std::uint32_t>> overlapping;
    CGAL::Protect_FPU_rounding<true> rounding;
    CGAL::box_intersection_d(boxes_a.begin(), boxes_a.end(), boxes_b.begin(), boxes_b.end(),
                             [&](const Box& x, const Box& y) {
                               const auto& s = ca_.corners[x.info()];
                               const auto& t = cb_.corners[y.info()];
                               for (int k = 0; k < 3; ++k)  // a corner of t surely off the plane of s
                                 if (certified::sure_sign(certified::orient3(
                                         ib[std::size_t(t[k])], ia[std::size_t(s[0])], ia[std::size_t(s[1])],
                                         ia[std::size_t(s[2])])) != 0)
                                   return;
                               // ... or surely apart in the plane: an edge line of one has the
                               // other on its outer side (closed), certainly.
                               const std::array<const certified::IP*, 3> ps = {&ia[std::size_t(s[0])], &ia[std::size_t(s[1])],
                                                                               &ia[std::size_t(s[2])]},
                                                                         pt = {&ib[std::size_t(t[0])], &ib[std::size_t(t[1])],
                                                                               &ib[std::size_t(t[2])]};
                               const int axis = dominant_axis(a_.point(s[0]), a_.point(s[1]), a_.point(s[2]));
                               const auto qs = ca_.points(x.info()), qt = cb_.points(y.info());
                               if (surely_apart_in_plane(qs, ps, qt, pt, axis) || surely_apart_in_plane(qt, pt, qs, ps, axis))
                                 return;
                               overlapping.emplace_back(x.info(), y.info());
                             },
                             box_cutoff);
    return overlapping;
  }

  /// 1. Face pairs of A and B in one plane that overlap with positive area (exact); marks them
  ///    contact faces, each pair in one set.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> coplanar_overlapping_pairs() {
    contact_.assign(na_ + nb_, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> confirmed;
    for (const auto& [fa, fb] : candidate_pairs()) {
      const auto s = ca_.points(fa), t = cb_.points(fb);
      bool coplanar = true;
      for (int k = 0; k < 3 && coplanar; ++k) coplanar = CGAL::coplanar(*s[0], *s[1], *s[2], *t[k]);
      if (!coplanar) continue;
      int axis = dominant_axis(*s[0], *s[1], *s[2]);
      if (projected_orientation(*s[0], *s[1], *s[2], axis) == CGAL::ZERO) continue;  // (rounded kernels)
      if (!interiors_overlap<Point>(s, t, axis)) continue;
      contact_[fa] = contact_[na_ + fb] = 1;
      sets_.join(fa, na_ + fb);
      confirmed.emplace_back(fa, fb);
    }
    return confirmed;
  }

  /// 2. Patches: contact faces joined across edges to contact faces of the same mesh in the same
  ///    plane; numbers them (patch_of_a_, patch_of_b_, count_).
  void group_into_patches() {
    auto join_neighbours = [&](const M& m, const FaceCorners<K>& fc, std::size_t offset) {
      for (auto f : m.faces()) {
        if (!contact_[offset + std::size_t(f)]) continue;
        for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
          const auto g = m.face(m.opposite(h));
          if (g == M::null_face() || !contact_[offset + std::size_t(g)]) continue;
          const auto s = fc.points(std::size_t(f));
          if (CGAL::coplanar(*s[0], *s[1], *s[2], m.point(m.target(m.next(m.opposite(h))))))
            sets_.join(offset + std::size_t(f), offset + std::size_t(g));
        }
      }
    };
    join_neighbours(a_, ca_, 0);
    join_neighbours(b_, cb_, na_);
    std::map<std::size_t, std::size_t> patch_index;  // set root -> patch
    patch_of_a_.assign(na_, -1);
    patch_of_b_.assign(nb_, -1);
    for (std::size_t n = 0; n < na_ + nb_; ++n) {
      if (!contact_[n]) continue;
      const auto [it, inserted] = patch_index.emplace(sets_.find(n), patch_index.size());
      (n < na_ ? patch_of_a_[n] : patch_of_b_[n - na_]) = long(it->second);
    }
    count_ = patch_index.size();
    patches_.assign(count_, Patch<K>());
    index_.assign(count_, {});
    edges_a_.assign(count_, {});
    edges_b_.assign(count_, {});
    border_b_.assign(count_, {});
    not_curve_.assign(count_, {});
    other_a_.assign(count_, {});
    other_b_.assign(count_, {});
    fixed_.assign(count_, {});
    area_.assign(count_, 0.0);
    axis_set_.assign(count_, 0);
  }

  /// 3. Per patch: the points, the border of each mesh's faces (must agree), the edges of each,
  ///    the area of A's faces (doubles).
  void collect(const M& m, const FaceCorners<K>& fc, const std::vector<long>& patch_of, bool is_a) {
    const auto [frozen, has_frozen] = m.template property_map<typename M::Face_index, bool>(frozen_face_property);
    const auto [shared, has_shared] = m.template property_map<typename M::Face_index, bool>(shared_face_property);
    for (auto f : m.faces()) {
      const long pi = patch_of[std::size_t(f)];
      if (pi < 0) continue;
      const std::size_t p = std::size_t(pi);
      const auto s = fc.points(std::size_t(f));
      if (!axis_set_[p]) {
        patches_[p].axis = dominant_axis(*s[0], *s[1], *s[2]);
        axis_set_[p] = 1;
      }
      std::array<std::size_t, 3> id;
      Patch<K>& patch = patches_[p];
      for (int k = 0; k < 3; ++k) {
        const auto [it, inserted] = index_[p].emplace(*s[k], patch.points.size());
        if (inserted) {
          patch.points.push_back(*s[k]);
          patch.in_a.push_back(0);
          patch.in_b.push_back(0);
        }
        id[k] = it->second;
        (is_a ? patch.in_a : patch.in_b)[id[k]] = 1;
      }
      if (is_a) area_[p] += projected_area(*s[0], *s[1], *s[2], patches_[p].axis);
      int k = 0;
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        // halfedges_around_face starts at m.halfedge(f): source(h) is corner k
        const std::pair<std::size_t, std::size_t> e = {std::min(id[k], id[(k + 1) % 3]), std::max(id[k], id[(k + 1) % 3])};
        ++k;
        (is_a ? edges_a_ : edges_b_)[p].insert(e);
        const V s = m.source(h), t = m.target(h);
        if (!(is_a ? curve_segments_a_ : curve_segments_b_).count({std::min(s, t), std::max(s, t)}))
          not_curve_[p].insert(e);
        if ((is_a ? other_segments_a_ : other_segments_b_).count({std::min(s, t), std::max(s, t)}))
          (is_a ? other_a_ : other_b_)[p].insert(e);
        const auto g = m.face(m.opposite(h));
        if (g == M::null_face() || patch_of[std::size_t(g)] != pi) {
          (is_a ? patches_[p].border : border_b_[p]).insert(e);
          // The face beyond may be split with the edge: in no patch, not frozen, not shared with a
          // third mesh.
          if (g != M::null_face() &&
              (patch_of[std::size_t(g)] >= 0 || (has_frozen && frozen[g]) || (has_shared && shared[g])))
            fixed_[p].insert(e);
        }
      }
    }
  }

  /// The vertex lists of other curves, renumbered into the rebuilt mesh (copies). A dropped vertex,
  /// or a segment no longer an edge (split or triangulated over by the contact), is an
  /// InternalError: those curves would no longer be embedded.
  static std::vector<std::vector<V>> renumbered(const std::vector<std::vector<V>*>& lists, const Rebuilt<K>& rebuilt) {
    const auto& map = rebuilt.vertex_of_old;
    std::vector<std::vector<V>> out;
    for (const auto* list : lists) {
      out.emplace_back();
      for (const V v : *list) {
        if (std::size_t(v) >= map.size() || map[std::size_t(v)] == V())
          throw InternalError("flat contacts: a vertex of another curve of the mesh was dropped");
        const V w = map[std::size_t(v)];
        if (!out.back().empty() && rebuilt.mesh.halfedge(out.back().back(), w) == M::null_halfedge())
          throw InternalError("flat contacts: a segment of another curve of the mesh is no longer an edge");
        out.back().push_back(w);
      }
    }
    return out;
  }

  struct ContactCurvesData {
    std::vector<Polyline<K>> curves;
    std::vector<std::vector<V>> vertices_a, vertices_b;
  };

  /// The curves after the rebuild: vertices renumbered, the split points inserted (in both).
  ContactCurvesData updated_curves(const Rebuilt<K>& ra, const Rebuilt<K>& rb, const std::vector<char>& unified) const {
    ContactCurvesData out{curves_.curves, curves_.vertices_a, curves_.vertices_b};
    auto renumber = [](std::vector<std::vector<V>>& curves, const std::vector<V>& map) {
      for (auto& curve : curves)
        for (auto& v : curve) {
          if (std::size_t(v) >= map.size() || map[std::size_t(v)] == V())
            throw InternalError("flat contacts: a curve vertex was dropped");
          v = map[std::size_t(v)];
        }
    };
    renumber(out.vertices_a, ra.vertex_of_old);
    renumber(out.vertices_b, rb.vertex_of_old);
    // Each split segment by its vertices in A: its patch, its ends in A and B, its split points.
    struct Chain {
      std::size_t patch;
      std::array<V, 2> a, b;
      std::vector<std::size_t> points;
    };
    std::map<std::pair<V, V>, Chain> chains;
    for (std::size_t p = 0; p < count_; ++p) {
      if (!unified[p]) continue;
      const auto& in_a = ra.vertex_of_point[p];
      const auto& in_b = rb.vertex_of_point[p];
      for (auto& [segment, points] : patches_[p].split_chains()) {
        const std::array<V, 2> a = {in_a[segment.first], in_a[segment.second]};
        chains[{std::min(a[0], a[1]), std::max(a[0], a[1])}] = {
            p, a, {in_b[segment.first], in_b[segment.second]}, std::move(points)};
      }
    }
    if (chains.empty()) return out;
    for (std::size_t c = 0; c < out.curves.size(); ++c) {
      const auto& points = out.curves[c];
      const auto& va = out.vertices_a[c];
      const auto& vb = out.vertices_b[c];
      Polyline<K> new_points;
      std::vector<V> new_va, new_vb;
      for (std::size_t k = 0; k < points.size(); ++k) {
        new_points.push_back(points[k]);
        new_va.push_back(va[k]);
        new_vb.push_back(vb[k]);
        if (k + 1 == points.size()) break;
        const auto it = chains.find({std::min(va[k], va[k + 1]), std::max(va[k], va[k + 1])});
        if (it == chains.end()) continue;
        const Chain& chain = it->second;
        const bool forward = va[k] == chain.a[0];
        if (vb[k] != chain.b[forward ? 0 : 1] || vb[k + 1] != chain.b[forward ? 1 : 0])
          throw InternalError("flat contacts: a split curve segment is not the same segment in both meshes");
        const Patch<K>& patch = patches_[chain.patch];
        for (std::size_t j = 0; j < chain.points.size(); ++j) {
          const std::size_t i = chain.points[forward ? j : chain.points.size() - 1 - j];
          new_points.push_back(patch.points[i]);
          new_va.push_back(ra.vertex_of_point[chain.patch][i]);
          new_vb.push_back(rb.vertex_of_point[chain.patch][i]);
        }
      }
      out.curves[c] = std::move(new_points);
      out.vertices_a[c] = std::move(new_va);
      out.vertices_b[c] = std::move(new_vb);
    }
    return out;
  }

  /// 4. Triangulates each patch whose borders agree; per patch, whether it was.
  std::vector<char> triangulate_patches(FlatContactStats& stats) {
    std::vector<char> unified(count_, 0);
    for (std::size_t p = 0; p < count_; ++p) {
      std::string why;
      if (patches_[p].border != border_b_[p]) {
        why = say("its border in A (", patches_[p].border.size(), " edges) is not its border in B (",
                  border_b_[p].size(), " edges): the curves do not bound it in both");
      } else {
        // Constraints: the border, and the curve segments inside (edges of both meshes).
        Patch<K>& patch = patches_[p];
        for (const auto& e : edges_a_[p]) {
          if (!edges_b_[p].count(e)) continue;
          const bool curve = !not_curve_[p].count(e);
          // A segment of other curves both meshes hold (a third tow's curves with each, where
          // it crosses the contact) is kept as it is: a constraint never split.
          const bool other_curve = other_a_[p].count(e) && other_b_[p].count(e);
          if (curve || other_curve || patch.border.count(e)) patch.constraints.push_back(e);
          if (curve && !fixed_[p].count(e)) patch.splittable.insert(e);
        }
        for (const auto& e : patch.border)
          if (!edges_b_[p].count(e)) why = "a border edge is not an edge of both";
        if (why.empty() && triangulate<K>(patch, area_[p], options_, why)) unified[p] = 1;
      }
      if (unified[p]) {
        ++stats.patches;
        stats.shared_faces += patches_[p].triangles.size();
        stats.steiner_points += patches_[p].steiner_points;
        stats.border_splits += patches_[p].splits.size();
        stats.shared_faces_below_bound += patches_[p].below_bound;
      } else if (stats.patches_left++ == 0) {
        const auto q = to_filtered(patches_[p].points.front());
        stats.first_left = say("the flat contact at (", q.x(), ", ", q.y(), ", ", q.z(), ") was left as it was: ", why);
      }
    }
    return unified;
  }

  M& a_;
  M& b_;
  const FaceCorners<K> ca_, cb_;
  const std::size_t na_, nb_;
  ContactCurves<K> curves_;
  const FlatContactOptions options_;
  const OtherCurveVertices<K> others_;
  std::set<std::pair<V, V>> curve_segments_a_, curve_segments_b_;  ///< (smaller vertex first)
  std::set<std::pair<V, V>> other_segments_a_, other_segments_b_;  ///< of `others_`, alike
  std::vector<char> contact_;  ///< per face of A, then of B: in a flat contact
  DisjointSets sets_{na_ + nb_};
  std::vector<long> patch_of_a_, patch_of_b_;
  std::size_t count_ = 0;
  std::vector<Patch<K>> patches_;
  std::vector<std::map<Point, std::size_t, PointLess>> index_;
  std::vector<std::set<std::pair<std::size_t, std::size_t>>> edges_a_, edges_b_, border_b_;
  /// Per patch: its edges that are no curve segment in A or in B; its border edges whose face
  /// beyond (in A or in B) may not be split (another patch's, or frozen).
  std::vector<std::set<std::pair<std::size_t, std::size_t>>> not_curve_, fixed_;
  /// Per patch: its edges that are segments of `others_` in A, in B (point ids).
  std::vector<std::set<std::pair<std::size_t, std::size_t>>> other_a_, other_b_;
  std::vector<double> area_;
  std::vector<char> axis_set_;
};

}  // namespace

template <class K>
FlatContactStats unify_flat_contacts(Mesh<K>& a, Mesh<K>& b, ContactCurves<K> curves, const FlatContactOptions& options,
                                     OtherCurveVertices<K> others) {
  if (a.has_garbage() || b.has_garbage()) throw InternalError("flat contacts: a mesh has garbage");
  if (curves.vertices_a.size() != curves.curves.size() || curves.vertices_b.size() != curves.curves.size())
    throw InternalError("flat contacts: the curves' vertices do not match the curves");
  try {
    return FlatContactUnifier<K>(a, b, curves, options, others).run();
  } catch (const InternalError& e) {
    if (!(options.min_angle_deg > 0)) throw;
    // The refined triangulations did not fit (nothing was changed): the plain ones.
    FlatContactOptions plain = options;
    plain.min_angle_deg = 0;
    FlatContactStats stats = FlatContactUnifier<K>(a, b, curves, plain, others).run();
    stats.refinement_failed = e.what();
    return stats;
  }
}

template FlatContactStats unify_flat_contacts<Exact>(Mesh<Exact>&, Mesh<Exact>&, ContactCurves<Exact>,
                                                        const FlatContactOptions&, OtherCurveVertices<Exact>);
template FlatContactStats unify_flat_contacts<Filtered>(Mesh<Filtered>&, Mesh<Filtered>&, ContactCurves<Filtered>,
                                                        const FlatContactOptions&, OtherCurveVertices<Filtered>);
template FlatContactStats unify_flat_contacts<Float>(Mesh<Float>&, Mesh<Float>&, ContactCurves<Float>,
                                                        const FlatContactOptions&, OtherCurveVertices<Float>);

}  // namespace seam::internal
