// The quality stage where the curve's segments are shorter than twice the feature size (none
// can be split), as where a grazing pair's curves run dense on CT tows. A face whose off-center
// encroaches such a segment, or lands nearer than feature_size to a vertex, tries points nearer
// its shortest edge (seam/improve.h, step 2c). The contract after every such edit: the mesh
// valid and in its plane, its area kept, the curve's points vertices and its segments edges, and
// every new face next to the curve below the bound reported with a cause.
#include <catch2/catch.hpp>

#include <seam/internal/improve_state.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using P = K::Point_3;
using V = M::Vertex_index;
using F = M::Face_index;
using K2 = CGAL::Exact_predicates_inexact_constructions_kernel;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K2>;

/// The smallest angle of a face (degrees, doubles).
double min_angle(const M& mesh, F f) {
  std::array<K2::Point_3, 3> p;
  int i = 0;
  for (V v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
    const auto& q = mesh.point(v);
    p[std::size_t(i++)] = K2::Point_3(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
  }
  double best = 180;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
    best = std::min(best, std::acos(std::clamp(a * b / std::sqrt(a * a * (b * b)), -1.0, 1.0)) * 180 / M_PI);
  }
  return best;
}

}  // namespace

TEST_CASE("improve: curve segments too short to split, the contract kept after every nearer point", "[improve]") {
  const double feature_size = 0.02;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    INFO("seed " << seed);
    // The unit square in z = 0: a wavy open curve across it, its points 0.6 to 1.9 x feature_size
    // apart, and free points at least twice feature_size from every other point; the constrained
    // Delaunay triangulation of them all.
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::vector<K2::Point_2> curve;
    for (double x = 0; x < 1; x += feature_size * (0.6 + 1.3 * uniform(rng)))
      curve.emplace_back(x, 0.5 + 0.05 * std::sin(9 * x) + 0.004 * (uniform(rng) - 0.5));
    curve.emplace_back(1.0, 0.5 + 0.05 * std::sin(9.0));
    std::vector<K2::Point_2> free{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    auto apart = [&](const K2::Point_2& p) {
      for (const auto* set : {&curve, &free})
        for (const auto& q : *set)
          if (CGAL::squared_distance(p, q) < 4 * feature_size * feature_size) return false;
      return true;
    };
    for (int i = 0; i < 4000 && free.size() < 124; ++i)
      if (const K2::Point_2 p(uniform(rng), uniform(rng)); apart(p)) free.push_back(p);
    CDT cdt;
    std::vector<CDT::Vertex_handle> on_curve;
    for (const auto& p : curve) on_curve.push_back(cdt.insert(p));
    for (std::size_t i = 0; i + 1 < on_curve.size(); ++i) cdt.insert_constraint(on_curve[i], on_curve[i + 1]);
    for (const auto& p : free) cdt.insert(p);
    M mesh;
    std::map<CDT::Vertex_handle, V> vertex_of;
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
      vertex_of[v] = mesh.add_vertex(P(v->point().x(), v->point().y(), 0));
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
      REQUIRE(mesh.add_face(vertex_of[f->vertex(0)], vertex_of[f->vertex(1)], vertex_of[f->vertex(2)]) != M::null_face());
    const M input = mesh;
    std::set<std::array<V, 3>> input_faces;
    for (F f : input.faces()) {
      std::array<V, 3> c;
      int i = 0;
      for (V v : CGAL::vertices_around_face(input.halfedge(f), input)) c[std::size_t(i++)] = v;
      std::sort(c.begin(), c.end());
      input_faces.insert(c);
    }

    seam::internal::SharedCurves<K> curves;
    curves.curves.push_back({});
    curves.vertices = {{{}}};
    for (const auto& v : on_curve) {
      curves.curves[0].push_back(P(v->point().x(), v->point().y(), 0));
      curves.vertices[0][0].push_back(vertex_of[v]);
    }
    std::vector<seam::internal::ImproveMesh<K>> meshes{{&mesh, &input, nullptr}};
    seam::ImproveOptions options;
    options.tolerance = 0.01;
    options.feature_size = feature_size;
    const auto stats = seam::internal::improve<K>(meshes, curves, options);
    INFO("insertions " << stats.insertions << ", merges " << stats.merges << ", below " << stats.below_bound_after);

    // The contract: valid, in the plane, the area kept, the curve embedded.
    REQUIRE(mesh.is_valid(false));
    for (V v : mesh.vertices()) CHECK(CGAL::to_double(mesh.point(v).z()) == 0);
    CHECK(std::abs(CGAL::to_double(CGAL::Polygon_mesh_processing::area(mesh)) -
                   CGAL::to_double(CGAL::Polygon_mesh_processing::area(input))) < 1e-12);
    const auto& vs = curves.vertices[0][0];
    REQUIRE(vs.size() == curves.curves[0].size());
    std::set<V> curve_vertices(vs.begin(), vs.end());
    for (std::size_t i = 0; i < vs.size(); ++i) {
      CHECK(mesh.point(vs[i]) == curves.curves[0][i]);
      if (i + 1 < vs.size()) CHECK(mesh.halfedge(vs[i], vs[i + 1]) != M::null_halfedge());
    }
    // The stage improved the band, and reports every new face next to the curve still below the
    // bound, each with a cause the stage can name (no budget ran out here).
    CHECK(stats.below_bound_after < stats.below_bound_before);
    std::set<std::size_t> reported;
    for (const auto& s : stats.shortfalls) {
      reported.insert(s.face);
      CHECK(s.min_angle_deg < options.min_angle_deg);
      CHECK(s.cause != seam::ShortfallCause::budget);
    }
    for (F f : mesh.faces()) {
      std::array<V, 3> c;
      int i = 0;
      bool touches_curve = false;
      for (V v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        c[std::size_t(i++)] = v;
        touches_curve = touches_curve || curve_vertices.count(v) > 0;
      }
      std::sort(c.begin(), c.end());
      if (touches_curve && !input_faces.count(c) && min_angle(mesh, f) < options.min_angle_deg - 1e-9)
        CHECK(reported.count(std::size_t(f)) == 1);
    }
  }
}
