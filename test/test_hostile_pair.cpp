// Hostile input to pair (issue 22). Extreme scales and offsets (class 1): inside seam::SupportedCoordinates a crossover
// scaled to the limits, or moved far from the origin, gives the same verified result as at unit
// scale; outside them every entry point refuses the input with InvalidInput (never SIGFPE).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/embed.h>
#include <seam/errors.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_support.h"

namespace {

using seam::Point3d;
using seam::TriangleSoup;

/// The small crossover of the tests, every coordinate c mapped to scale * c + offset.
std::pair<TriangleSoup, TriangleSoup> crossover_at(double scale, double offset) {
  const auto tows = seam::make_crossover(18, 10, 14, 9, seam::Section::lenticular, 0.45);
  TriangleSoup a = seam::make_tow(tows.weft), b = seam::make_tow(tows.warp);
  for (TriangleSoup* s : {&a, &b})
    for (Point3d& p : s->points)
      for (double& c : p) c = scale * c + offset;
  return {a, b};
}

/// pair<K> on the soups; under the exact kernel the result must be verified, and pass
/// check_pair on the outputs rounded to doubles (as written) at pair's verification tolerance.
/// The other kernels may refuse (InternalError) but never crash or return an unverified result.
template <class K> void pair_is_verified(const TriangleSoup& sa, const TriangleSoup& sb) {
  auto a = seam::mesh_from_soup<K>(sa, "A"), b = seam::mesh_from_soup<K>(sb, "B");
  const auto a0 = seam::mesh_from_soup<seam::Exact>(sa, "A"), b0 = seam::mesh_from_soup<seam::Exact>(sb, "B");
  seam::PairResult<K> r;
  try {
    r = seam::pair<K>(a, b, seam::PairOptions{});
  } catch (const seam::InternalError& e) {
    INFO("refused: " << e.what());
    CHECK(seam::kernel_traits<K>::kind != seam::KernelKind::exact);
    return;
  }
  REQUIRE(r.stats.verified);
  CHECK(r.stats.curves >= 1);
  const auto a2 = seam::mesh_from_soup<seam::Exact>(seam::soup_from_mesh<K>(a), "A2");
  const auto b2 = seam::mesh_from_soup<seam::Exact>(seam::soup_from_mesh<K>(b), "B2");
  const auto curves = seam::to_kernel<seam::Exact>(seam::to_doubles<K>(r.curves));
  const auto report = seam::check_pair<seam::Exact>(a0, b0, a2, b2, curves, r.stats.verify_tolerance);
  INFO("first problem: " << (report.ok() ? std::string() : report.problems.front()));
  CHECK(report.ok());
}

}  // namespace

TEMPLATE_TEST_CASE("hostile scale: a crossover at the limits of the supported scales and offsets is verified",
                   "[hostile][scale]", seam::Exact, seam::Filtered, seam::Float) {
  struct Case {
    const char* label;
    double scale, offset;
  };
  // The tows span about 12 units: 1e28 keeps every coordinate below 1e30, 1e-29 keeps them above
  // 1e-30 across, and an offset of 1e7 puts them at 1e-6 of their distance from the origin.
  const std::vector<Case> cases = {{"unit", 1, 0}, {"1e28", 1e28, 0}, {"1e-29", 1e-29, 0},
                                   {"offset 1e7", 1, 1e7}, {"1e-20 at offset 1e-14", 1e-20, 1e-14}};
  for (const Case& c : cases) {
    INFO("case " << c.label);
    const auto [a, b] = crossover_at(c.scale, c.offset);
    REQUIRE_NOTHROW(seam::validate_triangle_mesh(a, "A"));
    pair_is_verified<TestType>(a, b);
  }
}

TEST_CASE("hostile scale: meshes and curves outside the supported coordinates are refused by every entry point",
          "[hostile][scale]") {
  struct Case {
    const char* label;
    double scale, offset;
    const char* what;
  };
  const std::vector<Case> cases = {{"1e80", 1e80, 0, "supported magnitude"},
                                   {"1e31", 1e31, 0, "supported magnitude"},
                                   {"1e-150", 1e-150, 0, "supported size"},
                                   {"1e-32", 1e-32, 0, "supported size"},
                                   {"offset 1e15", 1, 1e15, "nearer the origin"},
                                   {"offset 1e9", 1, 1e9, "nearer the origin"}};
  for (const Case& c : cases) {
    INFO("case " << c.label);
    const auto [a, b] = crossover_at(c.scale, c.offset);
    CHECK_THROWS_WITH(seam::validate_triangle_mesh(a, "tow.off"),
                      Catch::StartsWith("tow.off") && Catch::Contains(c.what));
    // The library entry points refuse meshes built without validation.
    auto ma = seam::mesh_from_soup<seam::Exact>(a, "A"), mb = seam::mesh_from_soup<seam::Exact>(b, "B");
    CHECK_THROWS_AS(seam::pair<seam::Exact>(ma, mb, seam::PairOptions{}), seam::InvalidInput);
    std::vector<seam::Polyline<seam::Exact>> curve = {{ma.point(*ma.vertices().begin()), ma.point(*ma.vertices().begin())}};
    CHECK_THROWS_AS(seam::embed<seam::Exact>(ma, curve, seam::EmbedOptions{}), seam::InvalidInput);
  }
  // A curve point beyond the magnitude, next to a valid mesh.
  const auto [a, b] = crossover_at(1, 0);
  auto ma = seam::mesh_from_soup<seam::Exact>(a, "A"), mb = seam::mesh_from_soup<seam::Exact>(b, "B");
  const std::vector<seam::Polyline<seam::Exact>> far = {{{0, 0, 0}, {1e308, 0, 0}}};
  CHECK_THROWS_AS(seam::embed<seam::Exact>(ma, far, seam::EmbedOptions{}), seam::InvalidInput);
  CHECK_THROWS_AS(seam::pair_with_curves<seam::Exact>(ma, mb, far, seam::PairOptions{}), seam::InvalidInput);
  CHECK_THROWS_WITH(seam::parse_polylines("2 0 0 0 1e308 0 0\n", "c.txt"), Catch::Contains("supported magnitude"));
}

namespace {

/// An axis-aligned box of half sizes h around c, turned by `turn` about z (12 triangles, outward).
TriangleSoup box(Point3d c, Point3d h, double turn) {
  TriangleSoup s;
  for (int i = 0; i < 8; ++i) {
    const double x = (i & 1 ? 1 : -1) * h[0], y = (i & 2 ? 1 : -1) * h[1], z = (i & 4 ? 1 : -1) * h[2];
    s.points.push_back({c[0] + std::cos(turn) * x - std::sin(turn) * y, c[1] + std::sin(turn) * x + std::cos(turn) * y,
                        c[2] + z});
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({std::size_t(q[0]), std::size_t(q[1]), std::size_t(q[2])});
    s.triangles.push_back({std::size_t(q[0]), std::size_t(q[2]), std::size_t(q[3])});
  }
  return s;
}

}  // namespace

TEST_CASE("hostile pair: --max-area gives verified outputs in bounded work", "[hostile][max-area]") {
  // Two boxes crossing: before, max_area 0.01 ran the remeshing for 10 s (20 s with its redo);
  // then it was refused (exit 3): Steiner points of the area refinement came closer than the
  // vertex separation to each other (refinement cascading into a tiny spot) and to points of the
  // other mesh near the curve. Now every Steiner point keeps that far from every vertex of both.
  // The quality stage refines to the area bound too: with it, no face held to the bound (made
  // within the faces the curves cross or touch) is left above it, and fewer new faces are below
  // 20 degrees than the re-triangulation alone leaves. (New faces where its band grew farther
  // are graded to the input's size: counted in new_faces_above_max_area, not held to it.)
  const TriangleSoup sa = box({0, 0, 0}, {1, 1, 1}, 0), sb = box({0.7, 0.3, 0.2}, {0.6, 0.5, 0.4}, 0.3);
  std::size_t above[2] = {0, 0}, below_20[2] = {0, 0};  // with the stage, without
  for (const bool remesh : {true, false}) {
    INFO("remeshing " << (remesh ? "asked for" : "off"));
    auto a = seam::mesh_from_soup<seam::Exact>(sa, "A"), b = seam::mesh_from_soup<seam::Exact>(sb, "B");
    seam::PairOptions options;
    options.embed.max_area = 0.01;
    options.improve = remesh;
    const auto r = seam::pair<seam::Exact>(a, b, options);
    REQUIRE(r.stats.verified);  // as written: separation, no crossing, curves present
    CHECK(r.stats.improved == remesh);
    if (remesh) CHECK(r.stats.improve.above_max_area_after == 0);
    CHECK(r.stats.curves > 0);
    for (const auto* part : {&r.a, &r.b}) {
      // Work bounded by the area: no more new faces than a few per max_area of crossed surface.
      const double crossed_area = part == &r.a ? 4.0 * 2 : 2 * (1.2 * 1.0 + 1.2 * 0.8 + 1.0 * 0.8);
      CHECK(part->stats.steiner_points > 0);
      CHECK(double(part->stats.faces_added) <= 8 * crossed_area / options.embed.max_area);
      // Faces left larger than the bound (a crossed face of 2 reaches its 256 Steiner points) are
      // counted, as a count made here finds them.
      const auto& mesh = part == &r.a ? a : b;
      CHECK(part->stats.new_faces_above_max_area == seam_test::new_faces_larger_than<seam::Exact>(mesh, options.embed.max_area));
      CHECK(part->stats.largest_new_area > 0);
      above[remesh ? 0 : 1] += part->stats.new_faces_above_max_area;
      below_20[remesh ? 0 : 1] += part->stats.new_faces_below_20;
    }
  }
  INFO("above the area bound " << above[0] << " (without the stage " << above[1] << "), below 20 degrees "
                               << below_20[0] << " (" << below_20[1] << ")");
  CHECK(above[1] > 0);
  CHECK(below_20[0] < below_20[1]);
}
