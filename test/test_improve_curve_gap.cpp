// Shortfall::curve_gap (src/improve/curve_gap.cpp): how close two curve segments with no common
// point come near a face left below the bound, the witness that the curves, at the feature size,
// force it. On a face and curves placed by hand, the gap is the distance between the right pair of
// segments; segments with a common point, and segments beyond the face's ball grown by the feature
// size, do not count.
#include <catch2/catch.hpp>

#include <seam/internal/improve_state.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using P = K::Point_3;

/// The gap measured for the one face of a mesh holding the triangle (0,0,0), (1,0,0), (0,1,0),
/// everything moved by `offset`.
double gap_at_the_face(const std::vector<std::vector<P>>& curves, double feature_size,
                       const K::Vector_3& offset = K::Vector_3(0, 0, 0)) {
  M mesh;
  const auto a = mesh.add_vertex(P(0, 0, 0) + offset), b = mesh.add_vertex(P(1, 0, 0) + offset),
             c = mesh.add_vertex(P(0, 1, 0) + offset);
  const auto f = mesh.add_face(a, b, c);
  std::vector<seam::internal::ImproveMesh<K>> meshes{{&mesh, &mesh, nullptr}};
  seam::internal::SharedCurves<K> shared;
  for (const auto& curve : curves) {
    shared.curves.emplace_back();
    for (const auto& p : curve) shared.curves.back().push_back(p + offset);
  }
  std::vector<seam::Shortfall> shortfalls{{0, std::size_t(f), 5.0, seam::ShortfallCause::feature_size, seam::ShortfallCause::feature_size}};
  seam::internal::measure_curve_gaps<K>(meshes, shared, feature_size, shortfalls);
  return shortfalls.front().curve_gap;
}

}  // namespace

TEST_CASE("improve: the curve gap of a face is the distance between its nearest two curve segments with no common point",
          "[improve]") {
  const double fs = 0.1;
  // Two parallel curves across the face, 0.05 apart: the gap is 0.05.
  CHECK(gap_at_the_face({{P(0, 0.2, 0), P(0.5, 0.2, 0), P(1, 0.2, 0)}, {P(0, 0.25, 0), P(0.5, 0.25, 0), P(1, 0.25, 0)}}, fs) ==
        Approx(0.05));
  // One curve bending back on itself: its segments two apart come within 0.03 (a lens), its
  // consecutive segments (a common point) do not count.
  CHECK(gap_at_the_face({{P(0.1, 0.1, 0), P(0.6, 0.1, 0), P(0.6, 0.13, 0), P(0.1, 0.13, 0)}}, fs) == Approx(0.03));
  // A straight curve alone: every two of its segments share a point or lie 0.2 apart.
  CHECK(gap_at_the_face({{P(0, 0.2, 0), P(0.2, 0.2, 0), P(0.4, 0.2, 0), P(0.6, 0.2, 0)}}, fs) == Approx(0.2));
  // Two curves meeting at a point (a junction): no gap from the segments that share it.
  CHECK(std::isinf(gap_at_the_face({{P(0.2, 0.2, 0), P(0.4, 0.2, 0)}, {P(0.2, 0.2, 0), P(0.4, 0.21, 0)}}, fs)));
  // A curve beyond the face's ball grown by the feature size does not count: the ball about the
  // centroid (1/3, 1/3) through (1, 0) has radius 0.745; with fs 0.1, a segment at z = 0.9 lies
  // beyond it, at z = 0.8 within.
  const std::vector<P> inside = {P(0.3, 0.3, 0), P(0.4, 0.3, 0)};
  CHECK(std::isinf(gap_at_the_face({inside, {P(0.3, 0.3, 0.9), P(0.4, 0.3, 0.9)}}, fs)));
  CHECK(gap_at_the_face({inside, {P(0.3, 0.3, 0.8), P(0.4, 0.3, 0.8)}}, fs) == Approx(0.8));
}

TEST_CASE("improve: the curve gap is the same wherever the face lies, for long segments and for faces much larger "
          "than the feature size", "[improve]") {
  const std::vector<std::vector<P>> parallel = {{P(0, 0.2, 0), P(0.5, 0.2, 0), P(1, 0.2, 0)},
                                                {P(0, 0.25, 0), P(0.5, 0.25, 0), P(1, 0.25, 0)}};
  // Moved to negative coordinates, across the grid's cells (and its 21-bit keys' wrap).
  for (const auto& offset : {K::Vector_3(-1000.37, -7.71, -3.03), K::Vector_3(-3e6, 2e6, 5e5)})
    CHECK(gap_at_the_face(parallel, 0.1, offset) == Approx(0.05));
  // One curve a single segment 200 long: cells of 200/16.
  CHECK(gap_at_the_face({{P(-100, 0.2, 0), P(100, 0.2, 0)}, {P(0, 0.25, 0), P(0.5, 0.25, 0), P(1, 0.25, 0)}}, 0.1) ==
        Approx(0.05));
  // A feature size 1e-4 of the face: its box spans some 10^10 cells, the segments are tried one by one.
  CHECK(gap_at_the_face(parallel, 1e-4) == Approx(0.05));
}
