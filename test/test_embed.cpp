// Tests of seam::embed: invariants of the output on tiny degenerate inputs and a generated tow.
#include <catch2/catch.hpp>

#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/verify.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "test_support.h"

namespace {

/// A flat n x n grid in the plane z = 0 over [0, n]^2, each unit square split by its
/// (i, j)-(i+1, j+1) diagonal. An open mesh (it has a boundary).
template <class K> seam::Mesh<K> flat_grid(int n) {
  seam::TriangleSoup soup;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) soup.points.push_back({double(i), double(j), 0.0});
  auto id = [n](int i, int j) { return std::size_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      soup.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      soup.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return seam::mesh_from_soup<K>(soup, "grid");
}

/// `samples` + 1 points evenly spaced from a to b (both included), lifted by dz.
template <class K>
seam::Polyline<K> line(std::array<double, 2> a, std::array<double, 2> b, int samples, double dz = 0) {
  seam::Polyline<K> pl;
  for (int k = 0; k <= samples; ++k) {
    const double t = double(k) / samples;
    pl.emplace_back(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), dz);
  }
  return pl;
}

template <class K> seam::Polyline<K> from_xy(std::initializer_list<std::array<double, 2>> pts, double dz = 0) {
  seam::Polyline<K> pl;
  for (const auto& p : pts) pl.emplace_back(p[0], p[1], dz);
  return pl;
}

/// Runs embed and checks every invariant; returns the result.
template <class K>
seam::EmbedResult<K> embed_and_check(seam::Mesh<K>& mesh, const std::vector<seam::Polyline<K>>& curves,
                                     seam::EmbedOptions options, bool expect_closed = false) {
  const seam::Mesh<K> input = mesh;
  auto result = seam::embed<K>(mesh, curves, options);
  auto problems = seam::check_valid_mesh<K>(mesh, expect_closed);
  auto more = seam::check_curves_embedded<K>(mesh, result);
  problems.insert(problems.end(), more.begin(), more.end());
  if (options.snap_tol == 0) {
    more = seam::check_same_surface<K>(input, mesh);
    problems.insert(problems.end(), more.begin(), more.end());
  } else {
    more = seam::check_vertex_moves<K>(input, mesh, result.stats.snap_tol);
    problems.insert(problems.end(), more.begin(), more.end());
  }
  for (const auto& p : problems) UNSCOPED_INFO(p);
  CHECK(problems.empty());
  CHECK(result.curves.size() == curves.size());
  return result;
}

seam::EmbedOptions no_snap() {
  seam::EmbedOptions o;
  o.snap_tol = 0;
  return o;
}

}  // namespace

#define SEAM_KERNELS seam::Exact, seam::Filtered

TEMPLATE_TEST_CASE("embed: a curve through a mesh vertex passes through that vertex", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // slope 1/2 through the grid vertex (2, 2); no curve node there
  auto r = embed_and_check<K>(mesh, {line<K>({0.5, 1.25}, {3.5, 2.75}, 7)}, no_snap());
  CHECK(r.stats.curve_vertices_at_mesh_vertices >= 1);
  bool through = false;
  for (const auto& p : r.curves[0]) through |= (p == typename K::Point_3(2, 2, 0));
  CHECK(through);
}

TEMPLATE_TEST_CASE("embed: a curve along a mesh edge adds no face", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // along the grid line y = 1, from vertex (1, 1) to vertex (3, 1)
  auto r = embed_and_check<K>(mesh, {line<K>({1, 1}, {3, 1}, 10)}, no_snap());
  CHECK(r.stats.faces_crossed == 0);
  CHECK(r.curves[0].size() == 3);  // (1,1), (2,1), (3,1)
}

TEMPLATE_TEST_CASE("embed: a curve along an edge that ends inside it splits the edge", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  auto r = embed_and_check<K>(mesh, {line<K>({1.25, 1}, {2.5, 1}, 5)}, no_snap());
  CHECK(r.stats.crossing_points == 2);
}

TEMPLATE_TEST_CASE("embed: a crossing exactly at an edge end point is the vertex", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // a node exactly on the vertex (2, 1), the curve crossing there
  auto r = embed_and_check<K>(mesh, {from_xy<K>({{1.3, 0.4}, {2, 1}, {2.6, 1.9}})}, no_snap());
  CHECK(r.stats.curve_vertices_at_mesh_vertices == 1);
}

TEMPLATE_TEST_CASE("embed: a curve touching a vertex without crossing", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // a V whose apex touches (2, 2) from above
  auto r = embed_and_check<K>(mesh, {from_xy<K>({{1.1, 3.2}, {1.6, 2.6}, {2, 2}, {2.5, 2.7}, {2.9, 3.3}})}, no_snap());
  CHECK(r.stats.curve_vertices_at_mesh_vertices == 1);
}

TEMPLATE_TEST_CASE("embed: a curve passing within 1e-12 of a vertex", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  auto r = embed_and_check<K>(mesh, {line<K>({0.5, 1.25 + 1e-12}, {3.5, 2.75 + 1e-12}, 9)}, no_snap());
  CHECK(r.stats.crossing_points > 0);
  // With snapping the vertex moves onto the nearest node instead.
  auto mesh2 = flat_grid<K>(4);
  seam::EmbedOptions snap;
  snap.snap_tol = 0.2;
  embed_and_check<K>(mesh2, {line<K>({0.5, 1.25 + 1e-12}, {3.5, 2.75 + 1e-12}, 30)}, snap);
}

TEMPLATE_TEST_CASE("embed: duplicate consecutive curve points are harmless", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  auto r = embed_and_check<K>(
      mesh, {from_xy<K>({{0.3, 0.6}, {0.3, 0.6}, {1.7, 1.4}, {1.7, 1.4}, {1.7, 1.4}, {3.2, 2.1}})}, no_snap());
  CHECK(r.stats.crossing_points > 0);
}

TEMPLATE_TEST_CASE("embed: a closed curve inside a single face", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // inside the lower triangle of the square [1,2]x[1,2]: (1,1), (2,1), (2,2)
  seam::Polyline<K> loop;
  for (int k = 0; k < 40; ++k) {
    const double a = 2 * M_PI * k / 40;
    loop.emplace_back(1.7 + 0.1 * std::cos(a), 1.3 + 0.1 * std::sin(a), 0.0);
  }
  loop.push_back(loop.front());
  auto r = embed_and_check<K>(mesh, {loop}, no_snap());
  CHECK(r.stats.faces_crossed == 1);
  CHECK(r.stats.crossing_points == 0);
  CHECK(r.curves[0].size() >= 4);  // at least a triangle, closed
  CHECK(r.curves[0].front() == r.curves[0].back());
}

TEMPLATE_TEST_CASE("embed: an open curve ending inside faces keeps its end points", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(6);
  auto curve = line<K>({0.7, 0.2}, {4.6, 3.1}, 50);
  auto r = embed_and_check<K>(mesh, {curve}, no_snap());
  CHECK(r.curves[0].front() == curve.front());
  CHECK(r.curves[0].back() == curve.back());
}

TEMPLATE_TEST_CASE("embed: a long curve across a flat region of many coplanar faces", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(12);
  // a wavy curve slightly above the plane (the projection puts it on the surface)
  seam::Polyline<K> wave;
  for (int k = 0; k <= 400; ++k) {
    const double x = 0.5 + 11.0 * k / 400;
    wave.emplace_back(x, 6 + 3 * std::sin(x * 0.9), 1e-3);
  }
  auto r = embed_and_check<K>(mesh, {wave}, no_snap());
  CHECK(r.stats.crossing_points > 20);
  CHECK(r.stats.curve_nodes_out < r.stats.curve_nodes_in);
  CHECK(r.stats.max_curve_deviation < 1.5);
}

TEMPLATE_TEST_CASE("embed: two curves sharing faces", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(5);
  auto r = embed_and_check<K>(mesh, {line<K>({0.5, 1.1}, {4.5, 3.3}, 20), line<K>({0.5, 1.4}, {4.5, 3.6}, 20)},
                              no_snap());
  CHECK(r.curves.size() == 2);
}

TEMPLATE_TEST_CASE("embed: a curve that leaves and re-enters a face through the same edge", "[embed]", SEAM_KERNELS) {
  using K = TestType;
  auto mesh = flat_grid<K>(4);
  // dips below y = 2 (the edge between rows) and comes back
  auto r = embed_and_check<K>(mesh, {from_xy<K>({{1.2, 2.5}, {1.5, 1.8}, {1.8, 2.5}})}, no_snap());
  CHECK(r.stats.crossing_points >= 2);
  // the node below the edge is kept, or the curve would run along the edge
  bool kept = false;
  for (const auto& p : r.curves[0]) kept |= (p == typename K::Point_3(1.5, 1.8, 0));
  CHECK(kept);
}

TEST_CASE("embed: crossing curves are refused with a clear error", "[embed]") {
  using K = seam::Exact;
  auto mesh = flat_grid<K>(3);
  CHECK_THROWS_AS(seam::embed<K>(mesh, {line<K>({0.2, 0.5}, {0.6, 0.8}, 3), line<K>({0.2, 0.8}, {0.6, 0.5}, 3)}),
                  seam::InvalidInput);
}

TEST_CASE("embed: a curve node far from the surface is an input error", "[embed]") {
  using K = seam::Exact;
  auto mesh = flat_grid<K>(3);
  CHECK_THROWS_AS(seam::embed<K>(mesh, {from_xy<K>({{0.5, 0.5}, {1.5, 1.2}}, 50.0)}), seam::InvalidInput);
}

TEMPLATE_TEST_CASE("embed: a dense ring around a generated crimped tow", "[embed][tow]", seam::Exact, seam::Filtered,
                   seam::Float) {
  using K = TestType;
  seam::TowOptions tow;
  tow.segments_along = 40;
  tow.segments_around = 20;
  tow.crimp_amplitude = 0.4;
  tow.rotate_z = 0.3;
  tow.rotate_x = 0.2;
  auto mesh = seam::mesh_from_soup<K>(seam::make_tow(tow), "tow");
  const auto ring = seam::to_kernel<K>({seam::make_ring_curve(tow, 4.93, 0.6, 1500)});
  const auto ring2 = seam::to_kernel<K>({seam::make_ring_curve(tow, 7.41, -0.3, 1500)});
  std::vector<seam::Polyline<K>> curves{ring[0], ring2[0]};

  SECTION("without snapping the surface is unchanged") {
    auto r = embed_and_check<K>(mesh, curves, no_snap(), true);
    CHECK(r.stats.crossing_points > 40);
    CHECK(r.stats.faces_added > r.stats.faces_crossed);
    CHECK(r.stats.max_curve_deviation < r.stats.mean_edge_length);
    for (const auto& c : r.curves) CHECK(c.front() == c.back());
  }
  SECTION("with snapping vertices move at most the tolerance") {
    seam::EmbedOptions o;
    o.snap_tol = 0.05;
    auto r = embed_and_check<K>(mesh, curves, o, true);
    CHECK(r.stats.vertices_snapped > 0);
    CHECK(r.stats.max_snap_move <= 0.05);
  }
  SECTION("with an area bound no new face is larger") {
    seam::EmbedOptions o = no_snap();
    o.max_area = 0.002;
    auto r = embed_and_check<K>(mesh, curves, o, true);
    CHECK(r.stats.steiner_points > 0);
  }
}

TEST_CASE("embed: the exact kernel preserves the total area exactly", "[embed][exact]") {
  using K = seam::Exact;
  seam::TowOptions tow;
  tow.segments_along = 30;
  tow.segments_around = 16;
  auto mesh = seam::mesh_from_soup<K>(seam::make_tow(tow), "tow");
  const seam::Mesh<K> input = mesh;
  seam::EmbedOptions o = no_snap();
  o.max_area = 0.005;  // forces Steiner points too
  seam::embed<K>(mesh, seam::to_kernel<K>({seam::make_ring_curve(tow, 5.1, 0.5, 800)}), o);
  // sum of vector areas per input face, exactly (check_same_surface) and in total
  CHECK(seam::check_same_surface<K>(input, mesh).empty());
  // and the total area agrees when rounded
  auto area = [](const seam::Mesh<K>& m) {
    double sum = 0;
    for (auto f : m.faces()) {
      auto h = m.halfedge(f);
      sum += std::sqrt(CGAL::to_double(CGAL::squared_area(m.point(m.source(h)), m.point(m.target(h)),
                                                          m.point(m.target(m.next(h))))));
    }
    return sum;
  };
  CHECK(area(mesh) == Approx(area(input)).epsilon(1e-12));

}

TEST_CASE("embed: peak memory per curve node is bounded (exact kernel)", "[embed][memory]") {
  // Issue 22, class 8: each located node kept its projection, a lazy Epeck expression over a
  // triangle built for that node (about 370 bytes per node beside the node's own 136), so a
  // curve of 10 million nodes peaked at 5.4 GB. Now a face point keeps its input node until
  // coarsening keeps it, and the projections share one triangle per face.
  if (seam_test::sanitized_build) return;  // ASan's allocator and shadow memory change the figures
  using K = seam::Exact;
  const std::size_t n = 300000;
  std::vector<seam::Point3d> ring;  // around the centre of a 4 x 4 grid, 0.01 above it, closed
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * M_PI * double(i) / double(n);
    ring.push_back({2 + 1.3 * std::cos(a), 2 + 1.3 * std::sin(a), 0.01});
  }
  ring.push_back(ring.front());
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    auto mesh = flat_grid<K>(4);
    const seam::Mesh<K> input = mesh;
    std::ofstream("/proc/self/clear_refs") << "5";  // a fresh peak for this child
    const long before = seam_test::status_kb("VmHWM");
    int code = 3;
    try {
      const auto curves = seam::to_kernel<K>({ring});
      const auto result = seam::embed<K>(mesh, curves, no_snap());
      const long peak = seam_test::status_kb("VmHWM");
      const double bytes_per_node = (peak - before) * 1024.0 / double(n);
      std::printf("embed of a ring of %zu nodes: peak grew by %.0f bytes per node\n", n, bytes_per_node);
      std::fflush(stdout);
      const bool valid = seam::check_valid_mesh<K>(mesh, false).empty() &&
                         seam::check_curves_embedded<K>(mesh, result).empty() &&
                         seam::check_same_surface<K>(input, mesh).empty() && result.stats.curve_nodes_in == n &&
                         result.stats.crossing_points > 0;
      // 136 bytes for each input point (Epeck), about 40 for its traced location, and the snap
      // search's transient arrays; before: above 500.
      code = before < 0 ? 2 : !valid ? 3 : bytes_per_node <= 320 ? 0 : 1;
    } catch (...) {
      code = 4;
    }
    ::_exit(code);
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  REQUIRE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 2) return;  // no /proc: nothing to measure
  CHECK(WEXITSTATUS(status) == 0);
}
