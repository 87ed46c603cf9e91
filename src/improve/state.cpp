// seam: the quality stage's state: curve points numbered across the meshes, the band, the grid of
// faces; and the curves written back at the end.
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/embed.h>
#include <seam/errors.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/local_edits.h>
#include <seam/quality.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace seam {

const char* shortfall_cause_name(ShortfallCause cause) {
  switch (cause) {
    case ShortfallCause::input_angle: return "input_angle";
    case ShortfallCause::constraint_angle: return "constraint_angle";
    case ShortfallCause::feature_size: return "feature_size";
    case ShortfallCause::tolerance: return "tolerance";
    case ShortfallCause::crossing: return "crossing";
    case ShortfallCause::shape: return "shape";
    case ShortfallCause::budget: return "budget";
    case ShortfallCause::flat_contact: return "flat_contact";
  }
  return "?";
}

namespace internal {

// ---------------------------------------------------------------- input surface

struct InputSurface::Tree {
  using Primitive = CGAL::AABB_triangle_primitive<Filtered, std::vector<Filtered::Triangle_3>::const_iterator>;
  std::vector<Filtered::Triangle_3> triangles;
  CGAL::AABB_tree<CGAL::AABB_traits<Filtered, Primitive>> tree;
};

InputSurface::InputSurface(std::vector<Filtered::Triangle_3> triangles) : tree_(std::make_unique<Tree>()) {
  tree_->triangles = std::move(triangles);
  tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
  tree_->tree.build();
  if (!tree_->triangles.empty()) tree_->tree.accelerate_distance_queries();
}

InputSurface::~InputSurface() = default;

template <class K> std::unique_ptr<InputSurface> input_surface(const Mesh<K>& mesh) {
  std::vector<Filtered::Triangle_3> triangles;
  triangles.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    triangles.emplace_back(to_filtered(mesh.point(mesh.source(h))), to_filtered(mesh.point(mesh.target(h))),
                           to_filtered(mesh.point(mesh.target(mesh.next(h)))));
  }
  return std::make_unique<InputSurface>(std::move(triangles));
}
template std::unique_ptr<InputSurface> input_surface<Exact>(const Mesh<Exact>&);
template std::unique_ptr<InputSurface> input_surface<Filtered>(const Mesh<Filtered>&);
template std::unique_ptr<InputSurface> input_surface<Float>(const Mesh<Float>&);

std::pair<Filtered::Point_3, Filtered::Vector_3> InputSurface::closest(const Filtered::Point_3& p) const {
  if (tree_->triangles.empty()) return {p, Filtered::Vector_3(0, 0, 0)};
  const auto [q, it] = tree_->tree.closest_point_and_primitive(p);
  Filtered::Vector_3 n = CGAL::normal(it->vertex(0), it->vertex(1), it->vertex(2));
  const double len = std::sqrt(n.squared_length());
  return {q, len > 0 ? n / len : n};
}

namespace {

/// An AABB tree traversal that stops at the first face within a distance of a point: whether
/// the point is that near the surface (doubles), without finding its closest point.
template <class Primitive> struct WithinDistance {
  double squared_distance = 0;
  bool found = false;
  bool go_further() const { return !found; }
  void intersection(const Filtered::Point_3& p, const Primitive& primitive) {
    if (!found && CGAL::squared_distance(p, primitive.datum()) <= squared_distance) found = true;
  }
  template <class Node> bool do_intersect(const Filtered::Point_3& p, const Node& node) const {
    const CGAL::Bbox_3& b = node.bbox();
    double d = 0;
    for (int i = 0; i < 3; ++i) {
      const double below = b.min(i) - p[i], above = p[i] - b.max(i);
      const double out = std::max({below, above, 0.0});
      d += out * out;
    }
    return d <= squared_distance;
  }
};

}  // namespace

bool InputSurface::within(const Filtered::Point_3& p, double distance) const {
  if (tree_->triangles.empty()) return false;
  WithinDistance<Tree::Primitive> test{distance * distance};
  tree_->tree.traversal(p, test);
  return test.found;
}

namespace {

/// An AABB tree traversal that collects the faces whose boxes overlap a box.
template <class Primitive> struct BoxOverlap {
  CGAL::Bbox_3 box;
  std::vector<const Filtered::Triangle_3*> found;
  bool go_further() const { return true; }
  void intersection(const CGAL::Bbox_3&, const Primitive& primitive) {
    if (CGAL::do_overlap(box, primitive.datum().bbox())) found.push_back(&*primitive.id());
  }
  template <class Node> bool do_intersect(const CGAL::Bbox_3&, const Node& node) const {
    return CGAL::do_overlap(box, node.bbox());
  }
};

}  // namespace

std::optional<Filtered::Vector_3> InputSurface::face_within(const Filtered::Point_3& p, const Filtered::Point_3& q,
                                                            const Filtered::Point_3& r, double distance) const {
  if (tree_->triangles.empty()) return std::nullopt;
  const Filtered::Point_3 centroid = CGAL::centroid(p, q, r);
  const std::array<Filtered::Point_3, 7> samples{centroid, CGAL::midpoint(p, q), CGAL::midpoint(q, r),
                                                 CGAL::midpoint(r, p), p, q, r};
  // The samples' box grown by the distance, with room for the rounding of a squared distance
  // computed at most `distance` (a face that near a sample overlaps it).
  CGAL::Bbox_3 box;
  for (const auto& x : samples) box += x.bbox();
  const double grow = distance * (1 + 1e-6) + 1e-300;
  BoxOverlap<Tree::Primitive> near{CGAL::Bbox_3(box.xmin() - grow, box.ymin() - grow, box.zmin() - grow,
                                                box.xmax() + grow, box.ymax() + grow, box.zmax() + grow),
                                   {}};
  tree_->tree.traversal(near.box, near);
  if (near.found.empty()) return std::nullopt;
  const Filtered::Triangle_3* closest = nullptr;  // to the centroid
  double best = std::numeric_limits<double>::infinity();
  for (const Filtered::Triangle_3* t : near.found)
    if (const double d = CGAL::squared_distance(centroid, *t); d < best) best = d, closest = t;
  const double d2 = distance * distance;
  if (!(best <= d2)) return std::nullopt;
  // The other samples: that face first (the nearest to most of them), then the others.
  for (std::size_t i = 1; i < samples.size(); ++i)
    if (!(CGAL::squared_distance(samples[i], *closest) <= d2) &&
        std::none_of(near.found.begin(), near.found.end(),
                     [&](const Filtered::Triangle_3* t) { return CGAL::squared_distance(samples[i], *t) <= d2; }))
      return std::nullopt;
  Filtered::Vector_3 n = CGAL::normal(closest->vertex(0), closest->vertex(1), closest->vertex(2));
  const double len = std::sqrt(n.squared_length());
  return len > 0 ? n / len : n;
}

// ---------------------------------------------------------------- state

template <class K> double face_min_angle(const ImproveState<K>& s, std::size_t m, typename ImproveState<K>::F f) {
  const auto c = s.corners(m, f);
  const auto& g = s.mesh(m);
  return min_angle_deg(g.point(c[0]), g.point(c[1]), g.point(c[2]));
}

template <class K> bool ImproveState<K>::may_join_band(std::size_t m, F f) const {
  const MeshState& ms = meshes[m];
  if (f == M::null_face() || ms.band[f]) return false;
  return !((ms.has_shared && ms.shared[f]) || (ms.has_frozen && ms.frozen[f]));
}

namespace {

/// Curve points numbered across the meshes (the same point in two meshes is one), their links
/// along each curve, and each segment's curve.
template <class K> void number_curve_points(ImproveState<K>& s, const SharedCurves<K>& in) {
  using Point = typename K::Point_3;
  auto less = [](const Point& x, const Point& y) { return CGAL::compare_xyz(x, y) == CGAL::SMALLER; };
  std::map<Point, int, decltype(less)> ids(less);
  const std::size_t n_meshes = s.meshes.size();
  s.curves.resize(in.curves.size());
  for (std::size_t c = 0; c < in.curves.size(); ++c) {
    const auto& curve = in.curves[c];
    auto& sc = s.curves[c];
    sc.closed = is_closed(curve);
    const std::size_t n = sc.closed ? curve.size() - 1 : curve.size();
    for (std::size_t m = 0; m < n_meshes; ++m)
      if (in.vertices[m].size() > c && !in.vertices[m][c].empty()) sc.meshes.push_back(m);
    std::vector<int> id(n);
    for (std::size_t i = 0; i < n; ++i) {
      auto [it, added] = ids.emplace(curve[i], int(s.points.size()));
      if (added) s.points.push_back({curve[i], std::vector<typename Mesh<K>::Vertex_index>(n_meshes), false, {}});
      id[i] = it->second;
      for (std::size_t m : sc.meshes) {
        const auto v = in.vertices[m][c][i];
        s.points[std::size_t(id[i])].vertex[m] = v;
        s.meshes[m].point[v] = id[i];
      }
    }
    // The nodes along the curve, linked; each segment to the node at its start.
    const int first = int(s.nodes.size());
    for (std::size_t i = 0; i < n; ++i) {
      s.points[std::size_t(id[i])].nodes.push_back(first + int(i));
      s.nodes.push_back({id[i], i > 0 ? first + int(i) - 1 : -1, -1, int(c)});
    }
    for (std::size_t i = 0; i + 1 < n; ++i) s.nodes[std::size_t(first) + i].next = first + int(i) + 1;
    if (sc.closed && n > 1) {
      s.nodes[std::size_t(first)].prev = first + int(n) - 1;
      s.nodes[std::size_t(first) + n - 1].next = first;
    }
    if (n > 0) sc.first = first;
    const std::size_t links = n < 2 ? 0 : (sc.closed ? n : n - 1);
    for (std::size_t i = 0; i < links; ++i) {
      const int a = id[i], b = id[(i + 1) % n];
      if (a == b || !s.segment_node.emplace(std::make_pair(std::min(a, b), std::max(a, b)), first + int(i)).second)
        throw InternalError("improve: a curve runs twice along one segment");
    }
  }
}

/// The stage's own properties on each mesh, and the provenance properties the embedding made.
template <class K> void add_properties(typename ImproveState<K>::MeshState& ms) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  M& g = *ms.mesh;
  ms.point = g.template add_property_map<V, std::int32_t>("v:seam_improve_point", -1).first;
  ms.made = g.template add_property_map<V, bool>("v:seam_improve_made", false).first;
  ms.band = g.template add_property_map<F, bool>("f:seam_improve_band", false).first;
  ms.version = g.template add_property_map<F, std::uint32_t>("f:seam_improve_version", 0).first;
  ms.cause = g.template add_property_map<F, std::uint8_t>("f:seam_improve_cause", 0).first;
  ms.crease_memo = g.template add_property_map<typename M::Halfedge_index, CreaseMemo>("h:seam_improve_crease").first;
  for (auto h : g.halfedges()) ms.crease_memo[h] = CreaseMemo{};
  for (auto v : g.vertices()) ms.point[v] = -1, ms.made[v] = false;
  for (auto f : g.faces()) ms.band[f] = false, ms.version[f] = 0, ms.cause[f] = 0;
  bool added_source = false;
  std::tie(ms.source, added_source) = g.template add_property_map<F, std::uint32_t>(source_face_property, 0);
  if (added_source)
    for (auto f : g.faces()) ms.source[f] = std::uint32_t(std::size_t(f));
  ms.is_new = g.template add_property_map<F, bool>(new_face_property, false).first;
  std::tie(ms.shared, ms.has_shared) = g.template property_map<F, bool>(shared_face_property);
  std::tie(ms.frozen, ms.has_frozen) = g.template property_map<F, bool>(frozen_face_property);
}

/// How close two segments of the curve with no common point come (doubles); infinity where no
/// two are (a closed curve of three segments, an open one of two). A thin loop is narrower than
/// its box: a finer scale than its size needs to fit between its sides.
template <class P> double own_gap(const std::vector<P>& curve) {
  double gap = std::numeric_limits<double>::infinity();
  const std::size_t n = curve.size() - 1;  // segments (a closed curve repeats its first point)
  const bool closed = is_closed(curve);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 2; j < n; ++j) {
      if (closed && i == 0 && j == n - 1) continue;  // they meet at the first point
      const Filtered::Segment_3 a(to_filtered(curve[i]), to_filtered(curve[i + 1]));
      const Filtered::Segment_3 b(to_filtered(curve[j]), to_filtered(curve[j + 1]));
      gap = std::min(gap, std::sqrt(CGAL::squared_distance(a, b)));
    }
  return gap;
}

/// The small curves (see ImproveOptions::small_curve_limit), with the feature size at them: their
/// size over small_curve_divisions, or half the gap between their own sides where less (but not
/// below their size over the square of small_curve_divisions, nor twice min_separation). Only a
/// curve alone is one: no segment of another curve comes within max(2, 1 / grading) feature
/// sizes of its box (where its graded size is below feature_size), so that the finer scale meets
/// no gap between two curves, which it cannot mesh better (step 2d's merges may). A curve of one
/// point (a point of contact) has no size: none.
template <class K> void find_small_curves(ImproveState<K>& s, const SharedCurves<K>& in) {
  const ImproveOptions& o = s.options;
  if (!(o.small_curve_limit > 0) || !(o.small_curve_divisions >= 1) || !(o.small_curve_grading > 0)) return;
  std::vector<CGAL::Bbox_3> boxes;
  for (const auto& curve : in.curves) {
    CGAL::Bbox_3 box;
    for (const auto& p : curve) box += to_filtered(p).bbox();
    boxes.push_back(box);
  }
  // Where the graded size of a curve's scale stays below feature_size: (feature_size - scale) /
  // grading from its box, at most feature_size / grading.
  const double reach = std::max(2.0, 1.0 / o.small_curve_grading) * s.feature_size;
  for (std::size_t c = 0; c < in.curves.size(); ++c) {
    const CGAL::Bbox_3& box = boxes[c];
    const double size = bbox_diagonal(box);
    if (in.curves[c].size() < 2 || !(size > 0) || size >= o.small_curve_limit * s.feature_size) continue;
    const CGAL::Bbox_3 around(box.xmin() - reach, box.ymin() - reach, box.zmin() - reach, box.xmax() + reach,
                              box.ymax() + reach, box.zmax() + reach);
    bool alone = true;
    for (std::size_t d = 0; d < in.curves.size() && alone; ++d) {
      if (d == c || !CGAL::do_overlap(boxes[d], around)) continue;
      const auto& other = in.curves[d];
      if (other.size() == 1) alone = !CGAL::do_overlap(to_filtered(other[0]).bbox(), around);
      for (std::size_t i = 0; i + 1 < other.size() && alone; ++i)
        alone = !CGAL::do_overlap(to_filtered(other[i]).bbox() + to_filtered(other[i + 1]).bbox(), around);
    }
    if (!alone) continue;
    // Between its sides: at most small_curve_divisions^2 times finer than its size (a pinch
    // narrower than that is left to the merges: refined into, it made thousands of points).
    const double sides = std::max(own_gap(in.curves[c]) / 2, size / (o.small_curve_divisions * o.small_curve_divisions));
    // Not below twice the vertex separation: points closer are refused by the predicate anyway.
    const double scale = std::max(std::min({size / o.small_curve_divisions, sides}), 2 * o.min_separation);
    if (scale < s.feature_size) s.small_curves.push_back({box, scale});
  }
  s.stats.small_curves = s.small_curves.size();
}

/// ImproveOptions::bound_reach for one mesh, from its input faces' smallest angles (null: not
/// known): as given (254 at most), or automatically no limit where at least half of them meet the
/// bound, 1 where most do not.
template <class K>
std::uint8_t bound_reach_of(const ImproveOptions& options, const std::vector<double>* input_angles) {
  constexpr std::uint8_t no_limit = ImproveState<K>::MeshState::no_limit;
  if (options.bound_reach >= 0) return std::uint8_t(std::min<long>(options.bound_reach, no_limit));
  if (!input_angles || input_angles->empty()) return no_limit;
  const auto meeting = std::count_if(input_angles->begin(), input_angles->end(),
                                     [&](double a) { return a >= options.min_angle_deg; });
  return 2 * std::size_t(meeting) >= input_angles->size() ? no_limit : 1;
}

}  // namespace

template <class K>
void init_state(ImproveState<K>& s, std::vector<ImproveMesh<K>>& meshes, const SharedCurves<K>& curves,
                const ImproveOptions& options) {
  s.options = options;
  s.mean_edge = std::numeric_limits<double>::infinity();
  for (const auto& im : meshes) s.mean_edge = std::min(s.mean_edge, mean_edge_length<K>(*im.mesh));
  if (!(s.mean_edge > 0) || !std::isfinite(s.mean_edge)) s.mean_edge = 1;
  s.tolerance = std::max(0.0, options.tolerance);
  s.feature_size = feature_size_of(options, s.tolerance, s.mean_edge);
  s.meshes.resize(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    s.meshes[m].mesh = meshes[m].mesh;
    for (auto v : s.meshes[m].mesh->vertices()) fix_rounding(s.meshes[m].mesh->point(v));
  }
  // The input surfaces' trees (after fix_rounding: a tree of the mesh itself rounds its points),
  // a task per mesh: independent, the same trees in any order.
  tbb::parallel_for(std::size_t(0), meshes.size(), [&](std::size_t m) {
    s.meshes[m].input = input_surface<K>(meshes[m].input ? *meshes[m].input : *meshes[m].mesh);
  });
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    auto& ms = s.meshes[m];
    ms.source_min_angle = meshes[m].source_min_angle;
    ms.bound_reach = bound_reach_of<K>(options, ms.source_min_angle);
    s.stats.bound_reach.push_back(ms.bound_reach);
    add_properties<K>(ms);
  }
  number_curve_points<K>(s, curves);
  find_small_curves<K>(s, curves);
  for (auto& point : s.points) fix_rounding(point.p);  // (copies of the curves' points may be other objects)

  // The band: faces made by the embedding or touching a curve point, not shared or frozen.
  double band_area = 0;  // with max_area: for the budget
  s.stats.min_angle_deg_before = 180;
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    auto& ms = s.meshes[m];
    for (auto f : ms.mesh->faces()) {
      if ((ms.has_shared && ms.shared[f]) || (ms.has_frozen && ms.frozen[f])) continue;
      bool touches = ms.is_new[f];
      for (auto v : s.corners(m, f)) touches = touches || ms.point[v] >= 0;
      if (!touches) continue;
      ms.band[f] = true;
      ++s.stats.band_faces;
      ms.set_reach(f, 0);
      if (options.max_area > 0) band_area += s.face_area(m, f);
      const double angle = face_min_angle<K>(s, m, f);
      s.stats.min_angle_deg_before = std::min(s.stats.min_angle_deg_before, angle);
      if (angle < s.target_angle(m, f)) ++s.stats.below_bound_before;
    }
  }
  if (s.stats.band_faces == 0) s.stats.min_angle_deg_before = 0;
  // The grid: every face (the band may grow anywhere the meshes are not shared or frozen),
  // deferred: inserted where a query first reaches it, if it is still the face it was (version 0,
  // its corners where they were: an edit remakes a face it changes).
  s.grid = FaceGrid(s.mean_edge);
  using F = typename Mesh<K>::Face_index;
  s.grid.set_deferred({[&s](const FaceGrid::Entry& e) { return s.face_box(e.mesh, F(e.face)); },
                       [&s](const FaceGrid::Entry& e) { return s.is_live(e); }});
  for (std::size_t m = 0; m < s.meshes.size(); ++m)
    for (auto f : s.meshes[m].mesh->faces())
      s.grid.defer({std::uint32_t(m), std::uint32_t(std::size_t(f)), s.meshes[m].version[f]}, s.face_box(m, f));
  s.insertions_left = options.max_insertions_per_face * std::max<std::size_t>(s.stats.band_faces, 1);
  if (options.max_area > 0)  // one point per max_area (n points make about 2n faces)
    s.insertions_left += std::size_t(std::min(band_area / options.max_area, 1e9));
}

template <class K> void finish_state(ImproveState<K>& s, SharedCurves<K>& out) {
  using V = typename Mesh<K>::Vertex_index;
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    auto& ms = s.meshes[m];
    ms.mesh->collect_garbage();
    for (auto& p : s.points) p.vertex[m] = Mesh<K>::null_vertex();
    for (auto v : ms.mesh->vertices())
      if (ms.point[v] >= 0) s.points[std::size_t(ms.point[v])].vertex[m] = v;
  }
  for (std::size_t c = 0; c < s.curves.size(); ++c) {
    const auto& sc = s.curves[c];
    auto& points = out.curves[c];
    points.clear();
    for (std::size_t m : sc.meshes) out.vertices[m][c].clear();
    for (int node = sc.first, steps = 0; node >= 0; ++steps) {
      if (steps > int(s.nodes.size())) throw InternalError("improve: a curve's links form no chain");
      const int id = s.nodes[std::size_t(node)].point;
      points.push_back(s.points[std::size_t(id)].p);
      for (std::size_t m : sc.meshes) {
        const V v = s.points[std::size_t(id)].vertex[m];
        if (v == Mesh<K>::null_vertex()) throw InternalError("improve: a curve point lost its vertex");
        out.vertices[m][c].push_back(v);
      }
      node = s.nodes[std::size_t(node)].next;
      if (node == sc.first) {  // closed: repeat the first point
        if (points.size() == 1) break;  // (merged down to one point: a point of contact)
        points.push_back(points.front());
        for (std::size_t m : sc.meshes) out.vertices[m][c].push_back(out.vertices[m][c].front());
        break;
      }
    }
  }
}

template <class K> void drop_state_properties(ImproveState<K>& s) {
  for (auto& ms : s.meshes) {
    ms.mesh->remove_property_map(ms.point);
    ms.mesh->remove_property_map(ms.made);
    ms.mesh->remove_property_map(ms.band);
    ms.mesh->remove_property_map(ms.version);
    ms.mesh->remove_property_map(ms.cause);
    ms.mesh->remove_property_map(ms.crease_memo);
  }
}

template <class K> std::vector<double> face_min_angles(const Mesh<K>& input) {
  std::vector<double> angles;
  angles.reserve(input.number_of_faces());
  for (auto f : input.faces()) {
    const auto h = input.halfedge(f);
    angles.push_back(min_angle_deg(to_filtered(input.point(input.source(h))), to_filtered(input.point(input.target(h))),
                                   to_filtered(input.point(input.target(input.next(h))))));
  }
  return angles;
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template std::vector<double> face_min_angles<K>(const Mesh<K>&);                                           \
  template struct ImproveState<K>;                                                                            \
  template double face_min_angle<K>(const ImproveState<K>&, std::size_t, ImproveState<K>::F);               \
  template void init_state<K>(ImproveState<K>&, std::vector<ImproveMesh<K>>&, const SharedCurves<K>&,        \
                              const ImproveOptions&);                                                         \
  template void finish_state<K>(ImproveState<K>&, SharedCurves<K>&);                                         \
  template void drop_state_properties<K>(ImproveState<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace internal
}  // namespace seam
