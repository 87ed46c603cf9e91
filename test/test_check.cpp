// Tests of seam::check_pair and `seam check`. The reference producer of a conforming pair is
// CGAL's corefinement (in this test only): two interpenetrating cubes are corefined, and the
// curves are their intersection computed by CGAL::Polygon_mesh_processing::surface_intersection.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/generate.h>
#include <seam/io.h>

#include <catch2/catch.hpp>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <random>
#include <type_traits>
#include <set>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "test_support.h"
#include "tow_fixtures.h"

#ifndef SEAM_CLI_PATH
#error "SEAM_CLI_PATH (path of the seam binary) must be defined by the build"
#endif

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Catch::Contains;
using E = seam::Exact;

/// An axis-aligned cube [o, o + s]^3 as a closed, outward-oriented triangle soup.
seam::TriangleSoup cube_soup(double ox, double oy, double oz, double s = 1.0) {
  return seam_test::box_soup({ox, oy, oz}, {ox + s, oy + s, oz + s});
}

template <class K> seam::Mesh<K> cube(double ox, double oy, double oz, double s = 1.0) {
  return seam::mesh_from_soup<K>(cube_soup(ox, oy, oz, s), "cube");
}

/// A conforming pair made by corefinement, with its curves (exact kernel).
struct Corefined {
  seam::Mesh<E> a, b, a2, b2;
  std::vector<seam::Polyline<E>> curves;
};

Corefined corefined_cubes() {
  Corefined c;
  c.a = cube<E>(0, 0, 0);
  c.b = cube<E>(0.5, 0.5, 0.5);
  c.a2 = c.a;
  c.b2 = c.b;
  PMP::surface_intersection(c.a, c.b, std::back_inserter(c.curves));
  PMP::corefine(c.a2, c.b2);
  return c;
}

/// The same meshes and curves in kernel K (coordinates rounded to double: exact here, every
/// coordinate of the corefined cubes is a multiple of 1/4).
template <class K> seam::Mesh<K> convert(const seam::Mesh<E>& m) {
  return seam::mesh_from_soup<K>(seam::soup_from_mesh<E>(m), "converted");
}

std::string all(const seam::PairCheckReport& r) {
  std::string s;
  for (const auto& p : r.problems) s += p + "\n";
  return s;
}

bool any_contains(const seam::PairCheckReport& r, const std::string& what) {
  return all(r).find(what) != std::string::npos;
}

E::Triangle_3 triangle_of(const seam::Mesh<E>& m, seam::Mesh<E>::Face_index f) {
  const auto h = m.halfedge(f);
  return {m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
}

seam::Mesh<E>::Vertex_index vertex_at(const seam::Mesh<E>& m, const E::Point_3& p) {
  for (auto v : m.vertices())
    if (m.point(v) == p) return v;
  return seam::Mesh<E>::null_vertex();
}

}  // namespace

TEST_CASE("check_pair accepts a corefined pair of cubes", "[check]") {
  const Corefined c = corefined_cubes();
  REQUIRE(!c.curves.empty());
  const seam::PairCheckReport r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(r));
  CHECK(r.ok());
  CHECK(r.curves == c.curves.size());
  CHECK(r.curve_vertices > 3);
  CHECK(r.curve_segments >= r.curve_vertices);
  CHECK(r.intersecting_face_pairs_off_curve == 0);
  CHECK(r.face_pairs_on_curve > 0);
  CHECK(r.max_distance_a == 0);
  CHECK(r.max_distance_b == 0);
  CHECK(r.min_angle_deg_a > 0);
  CHECK(r.min_angle_deg_a <= 45);
  CHECK(r.new_faces_a > 0);
  CHECK(r.new_faces_a < r.faces_a2);  // some cube faces are not touched (e.g. x = 0)
  CHECK(r.below_20_a >= r.below_10_a);
  CHECK(r.faces_a2 == c.a2.number_of_faces());

  SECTION("the same under the filtered and float kernels") {
    using Fi = seam::Filtered;
    using Fl = seam::Float;
    const auto rf = seam::check_pair<Fi>(convert<Fi>(c.a), convert<Fi>(c.b), convert<Fi>(c.a2), convert<Fi>(c.b2),
                                         seam::to_kernel<Fi>(seam::to_doubles<E>(c.curves)), 1e-9);
    INFO(all(rf));
    CHECK(rf.ok());
    CHECK(rf.face_pairs_on_curve == r.face_pairs_on_curve);
    const auto rl = seam::check_pair<Fl>(convert<Fl>(c.a), convert<Fl>(c.b), convert<Fl>(c.a2), convert<Fl>(c.b2),
                                         seam::to_kernel<Fl>(seam::to_doubles<E>(c.curves)), 1e-9);
    INFO(all(rl));
    CHECK(rl.ok());
  }
}

TEST_CASE("check_pair rejects the non-conforming inputs as outputs", "[check]") {
  const Corefined c = corefined_cubes();
  const auto r = seam::check_pair<E>(c.a, c.b, c.a, c.b, c.curves, 1e-9);
  INFO(all(r));
  CHECK_FALSE(r.ok());
  CHECK(r.intersecting_face_pairs_off_curve > 0);
  CHECK(any_contains(r, "A2 and B2 intersect off the curves"));
  CHECK(any_contains(r, "curve points are not vertices"));
}

TEST_CASE("check_pair: a curve vertex moved by 1e-12 in B2 is missing", "[check]") {
  Corefined c = corefined_cubes();
  const auto p = c.curves[0][1];
  const auto v = vertex_at(c.b2, p);
  REQUIRE(v != seam::Mesh<E>::null_vertex());
  c.b2.point(v) = E::Point_3(p.x() + 1e-12, p.y(), p.z());
  const auto r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(r));
  CHECK_FALSE(r.ok());
  CHECK(any_contains(r, "B2: 1 curve points are not vertices with identical coordinates"));
  CHECK_FALSE(any_contains(r, "A2: 1 curve points"));
}

TEST_CASE("check_pair: an output vertex moved by 0.1 is beyond the tolerance", "[check]") {
  Corefined c = corefined_cubes();
  const auto v = vertex_at(c.a2, E::Point_3(0, 0, 0));
  REQUIRE(v != seam::Mesh<E>::null_vertex());
  c.a2.point(v) = E::Point_3(-0.1, 0, 0);
  const auto r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(r));
  CHECK_FALSE(r.ok());
  CHECK(r.problems.size() == 1);
  CHECK(any_contains(r, "A2: 1 vertices are farther than the tolerance"));
  CHECK(r.max_distance_a == Approx(0.1));
  CHECK(r.max_distance_b == 0);
  // With a tolerance that allows the move, it passes.
  CHECK(seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 0.11).ok());
}

TEST_CASE("check_pair: tolerance 0 holds exactly under the exact kernel", "[check]") {
  const Corefined c = corefined_cubes();
  const auto r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 0.0);
  INFO(all(r));
  CHECK(r.ok());
}

TEST_CASE("check_pair: curve segments must be edges of both outputs", "[check]") {
  Corefined c = corefined_cubes();
  // Two curve points not joined by an edge in either output.
  std::vector<E::Point_3> pts;
  for (const auto& pl : c.curves) pts.insert(pts.end(), pl.begin(), pl.end());
  bool found = false;
  for (std::size_t i = 0; i < pts.size() && !found; ++i)
    for (std::size_t j = i + 1; j < pts.size() && !found; ++j) {
      const auto ua = vertex_at(c.a2, pts[i]), wa = vertex_at(c.a2, pts[j]);
      const auto ub = vertex_at(c.b2, pts[i]), wb = vertex_at(c.b2, pts[j]);
      if (ua != wa && ub != wb && c.a2.halfedge(ua, wa) == seam::Mesh<E>::null_halfedge() &&
          c.b2.halfedge(ub, wb) == seam::Mesh<E>::null_halfedge()) {
        c.curves.push_back({pts[i], pts[j]});
        found = true;
      }
    }
  REQUIRE(found);
  const auto r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(r));
  CHECK_FALSE(r.ok());
  CHECK(any_contains(r, "A2: 1 curve segments are not edges"));
  CHECK(any_contains(r, "B2: 1 curve segments are not edges"));
}

TEST_CASE("check_pair: an output with a hole is not closed", "[check]") {
  Corefined c = corefined_cubes();
  const auto f = *c.a2.faces().begin();
  CGAL::Euler::remove_face(c.a2.halfedge(f), c.a2);
  c.a2.collect_garbage();
  const auto r = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(r));
  CHECK(any_contains(r, "A2 is not closed"));
}

TEST_CASE("check_pair without curves", "[check]") {
  const std::vector<seam::Polyline<E>> none;
  SECTION("disjoint cubes pass") {
    const auto a = cube<E>(0, 0, 0), b = cube<E>(3, 0, 0);
    const auto r = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    INFO(all(r));
    CHECK(r.ok());
    CHECK(r.curves == 0);
    CHECK(r.candidate_face_pairs == 0);
    CHECK(r.new_faces_a == 0);
    CHECK(r.below_20_a == 0);
    CHECK(r.min_angle_deg_a == Approx(45));
  }
  SECTION("nested cubes pass (the surfaces do not meet)") {
    const auto a = cube<E>(0, 0, 0, 4), b = cube<E>(1, 1, 1);
    const auto r = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    INFO(all(r));
    CHECK(r.ok());
  }
  SECTION("cubes touching at a corner fail") {
    const auto a = cube<E>(0, 0, 0), b = cube<E>(1, 1, 1);
    const auto r = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    INFO(all(r));
    CHECK_FALSE(r.ok());
    CHECK(any_contains(r, "touch at a vertex that is not a curve point"));
  }
  SECTION("cubes sharing a face fail") {
    const auto a = cube<E>(0, 0, 0), b = cube<E>(1, 0, 0);
    const auto r = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    INFO(all(r));
    CHECK_FALSE(r.ok());
    CHECK(r.intersecting_face_pairs_off_curve > 0);
  }
  SECTION("interpenetrating cubes fail") {
    const auto a = cube<E>(0, 0, 0), b = cube<E>(0.5, 0.5, 0.5);
    const auto r = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    CHECK(any_contains(r, "A2 and B2 intersect off the curves"));
  }
  SECTION("an output vertex closer than the separation to another fails, and both points are named") {
    // B 2e-9 beyond A in x (input corners that close are counted apart); A2's corner (1, 0, 0)
    // moved 1e-9 along A's edge, so it is no longer an input point: 3e-9 from B's corner.
    const auto a = cube<E>(0, 0, 0), b = cube<E>(1 + 2e-9, 0, 0);
    auto a2 = a;
    a2.point(seam::Mesh<E>::Vertex_index(1)) = E::Point_3(1 - 1e-9, 0, 0);
    const auto r = seam::check_pair<E>(a, b, a2, b, none, 1e-9);
    INFO(all(r));
    CHECK(any_contains(r, "closer than"));
    CHECK(r.close_vertex_pairs == 1);
    CHECK(r.close_vertex_pairs_in_inputs == 3);  // the other corners of the two facing squares
    REQUIRE(r.close_vertex_points.size() == 2);
    const std::array<double, 3> moved{1 - 1e-9, 0, 0}, corner{1 + 2e-9, 0, 0};
    CHECK(std::count(r.close_vertex_points.begin(), r.close_vertex_points.end(), moved) == 1);
    CHECK(std::count(r.close_vertex_points.begin(), r.close_vertex_points.end(), corner) == 1);
    const auto ok = seam::check_pair<E>(a, b, a, b, none, 1e-9);
    CHECK(ok.close_vertex_points.empty());
  }
}

TEST_CASE("check_pair: a self-intersecting output fails", "[check]") {
  seam::TriangleSoup two = cube_soup(0, 0, 0), second = cube_soup(0.5, 0.25, 0.25);
  for (auto t : second.triangles) two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  two.points.insert(two.points.end(), second.points.begin(), second.points.end());
  const auto a = seam::mesh_from_soup<E>(two, "two"), b = cube<E>(5, 5, 5);
  const auto r = seam::check_pair<E>(a, b, a, b, {}, 1e-9);
  INFO(all(r));
  CHECK(any_contains(r, "A2 self-intersects"));
}

namespace {

/// How a pair of triangles should be classified, from CGAL::intersection under the exact kernel:
/// 0 apart, 1 meeting exactly in their common points (a common vertex or edge), 2 anything else,
/// 3 the same triangle (a shared face: allowed).
int reference_meet(const std::array<E::Point_3, 3>& t, const std::array<E::Point_3, 3>& u) {
  const E::Triangle_3 tt(t[0], t[1], t[2]), tu(u[0], u[1], u[2]);
  const auto result = CGAL::intersection(tt, tu);
  if (!result) return 0;
  std::vector<E::Point_3> common;
  for (const auto& p : t)
    for (const auto& q : u)
      if (p == q) common.push_back(p);
  if (common.size() == 3) return 3;
  if (const auto* p = boost::get<E::Point_3>(&*result)) return common.size() == 1 && *p == common[0] ? 1 : 2;
  if (const auto* s = boost::get<E::Segment_3>(&*result))
    return common.size() == 2 && ((s->source() == common[0] && s->target() == common[1]) ||
                                  (s->source() == common[1] && s->target() == common[0]))
               ? 1
               : 2;
  return 2;
}

/// A mesh of one triangle.
template <class K> seam::Mesh<K> one_triangle(const std::array<E::Point_3, 3>& t) {
  seam::Mesh<K> m;
  std::array<typename seam::Mesh<K>::Vertex_index, 3> v;
  for (int i = 0; i < 3; ++i) {
    const auto& p = t[i];
    if constexpr (std::is_same_v<K, E>) v[i] = m.add_vertex(p);
    else v[i] = m.add_vertex(typename K::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())));
  }
  m.add_face(v[0], v[1], v[2]);
  return m;
}

/// Runs check_pair on the two triangles with their common points (and the edge between two) as
/// the curve, and compares with reference_meet: 0 -> no intersection found, 1 -> one pair on the
/// curve, 2 -> one pair off the curve, 3 -> a shared face.
template <class K> void compare_with_reference(const std::array<E::Point_3, 3>& t, const std::array<E::Point_3, 3>& u) {
  const int expected = reference_meet(t, u);
  std::vector<seam::Polyline<K>> curves(1);
  for (const auto& p : t)
    for (const auto& q : u)
      if (p == q) {
        if constexpr (std::is_same_v<K, E>) curves[0].push_back(p);
        else curves[0].emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
      }
  if (curves[0].empty()) curves.clear();
  const auto a = one_triangle<K>(t), b = one_triangle<K>(u);
  const auto r = seam::check_pair<K>(a, b, a, b, curves, 0.0);
  INFO("t = " << t[0] << " | " << t[1] << " | " << t[2] << "\nu = " << u[0] << " | " << u[1] << " | " << u[2]
              << "\nexpected " << expected << "\n" << all(r));
  CHECK(r.face_pairs_on_curve == (expected == 1 ? 1u : 0u));
  CHECK(r.intersecting_face_pairs_off_curve == (expected == 2 ? 1u : 0u));
  CHECK(r.shared_faces == (expected == 3 ? 1u : 0u));
  CHECK(r.ok() == (expected != 2));
}

}  // namespace

TEST_CASE("check_pair classifies triangle pairs like CGAL::intersection", "[check]") {
  // Random triangles on a coarse grid (many exact degeneracies: common vertices and edges,
  // coplanar faces, touching at a point or along an edge), some sharing corners on purpose.
  std::mt19937 random(12345);
  std::uniform_int_distribution<int> coordinate(0, 3), share(0, 5);
  auto grid_triangle = [&](int denominator) {
    std::array<E::Point_3, 3> t;
    for (auto& p : t)
      p = E::Point_3(E::FT(coordinate(random)) / denominator, E::FT(coordinate(random)) / denominator,
                     E::FT(coordinate(random)) / denominator);
    return t;
  };
  int pairs = 0, meeting = 0, beyond = 0;
  for (int n = 0; n < 3000; ++n) {
    const int denominator = n % 2 ? 1 : 3;  // thirds: not doubles, the exact kernel's intervals are wide
    auto t = grid_triangle(denominator), u = grid_triangle(denominator);
    const int s = share(random);
    if (s >= 2) u[0] = t[s % 3];
    if (s >= 4) u[2] = t[(s + 1) % 3];
    if (CGAL::collinear(t[0], t[1], t[2]) || CGAL::collinear(u[0], u[1], u[2])) continue;
    ++pairs;
    const int expected = reference_meet(t, u);
    meeting += expected == 1;
    beyond += expected == 2;
    compare_with_reference<E>(t, u);
    if (denominator == 1) {
      compare_with_reference<seam::Filtered>(t, u);
      compare_with_reference<seam::Float>(t, u);  // small integers: exact in doubles as well
    }
  }
  CHECK(pairs > 1000);
  CHECK(meeting > 100);
  CHECK(beyond > 100);
}

// ------------------------------------------------------------------ the command line

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

struct CheckRun {
  int code = -1;
  std::string out, err;
};

CheckRun run_check(const seam_test::TempDir& dir, const std::vector<std::string>& args) {
  std::string cmd = quote(SEAM_CLI_PATH) + " check";
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " </dev/null >" + quote(dir.file("stdout")) + " 2>" + quote(dir.file("stderr"));
  const int status = std::system(cmd.c_str());
  INFO("command: " << cmd);
  REQUIRE(status != -1);
  REQUIRE(WIFEXITED(status));
  CheckRun r;
  r.code = WEXITSTATUS(status);
  r.out = seam_test::read_bytes(dir.file("stdout"));
  r.err = seam_test::read_bytes(dir.file("stderr"));
  return r;
}

}  // namespace

TEST_CASE("check_pair: checks 3 and 6 on all cores give the report of one thread and find what a brute force finds",
          "[check]") {
  // Two crossing tows corefined by CGAL: many face pairs of the inputs meet (checks 3 and 6 work
  // through them in blocks of 256 on all cores).
  const auto tows = seam::make_crossover(200, 40, 150, 32, seam::Section::lenticular, 0.45);
  Corefined c;
  c.a = seam::mesh_from_soup<E>(seam::make_tow(tows.weft), "weft");
  c.b = seam::mesh_from_soup<E>(seam::make_tow(tows.warp), "warp");
  c.a2 = c.a;
  c.b2 = c.b;
  PMP::surface_intersection(c.a, c.b, std::back_inserter(c.curves));
  PMP::corefine(c.a2, c.b2);
  REQUIRE(!c.curves.empty());
  REQUIRE(c.curves[0].size() > 20);
  if (tbb::this_task_arena::max_concurrency() < 2) WARN("one core: the parallel paths run on one thread");

  // Brute force over every pair of input faces: the pairs whose boxes overlap, the pairs that
  // meet (their faces), and check 6's samples (a point: 1; a segment: 3; a triangle: 4; a polygon
  // of n corners: n + 1).
  std::size_t overlapping = 0, meeting = 0, samples = 0;
  std::set<std::size_t> meeting_a, meeting_b;
  std::vector<std::pair<CGAL::Bbox_3, seam::Mesh<E>::Face_index>> boxes_b;
  for (auto g : c.b.faces()) boxes_b.emplace_back(triangle_of(c.b, g).bbox(), g);
  for (auto f : c.a.faces()) {
    const auto s = triangle_of(c.a, f);
    const auto box_f = s.bbox();
    for (const auto& [box_g, g] : boxes_b) {
      if (!CGAL::do_overlap(box_f, box_g)) continue;
      ++overlapping;
      const auto t = triangle_of(c.b, g);
      if (!CGAL::do_intersect(s, t)) continue;
      ++meeting;
      meeting_a.insert(std::size_t(f));
      meeting_b.insert(std::size_t(g));
      const auto meet = CGAL::intersection(s, t);
      if (boost::get<E::Point_3>(&*meet)) samples += 1;
      if (boost::get<E::Segment_3>(&*meet)) samples += 3;
      if (boost::get<E::Triangle_3>(&*meet)) samples += 4;
      if (const auto* poly = boost::get<std::vector<E::Point_3>>(&*meet)) samples += poly->size() + 1;
    }
  }
  CHECK(meeting > 256);  // two blocks or more

  const auto whole = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, c.curves, 1e-9);
  INFO(all(whole));
  CHECK(whole.ok());
  CHECK(whole.intersection_samples == samples);
  CHECK(whole.uncovered_samples == 0);

  // Without the second half of the first curve: that part of the intersection is uncovered
  // (other checks fail too; the coverage check names it). The inputs as outputs: they cross off
  // any curve (check 3 names every meeting pair).
  std::vector<seam::Polyline<E>> fewer = c.curves;
  fewer[0].resize(fewer[0].size() / 2);
  const auto uncovered = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, fewer, 1e-9);
  CHECK(uncovered.intersection_samples == samples);  // the samples do not depend on the curves
  CHECK(uncovered.uncovered_samples > 0);
  CHECK(uncovered.max_uncovered_distance > 1e-3);
  CHECK(any_contains(uncovered, "missing from the curves"));
  const auto crossing = seam::check_pair<E>(c.a, c.b, c.a, c.b, {}, 1e-9);
  REQUIRE(crossing.shared_faces == 0);  // no vertex of A is one of B: every meeting is off the curves
  CHECK(crossing.candidate_face_pairs == overlapping);
  CHECK(crossing.intersecting_face_pairs_off_curve == meeting);
  CHECK(std::set<std::size_t>(crossing.conflict_faces_a.begin(), crossing.conflict_faces_a.end()) == meeting_a);
  CHECK(std::set<std::size_t>(crossing.conflict_faces_b.begin(), crossing.conflict_faces_b.end()) == meeting_b);
  CHECK(any_contains(crossing, "A2 and B2 intersect off the curves"));

  // The same reports on one thread (the pairs named, the first uncovered point, every figure).
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const auto serial_uncovered = seam::check_pair<E>(c.a, c.b, c.a2, c.b2, fewer, 1e-9);
  CHECK(serial_uncovered.problems == uncovered.problems);
  CHECK(serial_uncovered.uncovered_samples == uncovered.uncovered_samples);
  CHECK(serial_uncovered.max_uncovered_distance == uncovered.max_uncovered_distance);
  const auto serial_crossing = seam::check_pair<E>(c.a, c.b, c.a, c.b, {}, 1e-9);
  CHECK(serial_crossing.problems == crossing.problems);
  CHECK(serial_crossing.conflict_faces_a == crossing.conflict_faces_a);
  CHECK(serial_crossing.conflict_faces_b == crossing.conflict_faces_b);
}

TEST_CASE("seam check on files", "[check][cli]") {
  const Corefined c = corefined_cubes();
  seam_test::TempDir dir("seam_test_check");
  const std::string a = dir.file("a.off"), b = dir.file("b.off"), a2 = dir.file("a2.off"), b2 = dir.file("b2.off"),
                    curves = dir.file("curves.txt"), report = dir.file("report.json");
  seam::write_triangle_mesh(seam::soup_from_mesh<E>(c.a), a);
  seam::write_triangle_mesh(seam::soup_from_mesh<E>(c.b), b);
  seam::write_triangle_mesh(seam::soup_from_mesh<E>(c.a2), a2);
  seam::write_triangle_mesh(seam::soup_from_mesh<E>(c.b2), b2);
  seam::write_polylines(seam::to_doubles<E>(c.curves), curves);

  SECTION("the corefined pair passes: exit 0") {
    for (const std::string kernel : {"exact", "filtered", "float"}) {
      const auto r = run_check(dir, {a, b, a2, b2, curves, "--kernel", kernel, "--report", report});
      INFO("kernel " << kernel << "\nstdout:\n" << r.out << "stderr:\n" << r.err);
      CHECK(r.code == 0);
      CHECK(r.err.empty());
      CHECK_THAT(r.out, Contains("seam check: OK"));
      CHECK_THAT(r.out, !Contains("FAIL:"));
      const std::string json = seam_test::read_bytes(report);
      CHECK_THAT(json, Contains("\"ok\": true"));
      CHECK_THAT(json, Contains("\"intersecting_off_curves\": 0"));
    }
  }
  SECTION("the non-conforming pair fails: exit 1") {
    const auto r = run_check(dir, {a, b, a, b, curves, "--report", report});
    INFO("stdout:\n" << r.out << "stderr:\n" << r.err);
    CHECK(r.code == 1);
    CHECK_THAT(r.out, Contains("FAIL: A2 and B2 intersect off the curves"));
    CHECK_THAT(r.out, Contains("seam check: FAILED"));
    CHECK_THAT(seam_test::read_bytes(report), Contains("\"ok\": false"));
  }
  SECTION("a missing file: exit 2, named") {
    const std::string missing = dir.file("missing.off");
    const auto r = run_check(dir, {a, b, missing, b2, curves});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("missing.off"));
    CHECK(r.out.empty());
  }
  SECTION("an invalid mesh: exit 2, named") {
    seam_test::write_bytes(dir.file("bad.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    const auto r = run_check(dir, {a, b, a2, dir.file("bad.off"), curves});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("bad.off"));
  }
  SECTION("a negative tolerance: exit 2") {
    const auto r = run_check(dir, {a, b, a2, b2, curves, "--tol", "-1"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("--tol"));
  }
  SECTION("an empty curves file means no curves") {
    const std::string empty = dir.file("empty.txt"), far = dir.file("far.off");
    seam_test::write_bytes(empty, "# no curves\n\n");
    seam::write_triangle_mesh(cube_soup(3, 0, 0), far);
    CHECK(run_check(dir, {a, far, a, far, empty}).code == 0);
    CHECK(run_check(dir, {a, b, a, b, empty}).code == 1);
  }
}
