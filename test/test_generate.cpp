// Tests of the generated tow geometry (seam/generate.h).
//
// The checks here are mostly independent of the rest of the library: the mesh topology is
// checked by hand (directed edges), by building a CGAL::Surface_mesh face by face, and also with
// seam::validate_triangle_mesh / seam::mesh_from_soup (io.h); points are checked against the
// smooth surface by inverting the tube parameterisation (closest point on the path, then the
// section equation), not by calling tow_surface_point again.
//
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace {

using seam::Point3d;
using seam::Section;
using seam::TowOptions;
using seam::TriangleSoup;

constexpr double pi = 3.14159265358979323846;

Point3d sub(const Point3d& p, const Point3d& q) { return {p[0] - q[0], p[1] - q[1], p[2] - q[2]}; }
double dot(const Point3d& p, const Point3d& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }
Point3d cross(const Point3d& p, const Point3d& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}
double norm(const Point3d& p) { return std::sqrt(dot(p, p)); }

// ------------------------------------------------------------------ topology

struct TopologyReport {
  bool indices_in_range = true;
  bool no_degenerate_triangle = true;   // no repeated index, non-zero area
  bool oriented = true;                 // no directed edge used twice
  std::size_t boundary_edges = 0;       // directed edges whose reverse is missing
  bool manifold_vertices = true;        // each vertex's triangles form a single fan
  bool all_vertices_used = true;
};

TopologyReport check_topology(const TriangleSoup& soup) {
  TopologyReport r;
  const std::size_t n = soup.points.size();
  std::map<std::pair<std::size_t, std::size_t>, int> directed;
  std::vector<std::vector<std::size_t>> incident(n);
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    for (int k = 0; k < 3; ++k)
      if (t[k] >= n) r.indices_in_range = false;
    if (!r.indices_in_range) return r;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) r.no_degenerate_triangle = false;
    const Point3d normal = cross(sub(soup.points[t[1]], soup.points[t[0]]),
                                 sub(soup.points[t[2]], soup.points[t[0]]));
    if (!(norm(normal) > 0)) r.no_degenerate_triangle = false;
    for (int k = 0; k < 3; ++k) {
      if (++directed[{t[k], t[(k + 1) % 3]}] > 1) r.oriented = false;
      incident[t[k]].push_back(f);
    }
  }
  for (const auto& [edge, count] : directed)
    if (directed.find({edge.second, edge.first}) == directed.end()) ++r.boundary_edges;
  // Vertex fans: link edges (the opposite edges of the incident triangles) must form a single
  // path or cycle. Walk it: every link vertex has degree <= 2 and the link is connected.
  for (std::size_t v = 0; v < n; ++v) {
    if (incident[v].empty()) {
      r.all_vertices_used = false;
      continue;
    }
    std::map<std::size_t, std::vector<std::size_t>> link;
    for (std::size_t f : incident[v]) {
      const auto& t = soup.triangles[f];
      std::size_t k = 0;
      while (t[k] != v) ++k;
      const std::size_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      link[a].push_back(b);
      link[b].push_back(a);
    }
    for (const auto& [w, adj] : link)
      if (adj.size() > 2) r.manifold_vertices = false;
    std::set<std::size_t> seen;
    std::vector<std::size_t> stack = {link.begin()->first};
    while (!stack.empty()) {
      const std::size_t w = stack.back();
      stack.pop_back();
      if (!seen.insert(w).second) continue;
      for (std::size_t x : link[w]) stack.push_back(x);
    }
    if (seen.size() != link.size()) r.manifold_vertices = false;
  }
  return r;
}

/// Builds a CGAL Surface_mesh face by face; false if CGAL refuses a face (non-manifold or
/// inconsistently oriented).
bool build_surface_mesh(const TriangleSoup& soup, CGAL::Surface_mesh<CGAL::Epick::Point_3>& mesh) {
  using Mesh = CGAL::Surface_mesh<CGAL::Epick::Point_3>;
  std::vector<Mesh::Vertex_index> vs;
  for (const auto& p : soup.points) vs.push_back(mesh.add_vertex({p[0], p[1], p[2]}));
  for (const auto& t : soup.triangles)
    if (mesh.add_face(vs[t[0]], vs[t[1]], vs[t[2]]) == Mesh::null_face()) return false;
  return mesh.is_valid(false);
}

double signed_volume(const TriangleSoup& soup) {
  double v = 0;
  for (const auto& t : soup.triangles)
    v += dot(soup.points[t[0]], cross(soup.points[t[1]], soup.points[t[2]]));
  return v / 6.0;
}

// ------------------------------------------------------------------ the smooth surface, inverted

/// Path c(s) and its derivatives, as described in the brief (independent of generate.cpp).
struct Path {
  double A, k;
  Point3d c(double s) const { return {s, 0.0, A * std::sin(k * s)}; }
  Point3d d1(double s) const { return {1.0, 0.0, A * k * std::cos(k * s)}; }
  Point3d d2(double s) const { return {0.0, 0.0, -A * k * k * std::sin(k * s)}; }
};

/// Section coordinates of an untransformed point p: s with (p - c(s)) . c'(s) = 0 (Newton from
/// s = p.x), then u along y and v along the normal N = T x (0,1,0).
struct SectionCoords {
  double s, u, v;
};
SectionCoords section_coords(const TowOptions& o, const Point3d& p) {
  const Path path{o.crimp_amplitude, 2 * pi / o.crimp_wavelength};
  double s = p[0];
  for (int it = 0; it < 50; ++it) {
    const Point3d d = sub(p, path.c(s));
    const double f = dot(d, path.d1(s));
    const double df = -dot(path.d1(s), path.d1(s)) + dot(d, path.d2(s));
    const double step = f / df;
    s -= step;
    if (std::fabs(step) < 1e-15) break;
  }
  const Point3d t = path.d1(s);
  const Point3d T = {t[0] / norm(t), t[1] / norm(t), t[2] / norm(t)};
  const Point3d N = cross(T, Point3d{0, 1, 0});
  const Point3d d = sub(p, path.c(s));
  return {s, d[1], dot(d, N)};
}

/// Signed "distance-like" level of the section at (u, v): 0 on the boundary, < 0 inside.
/// Elliptical: ((u/a)^2 + (v/b)^2) - 1. Lenticular: |v| - h(u) (with |u| <= a).
double section_level(const TowOptions& o, double u, double v) {
  const double a = o.half_width, b = o.half_height;
  if (o.section == Section::elliptical) return (u / a) * (u / a) + (v / b) * (v / b) - 1.0;
  const double R = (a * a + b * b) / (2 * b);
  const double h = std::sqrt(std::max(0.0, R * R - u * u)) - (R - b);
  return std::max(std::fabs(v) - h, std::fabs(u) - a);
}

/// Rotation about z, then about x, then translation.
Point3d apply_transform(const TowOptions& o, const Point3d& p) {
  const double cz = std::cos(o.rotate_z), sz = std::sin(o.rotate_z);
  const double cx = std::cos(o.rotate_x), sx = std::sin(o.rotate_x);
  const double x = cz * p[0] - sz * p[1], y = sz * p[0] + cz * p[1], z = p[2];
  return {x + o.translate[0], cx * y - sx * z + o.translate[1], sx * y + cx * z + o.translate[2]};
}
Point3d undo_transform(const TowOptions& o, const Point3d& q) {
  const Point3d p = sub(q, o.translate);
  const double cz = std::cos(o.rotate_z), sz = std::sin(o.rotate_z);
  const double cx = std::cos(o.rotate_x), sx = std::sin(o.rotate_x);
  const double x = p[0], y = cx * p[1] + sx * p[2], z = -sx * p[1] + cx * p[2];
  return {cz * x + sz * y, -sz * x + cz * y, z};
}

double path_arc_length(const TowOptions& o) {  // composite Simpson, plenty of intervals
  const Path path{o.crimp_amplitude, 2 * pi / o.crimp_wavelength};
  const int n = 20000;
  const double h = o.length / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += w * norm(path.d1(i * h));
  }
  return sum * h / 3;
}

double lens_area(double a, double b) {
  const double R = (a * a + b * b) / (2 * b);
  return 2 * (R * R * std::acos((R - b) / R) - (R - b) * a);
}

TowOptions options_with(Section section, double crimp, int along, int around) {
  TowOptions o;
  o.section = section;
  o.crimp_amplitude = crimp;
  o.segments_along = along;
  o.segments_around = around;
  return o;
}

}  // namespace

TEST_CASE("generate: the tow is a closed, oriented 2-manifold with outward normals", "[generate]") {
  const Section section = GENERATE(Section::elliptical, Section::lenticular);
  const double crimp = GENERATE(0.0, 0.3);
  const auto dims = GENERATE(std::array<int, 2>{60, 24}, std::array<int, 2>{1, 3},
                             std::array<int, 2>{7, 11}, std::array<int, 2>{16, 64});
  TowOptions o = options_with(section, crimp, dims[0], dims[1]);
  CAPTURE(section == Section::elliptical, crimp, dims[0], dims[1]);

  const TriangleSoup soup = seam::make_tow(o);
  const std::size_t along = static_cast<std::size_t>(dims[0]);
  const std::size_t around = static_cast<std::size_t>(dims[1]);
  CHECK(soup.points.size() == (along + 1) * around + 2);
  CHECK(soup.triangles.size() == 2 * along * around + 2 * around);

  const TopologyReport r = check_topology(soup);
  CHECK(r.indices_in_range);
  CHECK(r.no_degenerate_triangle);
  CHECK(r.oriented);
  CHECK(r.boundary_edges == 0);
  CHECK(r.manifold_vertices);
  CHECK(r.all_vertices_used);

  CGAL::Surface_mesh<CGAL::Epick::Point_3> mesh;
  REQUIRE(build_surface_mesh(soup, mesh));
  CHECK(CGAL::is_closed(mesh));
  CHECK(CGAL::is_triangle_mesh(mesh));
  CHECK(mesh.number_of_faces() == soup.triangles.size());

  CHECK(signed_volume(soup) > 0);

  // The library's own validation and conversion accept it.
  CHECK_NOTHROW(seam::validate_triangle_mesh(soup, "tow"));
  const seam::Mesh<seam::Filtered> converted = seam::mesh_from_soup<seam::Filtered>(soup, "tow");
  CHECK(converted.number_of_vertices() == soup.points.size());
  CHECK(converted.number_of_faces() == soup.triangles.size());
  CHECK(CGAL::is_closed(converted));
}

TEST_CASE("generate: an uncapped tow is an oriented tube with two boundary loops", "[generate]") {
  TowOptions o = options_with(Section::lenticular, 0.3, 10, 12);
  o.capped = false;
  const TriangleSoup soup = seam::make_tow(o);
  CHECK(soup.points.size() == 11 * 12);
  CHECK(soup.triangles.size() == 2 * 10 * 12);
  const TopologyReport r = check_topology(soup);
  CHECK(r.oriented);
  CHECK(r.boundary_edges == 2 * 12);
  CHECK(r.manifold_vertices);
  CGAL::Surface_mesh<CGAL::Epick::Point_3> mesh;
  REQUIRE(build_surface_mesh(soup, mesh));
  CHECK_FALSE(CGAL::is_closed(mesh));
}

TEST_CASE("generate: the volume matches the analytic volume", "[generate]") {
  SECTION("elliptical, straight: the prism over the inscribed polygon, and pi a b L") {
    TowOptions o = options_with(Section::elliptical, 0.0, 8, 64);
    const double n = 64, a = o.half_width, b = o.half_height;
    const double polygon = 0.5 * n * a * b * std::sin(2 * pi / n);
    const double v = signed_volume(seam::make_tow(o));
    CHECK(v == Approx(polygon * o.length).epsilon(1e-10));
    CHECK(v == Approx(pi * a * b * o.length).epsilon(0.02));
    CHECK(v < pi * a * b * o.length);  // the facets lie inside the smooth surface
  }
  SECTION("elliptical, crimped: section area times the path's arc length") {
    TowOptions o = options_with(Section::elliptical, 0.3, 120, 64);
    const double expected = pi * o.half_width * o.half_height * path_arc_length(o);
    CHECK(signed_volume(seam::make_tow(o)) == Approx(expected).epsilon(0.02));
  }
  SECTION("lenticular, straight: the lens area times L") {
    TowOptions o = options_with(Section::lenticular, 0.0, 8, 64);
    // Shoelace area of the section polygon, from the profile written out here.
    const double a = o.half_width, b = o.half_height, R = (a * a + b * b) / (2 * b);
    double polygon = 0;
    std::vector<std::array<double, 2>> ring;
    for (int j = 0; j < 64; ++j) {
      const double phi = 2 * pi * j / 64, x = a * std::cos(phi);
      const double h = std::max(0.0, std::sqrt(std::max(0.0, R * R - x * x)) - (R - b));
      ring.push_back({x, std::sin(phi) < 0 ? -h : h});
    }
    for (int j = 0; j < 64; ++j) {
      const auto& p = ring[j];
      const auto& q = ring[(j + 1) % 64];
      polygon += 0.5 * (p[0] * q[1] - q[0] * p[1]);
    }
    const double v = signed_volume(seam::make_tow(o));
    CHECK(v == Approx(polygon * o.length).epsilon(1e-10));
    CHECK(v == Approx(lens_area(a, b) * o.length).epsilon(0.02));
    CHECK(v < lens_area(a, b) * o.length);
  }
  SECTION("lenticular, crimped") {
    TowOptions o = options_with(Section::lenticular, 0.3, 120, 64);
    const double expected = lens_area(o.half_width, o.half_height) * path_arc_length(o);
    CHECK(signed_volume(seam::make_tow(o)) == Approx(expected).epsilon(0.02));
  }
}

TEST_CASE("generate: mesh vertices lie on the smooth surface, facets inside it", "[generate]") {
  const Section section = GENERATE(Section::elliptical, Section::lenticular);
  const double crimp = GENERATE(0.0, 0.3);
  TowOptions o = options_with(section, crimp, 30, 24);
  CAPTURE(section == Section::elliptical, crimp);
  const TriangleSoup soup = seam::make_tow(o);
  const std::size_t ring_vertices = 31 * 24;

  for (std::size_t i = 0; i < ring_vertices; ++i) {
    const SectionCoords sc = section_coords(o, soup.points[i]);
    CHECK(sc.s == Approx(o.length * static_cast<double>(i / 24) / 30).margin(1e-9));
    CHECK(std::fabs(section_level(o, sc.u, sc.v)) < 1e-9);
  }
  // Cap centres on the path ends.
  const SectionCoords c0 = section_coords(o, soup.points[ring_vertices]);
  const SectionCoords c1 = section_coords(o, soup.points[ring_vertices + 1]);
  CHECK(c0.s == Approx(0).margin(1e-12));
  CHECK(c1.s == Approx(o.length).margin(1e-12));
  CHECK(std::hypot(c0.u, c0.v) < 1e-12);
  CHECK(std::hypot(c1.u, c1.v) < 1e-12);

  // Side facets: their centroids are inside the smooth tube for a straight path. Along a
  // crimped path, chords along s on the inner side of a bend lie outside the surface by up to
  // ~ curvature * ds^2 / 8; allow twice that: shrinking the section about its centre by
  // (1 - delta / b) moves its boundary inwards by at least delta (b is the inradius).
  const double ds = o.length / 30, k = 2 * pi / o.crimp_wavelength;
  const double delta = 2 * o.crimp_amplitude * k * k * ds * ds / 8;
  const double shrink = 1 - delta / o.half_height;
  for (std::size_t f = 0; f < 2 * 30 * 24; ++f) {
    const auto& t = soup.triangles[f];
    Point3d g{0, 0, 0};
    for (int q = 0; q < 3; ++q)
      for (int d = 0; d < 3; ++d) g[d] += soup.points[t[q]][d] / 3;
    const SectionCoords sc = section_coords(o, g);
    CHECK(section_level(o, sc.u * shrink, sc.v * shrink) < 0);
  }
}

TEST_CASE("generate: the rigid transform is rotate_z, then rotate_x, then translate", "[generate]") {
  TowOptions plain = options_with(Section::lenticular, 0.3, 20, 16);
  TowOptions moved = plain;
  moved.rotate_z = 0.7;
  moved.rotate_x = -1.1;
  moved.translate = {1.5, -2.0, 0.25};
  const TriangleSoup a = seam::make_tow(plain);
  const TriangleSoup b = seam::make_tow(moved);
  REQUIRE(a.points.size() == b.points.size());
  CHECK(a.triangles == b.triangles);
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const Point3d expected = apply_transform(moved, a.points[i]);
    CHECK(norm(sub(b.points[i], expected)) < 1e-12);
  }
  CHECK(signed_volume(b) == Approx(signed_volume(a)).epsilon(1e-9));

  const Point3d p = seam::tow_surface_point(moved, 3.3, 1.2);
  CHECK(norm(sub(p, apply_transform(moved, seam::tow_surface_point(plain, 3.3, 1.2)))) < 1e-12);
}

TEST_CASE("generate: the ring curve is closed and lies on the smooth surface", "[generate]") {
  const Section section = GENERATE(Section::elliptical, Section::lenticular);
  const bool transformed = GENERATE(false, true);
  CAPTURE(section == Section::elliptical, transformed);
  TowOptions o = options_with(section, 0.3, 60, 24);
  if (transformed) {
    o.rotate_z = 0.4;
    o.rotate_x = 0.9;
    o.translate = {-3.0, 1.0, 2.0};
  }
  const double s_center = 4.9, tilt = 0.4;
  const int samples = 500;
  const std::vector<Point3d> curve = seam::make_ring_curve(o, s_center, tilt, samples);

  REQUIRE(curve.size() == static_cast<std::size_t>(samples) + 1);
  CHECK(curve.front() == curve.back());
  for (std::size_t k = 0; k + 1 < curve.size(); ++k) CHECK(curve[k] != curve[k + 1]);

  for (int k = 0; k < samples; ++k) {
    const double phi = 2 * pi * k / samples;
    const SectionCoords sc = section_coords(o, undo_transform(o, curve[k]));
    CHECK(sc.s == Approx(s_center + tilt * std::cos(phi)).margin(1e-9));
    CHECK(std::fabs(section_level(o, sc.u, sc.v)) < 1e-9);
    // Once around, in order: the section point's angle is phi (for the ellipse, its
    // parametric angle; for the lens, u = a cos(phi) and v has the sign of sin(phi)).
    if (o.section == Section::elliptical) {
      const double angle = std::atan2(sc.v / o.half_height, sc.u / o.half_width);
      CHECK(std::fabs(std::remainder(angle - phi, 2 * pi)) < 1e-9);
    } else {
      CHECK(sc.u == Approx(o.half_width * std::cos(phi)).margin(1e-9));
      if (std::fabs(std::sin(phi)) > 1e-3) CHECK((sc.v > 0) == (std::sin(phi) > 0));
    }
  }
}

TEST_CASE("generate: the ring curve lies near, not on, the faceted mesh", "[generate]") {
  TowOptions o = options_with(Section::elliptical, 0.3, 60, 24);
  const TriangleSoup soup = seam::make_tow(o);
  const std::vector<Point3d> curve = seam::make_ring_curve(o, 4.9, 0.4, 97);
  using K = CGAL::Epick;
  std::vector<K::Triangle_3> triangles;
  for (const auto& t : soup.triangles) {
    auto P = [&](std::size_t i) { return K::Point_3(soup.points[i][0], soup.points[i][1], soup.points[i][2]); };
    triangles.emplace_back(P(t[0]), P(t[1]), P(t[2]));
  }
  // Chordal error around: at most a (1 - cos(pi / n)) (the ellipse is the image of a circle of
  // radius 1 by a map that stretches by at most a), plus a negligible sag along the path.
  const double chordal = o.half_width * (1 - std::cos(pi / 24));
  double max_distance = 0;
  for (const auto& p : curve) {
    const K::Point_3 q(p[0], p[1], p[2]);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : triangles) best = std::min(best, CGAL::squared_distance(q, t));
    max_distance = std::max(max_distance, std::sqrt(best));
  }
  CHECK(max_distance < chordal);
  CHECK(max_distance > 1e-4);
}

TEST_CASE("generate: invalid options are rejected", "[generate]") {
  TowOptions o;
  CHECK_NOTHROW(seam::make_tow(o));
  auto bad = [](auto change) {
    TowOptions x;
    change(x);
    return x;
  };
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.segments_around = 2; })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.segments_along = 0; })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.length = 0; })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.half_width = -1; })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.crimp_wavelength = 0; })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) { x.rotate_x = std::nan(""); })), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_tow(bad([](TowOptions& x) {
                    x.section = Section::lenticular;
                    x.half_height = 2 * x.half_width;
                  })),
                  seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_ring_curve(o, 0.2, 0.4, 100), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_ring_curve(o, 9.8, 0.4, 100), seam::InvalidInput);
  CHECK_THROWS_AS(seam::make_ring_curve(o, 5.0, 0.4, 2), seam::InvalidInput);
}
