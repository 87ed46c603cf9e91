// Tests of seam::textile and `seam textile`: all the crossings of a generated unit cell made
// conforming at once. Every pair is verified with seam::check_pair, the code of `seam check`.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/textile.h>

#include <algorithm>
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

struct Cell {
  std::vector<std::string> names;
  std::vector<seam::TriangleSoup> soups;
  template <class Kernel> std::vector<seam::Mesh<Kernel>> meshes() const {
    std::vector<seam::Mesh<Kernel>> m;
    for (std::size_t i = 0; i < soups.size(); ++i) m.push_back(seam::mesh_from_soup<Kernel>(soups[i], names[i]));
    return m;
  }
};

Cell weave(const seam::WeaveOptions& o) {
  Cell c;
  for (const auto& t : seam::make_weave(o)) {
    c.names.push_back(t.name);
    c.soups.push_back(seam::make_tow(t.options));
  }
  return c;
}

seam::WeaveOptions small_weave(int warps, int wefts) {
  seam::WeaveOptions o;
  o.warps = warps;
  o.wefts = wefts;
  o.segments_per_crossing = 10;
  o.segments_around = 14;
  return o;
}

/// Runs textile and checks every reported pair with seam::check_pair (tolerance 1e-9, above the
/// automatic snapping tolerance, 1e-10 x the diagonal of a tow).
/// `close_vertices_known`: the three-tow cell below, whose outputs keep vertices 2e-16 apart (a
/// ring vertex of A at x = 0 and a curve point at x = -2.2e-16: B's quarter turn is not exact),
/// closer than a volume mesher's tolerance (seam check's check 5): textile has no pass that
/// merges them yet, so only that problem is tolerated there.
seam::TextileResult<K> run_and_check(const Cell& cell, int threads, std::vector<Mesh>* outputs = nullptr,
                                     bool close_vertices_known = false) {
  const auto inputs = cell.meshes<K>();
  auto meshes = inputs;
  seam::TextileOptions options;
  options.threads = threads;
  auto result = seam::textile<K>(meshes, cell.names, options);
  // Every pair was verified as written (textile throws otherwise), and checks here as it is.
  CHECK(result.stats.verified);
  CHECK(result.stats.improved == (result.stats.intersecting_pairs > 0));
  const double tol = std::max(1e-9, result.stats.verify_tolerance);
  for (const auto& p : result.pairs) {
    INFO(cell.names[p.stats.a] << " x " << cell.names[p.stats.b]);
    const auto report = seam::check_pair<K>(inputs[p.stats.a], inputs[p.stats.b], meshes[p.stats.a],
                                            meshes[p.stats.b], p.curves, tol);
    for (const auto& problem : report.problems) UNSCOPED_INFO(problem);
    if (close_vertices_known && report.close_vertex_pairs > 0)
      CHECK(report.problems.size() == 1);
    else
      CHECK(report.ok());
    CHECK(report.curve_vertices == p.stats.curve_vertices);
  }
  if (outputs) *outputs = std::move(meshes);
  return result;
}

std::set<std::pair<std::string, std::string>> pair_names(const Cell& cell, const seam::TextileResult<K>& r) {
  std::set<std::pair<std::string, std::string>> s;
  for (const auto& p : r.pairs) s.emplace(cell.names[p.stats.a], cell.names[p.stats.b]);
  return s;
}

using seam_test::run_command;

/// Writes meshes as one OFF with their common vertices merged (what a volume mesher is given).
void write_merged(const std::vector<seam::TriangleSoup>& soups, const std::string& path) {
  seam::TriangleSoup merged;
  std::map<seam::Point3d, std::size_t> index;
  for (const auto& s : soups) {
    std::vector<std::size_t> map(s.points.size());
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      auto [it, inserted] = index.try_emplace(s.points[i], merged.points.size());
      if (inserted) merged.points.push_back(s.points[i]);
      map[i] = it->second;
    }
    for (const auto& t : s.triangles) merged.triangles.push_back({map[t[0]], map[t[1]], map[t[2]]});
  }
  seam::write_triangle_mesh(merged, path);
}

/// `tetgen -d` on a surface: the number of intersecting face pairs it reports (0 for "No faces are
/// intersecting."), or -1 when its output says neither.
long tetgen_intersecting_pairs(const std::string& off, const seam_test::TempDir& dir) {
  const std::string log = dir.file("tetgen.log");
  run_command("cd '" + dir.path.string() + "' && tetgen -d '" + off + "' > '" + log + "' 2>&1");
  const std::string text = seam_test::read_bytes(log);
  if (text.find("No faces are intersecting.") != std::string::npos) return 0;
  const auto at = text.find("!! Found ");
  if (at == std::string::npos) return -1;
  return std::strtol(text.c_str() + at + 9, nullptr, 10);
}

}  // namespace

TEST_CASE("make_weave: a plain weave's tows pass over and under alternately", "[textile]") {
  const auto tows = seam::make_weave(small_weave(2, 3));
  REQUIRE(tows.size() == 5);
  CHECK(tows[0].name == "weft0");
  CHECK(tows[3].name == "warp0");
  // weft j over warp i when i + j is even, and the warp then under it.
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 2; ++i) {
      const double weft = tows[std::size_t(j)].options.heights[std::size_t(i)];
      const double warp = tows[std::size_t(3 + i)].options.heights[std::size_t(j)];
      CHECK(weft == -warp);
      CHECK((weft > 0) == ((i + j) % 2 == 0));
    }
  for (const auto& t : tows) {
    const auto soup = seam::make_tow(t.options);
    REQUIRE_NOTHROW(seam::validate_triangle_mesh(soup, t.name));
  }
  seam::WeaveOptions bad = small_weave(2, 2);
  bad.overlap = 0.5;  // more than the tows are thick
  CHECK_THROWS_AS(seam::make_weave(bad), seam::InvalidInput);
}

TEST_CASE("textile: a 2x2 plain weave conforms at every crossing", "[textile]") {
  const Cell cell = weave(small_weave(2, 2));
  std::vector<Mesh> out;
  const auto r = run_and_check(cell, 2, &out);
  // The four weft-warp crossings, and no pair of parallel tows (they are apart).
  CHECK(pair_names(cell, r) == std::set<std::pair<std::string, std::string>>{
                                   {"weft0", "warp0"}, {"weft0", "warp1"}, {"weft1", "warp0"}, {"weft1", "warp1"}});
  CHECK(r.stats.candidate_pairs == 4);
  CHECK(r.stats.intersecting_pairs == 4);
  for (const auto& p : r.pairs) {
    CHECK(p.stats.curves >= 1);
    CHECK(p.stats.closed_curves == p.stats.curves);  // closed tows cross in closed curves
    CHECK(p.stats.quality_a.faces > 0);
    CHECK(p.stats.quality_b.faces > 0);
  }
  // Each tow received the curves of both its crossings.
  REQUIRE(r.tows.size() == 4);
  for (const auto& t : r.tows) CHECK(t.curves >= 2);
  for (const auto& m : out) CHECK(CGAL::is_closed(m));
}

TEST_CASE("textile: an area bound gives verified outputs with every new face's points apart", "[textile][max-area]") {
  // Before, a 2x2 weave under --max-area was refused (exit 3): Steiner points of the area
  // refinement came closer than the vertex separation to each other and to the other tow, and,
  // rounded, put new faces through the other tow where two tows touch over an area. The quality
  // stage then refines to the area bound as well as to the angle bound.
  const Cell cell = weave(small_weave(2, 2));
  const auto inputs = cell.meshes<K>();
  auto meshes = inputs;
  seam::TextileOptions options;
  options.embed.max_area = 0.01;
  const auto r = seam::textile<K>(meshes, cell.names, options);
  CHECK(r.stats.verified);
  CHECK(r.stats.improved);
  CHECK(r.stats.improve.above_max_area_after == 0);  // the faces held to the bound all meet it
  CHECK(r.stats.intersecting_pairs == 4);
  std::size_t steiner = 0;
  for (const auto& t : r.tows) steiner += t.steiner_points;
  CHECK(steiner > 0);
  for (const auto& p : r.pairs) {
    INFO(cell.names[p.stats.a] << " x " << cell.names[p.stats.b]);
    const auto report = seam::check_pair<K>(inputs[p.stats.a], inputs[p.stats.b], meshes[p.stats.a], meshes[p.stats.b],
                                            p.curves, std::max(1e-9, r.stats.verify_tolerance));
    for (const auto& problem : report.problems) UNSCOPED_INFO(problem);
    CHECK(report.ok());
  }
}

TEST_CASE("textile: the quality stage refines along every curve of every tow at once, within its tolerance",
          "[textile][improve]") {
  // Without it a third of the faces along the curves are below 10 degrees; with it, every face
  // below the bound is reported with its cause, none for want of budget, and the outputs verify.
  const Cell cell = weave(small_weave(2, 2));
  auto below = [](const seam::TextileResult<K>& r, std::size_t seam::CurveFaceQuality::*count) {
    std::size_t n = 0;
    for (const auto& p : r.pairs) n += p.stats.quality_a.*count + p.stats.quality_b.*count;
    return n;
  };
  seam::TextileOptions plain;
  plain.improve = false;
  auto m1 = cell.meshes<K>(), m2 = m1;
  const auto r1 = seam::textile<K>(m1, cell.names, plain);
  const auto r2 = seam::textile<K>(m2, cell.names, seam::TextileOptions{});
  CHECK_FALSE(r1.stats.improved);
  REQUIRE(r2.stats.improved);
  CHECK(r1.stats.verified);
  CHECK(r2.stats.verified);
  CHECK(r2.stats.note.empty());  // the improved tows were given, not the fallback
  const std::size_t before = below(r1, &seam::CurveFaceQuality::below_10);
  const std::size_t after = below(r2, &seam::CurveFaceQuality::below_10);
  INFO("below 10 degrees: " << before << " -> " << after);
  CHECK(before > 100);
  CHECK(after * 20 <= before);
  CHECK(below(r2, &seam::CurveFaceQuality::below_20) <= r2.stats.improve.shortfalls.size());
  for (const auto& s : r2.stats.improve.shortfalls) CHECK(s.cause != seam::ShortfallCause::budget);
  CHECK(r2.stats.improve_tolerance > 0);
  CHECK(r2.stats.verify_tolerance >= r2.stats.improve_tolerance);
  // Every tow holds exactly the curves of its pairs, point for point.
  auto key = [](const K::Point_3& q) {
    return std::array<double, 3>{CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())};
  };
  for (const auto& p : r2.pairs)
    for (const auto* m : {&m2[p.stats.a], &m2[p.stats.b]}) {
      std::map<std::array<double, 3>, Mesh::Vertex_index> at;
      for (auto w : m->vertices()) at[key(m->point(w))] = w;
      auto vertex = [&](const K::Point_3& q) {
        const auto it = at.find(key(q));
        return it != at.end() && m->point(it->second) == q ? it->second : Mesh::null_vertex();
      };
      for (const auto& c : p.curves)
        for (std::size_t i = 0; i + 1 < c.size(); ++i) {
          const auto u = vertex(c[i]), v = vertex(c[i + 1]);
          REQUIRE(u != Mesh::null_vertex());
          REQUIRE(v != Mesh::null_vertex());
          CHECK(m->halfedge(u, v) != Mesh::null_halfedge());
        }
    }
}

TEST_CASE("textile: a 2/1 twill of 3x3 tows conforms at every crossing", "[textile]") {
  seam::WeaveOptions o = small_weave(3, 3);
  o.over = 2;
  o.under = 1;
  o.section = seam::Section::lenticular;
  const Cell cell = weave(o);
  const auto r = run_and_check(cell, 2);
  CHECK(r.stats.intersecting_pairs == 9);
  CHECK(r.pairs.size() == 9);
}

TEST_CASE("textile: snapping each tow onto all its curves, then computing them again, conforms", "[textile]") {
  const Cell cell = weave(small_weave(2, 2));
  const auto inputs = cell.meshes<K>();
  auto meshes = inputs;
  seam::TextileOptions options;
  options.embed.snap_tol = 0.02;  // about 0.15 x the mean edge length
  options.improve = false;        // (its tolerance would move the surfaces too)
  const auto r = seam::textile<K>(meshes, cell.names, options);
  std::size_t snapped = 0;
  for (const auto& t : r.tows) snapped += t.vertices_snapped;
  CHECK(snapped > 0);
  CHECK(r.stats.intersecting_pairs == 4);
  for (const auto& p : r.pairs) {
    const auto report = seam::check_pair<K>(inputs[p.stats.a], inputs[p.stats.b], meshes[p.stats.a],
                                            meshes[p.stats.b], p.curves, 0.02 + 1e-12);
    for (const auto& problem : report.problems) UNSCOPED_INFO(problem);
    CHECK(report.ok());
    CHECK(report.max_distance_a > 0);  // the surfaces did move
  }
}

TEST_CASE("textile: tows that do not touch give no pair and unchanged meshes", "[textile]") {
  seam::WeaveOptions o = small_weave(2, 2);
  o.overlap = -0.02;  // a gap at every crossing: the boxes overlap, the surfaces do not meet
  const Cell cell = weave(o);
  std::vector<Mesh> out;
  const auto r = run_and_check(cell, 2, &out);
  CHECK(r.stats.candidate_pairs == 4);
  CHECK(r.pairs.empty());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto in = seam::soup_from_mesh<K>(cell.meshes<K>()[i]);
    const auto o2 = seam::soup_from_mesh<K>(out[i]);
    CHECK(in.points == o2.points);
    CHECK(in.triangles == o2.triangles);
  }

  // Mixed: one warp lifted clear of the cell, the other still crossing both wefts.
  Cell mixed = weave(small_weave(2, 2));
  for (auto& p : mixed.soups[3].points) p[2] += 1.0;  // warp1
  const auto rm = run_and_check(mixed, 2);
  CHECK(pair_names(mixed, rm) == std::set<std::pair<std::string, std::string>>{{"weft0", "warp0"}, {"weft1", "warp0"}});
}

TEST_CASE("textile: results are identical for 1 and 2 threads", "[textile]") {
  const Cell cell = weave(small_weave(2, 2));
  std::vector<Mesh> one, two;
  const auto r1 = run_and_check(cell, 1, &one);
  const auto r2 = run_and_check(cell, 2, &two);
  CHECK(r1.stats.threads == 1);
  CHECK(r2.stats.threads == 2);
  REQUIRE(one.size() == two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    const auto a = seam::soup_from_mesh<K>(one[i]), b = seam::soup_from_mesh<K>(two[i]);
    CHECK(a.points == b.points);
    CHECK(a.triangles == b.triangles);
  }
  REQUIRE(r1.pairs.size() == r2.pairs.size());
  for (std::size_t p = 0; p < r1.pairs.size(); ++p) {
    CHECK(r1.pairs[p].stats.a == r2.pairs[p].stats.a);
    CHECK(r1.pairs[p].stats.b == r2.pairs[p].stats.b);
    CHECK(seam::to_doubles<K>(r1.pairs[p].curves) == seam::to_doubles<K>(r2.pairs[p].curves));
  }
}

/// A straight tow along x, and two along y side by side that overlap each other and both dip into
/// the first: on its top the curves with the two meet, at points on all three surfaces.
Cell triple_cell() {
  seam::TowOptions a;
  a.length = 4;
  a.crimp_amplitude = 0;
  a.half_height = 0.3;
  a.segments_along = 24;
  a.segments_around = 20;
  a.translate = {-2, 0, 0};
  seam::TowOptions b = a;
  b.rotate_z = M_PI / 2;
  b.segments_along = 25;
  b.segments_around = 22;
  b.translate = {-0.3, -2, 0.4};
  seam::TowOptions c = b;
  c.length = 4.2;  // longer: its end caps do not lie in the plane of B's (a flat contact)
  c.translate = {0.3, -2.1, 0.4};
  Cell cell;
  cell.names = {"A", "B", "C"};
  for (const auto& t : {a, b, c}) cell.soups.push_back(seam::make_tow(t));
  return cell;
}

TEST_CASE("textile: where three tows overlap, the meeting point is a vertex of all three", "[textile]") {
  const Cell cell = triple_cell();
  std::vector<Mesh> out;
  const auto r = run_and_check(cell, 2, &out, true);  // every pair conforms
  CHECK(r.stats.intersecting_pairs == 3);
  CHECK(r.stats.triple_points >= 2);  // two meetings at least on the top of A (B and C overlap)
  // Points of the curves of A with B that are curve points of A with C too: vertices of all three.
  std::set<seam::Point3d> ab, ac, bc;
  for (const auto& p : r.pairs) {
    auto& s = p.stats.a == 0 && p.stats.b == 1 ? ab : p.stats.a == 0 ? ac : bc;
    for (const auto& c : seam::to_doubles<K>(p.curves)) s.insert(c.begin(), c.end());
  }
  std::size_t shared = 0;
  for (const auto& x : ab)
    if (ac.count(x)) {
      ++shared;
      CHECK(bc.count(x) == 1);
      for (const auto& m : out) {
        const auto soup = seam::soup_from_mesh<K>(m);
        CHECK(std::count(soup.points.begin(), soup.points.end(), x) == 1);
      }
    }
  CHECK(shared == r.stats.triple_points);
}

TEST_CASE("textile: tetgen finds no intersecting faces in the whole cell once embedded", "[textile]") {
  // All the output tows written as one surface (written to doubles and read back by TetGen), for
  // a plain weave and for the three tows overlapping in one place.
  for (const bool triple : {false, true}) {
    const Cell cell = triple ? triple_cell() : weave(small_weave(2, 2));
    seam_test::TempDir dir("seam_test_textile_tetgen");
    std::vector<Mesh> out;
    run_and_check(cell, 2, &out, triple);
    std::vector<seam::TriangleSoup> soups;
    for (const auto& m : out) soups.push_back(seam::soup_from_mesh<K>(m));
    write_merged(cell.soups, dir.file("inputs.off"));
    write_merged(soups, dir.file("outputs.off"));
    const long before = tetgen_intersecting_pairs("inputs.off", dir);
    const long after = tetgen_intersecting_pairs("outputs.off", dir);
    INFO(seam_test::read_bytes(dir.file("tetgen.log")));
    CHECK(before > 10);
    CHECK(after == 0);
  }
}

TEST_CASE("textile: under a rounded kernel a triple overlap stops the run, naming a tow", "[textile]") {
  // Rounded curve points of two neighbours meet within rounding: refused when the segments are
  // seen to meet, otherwise the re-triangulation of the tow fails; never a broken mesh.
  const Cell cell = triple_cell();
  auto meshes = cell.meshes<seam::Filtered>();
  try {
    seam::textile<seam::Filtered>(meshes, cell.names, {});
    FAIL("no exception");
  } catch (const seam::Error& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains("triple overlap") || Catch::Contains("use --kernel exact"));
    CHECK_THAT(what, Catch::Contains("'A'") || Catch::Contains("'B'") || Catch::Contains("'C'"));
  }
}

// Every pair's curves are those seam::pair finds on the same two tows (without snapping), under
// the exact and the filtered kernel. (Under the rounded kernels seam::pair's own outputs can cross
// next to the curve on these crossings, so seam::check_pair is run under the exact kernel only.)
TEST_CASE("textile: the curves of each pair are seam::pair's", "[textile]") {
  const Cell cell = weave(small_weave(2, 2));
  for (auto kind : {seam::KernelKind::exact, seam::KernelKind::filtered}) {
    seam::with_kernel(kind, [&](auto k) {
      using Kernel = decltype(k);
      INFO(seam::kernel_name(kind));
      const auto inputs = cell.meshes<Kernel>();
      auto meshes = inputs;
      seam::TextileOptions options;
      options.embed.snap_tol = 0;
      options.improve = false;  // (the quality stage splits curve segments)
      const auto r = seam::textile<Kernel>(meshes, cell.names, options);
      CHECK(r.stats.intersecting_pairs == 4);
      for (const auto& p : r.pairs) {
        auto a = inputs[p.stats.a], b = inputs[p.stats.b];
        seam::PairOptions po;
        po.embed.snap_tol = 0;
        po.improve = false;  // (the quality stage splits curve segments)
        const auto pr = seam::pair<Kernel>(a, b, po);
        // The same closed curves from the same first point; the direction may differ (textile
        // intersects only the parts of the tows whose boxes meet, so the pieces come in another order).
        REQUIRE(pr.curves.size() == p.curves.size());
        for (std::size_t c = 0; c < p.curves.size(); ++c) {
          auto reversed = p.curves[c];
          std::reverse(reversed.begin(), reversed.end());
          CHECK((pr.curves[c] == p.curves[c] || pr.curves[c] == reversed));
        }
      }
      return 0;
    });
  }
}

TEST_CASE("cli: seam textile writes every tow and pair, seam check passes on each, any thread count", "[textile][cli]") {
  seam_test::TempDir dir("seam_test_textile");
  const Cell cell = weave(small_weave(2, 2));
  std::string tows, list;
  for (std::size_t i = 0; i < cell.soups.size(); ++i) {
    seam::write_triangle_mesh(cell.soups[i], dir.file(cell.names[i] + ".off"));
    tows += " '" + dir.file(cell.names[i] + ".off") + "'";
    list += cell.names[i] + ".off\n";
  }
  seam_test::write_bytes(dir.file("tows.txt"), "# the cell\n" + list);
  const std::string seam = SEAM_CLI_PATH;
  const std::string out1 = dir.file("out1"), out2 = dir.file("out2");
  REQUIRE(run_command(seam + " textile" + tows + " --out-dir '" + out1 + "' --threads 1 --report '" +
                      dir.file("r.json") + "' > '" + dir.file("log1") + "' 2> '" + dir.file("err1") + "'") == 0);
  // Progress on stderr by default.
  CHECK_THAT(seam_test::read_bytes(dir.file("err1")), Catch::Contains("pairs 4/4"));
  REQUIRE(run_command(seam + " textile --tows '" + dir.file("tows.txt") + "' --out-dir '" + out2 +
                      "' --threads 2 --quiet > /dev/null 2> '" + dir.file("err2") + "'") == 0);
  CHECK(seam_test::read_bytes(dir.file("err2")).empty());  // --quiet

  const std::vector<std::string> expected = {"warp0.off",
                                             "warp1.off",
                                             "weft0.off",
                                             "weft0__warp0.polylines.txt",
                                             "weft0__warp1.polylines.txt",
                                             "weft1.off",
                                             "weft1__warp0.polylines.txt",
                                             "weft1__warp1.polylines.txt"};
  // The tolerance textile verified every pair at, from its summary line.
  const std::string log = seam_test::read_bytes(dir.file("log1"));
  const auto at = log.find("verified (seam check --tol ");
  REQUIRE(at != std::string::npos);
  const std::string tol = log.substr(at + 27, log.find(')', at) - at - 27);
  CHECK(std::stod(tol) > 0);
  CHECK(seam_test::entries(out1) == expected);
  CHECK(seam_test::entries(out2) == expected);
  for (const auto& name : expected)  // byte-identical for 1 and 2 threads
    CHECK(seam_test::read_bytes(out1 + "/" + name) == seam_test::read_bytes(out2 + "/" + name));
  for (const auto& weft : {"weft0", "weft1"})
    for (const auto& warp : {"warp0", "warp1"}) {
      const std::string a = weft, b = warp;
      const std::string cmd = seam + " check '" + dir.file(a + ".off") + "' '" + dir.file(b + ".off") + "' '" + out1 +
                              "/" + a + ".off' '" + out1 + "/" + b + ".off' '" + out1 + "/" + a + "__" + b +
                              ".polylines.txt' --tol " + tol + " > /dev/null";
      CHECK(run_command(cmd) == 0);
    }
  const std::string report = seam_test::read_bytes(dir.file("r.json"));
  CHECK_THAT(report, Catch::Contains("\"intersecting_pairs\": 4"));
  CHECK_THAT(report, Catch::Contains("\"below_10\""));
}

TEST_CASE("cli: seam textile rejects bad input with exit 2, one line, and writes nothing", "[textile][cli]") {
  seam_test::TempDir dir("seam_test_textile_bad");
  const Cell cell = weave(small_weave(1, 1));
  seam::write_triangle_mesh(cell.soups[0], dir.file("a.off"));
  std::filesystem::create_directories(dir.path / "other");
  seam::write_triangle_mesh(cell.soups[1], dir.file("other/a.off"));
  seam_test::write_bytes(dir.file("bad.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
  const std::string seam = SEAM_CLI_PATH, out = dir.file("out");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"'" + dir.file("a.off") + "' '" + dir.file("other/a.off") + "'", "same base name"},
      {"'" + dir.file("a.off") + "' '" + dir.file("bad.off") + "'", "bad.off"},
      {"'" + dir.file("a.off") + "' '" + dir.file("missing.off") + "'", "missing.off"},
      {"--tows '" + dir.file("missing.txt") + "'", "missing.txt"},
  };
  for (const auto& [args, needle] : cases) {
    INFO(args);
    CHECK(run_command(seam + " textile " + args + " --out-dir '" + out + "' --quiet > /dev/null 2> '" +
                      dir.file("err") + "'") == 2);
    const std::string err = seam_test::read_bytes(dir.file("err"));
    CHECK_THAT(err, Catch::StartsWith("seam: ") && Catch::Contains(needle));
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK(!std::filesystem::exists(out));
  }
}

TEST_CASE("textile: a tow in flat contact with two others shares one common triangulation with each", "[textile][flat_contacts]") {
  // A terraced tow (heights rounded to multiples of 0.05, like a tow from a voxel scan) between two
  // copies of itself moved by +-1 across it, heights kept: their tops and bottoms coincide with
  // the middle tow's over areas. The copies do not meet each other.
  auto terraced = seam::make_tow(seam_test::small_tow());
  for (auto& p : terraced.points) p[2] = 0.05 * std::round(p[2] / 0.05);
  // The middle tow second: the second tow of its first pair, the first of its second (pairs are
  // made in input order), so that its curves with each neighbour follow both contacts.
  Cell cell;
  for (const double dy : {1.0, 0.0, -1.0}) {
    auto copy = terraced;
    for (auto& p : copy.points) p[1] += dy;
    cell.soups.push_back(copy);
  }
  cell.names = {"left", "middle", "right"};
  std::vector<Mesh> out;
  const auto r = run_and_check(cell, 2, &out);  // every pair conforms, as written and as it is
  REQUIRE(r.stats.intersecting_pairs == 2);
  // Each pair's contact is one triangulation: its shared faces are faces of both outputs, and the
  // middle tow holds both contacts' faces (the second contact kept the first's).
  auto faces_of = [](const Mesh& m) {
    std::set<std::array<seam::Point3d, 3>> faces;
    const auto soup = seam::soup_from_mesh<K>(m);
    for (const auto& t : soup.triangles) {
      std::array<seam::Point3d, 3> f = {soup.points[t[0]], soup.points[t[1]], soup.points[t[2]]};
      std::sort(f.begin(), f.end());
      faces.insert(f);
    }
    return faces;
  };
  const auto middle = faces_of(out[1]);
  std::size_t shared_total = 0;
  for (const auto& p : r.pairs) {
    INFO(cell.names[p.stats.a] << " x " << cell.names[p.stats.b]);
    REQUIRE((p.stats.a == 1 || p.stats.b == 1));
    CHECK(p.stats.contact_patches > 0);
    CHECK(p.stats.contact_patches_left == 0);
    CHECK(p.stats.shared_faces > 0);
    std::size_t in_both = 0;
    for (const auto& f : faces_of(out[p.stats.a == 1 ? p.stats.b : p.stats.a])) in_both += middle.count(f);
    CHECK(in_both == p.stats.shared_faces);
    shared_total += in_both;
  }
  CHECK(shared_total > 0);
  // The whole cell as one surface (a face of two tows written once): TetGen finds no
  // intersecting faces.
  seam_test::TempDir dir("seam_test_textile_contacts");
  std::vector<seam::TriangleSoup> soups;
  for (const auto& m : out) soups.push_back(seam::soup_from_mesh<K>(m));
  seam_test::write_merged(soups, dir.file("outputs.off"));
  CHECK(tetgen_intersecting_pairs("outputs.off", dir) == 0);
}
