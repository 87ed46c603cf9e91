// ImproveOptions::bound_reach end to end: on an anisotropic crossover (tows swept with about four
// times as many sections as their spacing around, so most input faces are below the 20 degree
// bound), the bound at every reach remeshes the faces the band reaches one after another; a reach
// of 1 keeps the change near the curves. Asserted on both runs: the outputs are verified, every
// face left below the bound has a cause, and every face reported as input_angle is no worse than
// the input face it comes from (its smallest angle measured here on the input, not taken from
// the stage).
#include <catch2/catch.hpp>

#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "test_support.h"

namespace {

using K = seam::Exact;
using Mesh = seam::Mesh<K>;

double smallest_angle_deg(const std::array<std::array<double, 3>, 3>& p) {
  double smallest = 180;
  for (int i = 0; i < 3; ++i) {
    const auto& o = p[std::size_t(i)];
    const auto& u = p[std::size_t((i + 1) % 3)];
    const auto& v = p[std::size_t((i + 2) % 3)];
    double uu = 0, vv = 0, uv = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = u[std::size_t(k)] - o[std::size_t(k)], b = v[std::size_t(k)] - o[std::size_t(k)];
      uu += a * a, vv += b * b, uv += a * b;
    }
    smallest = std::min(smallest, std::acos(std::clamp(uv / std::sqrt(uu * vv), -1.0, 1.0)) * 180 / M_PI);
  }
  return smallest;
}

double input_face_angle(const seam::TriangleSoup& soup, std::size_t face) {
  std::array<std::array<double, 3>, 3> p;
  for (std::size_t k = 0; k < 3; ++k) p[k] = soup.points[soup.triangles[face][k]];
  return smallest_angle_deg(p);
}

}  // namespace

TEST_CASE("improve: bound_reach keeps the refinement of an anisotropic mesh near the curves", "[improve][pair]") {
  // Spacing along about 0.067 (weft) and 0.08 (warp), around about 0.25: input faces near 15 degrees.
  const auto tows = seam::make_crossover(150, 16, 125, 16, seam::Section::lenticular, 0.45);
  const seam::TriangleSoup soup_a = seam::make_tow(tows.weft), soup_b = seam::make_tow(tows.warp);
  // Runs: no limit, 1, and the default (automatic: 1 here, most input faces being below 20 degrees).
  const long reaches[3] = {254, 1, -1};
  std::size_t absorbed[3] = {0, 0, 0}, new_faces[3] = {0, 0, 0};
  for (int run = 0; run < 3; ++run) {
    INFO("bound_reach " << reaches[run]);
    Mesh a = seam::mesh_from_soup<K>(soup_a, "weft"), b = seam::mesh_from_soup<K>(soup_b, "warp");
    seam::PairOptions o;
    o.quality.bound_reach = reaches[run];
    const auto r = seam::pair<K>(a, b, o);
    REQUIRE(r.stats.improved);
    CHECK(r.stats.verified);
    CHECK(r.stats.improve.bound_reach == std::vector<std::size_t>(2, run == 0 ? 254 : 1));
    for (const auto& s : r.stats.improve.shortfalls) {
      CHECK(s.min_angle_deg < o.embed.min_angle_deg);
      CHECK(s.cause != seam::ShortfallCause::budget);
      if (s.cause != seam::ShortfallCause::input_angle) continue;
      const Mesh& m = s.mesh == 0 ? a : b;
      const auto source = m.property_map<Mesh::Face_index, std::uint32_t>(seam::source_face_property);
      REQUIRE(source.second);
      const seam::TriangleSoup& input = s.mesh == 0 ? soup_a : soup_b;
      const std::uint32_t from = source.first[Mesh::Face_index(static_cast<Mesh::size_type>(s.face))];
      REQUIRE(from < input.triangles.size());
      CHECK(s.min_angle_deg >= input_face_angle(input, from) - 1e-6);
    }
    absorbed[run] = r.stats.improve.faces_absorbed;
    new_faces[run] = r.a.stats.faces_added + r.b.stats.faces_added;
  }
  // The limit cuts the growth the bound forces on faces that were below it in the input.
  INFO("faces absorbed " << absorbed[0] << " -> " << absorbed[1] << ", new faces " << new_faces[0] << " -> "
                         << new_faces[1]);
  CHECK(absorbed[1] * 3 < absorbed[0]);
  CHECK(new_faces[1] < new_faces[0]);
  CHECK(absorbed[2] == absorbed[1]);
  CHECK(new_faces[2] == new_faces[1]);
}

TEST_CASE("improve: bound_reach is unlimited by default where most input faces meet the bound", "[improve][pair]") {
  // A crossover like the quality sweep's (about as many sections as points around).
  const auto tows = seam::make_crossover(30, 14, 23, 12, seam::Section::elliptical, 0.5);
  Mesh a = seam::mesh_from_soup<K>(seam::make_tow(tows.weft), "weft"), b = seam::mesh_from_soup<K>(seam::make_tow(tows.warp), "warp");
  const auto r = seam::pair<K>(a, b, seam::PairOptions{});
  REQUIRE(r.stats.improved);
  CHECK(r.stats.verified);
  CHECK(r.stats.improve.bound_reach == std::vector<std::size_t>(2, 254));
}
