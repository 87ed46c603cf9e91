// seam::volume_mesh, the FE exports and `seam mesh`: the invariants of the tetrahedral model,
// checked here independently of the library's own verification (long double volumes, CGAL's
// exact orientation, faces looked up by coordinates).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/generate.h>
#include <seam/kernels.h>
#include <seam/volume_mesh.h>

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include <sys/wait.h>

#include "test_support.h"

namespace fs = std::filesystem;

namespace {

using seam::Point3d;
using seam::TriangleSoup;

/// A closed box [lo, hi] with n x n quads per face, outward oriented, each quad split along the
/// diagonal from its lowest corner: two boxes with a common face triangulate it identically.
TriangleSoup box_tow(const Point3d& lo, const Point3d& hi, int n) {
  TriangleSoup soup;
  std::map<Point3d, std::size_t> index;
  const auto id = [&](const Point3d& p) {
    const auto [it, added] = index.emplace(p, soup.points.size());
    if (added) soup.points.push_back(p);
    return it->second;
  };
  const auto at = [&](int axis, int i) { return i == n ? hi[axis] : lo[axis] + (hi[axis] - lo[axis]) * i / n; };
  for (int a = 0; a < 3; ++a)
    for (const bool top : {false, true}) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::size_t q[4];
          for (int k = 0; k < 4; ++k) {
            Point3d p;
            p[a] = top ? hi[a] : lo[a];
            p[u] = at(u, i + (k == 1 || k == 2));
            p[v] = at(v, j + (k >= 2));
            q[k] = id(p);
          }
          if (top) {
            soup.triangles.push_back({q[0], q[1], q[2]});
            soup.triangles.push_back({q[0], q[2], q[3]});
          } else {
            soup.triangles.push_back({q[0], q[2], q[1]});
            soup.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return soup;
}

long double det(const Point3d& p, const Point3d& q, const Point3d& r, const Point3d& s) {
  long double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = (long double)q[k] - p[k];
    v[k] = (long double)r[k] - p[k];
    w[k] = (long double)s[k] - p[k];
  }
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

long double enclosed_volume(const TriangleSoup& s) {
  long double sum = 0;
  for (const auto& t : s.triangles) sum += det(s.points[0], s.points[t[0]], s.points[t[1]], s.points[t[2]]);
  return std::abs(sum) / 6;
}

std::array<std::size_t, 3> sorted(std::size_t a, std::size_t b, std::size_t c) {
  std::array<std::size_t, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

/// The invariants, checked independently: no inverted tet, region volumes equal to the enclosed
/// volumes (matrix: box minus tows) within 1e-9, every tow triangle a face of the mesh with a tet
/// of its tow behind it, every face shared by two tows a face of tets of both.
void check_model(const seam::VolumeMeshResult& r, const std::vector<TriangleSoup>& tows, const seam::AxisBox& box) {
  const auto& m = r.mesh;
  REQUIRE(m.region.size() == m.tets.size());
  REQUIRE(m.region_names.size() == tows.size() + 1);
  std::vector<long double> volume(tows.size() + 1, 0);
  std::size_t inverted = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& c = m.tets[t];
    const auto P = [&](int k) { return seam::Filtered::Point_3(m.points[c[k]][0], m.points[c[k]][1], m.points[c[k]][2]); };
    if (CGAL::orientation(P(0), P(1), P(2), P(3)) != CGAL::POSITIVE) ++inverted;
    volume.at(static_cast<std::size_t>(m.region[t])) += det(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]) / 6;
  }
  CHECK(inverted == 0);
  long double matrix = 1;
  for (int k = 0; k < 3; ++k) matrix *= (long double)box.max[k] - box.min[k];
  for (std::size_t i = 0; i < tows.size(); ++i) {
    const long double v = enclosed_volume(tows[i]);
    matrix -= v;
    INFO("tow " << i);
    CHECK(std::abs(volume[i + 1] - v) <= 1e-9 * v);
    CHECK(r.stats.regions.at(i + 1).relative_error <= 1e-9);
  }
  CHECK(std::abs(volume[0] - matrix) <= 1e-9 * matrix);
  // Faces by coordinates.
  std::map<Point3d, std::size_t> index;
  for (std::size_t i = 0; i < m.points.size(); ++i) index.emplace(m.points[i], i);
  std::map<std::array<std::size_t, 3>, std::multiset<int>> face_regions;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& c = m.tets[t];
      face_regions[sorted(c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4])].insert(m.region[t]);
    }
  std::map<std::array<std::size_t, 3>, std::set<int>> owners;
  std::size_t missing = 0, wrong = 0;
  for (std::size_t i = 0; i < tows.size(); ++i)
    for (const auto& t : tows[i].triangles) {
      std::size_t v[3];
      for (int k = 0; k < 3; ++k) {
        const auto it = index.find(tows[i].points[t[k]]);
        REQUIRE(it != index.end());
        v[k] = it->second;
      }
      const auto key = sorted(v[0], v[1], v[2]);
      owners[key].insert(static_cast<int>(i + 1));
      const auto it = face_regions.find(key);
      if (it == face_regions.end()) ++missing;
      else if (it->second.count(static_cast<int>(i + 1)) != 1) ++wrong;
    }
  CHECK(missing == 0);
  CHECK(wrong == 0);
  for (const auto& [key, who] : owners)
    if (who.size() == 2) CHECK(face_regions.at(key) == std::multiset<int>(who.begin(), who.end()));
}

seam::AxisBox make_box(const Point3d& lo, const Point3d& hi) {
  seam::AxisBox b;
  b.min = lo;
  b.max = hi;
  return b;
}

}  // namespace

TEST_CASE("volume_mesh: two disjoint tows and the matrix fill the box exactly") {
  seam::TowOptions a;
  a.segments_along = 16;
  a.segments_around = 12;
  seam::TowOptions b = a;
  b.translate = {0, 3, 0};
  const std::vector<TriangleSoup> tows{seam::make_tow(a), seam::make_tow(b)};
  seam::VolumeMeshOptions o;
  o.margin = 0.5;
  const auto r = seam::volume_mesh(tows, {"a", "b"}, o);
  check_model(r, tows, r.stats.box);
  CHECK(r.stats.steiner_points > 0);  // the quality bound refined the inside
  CHECK(r.contacts.empty());
  CHECK(r.stats.box.min[1] == Approx(-1.5));
  CHECK(r.stats.min_dihedral_deg > 0);
  CHECK(r.mesh.region_names == std::vector<std::string>{"matrix", "a", "b"});
}

TEST_CASE("volume_mesh: two boxes sharing a face, the contact faces are faces of tets of both") {
  const int n = 3;
  const std::vector<TriangleSoup> tows{box_tow({0, 0, 0}, {1, 1, 1}, n), box_tow({1, 0, 0}, {2, 1, 1}, n)};
  seam::VolumeMeshOptions o;
  o.box = make_box({-1, -1, -1}, {3, 2, 2});
  const auto r = seam::volume_mesh(tows, {"left", "right"}, o);
  check_model(r, tows, *o.box);
  REQUIRE(r.contacts.size() == 1);
  CHECK(r.contacts[0].a == 1);
  CHECK(r.contacts[0].b == 2);
  CHECK(r.contacts[0].faces.size() == std::size_t(2 * n * n));
  CHECK(r.stats.shared_triangles == std::size_t(2 * n * n));
  for (std::size_t i = 0; i < r.contacts[0].faces.size(); ++i) CHECK(r.mesh.region[r.contacts[0].tet_a[i]] == 1);
  CHECK(r.stats.regions.at(1).volume == 1.0);
  CHECK(r.stats.regions.at(0).volume == 4.0 * 3 * 3 - 2);
}

TEST_CASE("volume_mesh: a tow lying against the faces of the box becomes part of the box's boundary") {
  // The tow fills [0,1]^3; the box [0,2]x[0,1]x[0,1]: five of its faces lie in the box's faces.
  const std::vector<TriangleSoup> tows{box_tow({0, 0, 0}, {1, 1, 1}, 2)};
  seam::VolumeMeshOptions o;
  o.box = make_box({0, 0, 0}, {2, 1, 1});
  o.box_face_spacing = 0.25;
  const auto r = seam::volume_mesh(tows, {"tow"}, o);
  check_model(r, tows, *o.box);
  CHECK(r.stats.regions.at(0).volume == 1.0);
  CHECK(r.stats.regions.at(1).volume == 1.0);
  // The default box is the tows' bounding box: here the tow fills it, and the matrix is empty.
  const auto no_matrix = seam::volume_mesh(tows, {"tow"}, {});
  check_model(no_matrix, tows, no_matrix.stats.box);
  CHECK(no_matrix.stats.regions.at(0).tets == 0);
}

TEST_CASE("volume_mesh: the radius-edge bound and the volume bound refine the mesh") {
  const std::vector<TriangleSoup> tows{box_tow({0, 0, 0}, {1, 1, 1}, 2)};
  seam::VolumeMeshOptions o;
  o.box = make_box({-1, -1, -1}, {2, 2, 2});
  o.radius_edge = 0;
  const auto largest = [](const seam::VolumeMeshResult& r) {
    long double v = 0;
    for (const auto& c : r.mesh.tets) {
      const auto& P = r.mesh.points;
      v = std::max(v, det(P[c[0]], P[c[1]], P[c[2]], P[c[3]]) / 6);
    }
    return v;
  };
  const auto coarse = seam::volume_mesh(tows, {"tow"}, o);
  o.radius_edge = 1.5;
  o.max_volume = 0.01;
  const auto fine = seam::volume_mesh(tows, {"tow"}, o);
  check_model(fine, tows, *o.box);
  CHECK(fine.stats.tets > coarse.stats.tets);
  // Under -Y a tet on an input face keeps that face: the bound holds only where TetGen may add
  // points. With Steiner points on the surfaces allowed, it nearly holds everywhere (TetGen 1.5
  // leaves a few tets slightly above it: 0.0104 here).
  CHECK(largest(fine) < largest(coarse));
  o.steiner_on_surfaces = true;
  const auto split = seam::volume_mesh(tows, {"tow"}, o);
  CHECK(largest(split) < 0.02);
  CHECK(largest(split) < largest(fine));
  CHECK(split.stats.regions.at(1).relative_error == 0);
  CHECK(split.stats.regions.at(0).relative_error == 0);
}

namespace {

/// An oblique prism: the triangle (0, 0, 0), (0, 0.5, 0), (0, 0.2, 0.4) swept along (1, 0.2, 0.1)
/// from x = x0 to x = x1 in `segments` steps, closed by its end triangles, outward oriented. Its
/// cross-section in every plane x = c is a translate of that triangle (area 0.1).
TriangleSoup oblique_prism(double x0, double x1, int segments) {
  TriangleSoup s;
  const Point3d base[3] = {{0, 0, 0}, {0, 0.5, 0}, {0, 0.2, 0.4}};
  for (int i = 0; i <= segments; ++i) {
    const double x = i == segments ? x1 : x0 + (x1 - x0) * i / segments;
    for (const auto& b : base) s.points.push_back({x, b[1] + 0.2 * x, b[2] + 0.1 * x});
  }
  for (int i = 0; i < segments; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t a = 3 * i + k, b = 3 * i + (k + 1) % 3, c = a + 3, d = b + 3;
      s.triangles.push_back({a, c, d});
      s.triangles.push_back({a, d, b});
    }
  const std::size_t last = 3 * std::size_t(segments);
  s.triangles.push_back({0, 1, 2});
  s.triangles.push_back({last, last + 2, last + 1});
  long double signed_sum = 0;
  for (const auto& t : s.triangles) signed_sum += det(s.points[0], s.points[t[0]], s.points[t[1]], s.points[t[2]]);
  if (signed_sum < 0)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

/// A prism along x over the polygon `section` (points (y, z), counterclockwise, every corner
/// visible from the first), from x0 to x1 in `segments` steps, outward oriented.
TriangleSoup extruded(const std::vector<std::array<double, 2>>& section, double x0, double x1, int segments) {
  TriangleSoup s;
  const std::size_t n = section.size();
  for (int i = 0; i <= segments; ++i) {
    const double x = i == segments ? x1 : x0 + (x1 - x0) * i / segments;
    for (const auto& q : section) s.points.push_back({x, q[0], q[1]});
  }
  for (std::size_t i = 0; i < std::size_t(segments); ++i)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t a = n * i + k, b = n * i + (k + 1) % n, c = a + n, d = b + n;
      s.triangles.push_back({a, c, d});
      s.triangles.push_back({a, d, b});
    }
  const std::size_t last = n * std::size_t(segments);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    s.triangles.push_back({0, k, k + 1});
    s.triangles.push_back({last, last + k + 1, last + k});
  }
  long double signed_sum = 0;
  for (const auto& t : s.triangles) signed_sum += det(s.points[0], s.points[t[0]], s.points[t[1]], s.points[t[2]]);
  if (signed_sum < 0)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

/// Independent checks of a model of tows cut by its box: no inverted tet, the regions tile the
/// box exactly (long double sums), every tet face on the box's boundary lies in a box face.
std::vector<long double> check_cut_model(const seam::VolumeMeshResult& r, const seam::AxisBox& box) {
  const auto& m = r.mesh;
  std::vector<long double> volume(m.region_names.size(), 0);
  std::size_t inverted = 0;
  std::map<std::array<std::size_t, 3>, int> uses;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& c = m.tets[t];
    const auto P = [&](int k) { return seam::Filtered::Point_3(m.points[c[k]][0], m.points[c[k]][1], m.points[c[k]][2]); };
    if (CGAL::orientation(P(0), P(1), P(2), P(3)) != CGAL::POSITIVE) ++inverted;
    volume.at(static_cast<std::size_t>(m.region[t])) += det(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]) / 6;
    for (int k = 0; k < 4; ++k) ++uses[sorted(c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4])];
  }
  CHECK(inverted == 0);
  std::size_t off_box = 0;
  for (const auto& [f, n] : uses) {
    if (n != 1) continue;
    bool in_a_face = false;
    for (int a = 0; a < 3; ++a)
      for (const double c : {box.min[a], box.max[a]})
        in_a_face = in_a_face || (m.points[f[0]][a] == c && m.points[f[1]][a] == c && m.points[f[2]][a] == c);
    off_box += in_a_face ? 0 : 1;
  }
  CHECK(off_box == 0);
  long double total = 0, box_volume = 1;
  for (const long double v : volume) total += v;
  for (int k = 0; k < 3; ++k) box_volume *= (long double)box.max[k] - box.min[k];
  CHECK(std::abs(total - box_volume) <= 1e-12 * box_volume);
  for (const auto& rs : r.stats.regions) CHECK(rs.relative_error <= 1e-9);
  return volume;
}

}  // namespace

TEST_CASE("volume_mesh: tows crossing the box are cut by it and closed by its faces (a periodic cell)") {
  seam::VolumeMeshOptions o;
  o.box_face_spacing = 0.25;
  SECTION("a cube cut through its vertices and through its faces") {
    for (const int n : {2, 3}) {
      INFO("n = " << n);
      const auto cube = box_tow({0, 0, 0}, {1, 1, 1}, n);
      o.box = make_box({-1, -1, -1}, {0.5, 2, 2});
      const auto r = seam::volume_mesh({cube}, {"cube.off"}, o);
      CHECK(r.stats.clipped_tows == 1);
      const auto v = check_cut_model(r, *o.box);
      CHECK(std::abs(v[1] - 0.5L) <= 1e-15L);
      CHECK(r.stats.regions.at(1).volume == 0.5);
    }
  }
  SECTION("an oblique prism through two opposite faces, next to a tow inside the box") {
    // Cut at x = 0 and x = 1 between its rings of vertices: the tow in the box holds the
    // cross-section (area 0.1) times the length 1, up to the rounding of the cut points.
    const auto prism = oblique_prism(-0.55, 1.63, 7);
    const auto cube = box_tow({0.25, 0.5, 0.6}, {0.75, 0.9, 1.0}, 1);  // inside the box, apart
    o.box = make_box({0, -0.5, -0.5}, {1, 1.5, 1.5});
    const auto r = seam::volume_mesh({prism, cube}, {"prism", "cube"}, o);
    CHECK(r.stats.clipped_tows == 1);
    const auto v = check_cut_model(r, *o.box);
    CHECK(std::abs(v[1] - 0.1L) <= 1e-13L);
    CHECK(std::abs(v[2] - 0.5L * 0.4L * 0.4L) <= 1e-15L);
  }
  SECTION("faces in a box plane: kept where the tow is inside, dropped where it is outside") {
    const auto cube = box_tow({0, 0, 0}, {1, 1, 1}, 2);
    o.box = make_box({-1, -1, 0}, {0.5, 2, 2});  // the bottom face lies in z = 0, the cube above it
    const auto r = seam::volume_mesh({cube}, {"cube.off"}, o);
    CHECK(std::abs(check_cut_model(r, *o.box)[1] - 0.5L) <= 1e-15L);
    o.box = make_box({-1, -1, 1}, {0.5, 2, 2});  // only the top face, in z = 1, with the cube below
    CHECK_THROWS_WITH(seam::volume_mesh({cube}, {"cube.off"}, o), Catch::StartsWith("cube.off: the tow lies outside"));
    o.box = make_box({2, 2, 2}, {3, 3, 3});
    CHECK_THROWS_WITH(seam::volume_mesh({cube}, {"cube.off"}, o), Catch::StartsWith("cube.off: the tow lies outside"));
  }
  SECTION("vertices a hair's breadth from a box plane move onto it: no sliver") {
    const auto cube = box_tow({0, 0, 0}, {1, 1, 1}, 3);  // vertices at x = 1/3 (rounded)
    const double c = 1.0 / 3 + 1e-9;
    o.box = make_box({-1, -1, -1}, {c, 2, 2});
    o.cut_snap = 0;
    const auto sliver = seam::volume_mesh({cube}, {"cube.off"}, o);
    CHECK(sliver.stats.cut_snapped_vertices == 0);
    o.cut_snap = 0.1;
    const auto snapped = seam::volume_mesh({cube}, {"cube.off"}, o);
    CHECK(snapped.stats.cut_snapped_vertices == 12);  // the ring of vertices at x = 1/3
    CHECK(snapped.stats.cut_snap_max_move == Approx(1e-9).epsilon(1e-6));
    for (const auto* r : {&sliver, &snapped}) {
      const auto v = check_cut_model(*r, *o.box);
      CHECK(std::abs(v[1] - (long double)c) <= 1e-15L);
    }
    CHECK(sliver.stats.min_dihedral_deg < 1e-3);
    CHECK(snapped.stats.min_dihedral_deg > 5);
  }
  SECTION("a ridge just beyond a box plane stays there: moved onto it, it would pinch the tow") {
    // The tow's underside is a roof whose ridge (z = 0.05) lies 0.01 above the box's top face
    // z = 0.04, within the snapping distance; inside the box are two wedges beside it.
    const auto roof = extruded({{0, 0.05}, {1, -0.5}, {1, 1}, {-1, 1}, {-1, -0.5}}, 0, 1, 4);
    o.box = make_box({0.3, -2, -1}, {0.7, 2, 0.04});
    const auto r = seam::volume_mesh({roof}, {"roof"}, o);
    const auto v = check_cut_model(r, *o.box);
    // Each wedge: the integral of 0.04 - (0.05 - 0.55 |y|) for |y| from 1/55 to 1 (0.265 +
    // 1/11000), times the length 0.4.
    CHECK(std::abs(v[1] - 0.8L * (0.265L + 1.0L / 11000)) <= 1e-14L);
  }
}

TEST_CASE("volume_mesh: refused inputs name the tow") {
  const auto cube = box_tow({0, 0, 0}, {1, 1, 1}, 2);
  seam::VolumeMeshOptions o;
  o.margin = 1;
  const auto shifted = box_tow({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}, 2);
  // Crossing along common edges only (conforming, as after seam pair, but overlapping).
  CHECK_THROWS_WITH(seam::volume_mesh({cube, shifted}, {"a.off", "b.off"}, o), Catch::Contains("the tows overlap"));
  // One inside the other, not touching.
  const auto inner = box_tow({0.25, 0.25, 0.25}, {0.75, 0.75, 0.75}, 1);
  CHECK_THROWS_WITH(seam::volume_mesh({cube, inner}, {"a.off", "b.off"}, o), Catch::Contains("the tows overlap"));
  // Touching off the common vertices: a box against a finer one.
  const auto finer = box_tow({1, 0, 0}, {2, 1, 1}, 3);
  CHECK_THROWS_WITH(seam::volume_mesh({cube, finer}, {"a.off", "b.off"}, o), Catch::Contains("the tows overlap"));
  TriangleSoup open = cube;
  open.triangles.pop_back();
  CHECK_THROWS_WITH(seam::volume_mesh({open}, {"open.off"}, o), Catch::StartsWith("open.off: not closed"));
  o.radius_edge = 1.0;
  CHECK_THROWS_AS(seam::volume_mesh({cube}, {"cube.off"}, o), seam::InvalidInput);
}

TEST_CASE("write_volume_mesh: VTU, Abaqus and Gmsh files hold every tet and region") {
  const std::vector<TriangleSoup> tows{box_tow({0, 0, 0}, {1, 1, 1}, 2), box_tow({1, 0, 0}, {2, 1, 1}, 2)};
  seam::VolumeMeshOptions o;
  o.box = make_box({-1, -1, -1}, {3, 2, 2});
  const auto r = seam::volume_mesh(tows, {"left tow", "2right"}, o);
  const auto text = [&](const std::string& format) {
    std::ostringstream s;
    seam::write_volume_mesh(r.mesh, r.contacts, s, format);
    return s.str();
  };
  const std::string vtu = text("vtu"), inp = text(".INP"), msh = text("msh");
  CHECK_THAT(vtu, Catch::Contains("NumberOfCells=\"" + std::to_string(r.mesh.tets.size()) + "\""));
  CHECK_THAT(vtu, Catch::Contains("Name=\"region\""));
  CHECK_THAT(inp, Catch::Contains("*ELEMENT, TYPE=C3D4, ELSET=matrix"));
  CHECK_THAT(inp, Catch::Contains("ELSET=left_tow\n"));
  CHECK_THAT(inp, Catch::Contains("ELSET=R_2right\n"));
  CHECK_THAT(inp, Catch::Contains("*SURFACE, TYPE=ELEMENT, NAME=CONTACT_left_tow_R_2right"));
  CHECK_THAT(msh, Catch::StartsWith("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n"));
  CHECK_THAT(msh, Catch::Contains("3 2 \"left_tow\""));
  CHECK_THROWS_AS(text("vtk"), seam::InvalidInput);
  CHECK(seam::volume_mesh_format("a/model.MSH") == ".msh");
  CHECK_THROWS_WITH(seam::volume_mesh_format("model.stl"), Catch::StartsWith("model.stl: unknown volume mesh format"));
}

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs `seam ARGS` and returns the exit code; stderr into `err`.
int run_seam(const seam_test::TempDir& dir, const std::vector<std::string>& args, std::string& err) {
  std::string cmd = quote(SEAM_CLI_PATH);
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " </dev/null >" + quote(dir.file("stdout")) + " 2>" + quote(dir.file("stderr"));
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  err = seam_test::read_bytes(dir.file("stderr"));
  return WEXITSTATUS(status);
}

void write_off(const TriangleSoup& s, const std::string& path) {
  std::ostringstream out;
  seam::write_triangle_mesh(s, out, "off");
  seam_test::write_bytes(path, out.str());
}

}  // namespace

TEST_CASE("seam mesh: writes verified models, refuses bad input with exit 2 and writes nothing") {
  seam_test::TempDir dir("seam_test_mesh");
  fs::create_directories(dir.path / "out");
  const std::string left = dir.file("left.off"), right = dir.file("right.off");
  write_off(box_tow({0, 0, 0}, {1, 1, 1}, 2), left);
  write_off(box_tow({1, 0, 0}, {2, 1, 1}, 2), right);
  const std::string out = (dir.path / "out").string();
  std::string err;
  REQUIRE(run_seam(dir, {"mesh", left, right, "-o", out + "/m.vtu", "-o", out + "/m.inp", "-o", out + "/m.msh",
                         "--margin", "0.5", "--report", out + "/r.json"}, err) == 0);
  CHECK(seam_test::entries(dir.path / "out") == std::vector<std::string>{"m.inp", "m.msh", "m.vtu", "r.json"});
  const auto report = nlohmann::json::parse(seam_test::read_bytes(out + "/r.json"));
  CHECK(report["verified"] == true);
  CHECK(report["regions"].size() == 3);
  CHECK(report["regions"][1]["name"] == "left");
  CHECK(report["regions"][1]["volume"] == 1.0);
  fs::remove_all(dir.path / "out");
  fs::create_directories(dir.path / "out");

  const auto refused = [&](const std::vector<std::string>& args, const std::string& names) {
    std::string e;
    INFO(names);
    CHECK(run_seam(dir, args, e) == 2);
    CHECK(std::count(e.begin(), e.end(), '\n') == 1);
    CHECK_THAT(e, Catch::StartsWith("seam: ") && Catch::Contains(names));
    CHECK(seam_test::entries(dir.path / "out").empty());
  };
  refused({"mesh", left, right, "-o", out + "/m.vtu", "--box", "-1", "-1", "-1", "0.9", "2", "2"}, right + ": the tow lies outside");
  refused({"mesh", left, right, "-o", out + "/m.vtu", "--cut-snap", "0.6"}, "--cut-snap");
  refused({"mesh", left, right, "-o", out + "/m.stl"}, "m.stl");
  refused({"mesh", left, right, "-o", out + "/m.vtu", "--radius-edge", "0.5"}, "--radius-edge");
  refused({"mesh", left, right, "-o", out + "/m.vtu", "--box", "0", "0", "0", "-1", "1", "1"}, "--box");
  refused({"mesh", left, right, "-o", out + "/m.vtu", "-o", out + "/m.vtu"}, "the same path is given for two outputs");
  refused({"mesh", left, left, "-o", out + "/m.vtu", "--margin", "1"}, "the tows overlap");
  // A unit cell that cuts both boxes in half: written, verified, both cut.
  REQUIRE(run_seam(dir, {"mesh", left, right, "-o", out + "/cell.vtu", "--box", "0.5", "0", "0", "1.5", "1", "1",
                         "--report", out + "/cell.json"}, err) == 0);
  const auto cell = nlohmann::json::parse(seam_test::read_bytes(out + "/cell.json"));
  CHECK(cell["input"]["clipped_tows"] == 2);
  CHECK(cell["regions"][1]["volume"] == 0.5);
  CHECK(cell["regions"][2]["volume"] == 0.5);
  CHECK(cell["regions"][0]["tets"] == 0);  // the two halves fill the cell
}
