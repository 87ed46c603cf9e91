// seam: flat contacts made one common triangulation. See seam/internal/flat_contacts.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/errors.h>
#include <seam/internal/certified.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/message.h>
#include <seam/internal/splice.h>

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

/// Orientation of the projection of (p, q, r) along `axis` (exact under the exact kernel).
template <class P> CGAL::Sign projected_orientation(const P& p, const P& q, const P& r, int axis) {
  const auto [u, v] = kept_coordinates(axis);
  return CGAL::sign_of_determinant(q[u] - p[u], q[v] - p[v], r[u] - p[u], r[v] - p[v]);
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
  std::vector<typename K::Point_3> points;
  std::vector<std::pair<std::size_t, std::size_t>> constraints;
  std::set<std::pair<std::size_t, std::size_t>> border;
  int axis = 2;
  /// Per point: -1, or the point it stands for (a point of B only, closer than the separation to
  /// a point of A: B's vertex moves onto that point, in the plane, rather than make a tiny edge).
  std::vector<long> alias;
  std::vector<std::array<std::size_t, 3>> triangles;  ///< the result, positively oriented in the projection
};

/// The constrained Delaunay triangulation of the patch, projected along its axis: each point's two
/// kept coordinates (exact: a projection constructs nothing), with the 3D points kept by index.
template <class K> bool triangulate(Patch<K>& patch, double expected_area, std::string& why) {
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
  using Edge = typename CDT::Edge;
  CDT cdt;
  const auto [u, v] = kept_coordinates(patch.axis);
  std::vector<typename CDT::Vertex_handle> handle(patch.points.size());
  for (std::size_t i = 0; i < patch.points.size(); ++i) {
    if (patch.alias[i] >= 0) continue;
    handle[i] = cdt.insert(typename K::Point_2(patch.points[i][u], patch.points[i][v]));
    handle[i]->info() = i;
  }
  for (std::size_t i = 0; i < patch.points.size(); ++i)
    if (patch.alias[i] < 0 && handle[i]->info() != i) {  // two points with one projection: not planar after all
      why = "two of its points project onto one";
      return false;
    }
  try {
    for (const auto& [i, j] : patch.constraints) cdt.insert_constraint(handle[i], handle[j]);
  } catch (...) {  // constraints that cross (Exact_predicates_tag constructs no intersection)
    why = "its constraints cross";
    return false;
  }
  for (const auto& [i, j] : patch.constraints) {
    FH f;
    int k;
    if (!cdt.is_edge(handle[i], handle[j], f, k)) {
      why = "a constraint passes through another of its points";
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
  double area = 0;
  for (FH f : cdt.finite_face_handles()) {
    if (f->info().nesting % 2 != 1) continue;
    std::array<std::size_t, 3> t;
    for (int i = 0; i < 3; ++i) t[i] = f->vertex(i)->info();
    patch.triangles.push_back(t);
    const auto p = to_filtered(patch.points[t[0]]), q = to_filtered(patch.points[t[1]]),
               r = to_filtered(patch.points[t[2]]);
    area += std::abs((q[u] - p[u]) * (r[v] - p[v]) - (q[v] - p[v]) * (r[u] - p[u])) / 2;
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

/// The mesh with the faces of the unified patches replaced (see the header): vertices kept in
/// order, the patches' other points appended, faces in order, each patch's triangles where its
/// first face was.
template <class K>
Mesh<K> rebuilt(const Mesh<K>& mesh, const FaceCorners<K>& fc, const std::vector<long>& patch_of_face,
                const std::vector<Patch<K>>& patches, const std::vector<char>& unified) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  M out;
  for (V v : mesh.vertices()) out.add_vertex(mesh.point(v));
  const auto [source, has_source] = mesh.template property_map<F, std::uint32_t>(source_face_property);
  const auto [is_new, has_new] = mesh.template property_map<F, bool>(new_face_property);
  const auto [frozen, has_frozen] = mesh.template property_map<F, bool>(frozen_face_property);
  // Per patch: its points as vertices of `out`, its faces here (and their source faces), the
  // orientation of those faces in the projection.
  std::vector<std::vector<V>> vertex_of(patches.size());
  std::vector<std::vector<std::size_t>> faces_of(patches.size());
  for (auto f : mesh.faces()) {
    const long p = patch_of_face[std::size_t(f)];
    if (p >= 0 && unified[std::size_t(p)]) faces_of[std::size_t(p)].push_back(std::size_t(f));
  }
  std::vector<std::array<V, 3>> triangles;
  std::vector<std::uint32_t> from;
  std::vector<char> added, shared, frozen_mark;
  std::vector<char> emitted(patches.size(), 0);
  for (auto f : mesh.faces()) {
    const long pi = patch_of_face[std::size_t(f)];
    if (pi < 0 || !unified[std::size_t(pi)]) {
      triangles.push_back(fc.corners[std::size_t(f)]);
      from.push_back(has_source ? source[f] : std::uint32_t(std::size_t(f)));
      added.push_back(has_new && is_new[f]);
      shared.push_back(0);
      frozen_mark.push_back(has_frozen && frozen[f]);
      continue;
    }
    const std::size_t p = std::size_t(pi);
    if (emitted[p]) continue;
    emitted[p] = 1;
    const Patch<K>& patch = patches[p];
    std::map<typename K::Point_3, V, PointLess> here;
    for (std::size_t g : faces_of[p])
      for (V v : fc.corners[g]) here.emplace(mesh.point(v), v);
    // A vertex at a point that stands for another moves onto it (in the plane of the patch).
    for (std::size_t i = 0; i < patch.points.size(); ++i)
      if (patch.alias[i] >= 0)
        if (const auto it = here.find(patch.points[i]); it != here.end()) {
          const auto& target = patch.points[std::size_t(patch.alias[i])];
          out.point(it->second) = target;
          here.emplace(target, it->second);
        }
    std::vector<V> vs(patch.points.size());
    for (std::size_t i = 0; i < patch.points.size(); ++i) {
      if (patch.alias[i] >= 0) continue;
      const auto it = here.find(patch.points[i]);
      vs[i] = it != here.end() ? it->second : out.add_vertex(patch.points[i]);
    }
    const auto first = fc.points(faces_of[p].front());
    const bool reverse = projected_orientation(*first[0], *first[1], *first[2], patch.axis) != CGAL::POSITIVE;
    // This mesh's faces there, by their sorted corners, and as doubles (for the source faces).
    std::map<std::array<V, 3>, std::size_t> existing;
    for (std::size_t g : faces_of[p]) {
      auto key = fc.corners[g];
      std::sort(key.begin(), key.end());
      existing.emplace(key, g);
    }
    // Not a structured binding: C++17 lambdas cannot capture those (Clang refuses).
    const auto kept = kept_coordinates(patch.axis);
    auto projected = [&](const typename K::Point_3& q) {
      const auto d = to_filtered(q);
      return std::array<double, 2>{d[kept[0]], d[kept[1]]};
    };
    for (const auto& t : patch.triangles) {
      std::array<V, 3> tri = {vs[t[0]], vs[t[1]], vs[t[2]]};
      if (reverse) std::swap(tri[1], tri[2]);
      auto key = tri;
      std::sort(key.begin(), key.end());
      std::size_t origin = faces_of[p].front();
      bool unchanged = false;
      if (const auto it = existing.find(key); it != existing.end()) {
        origin = it->second, unchanged = true;
      } else {
        // The face of this mesh holding the centroid (doubles: provenance only).
        const auto a = projected(patch.points[t[0]]), b = projected(patch.points[t[1]]),
                   c = projected(patch.points[t[2]]);
        const std::array<double, 2> m = {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3};
        double best = -HUGE_VAL;
        for (std::size_t g : faces_of[p]) {
          const auto corners = fc.points(g);
          std::array<std::array<double, 2>, 3> x = {projected(*corners[0]), projected(*corners[1]),
                                                    projected(*corners[2])};
          const double turn = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]);
          double inside = HUGE_VAL;  // the smallest signed distance-like value over the three edges
          for (int i = 0; i < 3; ++i) {
            const auto &s = x[i], &e = x[(i + 1) % 3];
            inside = std::min(inside, ((e[0] - s[0]) * (m[1] - s[1]) - (e[1] - s[1]) * (m[0] - s[0])) * (turn > 0 ? 1 : -1));
          }
          if (inside > best) best = inside, origin = g;
          if (inside >= 0) break;
        }
      }
      const F g(static_cast<typename F::size_type>(origin));
      triangles.push_back(tri);
      from.push_back(has_source ? source[g] : std::uint32_t(origin));
      added.push_back(!unchanged || (has_new && is_new[g]));
      shared.push_back(1);
      frozen_mark.push_back(0);
    }
  }
  if (const std::size_t t = add_triangles<K>(out, triangles); t != triangles.size())
    throw InternalError("flat contacts: the common triangulation of a contact does not fit into the mesh (" +
                        misfit_cause(triangles, shared, t) + ")");
  auto out_source = out.template add_property_map<F, std::uint32_t>(source_face_property, 0).first;
  auto out_new = out.template add_property_map<F, bool>(new_face_property, false).first;
  auto out_shared = out.template add_property_map<F, bool>(shared_face_property, false).first;
  const bool any_frozen = std::any_of(frozen_mark.begin(), frozen_mark.end(), [](char c) { return c != 0; });
  std::optional<typename M::template Property_map<F, bool>> out_frozen;
  if (any_frozen) out_frozen = out.template add_property_map<F, bool>(frozen_face_property, false).first;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const F f(static_cast<typename F::size_type>(i));
    out_source[f] = from[i];
    out_new[f] = added[i] != 0;
    out_shared[f] = shared[i] != 0;
    if (out_frozen) (*out_frozen)[f] = frozen_mark[i] != 0;
  }
  return out;
}

/// The steps of unify_flat_contacts on one pair of meshes, each a method.
template <class K> class FlatContactUnifier {
 public:
  using M = Mesh<K>;
  using Point = typename K::Point_3;

  FlatContactUnifier(M& a, M& b, double min_separation)
      : a_(a), b_(b), ca_(a), cb_(b), na_(ca_.corners.size()), nb_(cb_.corners.size()), min_separation_(min_separation) {}

  FlatContactStats run() {
    FlatContactStats stats;
    const auto confirmed = coplanar_overlapping_pairs();
    if (confirmed.empty()) return stats;
    group_into_patches();
    collect(a_, ca_, patch_of_a_, true);
    std::vector<std::size_t> points_of_a(count_);
    for (std::size_t p = 0; p < count_; ++p) points_of_a[p] = patches_[p].points.size();
    collect(b_, cb_, patch_of_b_, false);
    alias_close_points_of_b(points_of_a);
    const std::vector<char> unified = triangulate_patches(stats);
    if (stats.patches == 0) return stats;
    for (std::size_t f = 0; f < na_; ++f)
      stats.faces_replaced_a += patch_of_a_[f] >= 0 && unified[std::size_t(patch_of_a_[f])];
    for (std::size_t f = 0; f < nb_; ++f)
      stats.faces_replaced_b += patch_of_b_[f] >= 0 && unified[std::size_t(patch_of_b_[f])];
    // 5. Both meshes rebuilt with the common triangulations.
    M a2 = rebuilt<K>(a_, ca_, patch_of_a_, patches_, unified);
    M b2 = rebuilt<K>(b_, cb_, patch_of_b_, patches_, unified);
    a_ = std::move(a2);
    b_ = std::move(b2);
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
                             });
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
    area_.assign(count_, 0.0);
    axis_set_.assign(count_, 0);
  }

  /// 3. Per patch: the points, the border of each mesh's faces (must agree), the edges of each,
  ///    the area of A's faces (doubles).
  void collect(const M& m, const FaceCorners<K>& fc, const std::vector<long>& patch_of, bool is_a) {
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
      for (int k = 0; k < 3; ++k) {
        const auto [it, inserted] = index_[p].emplace(*s[k], patches_[p].points.size());
        if (inserted) patches_[p].points.push_back(*s[k]);
        id[k] = it->second;
      }
      if (is_a) {
        const auto [u, v] = kept_coordinates(patches_[p].axis);
        const auto x = to_filtered(*s[0]), y = to_filtered(*s[1]), z = to_filtered(*s[2]);
        area_[p] += std::abs((y[u] - x[u]) * (z[v] - x[v]) - (y[v] - x[v]) * (z[u] - x[u])) / 2;
      }
      int k = 0;
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        // halfedges_around_face starts at m.halfedge(f): source(h) is corner k
        const std::pair<std::size_t, std::size_t> e = {std::min(id[k], id[(k + 1) % 3]), std::max(id[k], id[(k + 1) % 3])};
        ++k;
        (is_a ? edges_a_ : edges_b_)[p].insert(e);
        const auto g = m.face(m.opposite(h));
        if (g == M::null_face() || patch_of[std::size_t(g)] != pi) (is_a ? patches_[p].border : border_b_[p]).insert(e);
      }
    }
  }

  /// Points of B only (inside the patch: its border is A's too) closer than min_separation to a
  /// point of A stand for that point (box test on doubles, then the distance in doubles).
  void alias_close_points_of_b(const std::vector<std::size_t>& points_of_a) {
    std::vector<std::vector<char>> used_by_b(count_);
    for (std::size_t p = 0; p < count_; ++p) used_by_b[p].assign(patches_[p].points.size(), 0);
    for (auto f : b_.faces())
      if (const long pi = patch_of_b_[std::size_t(f)]; pi >= 0)
        for (const auto* q : cb_.points(std::size_t(f))) used_by_b[std::size_t(pi)][index_[std::size_t(pi)].at(*q)] = 1;
    for (std::size_t p = 0; p < count_; ++p) {
      auto& patch = patches_[p];
      patch.alias.assign(patch.points.size(), -1);
      std::vector<Box> of_a, of_b;
      for (std::size_t i = 0; i < patch.points.size(); ++i) {
        const auto q = to_filtered(patch.points[i]);
        const double r = min_separation_;
        (i < points_of_a[p] ? of_a : of_b)
            .emplace_back(CGAL::Bbox_3(q.x() - r, q.y() - r, q.z() - r, q.x() + r, q.y() + r, q.z() + r),
                          std::uint32_t(i));
      }
      if (of_b.empty()) continue;
      CGAL::box_intersection_d(of_a.begin(), of_a.end(), of_b.begin(), of_b.end(), [&](const Box& x, const Box& y) {
        const double d = std::sqrt(CGAL::squared_distance(to_filtered(patch.points[x.info()]),
                                                          to_filtered(patch.points[y.info()])));
        if (d < min_separation_ && patch.alias[y.info()] < 0 && !used_by_b[p][x.info()])
          patch.alias[y.info()] = long(x.info());
      });
    }
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
        for (const auto& e : edges_a_[p])
          if (edges_b_[p].count(e)) patches_[p].constraints.push_back(e);
        for (const auto& e : patches_[p].border)
          if (!edges_b_[p].count(e)) why = "a border edge is not an edge of both";
        if (why.empty() && triangulate<K>(patches_[p], area_[p], why)) unified[p] = 1;
      }
      if (unified[p]) {
        ++stats.patches;
        stats.shared_faces += patches_[p].triangles.size();
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
  const double min_separation_;
  std::vector<char> contact_;  ///< per face of A, then of B: in a flat contact
  DisjointSets sets_{na_ + nb_};
  std::vector<long> patch_of_a_, patch_of_b_;
  std::size_t count_ = 0;
  std::vector<Patch<K>> patches_;
  std::vector<std::map<Point, std::size_t, PointLess>> index_;
  std::vector<std::set<std::pair<std::size_t, std::size_t>>> edges_a_, edges_b_, border_b_;
  std::vector<double> area_;
  std::vector<char> axis_set_;
};

}  // namespace

template <class K> FlatContactStats unify_flat_contacts(Mesh<K>& a, Mesh<K>& b, double min_separation) {
  if (a.has_garbage() || b.has_garbage()) throw InternalError("flat contacts: a mesh has garbage");
  return FlatContactUnifier<K>(a, b, min_separation).run();
}

template FlatContactStats unify_flat_contacts<Exact>(Mesh<Exact>&, Mesh<Exact>&, double);
template FlatContactStats unify_flat_contacts<Filtered>(Mesh<Filtered>&, Mesh<Filtered>&, double);
template FlatContactStats unify_flat_contacts<Float>(Mesh<Float>&, Mesh<Float>&, double);

}  // namespace seam::internal
