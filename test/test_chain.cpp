// The whole chain on generated tows, as a user runs it: seam::pair makes two interpenetrating
// tows conforming, seam::resolve gives their overlap to one of them, seam::volume_mesh meshes both
// tows and the matrix box. The invariants are computed here, independently of the library's own
// checks: exact volumes of the surfaces (rational sums), summed tet volumes per region, the
// contact faces of the resolved tows as faces of tets of both tows.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/resolve.h>
#include <seam/volume_mesh.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace {

using K = seam::Exact;
using FT = K::FT;

K::Point_3 exact_point(const seam::Point3d& p) { return {p[0], p[1], p[2]}; }

/// The volume a closed, outward-oriented triangle soup encloses, exactly.
FT enclosed_volume(const seam::TriangleSoup& s) {
  FT v = 0;
  const K::Point_3 o(0, 0, 0);
  for (const auto& t : s.triangles)
    v += CGAL::determinant(exact_point(s.points[t[0]]) - o, exact_point(s.points[t[1]]) - o,
                           exact_point(s.points[t[2]]) - o);
  return v / 6;
}

/// The sum of the volumes of the tets of `region`, exactly.
FT tet_volume(const seam::TetMesh& m, int region) {
  FT v = 0;
  for (std::size_t i = 0; i < m.tets.size(); ++i) {
    if (m.region[i] != region) continue;
    const auto& t = m.tets[i];
    const auto a = exact_point(m.points[t[0]]);
    v += CGAL::determinant(exact_point(m.points[t[1]]) - a, exact_point(m.points[t[2]]) - a,
                           exact_point(m.points[t[3]]) - a) / 6;
  }
  return v;
}

double relative(const FT& x, const FT& y) { return CGAL::to_double(CGAL::abs(x - y) / CGAL::abs(y)); }

}  // namespace

TEST_CASE("chain: interpenetrating tows become one tetrahedral model (pair, resolve, mesh)", "[chain][resolve][mesh]") {
  const auto c = seam::make_crossover(36, 16, 27, 13, seam::Section::lenticular, 0.45);
  seam::Mesh<K> a = seam::mesh_from_soup<K>(seam::make_tow(c.weft), "weft");
  seam::Mesh<K> b = seam::mesh_from_soup<K>(seam::make_tow(c.warp), "warp");

  // 1. pair: conforming along the curves, verified as written.
  const auto paired = seam::pair<K>(a, b);
  REQUIRE(paired.stats.verified);
  REQUIRE(paired.stats.curves >= 1);
  const FT before_a = enclosed_volume(seam::soup_from_mesh<K>(a)), before_b = enclosed_volume(seam::soup_from_mesh<K>(b));

  // 2. resolve: the overlap goes to one tow; the two volumes now sum to the union's.
  const auto resolved = seam::resolve<K>(a, b);
  const auto soup_a = seam::soup_from_mesh<K>(a), soup_b = seam::soup_from_mesh<K>(b);
  const FT after_a = enclosed_volume(soup_a), after_b = enclosed_volume(soup_b);
  CHECK(resolved.overlap_volume > 0);
  CHECK(resolved.contact_faces > 0);
  // What the two lost together is the overlap, counted once: vol(A3) + vol(B3) = vol(A2 u B2).
  const FT lost = (before_a + before_b) - (after_a + after_b);
  CHECK(CGAL::to_double(lost) == Approx(resolved.overlap_volume).epsilon(1e-9));
  // The keeper is unchanged.
  CHECK((after_a == before_a || after_b == before_b));
  CHECK(CGAL::to_double(after_a) == Approx(resolved.volume_a_after).epsilon(1e-12));
  CHECK(CGAL::to_double(after_b) == Approx(resolved.volume_b_after).epsilon(1e-12));

  // 3. mesh: a region per tow and the matrix; each region's tets fill exactly its surface.
  seam::VolumeMeshOptions options;
  options.margin = 0.1;
  const auto model = seam::volume_mesh({soup_a, soup_b}, {"weft", "warp"}, options);
  const auto& m = model.mesh;
  REQUIRE(m.region_names.size() == 3);
  CHECK(relative(tet_volume(m, 1), after_a) <= 1e-9);
  CHECK(relative(tet_volume(m, 2), after_b) <= 1e-9);
  const auto& box = model.stats.box;
  const FT box_volume = (FT(box.max[0]) - FT(box.min[0])) * (FT(box.max[1]) - FT(box.min[1])) *
                        (FT(box.max[2]) - FT(box.min[2]));
  CHECK(relative(tet_volume(m, 0), box_volume - after_a - after_b) <= 1e-9);
  for (std::size_t i = 0; i < m.tets.size(); ++i) {  // no tet inverted or flat
    const auto& t = m.tets[i];
    if (CGAL::orientation(exact_point(m.points[t[0]]), exact_point(m.points[t[1]]), exact_point(m.points[t[2]]),
                          exact_point(m.points[t[3]])) != CGAL::POSITIVE)
      FAIL("tet " << i << " is not positively oriented");
  }

  // The contact surface: every face the two resolved tows share is a face of a weft tet and of a
  // warp tet (faces keyed by their sorted corner coordinates).
  using Face = std::array<seam::Point3d, 3>;
  auto key = [](seam::Point3d p, seam::Point3d q, seam::Point3d r) {
    Face f{p, q, r};
    std::sort(f.begin(), f.end());
    return f;
  };
  std::set<Face> faces_a;
  for (const auto& t : soup_a.triangles) faces_a.insert(key(soup_a.points[t[0]], soup_a.points[t[1]], soup_a.points[t[2]]));
  std::set<Face> shared;
  for (const auto& t : soup_b.triangles) {
    const Face f = key(soup_b.points[t[0]], soup_b.points[t[1]], soup_b.points[t[2]]);
    if (faces_a.count(f)) shared.insert(f);
  }
  CHECK(shared.size() == resolved.contact_faces);
  std::map<Face, std::set<int>> regions_at;
  for (std::size_t i = 0; i < m.tets.size(); ++i) {
    const auto& t = m.tets[i];
    for (int skip = 0; skip < 4; ++skip) {
      std::array<seam::Point3d, 3> f;
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != skip) f[std::size_t(n++)] = m.points[t[std::size_t(k)]];
      const Face fk = key(f[0], f[1], f[2]);
      if (shared.count(fk)) regions_at[fk].insert(m.region[i]);
    }
  }
  std::size_t both = 0;
  for (const auto& f : shared) both += regions_at[f] == std::set<int>{1, 2} ? 1 : 0;
  CHECK(both == shared.size());
  REQUIRE(model.contacts.size() == 1);
  CHECK(model.contacts.front().faces.size() == shared.size());
}
