// seam: independent verification of a conforming pair. See seam/check.h.
//
// Nothing here calls the embedding or the curve computation: the checks use the four meshes, the
// curves and CGAL predicates only. Vertices of different meshes are matched by their exact
// coordinates (std::map ordered by CGAL::compare_xyz), never by index.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/errors.h>
#include <seam/internal/certified.h>
#include <seam/quality.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/intersections.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/helpers.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <seam/internal/message.h>

#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <utility>

#if !defined(CGAL_HAS_THREADS)
#error "seam check decides face pairs on several threads: it needs CGAL_HAS_THREADS (build with -pthread)"
#endif

namespace seam {

namespace {

using internal::say;

template <class P> std::string point_text(const P& p) {
  return say("(", CGAL::to_double(p.x()), ", ", CGAL::to_double(p.y()), ", ", CGAL::to_double(p.z()), ")");
}

/// Exact lexicographic order of points.
struct PointLess {
  template <class P> bool operator()(const P& p, const P& q) const { return CGAL::compare_xyz(p, q) == CGAL::SMALLER; }
};

constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t max_examples = 5;  ///< face pairs named in one problem line
/// box_intersection_d's cutoff: a range of fewer boxes is scanned pair by pair instead of split
/// further. CGAL's default is 10; its own self-intersection test (Polygon_mesh_processing) uses
/// 2000: fewer levels of recursion, each of which copies and partitions the boxes. The pairs
/// found are the same; only the order in which they are reported can differ.
constexpr std::ptrdiff_t box_cutoff = 2000;

// Certified fast tests (seam/internal/certified.h): interval arithmetic that settles nearly
// every degenerate face pair next to the curves in doubles.
using internal::certified::I;
using internal::certified::IP;
using internal::certified::interval_point;
using internal::certified::orient2;
using internal::certified::orient3;
using internal::certified::sure_sign;
using internal::certified::surely_disjoint;
using internal::certified::surely_only_edge;
using internal::certified::surely_only_vertex;

/// How two faces meet. Their common corners are given: for corner k of the second face, ia[k] is
/// the corner of the first face at the same point, or -1.
enum class Meet : unsigned char { apart, at_vertex, along_edge, beyond };

template <class K> struct Corners {
  std::array<const typename K::Point_3*, 3> p;
  std::array<const IP*, 3> a;
  typename K::Triangle_3 triangle() const { return typename K::Triangle_3(*p[0], *p[1], *p[2]); }
};

/// apart: no common point. at_vertex / along_edge: exactly the common vertex / edge. beyond:
/// anything more (crossing, overlapping, touching away from the common corners).
template <class K> Meet meet(const Corners<K>& s, const Corners<K>& t, const int ia[3], int shared) {
  using Segment = typename K::Segment_3;
  switch (shared) {
    case 0:
      if (surely_disjoint(s.a, t.a)) return Meet::apart;
      return CGAL::do_intersect(s.triangle(), t.triangle()) ? Meet::beyond : Meet::apart;
    case 1: {
      int k = 0;
      while (ia[k] < 0) ++k;
      const int j = ia[k], j1 = (j + 1) % 3, j2 = (j + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      if (const auto only = surely_only_vertex(*s.a[j], *s.a[j1], *s.a[j2], *t.a[k1], *t.a[k2]))
        return *only ? Meet::at_vertex : Meet::beyond;
      // The intersection is more than the common vertex iff an opposite edge meets the other face
      // (the far end of the intersection lies on one of the opposite edges).
      if (CGAL::do_intersect(Segment(*s.p[j1], *s.p[j2]), t.triangle()) ||
          CGAL::do_intersect(Segment(*t.p[k1], *t.p[k2]), s.triangle()))
        return Meet::beyond;
      return Meet::at_vertex;
    }
    case 2: {
      int k = 0;
      while (ia[k] >= 0) ++k;  // the corner of t that is not shared
      const int jp = ia[(k + 1) % 3], jq = ia[(k + 2) % 3];
      const int j = 3 - jp - jq;  // the corner of s that is not shared
      if (surely_only_edge(*s.a[jp], *s.a[jq], *s.a[j], *t.a[k])) return Meet::along_edge;
      // Faces with a common edge overlap iff they are coplanar and on the same side of it.
      const auto &p = *s.p[jp], &q = *s.p[jq], &r = *s.p[j], &o = *t.p[k];
      if (CGAL::coplanar(p, q, r, o) && CGAL::coplanar_orientation(p, q, r, o) == CGAL::POSITIVE) return Meet::beyond;
      return Meet::along_edge;
    }
    default:
      return Meet::beyond;
  }
}

/// The two triangles lie in one plane (exact predicates).
template <class K> bool coplanar_faces(const Corners<K>& s, const Corners<K>& t) {
  for (int k = 0; k < 3; ++k)
    if (!CGAL::coplanar(*s.p[0], *s.p[1], *s.p[2], *t.p[k])) return false;
  return true;
}

template <class K> struct MeshView {
  using M = Mesh<K>;
  using Point = typename K::Point_3;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;

  const M& mesh;
  std::string name;
  bool structure_ok = false;  ///< valid halfedge structure of triangles: the other checks can run
  std::map<Point, V, PointLess> vertex_at;  ///< exact coordinates -> vertex
  std::vector<char> degenerate;             ///< per face index
  std::vector<IP> approx;                   ///< per vertex index

  MeshView(const M& m, std::string n) : mesh(m), name(std::move(n)) {}

  std::size_t vertex_slots() const { return mesh.number_of_vertices() + mesh.number_of_removed_vertices(); }
  std::size_t face_slots() const { return mesh.number_of_faces() + mesh.number_of_removed_faces(); }
  std::array<V, 3> corners(F f) const {
    const auto h = mesh.halfedge(f);
    return {mesh.source(h), mesh.target(h), mesh.target(mesh.next(h))};
  }
  Corners<K> geometry(const std::array<V, 3>& c) const {
    Corners<K> g;
    for (int i = 0; i < 3; ++i) {
      g.p[i] = &mesh.point(c[i]);
      g.a[i] = &approx[std::size_t(c[i])];
    }
    return g;
  }
};

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;

/// Whether face index i is in focus (every face without a focus).
inline bool in_focus(const std::vector<char>* focus, std::size_t i) {
  return !focus || (i < focus->size() && (*focus)[i]);
}

/// One box per non-degenerate face; with `select`, only the faces in focus (select = 1) or only
/// those not in focus (select = 0).
template <class K>
std::vector<Box> face_boxes(const MeshView<K>& view, const std::vector<char>* focus = nullptr, int select = 1) {
  std::vector<Box> result;
  result.reserve(view.mesh.number_of_faces());
  for (auto f : view.mesh.faces()) {
    if (view.degenerate[std::size_t(f)]) continue;  // reported by check 1
    if (focus && in_focus(focus, std::size_t(f)) != (select == 1)) continue;
    const auto c = view.corners(f);
    const auto& m = view.mesh;
    result.emplace_back(m.point(c[0]).bbox() + m.point(c[1]).bbox() + m.point(c[2]).bbox(), std::uint32_t(f));
  }
  return result;
}

/// How two faces with `shared` common corners that meet beyond them meet.
const char* beyond_text(int shared) {
  if (shared == 3) return "are the same triangle";
  if (shared == 2) return "overlap (coplanar on the same side of their common edge)";
  if (shared == 1) return "cross (beyond their common vertex)";
  return "cross";
}

/// Faces of one mesh meet only in their common vertices and edges (what is checked is the same
/// as CGAL::Polygon_mesh_processing::does_self_intersect, with the fast tests above first).
template <class K>
void check_self_intersections(const MeshView<K>& view, std::vector<std::string>& problems,
                              std::vector<std::size_t>& conflict_faces, const std::vector<char>* focus) {
  using F = typename Mesh<K>::Face_index;
  std::vector<Box> boxes = face_boxes(view);
  std::size_t count = 0;
  std::vector<std::string> examples;
  auto callback = [&](const Box& x, const Box& y) {
    const F f(x.info()), g(y.info());
    if (f == g) return;
    const auto cf = view.corners(f), cg = view.corners(g);
    int ia[3] = {-1, -1, -1};
    int shared = 0;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        if (cg[k] == cf[j]) {
          ia[k] = j;
          ++shared;
        }
    const Meet how = meet<K>(view.geometry(cf), view.geometry(cg), ia, shared);
    if (how != Meet::beyond) return;
    conflict_faces.push_back(std::size_t(f));
    conflict_faces.push_back(std::size_t(g));
    if (count++ < max_examples)
      examples.push_back(say("faces ", std::size_t(f), " and ", std::size_t(g), " ", beyond_text(shared)));
  };
  if (focus) {
    // The pairs with a face in focus: those boxes against all (a pair of two faces in focus is
    // seen twice, and reported twice).
    std::vector<Box> focused = face_boxes(view, focus, 1);
    CGAL::box_intersection_d(focused.begin(), focused.end(), boxes.begin(), boxes.end(), callback, box_cutoff);
  } else {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), callback, box_cutoff);
  }
  if (count) {
    std::string list;
    for (const auto& e : examples) list += (list.empty() ? "" : "; ") + e;
    if (count > examples.size()) list += "; ...";
    problems.push_back(say(view.name, " self-intersects: ", count, " face pairs (", list, ")"));
  }
}

/// Check 1: a valid triangle mesh, closed when its input is; fills the vertex map.
template <class K>
void check_mesh(MeshView<K>& view, bool expect_closed, std::vector<std::string>& problems,
                std::vector<std::size_t>& conflict_faces, const std::vector<char>* focus) {
  const auto& m = view.mesh;
  const std::string& name = view.name;
  if (m.number_of_faces() == 0) {
    problems.push_back(say(name, " has no face"));
    return;
  }
  if (!CGAL::is_valid_polygon_mesh(m)) {
    problems.push_back(say(name, " is not a valid polygon mesh (broken halfedge structure)"));
    return;
  }
  if (!CGAL::is_triangle_mesh(m)) {
    problems.push_back(say(name, " is not a triangle mesh"));
    return;
  }
  view.structure_ok = true;
  if (expect_closed && !CGAL::is_closed(m))
    problems.push_back(say(name, " is not closed (its input is): it has border edges"));

  std::size_t isolated = 0;
  std::size_t duplicates = 0;
  std::string first_duplicate;
  view.approx.assign(view.vertex_slots(), IP{I(0), I(0), I(0)});
  for (auto v : m.vertices()) {
    view.approx[std::size_t(v)] = interval_point(m.point(v));
    if (m.is_isolated(v)) ++isolated;
    const auto [it, inserted] = view.vertex_at.emplace(m.point(v), v);
    if (!inserted && duplicates++ == 0)
      first_duplicate = say("vertices ", std::size_t(it->second), " and ", std::size_t(v), " at ", point_text(m.point(v)));
  }
  if (isolated) problems.push_back(say(name, " has ", isolated, " isolated vertices (in no face)"));
  if (duplicates)
    problems.push_back(say(name, " has ", duplicates, " vertices at the same point as another vertex (first: ",
                           first_duplicate, ")"));

  view.degenerate.assign(view.face_slots(), 0);
  std::size_t degenerate = 0;
  std::size_t first_degenerate = 0;
  for (auto f : m.faces()) {
    if (!in_focus(focus, std::size_t(f))) continue;
    const auto c = view.corners(f);
    if (CGAL::collinear(m.point(c[0]), m.point(c[1]), m.point(c[2]))) {
      view.degenerate[std::size_t(f)] = 1;
      conflict_faces.push_back(std::size_t(f));
      if (degenerate++ == 0) first_degenerate = std::size_t(f);
    }
  }
  if (degenerate)
    problems.push_back(say(name, " has ", degenerate, " degenerate (zero-area) faces (first: face ", first_degenerate, ")"));
  check_self_intersections(view, problems, conflict_faces, focus);
}

/// The corners of face f rounded to doubles (the coordinates as written).
template <class K> std::array<Filtered::Point_3, 3> corners_in_doubles(const Mesh<K>& m, typename Mesh<K>::Face_index f) {
  const auto h = m.halfedge(f);
  return {to_filtered(m.point(m.source(h))), to_filtered(m.point(m.target(h))), to_filtered(m.point(m.target(m.next(h))))};
}

/// Input faces as triangles in doubles, with their faces, and a distance tree on them (built at
/// the first query).
template <class K> class TrianglesOfInput {
 public:
  using FP = Filtered::Point_3;
  using F = typename Mesh<K>::Face_index;
  void add(const Filtered::Triangle_3& t, F f) {
    triangles_.push_back(t);
    faces_.push_back(f);
  }
  bool empty() const { return triangles_.empty(); }
  std::size_t size() const { return triangles_.size(); }
  const Filtered::Triangle_3& triangle(std::size_t i) const { return triangles_[i]; }
  F face(std::size_t i) const { return faces_[i]; }
  /// The closest point of the triangles to q (doubles), and the input face it lies on.
  std::pair<FP, F> closest(const FP& q) {
    if (!tree_) {
      tree_.emplace(triangles_.begin(), triangles_.end());
      tree_->accelerate_distance_queries();
    }
    const auto [p, it] = tree_->closest_point_and_primitive(q);
    return {p, faces_[std::size_t(it - triangles_.cbegin())]};
  }

 private:
  using Primitive = CGAL::AABB_triangle_primitive<Filtered, std::vector<Filtered::Triangle_3>::const_iterator>;
  std::vector<Filtered::Triangle_3> triangles_;
  std::vector<F> faces_;
  std::optional<CGAL::AABB_tree<CGAL::AABB_traits<Filtered, Primitive>>> tree_;
};

/// Check 4's distances: of each output vertex in `off` (`points`: its point in doubles) from the
/// input surface, at most `tol`; their largest in `max_distance`. The tree is built over the
/// input faces whose boxes come within tol + 2 slack of a vertex to measure (one box search, not a
/// tree of every face: most output vertices are input vertices, which are not measured). A vertex
/// within tol + slack of the surface has its closest face among them, so its distance is the same
/// as over every face; a vertex farther is measured again over every face. Not where the reach is
/// many faces wide (a tolerance far above the default): the box search would then pair each vertex
/// with many faces.
template <class K>
void check_distances(const Mesh<K>& input, const MeshView<K>& out, const std::vector<typename Mesh<K>::Vertex_index>& off,
                     const std::vector<Filtered::Point_3>& points, double tol, double& max_distance,
                     std::vector<std::string>& problems) {
  using FP = Filtered::Point_3;
  max_distance = 0;
  if (off.empty() || input.number_of_faces() == 0) return;
  TrianglesOfInput<K> all, near;  // every input face; those near a vertex to measure
  std::vector<Box> input_boxes;   // (index into the input faces in face order)
  input_boxes.reserve(input.number_of_faces());
  CGAL::Bbox_3 box;
  double width_sum = 0;  // of the faces' boxes (their largest extent)
  for (auto f : input.faces()) {
    const auto c = corners_in_doubles<K>(input, f);
    all.add({c[0], c[1], c[2]}, f);
    const CGAL::Bbox_3 b = all.triangle(all.size() - 1).bbox();
    input_boxes.emplace_back(b, std::uint32_t(all.size() - 1));
    box += b;
    width_sum += std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
  }
  const double scale = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                 CGAL::square(box.zmax() - box.zmin()));
  // Rounding of the double distance: relative to the size, and a few units in the last place
  // of the coordinates (which dominate for a small mesh far from the origin).
  const double magnitude = std::max({std::abs(box.xmin()), std::abs(box.xmax()), std::abs(box.ymin()),
                                     std::abs(box.ymax()), std::abs(box.zmin()), std::abs(box.zmax())});
  const double slack = 1e-12 * scale + 64 * std::numeric_limits<double>::epsilon() * magnitude;
  const double reach = tol + 2 * slack;
  if (std::isfinite(reach) && reach <= 8 * width_sum / double(all.size())) {
    std::vector<Box> vertex_boxes;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const FP& p = points[i];
      vertex_boxes.emplace_back(
          CGAL::Bbox_3(p.x() - reach, p.y() - reach, p.z() - reach, p.x() + reach, p.y() + reach, p.z() + reach),
          std::uint32_t(i));
    }
    std::vector<char> taken(all.size(), 0);
    CGAL::box_intersection_d(input_boxes.begin(), input_boxes.end(), vertex_boxes.begin(), vertex_boxes.end(),
                             [&](const Box& x, const Box&) { taken[x.info()] = 1; }, box_cutoff);
    for (std::size_t i = 0; i < all.size(); ++i)
      if (taken[i]) near.add(all.triangle(i), all.face(i));
  }
  std::size_t far = 0;
  std::size_t first_far = 0;
  double first_far_distance = 0;
  for (std::size_t i = 0; i < off.size(); ++i) {
    const FP& query = points[i];
    std::pair<FP, typename Mesh<K>::Face_index> found;
    bool near_enough = false;
    if (!near.empty()) {
      found = near.closest(query);
      near_enough = std::sqrt(CGAL::squared_distance(query, found.first)) <= tol + slack;
    }
    if (!near_enough) found = all.closest(query);
    double d = std::sqrt(CGAL::squared_distance(query, found.first));
    bool within = d <= tol;
    if (!within && d <= tol + slack) {
      // Decide in the kernel (exactly under the exact kernel) with the closest face found.
      const auto h = input.halfedge(found.second);
      const typename K::Triangle_3 t(input.point(input.source(h)), input.point(input.target(h)),
                                     input.point(input.target(input.next(h))));
      const auto d2 = CGAL::squared_distance(out.mesh.point(off[i]), t);
      // (tol is finite here: d <= tol holds for every d when it is not; an infinite FT is a
      // CGAL assertion failure)
      within = d2 <= typename K::FT(tol) * typename K::FT(tol);
      d = std::min(d, std::sqrt(CGAL::to_double(d2)));
    }
    max_distance = std::max(max_distance, d);
    if (!within && far++ == 0) {
      first_far = std::size_t(off[i]);
      first_far_distance = d;
    }
  }
  if (far)
    problems.push_back(say(out.name, ": ", far, " vertices are farther than the tolerance ", tol,
                           " from the input surface (first: vertex ", first_far, " at distance ", first_far_distance,
                           "; largest ", max_distance, ")"));
}

/// Check 4 and the quality figures for one output mesh against its input.
template <class K>
void check_against_input(const Mesh<K>& input, const MeshView<K>& out, double tol, double& max_distance,
                         double& min_angle, std::size_t& below_10, std::size_t& below_20, std::size_t& new_faces,
                         std::vector<std::string>& problems) {
  const auto& m = out.mesh;

  // Output vertices at an input vertex's exact coordinates: on the input surface (distance 0).
  std::vector<std::uint32_t> to_out(input.number_of_vertices() + input.number_of_removed_vertices(), none);
  std::vector<char> at_input_vertex(out.vertex_slots(), 0);
  for (auto v : input.vertices()) {
    const auto it = out.vertex_at.find(input.point(v));
    if (it == out.vertex_at.end()) continue;
    to_out[std::size_t(v)] = std::uint32_t(it->second);
    at_input_vertex[std::size_t(it->second)] = 1;
  }

  // Distances of the other output vertices from the input surface.
  std::vector<typename Mesh<K>::Vertex_index> off;
  std::vector<Filtered::Point_3> off_points;  // their points in doubles, taken once
  for (auto v : m.vertices())
    if (!m.is_isolated(v) && !at_input_vertex[std::size_t(v)]) {
      off.push_back(v);
      off_points.push_back(to_filtered(m.point(v)));
    }
  check_distances<K>(input, out, off, off_points, tol, max_distance, problems);

  // Quality: every face's smallest angle; faces that are not input faces (same three points).
  std::vector<std::array<std::uint32_t, 3>> input_faces;  // sorted, for binary_search
  for (auto f : input.faces()) {
    const auto h = input.halfedge(f);
    std::array<std::uint32_t, 3> c = {to_out[std::size_t(input.source(h))], to_out[std::size_t(input.target(h))],
                                      to_out[std::size_t(input.target(input.next(h)))]};
    if (c[0] == none || c[1] == none || c[2] == none) continue;
    std::sort(c.begin(), c.end());
    input_faces.push_back(c);
  }
  std::sort(input_faces.begin(), input_faces.end());
  min_angle = 180;
  below_10 = below_20 = new_faces = 0;
  for (auto f : m.faces()) {
    const auto c = out.corners(f);
    const double angle = min_angle_deg(m.point(c[0]), m.point(c[1]), m.point(c[2]));
    min_angle = std::min(min_angle, angle);
    std::array<std::uint32_t, 3> k = {std::uint32_t(c[0]), std::uint32_t(c[1]), std::uint32_t(c[2])};
    std::sort(k.begin(), k.end());
    if (std::binary_search(input_faces.begin(), input_faces.end(), k)) continue;
    ++new_faces;
    if (angle < 10) ++below_10;
    if (angle < 20) ++below_20;
  }
  if (m.number_of_faces() == 0) min_angle = 0;
}

/// Check 5: distinct vertices of the outputs (A2 and B2; or one mesh), in doubles as written, are
/// at least min_vertex_separation x the diagonal of their common bounding box apart (TetGen takes
/// closer points for one: its -T tolerance, 1e-8 of that diagonal by default). Pairs that close in
/// the inputs are counted apart; `subject` names the outputs in the problem.
template <class K>
void check_vertex_separation(std::initializer_list<const Mesh<K>*> input_meshes,
                             std::initializer_list<const MeshView<K>*> outputs, PairCheckReport& report,
                             const char* subject) {
  // Pairs of vertices of the inputs themselves are not the outputs' doing: counted apart.
  std::vector<std::array<double, 3>> inputs;  // sorted, for binary_search
  for (const Mesh<K>* m : input_meshes)
    for (auto v : m->vertices()) {
      const auto q = to_filtered(m->point(v));
      inputs.push_back({q.x(), q.y(), q.z()});
    }
  std::sort(inputs.begin(), inputs.end());
  const auto in_inputs = [&](const std::array<double, 3>& p) { return std::binary_search(inputs.begin(), inputs.end(), p); };
  std::vector<std::array<double, 3>> points;
  CGAL::Bbox_3 box;
  for (const MeshView<K>* view : outputs)
    for (auto v : view->mesh.vertices()) {
      const auto q = to_filtered(view->mesh.point(v));
      points.push_back({q.x(), q.y(), q.z()});
      box += q.bbox();
    }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                    CGAL::square(box.zmax() - box.zmin()));
  const double r = min_vertex_separation * diagonal;
  report.min_separation = r;
  std::vector<Box> boxes;
  boxes.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    boxes.emplace_back(CGAL::Bbox_3(p[0] - r, p[1] - r, p[2] - r, p[0] + r, p[1] + r, p[2] + r), std::uint32_t(i));
  }
  std::size_t count = 0;
  std::string first;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    const auto &p = points[x.info()], &q = points[y.info()];
    const double d = std::sqrt(CGAL::square(p[0] - q[0]) + CGAL::square(p[1] - q[1]) + CGAL::square(p[2] - q[2]));
    if (d >= r) return;
    if (in_inputs(p) && in_inputs(q)) {
      ++report.close_vertex_pairs_in_inputs;
      return;
    }
    if (count < 1000) {
      report.close_vertex_points.push_back(p);
      report.close_vertex_points.push_back(q);
    }
    if (count++ == 0)
      first = say("(", p[0], ", ", p[1], ", ", p[2], ") and (", q[0], ", ", q[1], ", ", q[2], "), ", d, " apart");
  }, box_cutoff);
  report.close_vertex_pairs = count;
  if (count)
    report.problems.push_back(say(count, " pairs of distinct vertices of ", subject, " are closer than ", r,
                                  " (", min_vertex_separation,
                                  " of the diagonal: a volume mesher such as TetGen takes them for one point; first: ",
                                  first, ")"));
}

/// One box per face of the mesh, of its corners rounded to doubles, with its face index.
template <class K> std::vector<Box> boxes_in_doubles(const Mesh<K>& m) {
  std::vector<Box> boxes;
  boxes.reserve(m.number_of_faces());
  for (auto f : m.faces()) {
    const auto c = corners_in_doubles<K>(m, f);
    boxes.emplace_back(c[0].bbox() + c[1].bbox() + c[2].bbox(), std::uint32_t(f));
  }
  return boxes;
}

/// How far from the curves check 6 allows a sample of the intersection of faces s and t: tol
/// where they are coplanar (a flat contact does not move), else 2 tol / sin(angle between them),
/// how far their line of intersection moves when each face moves by tol (a grazing crossing moves
/// far along the surfaces when snapping moves them a little). The sine in doubles.
double coverage_allowance(const Exact::Triangle_3& s, const Exact::Triangle_3& t, double tol) {
  if (CGAL::coplanar(s[0], s[1], s[2], t[0]) && CGAL::coplanar(s[0], s[1], s[2], t[1]) &&
      CGAL::coplanar(s[0], s[1], s[2], t[2]))
    return tol;
  auto normal = [](const Exact::Triangle_3& x) {
    const Filtered::Point_3 p = to_filtered(x[0]), q = to_filtered(x[1]), r = to_filtered(x[2]);
    return CGAL::cross_product(q - p, r - p);
  };
  const auto u = normal(s), v = normal(t);
  const double sine = std::sqrt(CGAL::cross_product(u, v).squared_length() / (u.squared_length() * v.squared_length()));
  return sine > 0 ? 2 * tol / sine : std::numeric_limits<double>::infinity();
}

/// The samples of an exact intersection of two triangles, rounded to doubles, passed to `sample`:
/// a point; a segment's ends and middle; a triangle's corners and centroid; a polygon's corners
/// and the mean of their rounded positions.
template <class Meet, class Sample> void sample_intersection(const Meet& meet, Sample&& sample) {
  using FP = Filtered::Point_3;
  using EP = Exact::Point_3;
  auto rounded = [](const EP& p) { return FP(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())); };
  if (const EP* p = boost::get<EP>(&meet)) {
    sample(rounded(*p));
  } else if (const auto* g = boost::get<Exact::Segment_3>(&meet)) {
    sample(rounded(g->source()));
    sample(rounded(g->target()));
    sample(rounded(CGAL::midpoint(g->source(), g->target())));
  } else if (const auto* u = boost::get<Exact::Triangle_3>(&meet)) {
    for (int j = 0; j < 3; ++j) sample(rounded(u->vertex(j)));
    sample(rounded(CGAL::centroid(u->vertex(0), u->vertex(1), u->vertex(2))));
  } else if (const auto* poly = boost::get<std::vector<EP>>(&meet)) {
    double x0 = 0, y0 = 0, z0 = 0;
    for (const auto& q : *poly) {
      const FP r = rounded(q);
      sample(r);
      x0 += r.x(), y0 += r.y(), z0 += r.z();
    }
    if (!poly->empty()) {
      const double n = double(poly->size());
      sample(FP(x0 / n, y0 / n, z0 / n));
    }
  }
}

/// Check 6: the curves cover the intersection of the inputs. Every face pair of A and B that
/// meets is intersected exactly (Epeck, on the input coordinates as doubles: a rounded
/// construction can put a touching point far off in a degenerate configuration) and sampled (a
/// point; a segment's ends and middle; a flat contact's corners and centroid), the samples
/// rounded to doubles; each must lie within tol of a curve or of a shared face of the outputs.
///
/// The pairs whose boxes overlap are listed first (in box_intersection_d's order), then
/// intersected and sampled in blocks on all cores, and the blocks' findings are taken in that
/// order: the report is the same as one pass in order would give. Each pair's exact triangles are
/// its own, made from the doubles, so that no lazy number is shared between threads (and none is
/// refined by another pair's test: the rounded samples do not depend on the threads' order).
template <class K>
void check_coverage(const Mesh<K>& a, const Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                    const std::vector<Filtered::Triangle_3>& shared_triangles, double tol, PairCheckReport& report) {
  using FP = Filtered::Point_3;
  using FT3 = Filtered::Triangle_3;
  using FS = Filtered::Segment_3;
  using EP = Exact::Point_3;
  using ET3 = Exact::Triangle_3;
  // The faces' boxes in doubles (the same as the exact triangles' boxes: the corners are doubles).
  std::vector<Box> boxes_a = boxes_in_doubles<K>(a), boxes_b = boxes_in_doubles<K>(b);
  auto triangle_in_doubles = [](const Mesh<K>& m, std::uint32_t f) {
    const auto c = corners_in_doubles<K>(m, typename Mesh<K>::Face_index(f));
    return FT3(c[0], c[1], c[2]);
  };
  auto exact = [](const FT3& t) {
    auto point = [](const FP& p) { return EP(p.x(), p.y(), p.z()); };
    return ET3(point(t[0]), point(t[1]), point(t[2]));
  };
  std::vector<FS> segments;
  std::vector<FP> lone_points;  // curves of one point (an isolated contact)
  CGAL::Bbox_3 box;
  for (const auto& c : curves) {
    if (c.size() == 1) lone_points.push_back(to_filtered(c.front()));
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const FP p = to_filtered(c[i]), q = to_filtered(c[i + 1]);
      if (p == q)
        lone_points.push_back(p);
      else
        segments.emplace_back(p, q);
    }
  }
  for (const auto* boxes : {&boxes_a, &boxes_b})
    for (const Box& x : *boxes) box += x.bbox();
  const double scale = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                 CGAL::square(box.zmax() - box.zmin()));
  const double slack = 1e-12 * (scale + 1.0);  // rounding of the samples and the distances
  using SegmentTree = CGAL::AABB_tree<
      CGAL::AABB_traits<Filtered, CGAL::AABB_segment_primitive<Filtered, std::vector<FS>::const_iterator>>>;
  using TriangleTree = CGAL::AABB_tree<
      CGAL::AABB_traits<Filtered, CGAL::AABB_triangle_primitive<Filtered, std::vector<FT3>::const_iterator>>>;
  SegmentTree segment_tree(segments.begin(), segments.end());
  TriangleTree shared_tree(shared_triangles.begin(), shared_triangles.end());
  // Both trees and their search trees built here, before the threads query them (CGAL would
  // build them at the first query, under a lock).
  if (!segments.empty()) segment_tree.build(), segment_tree.accelerate_distance_queries();
  if (!shared_triangles.empty()) shared_tree.build(), shared_tree.accelerate_distance_queries();
  auto distance = [&](const FP& p) {
    double d2 = std::numeric_limits<double>::infinity();
    if (!segments.empty()) d2 = std::min(d2, segment_tree.squared_distance(p));
    if (!shared_triangles.empty()) d2 = std::min(d2, shared_tree.squared_distance(p));
    for (const auto& q : lone_points) d2 = std::min(d2, CGAL::squared_distance(p, q));
    return std::sqrt(d2);
  };

  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  CGAL::box_intersection_d(boxes_a.begin(), boxes_a.end(), boxes_b.begin(), boxes_b.end(),
                           [&](const Box& x, const Box& y) { pairs.emplace_back(x.info(), y.info()); }, box_cutoff);

  struct Uncovered {
    FP p;
    double distance, allowed;
  };
  struct Block {  // what a block of pairs found: its first uncovered sample in the pairs' order
    std::size_t samples = 0, uncovered = 0;
    std::optional<Uncovered> first;
    double max_distance = 0;
  };
  constexpr std::size_t block_size = 256;
  std::vector<Block> blocks((pairs.size() + block_size - 1) / block_size);
  tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t k) {
    Block& block = blocks[k];
    double allowed = tol;  // for the pair of faces being sampled: coverage_allowance
    auto sample = [&](const FP& p) {
      ++block.samples;
      const double d = distance(p);
      if (d <= allowed + slack) return;
      if (block.uncovered++ == 0) block.first = Uncovered{p, d, allowed};
      block.max_distance = std::max(block.max_distance, d);
    };
    for (std::size_t i = k * block_size; i < std::min(pairs.size(), (k + 1) * block_size); ++i) {
      // Whether they meet: Epick's exact predicates on the doubles (the exact triangles are made
      // only for the pairs that meet, most do not).
      const FT3 fs = triangle_in_doubles(a, pairs[i].first), ft = triangle_in_doubles(b, pairs[i].second);
      if (!CGAL::do_intersect(fs, ft)) continue;
      const ET3 s = exact(fs), t = exact(ft);
      const auto meet = CGAL::intersection(s, t);
      if (!meet) continue;
      allowed = coverage_allowance(s, t, tol);
      sample_intersection(*meet, sample);
    }
  });

  std::string first;
  for (const Block& block : blocks) {
    report.intersection_samples += block.samples;
    if (block.first && report.uncovered_samples == 0)
      first = say(point_text(block.first->p), ", ", block.first->distance, " from the curves (allowed there: ",
                  block.first->allowed, ")");
    report.uncovered_samples += block.uncovered;
    report.max_uncovered_distance = std::max(report.max_uncovered_distance, block.max_distance);
  }
  if (report.uncovered_samples)
    report.problems.push_back(say(report.uncovered_samples,
                                  " points of the intersection of A and B are farther than the tolerance ", tol,
                                  " (2 tol / sin of the faces' angle where they cross) from the curves and the shared",
                                  " faces: parts of the intersection are missing from the curves (first: ", first,
                                  "; largest distance ", report.max_uncovered_distance, ")"));
}

}  // namespace

namespace {

/// Shared faces: a face of A2 whose three corners are the corners of a face of B2 (exact
/// coordinates). Where the surfaces coincide (a flat contact) both must hold one common
/// triangulation, so the faces there are shared and the merged outputs are a valid PLC.
template <class K>
void mark_shared_faces(MeshView<K>& va, MeshView<K>& vb, const std::vector<std::uint32_t>& b_to_a,
                       std::vector<char>& shared_a, std::vector<char>& shared_b, PairCheckReport& report) {
  using F = typename Mesh<K>::Face_index;
  std::map<std::array<std::uint32_t, 3>, F> a_faces;
  for (auto f : va.mesh.faces()) {
    const auto c = va.corners(f);
    std::array<std::uint32_t, 3> key = {std::uint32_t(c[0]), std::uint32_t(c[1]), std::uint32_t(c[2])};
    std::sort(key.begin(), key.end());
    a_faces.emplace(key, f);
  }
  for (auto g : vb.mesh.faces()) {
    const auto c = vb.corners(g);
    std::array<std::uint32_t, 3> key;
    bool all = true;
    for (int k = 0; k < 3; ++k) all = all && (key[k] = b_to_a[std::size_t(c[k])]) != none;
    if (!all) continue;
    std::sort(key.begin(), key.end());
    const auto it = a_faces.find(key);
    if (it == a_faces.end()) continue;
    shared_a[std::size_t(it->second)] = shared_b[std::size_t(g)] = 1;
    ++report.shared_faces;
  }
}

/// Check 2: every curve point is a vertex, and every curve segment an edge, of both outputs (with
/// identical coordinates; of `va` only when `vb` is null). Returns the curve points; `curve_edges_a` gets the curve segments as
/// pairs of A2 vertex indices (both ends present in A2), smaller index first.
template <class K>
std::set<typename K::Point_3, PointLess> check_curves_present(const std::vector<Polyline<K>>& curves, MeshView<K>& va,
                                                              MeshView<K>* vb,
                                                              std::set<std::pair<std::uint32_t, std::uint32_t>>& curve_edges_a,
                                                              PairCheckReport& report) {
  using M = Mesh<K>;
  using Point = typename K::Point_3;
  using V = typename M::Vertex_index;
  std::set<Point, PointLess> curve_points;
  auto& problems = report.problems;
  report.curves = curves.size();
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto& pts = curves[c];
    if (pts.empty()) continue;
    report.curve_vertices += pts.size() - (is_closed(pts) ? 1 : 0);
    if (pts.size() >= 2) report.curve_segments += pts.size() - 1;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i)
      if (pts[i] == pts[i + 1]) problems.push_back(say("curve ", c, " segment ", i, " has zero length at ", point_text(pts[i])));
    curve_points.insert(pts.begin(), pts.end());
  }
  for (MeshView<K>* view : {&va, vb}) {
    if (!view || !view->structure_ok) continue;
    std::size_t missing_points = 0, missing_edges = 0;
    std::string first_point, first_edge;
    for (std::size_t c = 0; c < curves.size(); ++c) {
      const auto& pts = curves[c];
      std::vector<V> vs(pts.size(), M::null_vertex());
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto it = view->vertex_at.find(pts[i]);
        if (it != view->vertex_at.end()) {
          vs[i] = it->second;
        } else if (!(is_closed(pts) && i + 1 == pts.size()) && missing_points++ == 0) {
          first_point = say("curve ", c, " point ", i, " at ", point_text(pts[i]));
        }
      }
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        if (vs[i] == M::null_vertex() || vs[i + 1] == M::null_vertex() || vs[i] == vs[i + 1]) continue;
        if (view->mesh.halfedge(vs[i], vs[i + 1]) == M::null_halfedge()) {
          if (missing_edges++ == 0)
            first_edge = say("curve ", c, " segment ", i, " from ", point_text(pts[i]), " to ", point_text(pts[i + 1]));
        } else if (view == &va) {
          const auto u = std::uint32_t(vs[i]), w = std::uint32_t(vs[i + 1]);
          curve_edges_a.emplace(std::min(u, w), std::max(u, w));
        }
      }
    }
    if (missing_points)
      problems.push_back(say(view->name, ": ", missing_points,
                             " curve points are not vertices with identical coordinates (first: ", first_point, ")"));
    if (missing_edges)
      problems.push_back(say(view->name, ": ", missing_edges, " curve segments are not edges (first: ", first_edge, ")"));
  }

  return curve_points;
}

/// Check 3: A2 and B2 meet only along the curves, or where both faces are shared (one common
/// triangulation of a flat contact); with `restricted`, only the pairs with a face in focus.
/// Returns which faces of A2 are shared (for check 6).
template <class K>
std::vector<char> check_no_intersection_off_curves(MeshView<K>& va, MeshView<K>& vb,
                                                   const std::set<typename K::Point_3, PointLess>& curve_points,
                                                   const std::set<std::pair<std::uint32_t, std::uint32_t>>& curve_edges_a,
                                                   bool restricted, const std::vector<char>* focus_a,
                                                   const std::vector<char>* focus_b, PairCheckReport& report) {
  using F = typename Mesh<K>::Face_index;
  auto& problems = report.problems;
  // B2 vertex -> A2 vertex at the same point; A2 vertices that are curve points.
  std::vector<std::uint32_t> b_to_a(vb.vertex_slots(), none);
  for (auto v : vb.mesh.vertices()) {
    const auto it = va.vertex_at.find(vb.mesh.point(v));
    if (it != va.vertex_at.end()) b_to_a[std::size_t(v)] = std::uint32_t(it->second);
  }
  std::vector<char> on_curve_a(va.vertex_slots(), 0);
  for (const auto& p : curve_points) {
    const auto it = va.vertex_at.find(p);
    if (it != va.vertex_at.end()) on_curve_a[std::size_t(it->second)] = 1;
  }
  std::vector<char> shared_a(va.face_slots(), 0), shared_b(vb.face_slots(), 0);
  mark_shared_faces(va, vb, b_to_a, shared_a, shared_b, report);
  std::vector<std::string> examples;
  auto off_curve = [&](F fa, F fb, const char* why) {
    report.conflict_faces_a.push_back(std::size_t(fa));
    report.conflict_faces_b.push_back(std::size_t(fb));
    if (report.intersecting_face_pairs_off_curve++ < max_examples)
      examples.push_back(say("A2 face ", std::size_t(fa), " / B2 face ", std::size_t(fb), " ", why));
  };
  // Corners at the same point: ia[k] is the corner of fa equal to corner k of fb, or -1.
  auto common_corners = [&](const auto& ca, const auto& cb, int (&ia)[3]) {
    int shared = 0;
    for (int k = 0; k < 3; ++k) {
      ia[k] = -1;
      const std::uint32_t w = b_to_a[std::size_t(cb[k])];
      if (w == none) continue;
      for (int j = 0; j < 3; ++j)
        if (std::uint32_t(ca[j]) == w) {
          ia[k] = j;
          ++shared;
        }
    }
    return shared;
  };
  // The pairs whose boxes overlap, in box_intersection_d's order; how each pair meets is decided
  // in blocks on all cores (each answer depends on that pair's corners only; under the exact
  // kernel every point that is not a double was made exact first, see check_pair_unguarded, so
  // no thread refines a number another reads), then the pairs are counted and reported in that
  // order.
  std::vector<std::pair<F, F>> pairs;
  auto collect = [&](const Box& box_a, const Box& box_b) { pairs.emplace_back(F(box_a.info()), F(box_b.info())); };
  if (restricted) {
    // The pairs with a face in focus: A2's in focus against all of B2, the rest of A2 against
    // B2's in focus.
    std::vector<Box> focused_a = face_boxes(va, focus_a, 1), all_b = face_boxes(vb);
    CGAL::box_intersection_d(focused_a.begin(), focused_a.end(), all_b.begin(), all_b.end(), collect, box_cutoff);
    std::vector<Box> rest_a = face_boxes(va, focus_a, 0), focused_b = face_boxes(vb, focus_b, 1);
    CGAL::box_intersection_d(rest_a.begin(), rest_a.end(), focused_b.begin(), focused_b.end(), collect, box_cutoff);
  } else {
    std::vector<Box> boxes_a = face_boxes(va), boxes_b = face_boxes(vb);
    CGAL::box_intersection_d(boxes_a.begin(), boxes_a.end(), boxes_b.begin(), boxes_b.end(), collect, box_cutoff);
  }
  std::vector<Meet> meets(pairs.size(), Meet::apart);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto ca = va.corners(pairs[i].first), cb = vb.corners(pairs[i].second);
      int ia[3];
      const int shared = common_corners(ca, cb, ia);
      if (shared < 3) meets[i] = meet<K>(va.geometry(ca), vb.geometry(cb), ia, shared);
    }
  });
  report.candidate_face_pairs += pairs.size();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    // Apart, or the same triangle (a shared face, counted above; left apart in `meets`): nothing.
    if (meets[i] == Meet::apart) continue;
    const auto [fa, fb] = pairs[i];
    const auto ca = va.corners(fa), cb = vb.corners(fb);
    int ia[3];
    const int shared = common_corners(ca, cb, ia);
    // Two shared faces may meet in any common vertex or edge (inside a flat contact); every
    // other meeting must be a curve point or segment.
    const bool both_shared = shared_a[std::size_t(fa)] && shared_b[std::size_t(fb)];
    switch (meets[i]) {
      case Meet::apart:  // (skipped above)
        break;
      case Meet::beyond:
        off_curve(fa, fb,
                  coplanar_faces(va.geometry(ca), vb.geometry(cb))
                      ? "overlap in a common plane (a flat contact that is not one common triangulation)"
                      : beyond_text(shared));
        break;
      case Meet::at_vertex: {
        int k = 0;
        while (ia[k] < 0) ++k;
        if (on_curve_a[std::size_t(ca[ia[k]])] || both_shared)
          ++report.face_pairs_on_curve;
        else
          off_curve(fa, fb, "touch at a vertex that is not a curve point");
        break;
      }
      case Meet::along_edge: {
        int k = 0;
        while (ia[k] >= 0) ++k;
        const auto u = std::uint32_t(ca[ia[(k + 1) % 3]]), w = std::uint32_t(ca[ia[(k + 2) % 3]]);
        if (curve_edges_a.count({std::min(u, w), std::max(u, w)}) || both_shared)
          ++report.face_pairs_on_curve;
        else
          off_curve(fa, fb, "share an edge that is not a curve segment");
        break;
      }
    }
  }
  if (report.intersecting_face_pairs_off_curve) {
    std::string list;
    for (const auto& e : examples) list += (list.empty() ? "" : "; ") + e;
    if (report.intersecting_face_pairs_off_curve > examples.size()) list += "; ...";
    problems.push_back(say("A2 and B2 intersect off the curves: ", report.intersecting_face_pairs_off_curve,
                           " face pairs (", list, ")"));
  }
  return shared_a;
}

template <class K>
PairCheckReport check_pair_unguarded(const Mesh<K>& a, const Mesh<K>& b, const Mesh<K>& a2, const Mesh<K>& b2,
                                     const std::vector<Polyline<K>>& curves, double tol, const CheckFocus* focus,
                                     bool separation) {
  // Faces are restricted only when some are marked: an empty focus restricts nothing (and still
  // leaves check 4 and the figures to the caller).
  const bool restricted = focus && !(focus->faces_a.empty() && focus->faces_b.empty());
  const std::vector<char>* focus_a = restricted ? &focus->faces_a : nullptr;
  const std::vector<char>* focus_b = restricted ? &focus->faces_b : nullptr;
  PairCheckReport report;
  auto& problems = report.problems;
  // Under the exact kernel, the points that are not doubles made exact first (serially): the
  // checks then read them on several threads, and a number refined by one thread's test while
  // another reads it would make the roundings (checks 4 and 5) depend on the threads' order.
  for (const Mesh<K>* m : {&a, &b, &a2, &b2})
    for (auto v : m->vertices()) fix_rounding(m->point(v));
  report.tolerance = tol;
  report.vertices_a2 = a2.number_of_vertices();
  report.faces_a2 = a2.number_of_faces();
  report.vertices_b2 = b2.number_of_vertices();
  report.faces_b2 = b2.number_of_faces();

  // ------------------------------------------------------------ 1. valid meshes
  // The two meshes' checks are independent: run side by side, their problems listed A2's first.
  MeshView<K> va(a2, "A2"), vb(b2, "B2");
  {
    std::vector<std::string> problems_b;
    tbb::parallel_invoke([&] { check_mesh(va, CGAL::is_closed(a), problems, report.conflict_faces_a, focus_a); },
                         [&] { check_mesh(vb, CGAL::is_closed(b), problems_b, report.conflict_faces_b, focus_b); });
    problems.insert(problems.end(), problems_b.begin(), problems_b.end());
  }

  // ------------------------------------------------------------ 2. curves present in both
  std::set<std::pair<std::uint32_t, std::uint32_t>> curve_edges_a;
  const auto curve_points = check_curves_present<K>(curves, va, &vb, curve_edges_a, report);

  // ------------------------------------------------------------ 3. no intersection off the curves
  std::vector<char> shared_faces_a;  // per A2 face index: a shared face (kept for check 6)
  if (va.structure_ok && vb.structure_ok)
    shared_faces_a = check_no_intersection_off_curves<K>(va, vb, curve_points, curve_edges_a, restricted, focus_a,
                                                         focus_b, report);

  for (auto* faces : {&report.conflict_faces_a, &report.conflict_faces_b}) {
    std::sort(faces->begin(), faces->end());
    faces->erase(std::unique(faces->begin(), faces->end()), faces->end());
  }

  if (focus) return report;  // checks 4-6 and the figures are the caller's

  // Checks 5 and 4 beside check 6 (independent; each writes its own fields), their problems
  // listed in the order 5, 6, 4.
  PairCheckReport coverage;  // check 6's fields and problems
  std::size_t after_separation = 0;
  tbb::parallel_invoke(
      [&] {
        // ---------------------------------------------------------- 5. vertices apart
        if (va.structure_ok && vb.structure_ok && separation) check_vertex_separation<K>({&a, &b}, {&va, &vb}, report, "A2 and B2");
        after_separation = problems.size();
        // ---------------------------------------------------------- 4. within tol of the inputs + quality
        if (va.structure_ok)
          check_against_input(a, va, tol, report.max_distance_a, report.min_angle_deg_a, report.below_10_a,
                              report.below_20_a, report.new_faces_a, problems);
        if (vb.structure_ok)
          check_against_input(b, vb, tol, report.max_distance_b, report.min_angle_deg_b, report.below_10_b,
                              report.below_20_b, report.new_faces_b, problems);
      },
      [&] {
        // ---------------------------------------------------------- 6. coverage
        if (!(va.structure_ok && vb.structure_ok)) return;
        std::vector<Filtered::Triangle_3> shared_triangles;
        for (auto f : a2.faces())
          if (shared_faces_a[std::size_t(f)]) {
            const auto c = va.corners(f);
            shared_triangles.emplace_back(to_filtered(a2.point(c[0])), to_filtered(a2.point(c[1])),
                                          to_filtered(a2.point(c[2])));
          }
        check_coverage<K>(a, b, curves, shared_triangles, tol, coverage);
      });
  report.intersection_samples = coverage.intersection_samples;
  report.uncovered_samples = coverage.uncovered_samples;
  report.max_uncovered_distance = coverage.max_uncovered_distance;
  problems.insert(problems.begin() + std::ptrdiff_t(after_separation), coverage.problems.begin(),
                  coverage.problems.end());
  return report;
}

}  // namespace

template <class K>
PairCheckReport check_pair(const Mesh<K>& a, const Mesh<K>& b, const Mesh<K>& a2, const Mesh<K>& b2,
                           const std::vector<Polyline<K>>& curves, double tol, const CheckFocus* focus,
                           bool separation) {
  try {
    return check_pair_unguarded<K>(a, b, a2, b2, curves, tol, focus, separation);
  } catch (const CGAL::Failure_exception& e) {
    // Only where CGAL's assertions are compiled in (the fuzz build), and in practice only under
    // the float kernel, whose rounded predicates can contradict a CGAL precondition (a coplanar
    // triangle test, say): the check could not be done.
    throw InternalError(std::string("check: a CGAL assertion failed (") + e.expression() + ")");
  }
}

namespace {

/// The largest distance from a point of `from` to the segments of `to` (doubles; 0 when either is
/// empty): points against an AABB tree of segments, so n log n.
template <class K> double largest_distance(const std::vector<Polyline<K>>& from, const std::vector<Polyline<K>>& to) {
  using FS = Filtered::Segment_3;
  using Primitive = CGAL::AABB_segment_primitive<Filtered, typename std::vector<FS>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Filtered, Primitive>>;
  std::vector<FS> segments;
  for (const auto& c : to)
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const auto p = to_filtered(c[i]), q = to_filtered(c[i + 1]);
      if (p != q) segments.emplace_back(p, q);
    }
  if (segments.empty()) return 0;
  Tree tree(segments.begin(), segments.end());
  tree.accelerate_distance_queries();
  double largest = 0;
  for (const auto& c : from)
    for (const auto& p : c) largest = std::max(largest, std::sqrt(tree.squared_distance(to_filtered(p))));
  return largest;
}

template <class K>
EmbedCheckReport check_embedding_unguarded(const Mesh<K>& input, const Mesh<K>& output,
                                           const std::vector<Polyline<K>>& curves, double tol,
                                           const std::vector<Polyline<K>>* given) {
  // The pair checks' fields, filled for one mesh, then copied over.
  PairCheckReport pr;
  pr.tolerance = tol;
  MeshView<K> view(output, "the output");
  check_mesh(view, CGAL::is_closed(input), pr.problems, pr.conflict_faces_a, nullptr);
  std::set<std::pair<std::uint32_t, std::uint32_t>> curve_edges;
  check_curves_present<K>(curves, view, nullptr, curve_edges, pr);
  double max_distance = 0, min_angle = 0;
  std::size_t below_10 = 0, below_20 = 0, new_faces = 0;
  if (view.structure_ok) {
    check_vertex_separation<K>({&input}, {&view}, pr, "the output");
    check_against_input(input, view, tol, max_distance, min_angle, below_10, below_20, new_faces, pr.problems);
  }
  EmbedCheckReport r;
  r.problems = std::move(pr.problems);
  r.curves = pr.curves;
  r.curve_vertices = pr.curve_vertices;
  r.curve_segments = pr.curve_segments;
  r.tolerance = tol;
  r.max_distance = max_distance;
  r.min_angle_deg = min_angle;
  r.new_faces = new_faces;
  r.below_10 = below_10;
  r.below_20 = below_20;
  r.vertices = output.number_of_vertices();
  r.faces = output.number_of_faces();
  r.min_separation = pr.min_separation;
  r.close_vertex_pairs = pr.close_vertex_pairs;
  r.close_vertex_pairs_in_input = pr.close_vertex_pairs_in_inputs;
  std::sort(pr.conflict_faces_a.begin(), pr.conflict_faces_a.end());
  pr.conflict_faces_a.erase(std::unique(pr.conflict_faces_a.begin(), pr.conflict_faces_a.end()),
                            pr.conflict_faces_a.end());
  r.conflict_faces = std::move(pr.conflict_faces_a);
  if (given) {
    r.given_to_embedded = largest_distance<K>(*given, curves);
    r.embedded_to_given = largest_distance<K>(curves, *given);
  }
  return r;
}

}  // namespace

template <class K>
EmbedCheckReport check_embedding(const Mesh<K>& input, const Mesh<K>& output, const std::vector<Polyline<K>>& curves,
                                 double tol, const std::vector<Polyline<K>>* given) {
  try {
    return check_embedding_unguarded<K>(input, output, curves, tol, given);
  } catch (const CGAL::Failure_exception& e) {
    throw InternalError(std::string("check: a CGAL assertion failed (") + e.expression() + ")");
  }
}

#define SEAM_INSTANTIATE(K)                                                                                  \
  template EmbedCheckReport check_embedding<K>(const Mesh<K>&, const Mesh<K>&, const std::vector<Polyline<K>>&, \
                                               double, const std::vector<Polyline<K>>*);                      \
  template PairCheckReport check_pair<K>(const Mesh<K>&, const Mesh<K>&, const Mesh<K>&, const Mesh<K>&, \
                                         const std::vector<Polyline<K>>&, double, const CheckFocus*, bool);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
