// seam pair's targeted closing: where a curve point has a vertex or another curve point closer
// than the vertex separation (embedded, the two would be distinct vertices TetGen takes for one
// point), the inputs' vertices next to it that lie within the separation of a curve move onto
// it before the embedding. Found on a CT tow against a copy moved along a grid plane, where
// closing every such vertex lost a thin loop of touching intersection elsewhere
// (docs/real_tows.md, row 9).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/io.h>
#include <seam/pair.h>

#include <string>
#include <vector>

#include "tow_fixtures.h"

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;

/// The unit cube, and a tetrahedron inside it whose apex pokes 1e-9 out through the top face:
/// the two surfaces cross in a triangle about 1e-9 across around the apex.
std::pair<M, M> cube_and_poking_tetrahedron() {
  const auto cube = seam_test::box_soup({0, 0, 0}, {1, 1, 1});
  const auto tet = seam_test::tetrahedron({0.2, 0.2, 0.5}, {0.8, 0.2, 0.5}, {0.5, 0.8, 0.5}, {0.5, 0.5, 1 + 1e-9});
  return {seam::mesh_from_soup<K>(cube, "cube"), seam::mesh_from_soup<K>(tet, "tetrahedron")};
}

}  // namespace

TEST_CASE("pair: vertices of pairs left closer than the separation are closed, and the result verified",
          "[pair][separate]") {
  const auto [a, b] = cube_and_poking_tetrahedron();
  M a2 = a, b2 = b;
  seam::PairOptions options;
  options.improve = false;  // the embedding alone leaves the curve points 1e-9 from the apex
  const auto r = seam::pair<K>(a2, b2, options);
  INFO(r.stats.note);
  REQUIRE(r.stats.verified);
  // The curve points crowd around the apex (1e-9 from it): the first way moved the apex alone
  // onto the curve before the embedding, and its outputs passed.
  CHECK(r.stats.note.find("seam check failed") == std::string::npos);
  CHECK(r.stats.vertices_closed == 1);
  // The apex now touches the top face: one point of contact, a vertex of both outputs.
  CHECK(r.stats.touching_only);
  REQUIRE(r.curves.size() == 1);
  REQUIRE(r.curves[0].size() == 1);
  const auto contact = r.curves[0][0];
  CHECK(contact.z() == 1);
  auto has_vertex_at = [](const M& m, const K::Point_3& p) {
    for (auto v : m.vertices())
      if (m.point(v) == p) return true;
    return false;
  };
  CHECK(has_vertex_at(a2, contact));
  CHECK(has_vertex_at(b2, contact));
  // The independent check, with check 5 (the vertex separation).
  const auto report = seam::check_pair<K>(a, b, a2, b2, r.curves, r.stats.verify_tolerance);
  INFO((report.problems.empty() ? std::string() : report.problems.front()));
  CHECK(report.ok());
  CHECK(report.close_vertex_pairs == 0);
}
