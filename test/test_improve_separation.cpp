// The quality stage on a hand-made pair: a free vertex closer than the vertex separation to a
// curve point (TetGen would take the two for one), with slivers between it and the curve, as on a
// CT tow against a copy moved along a grid plane. The stage's contract there: no such pair left,
// the curve in both meshes, the surface kept. (Here flips first reshape the vertex's star and a
// merge then takes it; on the CT pair the merge would make a flat face and the vertex is removed
// instead, see Refiner::merge_short_edge.)
#include <catch2/catch.hpp>

#include <seam/internal/improve_state.h>
#include <seam/check.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <cmath>
#include <vector>

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using P = K::Point_3;
using V = M::Vertex_index;

/// The smallest distance between two distinct vertices of the meshes (doubles).
double closest_vertex_pair(const std::vector<const M*>& meshes) {
  std::vector<P> points;
  for (const M* m : meshes)
    for (V v : m->vertices()) points.push_back(m->point(v));
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j)
      if (points[i] != points[j]) best = std::min(best, std::sqrt(CGAL::to_double(CGAL::squared_distance(points[i], points[j]))));
  return best;
}

}  // namespace

TEST_CASE("improve: a free vertex closer than the separation to a curve point goes, the contract kept",
          "[improve]") {
  // A: the plane z = 0, the curve along x = 0.5 (points c0..c4), a free vertex v 2e-9 to the
  // right of c2 and joined to every curve point: four slivers between v and the curve.
  const double e = 2e-9;
  M a;
  std::vector<V> ca, cb;
  for (int i = 0; i < 5; ++i) ca.push_back(a.add_vertex(P(0.5, 0.25 * i, 0)));
  const V l0 = a.add_vertex(P(0, 0, 0)), l1 = a.add_vertex(P(0, 1, 0)), r = a.add_vertex(P(1, 0.5, 0));
  const V v = a.add_vertex(P(0.5 + e, 0.5, 0));
  const V r0 = a.add_vertex(P(1, 0, 0)), r1 = a.add_vertex(P(1, 1, 0));
  for (const auto& f : std::vector<std::array<V, 3>>{{l0, ca[0], ca[1]},
                                                     {l0, ca[1], ca[2]},
                                                     {l0, ca[2], l1},
                                                     {l1, ca[2], ca[3]},
                                                     {l1, ca[3], ca[4]},
                                                     {v, r, ca[4]},
                                                     {v, ca[4], ca[3]},
                                                     {v, ca[3], ca[2]},
                                                     {v, ca[2], ca[1]},
                                                     {v, ca[1], ca[0]},
                                                     {v, ca[0], r},
                                                     {ca[0], r0, r},
                                                     {r, r1, ca[4]}})
    REQUIRE(a.add_face(f[0], f[1], f[2]) != M::null_face());
  // B: the plane x = 0.5 through the curve.
  M b;
  for (int i = 0; i < 5; ++i) cb.push_back(b.add_vertex(P(0.5, 0.25 * i, 0)));
  const V t0 = b.add_vertex(P(0.5, 0, 1)), t1 = b.add_vertex(P(0.5, 1, 1));
  const V d0 = b.add_vertex(P(0.5, 0, -1)), d1 = b.add_vertex(P(0.5, 1, -1));
  for (const auto& f : std::vector<std::array<V, 3>>{{t0, cb[1], cb[0]},
                                                     {t0, cb[2], cb[1]},
                                                     {t0, t1, cb[2]},
                                                     {t1, cb[3], cb[2]},
                                                     {t1, cb[4], cb[3]},
                                                     {d0, cb[0], cb[1]},
                                                     {d0, cb[1], cb[2]},
                                                     {d0, cb[2], d1},
                                                     {d1, cb[2], cb[3]},
                                                     {d1, cb[3], cb[4]}})
    REQUIRE(b.add_face(f[0], f[1], f[2]) != M::null_face());
  const M a0 = a, b0 = b;
  const double area_a = CGAL::to_double(CGAL::Polygon_mesh_processing::area(a));

  seam::internal::SharedCurves<K> curves;
  curves.curves.push_back({});
  for (int i = 0; i < 5; ++i) curves.curves[0].push_back(P(0.5, 0.25 * i, 0));
  curves.vertices = {{ca}, {cb}};
  std::vector<seam::internal::ImproveMesh<K>> meshes{{&a, &a0, nullptr}, {&b, &b0, nullptr}};
  seam::ImproveOptions options;
  options.tolerance = 0.01;
  options.min_angle_deg = 20;
  options.curves_fixed = true;  // (no curve splits: the slivers are mended by merges or not at all)
  options.min_separation = 2e-8 * std::sqrt(6.0);  // of the diagonal, as seam pair sets it
  REQUIRE(closest_vertex_pair({&a, &b}) < options.min_separation);
  const auto stats = seam::internal::improve<K>(meshes, curves, options);
  INFO("merges " << stats.merges << ", flips " << stats.flips << ", insertions " << stats.insertions);

  // No two distinct vertices closer than the separation, in one mesh or across the two.
  CHECK(closest_vertex_pair({&a, &b}) >= options.min_separation);
  // The contract: both meshes valid, the curve's points vertices of both and its segments edges
  // of both, A's area unchanged (every edit lies in its plane).
  REQUIRE(a.is_valid(false));
  REQUIRE(b.is_valid(false));
  REQUIRE(curves.curves.size() == 1);
  for (std::size_t m = 0; m < 2; ++m) {
    const M& g = m == 0 ? a : b;
    const auto& vs = curves.vertices[m][0];
    REQUIRE(vs.size() == curves.curves[0].size());
    for (std::size_t i = 0; i < vs.size(); ++i) {
      CHECK(g.point(vs[i]) == curves.curves[0][i]);
      if (i + 1 < vs.size()) CHECK(g.halfedge(vs[i], vs[i + 1]) != M::null_halfedge());
    }
  }
  CHECK(std::abs(CGAL::to_double(CGAL::Polygon_mesh_processing::area(a)) - area_a) < 1e-12);
  for (V x : a.vertices()) CHECK(CGAL::to_double(a.point(x).z()) == 0);
  // A2 and B2 meet only on the curve: seam check, independent of the stage, agrees.
  const auto report = seam::check_pair<K>(a0, b0, a, b, curves.curves, options.tolerance);
  for (const auto& problem : report.problems) UNSCOPED_INFO(problem);
  CHECK(report.ok());
}
