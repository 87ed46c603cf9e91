// Tests of the flat-contact step (seam/internal/flat_contacts.h): two meshes that coincide over a
// plane come out with one common triangulation there, refined to the angle bound, with the
// curves (its border) still edges of both, the surfaces unchanged, and the faces beyond a split
// border edge cut in their own plane.
#include <catch2/catch.hpp>

#include <seam/improve.h>
#include <seam/internal/flat_contacts.h>
#include <seam/kernels.h>
#include <seam/quality.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

namespace {

using K = seam::Exact;
using Mesh = seam::Mesh<K>;
using V = Mesh::Vertex_index;
using P = K::Point_3;

/// The rectangle [0, 1] x [0, height] at z = 0 with `n` points on each side (its border,
/// counterclockwise from the origin), cut into a fan of triangles from the inner point `apex`.
/// Returns the border vertices in order.
std::vector<V> add_rectangle_fan(Mesh& m, int n, std::array<double, 2> apex, double height = 1) {
  std::vector<V> border;
  const std::array<std::array<double, 2>, 4> corner = {{{0, 0}, {1, 0}, {1, height}, {0, height}}};
  for (int side = 0; side < 4; ++side)
    for (int i = 0; i < n; ++i) {
      const auto& s = corner[std::size_t(side)];
      const auto& e = corner[std::size_t((side + 1) % 4)];
      const double t = double(i) / n;
      border.push_back(m.add_vertex(P(s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1]), 0)));
    }
  const V centre = m.add_vertex(P(apex[0], apex[1], 0));
  for (std::size_t k = 0; k < border.size(); ++k) m.add_face(centre, border[k], border[(k + 1) % border.size()]);
  return border;
}

double smallest_angle(const Mesh& m) {
  double smallest = 180;
  for (auto f : m.faces()) {
    const auto h = m.halfedge(f);
    smallest = std::min(smallest, seam::min_angle_deg(seam::to_filtered(m.point(m.source(h))),
                                                      seam::to_filtered(m.point(m.target(h))),
                                                      seam::to_filtered(m.point(m.target(m.next(h))))));
  }
  return smallest;
}

/// The faces as sorted triples of corner points (doubles).
std::set<std::array<std::array<double, 3>, 3>> face_set(const Mesh& m) {
  std::set<std::array<std::array<double, 3>, 3>> faces;
  for (auto f : m.faces()) {
    std::array<std::array<double, 3>, 3> t;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      const auto q = seam::to_filtered(m.point(v));
      t[std::size_t(k++)] = {q.x(), q.y(), q.z()};
    }
    std::sort(t.begin(), t.end());
    faces.insert(t);
  }
  return faces;
}

/// Every curve point is the point of its vertex in the mesh, every segment an edge.
template <class KK>
void require_curves_embedded(const seam::Mesh<KK>& m, const std::vector<seam::Polyline<KK>>& curves,
                             const std::vector<std::vector<typename seam::Mesh<KK>::Vertex_index>>& vertices) {
  REQUIRE(curves.size() == vertices.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    REQUIRE(curves[c].size() == vertices[c].size());
    for (std::size_t k = 0; k < curves[c].size(); ++k) {
      CHECK(m.point(vertices[c][k]) == curves[c][k]);
      if (k + 1 < curves[c].size())
        CHECK(m.halfedge(vertices[c][k], vertices[c][k + 1]) != seam::Mesh<KK>::null_halfedge());
    }
  }
}

/// The closed curve through A's border vertices (B's at the same places), and the refinement of
/// the contact to 20 degrees with it.
template <class KK> struct ClosedBorder {
  using VV = typename seam::Mesh<KK>::Vertex_index;
  std::vector<seam::Polyline<KK>> curves = std::vector<seam::Polyline<KK>>(1);
  std::vector<std::vector<VV>> va = std::vector<std::vector<VV>>(1), vb = std::vector<std::vector<VV>>(1);
  ClosedBorder(const seam::Mesh<KK>& a, const std::vector<VV>& border_a, const std::vector<VV>& border_b) {
    for (std::size_t k = 0; k <= border_a.size(); ++k) {
      const std::size_t i = k % border_a.size();
      curves[0].push_back(a.point(border_a[i]));
      va[0].push_back(border_a[i]);
      vb[0].push_back(border_b[i]);
    }
  }
  seam::internal::FlatContactStats unify(seam::Mesh<KK>& a, seam::Mesh<KK>& b, double feature_size, double max_area = 0) {
    seam::internal::FlatContactOptions options;
    options.min_angle_deg = 20;
    options.feature_size = feature_size;
    options.max_area = max_area;
    return seam::internal::unify_flat_contacts<KK>(a, b, {curves, va, vb}, options);
  }
};

double area(const Mesh& m) { return CGAL::to_double(CGAL::Polygon_mesh_processing::area(m)); }

}  // namespace

TEST_CASE("flat contacts: two fans of one rectangle become one refined triangulation, its border curve split in both",
          "[flat_contacts]") {
  Mesh a, b;
  // Fans from points near opposite corners: thin triangles, crossing each other.
  const auto border_a = add_rectangle_fan(a, 6, {0.05, 0.02}, 0.3);
  const auto border_b = add_rectangle_fan(b, 6, {0.9, 0.28}, 0.3);
  REQUIRE(smallest_angle(a) < 10);
  // The border is the one curve both hold (closed: the first point repeated).
  ClosedBorder<K> border(a, border_a, border_b);
  const std::size_t curve_points_before = border.curves[0].size();
  const auto stats = border.unify(a, b, 0.01);
  CHECK(stats.patches == 1);
  CHECK(stats.patches_left == 0);
  CHECK(stats.points_dropped == 2);  // the fans' centres: points of one mesh only
  // One triangulation in both, covering the rectangle.
  CHECK(face_set(a) == face_set(b));
  CHECK(area(a) == Approx(0.3).epsilon(1e-12));
  CHECK(area(b) == Approx(0.3).epsilon(1e-12));
  CHECK(CGAL::is_valid_polygon_mesh(a));
  CHECK(CGAL::is_valid_polygon_mesh(b));
  // Ruppert's bound holds: the corners are right angles, the border may be split (the mesh
  // border lies beyond it), and nothing reaches the feature size here.
  CHECK(stats.shared_faces_below_bound == 0);
  CHECK(smallest_angle(a) >= 20.0);
  // The splits are curve points in both, in order along the border.
  CHECK(stats.border_splits > 0);
  CHECK(border.curves[0].size() == curve_points_before + stats.border_splits);
  require_curves_embedded<K>(a, border.curves, border.va);
  require_curves_embedded<K>(b, border.curves, border.vb);
}

TEST_CASE("flat contacts: with max_area every face of the common triangulation is at most that large, on a tilted plane",
          "[flat_contacts]") {
  // The fans of the first test, on the plane z = 0.5 x + 0.3 y: its faces are larger than their
  // projections along z by sqrt(1 + 0.25 + 0.09), which the area bound must see.
  const double max_area = 0.004, scale = std::sqrt(1 + 0.25 + 0.09);
  for (const bool bounded : {false, true}) {
    INFO((bounded ? "max_area 0.004" : "no area bound"));
    Mesh a, b;
    const auto border_a = add_rectangle_fan(a, 6, {0.05, 0.02}, 0.3);
    const auto border_b = add_rectangle_fan(b, 6, {0.9, 0.28}, 0.3);
    for (Mesh* m : {&a, &b})
      for (V v : m->vertices()) {
        const P q = m->point(v);
        m->point(v) = P(q.x(), q.y(), q.x() / 2 + q.y() * 3 / 10);
      }
    ClosedBorder<K> border(a, border_a, border_b);
    const auto stats = border.unify(a, b, 0.01, bounded ? max_area : 0);
    CHECK(stats.patches == 1);
    CHECK(face_set(a) == face_set(b));
    CHECK(area(a) == Approx(0.3 * scale).epsilon(1e-12));
    CHECK(CGAL::is_valid_polygon_mesh(a));
    CHECK(stats.shared_faces_below_bound == 0);
    CHECK(smallest_angle(a) >= 20.0);
    require_curves_embedded<K>(a, border.curves, border.va);
    require_curves_embedded<K>(b, border.curves, border.vb);
    double largest = 0;
    for (auto f : a.faces()) largest = std::max(largest, CGAL::to_double(CGAL::Polygon_mesh_processing::face_area(f, a)));
    INFO("largest face " << largest);
    if (bounded)
      CHECK(largest <= max_area * (1 + 1e-9));
    else
      CHECK(largest > max_area);  // (the case needs the bound)
  }
}

TEST_CASE("flat contacts: a split border edge cuts the faces beyond it in each mesh within their plane",
          "[flat_contacts]") {
  Mesh a, b;
  // A thin rectangle as fans of four triangles (6 degree angles) from two inner points.
  const auto border_a = add_rectangle_fan(a, 1, {0.3, 0.1}, 0.2);
  const auto border_b = add_rectangle_fan(b, 1, {0.7, 0.1}, 0.2);
  // Beyond the side y = 0 (border points 0 and 1): A rises, B falls (a face each).
  a.add_face(border_a[1], border_a[0], a.add_vertex(P(0.5, -0.1, 1)));
  b.add_face(border_b[1], border_b[0], b.add_vertex(P(0.5, -0.1, -1)));
  const double area_a = area(a), area_b = area(b);
  ClosedBorder<K> border(a, border_a, border_b);
  const auto stats = border.unify(a, b, 0.01);
  REQUIRE(stats.patches == 1);
  CHECK(CGAL::is_valid_polygon_mesh(a));
  CHECK(CGAL::is_valid_polygon_mesh(b));
  // The surfaces are the same: areas kept, the faces beyond still in their planes.
  CHECK(area(a) == Approx(area_a).epsilon(1e-12));
  CHECK(area(b) == Approx(area_b).epsilon(1e-12));
  std::size_t beyond_a = 0, beyond_b = 0;
  for (auto f : a.faces())
    for (auto v : CGAL::vertices_around_face(a.halfedge(f), a))
      if (a.point(v).z() > 0) ++beyond_a;
  for (auto f : b.faces())
    for (auto v : CGAL::vertices_around_face(b.halfedge(f), b))
      if (b.point(v).z() < 0) ++beyond_b;
  // Each face beyond has its apex off the plane; a split of y = 0 made more of them.
  std::size_t splits_on_side = 0;
  for (const auto& p : border.curves[0])
    if (p.y() == 0 && p.x() > 0 && p.x() < 1) ++splits_on_side;
  CHECK(splits_on_side > 0);
  CHECK(beyond_a == splits_on_side + 1);
  CHECK(beyond_b == splits_on_side + 1);
  for (auto f : a.faces()) {  // every face beyond lies in the plane of the one it was cut from
    const auto h = a.halfedge(f);
    const P &p = a.point(a.source(h)), &q = a.point(a.target(h)), &r = a.point(a.target(a.next(h)));
    if (p.z() > 0 || q.z() > 0 || r.z() > 0)
      for (const P& x : {p, q, r}) CHECK(CGAL::coplanar(x, P(0, 0, 0), P(1, 0, 0), P(0.5, -0.1, 1)));
  }
  require_curves_embedded<K>(a, border.curves, border.va);
  require_curves_embedded<K>(b, border.curves, border.vb);
  // The contact is one triangulation in both, refined to the bound.
  std::size_t shared = 0;
  const auto faces_b = face_set(b);
  for (const auto& t : face_set(a)) shared += faces_b.count(t);
  CHECK(shared == stats.shared_faces);
  CHECK(stats.shared_faces_below_bound == 0);
}

TEST_CASE("flat contacts: under the filtered kernel, with coordinates whose middles round off the segments, the "
          "faces beyond stay in their planes and turned as they were",
          "[flat_contacts]") {
  using KF = seam::Filtered;
  using MF = seam::Mesh<KF>;
  using PF = KF::Point_3;
  using VF = MF::Vertex_index;
  // The second case's thin rectangle, turned in its plane and moved to coordinates without short
  // binary expansions: the middles of its sides round off them.
  const double x0 = 0.1234567891234, y0 = 0.3141592653589, w = 1.0 / 3, h = 0.0712345678901;
  const double c = std::cos(0.4321), s = std::sin(0.4321);
  auto at = [&](double along, double across, double z) {
    return PF(x0 + along * c - across * s, y0 + along * s + across * c, z);
  };
  auto rectangle = [&](MF& m, double cx) {
    std::vector<VF> border = {m.add_vertex(at(0, 0, 0)), m.add_vertex(at(w, 0, 0)), m.add_vertex(at(w, h, 0)),
                              m.add_vertex(at(0, h, 0))};
    const VF centre = m.add_vertex(at(cx * w, h / 2, 0));
    for (std::size_t k = 0; k < 4; ++k) m.add_face(centre, border[k], border[(k + 1) % 4]);
    return border;
  };
  MF a, b;
  const auto border_a = rectangle(a, 0.3), border_b = rectangle(b, 0.7);
  const PF apex_a = at(w / 2, -h, 0.4), apex_b = at(w / 2, -h, -0.4);
  a.add_face(border_a[1], border_a[0], a.add_vertex(apex_a));
  b.add_face(border_b[1], border_b[0], b.add_vertex(apex_b));
  const auto normal_a = CGAL::normal(a.point(border_a[1]), a.point(border_a[0]), apex_a);
  const auto normal_b = CGAL::normal(b.point(border_b[1]), b.point(border_b[0]), apex_b);
  ClosedBorder<KF> border(a, border_a, border_b);
  const auto stats = border.unify(a, b, 0.001);
  REQUIRE(stats.patches == 1);
  CHECK(stats.refinement_failed.empty());
  CHECK(CGAL::is_valid_polygon_mesh(a));
  CHECK(CGAL::is_valid_polygon_mesh(b));
  // Every face beyond the contact (a corner off the plane) lies in its plane, turned as it was
  // (exact predicates on the doubles); every face of the contact is turned like the others.
  auto check_turns = [](const MF& m, const PF& apex, const KF::Vector_3& normal) {
    for (auto f : m.faces()) {
      const auto h = m.halfedge(f);
      const PF &p = m.point(m.source(h)), &q = m.point(m.target(h)), &r = m.point(m.target(m.next(h)));
      CHECK(!CGAL::collinear(p, q, r));
      if (p.z() != 0 || q.z() != 0 || r.z() != 0) {
        for (const PF& x : {p, q, r}) CHECK(CGAL::coplanar(x, p, q, apex));
        CHECK(CGAL::cross_product(q - p, r - p) * normal > 0);
      } else {
        CHECK(CGAL::orientation(PF(0, 0, 0), PF(1, 0, 0), PF(0, 1, 0), PF(0, 0, 1)) ==
              CGAL::orientation(p, q, r, PF(p.x(), p.y(), 1)));
      }
    }
  };
  check_turns(a, apex_a, normal_a);
  check_turns(b, apex_b, normal_b);
  require_curves_embedded<KF>(a, border.curves, border.va);
  require_curves_embedded<KF>(b, border.curves, border.vb);
}

TEST_CASE("flat contacts: faces a sharp corner of the border forces below the bound stay there, each with its reason",
          "[flat_contacts]") {
  // A contact whose border has an 8 degree corner at the origin (a triangle, its sides curves),
  // fanned from different inner points in A and B.
  const double angle = 8 * 3.14159265358979 / 180;
  const std::array<P, 3> corner = {P(0, 0, 0), P(1, 0, 0), P(std::cos(angle), std::sin(angle), 0)};
  auto fan = [&](Mesh& m, double along) {
    std::vector<V> border;
    for (const P& p : corner) border.push_back(m.add_vertex(p));
    const V centre = m.add_vertex(P(along, along * std::tan(angle / 2), 0));
    for (std::size_t k = 0; k < 3; ++k) m.add_face(centre, border[k], border[(k + 1) % 3]);
    return border;
  };
  Mesh a, b;
  const auto border_a = fan(a, 0.6), border_b = fan(b, 0.8);
  ClosedBorder<K> border(a, border_a, border_b);
  const auto stats = border.unify(a, b, 0.005);
  REQUIRE(stats.patches == 1);
  CHECK(face_set(a) == face_set(b));
  const auto [reason, has_reason] = a.property_map<Mesh::Face_index, std::uint8_t>(seam::internal::shared_reason_property);
  REQUIRE(has_reason);
  std::size_t below = 0;
  for (auto f : a.faces()) {
    const auto h = a.halfedge(f);
    const auto p = seam::to_filtered(a.point(a.source(h))), q = seam::to_filtered(a.point(a.target(h))),
               r = seam::to_filtered(a.point(a.target(a.next(h))));
    if (seam::min_angle_deg(p, q, r) >= 20) continue;
    ++below;
    // Forced by the corner: near it, and said so (two constraints meeting there, or points as
    // close as the feature size).
    const double from_corner = std::sqrt(CGAL::squared_distance(CGAL::centroid(p, q, r), seam::Filtered::Point_3(0, 0, 0)));
    CHECK(from_corner < 0.5);
    const int why = int(reason[f]) - 1;
    CHECK((why == int(seam::ShortfallCause::constraint_angle) || why == int(seam::ShortfallCause::feature_size)));
  }
  CHECK(below > 0);
  CHECK(below == stats.shared_faces_below_bound);
  require_curves_embedded<K>(a, border.curves, border.va);
  require_curves_embedded<K>(b, border.curves, border.vb);
}
