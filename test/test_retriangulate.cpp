// Tests of the re-triangulation of one face: constraints kept, refinement never harmful.
#include <catch2/catch.hpp>

#include <seam/internal/retriangulate.h>
#include <seam/quality.h>

#include <random>

namespace {

template <class K> double patch_min_angle(const seam::internal::FaceConstraints<K>& fc,
                                          const seam::internal::FacePatch<K>& patch,
                                          const std::vector<typename K::Point_3>& by_id) {
  auto point = [&](long r) { return r >= 0 ? by_id[std::size_t(r)] : patch.steiner_points[std::size_t(-r - 1)]; };
  double worst = 180;
  for (const auto& t : patch.triangles) worst = std::min(worst, seam::min_angle_deg(point(t[0]), point(t[1]), point(t[2])));
  (void)fc;
  return worst;
}

}  // namespace

TEMPLATE_TEST_CASE("retriangulate: refinement keeps every constraint and never makes the worst angle worse",
                   "[retriangulate]", seam::Exact, seam::Filtered) {
  using K = TestType;
  using P = typename K::Point_3;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.95), len(0.001, 0.3);
  for (int trial = 0; trial < 40; ++trial) {
    seam::internal::FaceConstraints<K> fc;
    fc.corner_ids = {0, 1, 2};
    fc.corners = {P(0, 0, 0), P(10, 0, 1), P(4, 9, 2)};  // a tilted face
    // a short curve segment somewhere inside (barycentric), and a crossing point on edge 0
    auto inside = [&](double s, double t) {
      if (s + t > 0.95) s *= 0.5, t *= 0.5;
      return fc.corners[0] + (fc.corners[1] - fc.corners[0]) * s + (fc.corners[2] - fc.corners[0]) * t;
    };
    const double s = u(rng) * 0.6, t = u(rng) * 0.6, d = len(rng);
    const P a = inside(s, t), b = inside(s + d * 0.05, t + d * 0.03);
    const P x = fc.corners[0] + (fc.corners[1] - fc.corners[0]) * u(rng);
    fc.interior_points = {{3, a}, {4, b}};
    fc.edge_points[0] = {{5, x}};
    fc.segments = {{3, 4}, {5, 3}};
    const std::vector<P> by_id = {fc.corners[0], fc.corners[1], fc.corners[2], a, b, x};

    seam::internal::RetriangulateOptions plain, refined;
    plain.min_angle_deg = 0;
    refined.min_angle_deg = 20;
    const auto p0 = seam::internal::retriangulate_face<K>(fc, plain);
    const auto p1 = seam::internal::retriangulate_face<K>(fc, refined);
    CHECK(p0.steiner_points.empty());
    CHECK(patch_min_angle<K>(fc, p1, by_id) >= patch_min_angle<K>(fc, p0, by_id) - 1e-9);
    // Every constraint is an edge of the patch: each sub-edge appears in some triangle.
    auto has_edge = [&](const auto& patch, long i, long j) {
      for (const auto& tri : patch.triangles)
        for (int k = 0; k < 3; ++k)
          if ((tri[k] == i && tri[(k + 1) % 3] == j) || (tri[k] == j && tri[(k + 1) % 3] == i)) return true;
      return false;
    };
    for (auto [i, j] : std::vector<std::pair<long, long>>{{3, 4}, {5, 3}, {0, 5}, {5, 1}, {1, 2}, {2, 0}})
      CHECK(has_edge(p1, i, j));
    if constexpr (seam::kernel_traits<K>::exact_constructions) {
      // Every Steiner point lies exactly in the face's plane.
      for (const auto& q : p1.steiner_points) CHECK(CGAL::coplanar(fc.corners[0], fc.corners[1], fc.corners[2], q));
    }
  }
}
