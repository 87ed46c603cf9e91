// seam textile where a tow crosses an area over which two others coincide (a flat contact): its
// curves with the two run along the same segments there. Found on CT tows against copies of
// themselves moved along a grid plane (docs/real_tows.md, cells 5 and 6), which textile refused
// as a triple overlap along a segment. Now the points of both curves on that stretch become
// vertices of the crossing tow (step 3), the flat contact keeps those segments as constraints
// (step 4b), and the quality stage takes each common segment once (step 5).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/io.h>
#include <seam/textile.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "test_support.h"
#include "tow_fixtures.h"

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using Point = K::Point_3;

/// The segments of `curves`, each as (smaller point, larger point).
std::set<std::pair<Point, Point>> segments_of(const std::vector<seam::Polyline<K>>& curves) {
  std::set<std::pair<Point, Point>> out;
  for (const auto& c : curves)
    for (std::size_t i = 0; i + 1 < c.size(); ++i) out.insert(std::minmax(c[i], c[i + 1]));
  return out;
}

bool has_edge(const M& m, const Point& p, const Point& q) {
  for (auto e : m.edges()) {
    const auto h = m.halfedge(e);
    const auto &s = m.point(m.source(h)), &t = m.point(m.target(h));
    if ((s == p && t == q) || (s == q && t == p)) return true;
  }
  return false;
}

struct Run {
  std::vector<M> inputs, out;
  seam::TextileResult<K> result;
};

/// textile on `soups` (names a, b, c); every pair checked again with seam::check_pair at the
/// reported tolerance.
Run run_and_check(const std::vector<seam::TriangleSoup>& soups, bool improve) {
  const std::vector<std::string> names{"a", "b", "c"};
  Run run;
  for (std::size_t i = 0; i < soups.size(); ++i) run.inputs.push_back(seam::mesh_from_soup<K>(soups[i], names[i]));
  run.out = run.inputs;
  seam::TextileOptions options;
  options.improve = improve;
  run.result = seam::textile<K>(run.out, names, options);
  INFO(run.result.stats.note);
  REQUIRE(run.result.stats.verified);
  // The quality stage ran and its result is the one given (no fallback).
  CHECK(run.result.stats.improved == improve);
  CHECK(run.result.stats.note.find("quality stage") == std::string::npos);
  for (const auto& p : run.result.pairs) {
    INFO(names[p.stats.a] << " x " << names[p.stats.b]);
    const auto report = seam::check_pair<K>(run.inputs[p.stats.a], run.inputs[p.stats.b], run.out[p.stats.a],
                                            run.out[p.stats.b], p.curves,
                                            std::max(1e-9, run.result.stats.verify_tolerance));
    for (const auto& problem : report.problems) UNSCOPED_INFO(problem);
    CHECK(report.ok());
  }
  return run;
}

/// The invariants of a tow crossing the flat contact of two others: the three pairs meet; the
/// crossing tow's curves with the two share segments, and each of those is an edge of all three
/// outputs; `tetgen -d` finds no intersection in the three outputs merged.
void check_flat_crossing(const Run& run, const std::string& what) {
  INFO(what);
  const auto& pairs = run.result.pairs;
  REQUIRE(pairs.size() == 3);  // a-b (the flat contact), a-c, b-c
  CHECK(pairs[0].stats.contact_patches >= 1);
  const auto ac = segments_of(pairs[1].curves), bc = segments_of(pairs[2].curves);
  std::vector<std::pair<Point, Point>> common;
  std::set_intersection(ac.begin(), ac.end(), bc.begin(), bc.end(), std::back_inserter(common));
  CHECK(common.size() >= 4);
  CHECK(run.result.stats.flat_crossing_points > 0);
  for (const auto& [p, q] : common)
    for (const auto& m : run.out) CHECK(has_edge(m, p, q));
  seam_test::TempDir dir("seam_flat_crossing");
  std::vector<seam::TriangleSoup> soups;
  for (const auto& m : run.out) soups.push_back(seam::soup_from_mesh<K>(m));
  CHECK(seam_test::tetgen_intersecting_pairs(soups, dir) == 0);
}

/// The message of the InvalidInput seam::textile throws on `meshes` (empty when it throws none).
template <class Kernel>
std::string refusal(std::vector<seam::Mesh<Kernel>> meshes, const std::vector<std::string>& names) {
  try {
    seam::textile<Kernel>(meshes, names);
  } catch (const seam::InvalidInput& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("textile: a tow crossing inside the flat contact of two others", "[textile][flat]") {
  // a and b coincide over part of the plane x = 1 (b is moved and larger there, so the two
  // triangulate it differently); c crosses that plane inside the contact.
  const std::vector<seam::TriangleSoup> soups{seam_test::box_soup({0, 0, 0}, {1, 1, 1}),
                                              seam_test::box_soup({1, -0.2, 0.1}, {2, 1.1, 1.2}),
                                              seam_test::box_soup({0.5, 0.3, 0.2}, {1.5, 0.6, 0.8})};
  for (const bool improve : {false, true}) {
    const Run run = run_and_check(soups, improve);
    check_flat_crossing(run, improve ? "with the quality stage" : "without the quality stage");
  }
}

TEST_CASE("textile: a tow crossing the border of the flat contact of two others", "[textile][flat]") {
  // As above, but c leaves the contact through its border (y = 1, where a ends and b goes on):
  // its curves with a and with b run together inside the contact and part there.
  const std::vector<seam::TriangleSoup> soups{seam_test::box_soup({0, 0, 0}, {1, 1, 1}),
                                              seam_test::box_soup({1, -0.2, 0.1}, {2, 1.1, 1.2}),
                                              seam_test::box_soup({0.5, 0.3, 0.2}, {1.5, 1.05, 0.8})};
  for (const bool improve : {false, true}) {
    const Run run = run_and_check(soups, improve);
    check_flat_crossing(run, improve ? "with the quality stage" : "without the quality stage");
    CHECK(run.result.stats.triple_points >= 2);  // where the curves part, on the contact's border
  }
}

TEST_CASE("textile: three tows coinciding over an area are refused naming them; a flat crossing under a rounded kernel "
          "too",
          "[textile][flat]") {
  {
    // Three copies of the unit cube moved along y: the three coincide over parts of four of its
    // faces, and their curves run along the same edges.
    std::vector<M> meshes{seam::mesh_from_soup<K>(seam_test::box_soup({0, 0, 0}, {1, 1, 1}), "p"),
                          seam::mesh_from_soup<K>(seam_test::box_soup({0, 0.3, 0}, {1, 1.3, 1}), "q"),
                          seam::mesh_from_soup<K>(seam_test::box_soup({0, -0.3, 0}, {1, 0.7, 1}), "r")};
    const std::string what = refusal<K>(meshes, {"p", "q", "r"});
    CHECK_THAT(what, Catch::Contains("'p', 'q' and 'r'") && Catch::Contains("run along one segment"));
  }
  {
    // The first case above under the filtered kernel: refused as before (exact constructions
    // are needed to make the overlap's points vertices).
    using KF = seam::Filtered;
    std::vector<seam::Mesh<KF>> meshes{
        seam::mesh_from_soup<KF>(seam_test::box_soup({0, 0, 0}, {1, 1, 1}), "a"),
        seam::mesh_from_soup<KF>(seam_test::box_soup({1, -0.2, 0.1}, {2, 1.1, 1.2}), "b"),
        seam::mesh_from_soup<KF>(seam_test::box_soup({0.5, 0.3, 0.2}, {1.5, 0.6, 0.8}), "c")};
    const std::string what = refusal<KF>(meshes, {"a", "b", "c"});
    CHECK_THAT(what, Catch::Contains("triple overlap") && Catch::Contains("use --kernel exact"));
  }
}

TEST_CASE("textile: points of a flat crossing closer than the vertex separation are refused naming the three tows",
          "[textile][flat]") {
  // a: a prism over the house (0,0) (2,0) (2,1) (1,1.3) (0,1) in xz, along y from 0 to 1; b: a
  // prism over its roof, from y = -0.2 to 1.2, so the two coincide on the roof; c crosses the
  // roof where a diagonal of a and one of b cross it about 1e-16 apart. No step moves them apart, and
  // written as they are a volume mesher takes them for one point.
  const std::vector<std::array<std::size_t, 3>> prism_faces{
      {0, 1, 2}, {5, 7, 6}, {0, 2, 3}, {5, 8, 7}, {0, 3, 4}, {5, 9, 8}, {0, 6, 1}, {0, 5, 6},
      {1, 7, 2}, {1, 6, 7}, {2, 8, 3}, {2, 7, 8}, {3, 9, 4}, {3, 8, 9}, {4, 5, 0}, {4, 9, 5}};
  seam::TriangleSoup a, b;
  a.points = {{0, 0, 0}, {2, 0, 0}, {2, 0, 1}, {1, 0, 1.3}, {0, 0, 1}, {0, 1, 0}, {2, 1, 0}, {2, 1, 1}, {1, 1, 1.3}, {0, 1, 1}};
  b.points = {{1, -0.2, 1.3}, {2, -0.2, 1}, {2, -0.2, 2}, {0, -0.2, 2}, {0, -0.2, 1},
              {1, 1.2, 1.3},  {2, 1.2, 1},  {2, 1.2, 2},  {0, 1.2, 2},  {0, 1.2, 1}};
  a.triangles = b.triangles = prism_faces;
  std::vector<M> meshes{seam::mesh_from_soup<K>(a, "a"), seam::mesh_from_soup<K>(b, "b"),
                        seam::mesh_from_soup<K>(seam_test::box_soup({0.5, 0.3, 0.8}, {1.4, 0.6, 1.5}), "c")};
  const std::string what = refusal<K>(meshes, {"a", "b", "c"});
  CHECK_THAT(what, Catch::Contains("'a', 'b' and 'c'") && Catch::Contains("closer than the vertex separation"));
}
