// Tests of seam::resolve and `seam resolve`: the overlap of two paired tows given to one of them.
// Each case pairs generated tows with seam::pair first (as written: doubles), resolves them, and
// asserts properties of the result against independent computations: CGAL's corefinement for the
// overlap volume, seam::check_resolved and `tetgen -d` for the absence of intersections.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/resolve.h>

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "test_support.h"
#include "tow_fixtures.h"

namespace {

using K = seam::Exact;
using Mesh = seam::Mesh<K>;
namespace PMP = CGAL::Polygon_mesh_processing;

Mesh as_written(const Mesh& m) { return seam::mesh_from_soup<K>(seam::soup_from_mesh<K>(m), "mesh"); }

/// seam::pair on two soups, the outputs as written (doubles).
std::pair<Mesh, Mesh> paired(const seam::TriangleSoup& a, const seam::TriangleSoup& b) {
  Mesh ma = seam::mesh_from_soup<K>(a, "a"), mb = seam::mesh_from_soup<K>(b, "b");
  seam::PairOptions o;
  o.improve = false;  // fast; the curves are embedded all the same
  const auto r = seam::pair<K>(ma, mb, o);
  REQUIRE(r.stats.verified);
  return {as_written(ma), as_written(mb)};
}

/// Exact volume of a closed mesh (CGAL's, independent of seam's sums).
K::FT volume(const Mesh& m) { return PMP::volume(m); }

/// The volume of A ∩ B by CGAL's corefinement (exact kernel).
K::FT intersection_volume(Mesh a, Mesh b) {
  Mesh out;
  REQUIRE(PMP::corefine_and_compute_intersection(a, b, out));
  return out.number_of_faces() == 0 ? K::FT(0) : volume(out);
}

using Corners = std::array<K::Point_3, 3>;
struct CornersLess {
  bool operator()(const Corners& x, const Corners& y) const {
    for (int k = 0; k < 3; ++k) {
      const auto c = CGAL::compare_xyz(x[k], y[k]);
      if (c != CGAL::EQUAL) return c == CGAL::SMALLER;
    }
    return false;
  }
};
/// Faces as corner triples rotated to start at the smallest corner (orientation kept).
std::multiset<Corners, CornersLess> faces_of(const Mesh& m, bool reverse = false) {
  std::multiset<Corners, CornersLess> s;
  for (auto f : m.faces()) {
    Corners c;
    int i = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c[i++] = m.point(v);
    if (reverse) std::swap(c[1], c[2]);
    std::rotate(c.begin(), std::min_element(c.begin(), c.end(), [](const auto& p, const auto& q) {
                  return CGAL::compare_xyz(p, q) == CGAL::SMALLER;
                }), c.end());
    s.insert(c);
  }
  return s;
}

std::size_t common_faces(const Mesh& a, const Mesh& b_reversed_view) {
  const auto fa = faces_of(a), fb = faces_of(b_reversed_view, true);
  std::size_t n = 0;
  for (const auto& c : fa) n += fb.count(c);
  return n;
}

/// `tetgen -d` on both meshes merged (common vertices merged, a common face written once): the
/// number of intersecting face pairs it reports; -1 when tetgen is not installed.
long tetgen_pairs(const Mesh& a, const Mesh& b, const seam_test::TempDir& dir) {
  if (std::system("command -v tetgen > /dev/null 2>&1") != 0) return -1;
  return seam_test::tetgen_intersecting_pairs({seam::soup_from_mesh<K>(a), seam::soup_from_mesh<K>(b)}, dir);
}

/// Every invariant of a resolved pair: a2, b2 the inputs, a3, b3 the outputs.
void check_resolved_pair(const Mesh& a2, const Mesh& b2, const Mesh& a3, const Mesh& b3, const seam::ResolveStats& st,
                         const seam_test::TempDir& dir) {
  INFO("keeper " << seam::keeper_name(st.keeper) << ", note: " << st.note);
  for (const Mesh* m : {&a3, &b3}) {
    CHECK(m->is_valid(false));
    CHECK(CGAL::is_triangle_mesh(*m));
    CHECK(CGAL::is_closed(*m));
  }
  // The keeper is unchanged, face for face.
  const bool a_keeps = st.keeper == seam::Keeper::a;
  CHECK(faces_of(a_keeps ? a3 : b3) == faces_of(a_keeps ? a2 : b2));
  // Volumes: the overlap by CGAL's corefinement, every identity exact.
  const K::FT va2 = volume(a2), vb2 = volume(b2), va3 = volume(a3), vb3 = volume(b3);
  const K::FT overlap = intersection_volume(a2, b2);
  CHECK(va3 + vb3 == va2 + vb2 - overlap);  // vol(A3) + vol(B3) = vol(A2 ∪ B2)
  CHECK((a_keeps ? va3 == va2 : vb3 == vb2));
  CHECK(st.overlap_volume == Approx(CGAL::to_double(overlap)).epsilon(1e-12));
  CHECK(st.volume_a_before == Approx(CGAL::to_double(va2)).epsilon(1e-12));
  CHECK(st.volume_b_before == Approx(CGAL::to_double(vb2)).epsilon(1e-12));
  CHECK(st.volume_a_after == Approx(CGAL::to_double(va3)).epsilon(1e-12));
  CHECK(st.volume_b_after == Approx(CGAL::to_double(vb3)).epsilon(1e-12));
  // The contact surface: the same faces in both, opposite orientations.
  CHECK(common_faces(a3, b3) == st.contact_faces);
  CHECK(faces_of(a3).size() > 0);
  // No intersection but on shared faces, edges and vertices; no overlap of the interiors.
  const auto report = seam::check_resolved<K>(a3, b3);
  for (const auto& p : report.problems) UNSCOPED_INFO(p);
  CHECK(report.ok());
  CHECK(report.shared_faces == st.contact_faces);
  CHECK(tetgen_pairs(a3, b3, dir) <= 0);  // -1: no tetgen
}

using seam_test::small_tow;

}  // namespace

TEST_CASE("resolve: a crossover's overlap goes to either tow, closed, disjoint, volumes add up exactly",
          "[resolve]") {
  seam_test::TempDir dir("seam_test_resolve");
  const auto c = seam::make_crossover(30, 14, 23, 12, seam::Section::lenticular, 0.45);
  const auto [a2, b2] = paired(seam::make_tow(c.weft), seam::make_tow(c.warp));
  for (auto keeper : {seam::Keeper::a, seam::Keeper::b, seam::Keeper::automatic}) {
    INFO("keep " << seam::keeper_name(keeper));
    Mesh a3 = a2, b3 = b2;
    seam::ResolveOptions o;
    o.keeper = keeper;
    const auto st = seam::resolve<K>(a3, b3, o);
    CHECK(st.overlap_volume > 0);
    CHECK(st.shared_edges > 0);
    CHECK(st.patches_a_inside > 0);
    CHECK(st.patches_b_inside > 0);
    CHECK(st.faces_added > 0);
    CHECK(st.contact_faces == st.faces_added);  // no flat contact here
    if (keeper != seam::Keeper::automatic) CHECK(st.keeper == keeper);
    // auto: the smaller tow keeps the overlap.
    if (keeper == seam::Keeper::automatic)
      CHECK(st.keeper == (st.volume_a_before <= st.volume_b_before ? seam::Keeper::a : seam::Keeper::b));
    check_resolved_pair(a2, b2, a3, b3, st, dir);
    // Resolving again changes nothing: the tows touch without overlapping.
    Mesh a4 = a3, b4 = b3;
    const auto again = seam::resolve<K>(a4, b4, o);
    CHECK(again.overlap_volume == 0);
    CHECK(again.contact_faces == st.contact_faces);
    CHECK(faces_of(a4) == faces_of(a3));
    CHECK(faces_of(b4) == faces_of(b3));
  }
}

/// An axis-aligned box, outward-oriented, 12 triangles.
seam::TriangleSoup box(const seam::Point3d& lo, const seam::Point3d& hi) {
  seam::TriangleSoup s;
  for (int i = 0; i < 8; ++i) s.points.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  s.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

TEST_CASE("resolve: flat contacts (coplanar overlap) are dropped from the loser, the rest becomes contact",
          "[resolve]") {
  seam_test::TempDir dir("seam_test_resolve_flat");
  // Two boxes overlapping in [1, 2] x [0.5, 1] x [0, 1]: their tops and bottoms coincide there
  // (same orientation), made shared faces by seam::pair.
  const auto [a2, b2] = paired(box({0, 0, 0}, {2, 1, 1}), box({1, 0.5, 0}, {3, 1.5, 1}));
  for (auto keeper : {seam::Keeper::a, seam::Keeper::b}) {
    INFO("keep " << seam::keeper_name(keeper));
    Mesh a3 = a2, b3 = b2;
    seam::ResolveOptions o;
    o.keeper = keeper;
    const auto st = seam::resolve<K>(a3, b3, o);
    CHECK(st.shared_faces > 0);
    CHECK(st.shared_faces_same_orientation == st.shared_faces);
    CHECK(st.overlap_volume == 0.5);
    check_resolved_pair(a2, b2, a3, b3, st, dir);
  }
}

TEST_CASE("resolve: where the loser minus the keeper would be pinched, the input is refused", "[resolve]") {
  // A terraced tow (heights on a grid, as CT tows have) and a copy shifted along y: their crumpled
  // end caps cross in several curves through one point, where the difference of the two solids is
  // pinched whichever tow keeps the overlap: refused, naming the point; the inputs unchanged.
  auto s = seam::make_tow(small_tow());
  for (auto& p : s.points) p[2] = 0.05 * std::round(p[2] / 0.05);
  auto t = s;
  for (auto& p : t.points) p[1] += 0.2;
  const auto [a2, b2] = paired(s, t);
  Mesh a3 = a2, b3 = b2;
  CHECK_THROWS_WITH(seam::resolve<K>(a3, b3), Catch::Contains("not a closed 2-manifold at"));
  CHECK(faces_of(a3) == faces_of(a2));
  CHECK(faces_of(b3) == faces_of(b2));
}

TEST_CASE("resolve: a tow inside another: the smaller keeps it, the other becomes hollow", "[resolve]") {
  seam_test::TempDir dir("seam_test_resolve_nested");
  seam::TowOptions big, small;
  big.crimp_amplitude = small.crimp_amplitude = 0;
  big.segments_along = 10;
  small.length = 4;
  small.half_width = 0.5;
  small.half_height = 0.15;
  small.segments_along = 4;
  small.translate = {3, 0, 0};
  const Mesh a2 = seam::mesh_from_soup<K>(seam::make_tow(big), "big"), b2 = seam::mesh_from_soup<K>(seam::make_tow(small), "small");
  Mesh a3 = a2, b3 = b2;
  const auto st = seam::resolve<K>(a3, b3);
  CHECK(st.keeper == seam::Keeper::b);
  CHECK(st.shared_edges == 0);
  CHECK(st.contact_faces == b2.number_of_faces());
  CHECK(a3.number_of_faces() == a2.number_of_faces() + b2.number_of_faces());
  check_resolved_pair(a2, b2, a3, b3, st, dir);
  // Given to the big tow, nothing of the small one is left: refused, inputs unchanged.
  seam::ResolveOptions o;
  o.keeper = seam::Keeper::a;
  o.name_a = "big.off";
  o.name_b = "small.off";
  Mesh a4 = a2, b4 = b2;
  CHECK_THROWS_AS(seam::resolve<K>(a4, b4, o), seam::InvalidInput);
  CHECK_THROWS_WITH(seam::resolve<K>(a4, b4, o), Catch::Contains("small.off lies inside big.off"));
  CHECK(faces_of(a4) == faces_of(a2));
  CHECK(faces_of(b4) == faces_of(b2));
}

TEST_CASE("resolve: inputs without embedded curves, or open, are refused with InvalidInput", "[resolve]") {
  const auto c = seam::make_crossover(12, 8, 10, 8, seam::Section::elliptical, 0.45);
  Mesh a = seam::mesh_from_soup<K>(seam::make_tow(c.weft), "a"), b = seam::mesh_from_soup<K>(seam::make_tow(c.warp), "b");
  seam::ResolveOptions o;
  o.name_a = "weft.off";
  o.name_b = "warp.off";
  CHECK_THROWS_AS(seam::resolve<K>(a, b, o), seam::InvalidInput);
  CHECK_THROWS_WITH(seam::resolve<K>(a, b, o), Catch::Contains("weft.off, warp.off: not conforming"));
  auto open = c.weft;
  open.capped = false;
  Mesh o1 = seam::mesh_from_soup<K>(seam::make_tow(open), "open");
  CHECK_THROWS_WITH(seam::resolve<K>(o1, b, o), Catch::Contains("weft.off: not closed"));
}

TEST_CASE("resolve: the three kernels give the same outputs", "[resolve]") {
  const auto c = seam::make_crossover(16, 10, 14, 10, seam::Section::elliptical, 0.4);
  const auto [a2, b2] = paired(seam::make_tow(c.weft), seam::make_tow(c.warp));
  const seam::TriangleSoup sa = seam::soup_from_mesh<K>(a2), sb = seam::soup_from_mesh<K>(b2);
  Mesh a3 = a2, b3 = b2;
  const auto st = seam::resolve<K>(a3, b3);
  const auto expect_a = seam::soup_from_mesh<K>(a3), expect_b = seam::soup_from_mesh<K>(b3);
  auto run = [&](auto kernel) {
    using L = decltype(kernel);
    auto a = seam::mesh_from_soup<L>(sa, "a"), b = seam::mesh_from_soup<L>(sb, "b");
    const auto s = seam::resolve<L>(a, b);
    CHECK(s.keeper == st.keeper);
    CHECK(s.overlap_volume == st.overlap_volume);
    CHECK(s.contact_faces == st.contact_faces);
    CHECK(seam::soup_from_mesh<L>(a).points == expect_a.points);
    CHECK(seam::soup_from_mesh<L>(a).triangles == expect_a.triangles);
    CHECK(seam::soup_from_mesh<L>(b).points == expect_b.points);
    CHECK(seam::soup_from_mesh<L>(b).triangles == expect_b.triangles);
    CHECK(seam::check_resolved<L>(a, b).ok());
  };
  run(seam::Filtered{});
  run(seam::Float{});
}

// ------------------------------------------------------------------ the command line

namespace {

struct Run {
  int code = -1;
  std::string out, err;
};

Run run_seam(const seam_test::TempDir& dir, const std::vector<std::string>& args) {
  static int n = 0;
  const std::string id = std::to_string(n++), out = dir.file("stdout" + id), err = dir.file("stderr" + id);
  std::string cmd = "'" SEAM_CLI_PATH "'";
  for (const auto& a : args) cmd += " '" + a + "'";
  cmd += " </dev/null >'" + out + "' 2>'" + err + "'";
  const int status = std::system(cmd.c_str());
  INFO("command: " << cmd);
  REQUIRE(WIFEXITED(status));
  return {WEXITSTATUS(status), seam_test::read_bytes(out), seam_test::read_bytes(err)};
}

}  // namespace

TEST_CASE("cli: seam resolve writes verified outputs and a report, bad input exits 2 writing nothing",
          "[resolve][cli]") {
  seam_test::TempDir dir("seam_test_resolve_cli");
  seam_test::fs::create_directories(dir.path / "out");
  const auto c = seam::make_crossover(16, 10, 14, 10, seam::Section::elliptical, 0.4);
  const auto weft = seam::make_tow(c.weft), warp = seam::make_tow(c.warp);
  const auto [a2, b2] = paired(weft, warp);
  seam::write_triangle_mesh(seam::soup_from_mesh<K>(a2), dir.file("a2.off"));
  seam::write_triangle_mesh(seam::soup_from_mesh<K>(b2), dir.file("b2.off"));
  seam::write_triangle_mesh(weft, dir.file("weft.off"));
  seam::write_triangle_mesh(warp, dir.file("warp.off"));
  const std::string out_a = (dir.path / "out" / "a3.off").string(), out_b = (dir.path / "out" / "b3.off").string(),
                    report = (dir.path / "out" / "r.json").string();
  {
    const Run r = run_seam(dir, {"resolve", dir.file("a2.off"), dir.file("b2.off"), "--out-a", out_a, "--out-b", out_b,
                                 "--keep", "b", "--report", report});
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::StartsWith("seam resolve: B keeps the overlap"));
    CHECK_THAT(r.out, Catch::Contains("verified"));
    const Mesh a3 = seam::mesh_from_soup<K>(seam::read_triangle_mesh(out_a), "a3"),
               b3 = seam::mesh_from_soup<K>(seam::read_triangle_mesh(out_b), "b3");
    CHECK(seam::check_resolved<K>(a3, b3).ok());
    CHECK(seam_test::read_bytes(out_b) == seam_test::read_bytes(dir.file("b2.off")));  // the keeper as read
    const std::string json = seam_test::read_bytes(report);
    for (const char* key : {"\"keeper\": \"b\"", "\"overlap\"", "\"a_after\"", "\"contact_faces\"", "\"verified\": true"})
      CHECK_THAT(json, Catch::Contains(key));
  }
  const auto clean = [&] {
    std::error_code ec;
    seam_test::fs::remove_all(dir.path / "out", ec);
    seam_test::fs::create_directories(dir.path / "out");
  };
  const auto refused = [&](const Run& r, const std::string& names) {
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Catch::StartsWith("seam: ") && Catch::Contains(names) && !Catch::Contains("internal error"));
    CHECK(seam_test::entries(dir.path / "out").empty());
  };
  clean();
  // Not conforming (the tows as generated, curves not embedded).
  refused(run_seam(dir, {"resolve", dir.file("weft.off"), dir.file("warp.off"), "--out-a", out_a, "--out-b", out_b,
                         "--report", report}),
          "weft.off");
  // An output over an input; an unknown --keep; a missing input.
  refused(run_seam(dir, {"resolve", dir.file("a2.off"), dir.file("b2.off"), "--out-a", dir.file("b2.off"), "--out-b", out_b}),
          "b2.off");
  refused(run_seam(dir, {"resolve", dir.file("a2.off"), dir.file("b2.off"), "--out-a", out_a, "--out-b", out_b, "--keep", "c"}),
          "--keep");
  refused(run_seam(dir, {"resolve", dir.file("none.off"), dir.file("b2.off"), "--out-a", out_a, "--out-b", out_b}),
          "none.off");
}

TEST_CASE("cli: seam textile --resolve leaves the tows touching without overlap", "[resolve][cli][textile]") {
  seam_test::TempDir dir("seam_test_textile_resolve");
  const auto c = seam::make_crossover(16, 10, 14, 10, seam::Section::elliptical, 0.4);
  seam::write_triangle_mesh(seam::make_tow(c.weft), dir.file("weft.off"));
  seam::write_triangle_mesh(seam::make_tow(c.warp), dir.file("warp.off"));
  const std::string out = (dir.path / "out").string();
  const Run r = run_seam(dir, {"textile", dir.file("weft.off"), dir.file("warp.off"), "--out-dir", out, "--resolve",
                               "--no-improve", "--quiet", "--report", dir.file("r.json")});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("resolved: 1 pairs"));
  CHECK(seam_test::entries(dir.path / "out") == std::vector<std::string>{"warp.off", "weft.off"});  // no curves files
  const Mesh a3 = seam::mesh_from_soup<K>(seam::read_triangle_mesh(out + "/weft.off"), "weft"),
             b3 = seam::mesh_from_soup<K>(seam::read_triangle_mesh(out + "/warp.off"), "warp");
  const auto check = seam::check_resolved<K>(a3, b3);
  for (const auto& p : check.problems) UNSCOPED_INFO(p);
  CHECK(check.ok());
  CHECK(check.shared_faces > 0);
  CHECK_THAT(seam_test::read_bytes(dir.file("r.json")), Catch::Contains("\"resolve\""));
}
