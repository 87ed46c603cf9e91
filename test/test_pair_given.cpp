// Tests of seam::pair_with_curves (`seam pair --curves`): given curves embedded into both tows.
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/verify.h>

#include "test_support.h"

#include <cmath>

namespace {

/// One crossover of a plain weave (as in test_pair.cpp): an elliptical weft along x, a crimped
/// lenticular warp along y at another resolution, pushed 0.25 into each other.
std::pair<seam::TowOptions, seam::TowOptions> given_crossover(seam::Section warp_section = seam::Section::lenticular) {
  const auto c = seam::make_crossover(48, 20, 35, 15, warp_section, 0.45);
  return {c.weft, c.warp};
}

template <class K> seam::Mesh<K> mesh_of(const seam::TowOptions& o) {
  return seam::mesh_from_soup<K>(seam::make_tow(o), "tow");
}

}  // namespace

TEST_CASE("pair with given curves: the intersection given as the curves comes out conforming", "[pair][given]") {
  using K = seam::Exact;
  const auto [weft, warp] = given_crossover();
  const auto a = mesh_of<K>(weft), b = mesh_of<K>(warp);
  const auto given = seam::intersection_curves<K>(a, b);
  REQUIRE(given.size() == 1);
  for (double snap : {0.0, -1.0}) {
    // (Under the sanitizers only the default: the tolerance-0 refinement alone takes minutes there;
    // test_pair covers tolerance 0 under them.)
    if (seam_test::sanitized_build && snap == 0.0) continue;
    INFO("snap_tol " << snap);
    auto a2 = a, b2 = b;
    seam::PairOptions o;
    o.embed.snap_tol = snap;
    const auto r = seam::pair_with_curves<K>(a2, b2, given, o);
    REQUIRE(r.stats.given_curves);
    REQUIRE(r.curves.size() == 1);
    CHECK(seam::is_closed(r.curves[0]));
    // Without snapping (so without remeshing either) both meshes' crossings are on the common
    // curve: at least as many points as either has.
    if (snap == 0) CHECK(r.curves[0].size() >= r.a.stats.crossing_points);
    // Every curve vertex and segment in both outputs, with identical coordinates.
    CHECK(seam::check_curves_embedded<K>(a2, r.a).empty());
    CHECK(seam::check_curves_embedded<K>(b2, r.b).empty());
    CHECK(r.a.curves == r.b.curves);
    // The given curve lies on both surfaces: the outputs meet only along it, and hardly move.
    const double tol = snap == 0 ? 1e-12 : r.stats.snap_tol + 1e-12;
    const auto report = seam::check_pair<K>(a, b, a2, b2, r.curves, tol);
    for (const auto& p : report.problems) UNSCOPED_INFO(p);
    CHECK(report.ok());
    if (snap == 0) CHECK(r.stats.max_curve_move < 1e-12);
  }
}

TEST_CASE("pair with given curves: a curve nearby, densified, is shared by both outputs", "[pair][given]") {
  using K = seam::Exact;
  // Smooth sections: next to the sharp edge of a lenticular section a curve that cuts the corner
  // lies too far from the small faces there to move them onto it.
  const auto [weft, warp] = given_crossover(seam::Section::elliptical);
  auto a = mesh_of<K>(weft), b = mesh_of<K>(warp);
  const auto exact = seam::intersection_curves<K>(a, b);
  REQUIRE(exact.size() == 1);
  // Midpoints of the exact curve's segments: a curve from another tool, near both surfaces but
  // with other nodes.
  seam::Polyline<K> mid;
  for (std::size_t i = 0; i + 1 < exact[0].size(); ++i) mid.push_back(CGAL::midpoint(exact[0][i], exact[0][i + 1]));
  mid.push_back(mid.front());
  seam::PairOptions o;
  o.embed.snap_tol = 0;
  const auto r = seam::pair_with_curves<K>(a, b, {mid}, o);
  INFO(r.stats.note);
  REQUIRE(r.curves.size() == 1);
  for (const auto& p : seam::check_curves_embedded<K>(a, r.a)) UNSCOPED_INFO(p);
  CHECK(seam::check_curves_embedded<K>(a, r.a).empty());
  CHECK(seam::check_curves_embedded<K>(b, r.b).empty());
  CHECK(r.a.curves == r.b.curves);
  CHECK(seam::check_valid_mesh<K>(a, true).empty());
  CHECK(seam::check_valid_mesh<K>(b, true).empty());
}

TEST_CASE("pair with given curves: a curve far from the meshes is refused", "[pair][given]") {
  using K = seam::Exact;
  const auto [weft, warp] = given_crossover();
  auto a = mesh_of<K>(weft), b = mesh_of<K>(warp);
  const auto exact = seam::intersection_curves<K>(a, b);
  REQUIRE(exact.size() == 1);
  seam::Polyline<K> far;
  for (const auto& p : exact[0]) far.push_back(p + K::Vector_3(0, 0, 10));
  const auto a0 = a, b0 = b;
  CHECK_THROWS_AS(seam::pair_with_curves<K>(a, b, {far}), seam::InvalidInput);
  CHECK_THROWS_AS(seam::pair_with_curves<K>(a, b, {seam::Polyline<K>{exact[0][0]}}), seam::InvalidInput);
}

namespace {

/// The intersection of the smooth surfaces of the two tows (seam::smooth_intersection_points),
/// one point near each point and segment middle of the meshes' exact intersection: a dense curve
/// that lies off both meshes by up to their chordal error, as a NURBS intersection gives it.
std::vector<seam::Polyline<seam::Exact>> smooth_curves(const seam::TowOptions& weft, const seam::TowOptions& warp,
                                                       const seam::Mesh<seam::Exact>& a,
                                                       const seam::Mesh<seam::Exact>& b) {
  using K = seam::Exact;
  std::vector<seam::Polyline<K>> result;
  for (const auto& c : seam::to_doubles<K>(seam::intersection_curves<K>(a, b))) {
    std::vector<seam::Point3d> seeds;
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      seeds.push_back(c[i]);
      seeds.push_back({(c[i][0] + c[i + 1][0]) / 2, (c[i][1] + c[i + 1][1]) / 2, (c[i][2] + c[i + 1][2]) / 2});
    }
    auto smooth = seam::smooth_intersection_points(weft, warp, seeds);
    smooth.push_back(smooth.front());
    result.push_back(seam::to_kernel<K>({smooth}).front());
  }
  return result;
}

}  // namespace

TEST_CASE("pair with given curves: the smooth analytic intersection, off the facets, is embedded into both",
          "[pair][given]") {
  // The report's given curves: the intersection of the smooth tow surfaces, 0.001 to 0.01 off the
  // facets at these resolutions (the facets' chordal error), on both warp sections. They were
  // refused ("moving the mesh onto it would fold a face"); now the meshes' exact intersection is
  // embedded and moved onto them, with the faces along, in both alike.
  using K = seam::Exact;
  for (int r : {8, 12, 16})
    for (auto section : {seam::Section::elliptical, seam::Section::lenticular}) {
      if (seam_test::sanitized_build && r == 16) continue;  // (the Release suite runs it)
      INFO("resolution " << r << (section == seam::Section::lenticular ? ", lenticular" : ", elliptical"));
      const auto c = seam::make_crossover(6 * r, 2 * r + 4, 4 * r + 3, r + 7, section, 0.45);
      const auto a = mesh_of<K>(c.weft), b = mesh_of<K>(c.warp);
      const auto given = smooth_curves(c.weft, c.warp, a, b);
      REQUIRE(given.size() == 1);
      // How far the given curve lies from the facets: off them, by up to about their chordal error.
      double farthest = 0;
      std::vector<seam::Filtered::Triangle_3> facets;  // (doubles: a measurement)
      for (auto f : a.faces()) {
        const auto h = a.halfedge(f);
        facets.emplace_back(seam::to_filtered(a.point(a.source(h))), seam::to_filtered(a.point(a.target(h))),
                            seam::to_filtered(a.point(a.target(a.next(h)))));
      }
      const auto given_doubles = seam::to_doubles<K>(given);
      for (const auto& p : given_doubles.front()) {
        double d2 = HUGE_VAL;
        for (const auto& t : facets) d2 = std::min(d2, CGAL::squared_distance(t, seam::Filtered::Point_3(p[0], p[1], p[2])));
        farthest = std::max(farthest, std::sqrt(d2));
      }
      INFO("the given curve lies up to " << farthest << " from A's facets");
      CHECK(farthest > 1e-3);
      CHECK(farthest < 0.012);
      for (double snap : {0.0, -1.0}) {
        INFO("snap_tol " << snap);
        auto a2 = a, b2 = b;
        seam::PairOptions o;
        o.embed.snap_tol = snap;
        const auto res = seam::pair_with_curves<K>(a2, b2, given, o);
        INFO(res.stats.note);
        CHECK(res.stats.verified);
        REQUIRE(res.curves.size() == 1);
        CHECK(seam::is_closed(res.curves[0]));
        CHECK(seam::check_curves_embedded<K>(a2, res.a).empty());
        CHECK(seam::check_curves_embedded<K>(b2, res.b).empty());
        // Every curve vertex lies on the given curve (exactly: on one of its segments).
        for (const auto& p : res.curves[0]) {
          bool on = false;
          for (std::size_t i = 0; i + 1 < given[0].size() && !on; ++i)
            on = K::Segment_3(given[0][i], given[0][i + 1]).has_on(p);
          CHECK(on);
        }
        // seam check passes at the tolerance pair states (the largest move plus the snapping).
        const auto report = seam::check_pair<K>(a, b, a2, b2, res.curves, res.stats.verify_tolerance);
        for (const auto& p : report.problems) UNSCOPED_INFO(p);
        CHECK(report.ok());
      }
    }
}
