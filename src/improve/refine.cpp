// seam: the quality stage's refinement (see seam/improve.h for the algorithm, its bound and why
// it ends).
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/errors.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/improve_state.h>
#include <seam/quality.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <tuple>

namespace seam::internal {

namespace {

using FP = Filtered::Point_3;
using FV = Filtered::Vector_3;

/// What an attempt to mend a face did: changed the meshes, or not and why.
struct Outcome {
  bool changed = false;
  ShortfallCause cause = ShortfallCause::constraint_angle;
};

ShortfallCause cause_of(Verdict v) {
  switch (v) {
    case Verdict::tolerance: return ShortfallCause::tolerance;
    case Verdict::crossing: return ShortfallCause::crossing;
    case Verdict::separation: return ShortfallCause::feature_size;
    default: return ShortfallCause::shape;
  }
}

bool finite(const FP& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

/// The angle (radians) at corner a of triangle (a, b, c), doubles.
double angle_at(const FP& a, const FP& b, const FP& c) {
  const FV u = b - a, v = c - a;
  return std::atan2(std::sqrt(CGAL::cross_product(u, v).squared_length()), u * v);
}

template <class K> class Refiner {
 public:
  using S = ImproveState<K>;
  using M = typename S::M;
  using V = typename S::V;
  using H = typename S::H;
  using F = typename S::F;
  using Point = typename S::Point;

  explicit Refiner(S& s) : s_(s) {}

  void flip_all();
  void refine();
  void close_curve_points();
  std::size_t close_curve_points_pass(double separation, bool consecutive);
  bool flip_to_join(std::size_t m, V u, V w);
  F face_beyond(std::size_t m, V u, V w) const;

 private:
  S& s_;
  struct Item {
    double angle;
    std::size_t mesh;
    F face;
    std::uint32_t version;
    bool operator<(const Item& o) const { return angle > o.angle; }  // smallest angle first
  };
  std::priority_queue<Item> queue_;
  std::vector<std::tuple<std::size_t, V, V>> encroached_;  ///< constraint edges to split first
  std::uint8_t mending_reach_ = 0;  ///< the reach (MeshState::reach) of the face being mended
  bool is_encroached(std::size_t m, H h) const;
  void push_encroached(std::size_t m, F f);

  double angle(std::size_t m, F f) const { return face_min_angle<K>(s_, m, f); }
  /// The angle a face of the band is refined to: the bound within the input faces the band
  /// reached in at most the mesh's bound_reach steps from the band at the start. Farther, and
  /// everywhere with no tolerance (the input's edges are then creases, constraints), an input
  /// face's own small angle bounds the faces made from it, which are held to that instead: a face
  /// below the bound is mended only by splitting its edges, which changes the faces beyond, and
  /// where those are below it in the input too (an anisotropic mesh) each step needs the next.
  double angle_bound(std::size_t m, F f) const {
    return s_.tolerance > 0 && s_.meshes[m].reach_of(f) <= s_.meshes[m].bound_reach ? s_.options.min_angle_deg
                                                                                         : s_.target_angle(m, f);
  }
  /// A face held to ImproveOptions::max_area (MeshState::area_bounded) and larger.
  bool too_large(std::size_t m, F f) const {
    return s_.options.max_area > 0 && s_.meshes[m].area_bounded(f) && s_.face_area(m, f) > s_.options.max_area;
  }
  void push_if_bad(std::size_t m, F f);
  void push_made(const Applied<K>& made) {
    for (const auto& [m, f] : made.faces) push_if_bad(m, f), push_encroached(m, f);
  }
  /// Makes the edit if the predicate accepts it; otherwise returns the refusal.
  std::optional<Verdict> attempt(const Edit<K>& edit, Applied<K>* made = nullptr);
  std::vector<F> star(std::size_t m, V v) const {
    std::vector<F> faces;
    for (auto f : CGAL::faces_around_target(s_.mesh(m).halfedge(v), s_.mesh(m)))
      if (f != M::null_face()) faces.push_back(f);
    return faces;
  }
  EditCorner<K> corner(std::size_t m, V v) const { return {v, false, s_.mesh(m).point(v)}; }

  bool try_flip(std::size_t m, H h, Applied<K>* made = nullptr);
  void legalize(std::size_t m, V x);
  Outcome mend(std::size_t m, F f);
  /// Merges x into y or y into x, whichever leaves the better smallest angle (and above
  /// `must_beat` degrees, where that is given), if the predicate accepts it.
  std::optional<Outcome> merge_short_edge(std::size_t m, V x, V y, double must_beat = -1);
  bool merge_plan(std::size_t m, V u, V w, Edit<K>& edit) const;
  Outcome split_constraint(std::size_t m, H h);
  /// A constraint split_constraint would split (a curve segment, the mesh's border) shorter than
  /// twice the feature size at its middle (doubles): refused for the feature size. The band's
  /// border is never too short: the face beyond joins the band, nothing is split.
  bool too_short_to_split(std::size_t m, H h) const {
    if (band_border(m, h)) return false;
    const M& g = s_.mesh(m);
    const FP a = s_.fpoint(m, g.source(h)), b = s_.fpoint(m, g.target(h));
    return std::sqrt(CGAL::squared_distance(a, b)) < 2 * s_.feature_size_at(CGAL::midpoint(a, b));
  }
  /// The constraint of h is the band's border, no curve segment: a face beyond it, not in the band.
  bool band_border(std::size_t m, H h) const {
    const M& g = s_.mesh(m);
    if (!s_.face_in_band(m, g.face(h))) h = g.opposite(h);
    const F beyond = g.face(g.opposite(h));
    return beyond != M::null_face() && !s_.face_in_band(m, beyond) && !s_.is_curve_edge(m, g.source(h), g.target(h));
  }
  bool border_fixed(std::size_t m, H h) const;
  Outcome insert_circumcenter(std::size_t m, F f);
  bool walk(std::size_t m, F f, FP target, F& landed, FP& at, H& crossed) const;
  Outcome insert_at(std::size_t m, F g, const FP& at);
  std::vector<F> flip_cavity(std::size_t m, std::vector<F> region, const FP& x, std::size_t& flips) const;
  bool attempt_with_flips(const Edit<K>& edit, const std::vector<std::pair<V, V>>& split, Applied<K>& made);
};

template <class K> void Refiner<K>::push_if_bad(std::size_t m, F f) {
  const auto& ms = s_.meshes[m];
  if (!ms.band[f]) return;
  const double a = angle(m, f);
  if (a < angle_bound(m, f) || too_large(m, f)) queue_.push({a, m, f, ms.version[f]});
}

template <class K> std::optional<Verdict> Refiner<K>::attempt(const Edit<K>& edit, Applied<K>* made) {
  const Verdict v = accept_edit<K>(s_, edit);
  if (v != Verdict::accepted) return v;
  Applied<K> applied = apply_edit<K>(s_, edit);
  push_made(applied);
  if (made) *made = std::move(applied);
  return std::nullopt;
}

/// Flips the edge of h where that raises the smaller of the two faces' smallest angles, the
/// predicate permitting (a flip inside one plane keeps the surface).
template <class K> bool Refiner<K>::try_flip(std::size_t m, H h, Applied<K>* made) {
  const M& g = s_.mesh(m);
  if (g.is_removed(g.edge(h)) || g.is_border(g.edge(h))) return false;
  const F f0 = g.face(h), f1 = g.face(g.opposite(h));
  const V u = g.source(h), v = g.target(h), p = g.target(g.next(h)), q = g.target(g.next(g.opposite(h)));
  // Both faces in the band first (is_constraint asks it too): flip_all offers every edge of both
  // meshes, most of them outside the band, and their angles need not be computed.
  if (!s_.face_in_band(m, f0) || !s_.face_in_band(m, f1)) return false;
  if (p == q || g.halfedge(p, q) != M::null_halfedge()) return false;
  const FP fu = s_.fpoint(m, u), fv = s_.fpoint(m, v), fp = s_.fpoint(m, p), fq = s_.fpoint(m, q);
  const double before = std::min(angle(m, f0), angle(m, f1));
  const double after = std::min(min_angle_deg(fp, fu, fq), min_angle_deg(fp, fq, fv));
  // The angles first (doubles), the constraint test then (with no tolerance an exact coplanarity test).
  if (!(after > before + 1e-6) || s_.is_constraint(m, h)) return false;
  Edit<K> edit;
  edit.parts.emplace_back();
  if (!make_fan<K>(s_, m, {f0, f1}, corner(m, p), edit.parts.back())) return false;
  // Inside one plane, and convex: the two new faces cover the two old ones. Exact predicates: the
  // kernel's own under Exact (with no tolerance is_constraint found the four points coplanar
  // already), Epick's on the same doubles otherwise (the float kernel's predicates can contradict
  // each other, and coplanar_orientation's precondition then fails).
  const auto convex_in_one_plane = [](bool coplanar_known, const auto& pu, const auto& pv, const auto& pp, const auto& pq) {
    return (coplanar_known || CGAL::coplanar(pu, pv, pp, pq)) && !CGAL::collinear(pp, pq, pu) &&
           !CGAL::collinear(pu, pv, pp) && CGAL::coplanar_orientation(pp, pq, pu, pv) == CGAL::NEGATIVE &&
           CGAL::coplanar_orientation(pu, pv, pp, pq) == CGAL::NEGATIVE;
  };
  if constexpr (kernel_traits<K>::exact_constructions)
    edit.keeps_surface = convex_in_one_plane(!(s_.tolerance > 0), g.point(u), g.point(v), g.point(p), g.point(q));
  else
    edit.keeps_surface = convex_in_one_plane(false, fu, fv, fp, fq);
  if (attempt(edit, made)) return false;
  ++s_.stats.flips;
  return true;
}

template <class K> void Refiner<K>::flip_all() {
  for (std::size_t m = 0; m < s_.meshes.size(); ++m) {
    const M& g = s_.mesh(m);
    std::vector<H> todo;
    for (auto e : g.edges())
      if (!g.is_border(e)) todo.push_back(g.halfedge(e));
    // Each flip raises the sorted vector of angles; the cap only guards against rounding.
    for (std::size_t budget = 20 * todo.size() + 100; !todo.empty() && budget > 0; --budget) {
      const H h = todo.back();
      todo.pop_back();
      Applied<K> made;
      if (!try_flip(m, h, &made)) continue;
      for (const auto& made_face : made.faces)
        for (H k : CGAL::halfedges_around_face(g.halfedge(made_face.second), g)) todo.push_back(k);
    }
  }
}

/// Lawson's flips around a new vertex x: the edges opposite it, while a flip raises the angles.
template <class K> void Refiner<K>::legalize(std::size_t m, V x) {
  const M& g = s_.mesh(m);
  std::vector<H> todo;
  for (H h : CGAL::halfedges_around_target(g.halfedge(x), g))
    if (!g.is_border(h)) todo.push_back(g.next(g.next(h)));
  for (std::size_t budget = 64 + 8 * todo.size(); !todo.empty() && budget > 0; --budget) {
    const H h = todo.back();
    todo.pop_back();
    if (g.is_removed(g.edge(h)) || g.is_border(h) || g.target(g.next(h)) != x) continue;
    const V u = g.source(h), v = g.target(h), q = g.target(g.next(g.opposite(h)));
    if (!try_flip(m, h)) continue;
    for (H k : {g.halfedge(u, q), g.halfedge(q, v)})
      if (k != M::null_halfedge()) todo.push_back(k);
  }
}

/// A constraint edge is encroached when a corner of a face of the band beside it sees it at more
/// than 90 degrees (it lies inside the edge's diametral ball), and it is long enough to split.
template <class K> bool Refiner<K>::is_encroached(std::size_t m, H h) const {
  const M& g = s_.mesh(m);
  const FP a = s_.fpoint(m, g.source(h)), b = s_.fpoint(m, g.target(h));
  const double size = s_.feature_size_at(CGAL::midpoint(a, b));
  if (CGAL::squared_distance(a, b) < 4 * size * size) return false;
  for (H k : {h, g.opposite(h)}) {
    if (!s_.face_in_band(m, g.face(k))) continue;
    const FP w = s_.fpoint(m, g.target(g.next(k)));
    if ((a - w) * (b - w) < 0) return true;
  }
  return false;
}

template <class K> void Refiner<K>::push_encroached(std::size_t m, F f) {
  const M& g = s_.mesh(m);
  if (!s_.face_in_band(m, f)) return;
  for (H h : CGAL::halfedges_around_face(g.halfedge(f), g))
    if (is_encroached(m, h) && s_.is_constraint(m, h)) encroached_.emplace_back(m, g.source(h), g.target(h));
}

/// Curve points closer than options.min_separation merge where an edge joins them in every mesh
/// holding them: the merge moves faces by less than that, so it is held to that tolerance at
/// least. Where two such pairs sit side by side (a curve passing twice within 1e-17 of itself,
/// say), the fan of the first merge has a face two of whose corners are one point once written;
/// that is allowed here (Edit::coincident_corners_allowed), since the second merge may remove it
/// (if it does not, seam check refuses the output, as it would the two points).
template <class K> void Refiner<K>::close_curve_points() {
  const double separation = s_.options.min_separation;
  if (!(separation > 0)) return;
  const double tolerance = s_.tolerance;
  s_.tolerance = std::max(tolerance, 2 * separation);
  // In passes until one merges nothing, each first the pairs that are consecutive along a curve
  // (a merge of two points with a third between them can take that one's vertex with it, which
  // the predicate refuses: keeps_curve_points) and then the others: which merge of a cluster of
  // close points passes can depend on the order. Each merge removes a point, so the passes end.
  do {
    while (close_curve_points_pass(separation, true) > 0) {
    }
  } while (close_curve_points_pass(separation, false) > 0);
  s_.tolerance = tolerance;
}

/// One pass of close_curve_points over the points by x (only pairs joined by a curve segment, if
/// `consecutive`); the number of merges made.
template <class K> std::size_t Refiner<K>::close_curve_points_pass(double separation, bool consecutive) {
  std::size_t merged = 0;
  std::vector<std::pair<double, int>> by_x;
  for (std::size_t i = 0; i < s_.points.size(); ++i)
    if (!s_.points[i].removed) by_x.emplace_back(to_filtered(s_.points[i].p).x(), int(i));
  std::sort(by_x.begin(), by_x.end());
  for (std::size_t i = 0; i < by_x.size(); ++i)
    for (std::size_t j = i + 1; j < by_x.size() && by_x[j].first - by_x[i].first < separation; ++j) {
      const int u = by_x[i].second, w = by_x[j].second;
      const auto &pu = s_.points[std::size_t(u)], &pw = s_.points[std::size_t(w)];
      if (pu.removed || pw.removed || (consecutive && s_.segment_start(u, w) < 0) ||
          CGAL::squared_distance(to_filtered(pu.p), to_filtered(pw.p)) >= separation * separation)
        continue;
      Edit<K> edit;
      bool possible = true;
      for (std::size_t k = 0; k < s_.meshes.size() && possible; ++k) {
        const V uk = pu.vertex[k], wk = pw.vertex[k];
        if ((uk == M::null_vertex()) != (wk == M::null_vertex())) possible = false;
        if (uk == M::null_vertex() || !possible) continue;
        if (s_.mesh(k).is_border(uk)) {
          possible = false;
          break;
        }
        std::vector<F> region;
        if (s_.mesh(k).halfedge(uk, wk) != M::null_halfedge() || flip_to_join(k, uk, wk)) {
          region = star(k, uk);
        } else {
          // The flip alone refused (it would make the faces between two curves the same
          // triangles in both meshes, say): the flip and the merge in one edit, which takes the
          // face beyond the edge between u and w with u's star.
          const F beyond = face_beyond(k, uk, wk);
          if (beyond == M::null_face()) {
            possible = false;
            break;
          }
          region = star(k, uk);
          region.push_back(beyond);
        }
        edit.parts.emplace_back();
        possible = make_fan<K>(s_, k, region, corner(k, wk), edit.parts.back());
        if (!possible) {
          // A free vertex as close to u or w (it sits between them, say, so that the fan would
          // make an edge that is there already): it goes in the same edit, its star with u's.
          for (const V x : CGAL::vertices_around_target(s_.mesh(k).halfedge(uk), s_.mesh(k))) {
            if (!s_.is_free(k, x) || s_.meshes[k].made[x]) continue;
            const FP px = s_.fpoint(k, x);
            if (CGAL::squared_distance(px, s_.fpoint(k, uk)) >= separation * separation &&
                CGAL::squared_distance(px, s_.fpoint(k, wk)) >= separation * separation)
              continue;
            for (const F f : star(k, x))
              if (std::find(region.begin(), region.end(), f) == region.end()) region.push_back(f);
          }
          edit.parts.back() = EditPart<K>();
          possible = make_fan<K>(s_, k, region, corner(k, wk), edit.parts.back());
        }
      }
      if (!possible || edit.parts.empty()) continue;
      edit.merged_point = u;
      edit.merged_into = w;
      edit.coincident_corners_allowed = true;
      if (!attempt(edit)) ++s_.stats.merges, ++merged;
    }
  return merged;
}

/// The face of w across the edge of a face of u opposite u (one edge between them, not a curve
/// segment), or null.
template <class K> typename Refiner<K>::F Refiner<K>::face_beyond(std::size_t m, V u, V w) const {
  const M& g = s_.mesh(m);
  for (H in : CGAL::halfedges_around_target(g.halfedge(u), g)) {
    if (g.is_border(in)) continue;
    const H between = g.next(g.next(in));
    if (g.is_border(g.opposite(between)) || g.target(g.next(g.opposite(between))) != w) continue;
    if (s_.is_curve_edge(m, g.source(between), g.target(between))) return M::null_face();
    return g.face(g.opposite(between));
  }
  return M::null_face();
}

/// Joins u and w by an edge where one edge lies between them (a face (u, x, y) and across (x, y) a
/// face of w): that edge is flipped, the predicate permitting.
template <class K> bool Refiner<K>::flip_to_join(std::size_t m, V u, V w) {
  const M& g = s_.mesh(m);
  for (H in : CGAL::halfedges_around_target(g.halfedge(u), g)) {
    if (g.is_border(in)) continue;
    const H between = g.next(g.next(in));  // the edge of the face opposite u
    if (g.is_border(g.opposite(between)) || g.target(g.next(g.opposite(between))) != w) continue;
    if (s_.is_curve_edge(m, g.source(between), g.target(between))) return false;
    Edit<K> edit;
    edit.parts.emplace_back();
    if (!make_fan<K>(s_, m, {g.face(between), g.face(g.opposite(between))}, corner(m, u), edit.parts.back()))
      return false;
    if (attempt(edit)) return false;
    ++s_.stats.flips;
    return g.halfedge(u, w) != M::null_halfedge();
  }
  return false;
}

/// Ruppert's order: encroached constraints are split first, then faces below the bound mended,
/// worst first.
template <class K> void Refiner<K>::refine() {
  for (std::size_t m = 0; m < s_.meshes.size(); ++m)
    for (auto f : s_.mesh(m).faces()) push_if_bad(m, f), push_encroached(m, f);
  while (!queue_.empty() || !encroached_.empty()) {
    if (s_.insertions_left == 0) break;
    if (!encroached_.empty()) {
      const auto [m, u, v] = encroached_.back();
      encroached_.pop_back();
      const M& g = s_.mesh(m);
      if (g.is_removed(u) || g.is_removed(v)) continue;
      const H h = g.halfedge(u, v);
      if (h == M::null_halfedge() || !is_encroached(m, h) || !s_.is_constraint(m, h)) continue;
      split_constraint(m, h);
      continue;
    }
    const Item item = queue_.top();
    queue_.pop();
    const M& g = s_.mesh(item.mesh);
    if (g.is_removed(item.face) || s_.meshes[item.mesh].version[item.face] != item.version) continue;
    mending_reach_ = s_.meshes[item.mesh].reach_of(item.face);
    const Outcome out = mend(item.mesh, item.face);
    if (g.is_removed(item.face) || s_.meshes[item.mesh].version[item.face] != item.version) continue;
    if (out.changed)
      push_if_bad(item.mesh, item.face);  // still there (the band grew beside it, a constraint was split): again
    else
      s_.meshes[item.mesh].cause[item.face] = std::uint8_t(1 + int(out.cause));
  }
  // What is left when the budget ran out.
  while (!queue_.empty()) {
    const Item item = queue_.top();
    queue_.pop();
    if (!s_.mesh(item.mesh).is_removed(item.face) && s_.meshes[item.mesh].version[item.face] == item.version)
      s_.meshes[item.mesh].cause[item.face] = std::uint8_t(1 + int(ShortfallCause::budget));
  }
}

/// One step towards mending a face below the bound (seam/improve.h, steps 2a-c).
template <class K> Outcome Refiner<K>::mend(std::size_t m, F f) {
  const M& g = s_.mesh(m);
  const auto c = s_.corners(m, f);
  const std::array<FP, 3> p = {s_.fpoint(m, c[0]), s_.fpoint(m, c[1]), s_.fpoint(m, c[2])};
  // Within the angle bound, only too large: its circumcenter (steps a and the constraint test
  // below are about small angles).
  if (too_large(m, f) && angle(m, f) >= angle_bound(m, f)) return insert_circumcenter(m, f);
  // a. Edges shorter than the feature size (at their middle), shortest first: their ends merge.
  std::array<std::size_t, 3> order = {0, 1, 2};  // edge i joins corners i and i + 1
  auto length = [&](std::size_t i) { return std::sqrt(CGAL::squared_distance(p[i], p[(i + 1) % 3])); };
  auto size = [&](std::size_t i) { return s_.feature_size_at(CGAL::midpoint(p[i], p[(i + 1) % 3])); };
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return length(i) < length(j); });
  std::optional<Outcome> refused;
  for (std::size_t i : order) {
    if (length(i) >= size(i)) continue;
    if (auto out = merge_short_edge(m, c[i], c[(i + 1) % 3])) {
      if (out->changed) return *out;
      refused = out;
    }
  }
  // The smallest angle between two constraints: nothing inside the band can change it.
  std::size_t smallest = 0;
  for (std::size_t i = 1; i < 3; ++i)
    if (angle_at(p[i], p[(i + 1) % 3], p[(i + 2) % 3]) < angle_at(p[smallest], p[(smallest + 1) % 3], p[(smallest + 2) % 3]))
      smallest = i;
  H in = g.halfedge(f);  // the halfedges into and out of the smallest corner
  while (g.target(in) != c[smallest]) in = g.next(in);
  if (s_.is_constraint(m, in) && s_.is_constraint(m, g.next(in))) {
    // Between two constraints: a border the band can still move past (the face beyond joins),
    // or else the angle is forced. (Refining next to a small angle between constraints only
    // makes smaller faces there: Ruppert's cascade.)
    for (H h : {in, g.next(in)})
      if (!g.is_border(g.opposite(h)) && s_.may_join_band(m, g.face(g.opposite(h)))) return split_constraint(m, h);
    return {false, ShortfallCause::constraint_angle};
  }
  // Lawson's flip of its longest edge that is no constraint, where that raises the angles: the face
  // beyond may have joined the band, or changed, after the flips of step 0.
  for (auto i = order.rbegin(); i != order.rend(); ++i) {
    H e = g.halfedge(f);
    while (g.source(e) != c[*i]) e = g.next(e);  // from corner i to corner i + 1
    if (try_flip(m, e)) return {true, ShortfallCause::constraint_angle};  // (not across a constraint)
  }
  const Outcome out = insert_circumcenter(m, f);
  // d. Every point for it lay nearer than the feature size to a vertex: an edge of it shorter
  // than merge_reach x feature_size merges instead, shortest first, where that raises the face's
  // smallest angle (the step a edges were tried already).
  if (!out.changed && out.cause == ShortfallCause::feature_size) {
    const double now = angle(m, f);
    for (std::size_t i : order) {
      if (length(i) >= s_.options.merge_reach * size(i) || length(i) < size(i)) continue;
      if (auto merged = merge_short_edge(m, c[i], c[(i + 1) % 3], now); merged && merged->changed) return *merged;
    }
  }
  if (!out.changed && refused) return *refused;
  return out;
}

/// Whether u can merge into its neighbour w, and the edit that does it: a free u in its mesh; a
/// curve point u along a curve segment (u, w), in every mesh holding the curve, when u is an
/// inner point of one curve only, away from the band's border.
template <class K> bool Refiner<K>::merge_plan(std::size_t m, V u, V w, Edit<K>& edit) const {
  edit = Edit<K>();
  if (s_.meshes[m].made[u]) return false;  // an insertion or a split is never undone
  if (s_.is_free(m, u)) {
    edit.parts.emplace_back();
    return make_fan<K>(s_, m, star(m, u), corner(m, w), edit.parts.back());
  }
  const int pu = s_.meshes[m].point[u], pw = s_.meshes[m].point[w];
  if (s_.options.curves_fixed) return false;
  const int c = s_.curve_of_segment(pu, pw);
  if (c < 0 || !s_.holds_curve(m, c)) return false;
  const auto [nu, away] = s_.node_away_from(pu, pw);
  if (away < 0) return false;  // an end of an open curve
  int length = 1;              // a closed curve keeps three points
  for (int k = s_.nodes[std::size_t(nu)].next; k >= 0 && k != nu && length < 4; k = s_.nodes[std::size_t(k)].next) ++length;
  if (length < 4) return false;
  const auto& cp = s_.points[std::size_t(pu)];
  for (std::size_t k = 0; k < s_.meshes.size(); ++k) {
    const bool holds = s_.holds_curve(k, c);
    if (!holds && cp.vertex[k] != M::null_vertex()) return false;  // shared with another mesh
    if (!holds) continue;
    const V uk = cp.vertex[k], wk = s_.points[std::size_t(pw)].vertex[k];
    if (s_.mesh(k).is_border(uk)) return false;
    for (auto f : star(k, uk))
      if (!s_.face_in_band(k, f)) return false;
    // u must not be a point of another curve (a junction)
    int curve_links = 0;
    for (auto h : CGAL::halfedges_around_target(s_.mesh(k).halfedge(uk), s_.mesh(k)))
      if (s_.is_curve_edge(k, s_.mesh(k).source(h), uk)) ++curve_links;
    if (curve_links != 2) return false;
    edit.parts.emplace_back();
    if (!make_fan<K>(s_, k, star(k, uk), corner(k, wk), edit.parts.back())) return false;
  }
  edit.merged_point = pu;
  edit.merged_into = pw;
  return true;
}

template <class K> std::optional<Outcome> Refiner<K>::merge_short_edge(std::size_t m, V x, V y, double must_beat) {
  std::optional<Outcome> result;
  double best = must_beat < 0 ? -1 : must_beat;
  Edit<K> chosen;
  // Plans the merge of u into w and judges it; keeps it when its new faces' smallest angle is the
  // best so far. Returns the refusal, if the predicate refused it.
  auto consider = [&](V u, V w) -> std::optional<Verdict> {
    Edit<K> edit;
    if (!merge_plan(m, u, w, edit)) return std::nullopt;
    double worst = 180;
    for (const auto& part : edit.parts)
      for (const auto& a : part.added) worst = std::min(worst, min_angle_deg(a[0].p, a[1].p, a[2].p));
    if (worst <= best) return std::nullopt;  // (not chosen, whatever the predicate says)
    const Verdict v = accept_edit<K>(s_, edit);
    if (v != Verdict::accepted) return v;
    best = worst, chosen = std::move(edit);
    return std::nullopt;
  };
  for (auto [u, w] : {std::make_pair(x, y), std::make_pair(y, x)})
    if (const auto refused = consider(u, w); refused && !result) result = Outcome{false, cause_of(*refused)};
  if (best < 0 && std::sqrt(CGAL::squared_distance(s_.fpoint(m, x), s_.fpoint(m, y))) < s_.options.min_separation) {
    // Closer than the separation (a volume mesher takes them for one point) and neither merges
    // into the other (the fan would be flat: the other lies on a line of u's neighbours, say):
    // a free end is removed, its star fanned from another neighbour.
    for (const V u : {x, y}) {
      if (!s_.is_free(m, u)) continue;  // (merge_plan refuses a vertex the stage made)
      for (const V a : CGAL::vertices_around_target(s_.mesh(m).halfedge(u), s_.mesh(m)))
        if (a != x && a != y) consider(u, a);
    }
  }
  if (chosen.parts.empty()) return result;  // (none accepted, or none above must_beat)
  push_made(apply_edit<K>(s_, chosen));
  ++s_.stats.merges;
  return Outcome{true, ShortfallCause::constraint_angle};
}

/// Splits the constraint edge of h at its middle: a curve segment in every mesh holding it, the
/// band's border with the face beyond (or that face joins the band), the mesh's border alone.
template <class K> Outcome Refiner<K>::split_constraint(std::size_t m, H h) {
  const M& g = s_.mesh(m);
  if (!s_.face_in_band(m, g.face(h))) h = g.opposite(h);  // from the band's side
  const V x = g.source(h), y = g.target(h);
  if (too_short_to_split(m, h)) return {false, ShortfallCause::feature_size};
  const F beyond = g.face(g.opposite(h));
  const bool curve = s_.is_curve_edge(m, x, y);
  if (curve && s_.options.curves_fixed) return {false, ShortfallCause::constraint_angle};
  if (band_border(m, h)) {
    // The band's border: the face beyond joins the band (nothing changes in the surface), or, out
    // of reach (shared, frozen), the border stays as it is.
    if (!s_.may_join_band(m, beyond)) return {false, ShortfallCause::constraint_angle};
    s_.meshes[m].band[beyond] = true;
    // One step farther than the face it grows from: the band's face beside the edge, or, where
    // the edge lies beyond the band (a point encroaches an edge near where it lands), the face
    // being mended.
    const std::uint8_t from = s_.face_in_band(m, g.face(h)) ? s_.meshes[m].reach_of(g.face(h)) : mending_reach_;
    s_.meshes[m].set_reach(beyond, std::uint8_t(std::min<int>(from + 1, S::MeshState::no_limit)));
    ++s_.stats.faces_absorbed;
    push_if_bad(m, beyond);
    push_encroached(m, beyond);
    return {true, ShortfallCause::constraint_angle};
  }
  Edit<K> edit;
  edit.has_fresh = true;
  edit.fresh_point = CGAL::midpoint(g.point(x), g.point(y));
  make_exact(edit.fresh_point);
  edit.keeps_surface = kernel_traits<K>::exact_constructions;
  const EditCorner<K> fresh{M::null_vertex(), true, edit.fresh_point};
  std::vector<std::pair<V, V>> split_ends;  // per part
  auto faces_of = [&](std::size_t k, V a, V b, std::vector<F>& region) {
    const M& gk = s_.mesh(k);
    for (H e : {gk.halfedge(a, b), gk.halfedge(b, a)}) {
      const F f = gk.face(e);
      if (f == M::null_face()) continue;
      const auto& ms = s_.meshes[k];
      if ((ms.has_shared && ms.shared[f]) || (ms.has_frozen && ms.frozen[f])) return false;
      region.push_back(f);
    }
    return true;
  };
  if (curve) {
    const int px = s_.meshes[m].point[x], py = s_.meshes[m].point[y];
    edit.fresh_curve_point = true;
    edit.split_a = px;
    edit.split_b = py;
    // Every mesh holding a curve that runs along the segment (two curves can share it, and in a
    // textile their meshes can differ): split_curve_links gives the point to all of them.
    auto holds_segment = [&](std::size_t k) {
      for (const int n : s_.points[std::size_t(px)].nodes) {
        const auto& node = s_.nodes[std::size_t(n)];
        const bool along = (node.next >= 0 && s_.nodes[std::size_t(node.next)].point == py) ||
                           (node.prev >= 0 && s_.nodes[std::size_t(node.prev)].point == py);
        if (along && s_.holds_curve(k, node.curve)) return true;
      }
      return false;
    };
    for (std::size_t k = 0; k < s_.meshes.size(); ++k) {
      if (!holds_segment(k)) continue;
      std::vector<F> region;
      if (!faces_of(k, s_.points[std::size_t(px)].vertex[k], s_.points[std::size_t(py)].vertex[k], region))
        return {false, ShortfallCause::constraint_angle};
      edit.parts.emplace_back();
      const std::pair<V, V> ends{s_.points[std::size_t(px)].vertex[k], s_.points[std::size_t(py)].vertex[k]};
      if (!make_fan<K>(s_, k, region, fresh, edit.parts.back(), ends)) return {false, ShortfallCause::shape};
      split_ends.push_back(ends);
    }
  } else {
    std::vector<F> region;
    if (!faces_of(m, x, y, region)) return {false, ShortfallCause::constraint_angle};
    edit.parts.emplace_back();
    if (!make_fan<K>(s_, m, region, fresh, edit.parts.back(), {x, y})) return {false, ShortfallCause::shape};
    split_ends.push_back({x, y});
  }
  Applied<K> made;
  // The split and the flips around it in each mesh as one edit first (see insert_at), then the
  // split alone.
  if (!attempt_with_flips(edit, split_ends, made))
    if (const auto refused = attempt(edit, &made)) return {false, cause_of(*refused)};
  --s_.insertions_left;
  ++(curve ? s_.stats.curve_splits : s_.stats.edge_splits);
  for (std::size_t k = 0; k < edit.parts.size(); ++k) legalize(edit.parts[k].mesh, made.fresh[k]);
  return {true, ShortfallCause::constraint_angle};
}

/// Walks over the surface from face f towards `target` (in f's plane), unfolding each face into
/// the plane of the last. Stops in the face holding it (true: `landed`, `at`) or at the first
/// constraint on the way (false: `crossed`, or null when the walk is too long).
template <class K> bool Refiner<K>::walk(std::size_t m, F f, FP target, F& landed, FP& at, H& crossed) const {
  const M& g = s_.mesh(m);
  crossed = M::null_halfedge();
  F face = f;
  H entered = M::null_halfedge();
  for (int step = 0; step < 256; ++step) {
    H h = g.halfedge(face);
    std::array<H, 3> hs = {h, g.next(h), g.next(g.next(h))};  // hs[i] runs from corner i to i + 1
    std::array<FP, 3> p = {s_.fpoint(m, g.source(hs[0])), s_.fpoint(m, g.source(hs[1])), s_.fpoint(m, g.source(hs[2]))};
    const FV n = CGAL::cross_product(p[1] - p[0], p[2] - p[0]);
    const double nn = n.squared_length();
    if (!(nn > 0)) return false;
    // Barycentric coordinate of corner i: the signed area of (target, next two corners).
    std::array<double, 3> lambda;
    for (int i = 0; i < 3; ++i)
      lambda[std::size_t(i)] =
          CGAL::cross_product(p[std::size_t((i + 1) % 3)] - target, p[std::size_t((i + 2) % 3)] - target) * n / nn;
    int out = -1;
    for (int i = 0; i < 3; ++i)
      if (lambda[std::size_t(i)] < -1e-12 && (out < 0 || lambda[std::size_t(i)] < lambda[std::size_t(out)])) {
        const H e = hs[std::size_t((i + 1) % 3)];  // the edge opposite corner i
        if (e != entered) out = i;
      }
    if (out < 0) {
      landed = face;
      at = target;
      return true;
    }
    const H e = hs[std::size_t((out + 1) % 3)];
    if (s_.is_constraint(m, e)) {
      crossed = e;
      return false;
    }
    // Unfold: rotate the target about e from this face's plane into the next one's.
    const F next = g.face(g.opposite(e));
    const FP a = s_.fpoint(m, g.source(e)), b = s_.fpoint(m, g.target(e));
    const FP c = s_.fpoint(m, g.target(g.next(g.opposite(e))));
    FV along = b - a;
    if (!(along.squared_length() > 0)) return false;
    along = along / std::sqrt(along.squared_length());
    const FV n0 = n / std::sqrt(nn);
    const FV n1v = CGAL::cross_product(a - b, c - b);  // the next face's normal (a->b reversed in it)
    const double n1l = std::sqrt(n1v.squared_length());
    if (!(n1l > 0)) return false;
    const FV n1 = n1v / n1l;
    const FV rel = target - a;
    const FV across0 = CGAL::cross_product(n0, along), across1 = CGAL::cross_product(n1, along);
    target = a + (rel * along) * along + (rel * across0) * across1;
    entered = g.opposite(e);
    face = next;
  }
  return false;
}

template <class K> Outcome Refiner<K>::insert_circumcenter(std::size_t m, F f) {
  const M& g = s_.mesh(m);
  const auto c = s_.corners(m, f);
  const FP p0 = s_.fpoint(m, c[0]), p1 = s_.fpoint(m, c[1]), p2 = s_.fpoint(m, c[2]);
  if (CGAL::collinear(p0, p1, p2)) return {false, ShortfallCause::shape};
  F landed;
  FP at;
  H crossed;
  // Üngör's off-center: on the bisector of the shortest edge, no farther from it than the apex of
  // a triangle on that edge with the bound's angle there (the circumcenter where that is nearer).
  // The same bound as the circumcenter's (and fewer points); a sliver's circumcenter lies far away.
  const std::array<FP, 3> p = {p0, p1, p2};
  std::size_t shortest = 0;  // edge i joins p[i] and p[i + 1]
  for (std::size_t i = 1; i < 3; ++i)
    if (CGAL::squared_distance(p[i], p[(i + 1) % 3]) < CGAL::squared_distance(p[shortest], p[(shortest + 1) % 3]))
      shortest = i;
  const FP mid = CGAL::midpoint(p[shortest], p[(shortest + 1) % 3]), centre = CGAL::circumcenter(p0, p1, p2);
  const double half = 0.5 * std::sqrt(CGAL::squared_distance(p[shortest], p[(shortest + 1) % 3]));
  // (With two degrees to spare: a triangle made exactly at the bound may round below it.)
  const double bound = (s_.options.min_angle_deg + 2) * M_PI / 180;
  const double reach = half / std::tan(0.5 * bound);
  const double to_centre = std::sqrt(CGAL::squared_distance(mid, centre));
  if (!(to_centre > 0)) return {false, ShortfallCause::shape};
  // Where the off-center lies beyond a constraint that cannot be split (border_fixed, or shorter
  // than twice feature_size), or encroaches one, or lands nearer than feature_size to a vertex,
  // points nearer the shortest edge on the same bisector are tried:
  // each lies inside the face's circumcircle too (so the face goes), and down to
  // half x tan(bound) from the edge the new face on it still has the bound's angles. A few fixed
  // fractions: the number of tries per face is bounded.
  Outcome blocked{false, ShortfallCause::constraint_angle};
  // (split_constraint's refusal of a constraint it cannot split: the cause it gives)
  auto block = [&](H h) {
    blocked.cause = too_short_to_split(m, h) ? ShortfallCause::feature_size : ShortfallCause::constraint_angle;
  };
  for (const double scale : {1.0, 0.7, 0.5, 0.35}) {
    const double distance = std::min(to_centre, reach) * scale;
    if (scale < 1 && distance < half * std::tan(bound)) break;
    // (the circumcenter itself where that is nearer than the off-center)
    const FP target = scale == 1 && to_centre <= reach ? centre : mid + (centre - mid) * (distance / to_centre);
    if (!finite(target)) return {false, ShortfallCause::shape};  // (a face flat in doubles)
    if (!walk(m, f, target, landed, at, crossed)) {
      if (crossed == M::null_halfedge()) return {false, ShortfallCause::shape};
      if (!border_fixed(m, crossed) && !too_short_to_split(m, crossed)) return split_constraint(m, crossed);
      block(crossed);
      continue;
    }
    // The first constraint the point encroaches (inside its diametral ball), on the face it lands
    // in and the faces around it, is split instead; if it cannot be, a nearer point is tried.
    // (Preferring another encroached constraint that can be split was measured: worse.)
    H encroached = M::null_halfedge();
    for (V v : s_.corners(m, landed))
      for (H h : CGAL::halfedges_around_target(g.halfedge(v), g)) {
        for (H e : {h, g.next(h)}) {
          if (g.is_border(e) && g.is_border(g.opposite(e))) continue;
          const H inside = g.is_border(e) ? g.opposite(e) : e;
          if (encroached != M::null_halfedge() || !s_.is_constraint(m, inside)) continue;
          const FP a = s_.fpoint(m, g.source(inside)), b = s_.fpoint(m, g.target(inside));
          if (CGAL::squared_distance(at, CGAL::midpoint(a, b)) < 0.25 * CGAL::squared_distance(a, b)) encroached = inside;
        }
      }
    if (encroached == M::null_halfedge()) {
      const Outcome out = insert_at(m, landed, at);
      if (out.changed || out.cause != ShortfallCause::feature_size) return out;
      blocked = out;
      continue;
    }
    if (!border_fixed(m, encroached) && !too_short_to_split(m, encroached)) return split_constraint(m, encroached);
    block(encroached);
  }
  return blocked;
}

/// A constraint split_constraint refuses for what lies beyond it: a border of the band whose face
/// beyond is not in the band and may not join it (shared or frozen), or a
/// curve segment that stays (ImproveOptions::curves_fixed) or has a shared or frozen face beside
/// it here (the border of a flat contact).
template <class K> bool Refiner<K>::border_fixed(std::size_t m, H h) const {
  const M& g = s_.mesh(m);
  if (!s_.face_in_band(m, g.face(h))) h = g.opposite(h);
  const F beyond = g.face(g.opposite(h));
  if (s_.is_curve_edge(m, g.source(h), g.target(h))) {
    if (s_.options.curves_fixed) return true;
    const auto& ms = s_.meshes[m];
    for (const F f : {g.face(h), beyond})
      if (f != M::null_face() && ((ms.has_shared && ms.shared[f]) || (ms.has_frozen && ms.frozen[f]))) return true;
    return false;
  }
  return band_border(m, h) && !s_.may_join_band(m, beyond);
}

/// The faces Lawson's flips around a point x would remove, x fanned over `region` (a disk: the
/// face it is inserted in, the faces beside the edge it splits): the region, and the face beyond
/// each edge flipped (try_flip's test: the flip raises the two faces' smallest angle, the edge is
/// no constraint), simulated on the mesh as it is, without the predicate. Every edge those flips
/// make ends at x, so their result is x's fan over the faces returned. `flips`: how many.
template <class K>
std::vector<typename Refiner<K>::F> Refiner<K>::flip_cavity(std::size_t m, std::vector<F> region, const FP& x,
                                                            std::size_t& flips) const {
  const M& mesh = s_.mesh(m);
  std::vector<V> border;  // the region's vertices (a flip to one of them would pinch it)
  std::vector<H> todo;    // halfedges of the region's border, from inside
  for (F f : region)
    for (H h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
      if (std::find(border.begin(), border.end(), mesh.target(h)) == border.end()) border.push_back(mesh.target(h));
      const F across = mesh.face(mesh.opposite(h));
      if (across == M::null_face() || std::find(region.begin(), region.end(), across) == region.end()) todo.push_back(h);
    }
  flips = 0;
  for (std::size_t budget = 64 + 8 * todo.size(); !todo.empty() && budget > 0; --budget) {
    const H h = todo.back();
    todo.pop_back();
    const H o = mesh.opposite(h);
    if (mesh.is_border(o)) continue;
    const V u = mesh.source(h), v = mesh.target(h), q = mesh.target(mesh.next(o));
    if (std::find(border.begin(), border.end(), q) != border.end()) continue;
    const FP fu = s_.fpoint(m, u), fv = s_.fpoint(m, v), fq = s_.fpoint(m, q);
    const double before = std::min(min_angle_deg(x, fu, fv), angle(m, mesh.face(o)));
    const double after = std::min(min_angle_deg(x, fu, fq), min_angle_deg(x, fq, fv));
    if (!(after > before + 1e-6)) continue;
    // A constraint (ImproveState::is_constraint), its crease test on the quad the flip would
    // change, the one with x: the flip moves the surface by the distance between its diagonals.
    if (!s_.face_in_band(m, mesh.face(o)) || s_.is_curve_edge(m, u, v)) continue;
    if (s_.flip_moves_surface(fu, fv, x, fq).value_or(true)) continue;
    region.push_back(mesh.face(o));
    border.push_back(q);
    ++flips;
    todo.push_back(mesh.next(o));  // (u, q)
    todo.push_back(mesh.prev(o));  // (q, v)
  }
  return region;
}

/// Makes the edit of a fresh point (an insertion, a split) together with Lawson's flips around
/// it, as one edit: each part's region grown by flip_cavity, the point fanned over it (`split`:
/// per part, the ends of the edge it splits, for make_fan). False, nothing made, where no flip
/// would be made or the predicate refuses it (the fan's faces are judged as one edit: the flips'
/// end state). With no tolerance never: flips then keep the surface only inside one plane.
template <class K>
bool Refiner<K>::attempt_with_flips(const Edit<K>& edit, const std::vector<std::pair<V, V>>& split, Applied<K>& made) {
  if (!(s_.tolerance > 0)) return false;
  const FP x = to_filtered(edit.fresh_point);
  Edit<K> grown = edit;
  grown.keeps_surface = false;
  std::size_t flips = 0;
  for (std::size_t k = 0; k < edit.parts.size(); ++k) {
    const EditPart<K>& part = edit.parts[k];
    std::size_t part_flips = 0;
    const std::vector<F> cavity = flip_cavity(part.mesh, part.removed, x, part_flips);
    if (part_flips == 0) continue;
    EditPart<K> fan;
    if (!make_fan<K>(s_, part.mesh, cavity, {M::null_vertex(), true, edit.fresh_point}, fan, split[k])) return false;
    grown.parts[k] = std::move(fan);
    flips += part_flips;
  }
  if (flips == 0 || attempt(grown, &made)) return false;
  s_.stats.flips += flips;
  return true;
}

/// Inserts a point in face g (rounded to doubles; if the predicate refuses it, exactly in g), then
/// Lawson's flips around it. The rounded point and its flips are judged first as one edit (the
/// point's fan over flip_cavity): the flips' end state, one test instead of one per flip. Where
/// the predicate refuses that, the point alone, then each flip.
template <class K> Outcome Refiner<K>::insert_at(std::size_t m, F g, const FP& at) {
  const M& mesh = s_.mesh(m);
  // Closer than the feature size (at the point) to a vertex around g: refused (the point
  // inserted in the end, on the input surface or exactly in g, is tested again).
  auto too_close = [&](const FP& q) {
    const double size = s_.feature_size_at(q), size2 = size * size;
    for (V v : s_.corners(m, g))
      for (H h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh))
        if (CGAL::squared_distance(q, s_.fpoint(m, mesh.source(h))) < size2 ||
            CGAL::squared_distance(q, s_.fpoint(m, v)) < size2)
          return true;
    return false;
  };
  if (too_close(at)) return {false, ShortfallCause::feature_size};
  const auto c = s_.corners(m, g);
  // The point is put on the input surface (rounded to doubles), where the face is farther than
  // that from it; the predicate checks the faces it makes.
  const FP on_input = s_.meshes[m].input->closest(at).first;
  if (!finite(on_input)) return {false, ShortfallCause::shape};
  const bool rounded_too_close = too_close(on_input);
  Edit<K> edit;
  edit.has_fresh = true;
  edit.fresh_point = Point(on_input.x(), on_input.y(), on_input.z());
  edit.parts.emplace_back();
  if (!make_fan<K>(s_, m, {g}, {M::null_vertex(), true, edit.fresh_point}, edit.parts.back()))
    return {false, ShortfallCause::shape};
  Applied<K> made;
  // (With no tolerance, exactly in g at once.)
  if (!rounded_too_close && attempt_with_flips(edit, {{M::null_vertex(), M::null_vertex()}}, made)) {
    --s_.insertions_left;
    ++s_.stats.insertions;
    legalize(m, made.fresh.front());
    return {true, ShortfallCause::constraint_angle};
  }
  if (auto refused = s_.tolerance > 0 && !rounded_too_close ? attempt(edit, &made)
                                                             : std::optional<Verdict>(Verdict::tolerance)) {
    // Exactly in g: barycentric coordinates (doubles) of the point, the point made from them.
    const FP p0 = s_.fpoint(m, c[0]), p1 = s_.fpoint(m, c[1]), p2 = s_.fpoint(m, c[2]);
    const FV n = CGAL::cross_product(p1 - p0, p2 - p0);
    const double nn = n.squared_length();
    double l1 = CGAL::cross_product(p2 - at, p0 - at) * n / nn, l2 = CGAL::cross_product(p0 - at, p1 - at) * n / nn;
    if (!std::isfinite(l1) || !std::isfinite(l2)) return {false, ShortfallCause::shape};
    l1 = std::clamp(l1, 1e-3, 0.998);
    l2 = std::clamp(l2, 1e-3, 1.0 - l1 - 1e-3);
    const auto& q0 = mesh.point(c[0]);
    edit.fresh_point = q0 + (mesh.point(c[1]) - q0) * typename K::FT(l1) + (mesh.point(c[2]) - q0) * typename K::FT(l2);
    make_exact(edit.fresh_point);
    if (too_close(to_filtered(edit.fresh_point))) return {false, ShortfallCause::feature_size};
    edit.keeps_surface = kernel_traits<K>::exact_constructions;
    for (auto& a : edit.parts.back().added)
      for (auto& corner : a)
        if (corner.fresh) corner.p = edit.fresh_point;
    if (auto again = attempt(edit, &made)) return {false, cause_of(*again)};
  }
  --s_.insertions_left;
  ++s_.stats.insertions;
  legalize(m, made.fresh.front());
  return {true, ShortfallCause::constraint_angle};
}

/// The faces of the band below the bound, with their causes, and the new faces of flat contacts
/// below it (after the meshes' garbage went).
template <class K> void classify(ImproveState<K>& s) {
  using F = typename Mesh<K>::Face_index;
  s.stats.min_angle_deg_after = 180;
  bool any = false;
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    const auto& ms = s.meshes[m];
    const auto [reason, has_reason] = ms.mesh->template property_map<F, std::uint8_t>(shared_reason_property);
    for (auto f : ms.mesh->faces()) {
      if (!ms.band[f]) {  // left as it is; a new face of a flat contact is counted as such
        if (ms.has_shared && ms.shared[f] && ms.is_new[f])
          if (const double a = face_min_angle<K>(s, m, f); a < s.options.min_angle_deg) {
            const std::uint8_t why = has_reason ? reason[f] : 0;
            s.stats.shortfalls.push_back({m, std::size_t(f), a, ShortfallCause::flat_contact,
                                          why ? ShortfallCause(why - 1) : ShortfallCause::flat_contact});
          }
        continue;
      }
      if (s.options.max_area > 0 && ms.area_bounded(f) && s.face_area(m, f) > s.options.max_area * (1 + 1e-9))
        ++s.stats.above_max_area_after;
      const double a = face_min_angle<K>(s, m, f);
      any = true;
      s.stats.min_angle_deg_after = std::min(s.stats.min_angle_deg_after, a);
      if (a >= s.options.min_angle_deg) continue;
      ++s.stats.below_bound_after;
      if (!ms.is_new[f]) continue;  // a face of the input, as it was
      const ShortfallCause cause = a >= s.target_angle(m, f) ? ShortfallCause::input_angle
                                   : ms.cause[f]             ? ShortfallCause(ms.cause[f] - 1)
                                                             : ShortfallCause::budget;
      s.stats.shortfalls.push_back({m, std::size_t(f), a, cause, cause});
    }
  }
  if (!any) s.stats.min_angle_deg_after = 0;
}

}  // namespace

template <class K>
ImproveStats improve(std::vector<ImproveMesh<K>>& meshes, SharedCurves<K>& curves, const ImproveOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ImproveState<K> s;
  init_state<K>(s, meshes, curves, options);
  Refiner<K> refiner(s);
  refiner.close_curve_points();
  refiner.flip_all();
  refiner.refine();
  refiner.flip_all();  // (a last pass of flips, and the faces it leaves below the bound once more)
  refiner.refine();
  finish_state<K>(s, curves);
  classify<K>(s);
  s.stats.feature_size = s.feature_size;
  measure_curve_gaps<K>(meshes, curves, s.feature_size, s.stats.shortfalls);
  drop_state_properties<K>(s);
  s.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s.stats;
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template ImproveStats improve<K>(std::vector<ImproveMesh<K>>&, SharedCurves<K>&, const ImproveOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
